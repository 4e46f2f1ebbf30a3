#include "lights/triangle_light.h"

#include "core/sampling.h"
#include "materials/gltf_material.h"
#include "scene/scene.h"
#include "scene/surface_attributes.h"

namespace veach {

namespace {
// Emission from a triangle: one side (or both, chosen evenly, for double-sided materials),
// cosine-weighted around the side's normal.
float triangle_dir_pdf(const TriangleLight& tl, const Vec3& dir) {
    float c = dot(dir, tl.n);
    if (!tl.two_sided && c <= 0.0f) return 0.0f;
    float pdf = std::fabs(c) * k_inv_pi;
    return tl.two_sided ? 0.5f * pdf : pdf;
}
}  // namespace

double TriangleLight::power(const LightContext&) const {
    double p = double(area) * radiance_value.average() * k_pi * (two_sided ? 2.0 : 1.0);
    return std::isfinite(p) && area > 0.0f ? p : 0.0f;
}

Rgb TriangleLight::emitted_at(const LightContext& ctx, Vec2 b) const {
    if (!textured) return radiance_value;
    const Scene& scene = *ctx.scene;
    const Mesh& mesh = scene.meshes[scene.instances[instance].mesh];
    const uint32_t* idx = &mesh.indices[static_cast<size_t>(prim) * 3];
    SurfaceAttributes attr;
    interpolate_uvs(mesh, idx, 1.0f - b.x - b.y, b.x, b.y, &attr);
    return evaluate_emission(scene.material_of(mesh), scene, attr);
}

bool TriangleLight::sample_direct(const LightContext& ctx, const Vec3& receiver, float u1, float u2, float pmf,
                                  LightSample* out) const {
    Vec2 b = sample_uniform_triangle(u1, u2);
    Vec3 p = p0 + e1 * b.x + e2 * b.y;
    Vec3 d = p - receiver;
    float dist2 = length_squared(d);
    if (!(dist2 > 0.0f)) return false;
    float dist = std::sqrt(dist2);
    Vec3 wi = d / dist;
    float cos_light = -dot(wi, n);
    if (!(cos_light > 0.0f) && !(two_sided && cos_light < 0.0f)) return false;
    out->radiance = emitted_at(ctx, b);
    out->wi = wi;
    out->point = p;
    out->normal = cos_light > 0.0f ? n : -n;
    out->distance = dist;
    out->pdf_w = pmf * dist2 / (std::fabs(cos_light) * area);
    out->is_delta = false;
    out->is_infinite = false;
    return std::isfinite(out->pdf_w) && out->pdf_w > 0.0f;
}

float TriangleLight::pdf_direct_w(const LightContext&, const Vec3& receiver, const Vec3&, const Vec3& p,
                                  float pmf) const {
    Vec3 d = p - receiver;
    float dist2 = length_squared(d);
    float cos_light = std::fabs(dot(d, n)) / std::sqrt(dist2);
    if (!(cos_light > 0.0f) || !(area > 0.0f)) return 0.0f;
    return pmf * dist2 / (cos_light * area);
}

bool TriangleLight::sample_emission(const LightContext& ctx, float u_side, float u1, float u2, float u3, float u4,
                                    LightEmission* out) const {
    Vec2 b = sample_uniform_triangle(u1, u2);
    out->point = p0 + e1 * b.x + e2 * b.y;
    Vec3 side = n;
    if (two_sided && u_side < 0.5f) side = -side;
    Vec3 local = sample_cosine_hemisphere(u3, u4);
    out->dir = Frame(side).to_world(local);
    out->normal = side;
    out->value = emitted_at(ctx, b);
    out->pdf_pos_a = 1.0f / area;
    out->pdf_dir_w = triangle_dir_pdf(*this, out->dir);
    out->delta_position = out->delta_direction = out->infinite = false;
    return area > 0.0f && out->pdf_dir_w > 0.0f;
}

void TriangleLight::pdf_emission(const LightContext&, const Vec3&, const Vec3& dir, float* pdf_pos_a,
                                 float* pdf_dir_w) const {
    *pdf_pos_a = area > 0.0f ? 1.0f / area : 0.0f;
    *pdf_dir_w = triangle_dir_pdf(*this, dir);
}

bool TriangleLight::barycentrics(const Vec3& p, Vec2* b) const {
    Vec3 d = p - p0;
    float a11 = dot(e1, e1), a12 = dot(e1, e2), a22 = dot(e2, e2);
    float r1 = dot(d, e1), r2 = dot(d, e2);
    float det = a11 * a22 - a12 * a12;
    if (!(std::fabs(det) > 0.0f)) return false;
    *b = Vec2{(r1 * a22 - r2 * a12) / det, (r2 * a11 - r1 * a12) / det};
    return true;
}

Rgb TriangleLight::radiance(const LightContext& ctx, const Vec3& p, const Vec3& w) const {
    if (!textured) return radiance_toward(w, radiance_value);
    Vec2 b;
    if (!barycentrics(p, &b)) return Rgb(0.0f);
    return radiance_toward(w, emitted_at(ctx, b));
}

}  // namespace veach
