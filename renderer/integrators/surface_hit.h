// What an integrator knows about a ray's hit: position with its floating-point error bound,
// normals, texture coordinates and material. The error bound lets rays leave a surface without
// any epsilon tied to the scene's size.
#pragma once

#include "accel/embree_accel.h"
#include "integrators/render_scene.h"
#include "scene/scene.h"
#include "scene/surface_attributes.h"

namespace veach {

struct SurfaceHit {
    Vec3 p;        // world position, from barycentrics of the world-space vertices
    Vec3 p_error;  // per-axis bound on |p - true p|
    Vec3 ng;       // unit geometric normal (from the winding; not flipped toward the ray)
    Vec3 ns;       // unit shading normal, on the same side as ng (the normal map's, if any)
    Vec3 ns_vertex;  // with a normal map (normal_mapped): the vertex normal it tilts, same side
    Vec3 ns_coat;  // the clearcoat's shading normal (KHR_materials_clearcoat), same side; zero: ns
    SurfaceAttributes attr;
    const Material* material = nullptr;
    uint32_t instance = 0, prim = 0;
    float b1 = 0, b2 = 0;      // barycentrics
    bool thin_walled = false;  // RenderScene::thin_walled of the mesh
    bool normal_mapped = false;  // ns comes from the material's normal map
};

// Fills a SurfaceHit from an Embree hit. `footprint_width` is the width of the ray's cone where it
// hits, for texture filtering (CameraModel::footprint_width for camera rays); it sets
// attr.uv_footprint (see set_uv_footprint in surface_hit.cpp). 0, the default, means no
// footprint: textures are read at full resolution.
SurfaceHit make_surface_hit(const RenderScene& rs, const RayHit& hit, float footprint_width = 0.0f);

// A ray origin on the side of the surface that `w` points to, offset just past the position's
// error bound (pbrt-v3 section 3.9): relative to the coordinates' magnitude, so scale-invariant.
Vec3 offset_ray_origin(const Vec3& p, const Vec3& p_error, const Vec3& ng, const Vec3& w);

// Shadow rays stop this fraction short of their target: relative, so scale-invariant.
inline constexpr float k_shadow_epsilon = 1e-4f;

}  // namespace veach
