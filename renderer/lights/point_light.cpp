#include "lights/point_light.h"

#include "core/sampling.h"

namespace veach {

double PointLight::power(const LightContext&) const { return 4.0 * k_pi * intensity.average(); }

bool PointLight::sample_direct(const LightContext&, const Vec3& receiver, float u1, float u2, float pmf,
                               LightSample* out) const {
    float divisor;
    if (!origin().sample_direct(receiver, u1, u2, pmf, out, &divisor)) return false;
    out->radiance = intensity / divisor;
    return true;
}

float PointLight::pdf_direct_w(const LightContext&, const Vec3& receiver, const Vec3&, const Vec3&, float pmf) const {
    return origin().pdf_direct_w(receiver, pmf);
}

// From the sphere, cosine-weighted about the surface normal (uniform radiance); from a delta
// position, uniform over the sphere of directions.
bool PointLight::sample_emission(const LightContext&, float, float u1, float u2, float u3, float u4,
                                 LightEmission* out) const {
    const LightOrigin o = origin();
    o.sample_emission_origin(u1, u2, out);
    if (!o.delta()) {
        out->dir = Frame(out->normal).to_world(sample_cosine_hemisphere(u3, u4));
        out->value = intensity / (k_pi * radius * radius);
        out->pdf_dir_w = cosine_hemisphere_pdf_w(dot(out->dir, out->normal));
        return out->pdf_dir_w > 0.0f && std::isfinite(out->pdf_pos_a);
    }
    out->dir = sample_uniform_sphere(u3, u4);
    out->value = intensity;
    out->pdf_dir_w = k_inv_four_pi;
    return true;
}

void PointLight::pdf_emission(const LightContext&, const Vec3& p, const Vec3& dir, float* pdf_pos_a,
                              float* pdf_dir_w) const {
    *pdf_pos_a = origin().pdf_emission_pos_a();
    *pdf_dir_w = delta_position() ? k_inv_four_pi : cosine_hemisphere_pdf_w(dot(dir, normalize(p - position)));
}

Rgb PointLight::radiance(const LightContext&, const Vec3& p, const Vec3& w) const {
    if (!origin().emits_toward(p, w)) return Rgb(0.0f);
    return intensity / (k_pi * radius * radius);
}

bool PointLight::intersect(const Vec3& o, const Vec3& d, float t_max, LightHit* hit) const {
    return origin().intersect(o, d, t_max, hit);
}

}  // namespace veach
