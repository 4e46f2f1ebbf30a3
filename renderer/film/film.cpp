#include "film/film.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace veach {

Film::Film(int width, int height, const FilmSettings& settings)
    : m_width(width),
      m_height(height),
      m_settings(settings),
      m_filter(settings.filter),
      m_pixels(static_cast<size_t>(width) * height),
      m_splats(new std::atomic<double>[static_cast<size_t>(width) * height * 3]) {
    for (size_t i = 0; i < static_cast<size_t>(width) * height * 3; ++i) m_splats[i] = 0.0;
    if (settings.aovs) m_aovs.resize(m_pixels.size());
    if (settings.alpha) m_alpha_hits.assign(m_pixels.size(), 0.0);
    if (settings.halves) {
        m_odd.resize(m_pixels.size());
        m_features.resize(m_pixels.size());
        m_odd_splats.reset(new std::atomic<double>[m_pixels.size() * 3]);
        for (size_t i = 0; i < m_pixels.size() * 3; ++i) m_odd_splats[i] = 0.0;
    }
}

namespace {
void atomic_add(std::atomic<double>& a, double v) {
    double old = a.load(std::memory_order_relaxed);
    while (!a.compare_exchange_weak(old, old + v, std::memory_order_relaxed)) {}
}
}  // namespace

void Film::add_aovs(size_t i, const PixelAovs& aovs) {
    AovSums& a = m_aovs[i];
    if (a.count == 0.0) a.depth = aovs.hit ? aovs.depth : k_no_hit_depth;
    if (aovs.hit) {
        a.normal[0] += aovs.normal.x;
        a.normal[1] += aovs.normal.y;
        a.normal[2] += aovs.normal.z;
        a.albedo[0] += aovs.albedo.r;
        a.albedo[1] += aovs.albedo.g;
        a.albedo[2] += aovs.albedo.b;
    }
    a.count += 1.0;
}

void Film::add_to_halves(size_t i, const Rgb& radiance, uint32_t sample_index, const DenoiseFeatures* features) {
    if (sample_index & 1u) {
        HalfSums& h = m_odd[i];
        h.sum[0] += radiance.r;
        h.sum[1] += radiance.g;
        h.sum[2] += radiance.b;
        h.weight += 1.0;
    }
    if (!features || !features->hit) return;
    FeatureSums& f = m_features[i];
    const float albedo[3] = {features->albedo.r, features->albedo.g, features->albedo.b};
    const float normal[3] = {features->normal.x, features->normal.y, features->normal.z};
    const float position[3] = {features->position.x, features->position.y, features->position.z};
    for (int c = 0; c < 3; ++c) {
        f.albedo[c] += albedo[c];
        f.normal[c] += normal[c];
        f.position[c] += position[c];
    }
    f.depth += features->depth;
    f.hits += 1.0f;
}

void Film::add_splat(float fx, float fy, const Rgb& value, uint32_t sample_index) {
    splat_into(m_splats.get(), fx, fy, value);
    if (m_settings.halves && (sample_index & 1u)) splat_into(m_odd_splats.get(), fx, fy, value);
}

void Film::splat_into(std::atomic<double>* splats, float fx, float fy, const Rgb& value) {
    if (m_filter.is_unit_box()) {
        // The splat belongs to the pixel that contains it.
        int x = static_cast<int>(std::floor(fx));
        int y = static_cast<int>(std::floor(fy));
        if (x < 0 || y < 0 || x >= m_width || y >= m_height) return;
        size_t i = (static_cast<size_t>(y) * m_width + x) * 3;
        atomic_add(splats[i + 0], value.r);
        atomic_add(splats[i + 1], value.g);
        atomic_add(splats[i + 2], value.b);
        // Read before writing: a store on every splat would bounce the flag's cache line
        // between the threads.
        if (!m_has_splats.load(std::memory_order_relaxed)) m_has_splats.store(true, std::memory_order_relaxed);
        return;
    }
    // Pixel (x, y) estimates the integral of f(p - c) L(p) dp with c = (x + 0.5, y + 0.5): a
    // light-tracing contribution at p (already an estimate of L(p) dp) adds f(p - c) times itself
    // to each pixel whose support covers p. f is the same normalised density the camera samples
    // are drawn from, so the two estimators of one pixel agree.
    const float r = m_filter.radius();
    const int x0 = std::max(0, static_cast<int>(std::ceil(fx - 0.5f - r)));
    const int x1 = std::min(m_width - 1, static_cast<int>(std::floor(fx - 0.5f + r)));
    const int y0 = std::max(0, static_cast<int>(std::ceil(fy - 0.5f - r)));
    const int y1 = std::min(m_height - 1, static_cast<int>(std::floor(fy - 0.5f + r)));
    bool any = false;
    for (int y = y0; y <= y1; ++y) {
        const float wy = m_filter.pdf(fy - (y + 0.5f));
        if (!(wy > 0.0f)) continue;
        for (int x = x0; x <= x1; ++x) {
            const float w = wy * m_filter.pdf(fx - (x + 0.5f));
            if (!(w > 0.0f)) continue;
            size_t i = (static_cast<size_t>(y) * m_width + x) * 3;
            atomic_add(splats[i + 0], static_cast<double>(value.r) * w);
            atomic_add(splats[i + 1], static_cast<double>(value.g) * w);
            atomic_add(splats[i + 2], static_cast<double>(value.b) * w);
            any = true;
        }
    }
    if (any && !m_has_splats.load(std::memory_order_relaxed)) m_has_splats.store(true, std::memory_order_relaxed);
}

void Film::set_sample_plan(std::vector<uint32_t> plan, float target, int pilot_spp) {
    m_plan = std::move(plan);
    m_plan_target = target;
    m_plan_pilot_spp = pilot_spp;
    m_pilot_splats.resize(m_pixels.size() * 3);
    for (size_t i = 0; i < m_pilot_splats.size(); ++i) {
        m_pilot_splats[i] = m_splats[i].load(std::memory_order_relaxed);
        m_splats[i].store(0.0, std::memory_order_relaxed);
    }
    if (!m_settings.halves) return;
    m_odd_pilot_splats.resize(m_pixels.size() * 3);
    for (size_t i = 0; i < m_odd_pilot_splats.size(); ++i) {
        m_odd_pilot_splats[i] = m_odd_splats[i].load(std::memory_order_relaxed);
        m_odd_splats[i].store(0.0, std::memory_order_relaxed);
    }
}

uint64_t Film::planned_total(uint64_t spp) const {
    if (m_plan.empty()) return spp * m_pixels.size();
    uint64_t total = 0;
    for (uint32_t budget : m_plan) total += std::min<uint64_t>(budget, spp);
    return total;
}

Image Film::resolve(double splat_spp) const {
    Image img;
    img.width = m_width;
    img.height = m_height;
    const size_t n = m_pixels.size();
    img.rgba.resize(n * 4);
    img.variance.resize(n * 3);
    img.sample_count.resize(n);
    // Splats: every camera sample traced one light path, each an independent estimate of the
    // whole light-tracing image, so the sum over L paths divided by L / pixels is unbiased as long
    // as L does not depend on the paths' values. Without a plan L = spp x pixels. With one, the
    // number of paths after the pilot depends on the plan, which the pilot's paths helped make
    // (bdpt's camera values include connections to them), so the two groups are weighed apart
    // with a weight fixed in advance: alpha = pilot / spp for the pilot's paths (pilot x pixels of
    // them), 1 - alpha for the later ones (L_post of them, independent of the plan that counted
    // them). With no pixel stopped this is exactly (pilot + post) / spp, the plain average.
    double pilot_scale = 0.0, splat_scale = splat_spp > 0.0 ? 1.0 / splat_spp : 0.0;
    if (!m_plan.empty() && splat_spp > 0.0) {
        const double pilot = m_plan_pilot_spp, alpha = std::min(1.0, pilot / splat_spp);
        const double post =
            static_cast<double>(planned_total(static_cast<uint64_t>(splat_spp))) - pilot * static_cast<double>(n);
        // No path after the pilot (every pixel stopped there): the pilot's paths alone.
        pilot_scale = post > 0.0 ? alpha / pilot : 1.0 / pilot;
        splat_scale = post > 0.0 ? (1.0 - alpha) * static_cast<double>(n) / post : 0.0;
    }
    for (size_t i = 0; i < n; ++i) {
        const Pixel& p = m_pixels[i];
        double inv = p.weight > 0.0 ? 1.0 / p.weight : 0.0;
        img.sample_count[i] = static_cast<float>(p.weight);
        for (int c = 0; c < 3; ++c) {
            double mean = p.sum[c] * inv;
            double v = mean + m_splats[i * 3 + c].load(std::memory_order_relaxed) * splat_scale;
            if (!m_pilot_splats.empty()) v += m_pilot_splats[i * 3 + c] * pilot_scale;
            img.rgba[i * 4 + c] = static_cast<float>(v);
            // The unbiased sample variance s^2 = (sum x^2 - n mean^2) / (n - 1), divided by n:
            // the variance of the pixel's mean (camera samples only: splats are not per pixel).
            double var = 0.0;
            if (p.weight > 1.0) var = std::max(0.0, (p.sum_sq[c] - p.weight * mean * mean) / (p.weight - 1.0)) * inv;
            img.variance[i * 3 + c] = static_cast<float>(var);
        }
        // Splats (light tracing) add light, never coverage: alpha is the camera samples'.
        img.rgba[i * 4 + 3] = m_alpha_hits.empty() ? 1.0f : static_cast<float>(m_alpha_hits[i] * inv);
    }
    if (m_settings.aovs) {
        img.depth.resize(n);
        img.normal.resize(n * 3);
        img.albedo.resize(n * 3);
        for (size_t i = 0; i < n; ++i) {
            const AovSums& a = m_aovs[i];
            double inv = a.count > 0.0 ? 1.0 / a.count : 0.0;
            img.depth[i] = a.count > 0.0 ? static_cast<float>(a.depth) : k_no_hit_depth;
            for (int c = 0; c < 3; ++c) {
                img.normal[i * 3 + c] = static_cast<float>(a.normal[c] * inv);
                img.albedo[i * 3 + c] = static_cast<float>(a.albedo[c] * inv);
            }
        }
    }
    return img;
}

FilmHalves Film::resolve_halves(double splat_spp) const {
    FilmHalves out;
    if (!m_settings.halves) return out;
    const size_t n = m_pixels.size();
    // The light paths of one half: those of the camera samples of its parity. Indices [b, e) of
    // parity h number ceil((e - h) / 2) - ceil((b - h) / 2).
    auto of_parity = [](uint64_t b, uint64_t e, int h) -> uint64_t {
        auto upto = [h](uint64_t x) -> uint64_t { return x > static_cast<uint64_t>(h) ? (x - h + 1) / 2 : 0; };
        return e > b ? upto(e) - upto(b) : 0;
    };
    const uint64_t spp = splat_spp > 0.0 ? static_cast<uint64_t>(splat_spp) : 0;
    // As resolve(): per half, the splats over its paths per pixel; with a plan the pilot's and
    // the later paths weighed apart with the same fixed alpha.
    double scale[2] = {0, 0}, pilot_scale[2] = {0, 0};
    for (int h = 0; h < 2; ++h) {
        if (m_plan.empty()) {
            const uint64_t paths = of_parity(0, spp, h);
            scale[h] = paths ? 1.0 / static_cast<double>(paths) : 0.0;
            continue;
        }
        const uint64_t pilot = static_cast<uint64_t>(m_plan_pilot_spp), pilot_h = of_parity(0, pilot, h);
        const double alpha = spp ? std::min(1.0, static_cast<double>(pilot) / static_cast<double>(spp)) : 1.0;
        double post = 0.0;
        for (uint32_t budget : m_plan)
            post += static_cast<double>(of_parity(pilot, std::min<uint64_t>(budget, spp), h));
        if (pilot_h) pilot_scale[h] = post > 0.0 ? alpha / static_cast<double>(pilot_h) : 1.0 / static_cast<double>(pilot_h);
        scale[h] = post > 0.0 ? (1.0 - alpha) * static_cast<double>(n) / post : 0.0;
    }
    out.even.resize(n * 3);
    out.odd.resize(n * 3);
    out.albedo.resize(n * 3);
    out.normal.resize(n * 3);
    out.position.resize(n * 3);
    out.depth.resize(n);
    for (size_t i = 0; i < n; ++i) {
        const Pixel& p = m_pixels[i];
        const HalfSums& o = m_odd[i];
        const double even_weight = p.weight - o.weight;
        for (int c = 0; c < 3; ++c) {
            const double whole = p.weight > 0.0 ? p.sum[c] / p.weight : 0.0;
            // A half without camera samples (one sample per pixel) takes the whole's mean.
            const double odd_mean = o.weight > 0.0 ? o.sum[c] / o.weight : whole;
            const double even_mean = even_weight > 0.0 ? (p.sum[c] - o.sum[c]) / even_weight : whole;
            const double odd_splat = m_odd_splats[i * 3 + c].load(std::memory_order_relaxed);
            const double even_splat = m_splats[i * 3 + c].load(std::memory_order_relaxed) - odd_splat;
            double even = even_mean + even_splat * scale[0], odd = odd_mean + odd_splat * scale[1];
            if (!m_pilot_splats.empty()) {
                const double odd_pilot = m_odd_pilot_splats[i * 3 + c];
                even += (m_pilot_splats[i * 3 + c] - odd_pilot) * pilot_scale[0];
                odd += odd_pilot * pilot_scale[1];
            }
            out.even[i * 3 + c] = static_cast<float>(even);
            out.odd[i * 3 + c] = static_cast<float>(odd);
        }
        // Albedo and normal averaged over every sample (a pixel half covered has half the
        // albedo, as in the AOV passes); position and depth over the samples that hit.
        const FeatureSums& f = m_features[i];
        const double inv = p.weight > 0.0 ? 1.0 / p.weight : 0.0, inv_hits = f.hits > 0.0f ? 1.0 / f.hits : 0.0;
        for (int c = 0; c < 3; ++c) {
            out.albedo[i * 3 + c] = static_cast<float>(f.albedo[c] * inv);
            out.normal[i * 3 + c] = static_cast<float>(f.normal[c] * inv);
            out.position[i * 3 + c] = static_cast<float>(f.position[c] * inv_hits);
        }
        out.depth[i] = f.hits > 0.0f ? static_cast<float>(f.depth * inv_hits) : k_no_hit_depth;
    }
    return out;
}

namespace {
constexpr size_t k_pixel_doubles = 7;  // sum[3], sum_sq[3], weight
constexpr size_t k_aov_doubles = 8;    // normal[3], albedo[3], depth, count
// odd sums[3] and weight, odd splats[3], features: albedo[3], normal[3], depth, hits, position[3]
constexpr size_t k_half_doubles = 4 + 3 + 11;
}  // namespace

size_t Film::state_size(bool with_plan) const {
    size_t n = m_pixels.size();
    return n * k_pixel_doubles + m_aovs.size() * k_aov_doubles + m_alpha_hits.size() + n * 3 +
           (with_plan ? 2 + n * 4 : 0) + (m_settings.halves ? n * (k_half_doubles + (with_plan ? 3 : 0)) : 0);
}

void Film::save_state(double* out) const {
    for (const Pixel& p : m_pixels) {
        for (int c = 0; c < 3; ++c) *out++ = p.sum[c];
        for (int c = 0; c < 3; ++c) *out++ = p.sum_sq[c];
        *out++ = p.weight;
    }
    for (const AovSums& a : m_aovs) {
        for (int c = 0; c < 3; ++c) *out++ = a.normal[c];
        for (int c = 0; c < 3; ++c) *out++ = a.albedo[c];
        *out++ = a.depth;
        *out++ = a.count;
    }
    for (double hits : m_alpha_hits) *out++ = hits;
    for (size_t i = 0; i < m_pixels.size() * 3; ++i) *out++ = m_splats[i].load(std::memory_order_relaxed);
    if (!m_plan.empty()) {
        *out++ = m_plan_target;
        *out++ = m_plan_pilot_spp;
        for (uint32_t budget : m_plan) *out++ = budget;
        for (double v : m_pilot_splats) *out++ = v;
    }
    save_halves(out, !m_plan.empty());
}

// The halves' state, after everything else: with_plan adds the odd pilot splats.
void Film::save_halves(double* out, bool with_plan) const {
    if (!m_settings.halves) return;
    for (size_t i = 0; i < m_odd.size(); ++i) {
        const HalfSums& o = m_odd[i];
        const FeatureSums& f = m_features[i];
        for (int c = 0; c < 3; ++c) *out++ = o.sum[c];
        *out++ = o.weight;
        for (int c = 0; c < 3; ++c) *out++ = m_odd_splats[i * 3 + c].load(std::memory_order_relaxed);
        for (int c = 0; c < 3; ++c) *out++ = f.albedo[c];
        for (int c = 0; c < 3; ++c) *out++ = f.normal[c];
        *out++ = f.depth;
        *out++ = f.hits;
        for (int c = 0; c < 3; ++c) *out++ = f.position[c];
    }
    if (with_plan)
        for (double v : m_odd_pilot_splats) *out++ = v;
}

void Film::load_halves(const double* in, bool with_plan) {
    if (!m_settings.halves) return;
    for (size_t i = 0; i < m_odd.size(); ++i) {
        HalfSums& o = m_odd[i];
        FeatureSums& f = m_features[i];
        for (int c = 0; c < 3; ++c) o.sum[c] = *in++;
        o.weight = *in++;
        for (int c = 0; c < 3; ++c) m_odd_splats[i * 3 + c].store(*in++, std::memory_order_relaxed);
        for (int c = 0; c < 3; ++c) f.albedo[c] = static_cast<float>(*in++);
        for (int c = 0; c < 3; ++c) f.normal[c] = static_cast<float>(*in++);
        f.depth = static_cast<float>(*in++);
        f.hits = static_cast<float>(*in++);
        for (int c = 0; c < 3; ++c) f.position[c] = *in++;
    }
    m_odd_pilot_splats.clear();
    if (with_plan) m_odd_pilot_splats.assign(in, in + m_odd.size() * 3);
}

void Film::load_state(const double* in, size_t count) {
    const bool with_plan = count == state_size(true);
    if (!with_plan && count != state_size(false)) throw std::invalid_argument("film state of the wrong size");
    for (Pixel& p : m_pixels) {
        for (int c = 0; c < 3; ++c) p.sum[c] = *in++;
        for (int c = 0; c < 3; ++c) p.sum_sq[c] = *in++;
        p.weight = *in++;
    }
    for (AovSums& a : m_aovs) {
        for (int c = 0; c < 3; ++c) a.normal[c] = *in++;
        for (int c = 0; c < 3; ++c) a.albedo[c] = *in++;
        a.depth = *in++;
        a.count = *in++;
    }
    for (double& hits : m_alpha_hits) hits = *in++;
    bool any = false;
    for (size_t i = 0; i < m_pixels.size() * 3; ++i) {
        m_splats[i].store(*in, std::memory_order_relaxed);
        any = any || *in != 0.0;
        ++in;
    }
    m_plan.clear();
    m_pilot_splats.clear();
    m_plan_target = 0;
    m_plan_pilot_spp = 0;
    if (with_plan) {
        m_plan_target = static_cast<float>(*in++);
        m_plan_pilot_spp = static_cast<int>(*in++);
        m_plan.resize(m_pixels.size());
        for (uint32_t& budget : m_plan) budget = static_cast<uint32_t>(*in++);
        m_pilot_splats.assign(in, in + m_pixels.size() * 3);
        in += m_pixels.size() * 3;
        for (double v : m_pilot_splats) any = any || v != 0.0;
    }
    load_halves(in, with_plan);
    m_has_splats.store(any, std::memory_order_relaxed);
}

void Film::save_pixels(int x0, int y0, int x1, int y1, std::vector<double>* pixels, std::vector<double>* aovs) const {
    pixels->clear();
    aovs->clear();
    for (int y = y0; y < y1; ++y) {
        for (int x = x0; x < x1; ++x) {
            const size_t i = static_cast<size_t>(y) * m_width + x;
            const Pixel& p = m_pixels[i];
            pixels->insert(pixels->end(),
                           {p.sum[0], p.sum[1], p.sum[2], p.sum_sq[0], p.sum_sq[1], p.sum_sq[2], p.weight});
            if (m_aovs.empty()) continue;
            const AovSums& a = m_aovs[i];
            aovs->insert(aovs->end(), {a.normal[0], a.normal[1], a.normal[2], a.albedo[0], a.albedo[1], a.albedo[2],
                                       a.depth, a.count});
        }
    }
}

void Film::add_pixels(int x0, int y0, int x1, int y1, const double* pixels, const double* aovs) {
    for (int y = y0; y < y1; ++y) {
        for (int x = x0; x < x1; ++x) {
            const size_t i = static_cast<size_t>(y) * m_width + x;
            Pixel& p = m_pixels[i];
            for (int c = 0; c < 3; ++c) p.sum[c] += *pixels++;
            for (int c = 0; c < 3; ++c) p.sum_sq[c] += *pixels++;
            p.weight += *pixels++;
            if (m_aovs.empty() || !aovs) continue;
            AovSums& a = m_aovs[i];
            for (int c = 0; c < 3; ++c) a.normal[c] += *aovs++;
            for (int c = 0; c < 3; ++c) a.albedo[c] += *aovs++;
            const double depth = *aovs++, count = *aovs++;
            if (a.count == 0.0 && count > 0.0) a.depth = depth;  // the earliest sample's
            a.count += count;
        }
    }
}

void Film::save_splats(std::vector<double>* splats) const {
    splats->resize(m_pixels.size() * 3);
    for (size_t i = 0; i < splats->size(); ++i) (*splats)[i] = m_splats[i].load(std::memory_order_relaxed);
}

void Film::add_splats(const double* splats) {
    bool any = false;
    for (size_t i = 0; i < m_pixels.size() * 3; ++i) {
        const double v = m_splats[i].load(std::memory_order_relaxed) + splats[i];
        m_splats[i].store(v, std::memory_order_relaxed);
        any = any || v != 0.0;
    }
    if (any) m_has_splats.store(true, std::memory_order_relaxed);
}

}  // namespace veach
