// KHR_materials_sheen: the "Charlie" sheen lobe of Estevez & Kulla 2017 (Production Friendly
// Microfacet Sheen BRDF), as the extension specifies it, with Ashikhmin's visibility term
// (Ashikhmin & Premoze 2007), which the extension allows:
//
//   f_sheen = sheenColor * D(h) * V(wo, wi)
//   D(h)    = (2 + 1/a) sin(theta_h)^(1/a) / (2 pi),          a = sheenRoughness^2
//   V       = 1 / (4 (mu_i + mu_o - mu_i mu_o))
//
// Both are symmetric in (wo, wi). The material beneath is scaled as the extension says,
//
//   base * min(1 - max(sheenColor) E(mu_o), 1 - max(sheenColor) E(mu_i)),
//
// reciprocal, and conserving: the albedo of the whole is at most max(sheenColor) E(mu_o) plus
// (1 - max(sheenColor) E(mu_o)) times the base's. E(mu) = int D V mu_i dw_i comes from a table
// our own quadrature computes the first time it is needed.
#pragma once

#include "core/math.h"

namespace veach {

// Below this roughness the lobe degenerates into a spike at grazing (Estevez & Kulla clamp too).
inline constexpr float k_min_sheen_roughness = 0.07f;

inline float sheen_alpha(float roughness) {
    float r = std::max(roughness, k_min_sheen_roughness);
    return r * r;
}

// D * V for unit sheen colour; wo.z > 0, wi.z > 0.
inline float sheen_eval(const Vec3& wo, const Vec3& wi, float alpha) {
    Vec3 h = normalize(wo + wi);
    float sin2 = std::max(0.0f, 1.0f - h.z * h.z);
    float inv = 1.0f / alpha;
    float d = (2.0f + inv) * std::pow(sin2, 0.5f * inv) / (2.0f * k_pi);
    float v = 1.0f / (4.0f * (wi.z + wo.z - wi.z * wo.z));
    return d * v;
}

// Directional albedo E(mu) of sheen_eval, interpolated in (mu, roughness).
float sheen_albedo(float mu, float roughness);

}  // namespace veach
