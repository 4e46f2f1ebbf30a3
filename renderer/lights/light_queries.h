// What every light type answers, whatever its shape: the three queries bidirectional transport
// needs (after SmallVCM's Illuminate / Emit / GetRadiance and pbrt-v4's SampleLi / SampleLe /
// PDF_Le), with densities named by measure (pdf_w solid angle, pdf_a area).
//
//   sample_direct   a point on the light as seen from a receiver, with its solid-angle density
//   pdf_direct_w    the density sample_direct has for a given point (or direction) on the light
//   sample_emission a particle leaving the light: a point and a direction, with area and
//                   direction densities
//   pdf_emission    the densities sample_emission has for a given point and direction
//   radiance        what the light sends from a point on it along a direction (when a ray finds it)
//   power           an estimate of the emitted power, for choosing lights
//
// sample_direct and pdf_direct_w take the light's selection probability and multiply it in, in
// the order the integrators always used (so the images do not change by a rounding).
#pragma once

#include <cstdint>

#include "core/math.h"
#include "core/rgb.h"

namespace veach {

struct Scene;

// What lights need to know about the scene: its bounding sphere (lights at infinity emit through
// a disc covering it) and, for emissive triangles with textures, the scene itself.
struct LightContext {
    const Scene* scene = nullptr;
    Vec3 center;
    float radius = 1;
    // A stand-in point far along wi from the receiver, for lights at infinity.
    Vec3 far_point(const Vec3& receiver, const Vec3& wi) const {
        return receiver + wi * (4.0f * radius + length(receiver - center));
    }
    float disc_pdf_a() const { return 1.0f / (k_pi * radius * radius); }
};

// A light sampled toward a receiving point.
struct LightSample {
    Rgb radiance;        // arriving at the receiver along -wi (already times the light's falloff)
    Vec3 wi;             // unit, from the receiver toward the light
    Vec3 point;          // on the light (for lights at infinity: far away along wi)
    Vec3 normal;         // surface normal at `point` on the side facing the receiver; zero when none
    float distance = 0;  // receiver to light point; infinity for lights at infinity
    float pdf_w = 0;     // solid angle density of wi, including the choice of this light;
                         // for delta lights the selection probability alone
    bool is_delta = false;
    bool is_infinite = false;
    uint32_t light = 0;
};

// A particle leaving a light, for light subpaths. Densities are those of this light alone;
// multiply by LightSet::selection_pmf for the choice of the light.
struct LightEmission {
    Vec3 point;           // on the light; for lights at infinity on a disc of the scene's
                          // bounding radius outside the scene
    Vec3 normal;          // surface normal of a light with a surface on the emitting side, else zero
    Vec3 dir;             // unit, the direction the particle travels
    Rgb value;            // surfaces, environment, sun disc: radiance; point/spot: intensity x
                          // falloff; directional: irradiance
    float pdf_pos_a = 1;  // area density of the point (1 for point and spot: a delta)
    float pdf_dir_w = 1;  // solid-angle density of dir (1 for directional: a delta)
    bool delta_position = false;
    bool delta_direction = false;
    bool infinite = false;  // leaves from infinity (directional, sun disc, environment)
    uint32_t light = 0;
};

// A ray meeting a light's own surface (an area light or a sphere): lights that are not scene
// geometry are found by these analytic tests.
struct LightHit {
    float t = 0;
    Vec3 p;
    Vec3 n;  // the emitting side's normal
    uint32_t light = 0;
};

}  // namespace veach
