#include "integrators/bdpt/subpaths.h"

#include "integrators/bdpt/vertex_densities.h"
#include "integrators/shading_point.h"
#include "materials/volume_absorption.h"

namespace veach {

namespace {
// Subpaths start Russian roulette after this many vertices (camera and light vertex included).
constexpr int k_roulette_start_vertex = 4;
}  // namespace

void fill_surface_vertex(const RenderScene& rs, const RayHit& rh, const Vec3& dir, PathVertex* v,
                         float footprint_width) {
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
int random_walk(const SubpathContext& ctx, std::vector<PathVertex>& path, int count, Vec3 origin, Vec3 dir, Rgb beta,
                float pdf_w, TransportMode mode, int max_vertices, Sampler& rng, float roulette_scale,
                SegmentObserver* observer) {
    const RenderScene& rs = *ctx.rs;
    const LightSet& lights = *ctx.lights;
    Rgb sigma(0.0f);  // both subpaths start in air
    while (count < max_vertices) {
        RayHit rh;
        ++ctx.stats->rays;
        bool found = rs.accel().intersect(origin, dir, k_infinity, &rh, ctx.time);
        if (observer && mode == TransportMode::Radiance && !lights.shape_lights().empty())
            observer->segment(path, count, origin, dir, found ? rh.t : k_infinity, beta, sigma, pdf_w);
        if (!found) {
            if (mode == TransportMode::Radiance && !lights.infinite_lights().empty()) {
                // A camera subpath that escapes ends on the environment: a light vertex at
                // infinity, where directions are the area measure (pdf_fwd per solid angle).
                PathVertex& v = path[count];
                v.reset_endpoint(PathVertex::Kind::Light);
                v.infinite = true;
                v.light = lights.infinite_lights().front();  // the strategies visit each of them
                v.light_dir = -dir;
                v.p = origin + dir * (4.0f * lights.scene_radius() + length(origin));
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
        fill_surface_vertex(rs, rh, dir, &v, camera_ray ? ctx.camera->footprint_width(rh.t, dir) : 0.0f);
        beta *= beer_lambert(sigma, rh.t * length(dir));  // the segment just travelled
        v.beta = beta;
        v.sigma_in = sigma;
        if (prev.kind == PathVertex::Kind::Light && prev.infinite) {
            // Parallel rays from a disc: the density of the point is the disc's, projected.
            v.pdf_fwd = pdf_w * std::fabs(dot(v.ng, dir));
        } else if (prev.kind == PathVertex::Kind::Camera && ctx.camera->orthographic()) {
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

int trace_camera_subpath(const SubpathContext& ctx, std::vector<PathVertex>& path, float fx, float fy, int max_depth,
                         Sampler& rng, SegmentObserver* observer) {
    const CameraModel& camera = *ctx.camera;
    PathVertex& c = path[0];
    c.reset_endpoint(PathVertex::Kind::Camera);
    Vec3 origin, dir;
    camera.generate_ray(fx, fy, &origin, &dir);
    c.p = origin;
    c.beta = Rgb(1.0f);
    // An orthographic camera is a delta in direction: no strategy can reach it from a light.
    c.delta = camera.orthographic();
    float pdf_w = camera.orthographic() ? 1.0f / camera.image_plane_area() : camera.pdf_dir_w(dir);
    int max_vertices = max_depth + 2;
    return random_walk(ctx, path, 1, origin, dir, Rgb(1.0f), pdf_w, TransportMode::Radiance, max_vertices, rng, 1.0f,
                       observer);
}

int trace_light_subpath(const SubpathContext& ctx, std::vector<PathVertex>& path, int max_depth, Sampler& rng) {
    const LightSet& lights = *ctx.lights;
    LightEmission e;
    float u_select = rng.next_1d();
    Vec2 u_pos = rng.next_2d(), u_dir = rng.next_2d();
    float u1 = u_pos.x, u2 = u_pos.y, u3 = u_dir.x, u4 = u_dir.y;
    if (lights.empty() || !lights.sample_emission(u_select, u1, u2, u3, u4, &e)) return 0;
    float pmf = lights.selection_pmf(e.light);
    PathVertex& l = path[0];
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
    int max_vertices = max_depth + 1;
    Vec3 origin = e.point;
    if (l.has_normal) {
        // Leave the emitting triangle without hitting it again: the sampled point carries the
        // rounding error of its barycentric interpolation.
        l.p_error = abs(e.point) * (32.0f * 0x1p-24f);
        origin = offset_ray_origin(e.point, l.p_error, e.normal, e.dir);
    }
    if (!(beta.max() > 0.0f)) return 1;
    return random_walk(ctx, path, 1, origin, e.dir, beta, pdf_w, TransportMode::Importance, max_vertices, rng,
                       1.0f / beta.max());
}

bool visible(const SubpathContext& ctx, const PathVertex& a, const PathVertex& b) {
    ++ctx.stats->rays;
    Vec3 d = b.p - a.p;
    // Both ends leave their surfaces (or area lights) past the position's error bound.
    Vec3 o = a.has_normal ? offset_ray_origin(a.p, a.p_error, a.ng, d) : a.p;
    Vec3 target = b.has_normal ? offset_ray_origin(b.p, b.p_error, b.ng, -d) : b.p;
    Vec3 dt = target - o;
    float dist = length(dt);
    if (!(dist > 0.0f)) return false;
    return !ctx.rs->accel().occluded(o, dt / dist, dist * (1.0f - k_shadow_epsilon), ctx.time);
}

}  // namespace veach
