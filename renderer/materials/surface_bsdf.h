// A material's BSDF placed on a surface: world-space directions, the shading frame, the
// geometric-normal checks that stop light leaking through surfaces, and the transport mode.
//
// Shading normals make a BSDF non-symmetric (Veach 1997, section 5.3). In radiance mode the
// integrand is f(wo, wi) |wi.ns|. In importance mode (particles from lights, wo the direction
// the particle arrived from) the adjoint carries the factor |wo.ns| |wi.ng| / (|wo.ng| |wi.ns|),
// without which light tracing disagrees with path tracing on every smooth-shaded mesh.
//
// A normal map on an opaque material is not a shading frame: ns stays the vertex normal and the
// mapped normal becomes a facet of a microsurface (normal_map_microsurface.h), whose BSDF is
// reciprocal and conserves energy, so the adjoint factor is the vertex normal's alone (1 on flat
// geometry) and light tracing's weights stay bounded. Transmissive materials keep the mapped
// normal as their frame.
//
// Reflection and transmission are told apart by the geometric normal: wi on wo's side of the
// surface is a reflection, wi on the other side a transmission (only transmissive materials
// have one). A direction whose side by the shading normal disagrees with its side by the
// geometric normal gets nothing: that is how light would leak through a smooth-shaded surface.
#pragma once

#include "core/math.h"
#include "core/rng.h"
#include "materials/gltf_bsdf.h"
#include "materials/normal_map_microsurface.h"
#include "materials/transport_mode.h"

namespace veach {

class SurfaceBsdf {
public:
    // Black, and exactly Lambertian so that it builds nothing (a microfacet default would build
    // lobes, and the first one the Kulla-Conty tables, for every unfilled path-vertex slot).
    SurfaceBsdf() : m_bsdf(black_inputs()) {}
    // ng and ns as in SurfaceHit (same side); wo the direction back along the arriving ray.
    // Every face renders two-sided, as in Cycles: the normals are flipped toward wo.
    // ns_coat: the clearcoat's own shading normal (SurfaceHit::ns_coat, same side as ng), used
    // only when the material has a coat and it differs from ns; zero means "ns".
    SurfaceBsdf(const Vec3& ng, const Vec3& ns, const Vec3& wo, const ShadingInputs& in,
                const Vec3& ns_coat = Vec3(0.0f, 0.0f, 0.0f))
        : m_bsdf(in, dot(wo, ng) < 0.0f && !in.thin_walled ? 1.0f / in.ior : in.ior), m_thin(in.thin_walled) {
        // ng comes from the winding, so wo on its side means arriving from outside a closed
        // transmissive mesh: the far side is the interior with relative index ior.
        float side = dot(wo, ng) < 0.0f ? -1.0f : 1.0f;
        m_entering = side > 0.0f;
        m_ng = ng * side;
        face(ns * side, wo, in, ns_coat, side);
    }
    // With a normal map: ns is the vertex normal and n_map the mapped normal (SurfaceHit's
    // ns_vertex and ns). An opaque material sits on the mapped facet of the microsurface; a
    // transmissive one takes the mapped normal as its frame.
    struct NormalMapped {};
    SurfaceBsdf(NormalMapped, const Vec3& ng, const Vec3& ns, const Vec3& n_map, const Vec3& wo,
                const ShadingInputs& in, const Vec3& ns_coat = Vec3(0.0f, 0.0f, 0.0f));

    const Vec3& geometric_normal() const { return m_ng; }  // on wo's side
    const Vec3& shading_normal() const { return m_frame.n; }
    bool is_black() const { return m_bsdf.is_black(); }
    bool has_transmission() const { return m_bsdf.has_transmission(); }
    // True when wo arrived on the front (winding) side: a transmission enters the mesh.
    bool entering() const { return m_entering; }
    // KHR_materials_volume: the absorption of the medium a segment leaving this surface toward w
    // travels in. On wo's side it is the medium the path arrived through (`arrived`); across a
    // transmissive surface it is the interior of `material`'s mesh when entering and air when
    // leaving (closed, non-nested meshes); a thin wall has no interior. The interior's absorption (logarithms) is computed
    // only for a crossing.
    Rgb medium_toward(const Vec3& w, const Rgb& arrived, const Material& material) const {
        if (!has_transmission() || m_thin || dot(w, m_ng) >= 0.0f) return arrived;
        return m_entering ? material.absorption() : Rgb(0.0f);
    }

    // f(wo, wi) |wi.ns| (times the adjoint correction in importance mode).
    Rgb eval(const Vec3& wo, const Vec3& wi, TransportMode mode) const {
        Vec3 lo = m_frame.to_local(wo), li = m_frame.to_local(wi);
        if (!consistent(wo, lo) || !consistent(wi, li)) return Rgb(0.0f);
        Rgb f = m_mapped ? microsurface().eval(m_bsdf, lo, li, direction_key(li), mode)
                         : m_bsdf.eval(lo, li, mode) * std::fabs(li.z);
        if (mode == TransportMode::Importance) f *= importance_correction(wo, wi, lo.z, li.z);
        return f;
    }
    // Also answers reverse queries pdf_w(wi, wo) with the first direction on either side.
    float pdf_w(const Vec3& wo, const Vec3& wi) const {
        Vec3 lo = m_frame.to_local(wo), li = m_frame.to_local(wi);
        if (!consistent(wo, lo) || !consistent(wi, li)) return 0.0f;
        return m_mapped ? microsurface().pdf_w(m_bsdf, lo, li) : m_bsdf.pdf_w(lo, li);
    }
    // Samples wi. For non-delta lobes weight = eval / pdf.
    bool sample(const Vec3& wo, float u_lobe, float u1, float u2, TransportMode mode, BsdfSample* out) const {
        Vec3 lo = m_frame.to_local(wo);
        BsdfSample ls;
        if (m_mapped) {
            uint64_t key = direction_key(Vec3(u_lobe, u1, u2)) ^ 0x5bd1e9955bd1e995ull;
            if (!microsurface().sample(m_bsdf, lo, u_lobe, u1, u2, key, mode, &ls)) return false;
        } else if (!m_bsdf.sample(lo, u_lobe, u1, u2, &ls, mode)) {
            return false;
        }
        out->wi = m_frame.to_world(ls.wi);
        if (!consistent(out->wi, ls.wi)) return false;
        out->pdf_w = ls.pdf_w;
        out->delta = ls.delta;
        out->weight = ls.weight;
        if (mode == TransportMode::Importance) out->weight *= importance_correction(wo, out->wi, lo.z, ls.wi.z);
        return true;
    }
    bool is_pure_delta() const { return m_bsdf.is_pure_delta(); }

private:
    // The shading frame about n (on wo's side) and what depends on wo; ns_coat as given to the
    // constructor, turned to wo's side by `side`.
    void face(const Vec3& n, const Vec3& wo, const ShadingInputs& in, const Vec3& ns_coat, float side) {
        // The frame depends on the surface point and the side only, never on wo: a frame chosen
        // per viewing direction (e.g. falling back to ng when wo is below ns) would make the
        // BSDF non-reciprocal, and light tracing would then disagree with path tracing at the
        // terminator of every smooth low-poly mesh. Directions below ns see a black BSDF.
        m_frame = Frame(n);
        // Integrators ask about this wo again and again (light sample, MIS density, sampling):
        // the BSDF computes what depends on it once.
        if (in.clearcoat > 0.0f && (ns_coat.x != 0.0f || ns_coat.y != 0.0f || ns_coat.z != 0.0f))
            m_bsdf.set_coat_normal(m_frame.to_local(ns_coat * side));
        m_bsdf.set_outgoing(m_frame.to_local(wo));
    }
    // The normal map's microsurface on the vertex normal n (on wo's side), the mapped normal
    // n_map and the coat's normal (zero: the base's) on the same side. False when the mapped
    // normal is the vertex normal: the plain BSDF applies.
    bool place_on_microsurface(const Vec3& n, const Vec3& wo, const ShadingInputs& in, const Vec3& ns_coat,
                               const Vec3& n_map);
    NormalMapMicrosurface microsurface() const { return NormalMapMicrosurface(Vec3(m_map[0], m_map[1], m_map[2])); }

    static ShadingInputs black_inputs() {
        ShadingInputs in;
        in.base_color = Rgb(0.0f);
        in.dielectric_f0 = Rgb(0.0f);
        in.dielectric_f90 = 0.0f;
        return in;
    }
    float importance_correction(const Vec3& wo, const Vec3& wi, float wo_ns, float wi_ns) const {
        float num = std::fabs(wo_ns) * std::fabs(dot(wi, m_ng));
        float den = std::fabs(dot(wo, m_ng)) * std::fabs(wi_ns);
        return den > 0.0f ? num / den : 0.0f;
    }

    // The key of a random walk: this BSDF's (its wo's bits) with a direction's bits.
    uint64_t direction_key(const Vec3& w) const {
        return mix64(m_key ^ (uint64_t(float_bits(w.x)) << 32 | float_bits(w.y)) ^ uint64_t(float_bits(w.z)) << 16);
    }

    // The same side of the surface by the geometric and by the shading normal (local z).
    bool consistent(const Vec3& w, const Vec3& local) const {
        float g = dot(w, m_ng);
        return (g > 0.0f && local.z > 0.0f) || (g < 0.0f && local.z < 0.0f);
    }

    Vec3 m_ng;
    Frame m_frame;
    GltfBsdf m_bsdf;
    // A normal map on an opaque material: the mapped normal in the frame, as given to
    // NormalMapMicrosurface (rebuilt by each query, which keeps the BSDF small for the integrators
    // that store one per path vertex), and the key of its random walks. Set only when m_mapped.
    float m_map[3] = {0.0f, 0.0f, 1.0f};
    uint64_t m_key = 0;
    bool m_thin = false;  // a thin wall: air on both sides, no medium entered
    bool m_entering = true;
    bool m_mapped = false;
};

}  // namespace veach
