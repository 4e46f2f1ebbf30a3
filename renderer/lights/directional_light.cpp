#include "lights/directional_light.h"

#include "core/sampling.h"

namespace veach {

double DirectionalLight::power(const LightContext& ctx) const {
    return k_pi * double(ctx.radius) * ctx.radius * irradiance.average();
}

float DirectionalLight::disc_pdf_w(const Vec3& wi) const {
    float c = -dot(wi, direction);
    if (!(c > 0.0f)) return 0.0f;
    // The direction meets the plane one unit along the axis at distance tan(theta) from its centre.
    float tan2 = std::max(0.0f, 1.0f - c * c) / (c * c);
    if (tan2 > tan_half * tan_half) return 0.0f;
    return 1.0f / (k_pi * tan_half * tan_half * c * c * c);
}

Vec3 DirectionalLight::sample_disc(float u1, float u2) const {
    Frame frame(-direction);
    Vec2 d = sample_concentric_disk(u1, u2);
    return normalize(frame.n + (frame.s * d.x + frame.t * d.y) * tan_half);
}

bool DirectionalLight::sample_direct(const LightContext& ctx, const Vec3& receiver, float u1, float u2, float pmf,
                                     LightSample* out) const {
    out->distance = k_infinity;
    out->normal = Vec3();
    out->is_infinite = true;
    if (!delta_direction()) {
        out->wi = sample_disc(u1, u2);
        float pdf = disc_pdf_w(out->wi);
        if (!(pdf > 0.0f) || !std::isfinite(pdf)) return false;
        out->point = ctx.far_point(receiver, out->wi);
        out->radiance = irradiance * pdf;
        out->pdf_w = pmf * pdf;
        out->is_delta = false;
        return true;
    }
    out->wi = -direction;
    out->point = ctx.far_point(receiver, out->wi);
    out->radiance = irradiance;
    out->pdf_w = pmf;
    out->is_delta = true;
    return true;
}

float DirectionalLight::pdf_direct_w(const LightContext&, const Vec3&, const Vec3& wi, const Vec3&, float pmf) const {
    return delta_direction() ? 0.0f : pmf * disc_pdf_w(wi);
}

bool DirectionalLight::sample_emission(const LightContext& ctx, float, float u1, float u2, float u3, float u4,
                                       LightEmission* out) const {
    out->normal = Vec3(0, 0, 0);
    out->delta_position = false;
    out->infinite = true;
    out->pdf_pos_a = ctx.disc_pdf_a();
    Vec3 dir = direction;
    if (!delta_direction()) {
        Vec3 wi = sample_disc(u1, u2);
        float pdf = disc_pdf_w(wi);
        if (!(pdf > 0.0f) || !std::isfinite(pdf)) return false;
        dir = -wi;
        out->value = irradiance * pdf;
        out->pdf_dir_w = pdf;
        out->delta_direction = false;
    } else {
        out->value = irradiance;
        out->pdf_dir_w = 1.0f;
        out->delta_direction = true;
    }
    // Parallel rays through a disc that covers the scene's bounding sphere, placed outside it.
    Frame frame(dir);
    Vec2 d = sample_concentric_disk(u3, u4);
    out->point = ctx.center + (frame.s * d.x + frame.t * d.y) * ctx.radius - dir * ctx.radius;
    out->dir = dir;
    return true;
}

void DirectionalLight::pdf_emission(const LightContext& ctx, const Vec3&, const Vec3& dir, float* pdf_pos_a,
                                    float* pdf_dir_w) const {
    *pdf_pos_a = ctx.disc_pdf_a();
    *pdf_dir_w = delta_direction() ? 1.0f : disc_pdf_w(-dir);
}

Rgb DirectionalLight::radiance(const LightContext&, const Vec3&, const Vec3& w) const {
    if (delta_direction()) return Rgb(0.0f);
    return irradiance * disc_pdf_w(-w);
}

}  // namespace veach
