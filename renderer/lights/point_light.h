// A point light (KHR_lights_punctual "point"), or with a radius a sphere of uniform radiance:
// Blender's point light with its Radius. Intensity I (W/sr) is the same either way; the sphere's
// radiance is I / (pi r^2), so far away it lights exactly as the point does.
#pragma once

#include "lights/light_queries.h"
#include "lights/sphere_shape.h"

namespace veach {

struct PointLight {
    Vec3 position;
    Rgb intensity;     // W/sr
    float radius = 0;  // 0: a delta position

    LightOrigin origin() const { return {position, radius}; }
    bool delta_position() const { return origin().delta(); }
    bool at_infinity() const { return false; }

    double power(const LightContext& ctx) const;
    bool sample_direct(const LightContext& ctx, const Vec3& receiver, float u1, float u2, float pmf,
                       LightSample* out) const;
    float pdf_direct_w(const LightContext& ctx, const Vec3& receiver, const Vec3& wi, const Vec3& p, float pmf) const;
    bool sample_emission(const LightContext& ctx, float u_side, float u1, float u2, float u3, float u4,
                         LightEmission* out) const;
    void pdf_emission(const LightContext& ctx, const Vec3& p, const Vec3& dir, float* pdf_pos_a,
                      float* pdf_dir_w) const;
    Rgb radiance(const LightContext& ctx, const Vec3& p, const Vec3& w) const;
    bool intersect(const Vec3& o, const Vec3& d, float t_max, LightHit* hit) const;
};

}  // namespace veach
