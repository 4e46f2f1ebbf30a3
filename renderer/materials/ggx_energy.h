// Energy lost by single-scattering GGX, and the multiple-scattering lobe that gives it back
// (Kulla & Conty 2017, "Revisiting Physically Based Shading at Imageworks").
//
// A microfacet BRDF that counts one bounce on the microsurface loses the light that bounces
// twice or more: a white metal at roughness 1 reflects only ~60% at grazing incidence. With
// E(mu) the directional albedo of the single-scattering lobe with F = 1 and
// E_avg = 2 int_0^1 E(mu) mu dmu its cosine-weighted average, the lobe
//
//   f_ms(wo, wi) = (1 - E(mu_o)) (1 - E(mu_i)) / (pi (1 - E_avg))                     (KC 2017, eq. 2)
//
// is symmetric in (wo, wi) (reciprocal) and integrates against mu_i to exactly 1 - E(mu_o): a white
// metal becomes a perfect reflector at every roughness. A Fresnel F < 1 scales it by
//
//   F_ms = F_avg^2 E_avg / (1 - F_avg (1 - E_avg))                                     (KC 2017, eq. 6)
//
// the energy of the light that leaves after a geometric series of bounces, each absorbing
// 1 - F_avg. For Schlick's F = F0 + (F90 - F0) (1 - cos)^5, F_avg = F0 + (F90 - F0) / 21.
//
// The tables are computed by our own quadrature the first time they are needed (a function-local
// static: thread-safe initialisation, immutable afterwards, deterministic).
#pragma once

#include "core/math.h"
#include "core/rgb.h"

namespace veach {

struct GgxAlbedo {
    float e = 1;    // integral of D G2 / (4 mu_o mu_i) * mu_i over the hemisphere (F = 1)
    float e_w = 0;  // the same weighted by Schlick's (1 - wo.h)^5
};

// Directional albedos at mu = cos(theta_o), bilinearly interpolated in (mu, sqrt(alpha)).
GgxAlbedo ggx_albedo(float mu, float alpha);
// Their cosine-weighted hemispherical averages 2 int E(mu) mu dmu.
GgxAlbedo ggx_average_albedo(float alpha);

// The lobe shape (1 - E(mu_o)) (1 - E(mu_i)) / (pi (1 - E_avg)), zero when nothing is lost.
inline float ggx_multiple_scattering(float e_o, float e_i, float e_avg) {
    float lost = 1.0f - e_avg;
    if (!(lost > 1e-6f)) return 0.0f;
    return std::max(0.0f, 1.0f - e_o) * std::max(0.0f, 1.0f - e_i) / (k_pi * lost);
}

// F_ms of KC 2017 eq. 6 per channel, for Schlick's Fresnel between f0 and f90.
inline Rgb ggx_multiple_scattering_fresnel(const Rgb& f0, const Rgb& f90, float e_avg) {
    auto one = [e_avg](float a, float b) {
        float f_avg = a + (b - a) * (1.0f / 21.0f);
        float den = 1.0f - f_avg * (1.0f - e_avg);
        return den > 0.0f ? f_avg * f_avg * e_avg / den : 0.0f;
    };
    return {one(f0.r, f90.r), one(f0.g, f90.g), one(f0.b, f90.b)};
}

}  // namespace veach
