// The environment: radiance arriving from every direction at infinity, either uniform or an
// equirectangular (latitude-longitude) map. Directions are importance-sampled from a
// piecewise-constant density over the map, proportional to each cell's radiance times
// sin(theta), the Jacobian of the lat-long parameterisation (pbrt-v3 section 14.2.4):
//
//   pdf_w(w) = pdf_uv(u, v) / (2 pi^2 sin theta)
//
// Light subpaths leave it through a disc of the scene's bounding-sphere radius perpendicular to
// the chosen direction and outside the scene, as the directional light does.
#pragma once

#include <memory>
#include <vector>

#include "core/math.h"
#include "core/rgb.h"
#include "lights/light_queries.h"
#include "scene/scene.h"

namespace veach {

class EnvironmentLight {
public:
    // Keeps a pointer to env's map: `env` must outlive the light (the Scene outlives LightSet).
    explicit EnvironmentLight(const Environment& env);

    // Radiance arriving from unit direction `w` (w points from the scene toward the environment).
    Rgb radiance(const Vec3& w) const;
    // Draws a unit direction toward the environment; pdf_w its solid-angle density (0: none).
    Vec3 sample(float u1, float u2, float* pdf_w) const;
    // The density sample() has for unit direction w.
    float pdf_w(const Vec3& w) const;
    // Integral of radiance over the sphere (channel average), for choosing lights by power.
    float radiance_integral() const { return m_integral; }

    // The queries every light answers (lights/light_queries.h). In radiance(), w is the direction
    // light travels (from the environment toward the scene), p is not used.
    bool delta_position() const { return false; }
    bool at_infinity() const { return true; }
    double power(const LightContext& ctx) const;
    bool sample_direct(const LightContext& ctx, const Vec3& receiver, float u1, float u2, float pmf,
                       LightSample* out) const;
    float pdf_direct_w(const LightContext& ctx, const Vec3& receiver, const Vec3& wi, const Vec3& p, float pmf) const;
    bool sample_emission(const LightContext& ctx, float u_side, float u1, float u2, float u3, float u4,
                         LightEmission* out) const;
    void pdf_emission(const LightContext& ctx, const Vec3& p, const Vec3& dir, float* pdf_pos_a,
                      float* pdf_dir_w) const;
    Rgb radiance(const LightContext&, const Vec3&, const Vec3& w) const { return radiance(-w); }
    bool intersect(const Vec3&, const Vec3&, float, LightHit*) const { return false; }

private:
    struct Table;  // the map and its sampling tables, shared by copies
    Vec3 to_local(const Vec3& w) const;
    Vec3 to_world(const Vec3& l) const;

    Rgb m_uniform;  // strength x colour when there is no map
    float m_cos_rot = 1, m_sin_rot = 0;
    float m_integral = 0;
    std::shared_ptr<const Table> m_table;
};

}  // namespace veach
