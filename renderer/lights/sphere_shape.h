// A sphere that emits outward with uniform radiance: the shape of point and spot lights with a
// radius. Seen from outside it is sampled by the cone it subtends (uniform in solid angle, pbrt-v3
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

}  // namespace veach
