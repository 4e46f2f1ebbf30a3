#include "integrators/pt/path_tracer.h"

#include "core/rng.h"
#include "integrators/surface_hit.h"
#include "materials/surface_bsdf.h"

namespace veach {

namespace {
// Russian roulette starts after this many bounces: the first bounces carry most of the image
// and terminating them early only adds noise.
constexpr int k_roulette_start = 3;
}  // namespace

Rgb PathTracer::trace(const RenderScene& rs, Vec3 origin, Vec3 dir, Rng& rng, ThreadStats& stats) const {
    const Scene& scene = rs.scene();
    const LightSet& lights = rs.lights();
    Rgb radiance(0.0f);
    Rgb beta(1.0f);
    float prev_bsdf_pdf = 0.0f;  // solid-angle density of the direction that led here
    bool prev_specular = true;   // camera rays count as specular: no MIS for what they see
    Vec3 prev_p = origin;

    for (int bounce = 0;; ++bounce) {
        RayHit rh;
        ++stats.rays;
        if (!rs.accel().intersect(origin, dir, k_infinity, &rh)) break;
        SurfaceHit hit = make_surface_hit(rs, rh);
        Vec3 wo = -dir;

        // Emission found by the BSDF-sampled direction (or seen directly by the camera).
        int64_t emitter = lights.emitter_of(hit.instance, hit.prim);
        if (emitter >= 0) {
            const auto& tl = std::get<TriangleLight>(lights.light(static_cast<size_t>(emitter)));
            Rgb le = lights.triangle_radiance(tl, wo, evaluate_emission(*hit.material, scene, hit.attr));
            if (!le.is_black()) {
                float w = 1.0f;
                if (!prev_specular) {
                    float light_pdf = lights.pdf_direct_w(static_cast<size_t>(emitter), prev_p, hit.p);
                    w = power_heuristic(prev_bsdf_pdf, light_pdf);
                }
                radiance += beta * le * w;
            }
        }
        if (bounce >= m_settings.max_depth) break;

        ShadingInputs in = evaluate_material(*hit.material, scene, hit.attr);
        SurfaceBsdf bsdf(hit.ng, hit.ns, wo, in);
        if (bsdf.is_black()) break;

        // Next-event estimation.
        LightSample ls;
        if (!lights.empty() && !bsdf.is_pure_delta() &&
            lights.sample_direct(hit.p, rng.next_float(), rng.next_float(), rng.next_float(), &ls)) {
            Rgb f = bsdf.eval(wo, ls.wi, TransportMode::Radiance);
            if (!f.is_black()) {
                Vec3 o = offset_ray_origin(hit.p, hit.p_error, hit.ng, ls.wi);
                float t_max = ls.is_infinite ? k_infinity : length(ls.point - o) * (1.0f - k_shadow_epsilon);
                ++stats.rays;
                if (!rs.accel().occluded(o, ls.wi, t_max)) {
                    float w = ls.is_delta ? 1.0f : power_heuristic(ls.pdf_w, bsdf.pdf_w(wo, ls.wi));
                    radiance += beta * f * ls.radiance * (w / ls.pdf_w);
                }
            }
        } else {
            rng.next_float(); rng.next_float(); rng.next_float();  // keep the stream aligned
        }

        // Continue the path by sampling the BSDF.
        BsdfSample bs;
        if (!bsdf.sample(wo, rng.next_float(), rng.next_float(), rng.next_float(), TransportMode::Radiance, &bs))
            break;
        beta *= bs.weight;
        if (bounce + 1 >= k_roulette_start) {
            float q = std::min(1.0f, beta.max());
            if (rng.next_float() >= q) break;
            beta = beta / q;
        }
        if (beta.is_black()) break;
        prev_bsdf_pdf = bs.pdf_w;
        prev_specular = bs.delta;  // what a delta bounce finds cannot be sampled by a light sample
        prev_p = hit.p;
        origin = offset_ray_origin(hit.p, hit.p_error, hit.ng, bs.wi);
        dir = bs.wi;
    }
    return radiance;
}

void PathTracer::render_tile(const RenderScene& rs, const Tile& tile, uint32_t sample_begin, uint32_t sample_end,
                             Film& film, ThreadStats& stats) const {
    const CameraModel& camera = rs.camera();
    for (int y = tile.y0; y < tile.y1; ++y) {
        for (int x = tile.x0; x < tile.x1; ++x) {
            uint64_t pixel = static_cast<uint64_t>(y) * film.width() + x;
            for (uint32_t s = sample_begin; s < sample_end; ++s) {
                Rng rng = Rng::for_sample(m_settings.seed, pixel, s);
                float fx = x + rng.next_float(), fy = y + rng.next_float();
                Vec3 o, d;
                camera.generate_ray(fx, fy, &o, &d);
                Rgb l = trace(rs, o, d, rng, stats);
                if (!l.is_finite()) {
                    ++stats.nonfinite;  // dropped, never written
                    continue;
                }
                film.add_sample(x, y, l);
            }
        }
    }
}

}  // namespace veach
