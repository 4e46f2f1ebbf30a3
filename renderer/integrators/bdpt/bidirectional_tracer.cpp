#include "integrators/bdpt/bidirectional_tracer.h"

#include <vector>

#include "core/sobol_sampler.h"
#include "integrators/bdpt/camera_connection.h"
#include "integrators/bdpt/mis_weight.h"
#include "integrators/bdpt/strategy_families.h"
#include "integrators/bdpt/path_vertex.h"
#include "integrators/bdpt/subpaths.h"
#include "integrators/bdpt/vertex_densities.h"
#include "integrators/shading_point.h"
#include "materials/volume_absorption.h"

namespace veach {

namespace {

// Everything a thread needs for one tile: subpath storage allocated once, not per path.
struct Workspace {
    std::vector<PathVertex> camera, light;
    PathVertex light_sample;  // the light end of a next-event connection (s = 1)
    PathVertex seen;          // a light subpath vertex shaded again as the camera sees it (t = 1)
};

class Tracer final : public SegmentObserver {
public:
    Tracer(const RenderScene& rs, const RenderSettings& settings, const BdptOptions& options, ThreadStats& stats)
        : m_settings(settings), m_options(options) {
        m_ctx.rs = &rs;
        m_ctx.lights = &rs.lights();
        m_ctx.camera = &rs.camera();
        m_ctx.stats = &stats;
    }

    // Traces one pixel sample at shutter time `time` (both subpaths, and `camera`, the camera
    // they join, at that time); returns the camera-side estimate and splats the light-tracing one.
    // With `record`, every strategy's contribution goes there instead, unweighted (the probe).
    Rgb sample(Workspace& ws, const CameraModel& camera, float fx, float fy, float time, Sampler& rng, Film* film,
               ProbeSample* record = nullptr);

    // Lights with a shape (area lights, spheres) are not scene geometry and do not block rays: a
    // camera subpath segment that crosses one is, for that light, a complete path found by the
    // camera alone (s = 0), evaluated here with the crossing as a light vertex in slot `count`,
    // which the walk then reuses for the surface behind it.
    void segment(std::vector<PathVertex>& path, int count, const Vec3& origin, const Vec3& dir, float t_max,
                 const Rgb& beta, const Rgb& sigma, float pdf_w) override;

private:
    // Strategy (s, t) of the sample's subpaths: returns its camera-side contribution, splats a
    // t = 1 one.
    Rgb strategy(Workspace& ws, int s, int t, Sampler& rng, Film* film);
    Rgb emitted_toward(const PathVertex& v, const Vec3& w) const;
    float weight(const std::vector<PathVertex>& light, int s, const std::vector<PathVertex>& camera, int t,
                 const PathVertex* sampled_light) const {
        return mis_weight(*m_ctx.lights, *m_ctx.camera, light, s, camera, t, sampled_light, m_options.strategies);
    }
    // Contribution c of strategy (s, t) weighted; or, for the probe, recorded and zero.
    Rgb weighted(const Rgb& c, const std::vector<PathVertex>& light, int s, const std::vector<PathVertex>& camera,
                 int t, const PathVertex* sampled_light) {
        if (m_record) {
            record(c, light, s, camera, t, sampled_light, nullptr);
            return Rgb(0.0f);
        }
        return weighted() ? c * weight(light, s, camera, t, sampled_light) : c;
    }
    void record(const Rgb& c, const std::vector<PathVertex>& light, int s, const std::vector<PathVertex>& camera,
                int t, const PathVertex* sampled_light, const CameraConnection* splat) {
        ProbeContribution pc;
        pc.value = c;
        pc.family = static_cast<uint8_t>(strategy_family_index(s, t));
        mis_ratio_sums(*m_ctx.lights, *m_ctx.camera, light, s, camera, t, sampled_light, pc.ratio_squares,
                       pc.ratio_cubes);
        if (splat) {
            pc.splat = true;
            pc.px = splat->px;
            pc.py = splat->py;
        }
        m_record->contributions.push_back(pc);
    }
    bool wanted(int s, int t) const {
        if (s + t - 2 > m_settings.max_depth) return false;
        if (m_options.only_s >= 0) return s == m_options.only_s && t == m_options.only_t;
        return strategy_in(m_options.strategies, s, t);
    }
    bool weighted() const { return m_options.only_s < 0; }

    SubpathContext m_ctx;
    const RenderSettings& m_settings;
    const BdptOptions& m_options;
    Rgb m_shape_radiance;  // s = 0 contributions of shaped lights the camera subpath crossed
    ProbeSample* m_record = nullptr;
};

void Tracer::segment(std::vector<PathVertex>& path, int count, const Vec3& origin, const Vec3& dir, float t_max,
                     const Rgb& beta, const Rgb& sigma, float pdf_w) {
    const LightSet& lights = *m_ctx.lights;
    int t = count + 1;
    if (count >= static_cast<int>(path.size()) || !wanted(0, t)) return;
    for (uint32_t index : lights.shape_lights()) {
        LightHit lh;
        if (!lights.intersect(index, origin, dir, t_max, &lh)) continue;
        Rgb le = lights.radiance(index, lh.p, -dir);
        if (le.is_black()) continue;
        const PathVertex& prev = path[count - 1];
        PathVertex& v = path[count];
        v.reset_endpoint(PathVertex::Kind::Light);
        v.light = index;
        v.p = lh.p;
        v.ng = lh.n;
        v.has_normal = true;
        v.beta = beta * beer_lambert(sigma, lh.t * length(dir));
        if (prev.kind == PathVertex::Kind::Camera && m_ctx.camera->orthographic())
            v.pdf_fwd = pdf_w * std::fabs(dot(v.ng, dir));
        else
            v.pdf_fwd = to_area_density(pdf_w, prev, v);
        m_shape_radiance += weighted(v.beta * le, path, 0, path, t, nullptr);
    }
}

// Radiance a surface vertex on an emitter (or the environment vertex) sends toward unit direction w.
Rgb Tracer::emitted_toward(const PathVertex& v, const Vec3& w) const {
    const LightSet& lights = *m_ctx.lights;
    if (v.light < 0) return Rgb(0.0f);
    if (v.infinite) return lights.radiance(static_cast<size_t>(v.light), v.p, v.light_dir);
    if (v.kind == PathVertex::Kind::Light) return lights.radiance(static_cast<size_t>(v.light), v.p, w);
    if (v.kind != PathVertex::Kind::Surface) return Rgb(0.0f);
    return emitted_radiance(lights, m_ctx.rs->scene(), *v.material, v.attr, v.light, w);
}

Rgb Tracer::sample(Workspace& ws, const CameraModel& camera, float fx, float fy, float time, Sampler& rng, Film* film,
                   ProbeSample* record) {
    m_ctx.camera = &camera;
    m_ctx.time = time;
    m_shape_radiance = Rgb(0.0f);
    m_record = record;
    if (!record) {
        int n_camera = trace_camera_subpath(m_ctx, ws.camera, fx, fy, m_settings.max_depth, rng, this);
        int n_light = needs_light_subpath(m_options.strategies)
                          ? trace_light_subpath(m_ctx, ws.light, m_settings.max_depth, rng)
                          : 0;
        Rgb radiance = m_shape_radiance;
        for (int t = 1; t <= n_camera; ++t)
            for (int s = 0; s <= n_light || (s == 1 && t > 1); ++s)
                if (wanted(s, t)) radiance += strategy(ws, s, t, rng, film);
        return radiance;
    }
    // The probe: the same, with the rays of each part counted.
    record->contributions.clear();
    uint64_t& rays = m_ctx.stats->rays;
    uint64_t r0 = rays;
    int n_camera = trace_camera_subpath(m_ctx, ws.camera, fx, fy, m_settings.max_depth, rng, this);
    record->camera_rays = rays - r0;
    r0 = rays;
    int n_light = trace_light_subpath(m_ctx, ws.light, m_settings.max_depth, rng);
    record->light_rays = rays - r0;
    for (uint64_t& r : record->shadow_rays) r = 0;
    for (int t = 1; t <= n_camera; ++t) {
        for (int s = 0; s <= n_light || (s == 1 && t > 1); ++s) {
            if (!wanted(s, t)) continue;
            r0 = rays;
            strategy(ws, s, t, rng, film);
            record->shadow_rays[strategy_family_index(s, t)] += rays - r0;
        }
    }
    m_record = nullptr;
    return Rgb(0.0f);
}

Rgb Tracer::strategy(Workspace& ws, int s, int t, Sampler& rng, Film* film) {
    const LightSet& lights = *m_ctx.lights;
    const PathVertex& z = ws.camera[t - 1];
    if (s > 0 && z.kind == PathVertex::Kind::Light) return Rgb(0.0f);  // the environment ends a camera subpath
    if (s == 0) {
        // The camera subpath found an emitter by itself.
        if (t < 2 || z.light < 0) return Rgb(0.0f);
        if (z.infinite) {
            // The camera ray itself escaped: a transparent film's background, which no
            // other strategy samples (see mis_weight), so nothing else is left out.
            if (t == 2 && m_settings.transparent) return Rgb(0.0f);
            // Escaped: every light at infinity is seen along this direction, each with
            // its own densities.
            PathVertex& zi = ws.camera[t - 1];
            int64_t first = zi.light;
            Rgb radiance(0.0f);
            for (uint32_t index : lights.infinite_lights()) {
                zi.light = index;
                Rgb le = emitted_toward(zi, Vec3());
                if (le.is_black()) continue;
                radiance += weighted(zi.beta * le, ws.light, 0, ws.camera, t, nullptr);
            }
            zi.light = first;
            return radiance;
        }
        Rgb le = emitted_toward(z, normalize(ws.camera[t - 2].p - z.p));
        if (le.is_black()) return Rgb(0.0f);
        return weighted(z.beta * le, ws.light, 0, ws.camera, t, nullptr);
    } else if (t == 1) {
        // Connect light subpath vertex y to the camera; the result lands on another pixel.
        CameraConnection cc;
        if (!connect_to_camera(m_ctx, ws.light, s, z, ws.seen, &cc)) return Rgb(0.0f);
        float w = 1.0f;
        if (m_record || weighted()) {
            if (cc.reshaded) std::swap(ws.light[s - 1], ws.seen);
            if (m_record)
                record(cc.value, ws.light, s, ws.camera, 1, nullptr, &cc);
            else
                w = weight(ws.light, s, ws.camera, 1, nullptr);
            if (cc.reshaded) std::swap(ws.light[s - 1], ws.seen);
        }
        if (m_record) return Rgb(0.0f);
        Rgb c = cc.value * w;
        if (c.is_finite())
            film->add_splat(cc.px, cc.py, c, rng.sample_index());
        else
            ++m_ctx.stats->nonfinite;
        return Rgb(0.0f);
    } else if (s == 1) {
        // Next-event estimation: a fresh point on a light.
        if (z.bsdf.is_black() || z.bsdf.is_pure_delta()) return Rgb(0.0f);
        LightSample ls;
        float u_select = rng.next_1d();
        Vec2 u_light = rng.next_2d();
        if (!lights.sample_direct(z.p, u_select, u_light.x, u_light.y, &ls)) return Rgb(0.0f);
        Vec3 wo = normalize(ws.camera[t - 2].p - z.p);
        Rgb f = z.bsdf.eval(wo, ls.wi, TransportMode::Radiance);
        if (f.is_black()) return Rgb(0.0f);
        Vec3 o = offset_ray_origin(z.p, z.p_error, z.ng, ls.wi);
        float t_max = ls.is_infinite ? k_infinity : length(ls.point - o) * (1.0f - k_shadow_epsilon);
        ++m_ctx.stats->rays;
        if (m_ctx.rs->accel().occluded(o, ls.wi, t_max, m_ctx.time)) return Rgb(0.0f);
        Rgb c = z.beta * f * ls.radiance / ls.pdf_w;
        c *= beer_lambert(medium_toward(z, ls.wi), ls.is_infinite ? 0.0f : length(ls.point - z.p));
        if (m_record || weighted()) {
            PathVertex& lv = ws.light_sample;
            lv.reset_endpoint(PathVertex::Kind::Light);
            lv.light = ls.light;
            lv.p = ls.point;
            lv.infinite = ls.is_infinite;
            lv.delta_light = ls.is_delta;
            lv.light_dir = -ls.wi;
            if (length_squared(ls.normal) > 0.0f) {
                lv.has_normal = true;
                lv.ng = ls.normal;  // the side facing z
            }
            lv.pdf_fwd = light_origin_pdf_a(lights, lv, -ls.wi);
            return weighted(c, ws.light, 1, ws.camera, t, &lv);
        }
        return c;
    } else {
        // Join the two subpaths' end vertices.
        const PathVertex& y = ws.light[s - 1];
        if (y.bsdf.is_pure_delta() || z.bsdf.is_pure_delta() || z.bsdf.is_black()) return Rgb(0.0f);
        Vec3 d = z.p - y.p;
        float dist2 = length_squared(d);
        if (!(dist2 > 0.0f)) return Rgb(0.0f);
        Vec3 w = d / std::sqrt(dist2);
        Rgb fy = y.bsdf.eval(normalize(ws.light[s - 2].p - y.p), w, TransportMode::Importance);
        if (fy.is_black()) return Rgb(0.0f);
        Rgb fz = z.bsdf.eval(normalize(ws.camera[t - 2].p - z.p), -w, TransportMode::Radiance);
        if (fz.is_black()) return Rgb(0.0f);
        Rgb c = y.beta * fy * fz * z.beta / dist2;
        c *= beer_lambert(medium_toward(z, -w), std::sqrt(dist2));
        if (c.is_black() || !visible(m_ctx, z, y)) return Rgb(0.0f);
        return weighted(c, ws.light, s, ws.camera, t, nullptr);
    }
}

}  // namespace

struct BidirectionalTracer::TileState {
    Workspace ws;
    Tracer tracer;
};

BidirectionalTracer::TileState BidirectionalTracer::begin_tile(const RenderScene& rs, ThreadStats& stats) const {
    TileState state{Workspace{}, Tracer(rs, m_settings, m_options, stats)};
    state.ws.camera.resize(static_cast<size_t>(m_settings.max_depth) + 2);
    state.ws.light.resize(static_cast<size_t>(m_settings.max_depth) + 1);
    return state;
}

// Inline: its one caller is the loop instantiated below, into which it folds.
inline Rgb BidirectionalTracer::evaluate_pixel_sample(TileState& state, const RenderScene&, const CameraModel& camera,
                                                      float fx, float fy, float time, Sampler& rng, Film& film,
                                                      ThreadStats&) const {
    return state.tracer.sample(state.ws, camera, fx, fy, time, rng, &film);
}

void BidirectionalTracer::probe(const RenderScene& rs, const Film& film, uint64_t seed,
                                const std::vector<std::pair<int, int>>& pixels, size_t begin, size_t end, int samples,
                                const std::function<void(size_t, int, const ProbeSample&)>& visit) const {
    ThreadStats stats;
    TileState state = begin_tile(rs, stats);
    CameraModel moving_camera = rs.camera();
    ProbeSample record;
    for (size_t i = begin; i < end; ++i) {
        const auto [x, y] = pixels[i];
        const uint64_t pixel = static_cast<uint64_t>(y) * film.width() + x;
        for (int j = 0; j < samples; ++j) {
            // As the pixel loop draws a sample (pixel_sample_integrator.h).
            Sampler rng(m_settings.sampler, seed, pixel, static_cast<uint32_t>(j));
            auto [fx, fy] = film.sample_position(x, y, rng.next_2d());
            const float time = rs.shutter_time(rng);
            const CameraModel& camera = rs.camera_at(time, moving_camera);
            state.tracer.sample(state.ws, camera, fx, fy, time, rng, nullptr, &record);
            visit(i, j, record);
        }
    }
}

template class PixelSampleIntegrator<BidirectionalTracer>;

}  // namespace veach
