// Motion blur: a camera sample sees the scene at one time in the shutter, so a pixel is the
// average over the shutter of what it sees. Scenes are animated glTF files built here, imported
// with animation and given a shutter by capture_motion, as the C API does.
#include <gtest/gtest.h>

#include <cmath>

#include "../importers/gltf_test_builder.h"
#include "accel/embree_accel.h"
#include "integrators/surface_hit.h"
#include "camera/camera_model.h"
#include "core/sobol_sampler.h"
#include "render_helpers.h"
#include "scene/scene_motion.h"
#include "scene/surface_attributes.h"

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
using BlockEstimate = test::RunEstimate;

BlockEstimate block_estimate(const Scene& s, const std::string& integrator, int spp, int runs, uint64_t seed) {
    std::vector<std::vector<double>> blocks;
    for (int r = 0; r < runs; ++r)
        blocks.push_back(test::block_means(test::render(s, 32, spp, integrator, 8, 0, seed + r, nullptr, -1, -1, 16), 8));
    return test::mean_and_standard_error(blocks);
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

// Object motion: the camera stands still and geometry moves. What the tests look at is a black
// (non-emissive) occluder in front of an emissive backdrop (radiance 1): a pixel is 1 minus the
// fraction of the shutter and of its area the occluder covers. Emitters stay out of motion
// (scene_motion.h), so the moving thing is the occluder.
int rect(GltfBuilder& b, float x0, float x1, float y0, float y1, int material, json targets = nullptr) {
    int pos = b.positions({x0, y0, 0, x1, y0, 0, x1, y1, 0, x0, y0, 0, x1, y1, 0, x0, y1, 0});
    json prim = {{"attributes", {{"POSITION", pos}}}, {"material", material}};
    json mesh = json::object();
    if (!targets.is_null()) {
        prim["targets"] = targets;
        mesh["weights"] = json::array();
        for (size_t k = 0; k < targets.size(); ++k) mesh["weights"].push_back(0.0);
    }
    mesh["primitives"] = json::array({prim});
    return b.push("meshes", mesh);
}

enum class Motion { Slide, Morph, Turn };

// The backdrop (z = 0, emissive, x and y in [-4, 4]) and a black occluder at z = 0.5 under an
// orthographic camera at z = 1 looking down -Z (half extents 2 x `ymag`). Slide: the strip
// x in [-1, 0], y in [-3, 3] translated by -t along X at time t (seconds). Morph: the same strip
// displaced by a morph target (-1 along X) whose weight is t. Turn: the bar x in [0, 1.9],
// |y| < 0.5 turned about +Z by 90 degrees between times 0 and 1.
GltfBuilder occluder_scene(Motion motion, float ymag) {
    GltfBuilder b;
    // Black metal reflects nothing (F0 = 0): a black dielectric's 4% would bounce the backdrop's
    // light off the occluder's underside back into view.
    b.push("materials", {{"pbrMetallicRoughness", {{"baseColorFactor", {0, 0, 0, 1}}, {"metallicFactor", 1}}},
                         {"emissiveFactor", {1, 1, 1}}});
    b.push("materials", {{"pbrMetallicRoughness", {{"baseColorFactor", {0, 0, 0, 1}}, {"metallicFactor", 1}}}});
    b.place(rect(b, -4, 4, -4, 4, 0));
    int node = -1, input = b.accessor(std::vector<float>{0, 1}, k_float, "SCALAR"), output = -1;
    const char* path = "translation";
    if (motion == Motion::Slide) {
        node = b.place(rect(b, -1, 0, -3, 3, 1), {{"translation", {0, 0, 0.5}}});
        output = b.accessor(std::vector<float>{0, 0, 0.5, -1, 0, 0.5}, k_float, "VEC3");
    } else if (motion == Motion::Morph) {
        int delta = b.positions({-1, 0, 0, -1, 0, 0, -1, 0, 0, -1, 0, 0, -1, 0, 0, -1, 0, 0});
        node = b.place(rect(b, -1, 0, -3, 3, 1, json::array({{{"POSITION", delta}}})), {{"translation", {0, 0, 0.5}}});
        output = b.accessor(std::vector<float>{0, 1}, k_float, "SCALAR");
        path = "weights";
    } else {
        node = b.place(rect(b, 0, 1.9f, -0.5f, 0.5f, 1), {{"translation", {0, 0, 0.5}}});
        const float h = std::sqrt(0.5f);
        output = b.accessor(std::vector<float>{0, 0, 0, 1, 0, 0, h, h}, k_float, "VEC4");
        path = "rotation";
    }
    b.push("animations", {{"channels", {{{"sampler", 0}, {"target", {{"node", node}, {"path", path}}}}}},
                          {"samplers", {{{"input", input}, {"output", output}, {"interpolation", "LINEAR"}}}}});
    b.push("cameras", {{"type", "orthographic"},
                       {"orthographic", {{"xmag", 2}, {"ymag", ymag}, {"znear", 0.01}, {"zfar", 100}}}});
    int camera = b.push("nodes", {{"camera", 0}, {"translation", {0, 0, 1}}});
    b.doc["scenes"][0]["nodes"].push_back(camera);
    return b;
}

// A strip moving -X at one unit (8 pixels) per second over the still camera is what the panning
// camera above sees: the same box-filtered profile, pixel = 1 - coverage.
void expect_sliding_strip_profile(Motion motion) {
    Scene s = posed(occluder_scene(motion, 1), 0.55, -0.25, 0.25);
    ASSERT_TRUE(s.motion.enabled());
    if (motion == Motion::Slide) {
        ASSERT_EQ(s.motion.instance_to_world.size(), 2u);
        EXPECT_TRUE(s.motion.instance_to_world[0].empty());  // the backdrop stands still
        EXPECT_EQ(s.motion.instance_to_world[1].size(), size_t(k_motion_steps));
    } else {
        EXPECT_TRUE(s.motion.mesh_deforms(1));
        EXPECT_FALSE(s.motion.instance_moves(1));
    }
    Image img = test::render(s, 32, test::spp(64), "pt", 4, 0, 7, nullptr, -1, -1, 16);
    int ramp_pixels = 0;
    for (int x = 0; x < 32; ++x) {
        double m = 0;
        for (int y = 0; y < 16; ++y) m += pixel_mean(img, x, y);
        m /= 16;
        const double want = 1.0 - analytic_column(x, 0.3, 0.8);
        // As for the camera: the binomial bound of 16 x 64 samples is under 0.016.
        EXPECT_NEAR(m, want, test::tol(0.05)) << "column " << x;
        ramp_pixels += want > 0.01 && want < 0.99;
    }
    EXPECT_EQ(ramp_pixels, 10);
    // The same frame without a shutter is sharp: the strip where it is at 0.55 s.
    Image sharp = test::render(posed(occluder_scene(motion, 1), 0.5, 0, 0), 32, test::spp(16), "pt", 4, 0, 7,
                               nullptr, -1, -1, 16);
    for (int x = 0; x < 32; ++x)
        EXPECT_NEAR(pixel_mean(sharp, x, 8), 1.0 - analytic_column(x, 0.5, 0.5), 1e-5) << x;  // float sums
}

TEST(MotionBlur, MovingObjectBlursIntoTheBoxFilteredProfile) { expect_sliding_strip_profile(Motion::Slide); }

TEST(MotionBlur, DeformingMeshBlursIntoTheBoxFilteredProfile) {
    // A morph weight rising across the shutter: the vertices' time steps, interpolated linearly.
    expect_sliding_strip_profile(Motion::Morph);
}

// The fraction of the quarter turn (theta in [0, pi/2]) during which the bar x in [0, 1.9],
// |y| < 0.5 turned by theta covers point (px, py).
double turning_bar_coverage(double px, double py) {
    const int n = 256;
    int covered = 0;
    for (int k = 0; k < n; ++k) {
        const double th = (k + 0.5) / n * (k_pi / 2);
        const double x = px * std::cos(th) + py * std::sin(th), y = -px * std::sin(th) + py * std::cos(th);
        covered += x >= 0 && x <= 1.9 && std::fabs(y) <= 0.5;
    }
    return double(covered) / n;
}

TEST(MotionBlur, TurningObjectSweepsItsArcWithoutShrinking) {
    // A quarter turn in one shutter (0 to 1 s, three steps: 45 degrees each). Interpolating the
    // steps' matrices linearly would shrink the bar to cos(22.5 deg) = 0.92 of its length midway
    // between steps, leaving its outer arc (radius 1.75 to 1.9) less covered; the rotation
    // slerped, the sweep matches the analytic one at every radius of the quadrant it sweeps.
    Scene s = posed(occluder_scene(Motion::Turn, 2), 0.5, -0.5, 0.5);
    ASSERT_TRUE(s.motion.instance_moves(1));
    const int size = 32;
    Image img = test::render(s, size, test::spp(64), "pt", 4, 0, 11);
    // Rings of pixel centres 0.25 wide from the centre, in the quadrant x, y > 0: measured and
    // analytic mean (the analytic one over 8 x 8 points of each pixel).
    const int rings = 8;
    std::vector<double> got(rings, 0), want(rings, 0);
    std::vector<int> count(rings, 0);
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            const double cx = -2 + (x + 0.5) / 8, cy = 2 - (y + 0.5) / 8;
            const int ring = int(std::sqrt(cx * cx + cy * cy) / 0.25);
            if (ring >= rings || cx < 0 || cy < 0) continue;
            double a = 0;
            for (int j = 0; j < 8; ++j)
                for (int i = 0; i < 8; ++i)
                    a += turning_bar_coverage(cx + (i + 0.5 - 4) / 64, cy + (j + 0.5 - 4) / 64);
            want[size_t(ring)] += 1.0 - a / 64;
            got[size_t(ring)] += pixel_mean(img, x, y);
            count[size_t(ring)]++;
        }
    for (int r = 0; r < rings; ++r) {
        got[size_t(r)] /= count[size_t(r)];
        want[size_t(r)] /= count[size_t(r)];
        // At least 12 pixels x 64 samples per ring (47 in the outer one): a binomial mean's
        // standard error is under 0.018 (0.009).
        EXPECT_NEAR(got[size_t(r)], want[size_t(r)], test::tol(0.03)) << "ring " << r << " of " << count[size_t(r)];
    }
    // The outer arc is where a shrinking blend would show: the bar sweeps it (radius 1.75 to 2).
    EXPECT_LT(want[7], 0.85);
}

TEST(MotionBlur, TheAccelsTransformOfATurningObjectIsARotationAtEveryTime) {
    Scene s = posed(occluder_scene(Motion::Turn, 2), 0.5, -0.5, 0.5);
    Accel accel(s);
    Transform t;
    ASSERT_FALSE(accel.moving_transform(0, 0.25f, &t));  // the backdrop
    for (float u : {0.0f, 0.125f, 0.25f, 0.5f, 0.8f, 1.0f}) {
        ASSERT_TRUE(accel.moving_transform(1, u, &t));
        const double th = u * k_pi / 2;
        // Linear blending of the steps' matrices would give 0.927 for cos(11.25 deg) = 0.981.
        EXPECT_NEAR(t.m[0][0], std::cos(th), 1e-5) << u;
        EXPECT_NEAR(t.m[1][0], std::sin(th), 1e-5) << u;
        EXPECT_NEAR(t.m[0][1], -std::sin(th), 1e-5) << u;
        EXPECT_NEAR(t.m[2][2], 1.0, 1e-5) << u;
        EXPECT_NEAR(t.m[2][3], 0.5, 1e-5) << u;
        // Where it is, the ray finds it: straight down onto the bar's axis at radius 1.8.
        RayHit hit;
        const Vec3 o(float(1.8 * std::cos(th)), float(1.8 * std::sin(th)), 1.0f);
        ASSERT_TRUE(accel.intersect(o, Vec3(0, 0, -1), 10.0f, &hit, u)) << u;
        EXPECT_EQ(hit.instance, 1u) << u;
        EXPECT_NEAR(hit.t, 0.5f, 1e-5f);
        Vec3 p0, p1, p2;
        accel.triangle_world(hit.instance, hit.prim, &p0, &p1, &p2, u);
        const Vec3 p = barycentric(p0, p1, p2, 1.0f - hit.u - hit.v, hit.u, hit.v);
        expect_vec3(p, o.x, o.y, 0.5f, 1e-5f);
    }
}

TEST(MotionBlur, ShadingFindsTheHitWhereTheRayFoundIt) {
    // The hit point, its normal and its triangle come from the geometry at the ray's time: for a
    // turning bar (rigid, slerped) and a strip moved by a morph weight (vertex steps), p is where
    // the ray met the surface. The frame's pose would be up to a quarter turn (or 0.5) away.
    for (Motion motion : {Motion::Turn, Motion::Morph}) {
        Scene s = posed(occluder_scene(motion, 2), 0.5, -0.5, 0.5);
        RenderScene rs(s, &s.cameras[0], 16, 16);
        for (int j = 0; j < 16; ++j) {
            const float u = (j + 0.5f) / 16;
            Vec3 o;
            if (motion == Motion::Turn) {
                const float th = u * float(k_pi) / 2, r = 0.3f + 1.5f * (j % 5) / 4;
                o = Vec3(r * std::cos(th), r * std::sin(th), 1.0f);
            } else {
                o = Vec3(-0.5f - u, -2.0f + 0.25f * j, 1.0f);  // the strip's middle at time u
            }
            RayHit hit;
            ASSERT_TRUE(rs.accel().intersect(o, Vec3(0, 0, -1), 10.0f, &hit, u)) << j;
            ASSERT_EQ(hit.instance, 1u) << j;
            const SurfaceHit sh = make_surface_hit(rs, hit);
            expect_vec3(sh.p, o.x, o.y, 0.5f, 1e-5f);
            expect_vec3(sh.ng, 0, 0, 1, 1e-5f);
        }
    }
}

TEST(MotionBlur, AMirroredOrShearedTurningObjectKeepsItsShapeAtEveryTime) {
    // A mirrored (negative scale), stretched and turned node under a parent that scales it
    // unevenly (a shear in the child's frame) and turns: the decomposition keeps the mirror, the
    // stretch and the shear in its scale/shear part, so the transform Embree interpolates is the
    // parent's slerped turn applied to the same shape at every time.
    GltfBuilder b;
    b.push("materials", {{"pbrMetallicRoughness", {{"baseColorFactor", {0.5, 0.5, 0.5, 1}}}}});
    int mesh = rect(b, 0.2f, 1.0f, -0.1f, 0.3f, 0);
    // The child turned about an oblique axis, so the parent's stretch shears it in every plane.
    int child = b.push("nodes", {{"mesh", mesh},
                                 {"scale", {-1, 2, 0.5}},
                                 {"rotation", {0.2073903, 0.3110855, 0.4147807, 0.8295614}}});
    int parent = b.push("nodes", {{"children", {child}}, {"translation", {0.3, -0.2, 0.5}}, {"scale", {1.5, 0.7, 1}}});
    b.doc["scenes"] = json::array({{{"nodes", {parent}}}});
    b.doc["scene"] = 0;
    const float h = std::sqrt(0.5f);
    int input = b.accessor(std::vector<float>{0, 1}, k_float, "SCALAR");
    int output = b.accessor(std::vector<float>{0, 0, 0, 1, 0, 0, h, h}, k_float, "VEC4");
    b.push("animations", {{"channels", {{{"sampler", 0}, {"target", {{"node", parent}, {"path", "rotation"}}}}}},
                          {"samplers", {{{"input", input}, {"output", output}, {"interpolation", "LINEAR"}}}}});
    Scene s = posed(b, 0.5, -0.5, 0.5);
    ASSERT_TRUE(s.motion.instance_moves(0));
    Accel accel(s);
    const Transform local =
        rotation_quaternion(0.2073903f, 0.3110855f, 0.4147807f, 0.8295614f) * scaling(Vec3(-1, 2, 0.5f));
    for (float u : {0.0f, 0.1f, 0.25f, 0.6f, 1.0f}) {
        Transform t;
        ASSERT_TRUE(accel.moving_transform(0, u, &t));
        const float th = u * float(k_pi) / 2;
        const Transform want = translation(Vec3(0.3f, -0.2f, 0.5f)) *
                               rotation_quaternion(0, 0, std::sin(th / 2), std::cos(th / 2)) *
                               scaling(Vec3(1.5f, 0.7f, 1)) * local;
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 4; ++c) EXPECT_NEAR(t.m[r][c], want.m[r][c], 2e-5) << u << " " << r << c;
        EXPECT_LT(t.determinant(), 0.0f) << u;
    }
}

// A grey strip moving and turning between a point light and a lit floor, seen by a still
// perspective camera: a blurred object and its blurred shadow.
GltfBuilder lit_motion_scene() {
    GltfBuilder b;
    b.push("materials", {{"pbrMetallicRoughness", {{"baseColorFactor", {0.8, 0.8, 0.8, 1}}, {"metallicFactor", 0},
                                                   {"roughnessFactor", 1}}}});
    b.place(rect(b, -3, 3, -3, 3, 0));
    int node = b.place(rect(b, -0.4f, 0.4f, -1.2f, 1.2f, 0), {{"translation", {0, 0, 0.5}}});
    int input = b.accessor(std::vector<float>{0, 1}, k_float, "SCALAR");
    int moves = b.accessor(std::vector<float>{-0.6f, 0, 0.5f, 0.6f, 0, 0.5f}, k_float, "VEC3");
    const float h = std::sqrt(0.5f);
    int turns = b.accessor(std::vector<float>{0, 0, 0, 1, 0, 0, h, h}, k_float, "VEC4");
    b.push("animations",
           {{"channels", {{{"sampler", 0}, {"target", {{"node", node}, {"path", "translation"}}}},
                          {{"sampler", 1}, {"target", {{"node", node}, {"path", "rotation"}}}}}},
            {"samplers", {{{"input", input}, {"output", moves}, {"interpolation", "LINEAR"}},
                          {{"input", input}, {"output", turns}, {"interpolation", "LINEAR"}}}}});
    b.doc["extensionsUsed"] = {"KHR_lights_punctual"};
    b.doc["extensions"]["KHR_lights_punctual"]["lights"] = {{{"type", "point"}, {"intensity", 2000}}};
    int light = b.push("nodes", {{"translation", {0.3, 0.2, 1.6}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
    b.doc["scenes"][0]["nodes"].push_back(light);
    b.push("cameras", {{"type", "perspective"}, {"perspective", {{"yfov", 1.2}, {"znear", 0.01}}}});
    int camera = b.push("nodes", {{"camera", 0}, {"translation", {0, 0, 2.5}}});
    b.doc["scenes"][0]["nodes"].push_back(camera);
    return b;
}

TEST(MotionBlur, PtBdptAndLtAgreeOnAMovingAndTurningObject) {
    // BDPT's light subpaths (and lt's particles) meet the object where it is at the sample's
    // time, as pt's paths do.
    Scene s = posed(lit_motion_scene(), 0.5, -0.5, 0.5);
    ASSERT_TRUE(s.motion.instance_moves(1));
    const int runs = 8;
    BlockEstimate pt = block_estimate(s, "pt", test::spp(32), runs, 300);
    BlockEstimate bdpt = block_estimate(s, "bdpt", test::spp(32), runs, 400);
    // Light tracing alone (particles from the light splatted onto the camera where it stands).
    BlockEstimate lt = block_estimate(s, "lt", test::spp(32), runs, 500);
    BlockEstimate sharp = block_estimate(posed(lit_motion_scene(), 0.5, 0, 0), "pt", test::spp(32), runs, 300);
    double differs = 0;
    for (size_t k = 0; k < pt.mean.size(); ++k) {
        const double z = (pt.mean[k] - bdpt.mean[k]) / std::sqrt(pt.se[k] * pt.se[k] + bdpt.se[k] * bdpt.se[k] + 1e-12);
        EXPECT_LT(std::fabs(z), 4.5) << "block " << k << ": pt " << pt.mean[k] << " bdpt " << bdpt.mean[k];
        const double zl = (pt.mean[k] - lt.mean[k]) / std::sqrt(pt.se[k] * pt.se[k] + lt.se[k] * lt.se[k] + 1e-12);
        EXPECT_LT(std::fabs(zl), 4.5) << "block " << k << ": pt " << pt.mean[k] << " lt " << lt.mean[k];
        const double zs = (pt.mean[k] - sharp.mean[k]) / std::sqrt(pt.se[k] * pt.se[k] + sharp.se[k] * sharp.se[k] + 1e-12);
        differs = std::max(differs, std::fabs(zs));
    }
    // The blur is there to agree on: some block differs from the sharp frame far beyond noise
    // (about 28 standard errors at the full sample count; a sanitizer run's VEACH_TEST_SPP_DIVISOR
    // of 8 divides it by sqrt(8), while equal means put the largest block near 3 or 4).
    EXPECT_GT(differs, 6.0);
}

TEST(MotionBlur, ObjectsStillDuringTheShutterRenderBitForBitAsWithoutOne) {
    // Past the last key the object stands: no time steps, the frame's own transform and vertices.
    for (Motion motion : {Motion::Slide, Motion::Morph, Motion::Turn}) {
        const GltfBuilder b = occluder_scene(motion, 1);
        Scene still = posed(b, 3.0, -0.25, 0.25);
        Scene plain = posed(b, 3.0, 0, 0);
        EXPECT_TRUE(still.motion.enabled());
        EXPECT_FALSE(still.motion.instance_moves(1));
        EXPECT_FALSE(still.motion.mesh_deforms(1));
        for (const char* integrator : {"pt", "bdpt"}) {
            Image a = test::render(still, 16, 8, integrator, 8, 0, 3);
            Image c = test::render(plain, 16, 8, integrator, 8, 0, 3);
            ASSERT_EQ(a.rgba.size(), c.rgba.size());
            EXPECT_EQ(std::memcmp(a.rgba.data(), c.rgba.data(), a.rgba.size() * sizeof(float)), 0) << integrator;
        }
    }
}

TEST(MotionBlur, EmittersStayAtTheFramesPose) {
    // By decision (scene_motion.h): a moving emitter is not blurred, so that light sampling, built
    // from the frame's pose, meets it where rays do. The camera pan's emissive strip, made to
    // slide instead of the camera, renders with a shutter as it does without one.
    GltfBuilder b = pan_scene(true, false, 1);
    int input = b.accessor(std::vector<float>{0, 1}, k_float, "SCALAR");
    int output = b.accessor(std::vector<float>{0, 0, 0, -1, 0, 0}, k_float, "VEC3");
    b.doc["animations"] = json::array();  // the camera stands; the strip (node 0) slides -X
    b.push("animations", {{"channels", {{{"sampler", 0}, {"target", {{"node", 0}, {"path", "translation"}}}}}},
                          {"samplers", {{{"input", input}, {"output", output}, {"interpolation", "LINEAR"}}}}});
    Scene blurred = posed(b, 0.55, -0.25, 0.25);
    ASSERT_TRUE(blurred.motion.enabled());
    EXPECT_FALSE(blurred.motion.instance_moves(0));
    EXPECT_TRUE(blurred.motion.camera_to_world[0].empty());
    Scene sharp = posed(b, 0.55, 0, 0);
    for (const char* integrator : {"pt", "bdpt"}) {
        Image a = test::render(blurred, 32, 8, integrator, 4, 0, 7, nullptr, -1, -1, 16);
        Image c = test::render(sharp, 32, 8, integrator, 4, 0, 7, nullptr, -1, -1, 16);
        ASSERT_EQ(a.rgba.size(), c.rgba.size());
        EXPECT_EQ(std::memcmp(a.rgba.data(), c.rgba.data(), a.rgba.size() * sizeof(float)), 0) << integrator;
        // The strip, where it stands at 0.55 s (x in [-1.55, -0.55]: film columns 3.6 to 11.6), is sharp.
        EXPECT_NEAR(pixel_mean(a, 8, 8), 1.0, 1e-5) << integrator;
        EXPECT_NEAR(pixel_mean(a, 14, 8), 0.0, 1e-5) << integrator;
    }
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
