// A normal map as a microsurface (after Schüssler, Heitz, Hanika and Dachsbacher 2017,
// "Microfacet-based Normal Mapping for Robust Monte Carlo Path Tracing"). A mapped normal wp is
// not used as the shading frame: the surface point is a tiny groove made of two facets, the
// perturbed facet (normal wp, the material's BSDF) and a tangent facet (a vertical mirror wall,
// normal wt = -wp's horizontal part), sized so that their projected areas add up to the macro
// surface's in every direction (the area-weighted mean normal is the macro normal). Light
// reaching the point hits one facet or the other, may bounce between them, and leaves. The BSDF
// of that microsurface is reciprocal and conserves energy by construction (a white material
// reflects everything: the walls only redirect), so light tracing needs no adjoint correction
// and its weights stay bounded; strong grooves come out darker than flat by the light absorbed
// in the extra bounces, not by light lost.
//
// Everything here is in the macro frame (z = the vertex normal on wo's side), directions point
// away from the surface, and the material's BSDF fp is evaluated in the perturbed facet's own
// frame. With A_p = 1 / cos(theta_p) and A_t = tan(theta_p) (facet areas per unit macro area):
//
//   projected areas  a_p(w) = <w, wp>+ / wp.z,   a_t(w) = <w, wt>+ sin(theta_p) / wp.z
//   first facet hit  lambda_p(w) = a_p / (a_p + a_t),  lambda_t = 1 - lambda_p
//   leaving a facet  G1(w) = min(1, w.z+ / (a_p(w) + a_t(w)))   (the chance to escape along w)
//
// A ray leaving one facet that does not escape hits the other one. The BSDF sums all the paths
// through the two facets. sample() follows them (a random walk: weights are products of fp's
// weights, never above fp's albedo); eval() is an unbiased random-walk estimate with, at every
// visit of the perturbed facet, the paths leaving toward wi directly or by one mirror on the wall
// (Heitz et al. 2016's stochastic evaluation): reciprocal in expectation. pdf_w() is a
// deterministic density for multiple importance sampling only (the single- and double-bounce
// densities plus a cosine floor); sample() returns it, so every strategy weighs with the same
// function. Opaque materials only: transmission keeps the shading-normal frame (SurfaceBsdf).
#pragma once

#include <cstdint>

#include "core/math.h"
#include "materials/gltf_bsdf.h"

namespace veach {

class NormalMapMicrosurface {
public:
    NormalMapMicrosurface() = default;  // inactive: no tilt
    // wp: the mapped normal in the macro frame (unit). Below or too close to the macro surface it
    // is bent up to k_min_cos, keeping its azimuth.
    explicit NormalMapMicrosurface(const Vec3& wp);

    // False when wp is the macro normal (within float noise): the plain BSDF applies.
    bool active() const { return m_active; }
    // The perturbed facet's frame in the macro frame: fp's directions are p().to_local(w).
    const Frame& p() const { return m_p; }

    // f(wo, wi) wi.z of the microsurface, estimated by a random walk keyed by `key` (the same key
    // and directions give the same estimate).
    Rgb eval(const GltfBsdf& fp, const Vec3& wo, const Vec3& wi, uint64_t key, TransportMode mode) const;
    float pdf_w(const GltfBsdf& fp, const Vec3& wo, const Vec3& wi) const;
    // The first facet is chosen with u_lobe, the first visit of the perturbed facet samples fp
    // with (u_lobe rescaled, u1, u2); the rest of the walk draws from a stream keyed by `key`.
    bool sample(const GltfBsdf& fp, const Vec3& wo, float u_lobe, float u1, float u2, uint64_t key,
                TransportMode mode, BsdfSample* out) const;

    float lambda_p(const Vec3& w) const;
    float g1(const Vec3& w) const;
    // The mirror image of w in the tangent facet (its wt component reversed).
    Vec3 mirror_t(const Vec3& w) const { return w - m_wt * (2.0f * dot(w, m_wt)); }

    // Bent below this cosine to the macro normal: deeper grooves than 87 degrees need walks of
    // hundreds of bounces.
    static constexpr float k_min_cos = 0.05f;
    // Longest walk followed; the rest is dropped. Deep grooves make long walks: a white Lambert
    // on 80-degree grooves lost 0.25% to a cap of 64 events and nothing measurable (1 in 20,000
    // walks) to 128; at 60 degrees 64 already lost nothing.
    static constexpr int k_max_events = 256;

private:
    // fp's integrand toward wi from a visit of the perturbed facet arriving from `a` (fp's frame):
    // leaving directly, or by one mirror on the wall, then escaping.
    Rgb next_event(const GltfBsdf& fp, const Vec3& a, const Vec3& wi, float g1_wi, TransportMode mode) const;

    Frame m_p;
    Vec3 m_wp{0.0f, 0.0f, 1.0f}, m_wt{1.0f, 0.0f, 0.0f};
    float m_sin_p = 0.0f;
    bool m_active = false;
};

}  // namespace veach
