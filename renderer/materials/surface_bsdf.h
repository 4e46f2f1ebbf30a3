// A material's BSDF placed on a surface: world-space directions, the shading frame, the
// geometric-normal checks that stop light leaking through surfaces, and the transport mode.
//
// Shading normals make a BSDF non-symmetric (Veach 1997, section 5.3). In radiance mode the
// integrand is f(wo, wi) |wi.ns|. In importance mode (particles from lights, wo the direction
// the particle arrived from) the adjoint carries the factor |wo.ns| |wi.ng| / (|wo.ng| |wi.ns|),
// without which light tracing disagrees with path tracing on every smooth-shaded mesh.
#pragma once

#include "core/math.h"
#include "materials/gltf_material.h"

namespace veach {

class SurfaceBsdf {
public:
    SurfaceBsdf() : m_bsdf(ShadingInputs{}) {}
    // ng and ns as in SurfaceHit (same side); wo the direction back along the arriving ray.
    // Every face renders two-sided, as in Cycles: the normals are flipped toward wo.
    SurfaceBsdf(const Vec3& ng, const Vec3& ns, const Vec3& wo, const ShadingInputs& in)
        : m_bsdf(in) {
        float side = dot(wo, ng) < 0.0f ? -1.0f : 1.0f;
        m_ng = ng * side;
        Vec3 n = ns * side;
        // A shading normal that faces away from the viewer would make the surface black;
        // fall back to the geometric normal there.
        if (dot(wo, n) <= 0.0f) n = m_ng;
        m_frame = Frame(n);
    }

    const Vec3& geometric_normal() const { return m_ng; }  // on wo's side
    const Vec3& shading_normal() const { return m_frame.n; }
    bool is_black() const { return m_bsdf.is_black(); }

    // f(wo, wi) |wi.ns| (times the adjoint correction in importance mode).
    Rgb eval(const Vec3& wo, const Vec3& wi, TransportMode mode) const {
        if (dot(wi, m_ng) <= 0.0f) return Rgb(0.0f);  // reflection only, on wo's side
        Vec3 lo = m_frame.to_local(wo), li = m_frame.to_local(wi);
        Rgb f = m_bsdf.eval(lo, li) * std::fabs(li.z);
        if (mode == TransportMode::Importance) f *= importance_correction(wo, wi, lo.z, li.z);
        return f;
    }
    float pdf_w(const Vec3& wo, const Vec3& wi) const {
        if (dot(wi, m_ng) <= 0.0f) return 0.0f;
        return m_bsdf.pdf_w(m_frame.to_local(wo), m_frame.to_local(wi));
    }
    // Samples wi. For non-delta lobes weight = eval / pdf.
    bool sample(const Vec3& wo, float u_lobe, float u1, float u2, TransportMode mode, BsdfSample* out) const {
        Vec3 lo = m_frame.to_local(wo);
        BsdfSample ls;
        if (!m_bsdf.sample(lo, u_lobe, u1, u2, &ls)) return false;
        out->wi = m_frame.to_world(ls.wi);
        if (dot(out->wi, m_ng) <= 0.0f) return false;
        out->pdf_w = ls.pdf_w;
        out->delta = ls.delta;
        out->weight = ls.weight;
        if (mode == TransportMode::Importance) out->weight *= importance_correction(wo, out->wi, lo.z, ls.wi.z);
        return true;
    }
    bool is_pure_delta() const { return m_bsdf.is_pure_delta(); }

private:
    float importance_correction(const Vec3& wo, const Vec3& wi, float wo_ns, float wi_ns) const {
        float num = std::fabs(wo_ns) * std::fabs(dot(wi, m_ng));
        float den = std::fabs(dot(wo, m_ng)) * std::fabs(wi_ns);
        return den > 0.0f ? num / den : 0.0f;
    }

    Vec3 m_ng;
    Frame m_frame;
    GltfBsdf m_bsdf;
};

}  // namespace veach
