// Warping uniform random numbers to the densities the integrators need. Every function names
// the measure of its density: _w per solid angle, _a per area.
#pragma once

#include <cstdint>
#include <vector>

#include "core/math.h"

namespace veach {

// Cosine-weighted direction in the local frame (z up): pdf_w = cos(theta) / pi.
Vec3 sample_cosine_hemisphere(float u1, float u2);
inline float cosine_hemisphere_pdf_w(float cos_theta) { return cos_theta > 0.0f ? cos_theta * k_inv_pi : 0.0f; }

Vec3 sample_uniform_sphere(float u1, float u2);   // pdf_w = 1 / (4 pi)
Vec2 sample_concentric_disk(float u1, float u2);  // unit disk, pdf_a = 1 / pi

// Barycentric coordinates (b1, b2) uniform over a triangle (Heitz 2019 low-distortion map).
Vec2 sample_uniform_triangle(float u1, float u2);

// Uniform cone around +z with cos_max: pdf_w = 1 / (2 pi (1 - cos_max)).
Vec3 sample_uniform_cone(float u1, float u2, float cos_max);

inline float power_heuristic(float pdf_a, float pdf_b) {
    float a = pdf_a * pdf_a, b = pdf_b * pdf_b;
    if (std::isinf(a)) return 1.0f;
    return a + b > 0.0f ? a / (a + b) : 0.0f;
}

// A discrete distribution over n items by non-negative weight; sampling by binary search on
// the CDF.
class Distribution1D {
public:
    Distribution1D() = default;
    explicit Distribution1D(const std::vector<float>& weights);

    size_t size() const { return m_pmf.size(); }
    float total() const { return m_total; }
    // Returns an index; pmf the probability of choosing it. u_remapped is u rescaled to [0,1)
    // within the chosen bucket, for reuse.
    size_t sample(float u, float* pmf, float* u_remapped = nullptr) const;
    float pmf(size_t i) const { return i < m_pmf.size() ? m_pmf[i] : 0.0f; }

private:
    std::vector<float> m_pmf;
    std::vector<double> m_cdf;  // size n + 1
    float m_total = 0;
};

}  // namespace veach
