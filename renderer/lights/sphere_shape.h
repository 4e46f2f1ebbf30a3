// A sphere that emits outward: the shape of point and spot lights with a radius (LightOrigin, at the
// end, is what the two lights share). Seen from outside it is sampled by the cone it subtends (uniform in solid angle, pbrt-v3
// section 14.2.3); particles leave a uniform point of its surface in a cosine-weighted direction.
// A receiver inside the sphere sees nothing of it (it emits outward only).
#pragma once

#include "core/sampling.h"
#include "lights/light_queries.h"

namespace veach {

struct SphereShape {
    Vec3 center;
    float radius = 0;

    float area() const { return 4.0f * k_pi * radius * radius; }

    // 1 - cos of the subtended cone's half angle, without cancellation for small spheres; 0 when
    // the receiver is inside.
    float one_minus_cos_max(const Vec3& receiver) const {
        float d2 = length_squared(receiver - center);
        float r2 = radius * radius;
        if (!(d2 > r2)) return 0.0f;
        float sin2 = r2 / d2;
        float cos_max = std::sqrt(std::max(0.0f, 1.0f - sin2));
        return sin2 / (1.0f + cos_max);
    }

    // A point of the sphere seen from `receiver` along a direction uniform in the subtended cone.
    bool sample_toward(const Vec3& receiver, float u1, float u2, Vec3* wi, Vec3* p, Vec3* n, float* pdf_w) const {
        float omc = one_minus_cos_max(receiver);
        if (!(omc > 0.0f)) return false;
        Vec3 to_center = center - receiver;
        float dc = length(to_center);
        Vec3 axis = to_center / dc;
        // Uniform cone by 1 - cos theta = u1 (1 - cos_max), written without cancellation.
        float omct = u1 * omc;
        float sin2 = std::max(0.0f, omct * (2.0f - omct));
        float sin_t = std::sqrt(sin2), cos_t = 1.0f - omct;
        float phi = 2.0f * k_pi * u2;
        *wi = Frame(axis).to_world(Vec3(sin_t * std::cos(phi), sin_t * std::sin(phi), cos_t));
        // The nearer intersection with the sphere; at the cone's rim the ray grazes it.
        float b = dc * cos_t;
        float disc = radius * radius - dc * dc * sin2;
        float t = b - std::sqrt(std::max(0.0f, disc));
        *p = receiver + *wi * t;
        *n = normalize(*p - center);
        *pdf_w = 1.0f / (2.0f * k_pi * omc);
        return std::isfinite(*pdf_w) && t > 0.0f;
    }

    float pdf_toward(const Vec3& receiver) const {
        float omc = one_minus_cos_max(receiver);
        return omc > 0.0f ? 1.0f / (2.0f * k_pi * omc) : 0.0f;
    }

    // The first crossing of the ray with the sphere from outside (the side that emits toward it).
    bool intersect(const Vec3& o, const Vec3& d, float t_max, float* t_hit, Vec3* p, Vec3* n) const {
        Vec3 oc = o - center;
        float a = length_squared(d);
        float c = length_squared(oc) - radius * radius;
        if (!(c > 0.0f) || !(a > 0.0f)) return false;  // inside (or on) the sphere: nothing toward it
        float b = dot(oc, d);
        if (b >= 0.0f) return false;  // moving away
        // Discriminant by the difference of the ray's closest approach (stable for far spheres).
        Vec3 closest = oc - d * (b / a);
        float disc = radius * radius - length_squared(closest);
        if (disc < 0.0f) return false;
        float q = -b + std::sqrt(a * disc) * (b < 0.0f ? 1.0f : -1.0f);
        float t = c / q;
        if (!(t > 0.0f) || !(t < t_max)) return false;
        *t_hit = t;
        *p = o + d * t;
        *n = normalize(*p - center);
        return true;
    }
};

// Where a point or spot light emits from: its position, or with a radius the SphereShape around
// it. What the two lights share, sampled one way; each adds only its radiance (the spot's falloff)
// and the directions its particles leave in.
struct LightOrigin {
    Vec3 position;
    float radius = 0;  // 0: a delta position

    bool delta() const { return !(radius > 0.0f); }
    SphereShape sphere() const { return {position, radius}; }

    // A point of the light seen from `receiver`: all of `out` but its radiance, which is the
    // light's intensity (times its falloff along -wi) divided by *divisor: the squared distance
    // to a delta position (then I / r^2 with pdf = pmf makes the estimator exact), pi r^2 for the
    // sphere (its radiance).
    bool sample_direct(const Vec3& receiver, float u1, float u2, float pmf, LightSample* out, float* divisor) const {
        out->is_infinite = false;
        if (!delta()) {
            Vec3 wi, p, n;
            float pdf;
            if (!sphere().sample_toward(receiver, u1, u2, &wi, &p, &n, &pdf)) return false;
            out->wi = wi;
            out->point = p;
            out->normal = n;
            out->distance = length(p - receiver);
            out->pdf_w = pmf * pdf;
            out->is_delta = false;
            *divisor = k_pi * radius * radius;
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
        out->pdf_w = pmf;
        out->is_delta = true;
        *divisor = dist2;
        return true;
    }

    // The solid-angle density of sample_direct at `receiver` (pmf included); 0 for a delta.
    float pdf_direct_w(const Vec3& receiver, float pmf) const {
        return delta() ? 0.0f : pmf * sphere().pdf_toward(receiver);
    }

    // A particle's origin: the position, or a uniform point of the sphere with its outward
    // normal; point, normal, pdf_pos_a and the delta flags of `out`, not its direction.
    void sample_emission_origin(float u1, float u2, LightEmission* out) const {
        out->delta_direction = out->infinite = false;
        if (!delta()) {
            Vec3 n = sample_uniform_sphere(u1, u2);
            out->point = position + n * radius;
            out->normal = n;
            out->pdf_pos_a = 1.0f / sphere().area();
            out->delta_position = false;
            return;
        }
        out->normal = Vec3(0, 0, 0);
        out->point = position;
        out->pdf_pos_a = 1.0f;
        out->delta_position = true;
    }

    float pdf_emission_pos_a() const { return delta() ? 1.0f : 1.0f / sphere().area(); }

    // Whether a ray travelling along `w` that found the sphere at `p` sees its emitting side.
    bool emits_toward(const Vec3& p, const Vec3& w) const { return !delta() && dot(w, p - position) > 0.0f; }

    bool intersect(const Vec3& o, const Vec3& d, float t_max, LightHit* hit) const {
        return !delta() && sphere().intersect(o, d, t_max, &hit->t, &hit->p, &hit->n);
    }
};

}  // namespace veach
