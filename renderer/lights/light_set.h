// Every emitter of a scene in one list, chosen by power: emissive triangles (area lights) and
// KHR_lights_punctual point, spot and directional lights, and the environment. Each light answers the queries the
// integrators need, with densities named by measure (pdf_w solid angle, pdf_a area).
#pragma once

#include <cstdint>
#include <variant>
#include <vector>

#include "core/rgb.h"
#include "core/sampling.h"
#include "lights/environment_light.h"
#include "scene/scene.h"

namespace veach {

class Accel;

struct TriangleLight {
    uint32_t instance = 0, prim = 0;
    Vec3 p0, e1, e2;  // world: p = p0 + b1 e1 + b2 e2
    Vec3 n;           // unit normal from the winding
    float area = 0;
    bool two_sided = false;
    bool textured = false;  // radiance varies over the triangle (emissive texture)
    Rgb radiance;           // when not textured
};

struct PointLightData {
    Vec3 position;
    Rgb intensity;  // W/sr
};

struct SpotLightData {
    Vec3 position;
    Vec3 axis;      // unit, direction light travels along the cone axis
    Rgb intensity;  // W/sr on the axis
    float cos_outer = 0, cos_inner = 1;
    float smooth = 0;  // Blender: width of the smoothstep in cos(theta)
    SpotFalloff falloff = SpotFalloff::Gltf;
    float falloff_at(float cos_theta) const;
};

struct DirectionalLightData {
    Vec3 direction;  // unit, the direction light travels
    Rgb irradiance;  // W/m^2 on a surface facing it
};

using LightVariant = std::variant<TriangleLight, PointLightData, SpotLightData, DirectionalLightData, EnvironmentLight>;

// A light sampled toward a receiving point.
struct LightSample {
    Rgb radiance;        // arriving at the receiver along -wi (already times the light's falloff)
    Vec3 wi;             // unit, from the receiver toward the light
    Vec3 point;          // on the light (for delta directional: far away along wi)
    float distance = 0;  // receiver to light point; infinity for directional
    float pdf_w = 0;     // solid angle density of wi, including the choice of this light;
                         // for delta lights the selection probability alone
    bool is_delta = false;
    bool is_infinite = false;
    uint32_t light = 0;
};

// A particle leaving a light, for light subpaths. Densities are those of this light alone;
// multiply by selection_pmf for the choice of the light.
struct LightEmission {
    Vec3 point;           // on the light; for directional and environment lights on a disc
                          // of the scene's bounding radius outside the scene
    Vec3 normal;          // surface normal of an area light on the emitting side, else zero
    Vec3 dir;             // unit, the direction the particle travels
    Rgb value;            // area, environment: radiance; point/spot: intensity x falloff;
                          // directional: irradiance
    float pdf_pos_a = 1;  // area density of the point (1 for point and spot: a delta)
    float pdf_dir_w = 1;  // solid-angle density of dir (1 for directional: a delta)
    bool delta_position = false;
    bool delta_direction = false;
    uint32_t light = 0;
};

class LightSet {
public:
    LightSet(const Scene& scene, const Accel& accel);

    bool empty() const { return m_lights.empty(); }
    size_t size() const { return m_lights.size(); }
    const LightVariant& light(size_t i) const { return m_lights[i]; }
    float selection_pmf(size_t i) const { return m_select.pmf(i); }

    // Light index of triangle `prim` of `instance` when it emits, else -1.
    int64_t emitter_of(uint32_t instance, uint32_t prim) const {
        int64_t first = m_first_emitter[instance];
        return first < 0 ? -1 : first + prim;
    }

    // Samples a light and a point on it as seen from `receiver`.
    bool sample_direct(const Vec3& receiver, float u_select, float u1, float u2, LightSample* out) const;
    // Density (solid angle at the receiver, selection included) with which sample_direct would
    // produce the point `p` with normal `n` on triangle light `light`.
    float pdf_direct_w(size_t light, const Vec3& receiver, const Vec3& p) const;

    // Samples a light by power, a point on it and a direction to leave it in.
    bool sample_emission(float u_select, float u1, float u2, float u3, float u4, LightEmission* out) const;
    // The densities sample_emission has for leaving light `light` at `p` along `dir` (triangle
    // lights: cosine-weighted around the emitting side; point: uniform sphere; spot: uniform
    // cone; directional: uniform disc; environment: its map density toward -dir, uniform disc).
    void pdf_emission(size_t light, const Vec3& dir, float* pdf_pos_a, float* pdf_dir_w) const;
    bool is_delta_position(size_t light) const;
    bool is_directional(size_t light) const { return std::holds_alternative<DirectionalLightData>(m_lights[light]); }
    // The environment: index (-1 when the scene has none), radiance arriving from unit direction
    // w, and the solid-angle density (selection included) with which sample_direct picks w.
    int64_t environment_index() const { return m_environment; }
    bool is_environment(size_t light) const { return static_cast<int64_t>(light) == m_environment; }
    Rgb environment_radiance(const Vec3& w) const;
    float environment_pdf_w(const Vec3& w) const;
    float scene_radius() const { return m_scene_radius; }

    // Radiance a triangle light emits from its surface toward direction `w` (unit, away from the
    // surface), with the material's texture evaluated at `attr`.
    Rgb triangle_radiance(const TriangleLight& tl, const Vec3& w, const Rgb& emitted) const;

private:
    // Radiance of a triangle light at barycentrics b (its emissive texture, if any).
    Rgb emitted_radiance(const TriangleLight& tl, Vec2 b) const;

    const Scene& m_scene;
    std::vector<LightVariant> m_lights;
    std::vector<int64_t> m_first_emitter;  // per instance
    Distribution1D m_select;
    int64_t m_environment = -1;
    Vec3 m_scene_center;
    float m_scene_radius = 1;
};

}  // namespace veach
