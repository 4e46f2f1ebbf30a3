#include "lights/point_light.h"

#include "core/sampling.h"

namespace veach {

double PointLight::power(const LightContext&) const { return 4.0 * k_pi * intensity.average(); }

bool PointLight::sample_direct(const LightContext&, const Vec3& receiver, float u1, float u2, float pmf,
                               LightSample* out) const {
    if (!delta_position()) {
        Vec3 wi, p, n;
        float pdf;
        if (!sphere().sample_toward(receiver, u1, u2, &wi, &p, &n, &pdf)) return false;
        out->wi = wi;
        out->point = p;
        out->normal = n;
        out->distance = length(p - receiver);
        out->radiance = sphere_radiance();
        out->pdf_w = pmf * pdf;
        out->is_delta = false;
        out->is_infinite = false;
        return out->pdf_w > 0.0f;
    }
    Vec3 d = position - receiver;
    float dist2 = length_squared(d);
    if (!(dist2 > 0.0f)) return false;
    float dist = std::sqrt(dist2);
    out->wi = d / dist;
    out->point = position;
    out->normal = Vec3();
    out->distance = dist;
    // Radiance-like quantity: I / r^2 is the irradiance normal to wi; with pdf = pmf the
    // estimator f cos I / (r^2 pmf) is exact.
    out->radiance = intensity / dist2;
    out->pdf_w = pmf;
    out->is_delta = true;
    out->is_infinite = false;
    return true;
}

float PointLight::pdf_direct_w(const LightContext&, const Vec3& receiver, const Vec3&, const Vec3&, float pmf) const {
    return delta_position() ? 0.0f : pmf * sphere().pdf_toward(receiver);
}

bool PointLight::sample_emission(const LightContext&, float, float u1, float u2, float u3, float u4,
                                 LightEmission* out) const {
    out->delta_direction = out->infinite = false;
    if (!delta_position()) {
        Vec3 n = sample_uniform_sphere(u1, u2);
        out->point = position + n * radius;
        out->normal = n;
        out->dir = Frame(n).to_world(sample_cosine_hemisphere(u3, u4));
        out->value = sphere_radiance();
        out->pdf_pos_a = 1.0f / sphere().area();
        out->pdf_dir_w = cosine_hemisphere_pdf_w(dot(out->dir, n));
        out->delta_position = false;
        return out->pdf_dir_w > 0.0f && std::isfinite(out->pdf_pos_a);
    }
    out->normal = Vec3(0, 0, 0);
    out->point = position;
    out->dir = sample_uniform_sphere(u3, u4);
    out->value = intensity;
    out->pdf_pos_a = 1.0f;
    out->pdf_dir_w = k_inv_four_pi;
    out->delta_position = true;
    return true;
}

void PointLight::pdf_emission(const LightContext&, const Vec3& p, const Vec3& dir, float* pdf_pos_a,
                              float* pdf_dir_w) const {
    if (delta_position()) {
        *pdf_pos_a = 1.0f;
        *pdf_dir_w = k_inv_four_pi;
        return;
    }
    *pdf_pos_a = 1.0f / sphere().area();
    *pdf_dir_w = cosine_hemisphere_pdf_w(dot(dir, normalize(p - position)));
}

Rgb PointLight::radiance(const LightContext&, const Vec3& p, const Vec3& w) const {
    if (delta_position() || !(dot(w, p - position) > 0.0f)) return Rgb(0.0f);
    return sphere_radiance();
}

bool PointLight::intersect(const Vec3& o, const Vec3& d, float t_max, LightHit* hit) const {
    return !delta_position() && sphere().intersect(o, d, t_max, &hit->t, &hit->p, &hit->n);
}

}  // namespace veach
