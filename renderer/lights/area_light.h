// Blender's area light: a rectangle (square) or an ellipse (disk) of uniform radiance, one-sided,
// emitting along its local -Z. Cycles (3.4) gives a light of power P watts over area A the
// radiance P / (4 A) (measured against Cycles: the reference_light_* scenes), so it emits
// pi P / 4 W; the importer does that conversion. Not scene geometry: rays find it by
// `intersect`, and it casts no shadow (in Cycles, rays pass through lights).
#pragma once

#include "lights/light_queries.h"
#include "scene/scene.h"

namespace veach {

struct AreaLight {
    Vec3 center;
    Vec3 axis_u, axis_v;  // half extents (the ellipse's semi-axes)
    Vec3 n;               // unit, the emitting side
    AreaShape shape = AreaShape::Rectangle;
    float area = 0;
    Rgb radiance_value;

    static AreaLight make(const Vec3& center, const Vec3& axis_u, const Vec3& axis_v, const Vec3& emit_dir,
                          AreaShape shape, const Rgb& radiance);
    bool delta_position() const { return false; }
    bool at_infinity() const { return false; }
    Vec3 point_at(float u1, float u2) const;  // uniform over the shape

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
