#include "integrators/first_hit_aovs.h"

#include <cmath>

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

DenoiseFeatures denoise_features(const RenderScene& rs, const CameraModel& camera, float fx, float fy, float time,
                                 float u_lobe) {
    DenoiseFeatures f;
    Vec3 o, d;
    camera.generate_ray(fx, fy, &o, &d);
    Rgb tint(1.0f);
    constexpr int k_max_delta_bounces = 8;
    for (int bounce = 0; bounce <= k_max_delta_bounces; ++bounce) {
        RayHit rh;
        if (!rs.accel().intersect(o, d, k_infinity, &rh, time)) return f;
        const ShadingPoint sp = make_shading_point(rs, rh);
        const SurfaceHit& hit = sp.hit;
        if (bounce == 0) f.depth = rh.t * dot(d, camera.forward());
        const Vec3 wo = -d;
        const SurfaceBsdf bsdf = sp.bsdf(rs, wo);
        if (bounce < k_max_delta_bounces && !bsdf.is_black() && bsdf.is_pure_delta()) {
            BsdfSample bs;
            // The delta lobes ignore the direction numbers: only u_lobe chooses.
            if (bsdf.sample(wo, u_lobe, 0.5f, 0.5f, TransportMode::Radiance, &bs) && !bs.weight.is_black()) {
                // Reuse the choice for the next glass: stretch the part of [0, 1) it fell in.
                u_lobe = std::fmod(u_lobe * 7.0f + 0.3f, 1.0f);
                tint = tint * bs.weight;
                o = offset_ray_origin(hit.p, hit.p_error, hit.ng, bs.wi);
                d = bs.wi;
                continue;
            }
        }
        f.hit = true;
        f.position = hit.p;
        f.normal = dot(hit.ng, d) > 0.0f ? -hit.ns : hit.ns;
        f.albedo = tint * sp.inputs(rs).base_color;
        return f;
    }
    return f;
}

}  // namespace veach
