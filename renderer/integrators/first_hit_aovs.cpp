#include "integrators/first_hit_aovs.h"

#include "integrators/shading_point.h"

namespace veach {

PixelAovs first_hit_aovs(const RenderScene& rs, const CameraModel& camera, float fx, float fy, float time) {
    PixelAovs aovs;
    Vec3 o, d;
    camera.generate_ray(fx, fy, &o, &d);
    RayHit rh;
    if (!rs.accel().intersect(o, d, k_infinity, &rh, time)) return aovs;
    const ShadingPoint sp = make_shading_point(rs, rh);
    const SurfaceHit& hit = sp.hit;
    aovs.hit = true;
    // Blender's Z pass is the depth along the camera's view axis, not the distance along the
    // ray: t |d| cos(angle to forward). For an orthographic camera o lies on the image plane, so
    // the same formula holds.
    aovs.depth = rh.t * dot(d, camera.forward());
    // Cycles reports the shading normal flipped to the side the camera sees (its back-facing
    // flip), in world space.
    aovs.normal = dot(hit.ng, d) > 0.0f ? -hit.ns : hit.ns;
    aovs.albedo = sp.inputs(rs).base_color;
    return aovs;
}

}  // namespace veach
