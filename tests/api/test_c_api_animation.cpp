// The C API's scene options for animation: `time` (a sequence poses a loaded scene again),
// `animation` (all, or one by name or index) and `shutter`, through libveach.so alone.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>

#include "capi_fixture.h"
#include "veach/veach.h"

namespace {

// An orthographic camera over [-1, 1]^2 and an emissive quad (radiance 1) on its left half that
// slides out of view by -1 in x between t = 0 and 1: the image mean is 0.5 at t = 0, 0.25 at 0.5.
std::string slide_gltf() {
    std::ifstream in(std::string(VEACH_TEST_DATA_DIR) + "/gltf/slide.gltf");
    return std::string(std::istreambuf_iterator<char>(in), {});
}

}  // namespace

TEST_F(CApi, SceneTimeAfterTheLoadPosesItAgainWithoutReadingTheFile) {
    const std::string text = slide_gltf();
    ASSERT_FALSE(text.empty());
    const std::string path = ::testing::TempDir() + "/veach_capi_slide.gltf";
    std::ofstream(path) << text;
    VeachScene s = veachNewScene(m_device);
    double t = 0;
    ASSERT_EQ(veachGetSceneFloat(s, "time", &t), VEACH_ERROR_NONE);
    EXPECT_TRUE(std::isnan(t));  // unset: the static pose
    ASSERT_EQ(veachSetSceneFloat(s, "time", 0.0), VEACH_ERROR_NONE);
    ASSERT_EQ(veachLoadSceneFile(s, path.c_str()), VEACH_ERROR_NONE) << veachGetLastError();
    std::remove(path.c_str());  // whatever comes next cannot read the file
    auto render_mean = [&](int spp) {
        VeachRender r = veachNewRender(s);
        veachSetInt(r, "width", 16);
        veachSetInt(r, "height", 16);
        veachSetInt(r, "spp", spp);
        veachSetString(r, "integrator", "pt");
        EXPECT_EQ(veachRender(r), VEACH_ERROR_NONE) << veachGetLastError();
        double mean = mean_rgb(combined(r));
        veachReleaseRender(r);
        return mean;
    };
    EXPECT_NEAR(render_mean(2), 0.5, 1e-6);
    ASSERT_EQ(veachSetSceneFloat(s, "time", 0.5), VEACH_ERROR_NONE) << veachGetLastError();
    EXPECT_NEAR(render_mean(2), 0.25, 1e-6);
    ASSERT_EQ(veachGetSceneFloat(s, "time", &t), VEACH_ERROR_NONE);
    EXPECT_EQ(t, 0.5);

    // Never while a render of the scene runs.
    VeachRender busy = veachNewRender(s);
    veachSetInt(busy, "width", 64);
    veachSetInt(busy, "height", 64);
    veachSetInt(busy, "spp", 1 << 20);
    ASSERT_EQ(veachRenderAsync(busy), VEACH_ERROR_NONE);
    EXPECT_REFUSED(veachSetSceneFloat(s, "time", 1.0), VEACH_ERROR_INVALID_OPERATION, "running");
    veachCancelRender(busy);
    veachWaitRender(busy, -1);
    EXPECT_EQ(veachSetSceneFloat(s, "time", 1.0), VEACH_ERROR_NONE) << veachGetLastError();
    EXPECT_NEAR(render_mean(2), 0.0, 1e-6);
    veachReleaseRender(busy);
    veachReleaseScene(s);

    // A scene loaded without a time has nothing to pose.
    VeachScene still = veachNewSceneFromFile(m_device, k_cornell.c_str());
    EXPECT_REFUSED(veachSetSceneFloat(still, "time", 1.0), VEACH_ERROR_INVALID_OPERATION, "without a time");
    veachReleaseScene(still);
}

TEST_F(CApi, SceneAnimationPlaysAllByDefaultOrOneByNameOrIndex) {
    // slide.gltf's animations: "slide" moves the quad out of view by t = 1, "idle" keeps the
    // camera where it is. At t = 1 the mean is 0 when "slide" plays, 0.5 when only "idle" does.
    const std::string path = ::testing::TempDir() + "/veach_capi_animation.gltf";
    std::ofstream(path) << slide_gltf();
    auto mean_at_1 = [&](const char* animation) {
        VeachScene s = veachNewScene(m_device);
        EXPECT_EQ(veachSetSceneFloat(s, "time", 1.0), VEACH_ERROR_NONE);
        if (animation) {
            EXPECT_EQ(veachSetSceneString(s, "animation", animation), VEACH_ERROR_NONE);
        }
        EXPECT_EQ(veachLoadSceneFile(s, path.c_str()), VEACH_ERROR_NONE) << veachGetLastError();
        VeachRender r = veachNewRender(s);
        veachSetInt(r, "width", 16);
        veachSetInt(r, "height", 16);
        veachSetInt(r, "spp", 2);
        veachSetString(r, "integrator", "pt");
        EXPECT_EQ(veachRender(r), VEACH_ERROR_NONE) << veachGetLastError();
        double mean = mean_rgb(combined(r));
        veachReleaseRender(r);
        veachReleaseScene(s);
        return mean;
    };
    EXPECT_NEAR(mean_at_1(nullptr), 0.0, 1e-6);  // "all", the default
    EXPECT_NEAR(mean_at_1("all"), 0.0, 1e-6);
    EXPECT_NEAR(mean_at_1("idle"), 0.5, 1e-6);
    EXPECT_NEAR(mean_at_1("1"), 0.5, 1e-6);  // "idle" by its index
    EXPECT_NEAR(mean_at_1("slide"), 0.0, 1e-6);
    VeachScene s = veachNewScene(m_device);
    ASSERT_EQ(veachSetSceneFloat(s, "time", 1.0), VEACH_ERROR_NONE);
    ASSERT_EQ(veachSetSceneString(s, "animation", "walk"), VEACH_ERROR_NONE);
    EXPECT_REFUSED(veachLoadSceneFile(s, path.c_str()), VEACH_ERROR_BAD_INPUT, "'slide', 'idle'");
    veachReleaseScene(s);
    std::remove(path.c_str());
}

TEST_F(CApi, SceneShutterIsCheckedBeforeTheLoadAndNeedsATime) {
    VeachScene s = veachNewScene(m_device);
    EXPECT_REFUSED(veachSetSceneString(s, "shutter", "0.25,-0.25"), VEACH_ERROR_INVALID_ARGUMENT, "opens after");
    EXPECT_REFUSED(veachSetSceneString(s, "shutter", "nan,0.25"), VEACH_ERROR_INVALID_ARGUMENT, "OPEN,CLOSE");
    EXPECT_REFUSED(veachSetSceneString(s, "shutter", "0.25"), VEACH_ERROR_INVALID_ARGUMENT, "OPEN,CLOSE");
    EXPECT_REFUSED(veachSetSceneString(s, "shutter", "0,inf"), VEACH_ERROR_INVALID_ARGUMENT, "OPEN,CLOSE");
    ASSERT_EQ(veachSetSceneString(s, "shutter", "-0.01,0.01"), VEACH_ERROR_NONE) << veachGetLastError();
    char value[64];
    size_t length = 0;
    ASSERT_EQ(veachGetSceneString(s, "shutter", value, sizeof(value), &length), VEACH_ERROR_NONE);
    EXPECT_STREQ(value, "-0.01,0.01");
    // Motion blur is the animation across the shutter: without a time there is none to sample.
    EXPECT_REFUSED(veachLoadSceneFile(s, k_cornell.c_str()), VEACH_ERROR_INVALID_OPERATION, "needs 'time'");
    veachReleaseScene(s);
    // With a time it loads; an empty shutter is none.
    VeachScene t = veachNewScene(m_device);
    ASSERT_EQ(veachSetSceneFloat(t, "time", 0.0), VEACH_ERROR_NONE);
    ASSERT_EQ(veachSetSceneString(t, "shutter", "0,0"), VEACH_ERROR_NONE);
    EXPECT_EQ(veachLoadSceneFile(t, k_cornell.c_str()), VEACH_ERROR_NONE) << veachGetLastError();
    veachReleaseScene(t);
}
