// A spot light (KHR_lights_punctual "spot", or Blender's spot with its profile), optionally with
// a radius: then a sphere whose radiance toward a direction w is I f(w . axis) / (pi r^2), the
// falloff taken on the direction light travels, so far away it lights exactly as the point does.
// Its particles leave a uniform point of the sphere in a direction uniform in the cone.
#pragma once

#include "lights/light_queries.h"
#include "lights/sphere_shape.h"
#include "scene/scene.h"

namespace veach {

struct SpotLight {
    Vec3 position;
    Vec3 axis;      // unit, direction light travels along the cone axis
    Rgb intensity;  // W/sr on the axis
    float cos_outer = 0, cos_inner = 1;
    float smooth = 0;  // Blender: width of the smoothstep in cos(theta)
    SpotFalloff falloff = SpotFalloff::Gltf;
    float radius = 0;  // 0: a delta position

    float falloff_at(float cos_theta) const;
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
