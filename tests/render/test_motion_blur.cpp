// Motion blur: a camera sample sees the scene at one time in the shutter, so a pixel is the
// average over the shutter of what it sees. Scenes are animated glTF files built here, imported
// with animation and given a shutter by capture_motion, as the C API does.
#include <gtest/gtest.h>

#include <cmath>

#include "../importers/gltf_test_builder.h"
#include "camera/camera_model.h"
#include "core/sobol_sampler.h"
#include "render_helpers.h"
#include "scene/scene_motion.h"

namespace veach {
namespace {

using namespace gltf_test;

// A rectangle in the plane z = 0 facing +Z, x in [x0, x1], y in [-3, 3].
int rectangle(GltfBuilder& b, float x0, float x1, int material) {
    int pos = b.positions({x0, -3, 0, x1, -3, 0, x1, 3, 0, x0, -3, 0, x1, 3, 0, x0, 3, 0});
    return b.push("meshes", {{"primitives", json::array({{{"attributes", {{"POSITION", pos}}}, {"material", material}}})}});
}

// What the tests look at: an emissive strip x in [-1, 0] (radiance 1, black otherwise) and, with
// `floor`, a diffuse rectangle x in [0, 2] beside it under a point light. The camera looks down
// -Z from z = `height` and travels +X from x = 0 at time 0 to x = 1 at time 1 (seconds).
// Orthographic: half extents 2 x 1 (32 x 16 pixels are 8 per unit).
GltfBuilder pan_scene(bool orthographic, bool floor, float height) {
    GltfBuilder b;
    b.push("materials", {{"pbrMetallicRoughness", {{"baseColorFactor", {0, 0, 0, 1}}, {"metallicFactor", 0}}},
                         {"emissiveFactor", {1, 1, 1}}});
    b.place(rectangle(b, -1, 0, 0));
    if (floor) {
        b.push("materials", {{"pbrMetallicRoughness", {{"baseColorFactor", {0.8, 0.8, 0.8, 1}}, {"metallicFactor", 0},
                                                       {"roughnessFactor", 1}}}});
        b.place(rectangle(b, 0, 2, 1));
        b.doc["extensionsUsed"] = {"KHR_lights_punctual"};
        b.doc["extensions"]["KHR_lights_punctual"]["lights"] = {{{"type", "point"}, {"intensity", 2}}};
        int light = b.push("nodes", {{"translation", {0.7, 0.2, 0.6}},
                                     {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
        b.doc["scenes"][0]["nodes"].push_back(light);
    }
    if (orthographic)
        b.push("cameras", {{"type", "orthographic"},
                           {"orthographic", {{"xmag", 2}, {"ymag", 1}, {"znear", 0.01}, {"zfar", 100}}}});
    else
        b.push("cameras", {{"type", "perspective"}, {"perspective", {{"yfov", 1.0}, {"znear", 0.01}}}});
    int camera = b.push("nodes", {{"camera", 0}, {"translation", {0, 0, height}}});
    b.doc["scenes"][0]["nodes"].push_back(camera);
    int input = b.accessor(std::vector<float>{0, 1}, k_float, "SCALAR");
    int output = b.accessor(std::vector<float>{0, 0, height, 1, 0, height}, k_float, "VEC3");
    b.push("animations",
           {{"channels", {{{"sampler", 0}, {"target", {{"node", camera}, {"path", "translation"}}}}}},
            {"samplers", {{{"input", input}, {"output", output}, {"interpolation", "LINEAR"}}}}});
    return b;
}

// The scene posed at `seconds` with motion over [seconds + open, seconds + close].
Scene posed(const GltfBuilder& b, double seconds, double open, double close) {
    ImportOptions o;
    o.animate = true;
    Scene s = load(b, o);
    pose_scene(s, seconds);
    capture_motion(s, seconds, open, close);
    return s;
}

double pixel_mean(const Image& img, int x, int y) {
    const float* p = img.pixel(x, y);
    return (double(p[0]) + p[1] + p[2]) / 3.0;
}

// The fraction of film column `column` (8 pixels per unit, the film's left edge at camera x - 2)
// that the strip [-1, 0] covers, averaged over camera positions cx in [c0, c1]: the box filter's
// pixel integral times the shutter's box in time, by the midpoint rule.
double analytic_column(int column, double c0, double c1) {
    const int n = 20000;
    double sum = 0;
    for (int k = 0; k < n; ++k) {
        const double cx = c0 + (c1 - c0) * (k + 0.5) / n;
        const double lo = cx - 2 + column / 8.0, hi = lo + 1 / 8.0;
        sum += std::max(0.0, std::min(hi, 0.0) - std::max(lo, -1.0)) * 8.0;
    }
    return sum / n;
}

TEST(MotionBlur, CameraPanBlursAStripIntoTheBoxFilteredProfile) {
    // Frame time 0.55 s, shutter [-0.25, 0.25] s: the camera sweeps x from 0.3 to 0.8, so each
    // edge of the strip (from film x 10.4 to 14.4, and 18.4 to 22.4) is smeared over 4 pixels: a
    // linear ramp, convolved with the pixel's box.
    Scene s = posed(pan_scene(true, false, 1), 0.55, -0.25, 0.25);
    ASSERT_TRUE(s.motion.enabled());
    ASSERT_EQ(s.motion.camera_to_world.size(), 1u);
    ASSERT_EQ(s.motion.camera_to_world[0].size(), size_t(k_motion_steps));
    Image img = test::render(s, 32, test::spp(64), "pt", 4, 0, 7, nullptr, -1, -1, 16);
    int ramp_pixels = 0;
    for (int x = 0; x < 32; ++x) {
        double m = 0;
        for (int y = 0; y < 16; ++y) m += pixel_mean(img, x, y);
        m /= 16;
        const double want = analytic_column(x, 0.3, 0.8);
        // Each column: 16 x 64 samples of a 0/1 coverage, stratified in position and time; the
        // binomial bound sqrt(p (1 - p) / n) is under 0.016.
        EXPECT_NEAR(m, want, test::tol(0.05)) << "column " << x;
        ramp_pixels += want > 0.01 && want < 0.99;
    }
    EXPECT_EQ(ramp_pixels, 10);  // two edges, each a ramp over 4 pixels starting mid-pixel: 5 pixels
    // Without a shutter the same frame is sharp: every column is covered fully or not at all.
    Image sharp = test::render(posed(pan_scene(true, false, 1), 0.5, 0, 0), 32, test::spp(16), "pt", 4, 0, 7,
                               nullptr, -1, -1, 16);
    for (int x = 0; x < 32; ++x) EXPECT_NEAR(pixel_mean(sharp, x, 8), analytic_column(x, 0.5, 0.5), 1e-6) << x;
}

TEST(MotionBlur, AnEmptyShutterOrAStillSceneRendersBitForBitAsWithoutOne) {
    const GltfBuilder b = pan_scene(false, true, 2);
    Scene plain = posed(b, 0.5, 0, 0);
    EXPECT_FALSE(plain.motion.enabled());
    // After the animation's last key nothing moves: the shutter has nothing to blur.
    Scene still = posed(b, 3.0, -0.25, 0.25);
    Scene still_plain = posed(b, 3.0, 0, 0);
    EXPECT_TRUE(still.motion.enabled());
    EXPECT_TRUE(still.motion.camera_to_world[0].empty());
    for (const char* integrator : {"pt", "bdpt"}) {
        Image a = test::render(still, 16, 8, integrator, 8, 0, 3);
        Image c = test::render(still_plain, 16, 8, integrator, 8, 0, 3);
        ASSERT_EQ(a.rgba.size(), c.rgba.size());
        EXPECT_EQ(std::memcmp(a.rgba.data(), c.rgba.data(), a.rgba.size() * sizeof(float)), 0) << integrator;
    }
}

// Block means of `runs` renders with different seeds: their mean and standard error per block.
struct BlockEstimate {
    std::vector<double> mean, se;
};

BlockEstimate block_estimate(const Scene& s, const std::string& integrator, int spp, int runs, uint64_t seed) {
    std::vector<std::vector<double>> blocks;
    for (int r = 0; r < runs; ++r)
        blocks.push_back(test::block_means(test::render(s, 32, spp, integrator, 8, 0, seed + r, nullptr, -1, -1, 16), 8));
    BlockEstimate e;
    for (size_t k = 0; k < blocks[0].size(); ++k) {
        double sum = 0, sum2 = 0;
        for (int r = 0; r < runs; ++r) {
            sum += blocks[r][k];
            sum2 += blocks[r][k] * blocks[r][k];
        }
        const double m = sum / runs;
        e.mean.push_back(m);
        e.se.push_back(std::sqrt(std::max(0.0, (sum2 / runs - m * m) * runs / (runs - 1)) / runs));
    }
    return e;
}

TEST(MotionBlur, PtAndBdptAgreeOnAPanningPerspectiveCamera) {
    // BDPT's light subpaths and their connections to the camera (light tracing projects onto the
    // camera where it stands at the sample's time) estimate the same blurred image as pt.
    Scene s = posed(pan_scene(false, true, 2), 0.5, -0.5, 0.5);
    ASSERT_FALSE(s.motion.camera_to_world[0].empty());
    const int runs = 8;
    BlockEstimate pt = block_estimate(s, "pt", test::spp(32), runs, 100);
    BlockEstimate bdpt = block_estimate(s, "bdpt", test::spp(32), runs, 200);
    double mean_pt = 0;
    for (size_t k = 0; k < pt.mean.size(); ++k) {
        const double z = (pt.mean[k] - bdpt.mean[k]) / std::sqrt(pt.se[k] * pt.se[k] + bdpt.se[k] * bdpt.se[k] + 1e-12);
        EXPECT_LT(std::fabs(z), 4.5) << "block " << k << ": pt " << pt.mean[k] << " bdpt " << bdpt.mean[k];
        mean_pt += pt.mean[k];
    }
    EXPECT_GT(mean_pt, 0.0);
}

TEST(MotionBlur, CameraInterpolationSlerpsTheOrientation) {
    // Steps a (looking down -Z) and b (turned 90 degrees about +Y: looking down -X); halfway it
    // looks along the diagonal, and the position moves linearly.
    Camera ca, cb;
    cb.camera_to_world = translation(Vec3(2, 0, 0)) * rotation_quaternion(0, std::sqrt(0.5f), 0, std::sqrt(0.5f));
    Bounds3 none;
    CameraModel a(&ca, none, 16, 16), b(&cb, none, 16, 16);
    CameraModel h = CameraModel::interpolate(a, b, 0.5f);
    const float d = std::sqrt(0.5f);
    expect_vec3(h.forward(), -d, 0, -d, 1e-5f);
    expect_vec3(h.position(), 1, 0, 0, 1e-6f);
    expect_vec3(CameraModel::interpolate(a, b, 0.0f).forward(), 0, 0, -1, 1e-6f);
    expect_vec3(CameraModel::interpolate(a, b, 1.0f).forward(), -1, 0, 0, 1e-5f);
}

TEST(MotionBlur, ShutterTimesStratifyEachPixelsSamples) {
    // 64 samples of one pixel: one in each 1/64 of the shutter (Owen-scrambled van der Corput).
    std::vector<int> bins(64, 0);
    for (uint32_t s = 0; s < 64; ++s) {
        float u = Sampler(SamplerKind::Sobol, 5, 1234, s).shutter_time();
        ASSERT_GE(u, 0.0f);
        ASSERT_LT(u, 1.0f);
        bins[static_cast<size_t>(u * 64)]++;
    }
    for (int k = 0; k < 64; ++k) EXPECT_EQ(bins[k], 1) << k;
}

}  // namespace
}  // namespace veach
