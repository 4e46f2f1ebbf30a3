#include "materials/ggx_energy.h"

#include <array>

#include "materials/microfacet_ggx.h"

namespace veach {
namespace {

// 32 x 32 samples of (mu, sqrt(alpha)); each entry integrates 32 x 32 stratified visible-normal
// samples. The estimand G2 / G1 is smooth and bounded by 1, so the quadrature error (~1e-4) is far
// below the 2% the furnace tests allow.
constexpr int k_n = 32;
constexpr int k_strata = 32;
// The first mu row sits just above grazing, where the Smith functions are still finite.
constexpr float k_min_mu = 1e-3f;

struct Tables {
    std::array<GgxAlbedo, k_n * k_n> albedo;  // [roughness row][mu column]
    std::array<GgxAlbedo, k_n> average;
};

float mu_of(int i) { return std::max(k_min_mu, static_cast<float>(i) / (k_n - 1)); }
float alpha_of(int j) {
    float r = static_cast<float>(j) / (k_n - 1);
    return std::max(r * r, k_min_ggx_alpha);
}

// E and E_w by importance sampling the visible normals: f cos / pdf = G2(wo, wi) / G1(wo).
GgxAlbedo integrate(float mu, float alpha) {
    Vec3 wo(std::sqrt(std::max(0.0f, 1.0f - mu * mu)), 0.0f, mu);
    double e = 0, e_w = 0;
    for (int a = 0; a < k_strata; ++a)
        for (int b = 0; b < k_strata; ++b) {
            float u1 = (a + 0.5f) / k_strata, u2 = (b + 0.5f) / k_strata;
            Vec3 h = ggx_sample_visible_normal(wo, alpha, u1, u2);
            Vec3 wi = reflect(wo, h);
            if (wi.z <= 0.0f) continue;
            double w = ggx_g2(wo, wi, alpha) / ggx_g1(wo, alpha);
            float c = clamp(1.0f - dot(wo, h), 0.0f, 1.0f);
            e += w;
            e_w += w * (c * c) * (c * c) * c;
        }
    double n = static_cast<double>(k_strata) * k_strata;
    return {static_cast<float>(std::min(1.0, e / n)), static_cast<float>(e_w / n)};
}

Tables compute() {
    Tables t;
    for (int j = 0; j < k_n; ++j) {
        for (int i = 0; i < k_n; ++i) t.albedo[j * k_n + i] = integrate(mu_of(i), alpha_of(j));
        // 2 int E(mu) mu dmu of the piecewise-linear interpolant, by 8 midpoints per interval.
        double e = 0, e_w = 0;
        const int sub = 8;
        for (int i = 0; i + 1 < k_n; ++i)
            for (int s = 0; s < sub; ++s) {
                float f = (s + 0.5f) / sub;
                float mu = (i + f) / (k_n - 1);
                const GgxAlbedo& a = t.albedo[j * k_n + i];
                const GgxAlbedo& b = t.albedo[j * k_n + i + 1];
                double w = 2.0 * mu / ((k_n - 1) * sub);
                e += w * (a.e + (b.e - a.e) * f);
                e_w += w * (a.e_w + (b.e_w - a.e_w) * f);
            }
        t.average[j] = {static_cast<float>(e), static_cast<float>(e_w)};
    }
    return t;
}

const Tables& tables() {
    static const Tables t = compute();
    return t;
}

// Row coordinate of alpha: the table is uniform in roughness = sqrt(alpha).
void row_of(float alpha, int* j, float* f) {
    float x = clamp(std::sqrt(std::max(alpha, 0.0f)), 0.0f, 1.0f) * (k_n - 1);
    *j = std::min(static_cast<int>(x), k_n - 2);
    *f = x - *j;
}

GgxAlbedo mix(const GgxAlbedo& a, const GgxAlbedo& b, float f) {
    return {a.e + (b.e - a.e) * f, a.e_w + (b.e_w - a.e_w) * f};
}

}  // namespace

GgxAlbedo ggx_albedo(float mu, float alpha) {
    const Tables& t = tables();
    int j;
    float fj;
    row_of(alpha, &j, &fj);
    float x = clamp(mu, 0.0f, 1.0f) * (k_n - 1);
    int i = std::min(static_cast<int>(x), k_n - 2);
    float fi = x - i;
    GgxAlbedo lo = mix(t.albedo[j * k_n + i], t.albedo[j * k_n + i + 1], fi);
    GgxAlbedo hi = mix(t.albedo[(j + 1) * k_n + i], t.albedo[(j + 1) * k_n + i + 1], fi);
    return mix(lo, hi, fj);
}

GgxAlbedo ggx_average_albedo(float alpha) {
    const Tables& t = tables();
    int j;
    float fj;
    row_of(alpha, &j, &fj);
    return mix(t.average[j], t.average[j + 1], fj);
}

}  // namespace veach
