// Fresnel reflectance: Schlick's approximation (what glTF's Appendix B specifies for opaque
// materials) and the exact dielectric equations (for refraction, where total internal reflection
// must come out of the physics rather than an approximation).
#pragma once

#include "core/math.h"

namespace veach {

// (1 - cos)^5, the weight of F90 in Schlick's F = F0 + (F90 - F0) (1 - cos)^5.
inline float schlick_weight(float cos_theta) {
    float m = clamp(1.0f - cos_theta, 0.0f, 1.0f);
    float m2 = m * m;
    return m2 * m2 * m;
}

// Unpolarised Fresnel reflectance of a smooth dielectric interface for light arriving at cos_i
// (> 0) on the side whose index is 1, the other side having relative index eta (Born & Wolf;
// Walter et al. 2007 eq. 22). 1 under total internal reflection (eta < 1).
inline float fresnel_dielectric(float cos_i, float eta) {
    cos_i = clamp(cos_i, 0.0f, 1.0f);
    float sin2_t = (1.0f - cos_i * cos_i) / (eta * eta);
    if (sin2_t >= 1.0f) return 1.0f;
    float cos_t = std::sqrt(1.0f - sin2_t);
    float rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    float rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    return 0.5f * (rs * rs + rp * rp);
}

// Snell refraction of w (pointing away from the surface, w.n > 0) through the interface with
// normal n into the side of relative index eta. False under total internal reflection.
inline bool refract(const Vec3& w, const Vec3& n, float eta, Vec3* out) {
    float cos_i = dot(w, n);
    float sin2_t = std::max(0.0f, 1.0f - cos_i * cos_i) / (eta * eta);
    if (sin2_t >= 1.0f) return false;
    float cos_t = std::sqrt(1.0f - sin2_t);
    *out = -w / eta + n * (cos_i / eta - cos_t);
    return true;
}

}  // namespace veach
