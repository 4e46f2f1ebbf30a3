// The rough dielectric interface of KHR_materials_transmission: GGX reflection and refraction
// weighted by the exact Fresnel equations (Walter, Marschner, Li & Torrance 2007, "Microfacet
// Models for Refraction through Rough Surfaces"). Local frame, wo.z > 0 (the caller mirrors the
// frame when wo is below), eta = index of the far side / index of wo's side.
//
//   reflection: f_r = F(wo.h) D(h) G2 / (4 |wo.z| |wi.z|),                h = normalize(wo + wi)
//   refraction: f_t = (1 - F) D(h) G2 |wi.h| |wo.h| / (|wi.z| |wo.z| (wi.h + wo.h / eta)^2) / eta^2
//                                                             h = normalize(wo + eta wi)   (eq. 16, 21)
//
// The 1/eta^2 (radiance mode) is the change of radiance across the interface: radiance is
// compressed into a narrower cone when it enters a denser medium. Particles (importance mode)
// carry flux, which is not rescaled (Veach 1997, section 5.2): there the factor is dropped.
// Sampling draws h from the visible normals of wo and picks reflection with probability F.
#pragma once

#include "core/math.h"
#include "materials/fresnel.h"
#include "materials/microfacet_ggx.h"

namespace veach {

struct DielectricLobeValue {
    float f = 0;      // f(wo, wi), no cosine, before any tint
    float pdf_w = 0;  // density of dielectric_sample producing wi
};

// The generalised half vector on wo's side (+z), or false when wo and wi make no valid pair.
inline bool dielectric_half_vector(const Vec3& wo, const Vec3& wi, float eta, Vec3* h) {
    bool reflect_pair = wi.z > 0.0f;
    Vec3 m = reflect_pair ? wo + wi : wo + wi * eta;
    float len = length(m);
    if (!(len > 0.0f)) return false;
    m = m / len;
    if (m.z < 0.0f) m = -m;
    // Back-facing microfacets contribute nothing (Walter et al. 2007, section 5.1).
    if (dot(wo, m) <= 0.0f || (reflect_pair ? dot(wi, m) <= 0.0f : dot(wi, m) >= 0.0f)) return false;
    *h = m;
    return true;
}

inline DielectricLobeValue dielectric_eval(const Vec3& wo, const Vec3& wi, float alpha, float eta, bool radiance) {
    DielectricLobeValue v;
    Vec3 h;
    if (wo.z <= 0.0f || wi.z == 0.0f || !dielectric_half_vector(wo, wi, eta, &h)) return v;
    float wo_h = dot(wo, h), wi_h = dot(wi, h);
    float fr = fresnel_dielectric(wo_h, eta);
    float d = ggx_d(h, alpha), g2 = ggx_g2(wo, wi, alpha);
    float visible = ggx_g1(wo, alpha) * d * wo_h / wo.z;  // D_wo(h)
    if (wi.z > 0.0f) {
        v.f = fr * d * g2 / (4.0f * wo.z * wi.z);
        v.pdf_w = fr * visible / (4.0f * wo_h);
    } else {
        float den = wi_h + wo_h / eta;
        float jacobian = std::fabs(wi_h) / (den * den);  // dh / dwi (Walter eq. 17, with eta_o = 1)
        v.f = (1.0f - fr) * d * g2 * std::fabs(wi_h) * wo_h / (std::fabs(wi.z) * wo.z * den * den);
        if (radiance) v.f /= eta * eta;
        v.pdf_w = (1.0f - fr) * visible * jacobian;
    }
    return v;
}

// A thin wall (both sides air, no interior): light refracts in and straight back out, so the
// transmitted lobe is the reflection lobe mirrored through the surface plane, weighted by 1 - F
// where reflection is weighted by F (the glTF transmission extension's thin-walled BTDF). No
// radiance is compressed into a denser medium, so there is no 1/eta^2 in either mode; the lobe
// is symmetric in wo and wi (reciprocal), and in a uniform environment reflection plus
// transmission return exactly what arrives (R + T = 1 before the base colour's tint).
inline DielectricLobeValue thin_dielectric_eval(const Vec3& wo, const Vec3& wi, float alpha, float eta) {
    DielectricLobeValue v;
    if (wo.z <= 0.0f || wi.z == 0.0f) return v;
    Vec3 wr(wi.x, wi.y, std::fabs(wi.z));  // wi mirrored to wo's side
    Vec3 m = wo + wr;
    float len = length(m);
    if (!(len > 0.0f)) return v;
    Vec3 h = m / len;
    float wo_h = dot(wo, h);
    if (wo_h <= 0.0f || dot(wr, h) <= 0.0f) return v;
    float fr = fresnel_dielectric(wo_h, eta);
    float share = wi.z > 0.0f ? fr : 1.0f - fr;
    float d = ggx_d(h, alpha);
    v.f = share * d * ggx_g2(wo, wr, alpha) / (4.0f * wo.z * wr.z);
    v.pdf_w = share * ggx_g1(wo, alpha) * d / (4.0f * wo.z);  // D_wo(h) / (4 wo.h), wo.h cancelled
    return v;
}

inline bool thin_dielectric_sample(const Vec3& wo, float alpha, float eta, float u_choice, float u1, float u2,
                                   Vec3* wi, bool* transmitted) {
    Vec3 h = ggx_sample_visible_normal(wo, alpha, u1, u2);
    Vec3 r = reflect(wo, h);
    if (!(r.z > 0.0f)) return false;
    *transmitted = u_choice >= fresnel_dielectric(dot(wo, h), eta);
    *wi = *transmitted ? Vec3(r.x, r.y, -r.z) : r;
    return true;
}

// Draws wi; *transmitted tells which side. The caller computes f and pdf with dielectric_eval
// (rough) or uses the discrete probabilities (smooth, see GltfBsdf).
inline bool dielectric_sample(const Vec3& wo, float alpha, float eta, float u_choice, float u1, float u2, Vec3* wi,
                              bool* transmitted) {
    Vec3 h = ggx_sample_visible_normal(wo, alpha, u1, u2);
    float fr = fresnel_dielectric(dot(wo, h), eta);
    if (u_choice < fr) {
        *wi = reflect(wo, h);
        *transmitted = false;
        return wi->z > 0.0f;
    }
    if (!refract(wo, h, eta, wi)) return false;  // cannot happen: fr = 1 under TIR
    *transmitted = true;
    return wi->z < 0.0f;
}

}  // namespace veach
