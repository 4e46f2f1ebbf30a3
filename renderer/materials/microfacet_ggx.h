// The GGX (Trowbridge-Reitz) microfacet distribution with the height-correlated Smith masking-
// shadowing function, in a local frame with the normal along +z. alpha = roughness^2 as the
// glTF spec defines it.
#pragma once

#include "core/math.h"

namespace veach {

// Below this alpha the lobe is so narrow that float arithmetic breaks down; roughness 0 is
// clamped here (about 0.0032 roughness), which is indistinguishable from a mirror in an image.
inline constexpr float k_min_ggx_alpha = 1e-5f;

// D(h) = a2 / (pi (cos^2 (a2 - 1) + 1)^2), with the denominator's bracket written as
// sin^2 + a2 cos^2 (the same for a unit h): the textbook form rounds a2 - 1 to -1 in float once
// a2 < 3e-8 (roughness 0.0131) and then divides by zero at the peak. This one keeps full relative
// precision for every alpha, down to k_min_ggx_alpha.
inline float ggx_d(const Vec3& h, float alpha) {
    if (h.z <= 0.0f) return 0.0f;
    float a2 = alpha * alpha;
    float t = (h.x * h.x + h.y * h.y) + h.z * h.z * a2;
    return a2 / (k_pi * t * t);
}

// Smith's Lambda for GGX.
inline float ggx_lambda(const Vec3& w, float alpha) {
    float cos2 = w.z * w.z;
    if (cos2 <= 0.0f) return k_infinity;
    float tan2 = std::max(0.0f, 1.0f - cos2) / cos2;
    return 0.5f * (-1.0f + std::sqrt(1.0f + alpha * alpha * tan2));
}

inline float ggx_g1(const Vec3& w, float alpha) { return 1.0f / (1.0f + ggx_lambda(w, alpha)); }

// Height-correlated masking-shadowing G2 (Heitz 2014), what glTF's Appendix B specifies.
inline float ggx_g2(const Vec3& wo, const Vec3& wi, float alpha) {
    return 1.0f / (1.0f + ggx_lambda(wo, alpha) + ggx_lambda(wi, alpha));
}

// A microfacet normal from the distribution of normals visible from wo (Heitz 2018). The density
// of the reflected direction is ggx_reflection_pdf_w.
inline Vec3 ggx_sample_visible_normal(const Vec3& wo, float alpha, float u1, float u2) {
    Vec3 vh = normalize(Vec3(alpha * wo.x, alpha * wo.y, wo.z));
    float lensq = vh.x * vh.x + vh.y * vh.y;
    Vec3 t1 = lensq > 0.0f ? Vec3(-vh.y, vh.x, 0.0f) / std::sqrt(lensq) : Vec3(1.0f, 0.0f, 0.0f);
    Vec3 t2 = cross(vh, t1);
    float r = std::sqrt(u1);
    float phi = 2.0f * k_pi * u2;
    float p1 = r * std::cos(phi);
    float p2 = r * std::sin(phi);
    float s = 0.5f * (1.0f + vh.z);
    p2 = (1.0f - s) * safe_sqrt(1.0f - p1 * p1) + s * p2;
    Vec3 nh = t1 * p1 + t2 * p2 + vh * safe_sqrt(1.0f - p1 * p1 - p2 * p2);
    return normalize(Vec3(alpha * nh.x, alpha * nh.y, std::max(1e-6f, nh.z)));
}

// Solid-angle density of wi = reflect(wo, h) when h is drawn from the visible normals:
// D_wo(h) / (4 wo.h) = G1(wo) D(h) / (4 wo.z).
inline float ggx_reflection_pdf_w(const Vec3& wo, const Vec3& h, float alpha) {
    if (wo.z <= 0.0f) return 0.0f;
    return ggx_g1(wo, alpha) * ggx_d(h, alpha) / (4.0f * wo.z);
}

inline Vec3 reflect(const Vec3& w, const Vec3& n) { return n * (2.0f * dot(w, n)) - w; }

}  // namespace veach
