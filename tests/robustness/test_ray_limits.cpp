// No ray Embree cannot take ever reaches it: Debian's Embree asserts that every origin and
// direction component is finite and within 1.844e18, and an assertion aborts the whole process
// (and a resumed render at the same sample). Cameras that give no usable ray are refused by name
// before rendering; what slips past is dropped by the ray queries themselves and counted.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "../render/render_helpers.h"
#include "../render/test_scenes.h"
#include "accel/embree_accel.h"
#include "camera/camera_model.h"

namespace veach {
namespace {

constexpr float k_nan = std::numeric_limits<float>::quiet_NaN();

Scene lit_sphere() {
    Scene s;
    s.meshes.push_back(test::make_sphere(1.0f, Vec3(0, 0, -5), 24, 12));
    s.materials.push_back(test::lambert(Rgb(0.5f), Rgb(1.0f)));
    s.meshes[0].material = 0;
    s.instances.push_back({0, Transform()});
    return s;
}

// A camera at the origin looking down -Z, through `node` (its world transform).
Camera camera_with(const Transform& node) {
    Camera c = test::camera_at(Vec3(0, 0, 0));
    c.name = "cam";
    c.camera_to_world = node;
    return c;
}

std::string refusal(const Camera& c) {
    try {
        CameraModel model(&c, Bounds3{}, 16, 16);
    } catch (const std::invalid_argument& e) {
        return e.what();
    }
    return "";
}

// The ray queries refuse what Embree would abort on, count it on the calling thread, and answer
// conservatively: no hit for intersect, blocked for occluded.
TEST(RayLimits, QueriesDropRaysEmbreeCannotTake) {
    Scene s = lit_sphere();
    Accel accel(s);
    RayHit hit;
    ASSERT_TRUE(accel.intersect(Vec3(0, 0, 0), Vec3(0, 0, -1), k_infinity, &hit));  // the sphere itself
    const uint64_t before = Accel::rejected_rays_on_this_thread();
    EXPECT_FALSE(accel.intersect(Vec3(0, 0, 0), Vec3(k_nan, 0, -1), k_infinity, &hit));
    EXPECT_FALSE(accel.intersect(Vec3(2e18f, 0, 0), Vec3(0, 0, -1), k_infinity, &hit));
    EXPECT_FALSE(accel.intersect(Vec3(0, 0, 0), Vec3(0, 0, -k_infinity), k_infinity, &hit));
    EXPECT_FALSE(accel.intersect(Vec3(0, 0, 0), Vec3(0, 0, -1), k_nan, &hit));
    EXPECT_TRUE(accel.occluded(Vec3(0, k_nan, 0), Vec3(0, 0, 1), 1.0f));
    EXPECT_EQ(Accel::rejected_rays_on_this_thread() - before, 5u);
    // A legal ray near the limit is traced (it misses: the sphere is not there).
    EXPECT_FALSE(accel.intersect(Vec3(9e17f, 0, 0), Vec3(0, 0, -1), k_infinity, &hit));
    EXPECT_FALSE(accel.occluded(Vec3(0, 0, 0), Vec3(0, 0, 1), 1.0f));
    EXPECT_EQ(Accel::rejected_rays_on_this_thread() - before, 5u);
}

// The reproducers of degenerate camera nodes: each is refused with a message naming the camera.
TEST(RayLimits, DegenerateCamerasAreRefusedByName) {
    const Transform none = scaling(Vec3(0, 0, 0));
    const Transform flat = scaling(Vec3(1, 0, 1));  // no up direction
    Transform up_along_forward;                     // +Y and -Z columns parallel
    up_along_forward.m[1][1] = 0;
    up_along_forward.m[2][1] = -1;
    const Transform far = translation(Vec3(1e38f, 0, 0));
    Transform nan = translation(Vec3(0, k_nan, 0));
    for (const Transform& t : {none, flat, up_along_forward, far, nan}) {
        std::string message = refusal(camera_with(t));
        EXPECT_NE(message.find("camera 'cam'"), std::string::npos) << message;
    }
    Camera ortho = camera_with(Transform());
    ortho.orthographic = true;
    ortho.xmag = ortho.ymag = k_infinity;  // 1e39 in the file: finite as double, not as float
    EXPECT_NE(refusal(ortho).find("orthographic"), std::string::npos);
    ortho.xmag = ortho.ymag = 3e38f;  // finite, but its rays would start past the limit
    EXPECT_NE(refusal(ortho).find("orthographic"), std::string::npos);
    Camera fov = camera_with(Transform());
    fov.yfov = k_nan;
    EXPECT_NE(refusal(fov).find("field of view"), std::string::npos);
}

// A uniform node scale does not change what a camera sees, at 1e-25 (whose float axis lengths
// underflow when squared) as at 1e25: the same image as scale 1, exactly.
TEST(RayLimits, UniformlyScaledCameraSeesTheSameImage) {
    Scene s = lit_sphere();
    s.cameras.push_back(camera_with(Transform()));
    RenderStats stats;
    Image reference = test::render(s, 16, 4, "pt", 8, 0, 1, &stats);
    for (float k : {1e-25f, 1e25f}) {
        s.cameras[0].camera_to_world = scaling(Vec3(k, k, k));
        Image scaled = test::render(s, 16, 4, "pt", 8, 0, 1, &stats);
        EXPECT_EQ(stats.nonfinite_samples, 0u);
        ASSERT_EQ(scaled.rgba.size(), reference.rgba.size());
        double diff = 0;
        for (size_t i = 0; i < scaled.rgba.size(); ++i)
            diff = std::max(diff, double(std::fabs(scaled.rgba[i] - reference.rgba[i])));
        EXPECT_LT(diff, 1e-5) << "scale " << k;
    }
}

// No camera and geometry so large that the default camera would stand past the limit: refused
// with a message saying so, never an abort.
TEST(RayLimits, DefaultCameraForAHugeSceneIsRefused) {
    Bounds3 b;
    b.extend(Vec3(-1e30f, -1e30f, -1e30f));
    b.extend(Vec3(1e30f, 1e30f, 1e30f));
    try {
        CameraModel model(nullptr, b, 16, 16);
        FAIL() << "a default camera 1e30 away was accepted";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("default camera"), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace veach
