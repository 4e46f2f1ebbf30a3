// A directional light (KHR_lights_punctual "directional"), or with an angle Blender's sun disc.
// The disc is Cycles' (3.4): directions through a disc of radius tan(angle / 2) one unit along the
// axis, uniform over that disc, so pdf_w = 1 / (pi tan^2(angle/2) cos^3 theta) with theta the
// angle to the axis; its radiance is the irradiance E times that density, which makes a sample's
// weight E exactly and a surface facing the sun receive E times the mean cosine over the disc.
// Particles leave through a disc of the scene's bounding radius outside the scene.
#pragma once

#include "lights/light_queries.h"

namespace veach {

struct DirectionalLight {
    Vec3 direction;      // unit, the direction light travels
    Rgb irradiance;      // W/m^2 (Blender's Strength)
    float tan_half = 0;  // tan(angle / 2); 0: a delta direction

    bool delta_direction() const { return !(tan_half > 0.0f); }
    bool delta_position() const { return false; }
    bool at_infinity() const { return true; }
    // Density of the direction wi toward the sun (zero outside its disc).
    float disc_pdf_w(const Vec3& wi) const;

    double power(const LightContext& ctx) const;
    bool sample_direct(const LightContext& ctx, const Vec3& receiver, float u1, float u2, float pmf,
                       LightSample* out) const;
    float pdf_direct_w(const LightContext& ctx, const Vec3& receiver, const Vec3& wi, const Vec3& p, float pmf) const;
    bool sample_emission(const LightContext& ctx, float u_side, float u1, float u2, float u3, float u4,
                         LightEmission* out) const;
    void pdf_emission(const LightContext& ctx, const Vec3& p, const Vec3& dir, float* pdf_pos_a,
                      float* pdf_dir_w) const;
    // Radiance arriving along travel direction w (from the sun toward the scene).
    Rgb radiance(const LightContext& ctx, const Vec3& p, const Vec3& w) const;
    bool intersect(const Vec3&, const Vec3&, float, LightHit*) const { return false; }

private:
    Vec3 sample_disc(float u1, float u2) const;  // a unit direction toward the sun
};

}  // namespace veach
