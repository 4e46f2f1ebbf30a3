// Every emitter of a scene in one list: emissive triangles, KHR_lights_punctual point, spot and
// directional lights (with Blender's radius, sun angle and area shapes: VEACH_lights_blender), and
// the environment. Each light type lives in its own file and answers the queries of
// lights/light_queries.h; a Light is a closed variant over them, dispatched by std::visit. The
// LightSet only chooses among them (by power) and forwards.
#pragma once

#include <cstdint>
#include <variant>
#include <vector>

#include "core/sampling.h"
#include "lights/area_light.h"
#include "lights/directional_light.h"
#include "lights/environment_light.h"
#include "lights/light_queries.h"
#include "lights/point_light.h"
#include "lights/spot_light.h"
#include "lights/triangle_light.h"
#include "scene/scene.h"

namespace veach {

class Accel;

using Light = std::variant<TriangleLight, PointLight, SpotLight, DirectionalLight, AreaLight, EnvironmentLight>;

class LightSet {
public:
    // `bounds`: what the lights at infinity must cover (a moving object's whole path through the
    // shutter); null is scene.bounds().
    LightSet(const Scene& scene, const Accel& accel, const Bounds3* bounds = nullptr);

    bool empty() const { return m_lights.empty(); }
    size_t size() const { return m_lights.size(); }
    const Light& light(size_t i) const { return m_lights[i]; }
    float selection_pmf(size_t i) const { return m_select.pmf(i); }
    const LightContext& context() const { return m_ctx; }

    // Light index of triangle `prim` of `instance` when it emits, else -1.
    int64_t emitter_of(uint32_t instance, uint32_t prim) const {
        int64_t first = m_first_emitter[instance];
        return first < 0 ? -1 : first + prim;
    }

    // Samples a light and a point on it as seen from `receiver`.
    bool sample_direct(const Vec3& receiver, float u_select, float u1, float u2, LightSample* out) const;
    // Density (solid angle at the receiver, selection included) with which sample_direct would
    // produce point `p` on light `light` in unit direction `wi` from the receiver (lights at
    // infinity read wi, the others p).
    float pdf_direct_w(size_t light, const Vec3& receiver, const Vec3& p, const Vec3& wi) const {
        float pmf = m_select.pmf(light);
        return std::visit([&](const auto& l) { return l.pdf_direct_w(m_ctx, receiver, wi, p, pmf); }, m_lights[light]);
    }

    // Samples a light by power, a point on it and a direction to leave it in.
    bool sample_emission(float u_select, float u1, float u2, float u3, float u4, LightEmission* out) const;
    // The densities sample_emission has for leaving light `light` at `p` along `dir`.
    void pdf_emission(size_t light, const Vec3& p, const Vec3& dir, float* pdf_pos_a, float* pdf_dir_w) const {
        std::visit([&](const auto& l) { l.pdf_emission(m_ctx, p, dir, pdf_pos_a, pdf_dir_w); }, m_lights[light]);
    }
    // Radiance light `light` sends from point p (ignored at infinity) along unit direction w.
    Rgb radiance(size_t light, const Vec3& p, const Vec3& w) const {
        return std::visit([&](const auto& l) { return l.radiance(m_ctx, p, w); }, m_lights[light]);
    }
    bool is_delta_position(size_t light) const {
        return std::visit([](const auto& l) { return l.delta_position(); }, m_lights[light]);
    }
    bool is_at_infinity(size_t light) const {
        return std::visit([](const auto& l) { return l.at_infinity(); }, m_lights[light]);
    }

    // Lights at infinity a ray can find by escaping (the environment, sun discs), and lights with
    // a surface of their own that rays find by analytic tests (area lights, spheres). Neither
    // blocks rays: what a ray meets behind them is still found, as in Cycles.
    const std::vector<uint32_t>& infinite_lights() const { return m_infinite; }
    const std::vector<uint32_t>& shape_lights() const { return m_shapes; }
    bool intersect(size_t light, const Vec3& o, const Vec3& d, float t_max, LightHit* hit) const {
        return std::visit([&](const auto& l) { return l.intersect(o, d, t_max, hit); }, m_lights[light]);
    }

    // The environment: index (-1 when the scene has none).
    int64_t environment_index() const { return m_environment; }
    bool is_environment(size_t light) const { return static_cast<int64_t>(light) == m_environment; }
    float scene_radius() const { return m_ctx.radius; }

private:
    std::vector<Light> m_lights;
    std::vector<int64_t> m_first_emitter;  // per instance
    std::vector<uint32_t> m_infinite, m_shapes;
    Distribution1D m_select;
    int64_t m_environment = -1;
    LightContext m_ctx;
};

}  // namespace veach
