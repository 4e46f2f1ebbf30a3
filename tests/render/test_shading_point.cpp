// The shading point is where a hit becomes emission and a BSDF for every integrator: what it
// says a surface emits must be what the light sampler says the same light emits at the same
// point (pt's and BDPT's MIS weigh one against the other), on the side the light faces only,
// and the emitter it names must be the light the point lies on.
#include <gtest/gtest.h>

#include <cmath>
#include <variant>

#include "importers/importer.h"
#include "integrators/first_hit_aovs.h"
#include "integrators/shading_point.h"

namespace veach {
namespace {

TEST(ShadingPoint, EmissionIsTheLightSetsOnTheSideItFaces) {
    const Scene scene = import_scene(std::string(VEACH_EXAMPLES_DIR) + "/cornell/cornell.gltf");
    RenderScene rs(scene, &scene.cameras.at(0), 16, 16);
    const LightSet& lights = rs.lights();
    int checked = 0;
    for (size_t i = 0; i < lights.size(); ++i) {
        const auto* tl = std::get_if<TriangleLight>(&lights.light(i));
        if (!tl) continue;
        // A ray onto the triangle's centroid from the side its normal faces.
        const Vec3 c = tl->p0 + tl->e1 * (1.0f / 3.0f) + tl->e2 * (1.0f / 3.0f);
        const Vec3 o = c + tl->n * 0.01f;
        RayHit rh;
        ASSERT_TRUE(rs.accel().intersect(o, -tl->n, k_infinity, &rh, 0.0f));
        const ShadingPoint sp = make_shading_point(rs, rh);
        if (sp.hit.instance != tl->instance || sp.hit.prim != tl->prim) continue;  // another triangle in front
        EXPECT_EQ(sp.emitter(rs), static_cast<int64_t>(i));
        const Rgb le = sp.emitted(rs, sp.emitter(rs), tl->n);
        const Rgb expected = lights.radiance(i, sp.hit.p, tl->n);
        EXPECT_GT(le.max(), 0.0f);
        EXPECT_NEAR(le.r, expected.r, 1e-6f * expected.r);
        EXPECT_NEAR(le.g, expected.g, 1e-6f * expected.g);
        EXPECT_NEAR(le.b, expected.b, 1e-6f * expected.b);
        if (!tl->two_sided) EXPECT_TRUE(sp.emitted(rs, sp.emitter(rs), -tl->n).is_black());
        ++checked;
    }
    EXPECT_GT(checked, 0);
}

TEST(ShadingPoint, ANonEmitterNamesNoEmitterAndItsBsdfReflects) {
    const Scene scene = import_scene(std::string(VEACH_EXAMPLES_DIR) + "/cornell/cornell.gltf");
    RenderScene rs(scene, &scene.cameras.at(0), 16, 16);
    // The camera's central ray finds the back wall, a diffuse surface.
    Vec3 o, d;
    rs.camera().generate_ray(8.0f, 8.0f, &o, &d);
    RayHit rh;
    ASSERT_TRUE(rs.accel().intersect(o, d, k_infinity, &rh, 0.0f));
    const ShadingPoint sp = make_shading_point(rs, rh);
    EXPECT_EQ(sp.emitter(rs), -1);
    const Vec3 wo = -d;
    const SurfaceBsdf bsdf = sp.bsdf(rs, wo);
    EXPECT_FALSE(bsdf.is_black());
    // Light arriving along the facing normal comes back toward the camera.
    const Vec3 n = dot(sp.hit.ns, wo) > 0.0f ? sp.hit.ns : -sp.hit.ns;
    EXPECT_GT(bsdf.eval(wo, n, TransportMode::Radiance).max(), 0.0f);
}

// The denoiser's features see through a smooth mirror: once the floor is a perfect mirror (metal,
// roughness 0, white), a camera ray onto it reports the surface the mirror shows (where the
// reflections, traced here by the law of reflection, land: position, facing normal, base colour),
// not the floor; the first-hit AOVs and the depth still see the floor, and a diffuse floor
// reports itself.
TEST(ShadingPoint, DenoiseFeaturesSeeThroughAMirror) {
    Scene scene = import_scene(std::string(VEACH_EXAMPLES_DIR) + "/cornell/cornell.gltf");
    const float fx0 = 8.0f, fy0 = 13.5f;  // low in the frame: the floor
    size_t floor_index = 0;
    {
        RenderScene rs(scene, &scene.cameras.at(0), 16, 16);
        const PixelAovs first = first_hit_aovs(rs, rs.camera(), fx0, fy0, 0.0f);
        const DenoiseFeatures diffuse = denoise_features(rs, rs.camera(), fx0, fy0, 0.0f, 0.5f);
        ASSERT_TRUE(first.hit && diffuse.hit);
        EXPECT_NEAR(diffuse.albedo.r, first.albedo.r, 1e-6f);
        EXPECT_NEAR(dot(diffuse.normal, first.normal), 1.0f, 1e-5f);
        Vec3 o, d;
        rs.camera().generate_ray(fx0, fy0, &o, &d);
        RayHit rh;
        ASSERT_TRUE(rs.accel().intersect(o, d, k_infinity, &rh, 0.0f));
        floor_index = static_cast<size_t>(make_shading_point(rs, rh).hit.material - scene.materials.data());
    }
    Material& mirror = scene.materials.at(floor_index);
    mirror.base_color = Rgb(1.0f);
    mirror.base_color_texture = {};
    mirror.metallic = 1.0f;
    mirror.roughness = 0.0f;
    mirror.metallic_roughness_texture = {};
    const Material* mirror_material = &mirror;
    RenderScene rs(scene, &scene.cameras.at(0), 16, 16);
    // The pixels whose ray meets the mirror and, reflected (the example's white walls share the
    // floor's material, so perhaps more than once), a surface of another material.
    int checked = 0;
    for (float fy = 9.5f; fy < 16.0f; fy += 1.0f) {
        for (float fx = 0.5f; fx < 16.0f; fx += 1.0f) {
            Vec3 o, d;
            rs.camera().generate_ray(fx, fy, &o, &d);
            RayHit rh;
            if (!rs.accel().intersect(o, d, k_infinity, &rh, 0.0f)) continue;
            SurfaceHit shown = make_shading_point(rs, rh).hit;
            if (shown.material != mirror_material) continue;
            const Vec3 first_p = shown.p;
            const float depth = rh.t * dot(d, rs.camera().forward());
            bool found = false;
            for (int bounce = 0; bounce < 8 && shown.material == mirror_material; ++bounce) {
                const Vec3 n = dot(shown.ng, d) > 0.0f ? -shown.ng : shown.ng;
                const Vec3 r = d - n * (2.0f * dot(d, n));
                found = rs.accel().intersect(offset_ray_origin(shown.p, shown.p_error, shown.ng, r), r, k_infinity,
                                             &rh, 0.0f);
                if (!found) break;
                shown = make_shading_point(rs, rh).hit;
                d = r;
            }
            if (!found || shown.material == mirror_material) continue;
            const DenoiseFeatures seen = denoise_features(rs, rs.camera(), fx, fy, 0.0f, 0.5f);
            const PixelAovs aovs = first_hit_aovs(rs, rs.camera(), fx, fy, 0.0f);
            ASSERT_TRUE(seen.hit && aovs.hit);
            EXPECT_NEAR(seen.depth, aovs.depth, 1e-5f * aovs.depth);  // depth is the first hit's
            EXPECT_LT(length(seen.position - shown.p), 1e-3f * (1.0f + length(shown.p))) << fx << "," << fy;
            EXPECT_GT(length(seen.position - first_p), 1e-2f);
            const Vec3 shown_n = dot(shown.ng, d) > 0.0f ? -shown.ns : shown.ns;
            EXPECT_NEAR(dot(seen.normal, shown_n), 1.0f, 1e-3f);
            EXPECT_LT(dot(aovs.normal, shown_n), 0.99f);  // the AOVs see the mirror
            // A white metal's tint is its Fresnel at base colour 1: 1.
            EXPECT_NEAR(seen.albedo.r, shown.material->base_color.r, 1e-3f);
            EXPECT_NEAR(seen.albedo.g, shown.material->base_color.g, 1e-3f);
            ++checked;
        }
    }
    EXPECT_GT(checked, 3);
}

}  // namespace
}  // namespace veach
