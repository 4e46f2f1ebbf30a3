#include "integrators/bdpt/camera_connection.h"

#include "integrators/shading_point.h"
#include "materials/volume_absorption.h"

namespace veach {

namespace {

// The emissive texture of triangle light `tl` at point p, read with the footprint of the camera
// ray that would reach p from `distance` along unit `dir`.
Rgb emission_seen_by_camera(const SubpathContext& ctx, const TriangleLight& tl, const Vec3& p, float distance,
                            const Vec3& dir) {
    Vec2 b;
    if (!tl.barycentrics(p, &b)) return Rgb(0.0f);
    RayHit rh;
    rh.instance = tl.instance;
    rh.prim = tl.prim;
    rh.u = b.x;
    rh.v = b.y;
    SurfaceHit hit = make_surface_hit(*ctx.rs, rh, ctx.camera->footprint_width(distance, dir));
    return evaluate_emission(*hit.material, ctx.rs->scene(), hit.attr);
}

}  // namespace

bool connect_to_camera(const SubpathContext& ctx, const std::vector<PathVertex>& light, int s, const PathVertex& z,
                       PathVertex& seen, CameraConnection* out) {
    const CameraModel& camera = *ctx.camera;
    const LightSet& lights = *ctx.lights;
    const PathVertex& y = light[s - 1];
    if (camera.orthographic()) return false;
    if (s > 1 && y.bsdf.is_pure_delta()) return false;
    if (s == 1 && y.delta_light) return false;  // point and sun lights are invisible to the camera
    if (s == 1 && y.infinite) return false;     // the environment: seen by s = 0 alone
    Vec3 d = y.p - z.p;
    float dist2 = length_squared(d);
    if (!(dist2 > 0.0f)) return false;
    Vec3 w = d / std::sqrt(dist2);
    float we = camera.importance(w);
    float px, py;
    if (!(we > 0.0f) || !camera.project(y.p, &px, &py)) return false;
    Rgb f;
    Rgb y_beta = y.beta;
    // Every other strategy reaches this point by the camera's own ray, which reads its textures
    // with the pixel's footprint (README "Textures"): shaded again with that footprint, y makes
    // the same integrand, and its densities in the MIS weight are the ones the camera strategies
    // use for the same vertex.
    bool reshaded = s > 1 && y.material && y.material->has_textures();
    if (reshaded) {
        seen = y;
        RayHit rh;
        rh.instance = y.instance;
        rh.prim = y.prim;
        rh.u = y.b1;
        rh.v = y.b2;
        rh.time = ctx.time;  // where the subpath found it
        fill_surface_vertex(*ctx.rs, rh, normalize(y.p - light[s - 2].p), &seen,
                            camera.footprint_width(std::sqrt(dist2), w));
        seen.delta = y.delta;
        seen.p = y.p;  // bit-identical to the vertex the subpath found
    }
    const PathVertex& ys = reshaded ? seen : y;
    if (s == 1) {
        // y.beta = Le / (pmf pdf_pos): the light point itself, seen by the camera. Whether it
        // emits toward the camera does not depend on the side the emission sample picked for its
        // direction.
        const Light& yl = lights.light(static_cast<size_t>(y.light));
        if (const auto* tl = std::get_if<TriangleLight>(&yl)) {
            if (tl->radiance_toward(-w, Rgb(1.0f)).is_black()) return false;
            // The camera's own ray reads an emissive texture with the pixel's footprint (README
            // "Textures"): so does this strategy, for one integrand.
            if (tl->textured) {
                float pdf_pos, pdf_dir;
                lights.pdf_emission(static_cast<size_t>(y.light), y.p, -w, &pdf_pos, &pdf_dir);
                y_beta = emission_seen_by_camera(ctx, *tl, y.p, std::sqrt(dist2), w) /
                         (lights.selection_pmf(static_cast<size_t>(y.light)) * pdf_pos);
            }
        } else {
            // Lights whose radiance depends on the direction (spheres of spot lights).
            float pdf_pos, pdf_dir;
            lights.pdf_emission(static_cast<size_t>(y.light), y.p, -w, &pdf_pos, &pdf_dir);
            Rgb le = lights.radiance(static_cast<size_t>(y.light), y.p, -w);
            if (le.is_black() || !(pdf_pos > 0.0f)) return false;
            y_beta = le / (lights.selection_pmf(static_cast<size_t>(y.light)) * pdf_pos);
        }
        f = Rgb(std::fabs(dot(y.ng, w)));
    } else {
        f = ys.bsdf.eval(normalize(light[s - 2].p - y.p), -w, TransportMode::Importance);
    }
    if (f.is_black()) return false;
    Rgb c = y_beta * f * (we * dot(w, camera.forward()) / dist2);
    c *= beer_lambert(medium_toward(ys, -w), std::sqrt(dist2));
    if (c.is_black() || !visible(ctx, y, z)) return false;
    out->px = px;
    out->py = py;
    out->value = c;
    out->reshaded = reshaded;
    return true;
}

}  // namespace veach
