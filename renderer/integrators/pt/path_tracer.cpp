#include "integrators/pt/path_tracer.h"

#include "core/sobol_sampler.h"
#include "integrators/shading_point.h"
#include "materials/volume_absorption.h"

namespace veach {

namespace {
// Russian roulette starts after this many bounces: the first bounces carry most of the image
// and terminating them early only adds noise.
constexpr int k_roulette_start = 3;
}  // namespace

Rgb PathTracer::trace(const RenderScene& rs, const CameraModel& camera, Vec3 origin, Vec3 dir, float time,
                      Sampler& rng, ThreadStats& stats) const {
    const LightSet& lights = rs.lights();
    Rgb radiance(0.0f);
    Rgb beta(1.0f);
    Rgb sigma_a(0.0f);           // absorption of the medium the ray travels in (KHR_materials_volume)
    float prev_bsdf_pdf = 0.0f;  // solid-angle density of the direction that led here
    bool prev_specular = true;   // camera rays count as specular: no MIS for what they see
    Vec3 prev_p = origin;

    for (int bounce = 0;; ++bounce) {
        RayHit rh;
        ++stats.rays;
        bool found = rs.accel().intersect(origin, dir, k_infinity, &rh, time);
        // Lights with a shape of their own (area lights, spheres) are not scene geometry: the ray
        // picks up what they send toward it and goes on (they cast no shadow), as in Cycles.
        if (!lights.shape_lights().empty()) {
            float t_max = found ? rh.t : k_infinity;
            for (uint32_t index : lights.shape_lights()) {
                LightHit lh;
                if (!lights.intersect(index, origin, dir, t_max, &lh)) continue;
                Rgb le = lights.radiance(index, lh.p, -dir);
                if (le.is_black()) continue;
                float w = prev_specular ? 1.0f
                                        : power_heuristic(prev_bsdf_pdf, lights.pdf_direct_w(index, prev_p, lh.p, dir));
                radiance += beta * beer_lambert(sigma_a, lh.t * length(dir)) * le * w;
            }
        }
        if (!found) {
            if (bounce == 0 && m_settings.transparent) break;  // a transparent film's background
            // Escaped: the environment and sun discs, weighted against the light sample that
            // could have chosen the same direction (its density is per solid angle, as the BSDF's).
            for (uint32_t index : lights.infinite_lights()) {
                Rgb le = lights.radiance(index, origin, -dir);
                float w = prev_specular
                              ? 1.0f
                              : power_heuristic(prev_bsdf_pdf, lights.pdf_direct_w(index, origin, origin, dir));
                radiance += beta * le * w;
            }
            break;
        }
        // The camera ray's cone picks texture mip levels; later bounces read full resolution
        // (README, "Textures").
        const ShadingPoint sp = make_shading_point(rs, rh, bounce == 0 ? camera.footprint_width(rh.t, dir) : 0.0f);
        const SurfaceHit& hit = sp.hit;
        beta *= beer_lambert(sigma_a, rh.t * length(dir));  // the segment just travelled
        Vec3 wo = -dir;

        // Emission found by the BSDF-sampled direction (or seen directly by the camera).
        const int64_t emitter = sp.emitter(rs);
        if (emitter >= 0) {
            Rgb le = sp.emitted(rs, emitter, wo);
            if (!le.is_black()) {
                float w = 1.0f;
                if (!prev_specular) {
                    float light_pdf = lights.pdf_direct_w(static_cast<size_t>(emitter), prev_p, hit.p, dir);
                    w = power_heuristic(prev_bsdf_pdf, light_pdf);
                }
                radiance += beta * le * w;
            }
        }
        if (bounce >= m_settings.max_depth) break;

        SurfaceBsdf bsdf = sp.bsdf(rs, wo);
        if (bsdf.is_black()) break;

        // Next-event estimation.
        // The same dimensions are drawn whether or not a light sample is taken, so the
        // sampler's pairs stay aligned from path to path.
        float u_light_select = rng.next_1d();
        Vec2 u_light = rng.next_2d();
        LightSample ls;
        if (!lights.empty() && !bsdf.is_pure_delta() &&
            lights.sample_direct(hit.p, u_light_select, u_light.x, u_light.y, &ls)) {
            Rgb f = bsdf.eval(wo, ls.wi, TransportMode::Radiance);
            if (!f.is_black()) {
                Vec3 o = offset_ray_origin(hit.p, hit.p_error, hit.ng, ls.wi);
                float t_max = ls.is_infinite ? k_infinity : length(ls.point - o) * (1.0f - k_shadow_epsilon);
                ++stats.rays;
                if (!rs.accel().occluded(o, ls.wi, t_max, time)) {
                    float w = ls.is_delta ? 1.0f : power_heuristic(ls.pdf_w, bsdf.pdf_w(wo, ls.wi));
                    // The shadow segment travels in the medium on its side of this surface (a
                    // light sample through the wall of a glass block leaves the block at once).
                    Rgb sigma_ls = bsdf.medium_toward(ls.wi, sigma_a, *hit.material);
                    Rgb tr = beer_lambert(sigma_ls, ls.is_infinite ? 0.0f : length(ls.point - hit.p));
                    radiance += beta * tr * f * ls.radiance * (w / ls.pdf_w);
                }
            }
        }

        // Continue the path by sampling the BSDF.
        BsdfSample bs;
        float u_lobe = rng.next_1d();
        Vec2 u_dir = rng.next_2d();
        if (!bsdf.sample(wo, u_lobe, u_dir.x, u_dir.y, TransportMode::Radiance, &bs)) break;
        beta *= bs.weight;
        // Crossing a transmissive surface changes the medium.
        sigma_a = bsdf.medium_toward(bs.wi, sigma_a, *hit.material);
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

template class PixelSampleIntegrator<PathTracer>;

}  // namespace veach
