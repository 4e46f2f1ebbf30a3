#include "core/sampling.h"

#include <algorithm>

namespace veach {

namespace {
// cos and sin of x in [-pi/4, pi/4] by their Taylor series to x^10 and x^11: the truncation
// error there, (pi/4)^12 / 12! < 1e-10, is far below a float's rounding, so this is as exact as
// std::cos / std::sin but a few multiplies instead of a call with range reduction (every cosine
// sample, i.e. every diffuse bounce, maps through here).
void cos_sin_quarter(float x, float* c, float* s) {
    float x2 = x * x;
    *c = 1.0f + x2 * (-1.0f / 2 + x2 * (1.0f / 24 + x2 * (-1.0f / 720 + x2 * (1.0f / 40320 + x2 * (-1.0f / 3628800)))));
    *s = x * (1.0f + x2 * (-1.0f / 6 +
                           x2 * (1.0f / 120 + x2 * (-1.0f / 5040 + x2 * (1.0f / 362880 + x2 * (-1.0f / 39916800))))));
}
}  // namespace

Vec2 sample_concentric_disk(float u1, float u2) {
    // Shirley-Chiu concentric map: area-preserving, low distortion. The angle is within pi/4 of
    // an axis: phi = x (|a| > |b|) or phi = pi/2 - x, with |x| <= pi/4.
    // Written with selects rather than branches: which case applies is a coin flip per sample,
    // which a branch predictor cannot learn.
    float a = 2.0f * u1 - 1.0f, b = 2.0f * u2 - 1.0f;
    if (a == 0.0f && b == 0.0f) return {0.0f, 0.0f};
    bool near_x = std::fabs(a) > std::fabs(b);
    float r = near_x ? a : b, t = near_x ? b : a;
    float c, s;
    cos_sin_quarter((k_pi / 4.0f) * (t / r), &c, &s);
    // phi = x: (r cos x, r sin x); phi = pi/2 - x: cos(pi/2 - x) = sin x, sin(pi/2 - x) = cos x.
    return {r * (near_x ? c : s), r * (near_x ? s : c)};
}

Vec3 sample_cosine_hemisphere(float u1, float u2) {
    // Malley's method: project the uniform disk onto the hemisphere.
    Vec2 d = sample_concentric_disk(u1, u2);
    float z = safe_sqrt(1.0f - d.x * d.x - d.y * d.y);
    return {d.x, d.y, z};
}

Vec3 sample_uniform_sphere(float u1, float u2) {
    float z = 1.0f - 2.0f * u1;
    float r = safe_sqrt(1.0f - z * z);
    float phi = 2.0f * k_pi * u2;
    return {r * std::cos(phi), r * std::sin(phi), z};
}

Vec3 sample_uniform_cone(float u1, float u2, float cos_max) {
    float cos_theta = 1.0f - u1 * (1.0f - cos_max);
    float sin_theta = safe_sqrt(1.0f - cos_theta * cos_theta);
    float phi = 2.0f * k_pi * u2;
    return {sin_theta * std::cos(phi), sin_theta * std::sin(phi), cos_theta};
}

Vec2 sample_uniform_triangle(float u1, float u2) {
    // Heitz 2019, "A Low-Distortion Map Between Triangle and Square".
    float b0, b1;
    if (u2 > u1) {
        b0 = u1 * 0.5f;
        b1 = u2 - b0;
    } else {
        b1 = u2 * 0.5f;
        b0 = u1 - b1;
    }
    return {b0, b1};
}

Distribution1D::Distribution1D(const std::vector<float>& weights) {
    size_t n = weights.size();
    m_pmf.resize(n);
    m_cdf.resize(n + 1);
    double total = 0.0;
    m_cdf[0] = 0.0;
    for (size_t i = 0; i < n; ++i) {
        float w = std::isfinite(weights[i]) && weights[i] > 0.0f ? weights[i] : 0.0f;
        total += w;
        m_cdf[i + 1] = total;
    }
    m_total = static_cast<float>(total);
    for (size_t i = 0; i < n; ++i) {
        float w = std::isfinite(weights[i]) && weights[i] > 0.0f ? weights[i] : 0.0f;
        m_pmf[i] = total > 0.0 ? static_cast<float>(w / total) : 0.0f;
    }
    if (total > 0.0)
        for (double& c : m_cdf) c /= total;
}

size_t Distribution1D::sample(float u, float* pmf, float* u_remapped) const {
    if (m_pmf.empty() || m_total <= 0.0f) {
        if (pmf) *pmf = 0.0f;
        return 0;
    }
    // The first index i with cdf[i + 1] > u, skipping zero-weight entries.
    auto it = std::upper_bound(m_cdf.begin() + 1, m_cdf.end(), static_cast<double>(u));
    size_t i = std::min<size_t>(static_cast<size_t>(it - m_cdf.begin()) - 1, m_pmf.size() - 1);
    while (m_pmf[i] == 0.0f && i > 0) --i;  // u exactly on a boundary of trailing zeros
    if (pmf) *pmf = m_pmf[i];
    if (u_remapped) {
        double width = m_cdf[i + 1] - m_cdf[i];
        float r = width > 0.0 ? static_cast<float>((u - m_cdf[i]) / width) : 0.0f;
        *u_remapped = std::min(std::max(r, 0.0f), 0x1.fffffep-1f);
    }
    return i;
}

}  // namespace veach
