#include "integrators/lt/light_tracer.h"

#include <vector>

#include "integrators/bdpt/camera_connection.h"
#include "integrators/bdpt/subpaths.h"

namespace veach {

struct LightTracer::TileState {
    std::vector<PathVertex> light;
    PathVertex camera_vertex;
    PathVertex seen;  // a light subpath vertex shaded again as the camera sees it
};

LightTracer::TileState LightTracer::begin_tile(const RenderScene&, ThreadStats&) const {
    TileState state;
    state.light.resize(static_cast<size_t>(m_settings.max_depth) + 1);
    return state;
}

// Inline: its one caller is the loop instantiated below, into which it folds.
inline Rgb LightTracer::evaluate_pixel_sample(TileState& state, const RenderScene& rs, const CameraModel& camera,
                                              float fx, float fy, float time, Sampler& rng, Film& film,
                                              ThreadStats& stats) const {
    SubpathContext ctx;
    ctx.rs = &rs;
    ctx.lights = &rs.lights();
    ctx.camera = &camera;
    ctx.time = time;
    ctx.stats = &stats;
    const LightSet& lights = rs.lights();

    // The camera ray escaping to the lights at infinity (a transparent film's background sees none).
    Rgb radiance(0.0f);
    Vec3 origin, dir;
    camera.generate_ray(fx, fy, &origin, &dir);
    if (!lights.infinite_lights().empty() && !m_settings.transparent) {
        RayHit rh;
        ++stats.rays;
        if (!rs.accel().intersect(origin, dir, k_infinity, &rh, time)) {
            const Vec3 far = origin + dir * (4.0f * lights.scene_radius() + length(origin));
            for (uint32_t index : lights.infinite_lights()) radiance += lights.radiance(index, far, -dir);
        }
    }

    PathVertex& z = state.camera_vertex;
    z.reset_endpoint(PathVertex::Kind::Camera);
    z.p = origin;
    z.beta = Rgb(1.0f);
    z.delta = camera.orthographic();
    const int n_light = trace_light_subpath(ctx, state.light, m_settings.max_depth, rng);
    for (int s = 1; s <= n_light; ++s) {
        CameraConnection cc;
        if (!connect_to_camera(ctx, state.light, s, z, state.seen, &cc)) continue;
        if (cc.value.is_finite())
            film.add_splat(cc.px, cc.py, cc.value, rng.sample_index());
        else
            ++stats.nonfinite;
    }
    return radiance;
}

template class PixelSampleIntegrator<LightTracer>;

}  // namespace veach
