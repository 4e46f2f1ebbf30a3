#include "lights/area_light.h"

#include "core/sampling.h"

namespace veach {

AreaLight AreaLight::make(const Vec3& center, const Vec3& axis_u, const Vec3& axis_v, const Vec3& emit_dir,
                          AreaShape shape, const Rgb& radiance) {
    AreaLight a;
    a.center = center;
    a.axis_u = axis_u;
    a.axis_v = axis_v;
    a.shape = shape;
    a.radiance_value = radiance;
    Vec3 c = cross(axis_u, axis_v);
    float len = length(c);
    a.n = len > 0.0f ? c / len : normalize(emit_dir);
    if (dot(a.n, emit_dir) < 0.0f) a.n = -a.n;
    a.area = (shape == AreaShape::Rectangle ? 4.0f : k_pi) * len;
    return a;
}

Vec3 AreaLight::point_at(float u1, float u2) const {
    Vec2 d = shape == AreaShape::Rectangle ? Vec2{2.0f * u1 - 1.0f, 2.0f * u2 - 1.0f} : sample_concentric_disk(u1, u2);
    return center + axis_u * d.x + axis_v * d.y;
}

double AreaLight::power(const LightContext&) const {
    double p = double(area) * radiance_value.average() * k_pi;
    return std::isfinite(p) && area > 0.0f ? p : 0.0f;
}

bool AreaLight::sample_direct(const LightContext&, const Vec3& receiver, float u1, float u2, float pmf,
                              LightSample* out) const {
    Vec3 p = point_at(u1, u2);
    Vec3 d = p - receiver;
    float dist2 = length_squared(d);
    if (!(dist2 > 0.0f)) return false;
    float dist = std::sqrt(dist2);
    Vec3 wi = d / dist;
    float cos_light = -dot(wi, n);
    if (!(cos_light > 0.0f)) return false;
    out->radiance = radiance_value;
    out->wi = wi;
    out->point = p;
    out->normal = n;
    out->distance = dist;
    out->pdf_w = pmf * dist2 / (cos_light * area);
    out->is_delta = false;
    out->is_infinite = false;
    return std::isfinite(out->pdf_w) && out->pdf_w > 0.0f;
}

float AreaLight::pdf_direct_w(const LightContext&, const Vec3& receiver, const Vec3&, const Vec3& p, float pmf) const {
    Vec3 d = p - receiver;
    float dist2 = length_squared(d);
    float cos_light = -dot(d, n) / std::sqrt(dist2);
    if (!(cos_light > 0.0f) || !(area > 0.0f)) return 0.0f;
    return pmf * dist2 / (cos_light * area);
}

bool AreaLight::sample_emission(const LightContext&, float, float u1, float u2, float u3, float u4,
                                LightEmission* out) const {
    out->point = point_at(u1, u2);
    out->dir = Frame(n).to_world(sample_cosine_hemisphere(u3, u4));
    out->normal = n;
    out->value = radiance_value;
    out->pdf_pos_a = 1.0f / area;
    out->pdf_dir_w = cosine_hemisphere_pdf_w(dot(out->dir, n));
    out->delta_position = out->delta_direction = out->infinite = false;
    return area > 0.0f && out->pdf_dir_w > 0.0f;
}

void AreaLight::pdf_emission(const LightContext&, const Vec3&, const Vec3& dir, float* pdf_pos_a,
                             float* pdf_dir_w) const {
    *pdf_pos_a = area > 0.0f ? 1.0f / area : 0.0f;
    *pdf_dir_w = cosine_hemisphere_pdf_w(dot(dir, n));
}

Rgb AreaLight::radiance(const LightContext&, const Vec3&, const Vec3& w) const {
    return dot(w, n) > 0.0f ? radiance_value : Rgb(0.0f);
}

bool AreaLight::intersect(const Vec3& o, const Vec3& d, float t_max, LightHit* hit) const {
    float dn = dot(d, n);
    if (!(dn < 0.0f)) return false;  // only rays arriving at the emitting side see it
    float t = dot(center - o, n) / dn;
    if (!(t > 0.0f) || !(t < t_max)) return false;
    Vec3 p = o + d * t;
    Vec3 q = p - center;
    float a = dot(q, axis_u) / length_squared(axis_u);
    float b = dot(q, axis_v) / length_squared(axis_v);
    bool inside =
        shape == AreaShape::Rectangle ? (std::fabs(a) <= 1.0f && std::fabs(b) <= 1.0f) : (a * a + b * b <= 1.0f);
    if (!inside) return false;
    hit->t = t;
    hit->p = p;
    hit->n = n;
    return true;
}

}  // namespace veach
