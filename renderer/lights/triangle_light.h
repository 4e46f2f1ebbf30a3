// One emissive triangle of a mesh whose material emits: an area light that is also scene
// geometry, so rays find it through the accelerator (the integrators look its index up with
// LightSet::emitter_of) and its radiance may come from an emissive texture.
#pragma once

#include "lights/light_queries.h"

namespace veach {

struct TriangleLight {
    uint32_t instance = 0, prim = 0;
    Vec3 p0, e1, e2;  // world: p = p0 + b1 e1 + b2 e2
    Vec3 n;           // unit normal from the winding
    float area = 0;
    bool two_sided = false;
    bool textured = false;  // radiance varies over the triangle (emissive texture)
    Rgb radiance_value;     // when not textured

    bool delta_position() const { return false; }
    bool at_infinity() const { return false; }
    double power(const LightContext& ctx) const;
    bool sample_direct(const LightContext& ctx, const Vec3& receiver, float u1, float u2, float pmf,
                       LightSample* out) const;
    float pdf_direct_w(const LightContext& ctx, const Vec3& receiver, const Vec3& wi, const Vec3& p, float pmf) const;
    bool sample_emission(const LightContext& ctx, float u_side, float u1, float u2, float u3, float u4,
                         LightEmission* out) const;
    void pdf_emission(const LightContext& ctx, const Vec3& p, const Vec3& dir, float* pdf_pos_a,
                      float* pdf_dir_w) const;
    // Radiance from point p toward unit direction w (away from the surface).
    Rgb radiance(const LightContext& ctx, const Vec3& p, const Vec3& w) const;
    // The same when the caller has evaluated the material's emission at the point already.
    Rgb radiance_toward(const Vec3& w, const Rgb& emitted) const {
        float c = dot(w, n);
        if (c > 0.0f || (two_sided && c < 0.0f)) return emitted;
        return Rgb(0.0f);
    }
    // Barycentrics (of the second and third corners, as a ray hit's u and v) of a point on the
    // triangle, least squares for points slightly off its plane; false for a degenerate triangle.
    bool barycentrics(const Vec3& p, Vec2* b) const;
    // Triangles are found by the accelerator, never by this.
    bool intersect(const Vec3&, const Vec3&, float, LightHit*) const { return false; }

private:
    Rgb emitted_at(const LightContext& ctx, Vec2 b) const;  // the emissive texture at barycentrics b
};

}  // namespace veach
