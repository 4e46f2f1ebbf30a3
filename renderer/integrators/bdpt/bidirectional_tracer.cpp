#include "integrators/bdpt/bidirectional_tracer.h"

#include <vector>

#include "core/sobol_sampler.h"
#include "integrators/bdpt/path_vertex.h"
#include "integrators/first_hit_aovs.h"
#include "integrators/shading_point.h"
#include "materials/volume_absorption.h"

namespace veach {

namespace {

// Subpaths start Russian roulette after this many vertices (camera and light vertex included).
constexpr int k_roulette_start_vertex = 4;

float remap0(float v) { return v != 0.0f ? v : 1.0f; }

// Converts a solid-angle density at `from` toward `to` into an area density at `to`.
float to_area_density(float pdf_w, const PathVertex& from, const PathVertex& to) {
    if (to.infinite) return pdf_w;  // directions are the "area" measure at infinity
    Vec3 d = to.p - from.p;
    float dist2 = length_squared(d);
    if (!(dist2 > 0.0f)) return 0.0f;
    float pdf = pdf_w / dist2;
    if (to.has_normal) pdf *= std::fabs(dot(to.ng, d)) / std::sqrt(dist2);
    return pdf;
}

// KHR_materials_volume. Media are the interiors of closed, non-nested transmissive meshes, as the
// path tracer assumes; cameras, lights and the environment are in air. A vertex knows the medium
// its own subpath arrived through (sigma_in); a segment leaving it on that side travels in the
// same medium, one leaving through a transmissive surface travels in the mesh's interior when it
// enters and in air when it leaves. Beer-Lambert transmittance is part of each edge's throughput:
// it is symmetric in the two ends and no sampling decision depends on it, so every strategy's
// densities, and with them the MIS weights, are those of the medium-free path. A connection edge
// takes its medium from the camera-side end (the path tracer's light-sample rule); in a closed
// scene the light-side end agrees, since the edge is unoccluded.
Rgb medium_toward(const PathVertex& v, const Vec3& w) {
    if (v.kind != PathVertex::Kind::Surface) return v.sigma_in;
    return v.bsdf.medium_toward(w, v.sigma_in, *v.material);
}

// Everything a thread needs for one tile: subpath storage allocated once, not per path.
struct Workspace {
    std::vector<PathVertex> camera, light;
    PathVertex light_sample;  // the light end of a next-event connection (s = 1)
    PathVertex seen;          // a light subpath vertex shaded again as the camera sees it (t = 1)
};

class Tracer {
public:
    Tracer(const RenderScene& rs, const RenderSettings& settings, const BdptOptions& options, ThreadStats& stats)
        : m_rs(rs),
          m_lights(rs.lights()),
          m_camera(&rs.camera()),
          m_settings(settings),
          m_options(options),
          m_stats(stats) {}

    // Traces one pixel sample at shutter time `time` (both subpaths, and `camera`, the camera
    // they join, at that time); returns the camera-side estimate and splats the light-tracing one.
    Rgb sample(Workspace& ws, const CameraModel& camera, float fx, float fy, float time, Sampler& rng, Film& film);

private:
    int trace_camera_subpath(Workspace& ws, float fx, float fy, Sampler& rng);
    int trace_light_subpath(Workspace& ws, Sampler& rng);
    int random_walk(std::vector<PathVertex>& path, int count, Vec3 origin, Vec3 dir, Rgb beta, float pdf_w,
                    TransportMode mode, int max_vertices, Sampler& rng, float roulette_scale);
    void add_shape_lights_crossed(std::vector<PathVertex>& path, int count, const Vec3& origin, const Vec3& dir,
                                  float t_max, const Rgb& beta, const Rgb& sigma, float pdf_w);
    bool visible(const PathVertex& a, const PathVertex& b);
    Rgb emitted_toward(const PathVertex& v, const Vec3& w) const;
    Rgb emission_seen_by_camera(const TriangleLight& tl, const Vec3& p, float distance, const Vec3& dir) const;
    float light_origin_pdf_a(const PathVertex& v, const Vec3& dir_out) const;
    float light_emission_pdf_area(const PathVertex& light_v, const PathVertex& to) const;
    float mis_weight(const std::vector<PathVertex>& light, int s, const std::vector<PathVertex>& camera, int t,
                     const PathVertex* sampled_light) const;
    bool wanted(int s, int t) const {
        if (s + t - 2 > m_settings.max_depth) return false;
        if (m_options.only_s >= 0) return s == m_options.only_s && t == m_options.only_t;
        // Light tracing: the t = 1 strategies, and the camera ray that escapes to a light at
        // infinity (s = 0, t = 2), the one path no light subpath can reach: a particle from
        // infinity meets the pinhole with probability zero.
        if (m_options.light_tracing_only) return t == 1 || (s == 0 && t == 2);
        return true;
    }
    bool weighted() const { return m_options.only_s < 0 && !m_options.light_tracing_only; }

    const RenderScene& m_rs;
    const LightSet& m_lights;
    const CameraModel* m_camera;  // the camera at the sample's shutter time
    float m_time = 0.0f;   // the sample's shutter time, every ray's
    const RenderSettings& m_settings;
    const BdptOptions& m_options;
    ThreadStats& m_stats;
    Rgb m_shape_radiance;  // s = 0 contributions of shaped lights the camera subpath crossed
};

// Fills a surface vertex from a hit and builds its BSDF facing the arriving direction.
void fill_surface_vertex(const RenderScene& rs, const RayHit& rh, const Vec3& dir, PathVertex* v,
                         float footprint_width = 0.0f) {
    const ShadingPoint sp = make_shading_point(rs, rh, footprint_width);
    const SurfaceHit& hit = sp.hit;
    v->kind = PathVertex::Kind::Surface;
    v->p = hit.p;
    v->p_error = hit.p_error;
    v->ng = hit.ng;
    v->has_normal = true;
    v->delta = false;
    v->delta_light = false;
    v->infinite = false;
    v->material = hit.material;
    v->attr = hit.attr;
    v->instance = hit.instance;
    v->prim = hit.prim;
    v->b1 = hit.b1;
    v->b2 = hit.b2;
    v->light = sp.emitter(rs);
    v->bsdf = sp.bsdf(rs, -dir);
}

// roulette_scale: 1 / the throughput the subpath started with, so that Russian roulette follows
// the fraction of it still carried (a light subpath's throughput is in units of emitted power,
// far above 1, and compared with 1 it would never be terminated).
int Tracer::random_walk(std::vector<PathVertex>& path, int count, Vec3 origin, Vec3 dir, Rgb beta, float pdf_w,
                        TransportMode mode, int max_vertices, Sampler& rng, float roulette_scale) {
    Rgb sigma(0.0f);  // both subpaths start in air
    while (count < max_vertices) {
        RayHit rh;
        ++m_stats.rays;
        bool found = m_rs.accel().intersect(origin, dir, k_infinity, &rh, m_time);
        if (mode == TransportMode::Radiance && !m_lights.shape_lights().empty())
            add_shape_lights_crossed(path, count, origin, dir, found ? rh.t : k_infinity, beta, sigma, pdf_w);
        if (!found) {
            if (mode == TransportMode::Radiance && !m_lights.infinite_lights().empty()) {
                // A camera subpath that escapes ends on the environment: a light vertex at
                // infinity, where directions are the area measure (pdf_fwd per solid angle).
                PathVertex& v = path[count];
                v.reset_endpoint(PathVertex::Kind::Light);
                v.infinite = true;
                v.light = m_lights.infinite_lights().front();  // sample() visits each of them
                v.light_dir = -dir;
                v.p = origin + dir * (4.0f * m_lights.scene_radius() + length(origin));
                v.beta = beta;
                v.pdf_fwd = pdf_w;
                ++count;
            }
            break;
        }
        PathVertex& prev = path[count - 1];
        PathVertex& v = path[count];
        // Only the camera ray carries a cone for texture mip levels (README, "Textures").
        bool camera_ray = prev.kind == PathVertex::Kind::Camera;
        fill_surface_vertex(m_rs, rh, dir, &v, camera_ray ? m_camera->footprint_width(rh.t, dir) : 0.0f);
        beta *= beer_lambert(sigma, rh.t * length(dir));  // the segment just travelled
        v.beta = beta;
        v.sigma_in = sigma;
        if (prev.kind == PathVertex::Kind::Light && prev.infinite) {
            // Parallel rays from a disc: the density of the point is the disc's, projected.
            v.pdf_fwd = pdf_w * std::fabs(dot(v.ng, dir));
        } else if (prev.kind == PathVertex::Kind::Camera && m_camera->orthographic()) {
            v.pdf_fwd = pdf_w * std::fabs(dot(v.ng, dir));
        } else {
            v.pdf_fwd = to_area_density(pdf_w, prev, v);
        }
        v.pdf_rev = 0.0f;
        ++count;
        if (count >= max_vertices) break;

        Vec3 wo = -dir;
        BsdfSample bs;
        float u_lobe = rng.next_1d();
        Vec2 u_dir = rng.next_2d();
        if (v.bsdf.is_black() || !v.bsdf.sample(wo, u_lobe, u_dir.x, u_dir.y, mode, &bs)) break;
        Vec3 wi = bs.wi;
        float pdf_fwd_w = bs.pdf_w;
        float pdf_rev_w = v.bsdf.pdf_w(wi, wo);
        if (bs.delta) {
            // A delta bounce: no other strategy can produce this vertex pair; the zero densities
            // are skipped by the MIS recurrence (remap0) and the delta flag excludes them.
            v.delta = true;
            pdf_fwd_w = pdf_rev_w = 0.0f;
        }
        beta *= bs.weight;
        if (count >= k_roulette_start_vertex) {
            float q = std::min(1.0f, beta.max() * roulette_scale);
            if (rng.next_float() >= q) break;
            beta = beta / q;
        }
        if (beta.is_black()) break;
        prev.pdf_rev = to_area_density(pdf_rev_w, v, prev);
        pdf_w = pdf_fwd_w;
        sigma = medium_toward(v, wi);
        origin = offset_ray_origin(v.p, v.p_error, v.ng, wi);
        dir = wi;
    }
    return count;
}

// Lights with a shape (area lights, spheres) are not scene geometry and do not block rays: a camera
// subpath segment that crosses one is, for that light, a complete path found by the camera alone
// (s = 0), evaluated here with the crossing as a light vertex in slot `count`, which the walk then
// reuses for the surface behind it.
void Tracer::add_shape_lights_crossed(std::vector<PathVertex>& path, int count, const Vec3& origin, const Vec3& dir,
                                      float t_max, const Rgb& beta, const Rgb& sigma, float pdf_w) {
    int t = count + 1;
    // Light tracing reaches a shaped light the camera sees by its s = 1, t = 1 strategy.
    if (count >= static_cast<int>(path.size()) || !wanted(0, t) || m_options.light_tracing_only) return;
    for (uint32_t index : m_lights.shape_lights()) {
        LightHit lh;
        if (!m_lights.intersect(index, origin, dir, t_max, &lh)) continue;
        Rgb le = m_lights.radiance(index, lh.p, -dir);
        if (le.is_black()) continue;
        const PathVertex& prev = path[count - 1];
        PathVertex& v = path[count];
        v.reset_endpoint(PathVertex::Kind::Light);
        v.light = index;
        v.p = lh.p;
        v.ng = lh.n;
        v.has_normal = true;
        v.beta = beta * beer_lambert(sigma, lh.t * length(dir));
        if (prev.kind == PathVertex::Kind::Camera && m_camera->orthographic())
            v.pdf_fwd = pdf_w * std::fabs(dot(v.ng, dir));
        else
            v.pdf_fwd = to_area_density(pdf_w, prev, v);
        float w = weighted() ? mis_weight(path, 0, path, t, nullptr) : 1.0f;
        m_shape_radiance += v.beta * le * w;
    }
}

int Tracer::trace_camera_subpath(Workspace& ws, float fx, float fy, Sampler& rng) {
    PathVertex& c = ws.camera[0];
    c.reset_endpoint(PathVertex::Kind::Camera);
    Vec3 origin, dir;
    m_camera->generate_ray(fx, fy, &origin, &dir);
    c.p = origin;
    c.beta = Rgb(1.0f);
    // An orthographic camera is a delta in direction: no strategy can reach it from a light.
    c.delta = m_camera->orthographic();
    float pdf_w = m_camera->orthographic() ? 1.0f / m_camera->image_plane_area() : m_camera->pdf_dir_w(dir);
    int max_vertices = m_settings.max_depth + 2;
    return random_walk(ws.camera, 1, origin, dir, Rgb(1.0f), pdf_w, TransportMode::Radiance, max_vertices, rng, 1.0f);
}

int Tracer::trace_light_subpath(Workspace& ws, Sampler& rng) {
    LightEmission e;
    float u_select = rng.next_1d();
    Vec2 u_pos = rng.next_2d(), u_dir = rng.next_2d();
    float u1 = u_pos.x, u2 = u_pos.y, u3 = u_dir.x, u4 = u_dir.y;
    if (m_lights.empty() || !m_lights.sample_emission(u_select, u1, u2, u3, u4, &e)) return 0;
    float pmf = m_lights.selection_pmf(e.light);
    PathVertex& l = ws.light[0];
    l.reset_endpoint(PathVertex::Kind::Light);
    l.light = e.light;
    l.p = e.point;
    l.ng = e.normal;
    // The environment and sun discs emit from a disc at infinity: no surface, no normal.
    bool environment = e.infinite && !e.delta_direction;
    l.has_normal = !e.delta_position && !e.delta_direction && !environment;
    l.delta_light = e.delta_position || e.delta_direction;
    l.infinite = e.delta_direction || environment;
    l.light_dir = e.dir;
    l.beta = e.value / (pmf * e.pdf_pos_a);
    // At infinity the vertex's "area" density is the density of its direction (pbrt-v3 16.3).
    l.pdf_fwd = pmf * (environment ? e.pdf_dir_w : e.pdf_pos_a);
    Rgb beta = l.beta;
    float pdf_w = e.pdf_dir_w;
    if (environment) {
        beta = beta / e.pdf_dir_w;
        pdf_w = e.pdf_pos_a;  // the first hit's density: the disc's, projected
    } else if (e.delta_direction) {
        pdf_w = e.pdf_pos_a;  // handed to the first hit as the disc's area density
    } else {
        float cos_light = l.has_normal ? std::fabs(dot(e.normal, e.dir)) : 1.0f;
        beta = beta * (cos_light / e.pdf_dir_w);
    }
    int max_vertices = m_settings.max_depth + 1;
    Vec3 origin = e.point;
    if (l.has_normal) {
        // Leave the emitting triangle without hitting it again: the sampled point carries the
        // rounding error of its barycentric interpolation.
        l.p_error = abs(e.point) * (32.0f * 0x1p-24f);
        origin = offset_ray_origin(e.point, l.p_error, e.normal, e.dir);
    }
    if (!(beta.max() > 0.0f)) return 1;
    return random_walk(ws.light, 1, origin, e.dir, beta, pdf_w, TransportMode::Importance, max_vertices, rng,
                       1.0f / beta.max());
}

bool Tracer::visible(const PathVertex& a, const PathVertex& b) {
    ++m_stats.rays;
    Vec3 d = b.p - a.p;
    // Both ends leave their surfaces (or area lights) past the position's error bound.
    Vec3 o = a.has_normal ? offset_ray_origin(a.p, a.p_error, a.ng, d) : a.p;
    Vec3 target = b.has_normal ? offset_ray_origin(b.p, b.p_error, b.ng, -d) : b.p;
    Vec3 dt = target - o;
    float dist = length(dt);
    if (!(dist > 0.0f)) return false;
    return !m_rs.accel().occluded(o, dt / dist, dist * (1.0f - k_shadow_epsilon), m_time);
}

// Radiance a surface vertex on an emitter (or the environment vertex) sends toward unit direction w.
Rgb Tracer::emitted_toward(const PathVertex& v, const Vec3& w) const {
    if (v.light < 0) return Rgb(0.0f);
    if (v.infinite) return m_lights.radiance(static_cast<size_t>(v.light), v.p, v.light_dir);
    if (v.kind == PathVertex::Kind::Light) return m_lights.radiance(static_cast<size_t>(v.light), v.p, w);
    if (v.kind != PathVertex::Kind::Surface) return Rgb(0.0f);
    return emitted_radiance(m_lights, m_rs.scene(), *v.material, v.attr, v.light, w);
}

// The emissive texture of triangle light `tl` at point p, read with the footprint of the camera
// ray that would reach p from `distance` along unit `dir`.
Rgb Tracer::emission_seen_by_camera(const TriangleLight& tl, const Vec3& p, float distance, const Vec3& dir) const {
    Vec2 b;
    if (!tl.barycentrics(p, &b)) return Rgb(0.0f);
    RayHit rh;
    rh.instance = tl.instance;
    rh.prim = tl.prim;
    rh.u = b.x;
    rh.v = b.y;
    SurfaceHit hit = make_surface_hit(m_rs, rh, m_camera->footprint_width(distance, dir));
    return evaluate_emission(*hit.material, m_rs.scene(), hit.attr);
}

// Area density with which the light sampler produces point v (on a light) as a path origin.
float Tracer::light_origin_pdf_a(const PathVertex& v, const Vec3& dir_out) const {
    float pdf_pos, pdf_dir;
    if (m_lights.is_at_infinity(static_cast<size_t>(v.light)) && !v.delta_light) {
        // At infinity the origin's "area" density is that of its direction.
        m_lights.pdf_emission(static_cast<size_t>(v.light), v.p, v.light_dir, &pdf_pos, &pdf_dir);
        return m_lights.selection_pmf(static_cast<size_t>(v.light)) * pdf_dir;
    }
    m_lights.pdf_emission(static_cast<size_t>(v.light), v.p, dir_out, &pdf_pos, &pdf_dir);
    return m_lights.selection_pmf(static_cast<size_t>(v.light)) * pdf_pos;
}

// Area density at `to` of a particle emitted from light vertex (or emitter surface) `light_v`.
float Tracer::light_emission_pdf_area(const PathVertex& light_v, const PathVertex& to) const {
    if (light_v.infinite) {
        float pdf_pos, pdf_dir;
        m_lights.pdf_emission(static_cast<size_t>(light_v.light), light_v.p, light_v.light_dir, &pdf_pos, &pdf_dir);
        return to.has_normal ? pdf_pos * std::fabs(dot(to.ng, light_v.light_dir)) : pdf_pos;
    }
    Vec3 d = to.p - light_v.p;
    float len = length(d);
    if (!(len > 0.0f)) return 0.0f;
    float pdf_pos, pdf_dir;
    m_lights.pdf_emission(static_cast<size_t>(light_v.light), light_v.p, d / len, &pdf_pos, &pdf_dir);
    return to_area_density(pdf_dir, light_v, to);
}

float Tracer::mis_weight(const std::vector<PathVertex>& light, int s, const std::vector<PathVertex>& camera, int t,
                         const PathVertex* sampled_light) const {
    // The vertices at the connection, whose pdf_rev depend on the strategy.
    const PathVertex* y = s > 0 ? (s == 1 && sampled_light ? sampled_light : &light[s - 1]) : nullptr;
    const PathVertex* y_prev = s > 1 ? &light[s - 2] : nullptr;
    const PathVertex* z = &camera[t - 1];
    const PathVertex* z_prev = t > 1 ? &camera[t - 2] : nullptr;

    float z_rev = 0, z_prev_rev = 0, y_rev = 0, y_prev_rev = 0;
    if (s == 0) {
        z_rev = light_origin_pdf_a(*z, z_prev ? normalize(z_prev->p - z->p) : Vec3(0, 0, 1));
        if (z_prev) {
            z_prev_rev = light_emission_pdf_area(*z, *z_prev);  // z as the origin of a light subpath
        }
    } else {
        if (t > 1) {
            if (s == 1) {
                z_rev = light_emission_pdf_area(*y, *z);
            } else {
                Vec3 wo = normalize(y_prev->p - y->p), wi = normalize(z->p - y->p);
                z_rev = to_area_density(y->bsdf.pdf_w(wo, wi), *y, *z);
            }
            Vec3 wo = normalize(y->p - z->p), wi = normalize(z_prev->p - z->p);
            z_prev_rev = to_area_density(z->bsdf.pdf_w(wo, wi), *z, *z_prev);
        }
        if (t == 1) {
            y_rev = to_area_density(m_camera->pdf_dir_w(normalize(y->p - z->p)), *z, *y);
        } else {
            Vec3 wo = normalize(z_prev->p - z->p), wi = normalize(y->p - z->p);
            y_rev = to_area_density(z->bsdf.pdf_w(wo, wi), *z, *y);
        }
        if (y_prev) {
            Vec3 wo = normalize(z->p - y->p), wi = normalize(y_prev->p - y->p);
            y_prev_rev = to_area_density(y->bsdf.pdf_w(wo, wi), *y, *y_prev);
        }
    }

    double sum = 0.0;
    // Camera side: strategies that would have made more of the path from the light.
    double r = 1.0;
    for (int i = t - 1; i > 0; --i) {
        float rev = i == t - 1 ? z_rev : (i == t - 2 ? z_prev_rev : camera[i].pdf_rev);
        r *= remap0(rev) / remap0(camera[i].pdf_fwd);
        // (s, t) = (1, 1) from the environment is never sampled: the camera sees it only by s = 0.
        bool unsampled = s == 0 && t == 2 && camera[1].infinite;
        if (!camera[i].delta && !camera[i - 1].delta && !unsampled) sum += r * r;
    }
    // Light side: strategies that would have made more of the path from the camera.
    r = 1.0;
    for (int i = s - 1; i >= 0; --i) {
        const PathVertex& v = (i == 0 && s == 1 && sampled_light) ? *sampled_light : light[i];
        float rev = i == s - 1 ? y_rev : (i == s - 2 ? y_prev_rev : v.pdf_rev);
        r *= remap0(rev) / remap0(v.pdf_fwd);
        bool delta_before = i > 0 ? light[i - 1].delta : v.delta_light;
        if (!v.delta && !delta_before) sum += r * r;
    }
    return static_cast<float>(1.0 / (1.0 + sum));
}

Rgb Tracer::sample(Workspace& ws, const CameraModel& camera, float fx, float fy, float time, Sampler& rng,
                   Film& film) {
    m_camera = &camera;
    m_time = time;
    m_shape_radiance = Rgb(0.0f);
    int n_camera = trace_camera_subpath(ws, fx, fy, rng);
    int n_light = trace_light_subpath(ws, rng);
    Rgb radiance = m_shape_radiance;

    for (int t = 1; t <= n_camera; ++t) {
        for (int s = 0; s <= n_light || (s == 1 && t > 1); ++s) {
            if (!wanted(s, t)) continue;
            const PathVertex& z = ws.camera[t - 1];
            if (s > 0 && z.kind == PathVertex::Kind::Light) continue;  // the environment ends a camera subpath
            if (s == 0) {
                // The camera subpath found an emitter by itself.
                if (t < 2 || z.light < 0) continue;
                if (m_options.light_tracing_only && !z.infinite) continue;  // reached by s = 1, t = 1
                if (z.infinite) {
                    // The camera ray itself escaped: a transparent film's background, which no
                    // other strategy samples (see mis_weight), so nothing else is left out.
                    if (t == 2 && m_settings.transparent) continue;
                    // Escaped: every light at infinity is seen along this direction, each with
                    // its own densities.
                    PathVertex& zi = ws.camera[t - 1];
                    int64_t first = zi.light;
                    for (uint32_t index : m_lights.infinite_lights()) {
                        zi.light = index;
                        Rgb le = emitted_toward(zi, Vec3());
                        if (le.is_black()) continue;
                        float w = weighted() ? mis_weight(ws.light, 0, ws.camera, t, nullptr) : 1.0f;
                        radiance += zi.beta * le * w;
                    }
                    zi.light = first;
                    continue;
                }
                Rgb le = emitted_toward(z, normalize(ws.camera[t - 2].p - z.p));
                if (le.is_black()) continue;
                Rgb c = z.beta * le;
                float w = weighted() ? mis_weight(ws.light, 0, ws.camera, t, nullptr) : 1.0f;
                radiance += c * w;
            } else if (t == 1) {
                // Connect light subpath vertex y to the camera; the result lands on another pixel.
                const PathVertex& y = ws.light[s - 1];
                if (m_camera->orthographic()) continue;
                if (s > 1 && y.bsdf.is_pure_delta()) continue;
                if (s == 1 && y.delta_light) continue;  // point and sun lights are invisible to the camera
                if (s == 1 && y.infinite) continue;     // the environment: seen by s = 0 alone
                Vec3 d = y.p - z.p;
                float dist2 = length_squared(d);
                if (!(dist2 > 0.0f)) continue;
                Vec3 w = d / std::sqrt(dist2);
                float we = m_camera->importance(w);
                float px, py;
                if (!(we > 0.0f) || !m_camera->project(y.p, &px, &py)) continue;
                Rgb f;
                Rgb y_beta = y.beta;
                // Every other strategy reaches this point by the camera's own ray, which reads its
                // textures with the pixel's footprint (README "Textures"): shaded again with that
                // footprint, y makes the same integrand, and its densities in the MIS weight are
                // the ones the camera strategies use for the same vertex.
                bool reshaded = s > 1 && y.material && y.material->has_textures();
                if (reshaded) {
                    PathVertex& seen = ws.seen;
                    seen = y;
                    RayHit rh;
                    rh.instance = y.instance;
                    rh.prim = y.prim;
                    rh.u = y.b1;
                    rh.v = y.b2;
                    rh.time = m_time;  // where the subpath found it
                    fill_surface_vertex(m_rs, rh, normalize(y.p - ws.light[s - 2].p), &seen,
                                        m_camera->footprint_width(std::sqrt(dist2), w));
                    seen.delta = y.delta;
                    seen.p = y.p;  // bit-identical to the vertex the subpath found
                }
                const PathVertex& ys = reshaded ? ws.seen : y;
                if (s == 1) {
                    // y.beta = Le / (pmf pdf_pos): the light point itself, seen by the camera.
                    // Whether it emits toward the camera does not depend on the side the
                    // emission sample picked for its direction.
                    const Light& yl = m_lights.light(static_cast<size_t>(y.light));
                    if (const auto* tl = std::get_if<TriangleLight>(&yl)) {
                        if (tl->radiance_toward(-w, Rgb(1.0f)).is_black()) continue;
                        // The camera's own ray reads an emissive texture with the pixel's
                        // footprint (README "Textures"): so does this strategy, for one integrand.
                        if (tl->textured) {
                            float pdf_pos, pdf_dir;
                            m_lights.pdf_emission(static_cast<size_t>(y.light), y.p, -w, &pdf_pos, &pdf_dir);
                            y_beta = emission_seen_by_camera(*tl, y.p, std::sqrt(dist2), w) /
                                     (m_lights.selection_pmf(static_cast<size_t>(y.light)) * pdf_pos);
                        }
                    } else {
                        // Lights whose radiance depends on the direction (spheres of spot lights).
                        float pdf_pos, pdf_dir;
                        m_lights.pdf_emission(static_cast<size_t>(y.light), y.p, -w, &pdf_pos, &pdf_dir);
                        Rgb le = m_lights.radiance(static_cast<size_t>(y.light), y.p, -w);
                        if (le.is_black() || !(pdf_pos > 0.0f)) continue;
                        y_beta = le / (m_lights.selection_pmf(static_cast<size_t>(y.light)) * pdf_pos);
                    }
                    f = Rgb(std::fabs(dot(y.ng, w)));
                } else {
                    f = ys.bsdf.eval(normalize(ws.light[s - 2].p - y.p), -w, TransportMode::Importance);
                }
                if (f.is_black()) continue;
                Rgb c = y_beta * f * (we * dot(w, m_camera->forward()) / dist2);
                c *= beer_lambert(medium_toward(ys, -w), std::sqrt(dist2));
                if (c.is_black() || !visible(y, z)) continue;
                float weight = 1.0f;
                if (weighted()) {
                    if (reshaded) std::swap(ws.light[s - 1], ws.seen);
                    weight = mis_weight(ws.light, s, ws.camera, 1, nullptr);
                    if (reshaded) std::swap(ws.light[s - 1], ws.seen);
                }
                c = c * weight;
                if (c.is_finite())
                    film.add_splat(px, py, c, rng.sample_index());
                else
                    ++m_stats.nonfinite;
            } else if (s == 1) {
                // Next-event estimation: a fresh point on a light.
                if (z.bsdf.is_black() || z.bsdf.is_pure_delta()) continue;
                LightSample ls;
                float u_select = rng.next_1d();
                Vec2 u_light = rng.next_2d();
                if (!m_lights.sample_direct(z.p, u_select, u_light.x, u_light.y, &ls)) continue;
                Vec3 wo = normalize(ws.camera[t - 2].p - z.p);
                Rgb f = z.bsdf.eval(wo, ls.wi, TransportMode::Radiance);
                if (f.is_black()) continue;
                Vec3 o = offset_ray_origin(z.p, z.p_error, z.ng, ls.wi);
                float t_max = ls.is_infinite ? k_infinity : length(ls.point - o) * (1.0f - k_shadow_epsilon);
                ++m_stats.rays;
                if (m_rs.accel().occluded(o, ls.wi, t_max, m_time)) continue;
                Rgb c = z.beta * f * ls.radiance / ls.pdf_w;
                c *= beer_lambert(medium_toward(z, ls.wi), ls.is_infinite ? 0.0f : length(ls.point - z.p));
                float w = 1.0f;
                if (weighted()) {
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
                    lv.pdf_fwd = light_origin_pdf_a(lv, -ls.wi);
                    w = mis_weight(ws.light, 1, ws.camera, t, &lv);
                }
                radiance += c * w;
            } else {
                // Join the two subpaths' end vertices.
                const PathVertex& y = ws.light[s - 1];
                if (y.bsdf.is_pure_delta() || z.bsdf.is_pure_delta() || z.bsdf.is_black()) continue;
                Vec3 d = z.p - y.p;
                float dist2 = length_squared(d);
                if (!(dist2 > 0.0f)) continue;
                Vec3 w = d / std::sqrt(dist2);
                Rgb fy = y.bsdf.eval(normalize(ws.light[s - 2].p - y.p), w, TransportMode::Importance);
                if (fy.is_black()) continue;
                Rgb fz = z.bsdf.eval(normalize(ws.camera[t - 2].p - z.p), -w, TransportMode::Radiance);
                if (fz.is_black()) continue;
                Rgb c = y.beta * fy * fz * z.beta / dist2;
                c *= beer_lambert(medium_toward(z, -w), std::sqrt(dist2));
                if (c.is_black() || !visible(z, y)) continue;
                float weight = weighted() ? mis_weight(ws.light, s, ws.camera, t, nullptr) : 1.0f;
                radiance += c * weight;
            }
        }
    }
    return radiance;
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
    return state.tracer.sample(state.ws, camera, fx, fy, time, rng, film);
}

template class PixelSampleIntegrator<BidirectionalTracer>;

}  // namespace veach
