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
    float divisor;
    if (!origin().sample_direct(receiver, u1, u2, pmf, out, &divisor)) return false;
    float f = falloff_at(dot(-out->wi, axis));
    if (!(f > 0.0f)) return false;
    out->radiance = intensity * (f / divisor);
    return true;
}

float SpotLight::pdf_direct_w(const LightContext&, const Vec3& receiver, const Vec3&, const Vec3&, float pmf) const {
    return origin().pdf_direct_w(receiver, pmf);
}

// A direction uniform in the cone, from the position or a uniform point of the sphere (a
// cosine-weighted one would mostly leave outside the cone, carrying nothing); directions into the
// sphere at that point carry nothing either.
bool SpotLight::sample_emission(const LightContext&, float, float u1, float u2, float u3, float u4,
                                LightEmission* out) const {
    const LightOrigin o = origin();
    o.sample_emission_origin(u1, u2, out);
    out->dir = Frame(axis).to_world(sample_uniform_cone(u3, u4, cos_outer));
    float f = falloff_at(dot(out->dir, axis));
    out->pdf_dir_w = 1.0f / (2.0f * k_pi * (1.0f - cos_outer));
    if (o.delta()) {
        out->value = intensity * f;
        return f > 0.0f && std::isfinite(out->pdf_dir_w);
    }
    out->value = intensity * (f / (k_pi * radius * radius));
    return f > 0.0f && dot(out->dir, out->normal) > 0.0f && std::isfinite(out->pdf_dir_w) &&
           std::isfinite(out->pdf_pos_a);
}

void SpotLight::pdf_emission(const LightContext&, const Vec3&, const Vec3& dir, float* pdf_pos_a,
                             float* pdf_dir_w) const {
    *pdf_pos_a = origin().pdf_emission_pos_a();
    *pdf_dir_w = dot(dir, axis) > cos_outer ? 1.0f / (2.0f * k_pi * (1.0f - cos_outer)) : 0.0f;
}

Rgb SpotLight::radiance(const LightContext&, const Vec3& p, const Vec3& w) const {
    if (!origin().emits_toward(p, w)) return Rgb(0.0f);
    return intensity * (falloff_at(dot(w, axis)) / (k_pi * radius * radius));
}

bool SpotLight::intersect(const Vec3& o, const Vec3& d, float t_max, LightHit* hit) const {
    return origin().intersect(o, d, t_max, hit);
}

}  // namespace veach
