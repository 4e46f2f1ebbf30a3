// The shading point: what every integrator (pt, BDPT's subpath vertices) and the AOV pass make of
// a ray's hit, written once, so that a material feature (another normal, another input of a
// lobe) touches this file and the material's, never an integrator. make_shading_point turns the
// hit into the geometry frame (SurfaceHit: the error-bounded point, geometric, shading and
// clearcoat normals, attributes with the ray's footprint in each UV set); the rest is asked for
// when needed, because a path can end before needing it (an emitter seen at the depth limit
// needs no BSDF):
//   emitter: the emissive triangle the point lies on, if any;
//   emitted: what the surface sends toward wo when it is an emitter; its densities (per solid
//     angle toward a receiver, per area and direction as a particle's origin) are the LightSet's
//     queries on the same emitter index;
//   inputs: the material's inputs there (textures read with the hit's footprints), thin-walled
//     as its mesh is;
//   bsdf: the BSDF facing wo.
#pragma once

#include <cstdint>
#include <variant>

#include "integrators/render_scene.h"
#include "integrators/surface_hit.h"
#include "materials/gltf_material.h"
#include "materials/surface_bsdf.h"

namespace veach {

// Radiance a surface of material `m` emits toward unit `wo` at a point with attributes `attr`
// on emitter `emitter` (a LightSet index of an emissive triangle): the emissive texture there,
// times the light's side and strength.
inline Rgb emitted_radiance(const LightSet& lights, const Scene& scene, const Material& m,
                            const SurfaceAttributes& attr, int64_t emitter, const Vec3& wo) {
    const auto& tl = std::get<TriangleLight>(lights.light(static_cast<size_t>(emitter)));
    return tl.radiance_toward(wo, evaluate_emission(m, scene, attr));
}

struct ShadingPoint {
    SurfaceHit hit;

    // The LightSet index of the emissive triangle hit; -1: it emits nothing. Asked for where it
    // is used rather than kept in the struct, which made pt's loop dearer (docs/BENCHMARKS.md).
    int64_t emitter(const RenderScene& rs) const { return rs.lights().emitter_of(hit.instance, hit.prim); }
    // What the surface sends toward unit `wo`, on emitter `emitter` (this point's, >= 0).
    Rgb emitted(const RenderScene& rs, int64_t emitter, const Vec3& wo) const {
        return emitted_radiance(rs.lights(), rs.scene(), *hit.material, hit.attr, emitter, wo);
    }
    ShadingInputs inputs(const RenderScene& rs) const {
        ShadingInputs in = evaluate_material(*hit.material, rs.scene(), hit.attr);
        in.thin_walled = hit.thin_walled;
        return in;
    }
    // wo: the unit direction back along the arriving ray.
    SurfaceBsdf bsdf(const RenderScene& rs, const Vec3& wo) const {
        if (!hit.normal_mapped) return SurfaceBsdf(hit.ng, hit.ns, wo, inputs(rs), hit.ns_coat);
        return SurfaceBsdf(SurfaceBsdf::NormalMapped{}, hit.ng, hit.ns_vertex, hit.ns, wo, inputs(rs), hit.ns_coat);
    }
};

// `footprint_width`: as make_surface_hit's (the ray cone's width at the hit; 0: full resolution).
inline ShadingPoint make_shading_point(const RenderScene& rs, const RayHit& rh, float footprint_width = 0.0f) {
    return ShadingPoint{make_surface_hit(rs, rh, footprint_width)};
}

}  // namespace veach
