// The Lambertian lobe: f = albedo / pi, sampled by the cosine-weighted hemisphere.
#pragma once

#include "core/rgb.h"
#include "core/sampling.h"

namespace veach {

inline Rgb lambert_eval(const Rgb& albedo, const Vec3& wo, const Vec3& wi) {
    return (wo.z > 0.0f && wi.z > 0.0f) ? albedo * k_inv_pi : Rgb(0.0f);
}
inline float lambert_pdf_w(const Vec3& wo, const Vec3& wi) {
    return wo.z > 0.0f ? cosine_hemisphere_pdf_w(wi.z) : 0.0f;
}
inline Vec3 lambert_sample(float u1, float u2) { return sample_cosine_hemisphere(u1, u2); }

}  // namespace veach
