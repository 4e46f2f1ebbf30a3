#include "lights/environment_light.h"

#include <algorithm>

#include "core/sampling.h"

namespace veach {

// The map (radiance, strength applied) and a piecewise-constant 2D density over its cells: a
// marginal over rows and one conditional per row, both as cumulative tables. Cell weights are
// the exact integral of the bilinearly interpolated radiance over the cell (a 3x3 tent of
// texels: 9/16 centre, 3/32 edges, 1/64 corners), so every direction with radiance has density.
struct EnvironmentLight::Table {
    int width = 0, height = 0;
    const float* rgb = nullptr;  // the Scene's texels (width * height * 3), not copied: maps are big
    float strength = 1;
    std::vector<float> weight;     // per cell: average radiance x sin(theta at the row centre)
    std::vector<float> cond_cdf;   // per row: width + 1 entries, normalised
    std::vector<double> marg_cdf;  // height + 1 entries, normalised
    double total = 0;              // sum of weights

    // Radiance of texel (x, y): u wraps around, v clamps at the poles; negative or NaN texels
    // emit nothing.
    Rgb texel(int x, int y) const {
        x %= width;
        if (x < 0) x += width;
        y = std::clamp(y, 0, height - 1);
        const float* p = &rgb[(static_cast<size_t>(y) * width + x) * 3];
        auto clean = [&](float v) {
            v *= strength;
            return std::isfinite(v) && v > 0.0f ? v : 0.0f;
        };
        return {clean(p[0]), clean(p[1]), clean(p[2])};
    }
};

namespace {

// Finds the bucket of u in a normalised cumulative table [c_0 = 0, ..., c_n = 1], skipping
// empty buckets, and rescales u to [0, 1) within it.
template <typename T>
int sample_cdf(const T* cdf, int n, float u, float* u_remapped) {
    const T* it = std::upper_bound(cdf + 1, cdf + n + 1, static_cast<T>(u));
    int i = std::min(static_cast<int>(it - cdf) - 1, n - 1);
    while (i > 0 && !(cdf[i + 1] > cdf[i])) --i;
    double width = static_cast<double>(cdf[i + 1]) - static_cast<double>(cdf[i]);
    float r = width > 0.0 ? static_cast<float>((u - static_cast<double>(cdf[i])) / width) : 0.5f;
    *u_remapped = std::clamp(r, 0.0f, 0x1.fffffep-1f);
    return i;
}

}  // namespace

EnvironmentLight::EnvironmentLight(const Environment& env) {
    m_cos_rot = std::cos(env.rotation);
    m_sin_rot = std::sin(env.rotation);
    float strength = std::isfinite(env.strength) && env.strength > 0.0f ? env.strength : 0.0f;
    m_uniform = env.color * strength;
    if (!env.has_map() || env.texels.size() < static_cast<size_t>(env.width) * env.height * 3) {
        m_integral = 4.0f * k_pi * m_uniform.average();
        return;
    }
    auto t = std::make_shared<Table>();
    const int w = env.width, h = env.height;
    t->width = w;
    t->height = h;
    t->rgb = env.texels.data();
    t->strength = strength;
    t->weight.resize(static_cast<size_t>(w) * h);
    t->cond_cdf.resize(static_cast<size_t>(w + 1) * h);
    t->marg_cdf.resize(static_cast<size_t>(h) + 1);
    auto avg = [&](int x, int y) { return t->texel(x, y).average(); };
    std::vector<double> row_sum(h, 0.0);
    for (int y = 0; y < h; ++y) {
        float sin_theta = std::sin(k_pi * (y + 0.5f) / h);
        for (int x = 0; x < w; ++x) {
            float c = avg(x, y);
            float e = avg(x - 1, y) + avg(x + 1, y) + avg(x, y - 1) + avg(x, y + 1);
            float k = avg(x - 1, y - 1) + avg(x + 1, y - 1) + avg(x - 1, y + 1) + avg(x + 1, y + 1);
            float wgt = (c * (9.0f / 16.0f) + e * (3.0f / 32.0f) + k * (1.0f / 64.0f)) * sin_theta;
            t->weight[static_cast<size_t>(y) * w + x] = wgt;
            row_sum[y] += wgt;
        }
        float* cdf = &t->cond_cdf[static_cast<size_t>(y) * (w + 1)];
        double acc = 0.0;
        cdf[0] = 0.0f;
        for (int x = 0; x < w; ++x) {
            acc += t->weight[static_cast<size_t>(y) * w + x];
            cdf[x + 1] = row_sum[y] > 0.0 ? static_cast<float>(acc / row_sum[y]) : static_cast<float>(x + 1) / w;
        }
        cdf[w] = 1.0f;
        t->total += row_sum[y];
    }
    double acc = 0.0;
    t->marg_cdf[0] = 0.0;
    for (int y = 0; y < h; ++y) {
        acc += row_sum[y];
        t->marg_cdf[y + 1] = t->total > 0.0 ? acc / t->total : static_cast<double>(y + 1) / h;
    }
    t->marg_cdf[h] = 1.0;
    // Each cell spans du dv = 1 / (w h), and d omega = 2 pi^2 sin(theta) du dv.
    m_integral = static_cast<float>(t->total * 2.0 * k_pi * k_pi / (static_cast<double>(w) * h));
    m_table = std::move(t);
}

Vec3 EnvironmentLight::to_local(const Vec3& w) const {
    return {m_cos_rot * w.x + m_sin_rot * w.z, w.y, -m_sin_rot * w.x + m_cos_rot * w.z};
}

Vec3 EnvironmentLight::to_world(const Vec3& l) const {
    return {m_cos_rot * l.x - m_sin_rot * l.z, l.y, m_sin_rot * l.x + m_cos_rot * l.z};
}

Rgb EnvironmentLight::radiance(const Vec3& w) const {
    if (!m_table) return m_uniform;
    const Table& t = *m_table;
    Vec3 l = to_local(w);
    // u = 0.5 + atan2(z, x) / 2 pi, v = theta / pi: Cycles' equirectangular mapping in glTF axes.
    float u = 0.5f + std::atan2(l.z, l.x) * k_inv_two_pi;
    float v = std::acos(clamp(l.y, -1.0f, 1.0f)) * k_inv_pi;
    if (!std::isfinite(u) || !std::isfinite(v)) return Rgb(0.0f);
    float fx = u * t.width - 0.5f, fy = v * t.height - 0.5f;
    float x0f = std::floor(fx), y0f = std::floor(fy);
    float tx = fx - x0f, ty = fy - y0f;
    int x0 = static_cast<int>(x0f), y0 = static_cast<int>(y0f);
    return lerp(lerp(t.texel(x0, y0), t.texel(x0 + 1, y0), tx), lerp(t.texel(x0, y0 + 1), t.texel(x0 + 1, y0 + 1), tx),
                ty);
}

Vec3 EnvironmentLight::sample(float u1, float u2, float* pdf_w) const {
    if (!m_table || !(m_table->total > 0.0)) {
        *pdf_w = m_table ? 0.0f : k_inv_four_pi;
        return sample_uniform_sphere(u1, u2);
    }
    const Table& t = *m_table;
    float v_in, u_in;
    int y = sample_cdf(t.marg_cdf.data(), t.height, u1, &v_in);
    int x = sample_cdf(&t.cond_cdf[static_cast<size_t>(y) * (t.width + 1)], t.width, u2, &u_in);
    float u = (x + u_in) / t.width, v = (y + v_in) / t.height;
    float theta = v * k_pi, phi = (u - 0.5f) * 2.0f * k_pi;
    float sin_theta = std::sin(theta);
    Vec3 l(sin_theta * std::cos(phi), std::cos(theta), sin_theta * std::sin(phi));
    float w = t.weight[static_cast<size_t>(y) * t.width + x];
    *pdf_w = sin_theta > 0.0f ? static_cast<float>(w / t.total * t.width * t.height / (2.0 * k_pi * k_pi * sin_theta))
                              : 0.0f;
    return to_world(l);
}

float EnvironmentLight::pdf_w(const Vec3& w) const {
    if (!m_table) return k_inv_four_pi;
    const Table& t = *m_table;
    if (!(t.total > 0.0)) return 0.0f;
    Vec3 l = to_local(w);
    float sin_theta = std::sqrt(l.x * l.x + l.z * l.z);
    if (!(sin_theta > 0.0f)) return 0.0f;
    float u = 0.5f + std::atan2(l.z, l.x) * k_inv_two_pi;
    float v = std::acos(clamp(l.y, -1.0f, 1.0f)) * k_inv_pi;
    int x = std::clamp(static_cast<int>(u * t.width), 0, t.width - 1);
    int y = std::clamp(static_cast<int>(v * t.height), 0, t.height - 1);
    float cell = t.weight[static_cast<size_t>(y) * t.width + x];
    return static_cast<float>(cell / t.total * t.width * t.height / (2.0 * k_pi * k_pi * sin_theta));
}

double EnvironmentLight::power(const LightContext& ctx) const {
    // The power that crosses the scene's bounding disc: pi R^2 times radiance over the sphere.
    return k_pi * double(ctx.radius) * ctx.radius * radiance_integral();
}

bool EnvironmentLight::sample_direct(const LightContext& ctx, const Vec3& receiver, float u1, float u2, float pmf,
                                     LightSample* out) const {
    float pdf_dir;
    out->wi = sample(u1, u2, &pdf_dir);
    if (!(pdf_dir > 0.0f)) return false;
    out->distance = k_infinity;
    out->point = ctx.far_point(receiver, out->wi);
    out->normal = Vec3();
    out->radiance = radiance(out->wi);
    out->pdf_w = pmf * pdf_dir;
    out->is_delta = false;
    out->is_infinite = true;
    return std::isfinite(out->pdf_w) && !out->radiance.is_black();
}

float EnvironmentLight::pdf_direct_w(const LightContext&, const Vec3&, const Vec3& wi, const Vec3&, float pmf) const {
    return pmf * pdf_w(wi);
}

bool EnvironmentLight::sample_emission(const LightContext& ctx, float, float u1, float u2, float u3, float u4,
                                       LightEmission* out) const {
    // A direction toward the environment from its map density, then parallel rays along the
    // opposite direction through a disc covering the scene's bounding sphere, outside it
    // (pbrt-v3 section 16.1.2): pdf_pos_a = 1 / (pi R^2).
    float pdf_dir;
    Vec3 w = sample(u1, u2, &pdf_dir);
    if (!(pdf_dir > 0.0f)) return false;
    Frame frame(-w);
    Vec2 d = sample_concentric_disk(u3, u4);
    out->point = ctx.center + (frame.s * d.x + frame.t * d.y) * ctx.radius + w * ctx.radius;
    out->normal = Vec3(0, 0, 0);
    out->dir = -w;
    out->value = radiance(w);
    out->pdf_pos_a = ctx.disc_pdf_a();
    out->pdf_dir_w = pdf_dir;
    out->delta_position = out->delta_direction = false;
    out->infinite = true;
    return std::isfinite(pdf_dir) && !out->value.is_black();
}

void EnvironmentLight::pdf_emission(const LightContext& ctx, const Vec3&, const Vec3& dir, float* pdf_pos_a,
                                    float* pdf_dir_w) const {
    *pdf_pos_a = ctx.disc_pdf_a();
    *pdf_dir_w = pdf_w(-dir);  // dir is the way the particle travels, away from the sky
}

}  // namespace veach
