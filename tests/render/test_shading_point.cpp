// The shading point is where a hit becomes emission and a BSDF for every integrator: what it
// says a surface emits must be what the light sampler says the same light emits at the same
// point (pt's and BDPT's MIS weigh one against the other), on the side the light faces only,
// and the emitter it names must be the light the point lies on.
#include <gtest/gtest.h>

#include <cmath>
#include <variant>

#include "importers/importer.h"
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

}  // namespace
}  // namespace veach
