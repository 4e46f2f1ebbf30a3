// Scenes whose radiance is known in closed form: every integrator must reproduce it.
#include <gtest/gtest.h>

#include <cmath>

#include "render_helpers.h"
#include "test_scenes.h"

namespace veach {
namespace {

// Inside a closed surface where every point emits Le and reflects with albedo a, radiance is
// the same everywhere and solves L = Le + a L: L = Le / (1 - a). With at most D bounces the
// Neumann series stops: L = Le (1 - a^(D+1)) / (1 - a).
Scene emissive_furnace(float albedo, float le) {
    Scene s;
    s.meshes.push_back(test::make_sphere(1.0f, Vec3(0, 0, 0), 48, 24));
    s.materials.push_back(test::lambert(Rgb(albedo), Rgb(le)));
    s.meshes[0].material = 0;
    s.instances.push_back({0, Transform()});
    s.cameras.push_back(test::camera_at(Vec3(0.1f, -0.2f, 0.05f)));
    return s;
}

class AnalyticScenes : public ::testing::TestWithParam<std::string> {};

TEST_P(AnalyticScenes, EmissiveFurnaceSeesLeOverOneMinusAlbedo) {
    const float a = 0.6f, le = 0.5f;
    Scene s = emissive_furnace(a, le);
    RenderStats stats;
    // Light tracing splats land unevenly: it needs more paths for the same noise.
    int spp = GetParam() == "lt" ? 512 : 64;
    Image img = test::render(s, 32, test::spp(spp), GetParam(), 200, 0, 7, &stats);
    double expected = le / (1.0 - a);
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(test::channel_mean(img, c), expected, test::tol(0.01) * expected) << "channel " << c;
    for (double b : test::block_means(img, 8)) EXPECT_NEAR(b, expected, test::tol(0.03) * expected);
    EXPECT_EQ(stats.nonfinite_samples, 0u);
}

TEST_P(AnalyticScenes, EmissiveFurnaceWithDepthLimitSumsDPlusOneTerms) {
    const float a = 0.6f, le = 0.5f;
    const int depth = 2;
    Scene s = emissive_furnace(a, le);
    Image img = test::render(s, 32, test::spp(GetParam() == "lt" ? 512 : 64), GetParam(), depth);
    double expected = le * (1.0 - std::pow(a, depth + 1)) / (1.0 - a);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(test::channel_mean(img, c), expected, test::tol(0.01) * expected);
}

// A point light of intensity I at the centre of a sphere of radius r with albedo a: the wall's
// first-bounce radiance is a I / (pi r^2), and every further bounce inside a sphere spreads
// uniformly, multiplying by a: L = a I / (pi r^2) (1 - a^D) / (1 - a) with D bounces.
TEST_P(AnalyticScenes, PointLightInSphere) {
    const float a = 0.5f, intensity = 2.0f, r = 1.5f;
    const int depth = 3;
    Scene s;
    s.meshes.push_back(test::make_sphere(r, Vec3(0, 0, 0), 96, 48));
    s.materials.push_back(test::lambert(Rgb(a)));
    s.meshes[0].material = 0;
    s.instances.push_back({0, Transform()});
    PunctualLight pl;
    pl.type = LightType::Point;
    pl.intensity = Rgb(intensity);
    pl.position = Vec3(0, 0, 0);
    s.lights.push_back(pl);
    s.cameras.push_back(test::camera_at(Vec3(0.3f, 0.1f, 0.2f)));
    Image img = test::render(s, 32, test::spp(GetParam() == "lt" ? 256 : 64), GetParam(), depth);
    double expected = a * intensity / (k_pi * r * r) * (1.0 - std::pow(a, depth)) / (1.0 - a);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(test::channel_mean(img, c), expected, test::tol(0.01) * expected);
}

INSTANTIATE_TEST_SUITE_P(Integrators, AnalyticScenes, ::testing::Values("pt", "bdpt", "lt"));

}  // namespace
}  // namespace veach
