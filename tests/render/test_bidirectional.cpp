// Bidirectional path tracing solves the same equation as path tracing: every strategy, weighted
// or alone, converges to the same image.
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>

#include "importers/importer.h"
#include "render_helpers.h"
#include "test_scenes.h"

namespace veach {
namespace {

Scene cornell() { return import_scene(std::string(VEACH_EXAMPLES_DIR) + "/cornell/cornell.gltf"); }

std::string shared_scene(const std::string& name) {
    return std::string(VEACH_SHARED_DIR) + "/scenes/" + name + "/" + name + ".gltf";
}

void expect_agree(const Image& x, const Image& ref, int block, double mean_tol, double block_tol, const std::string& what) {
    test::ImageComparison c = test::compare_images(x, ref, block);
    for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(c.mean_ratio[ch], 1.0, test::tol(mean_tol)) << what << " channel " << ch;
    EXPECT_LT(c.worst_block, test::tol(block_tol)) << what;
}

// pt, bdpt and lt on the public scenes: means within 1%, 16x16 block means within 3%.
class IntegratorsAgree : public ::testing::TestWithParam<std::string> {};

TEST_P(IntegratorsAgree, OnPublicScene) {
    std::string path = shared_scene(GetParam());
    if (!std::ifstream(path).good()) GTEST_SKIP() << "no " << path;
    Scene s = import_scene(path);
    // Light tracing's block noise depends on the light paths landing per block (256 pixels x
    // spp), not on the image size: a small image with many samples per pixel is the cheap way to
    // "high spp".
    const int w = 64, h = GetParam() == "cornell" ? 64 : 48;
    RenderStats stats;
    Image pt = test::render(s, w, test::spp(1024), "pt", 64, 0, 11, &stats, -1, -1, h);
    EXPECT_EQ(stats.nonfinite_samples, 0u);
    Image bdpt = test::render(s, w, test::spp(512), "bdpt", 64, 0, 12, &stats, -1, -1, h);
    EXPECT_EQ(stats.nonfinite_samples, 0u);
    Image lt = test::render(s, w, test::spp(2048), "lt", 64, 0, 13, &stats, -1, -1, h);
    EXPECT_EQ(stats.nonfinite_samples, 0u);
    expect_agree(bdpt, pt, 16, 0.01, 0.03, "bdpt vs pt");
    expect_agree(lt, pt, 16, 0.01, 0.03, "lt vs pt");
}

INSTANTIATE_TEST_SUITE_P(Scenes, IntegratorsAgree, ::testing::Values("cornell", "lights"));

// Copper and near-smooth glass (caustics): bdpt's weights over glossy transmission agree with pt.
// Light tracing alone is not compared here: connecting a light path to the camera through a
// roughness-0.05 glass lobe is heavy-tailed (at 4096 spp its image mean still swings from 0.95 to
// 1.16 of pt's between seeds, carried by single pixels), and within bdpt MIS gives those paths
// to the camera-side strategies.
TEST(IntegratorsAgreeOnCaustics, SpheresBdptAgreesWithPt) {
    std::string path = shared_scene("spheres");
    if (!std::ifstream(path).good()) GTEST_SKIP() << "no " << path;
    // Caustic fireflies do not shrink like sqrt(spp): at a fraction of the samples (sanitizer
    // builds) the comparison says nothing; reference_spheres_pt runs the same paths there.
    if (test::spp_divisor() > 1) GTEST_SKIP() << "needs full sample counts";
    Scene s = import_scene(path);
    RenderStats stats;
    Image pt = test::render(s, 64, test::spp(4096), "pt", 64, 0, 51, &stats, -1, -1, 48);
    EXPECT_EQ(stats.nonfinite_samples, 0u);
    Image bdpt = test::render(s, 64, test::spp(1024), "bdpt", 64, 0, 52, &stats, -1, -1, 48);
    EXPECT_EQ(stats.nonfinite_samples, 0u);
    expect_agree(bdpt, pt, 16, 0.01, 0.03, "bdpt vs pt");
}

// Each single strategy (s light vertices, t camera vertices) with s + t <= 4 renders the paths
// of exactly s + t - 2 bounces; all strategies of one length agree with next-event estimation
// (s = 1), the least noisy of them.
TEST(BidirectionalStrategies, EveryStrategyUpToFourVerticesConvergesOnCornell) {
    Scene s = cornell();
    const int size = 32;
    for (int length = 2; length <= 4; ++length) {
        // The depth limit keeps the subpaths as short as the strategy needs.
        int depth = length - 2;
        Image reference = test::render(s, size, test::spp(2048), "bdpt", depth, 0, 21, nullptr, 1, length - 1);
        for (int strategy_s = 0; strategy_s < length; ++strategy_s) {
            int strategy_t = length - strategy_s;
            if (strategy_s == 1) continue;
            // Hitting the small light by chance (s = 0) and the unweighted 1/d^2 connections
            // (s, t >= 2) are the noisy ones: more samples.
            int spp = strategy_s == 0 || strategy_t >= 2 ? 4096 : 1024;
            Image img = test::render(s, size, test::spp(spp), "bdpt", depth, 0, 22, nullptr, strategy_s, strategy_t);
            expect_agree(img, reference, 16, 0.03, 0.05,
                         "strategy " + std::to_string(strategy_s) + "," + std::to_string(strategy_t));
        }
    }
}

// Veach's shading-normal correction: on a smooth-shaded low-poly sphere, light tracing (which
// transports importance) agrees with path tracing only when the adjoint BSDF is used.
TEST(BidirectionalShadingNormals, LowPolySmoothSphereUnderPointLight) {
    Scene s;
    Mesh sphere = test::make_sphere(1.0f, Vec3(0, 0, 0), 10, 5);
    for (const Vec3& p : sphere.positions) sphere.normals.push_back(normalize(p));
    sphere.material = 0;
    s.meshes.push_back(sphere);
    s.materials.push_back(test::lambert(Rgb(0.8f)));
    s.instances.push_back({0, Transform()});
    PunctualLight pl;
    pl.type = LightType::Point;
    pl.intensity = Rgb(10.0f);
    pl.position = Vec3(2.0f, 3.0f, 3.0f);
    s.lights.push_back(pl);
    s.cameras.push_back(test::camera_at(Vec3(0, 0, 2.4f), 0.9f));
    Image pt = test::render(s, 32, test::spp(2048), "pt", 8, 0, 31);
    Image bdpt = test::render(s, 32, test::spp(256), "bdpt", 8, 0, 33);
    expect_agree(bdpt, pt, 16, 0.01, 0.03, "bdpt vs pt");
    // Light tracing divides by |wo.ng| near the terminator, a heavy-tailed estimator: its dim
    // terminator block converges slowly (6% at 4096 spp), while without the correction the
    // blocks are 50% off and the mean 5% low.
    Image lt = test::render(s, 32, test::spp(4096), "lt", 8, 0, 32);
    expect_agree(lt, pt, 16, 0.02, 0.10, "lt vs pt");
}

// A smooth mirror (a Dirac delta BSDF) lit by an area light: strategies that cannot sample a
// delta vertex get weight zero, and bdpt still agrees with pt. (No point light here: its
// caustic through a perfect mirror is a path pt cannot sample at all, and bdpt renders it.)
TEST(BidirectionalDelta, MirrorSphereUnderAreaLight) {
    Scene s;
    Mesh sphere = test::make_sphere(0.6f, Vec3(0, 0.6f, 0), 64, 32);
    for (const Vec3& p : sphere.positions) sphere.normals.push_back(normalize(p - Vec3(0, 0.6f, 0)));
    sphere.material = 0;
    Mesh floor;
    floor.positions = {{-3, 0, -3}, {3, 0, -3}, {3, 0, 3}, {-3, 0, 3}};
    floor.indices = {0, 2, 1, 0, 3, 2};
    floor.material = 1;
    Mesh lamp;
    lamp.positions = {{-0.4f, 2.5f, -0.4f}, {0.4f, 2.5f, -0.4f}, {0.4f, 2.5f, 0.4f}, {-0.4f, 2.5f, 0.4f}};
    lamp.indices = {0, 1, 2, 0, 2, 3};
    lamp.material = 2;
    s.meshes = {sphere, floor, lamp};
    Material mirror;
    mirror.base_color = Rgb(0.9f);
    mirror.metallic = 1;
    mirror.roughness = 0;
    s.materials = {mirror, test::lambert(Rgb(0.7f)), test::lambert(Rgb(0), Rgb(8.0f))};
    for (uint32_t i = 0; i < 3; ++i) s.instances.push_back({i, Transform()});
    Camera cam = test::camera_at(Vec3(0, 1.0f, 3.0f), 0.9f);
    s.cameras.push_back(cam);
    RenderStats stats;
    Image pt = test::render(s, 64, test::spp(512), "pt", 16, 0, 41, &stats);
    EXPECT_EQ(stats.nonfinite_samples, 0u);
    Image bdpt = test::render(s, 64, test::spp(256), "bdpt", 16, 0, 42, &stats);
    EXPECT_EQ(stats.nonfinite_samples, 0u);
    expect_agree(bdpt, pt, 16, 0.02, 0.05, "bdpt vs pt");
}

// Light-tracing splats are summed with atomics: thread count may change only the order of
// floating-point additions.
TEST(BidirectionalDeterminism, OneAndTwoThreadsAgreeToRounding) {
    Scene s = cornell();
    Image one = test::render(s, 32, test::spp(4), "bdpt", 64, 1, 5);
    Image two = test::render(s, 32, test::spp(4), "bdpt", 64, 2, 5);
    ASSERT_EQ(one.rgba.size(), two.rgba.size());
    for (size_t i = 0; i < one.rgba.size(); ++i)
        ASSERT_NEAR(one.rgba[i], two.rgba[i], 1e-6 * std::max(1.0f, std::fabs(one.rgba[i]))) << "value " << i;
}

}  // namespace
}  // namespace veach
