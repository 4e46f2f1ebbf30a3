#include "lights/spot_light.h"

#include "core/sampling.h"

namespace veach {

float SpotLight::falloff_at(float cos_theta) const {
    if (cos_theta <= cos_outer) return 0.0f;
    if (falloff == SpotFalloff::Blender) {
        // Cycles 3.4: the cosine to the axis times a smoothstep over the blend region.
        float t = cos_theta - cos_outer;
        float s = (smooth > 0.0f && t < smooth) ? smoothstep01(t / smooth) : 1.0f;
        return cos_theta * s;
    }
    // glTF's recommended falloff: a squared linear ramp from the outer to the inner cone.
    float scale = 1.0f / std::max(1e-3f, cos_inner - cos_outer);
    float a = clamp((cos_theta - cos_outer) * scale, 0.0f, 1.0f);
    return a * a;
}

// The cone's solid angle bounds the emitted power.
double SpotLight::power(const LightContext&) const { return 2.0 * k_pi * (1.0 - cos_outer) * intensity.average(); }

bool SpotLight::sample_direct(const LightContext&, const Vec3& receiver, float u1, float u2, float pmf,
                              LightSample* out) const {
    if (!delta_position()) {
        Vec3 wi, p, n;
        float pdf;
        if (!sphere().sample_toward(receiver, u1, u2, &wi, &p, &n, &pdf)) return false;
        float f = falloff_at(dot(-wi, axis));
        if (!(f > 0.0f)) return false;
        out->wi = wi;
        out->point = p;
        out->normal = n;
        out->distance = length(p - receiver);
        out->radiance = intensity * (f / (k_pi * radius * radius));
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
    float f = falloff_at(dot(-out->wi, axis));
    if (!(f > 0.0f)) return false;
    out->point = position;
    out->normal = Vec3();
    out->distance = dist;
    out->radiance = intensity * (f / dist2);
    out->pdf_w = pmf;
    out->is_delta = true;
    out->is_infinite = false;
    return true;
}

float SpotLight::pdf_direct_w(const LightContext&, const Vec3& receiver, const Vec3&, const Vec3&, float pmf) const {
    return delta_position() ? 0.0f : pmf * sphere().pdf_toward(receiver);
}

bool SpotLight::sample_emission(const LightContext&, float, float u1, float u2, float u3, float u4,
                                LightEmission* out) const {
    out->delta_direction = out->infinite = false;
    if (!delta_position()) {
        // A uniform point of the sphere and a direction uniform in the cone (a cosine-weighted
        // one would mostly leave outside the cone, carrying nothing); directions into the
        // sphere at that point carry nothing either.
        Vec3 n = sample_uniform_sphere(u1, u2);
        out->point = position + n * radius;
        out->normal = n;
        out->dir = Frame(axis).to_world(sample_uniform_cone(u3, u4, cos_outer));
        float f = falloff_at(dot(out->dir, axis));
        out->value = intensity * (f / (k_pi * radius * radius));
        out->pdf_pos_a = 1.0f / sphere().area();
        out->pdf_dir_w = 1.0f / (2.0f * k_pi * (1.0f - cos_outer));
        out->delta_position = false;
        return f > 0.0f && dot(out->dir, n) > 0.0f && std::isfinite(out->pdf_dir_w) && std::isfinite(out->pdf_pos_a);
    }
    out->normal = Vec3(0, 0, 0);
    out->point = position;
    out->dir = Frame(axis).to_world(sample_uniform_cone(u3, u4, cos_outer));
    float f = falloff_at(dot(out->dir, axis));
    out->value = intensity * f;
    out->pdf_pos_a = 1.0f;
    out->pdf_dir_w = 1.0f / (2.0f * k_pi * (1.0f - cos_outer));
    out->delta_position = true;
    return f > 0.0f && std::isfinite(out->pdf_dir_w);
}

void SpotLight::pdf_emission(const LightContext&, const Vec3& p, const Vec3& dir, float* pdf_pos_a,
                             float* pdf_dir_w) const {
    if (delta_position()) {
        *pdf_pos_a = 1.0f;
        *pdf_dir_w = dot(dir, axis) > cos_outer ? 1.0f / (2.0f * k_pi * (1.0f - cos_outer)) : 0.0f;
        return;
    }
    *pdf_pos_a = 1.0f / sphere().area();
    *pdf_dir_w = dot(dir, axis) > cos_outer ? 1.0f / (2.0f * k_pi * (1.0f - cos_outer)) : 0.0f;
}

Rgb SpotLight::radiance(const LightContext&, const Vec3& p, const Vec3& w) const {
    if (delta_position() || !(dot(w, p - position) > 0.0f)) return Rgb(0.0f);
    return intensity * (falloff_at(dot(w, axis)) / (k_pi * radius * radius));
}

bool SpotLight::intersect(const Vec3& o, const Vec3& d, float t_max, LightHit* hit) const {
    return !delta_position() && sphere().intersect(o, d, t_max, &hit->t, &hit->p, &hit->n);
}

}  // namespace veach
