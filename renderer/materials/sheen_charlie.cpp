#include "materials/sheen_charlie.h"

#include <array>

#include "core/sampling.h"

namespace veach {
namespace {

// 32 x 32 entries over (mu, roughness in [k_min_sheen_roughness, 1]), each a 48 x 48 stratified
// cosine-weighted quadrature: f cos / pdf = pi D V.
constexpr int k_n = 32;
constexpr int k_strata = 48;

float mu_of(int i) { return std::max(1e-3f, static_cast<float>(i) / (k_n - 1)); }
float roughness_of(int j) {
    return k_min_sheen_roughness + (1.0f - k_min_sheen_roughness) * static_cast<float>(j) / (k_n - 1);
}

std::array<float, k_n * k_n> compute() {
    std::array<float, k_n * k_n> t{};
    for (int j = 0; j < k_n; ++j)
        for (int i = 0; i < k_n; ++i) {
            float mu = mu_of(i), alpha = sheen_alpha(roughness_of(j));
            Vec3 wo(std::sqrt(1.0f - mu * mu), 0.0f, mu);
            double sum = 0;
            for (int a = 0; a < k_strata; ++a)
                for (int b = 0; b < k_strata; ++b) {
                    Vec3 wi = sample_cosine_hemisphere((a + 0.5f) / k_strata, (b + 0.5f) / k_strata);
                    if (wi.z <= 0.0f) continue;
                    sum += k_pi * sheen_eval(wo, wi, alpha);
                }
            t[j * k_n + i] = static_cast<float>(std::min(1.0, sum / (k_strata * k_strata)));
        }
    return t;
}

}  // namespace

float sheen_albedo(float mu, float roughness) {
    static const std::array<float, k_n* k_n> table = compute();
    float y = clamp((roughness - k_min_sheen_roughness) / (1.0f - k_min_sheen_roughness), 0.0f, 1.0f) * (k_n - 1);
    int j = std::min(static_cast<int>(y), k_n - 2);
    float fj = y - j;
    float x = clamp(mu, 0.0f, 1.0f) * (k_n - 1);
    int i = std::min(static_cast<int>(x), k_n - 2);
    float fi = x - i;
    auto at = [&](int jj, int ii) { return table[jj * k_n + ii]; };
    float lo = at(j, i) + (at(j, i + 1) - at(j, i)) * fi;
    float hi = at(j + 1, i) + (at(j + 1, i + 1) - at(j + 1, i)) * fi;
    return lo + (hi - lo) * fj;
}

}  // namespace veach
