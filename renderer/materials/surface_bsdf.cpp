#include "materials/surface_bsdf.h"

namespace veach {

SurfaceBsdf::SurfaceBsdf(NormalMapped, const Vec3& ng, const Vec3& ns, const Vec3& n_map, const Vec3& wo,
                         const ShadingInputs& in, const Vec3& ns_coat)
    : m_bsdf(in, dot(wo, ng) < 0.0f && !in.thin_walled ? 1.0f / in.ior : in.ior), m_thin(in.thin_walled) {
    float side = dot(wo, ng) < 0.0f ? -1.0f : 1.0f;
    m_entering = side > 0.0f;
    m_ng = ng * side;
    // The microsurface is opaque: a transmissive material keeps the mapped normal as its frame.
    if (m_bsdf.has_transmission())
        face(n_map * side, wo, in, ns_coat, side);
    else if (!place_on_microsurface(ns * side, wo, in, ns_coat * side, n_map * side))
        face(ns * side, wo, in, ns_coat, side);
}

bool SurfaceBsdf::place_on_microsurface(const Vec3& n, const Vec3& wo, const ShadingInputs& in, const Vec3& ns_coat,
                                        const Vec3& n_map) {
    m_frame = Frame(n);
    const Vec3 map = m_frame.to_local(n_map);
    NormalMapMicrosurface micro(map);
    if (!micro.active()) return false;
    m_mapped = true;
    m_map[0] = map.x;
    m_map[1] = map.y;
    m_map[2] = map.z;
    // The material sits on the perturbed facet: its directions (and the coat's normal) in that
    // facet's frame. The walks of this BSDF are keyed by wo.
    Vec3 lo = m_frame.to_local(wo);
    m_key = mix64(uint64_t(float_bits(lo.x)) << 32 | float_bits(lo.y)) ^ float_bits(lo.z);
    if (in.clearcoat > 0.0f && (ns_coat.x != 0.0f || ns_coat.y != 0.0f || ns_coat.z != 0.0f))
        m_bsdf.set_coat_normal(micro.p().to_local(m_frame.to_local(ns_coat)));
    m_bsdf.set_outgoing(micro.p().to_local(lo));
    return true;
}

}  // namespace veach
