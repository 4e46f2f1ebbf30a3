// The C API's contract, tested through libveach.so and nothing else (this executable links only
// the shared library, so it also proves the exported symbol set is complete):
// - errors come back as codes, through the device callback and the per-thread last error, never
//   as a crash or an exception;
// - a render through the API equals itself whatever the path (sync, async, in memory, with a
//   padded stride, alongside another render): randomness is keyed by (seed, pixel, sample), so
//   the path tracer's images must be bit-identical;
// - cancel stops a render promptly (the latency is measured and printed; the bound asserted is a
//   generous 2 s so that a loaded machine cannot make it flake).
#include <dlfcn.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <thread>
#include <vector>

#include "capi_fixture.h"
#include "veach/veach.h"
#include "veach/veach.hpp"

namespace {

TEST(CApiVersion, LibraryMatchesHeader) {
    // A host compiled against one header and run with another library must be able to tell.
    EXPECT_EQ(veachGetVersion(), VEACH_VERSION);
    char expected[32];
    std::snprintf(expected, sizeof(expected), "%d.%d.%d", VEACH_VERSION_MAJOR, VEACH_VERSION_MINOR,
                  VEACH_VERSION_PATCH);
    EXPECT_STREQ(veachGetVersionString(), expected);
}

TEST_F(CApi, MissingFileIsReportedThroughCallbackAndLastError) {
    VeachScene s = veachNewSceneFromFile(m_device, "/nonexistent/scene.gltf");
    EXPECT_EQ(s, nullptr);
    EXPECT_EQ(m_errors.calls, 1);
    EXPECT_EQ(m_errors.last_code, VEACH_ERROR_BAD_INPUT);
    EXPECT_NE(m_errors.last_message.find("/nonexistent/scene.gltf"), std::string::npos) << m_errors.last_message;
    EXPECT_EQ(veachGetLastErrorCode(), VEACH_ERROR_BAD_INPUT);
    EXPECT_EQ(m_errors.last_message, veachGetLastError());
    // The next successful call clears the last error.
    EXPECT_EQ(veachGetSceneCameraCount(nullptr), -1);
    EXPECT_EQ(veachGetLastErrorCode(), VEACH_ERROR_INVALID_ARGUMENT);
    veachGetVersionString();
    EXPECT_NE(std::string(veachGetLastError()), "");  // getters of the error do not reset it
}

TEST_F(CApi, MalformedSceneIsAnErrorNotACrash) {
    VeachScene s = veachNewSceneFromFile(m_device, VEACH_TEST_DATA_DIR "/gltf/bad_json.gltf");
    EXPECT_EQ(s, nullptr);
    EXPECT_EQ(veachGetLastErrorCode(), VEACH_ERROR_BAD_INPUT);
    EXPECT_NE(std::string(veachGetLastError()).find("bad_json.gltf"), std::string::npos) << veachGetLastError();

    // Garbage claiming to be a .glb in memory.
    const char garbage[] = "glTF\x02\0\0\0garbage that is not a binary glTF container";
    s = veachNewSceneFromMemory(m_device, garbage, sizeof(garbage), "glb", nullptr);
    EXPECT_EQ(s, nullptr);
    EXPECT_EQ(veachGetLastErrorCode(), VEACH_ERROR_BAD_INPUT);
    EXPECT_EQ(m_errors.calls, 2);
}

TEST_F(CApi, NullHandlesAndBadOptionsAreErrors) {
    EXPECT_EQ(veachNewRender(nullptr), nullptr);
    EXPECT_EQ(veachGetLastErrorCode(), VEACH_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(veachRender(nullptr), VEACH_ERROR_INVALID_ARGUMENT);
    veachReleaseRender(nullptr);  // like free(NULL): nothing

    VeachScene s = veachNewSceneFromFile(m_device, k_cornell.c_str());
    ASSERT_NE(s, nullptr) << veachGetLastError();
    VeachRender r = veachNewRender(s);
    EXPECT_EQ(veachSetInt(r, "no_such_option", 1), VEACH_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(veachGetLastError()).find("no_such_option"), std::string::npos);
    EXPECT_EQ(veachSetFloat(r, "spp", 2.0), VEACH_ERROR_INVALID_ARGUMENT);  // spp is an int
    EXPECT_NE(std::string(veachGetLastError()).find("is an int"), std::string::npos) << veachGetLastError();
    EXPECT_EQ(veachSetInt(r, "spp", 0), VEACH_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(veachSetString(r, "integrator", "magic"), VEACH_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(veachGetLastError()).find("pt"), std::string::npos);  // names the known ones
    EXPECT_EQ(veachSetString(r, "camera", "nope"), VEACH_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(veachSetInt(r, "result_width", 3), VEACH_ERROR_INVALID_ARGUMENT);  // read-only
    EXPECT_EQ(veachSetFloat(r, "time_limit", -1), VEACH_ERROR_INVALID_ARGUMENT);
    std::vector<float> px(16);
    EXPECT_EQ(veachGetPass(r, "combined", px.data(), px.size() * sizeof(float), 0), VEACH_ERROR_INVALID_OPERATION);  // nothing rendered
    EXPECT_EQ(m_errors.calls, 8);
    long long spp = 0;
    EXPECT_EQ(veachGetInt(r, "spp", &spp), VEACH_ERROR_NONE);
    EXPECT_EQ(spp, 64);  // the failed sets left the default alone
    veachReleaseRender(r);
    veachReleaseScene(s);
}

TEST_F(CApi, RenderReportsProgressAndCopiesPassesWithStride) {
    VeachScene s = veachNewSceneFromFile(m_device, k_cornell.c_str());
    ASSERT_NE(s, nullptr) << veachGetLastError();
    EXPECT_GE(veachGetSceneCameraCount(s), 1);
    VeachRender r = new_cornell_render(s, 8);
    std::vector<double> fractions;
    veachSetProgressFunction(
        r,
        [](void* user, double fraction, double eta) {
            static_cast<std::vector<double>*>(user)->push_back(fraction);
            return eta >= 0;
        },
        &fractions);
    ASSERT_EQ(veachRender(r), VEACH_ERROR_NONE) << veachGetLastError();
    EXPECT_EQ(veachGetRenderStatus(r), VEACH_STATUS_DONE);
    ASSERT_FALSE(fractions.empty());
    for (size_t i = 1; i < fractions.size(); ++i) EXPECT_GE(fractions[i], fractions[i - 1]);
    EXPECT_DOUBLE_EQ(fractions.back(), 1.0);
    long long spp_done = 0;
    veachGetInt(r, "result_spp", &spp_done);
    EXPECT_EQ(spp_done, 8);

    std::vector<float> tight = combined(r);
    double mean = mean_rgb(tight);
    EXPECT_GT(mean, 0.01);  // a lit box: the light and the walls it lights are in view
    EXPECT_LT(mean, 10.0);
    // A padded stride (e.g. a host's image with alignment) holds exactly the same rows.
    const size_t row_floats = 48 * 4, stride_floats = row_floats + 12;
    std::vector<float> padded(stride_floats * 48, -1.0f);
    ASSERT_EQ(veachGetPass(r, "combined", padded.data(), padded.size() * sizeof(float), stride_floats * sizeof(float)), VEACH_ERROR_NONE);
    for (size_t y = 0; y < 48; ++y) {
        EXPECT_TRUE(std::equal(tight.begin() + y * row_floats, tight.begin() + (y + 1) * row_floats,
                               padded.begin() + y * stride_floats));
        EXPECT_EQ(padded[y * stride_floats + row_floats], -1.0f);  // the padding is untouched
    }
    EXPECT_EQ(veachGetPass(r, "combined", padded.data(), padded.size() * sizeof(float), 16), VEACH_ERROR_INVALID_ARGUMENT);  // stride < row
    veachReleaseRender(r);
    veachReleaseScene(s);
}

// veachGetPass knows the destination's size: one byte short of the last row is refused and not
// a byte of the buffer is written. Programs linked against 0.5 call the form without the size,
// which the library still exports under the symbol version VEACH_0 and which copies the same.
TEST_F(CApi, GetPassRefusesASmallDestinationAndKeepsThe05Form) {
    VeachScene s = veachNewSceneFromFile(m_device, k_cornell.c_str());
    ASSERT_NE(s, nullptr);
    VeachRender r = new_cornell_render(s, 2);
    ASSERT_EQ(veachRender(r), VEACH_ERROR_NONE);
    const size_t row = 48 * 4 * sizeof(float), stride = row + 64, needed = 47 * stride + row;
    std::vector<unsigned char> buffer(needed, 0xAB);
    auto* dst = reinterpret_cast<float*>(buffer.data());
    EXPECT_EQ(veachGetPass(r, "combined", dst, needed - 1, stride), VEACH_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(veachGetLastError()).find("destination"), std::string::npos) << veachGetLastError();
    EXPECT_TRUE(std::all_of(buffer.begin(), buffer.end(), [](unsigned char b) { return b == 0xAB; }));
    EXPECT_EQ(veachGetPass(r, "combined", dst, 0, 0), VEACH_ERROR_INVALID_ARGUMENT);
    ASSERT_EQ(veachGetPass(r, "combined", dst, needed, stride), VEACH_ERROR_NONE) << veachGetLastError();
    std::vector<unsigned char> expected = buffer;

    using GetPass05 = VeachError (*)(VeachRender, const char*, float*, size_t);
    auto old_form = reinterpret_cast<GetPass05>(dlvsym(RTLD_DEFAULT, "veachGetPass", "VEACH_0"));
    ASSERT_NE(old_form, nullptr) << "libveach lost veachGetPass@VEACH_0";
    auto new_form = dlvsym(RTLD_DEFAULT, "veachGetPass", "VEACH_0.6");
    EXPECT_EQ(new_form, reinterpret_cast<void*>(&veachGetPass));
    std::fill(buffer.begin(), buffer.end(), 0xAB);
    ASSERT_EQ(old_form(r, "combined", dst, stride), VEACH_ERROR_NONE);
    EXPECT_EQ(buffer, expected);
    veachReleaseRender(r);
    veachReleaseScene(s);
}

// An option of one integrator given to another is refused, not ignored.
TEST_F(CApi, BdptStrategyWithAnotherIntegratorIsRefused) {
    VeachScene s = veachNewSceneFromFile(m_device, k_cornell.c_str());
    ASSERT_NE(s, nullptr);
    VeachRender r = new_cornell_render(s, 1);
    ASSERT_EQ(veachSetInt(r, "bdpt_s", 1), VEACH_ERROR_NONE);
    ASSERT_EQ(veachSetInt(r, "bdpt_t", 2), VEACH_ERROR_NONE);
    for (const char* other : {"pt", "lt"}) {
        ASSERT_EQ(veachSetString(r, "integrator", other), VEACH_ERROR_NONE);
        EXPECT_EQ(veachRender(r), VEACH_ERROR_INVALID_ARGUMENT) << other;
        EXPECT_NE(std::string(veachGetLastError()).find("only to the bdpt integrator"), std::string::npos)
            << veachGetLastError();
    }
    ASSERT_EQ(veachSetString(r, "integrator", "bdpt"), VEACH_ERROR_NONE);
    EXPECT_EQ(veachRender(r), VEACH_ERROR_NONE) << veachGetLastError();
    veachReleaseRender(r);
    veachReleaseScene(s);
}

TEST_F(CApi, DepthPassWhenAovsRequested) {
    VeachScene s = veachNewSceneFromFile(m_device, k_cornell.c_str());
    ASSERT_NE(s, nullptr);
    VeachRender r = new_cornell_render(s, 2);
    std::vector<float> depth(48 * 48 * 4);
    ASSERT_EQ(veachRender(r), VEACH_ERROR_NONE);
    EXPECT_EQ(veachGetPass(r, "depth", depth.data(), depth.size() * sizeof(float), 0), VEACH_ERROR_INVALID_OPERATION);  // not recorded
    ASSERT_EQ(veachSetInt(r, "aovs", 1), VEACH_ERROR_NONE);
    ASSERT_EQ(veachRender(r), VEACH_ERROR_NONE);
    ASSERT_EQ(veachGetPass(r, "depth", depth.data(), depth.size() * sizeof(float), 0), VEACH_ERROR_NONE) << veachGetLastError();
    // Inside a closed box every camera ray hits something in front of the camera.
    size_t center = (24 * 48 + 24) * 4;
    EXPECT_GT(depth[center], 0.0f);
    EXPECT_LT(depth[center], 1e9f);
    veachReleaseRender(r);
    veachReleaseScene(s);
}

TEST_F(CApi, SamplesPassCountsEachPixelsSamples) {
    VeachScene s = veachNewSceneFromFile(m_device, k_cornell.c_str());
    ASSERT_NE(s, nullptr);
    VeachRender r = new_cornell_render(s, 6);
    ASSERT_EQ(veachRender(r), VEACH_ERROR_NONE);
    std::vector<float> samples(48 * 48 * 4);
    ASSERT_EQ(veachGetPass(r, "samples", samples.data(), samples.size() * sizeof(float), 0), VEACH_ERROR_NONE) << veachGetLastError();
    // Without adaptive sampling every pixel averages exactly the samples asked for.
    for (size_t i = 0; i < samples.size(); i += 4) {
        ASSERT_EQ(samples[i], 6.0f) << "pixel " << i / 4;
        ASSERT_EQ(samples[i + 3], 1.0f);
    }
    ASSERT_EQ(veachSetFloat(r, "noise", 0.5), VEACH_ERROR_NONE);
    ASSERT_EQ(veachSetInt(r, "spp", 64), VEACH_ERROR_NONE);
    ASSERT_EQ(veachRender(r), VEACH_ERROR_NONE);
    ASSERT_EQ(veachGetPass(r, "samples", samples.data(), samples.size() * sizeof(float), 0), VEACH_ERROR_NONE);
    // A loose noise threshold stops some pixels early, never past the samples asked for.
    float least = 1e9f, most = 0;
    for (size_t i = 0; i < samples.size(); i += 4)
        least = std::min(least, samples[i]), most = std::max(most, samples[i]);
    EXPECT_LT(least, 64.0f);
    EXPECT_LE(most, 64.0f);
    EXPECT_GT(least, 0.0f);
    veachReleaseRender(r);
    veachReleaseScene(s);
}

TEST_F(CApi, SceneFromMemoryRendersLikeTheFile) {
    std::ifstream f(k_cornell, std::ios::binary);
    std::vector<char> bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
    ASSERT_FALSE(bytes.empty());
    VeachScene from_memory =
        veachNewSceneFromMemory(m_device, bytes.data(), bytes.size(), "gltf", VEACH_EXAMPLES_DIR "/cornell");
    ASSERT_NE(from_memory, nullptr) << veachGetLastError();
    VeachScene from_file = veachNewSceneFromFile(m_device, k_cornell.c_str());
    VeachRender a = new_cornell_render(from_memory), b = new_cornell_render(from_file);
    ASSERT_EQ(veachRender(a), VEACH_ERROR_NONE);
    ASSERT_EQ(veachRender(b), VEACH_ERROR_NONE);
    EXPECT_EQ(combined(a), combined(b));
    for (VeachRender r : {a, b}) veachReleaseRender(r);
    veachReleaseScene(from_memory);
    veachReleaseScene(from_file);
}

TEST_F(CApi, ConcurrentRendersEqualRendersAlone) {
    // Two scenes, two renders at once in one process, with different thread counts and seeds:
    // no state is shared, so each image is bit-identical to the same render done alone.
    VeachScene s1 = veachNewSceneFromFile(m_device, k_cornell.c_str());
    VeachScene s2 = veachNewSceneFromFile(m_device, k_cornell.c_str());
    ASSERT_TRUE(s1 && s2);
    VeachRender alone1 = new_cornell_render(s1, 8, 1), alone2 = new_cornell_render(s2, 8, 2);
    veachSetInt(alone1, "threads", 1);
    veachSetInt(alone2, "threads", 2);
    ASSERT_EQ(veachRender(alone1), VEACH_ERROR_NONE);
    ASSERT_EQ(veachRender(alone2), VEACH_ERROR_NONE);

    VeachRender both1 = new_cornell_render(s1, 8, 1), both2 = new_cornell_render(s2, 8, 2);
    veachSetInt(both1, "threads", 2);
    veachSetInt(both2, "threads", 1);
    ASSERT_EQ(veachRenderAsync(both1), VEACH_ERROR_NONE);
    ASSERT_EQ(veachRenderAsync(both2), VEACH_ERROR_NONE);
    EXPECT_EQ(veachSetInt(both1, "spp", 3), VEACH_ERROR_INVALID_OPERATION);  // running: options frozen
    EXPECT_EQ(veachRender(both2), VEACH_ERROR_INVALID_OPERATION);
    EXPECT_EQ(veachWaitRender(both1, -1), VEACH_STATUS_DONE);
    EXPECT_EQ(veachWaitRender(both2, -1), VEACH_STATUS_DONE);

    EXPECT_EQ(combined(both1), combined(alone1));
    EXPECT_EQ(combined(both2), combined(alone2));
    EXPECT_NE(combined(alone1), combined(alone2));  // the seeds differ: the comparison can fail
    for (VeachRender r : {alone1, alone2, both1, both2}) veachReleaseRender(r);
    veachReleaseScene(s1);
    veachReleaseScene(s2);
}

TEST_F(CApi, CancelFromAnotherThreadStopsPromptly) {
    VeachScene s = veachNewSceneFromFile(m_device, k_cornell.c_str());
    ASSERT_NE(s, nullptr);
    VeachRender r = new_cornell_render(s, 1 << 20);
    veachSetInt(r, "width", 160);
    veachSetInt(r, "height", 160);

    // Asynchronous: cancel once the first pass is done (the BVH is built, tiles are running).
    ASSERT_EQ(veachRenderAsync(r), VEACH_ERROR_NONE);
    for (int i = 0; i < 2000; ++i) {
        double progress = 0;
        veachGetFloat(r, "progress", &progress);
        if (progress > 0) break;
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    EXPECT_EQ(veachWaitRender(r, 0), VEACH_STATUS_RUNNING);
    auto t0 = std::chrono::steady_clock::now();
    veachCancelRender(r);
    VeachStatus status = veachWaitRender(r, -1);
    double latency_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    EXPECT_EQ(status, VEACH_STATUS_CANCELLED);
    EXPECT_LT(latency_ms, 2000.0);
    std::printf("[ measure  ] async cancel latency: %.1f ms\n", latency_ms);
    RecordProperty("async_cancel_latency_ms", static_cast<int>(latency_ms));
    long long spp_done = -1;
    veachGetInt(r, "result_spp", &spp_done);
    EXPECT_GE(spp_done, 1);
    EXPECT_LT(spp_done, 1 << 20);
    EXPECT_GT(mean_rgb(combined(r)), 0.0);  // the partial image is there

    // Synchronous render cancelled from another thread: the call itself returns.
    std::atomic<bool> started{false};
    veachSetProgressFunction(
        r, [](void* user, double, double) { return static_cast<std::atomic<bool>*>(user)->exchange(true), true; },
        &started);
    std::chrono::steady_clock::time_point cancelled_at;
    std::thread canceller([&] {
        while (!started) std::this_thread::sleep_for(std::chrono::milliseconds(2));
        cancelled_at = std::chrono::steady_clock::now();
        veachCancelRender(r);
    });
    VeachError e = veachRender(r);
    auto returned_at = std::chrono::steady_clock::now();
    canceller.join();
    EXPECT_EQ(e, VEACH_ERROR_CANCELLED);
    EXPECT_EQ(veachGetLastErrorCode(), VEACH_ERROR_CANCELLED);
    EXPECT_EQ(veachGetRenderStatus(r), VEACH_STATUS_CANCELLED);
    latency_ms = std::chrono::duration<double, std::milli>(returned_at - cancelled_at).count();
    EXPECT_LT(latency_ms, 2000.0);
    std::printf("[ measure  ] sync cancel latency: %.1f ms\n", latency_ms);
    RecordProperty("sync_cancel_latency_ms", static_cast<int>(latency_ms));

    // Releasing a running render cancels and joins it (no leak, no crash).
    ASSERT_EQ(veachRenderAsync(r), VEACH_ERROR_NONE);
    veachReleaseRender(r);
    veachReleaseScene(s);
}

TEST_F(CApi, ProgressCallbackReturningFalseCancels) {
    VeachScene s = veachNewSceneFromFile(m_device, k_cornell.c_str());
    VeachRender r = new_cornell_render(s, 1000);
    veachSetProgressFunction(
        r, [](void*, double, double) { return false; }, nullptr);
    EXPECT_EQ(veachRender(r), VEACH_ERROR_CANCELLED);
    long long spp_done = 0;
    veachGetInt(r, "result_spp", &spp_done);
    EXPECT_LT(spp_done, 1000);
    veachReleaseRender(r);
    veachReleaseScene(s);
}

TEST_F(CApi, WriteImageIsAtomicAndReportsFailures) {
    VeachScene s = veachNewSceneFromFile(m_device, k_cornell.c_str());
    VeachRender r = new_cornell_render(s, 2);
    ASSERT_EQ(veachRender(r), VEACH_ERROR_NONE);
    auto dir = std::filesystem::temp_directory_path() / ("veach_capi_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    auto exr = dir / "out.exr";
    EXPECT_EQ(veachWriteImage(r, exr.c_str()), VEACH_ERROR_NONE) << veachGetLastError();
    EXPECT_GT(std::filesystem::file_size(exr), 1000u);
    EXPECT_EQ(veachWriteImage(r, (dir / "missing" / "out.png").c_str()), VEACH_ERROR_OUTPUT);
    EXPECT_EQ(m_errors.last_code, VEACH_ERROR_OUTPUT);
    EXPECT_FALSE(std::filesystem::exists(dir / "missing" / "out.png"));
    std::filesystem::remove_all(dir);
    veachReleaseRender(r);
    veachReleaseScene(s);
}

TEST(CppWrapper, ThrowsWithTheLibrarysCodeAndRenders) {
    veach::Device device;
    try {
        veach::Scene missing(device, "/nonexistent.glb");
        FAIL() << "no exception";
    } catch (const veach::Error& e) {
        EXPECT_EQ(e.code(), VEACH_ERROR_BAD_INPUT);
        EXPECT_NE(std::string(e.what()).find("/nonexistent.glb"), std::string::npos);
    }
    veach::Scene scene(device, k_cornell);
    veach::Render render(scene);
    render.set("width", 32).set("height", 32).set("spp", 2).set("integrator", "pt");
    EXPECT_THROW(render.set("integrator", "nope"), veach::Error);
    int calls = 0;
    render.on_progress([&](double, double) { return ++calls > 0; });
    EXPECT_TRUE(render.render());
    EXPECT_GT(calls, 0);
    std::vector<float> px = render.pass();
    EXPECT_EQ(px.size(), 32u * 32u * 4u);
    EXPECT_EQ(render.width(), 32);
}

// ---- Options added in 0.2 (what the `veach` command needs) -------------------------------

// A glTF with nothing in it: every camera ray escapes to the environment.
const char k_empty_gltf[] = R"({"asset": {"version": "2.0"}, "scenes": [{"nodes": []}], "scene": 0})";

std::string scene_string(VeachScene s, const char* name) {
    size_t length = 0;
    EXPECT_EQ(veachGetSceneString(s, name, nullptr, 0, &length), VEACH_ERROR_NONE) << veachGetLastError();
    std::string out(length + 1, '\0');
    EXPECT_EQ(veachGetSceneString(s, name, out.data(), out.size(), &length), VEACH_ERROR_NONE);
    out.resize(length);
    return out;
}

std::string render_string(VeachRender r, const char* name) {
    size_t length = 0;
    EXPECT_EQ(veachGetString(r, name, nullptr, 0, &length), VEACH_ERROR_NONE) << veachGetLastError();
    std::string out(length + 1, '\0');
    EXPECT_EQ(veachGetString(r, name, out.data(), out.size(), &length), VEACH_ERROR_NONE);
    out.resize(length);
    return out;
}

long long get_int(VeachRender r, const char* name) {
    long long v = -12345;
    EXPECT_EQ(veachGetInt(r, name, &v), VEACH_ERROR_NONE) << veachGetLastError();
    return v;
}

TEST_F(CApi, SceneOptionsAreCheckedAndFrozenByTheLoad) {
    VeachScene s = veachNewScene(m_device);
    ASSERT_NE(s, nullptr);
    EXPECT_REFUSED(veachSetSceneString(s, "spot_falloff", "cone"), VEACH_ERROR_INVALID_ARGUMENT,
                   "auto, blender or gltf");
    EXPECT_REFUSED(veachSetSceneString(s, "default_material", "grey"), VEACH_ERROR_INVALID_ARGUMENT,
                   "auto, blender or gltf");
    EXPECT_REFUSED(veachSetSceneString(s, "env_color", "1,2"), VEACH_ERROR_INVALID_ARGUMENT, "R,G,B");
    EXPECT_REFUSED(veachSetSceneString(s, "env_color", "1,-2,3"), VEACH_ERROR_INVALID_ARGUMENT, "R,G,B");
    EXPECT_REFUSED(veachSetSceneFloat(s, "env_strength", -1), VEACH_ERROR_INVALID_ARGUMENT, "env_strength");
    EXPECT_REFUSED(veachSetSceneFloat(s, "env_rotate", NAN), VEACH_ERROR_INVALID_ARGUMENT, "finite");
    EXPECT_REFUSED(veachSetSceneInt(s, "scene_index", -2), VEACH_ERROR_INVALID_ARGUMENT, "scene_index");
    EXPECT_REFUSED(veachSetSceneInt(s, "allow_external_files", 2), VEACH_ERROR_INVALID_ARGUMENT, "0 or 1");
    EXPECT_REFUSED(veachSetSceneFloat(s, "variant", 1), VEACH_ERROR_INVALID_ARGUMENT, "is a string");
    EXPECT_REFUSED(veachSetSceneInt(s, "no_such", 1), VEACH_ERROR_INVALID_ARGUMENT, "no_such");
    EXPECT_REFUSED(veachSetSceneInt(s, "triangles", 1), VEACH_ERROR_INVALID_ARGUMENT, "read-only");
    EXPECT_EQ(veachSetSceneString(s, "env_color", "0.5,0.25,1"), VEACH_ERROR_NONE);
    EXPECT_REFUSED(veachSetSceneString(s, "env_map", "sky.exr"), VEACH_ERROR_INVALID_ARGUMENT, "exclude");
    // Not loaded yet: no render, no results.
    EXPECT_EQ(veachNewRender(s), nullptr);
    EXPECT_EQ(veachGetLastErrorCode(), VEACH_ERROR_INVALID_OPERATION);
    EXPECT_NE(std::string(veachGetLastError()).find("not loaded"), std::string::npos) << veachGetLastError();
    long long v = 0;
    EXPECT_EQ(veachGetSceneInt(s, "triangles", &v), VEACH_ERROR_INVALID_OPERATION);
    EXPECT_EQ(veachSetSceneString(s, "spot_falloff", "blender"), VEACH_ERROR_NONE);
    EXPECT_EQ(scene_string(s, "default_material"), "auto");
    EXPECT_EQ(veachSetSceneString(s, "default_material", "gltf"), VEACH_ERROR_NONE);
    ASSERT_EQ(veachLoadSceneFile(s, k_cornell.c_str()), VEACH_ERROR_NONE) << veachGetLastError();
    // Loaded: options are frozen, a second load is refused, results are there.
    EXPECT_REFUSED(veachSetSceneString(s, "variant", "x"), VEACH_ERROR_INVALID_OPERATION, "loaded");
    EXPECT_REFUSED(veachLoadSceneFile(s, k_cornell.c_str()), VEACH_ERROR_INVALID_OPERATION, "loaded");
    EXPECT_EQ(scene_string(s, "spot_falloff"), "blender");
    EXPECT_EQ(scene_string(s, "default_material"), "gltf");
    EXPECT_EQ(scene_string(s, "env_color"), "0.5,0.25,1");
    EXPECT_EQ(scene_string(s, "source"), k_cornell);
    EXPECT_EQ(veachGetSceneInt(s, "cameras", &v), VEACH_ERROR_NONE);
    EXPECT_EQ(v, veachGetSceneCameraCount(s));
    EXPECT_EQ(veachGetSceneInt(s, "triangles", &v), VEACH_ERROR_NONE);
    EXPECT_GE(v, 12);  // at least the box's six quads
    EXPECT_NE(scene_string(s, "features").find("emissive_meshes"), std::string::npos);
    veachReleaseScene(s);
}

TEST_F(CApi, BadSceneContentFailsTheLoadWithBadInput) {
    VeachScene s = veachNewScene(m_device);
    veachSetSceneString(s, "env_map", "/nonexistent/sky.exr");
    EXPECT_REFUSED(veachLoadSceneFile(s, k_cornell.c_str()), VEACH_ERROR_BAD_INPUT, "/nonexistent/sky.exr");
    veachReleaseScene(s);
    s = veachNewScene(m_device);
    veachSetSceneString(s, "variant", "no such variant");
    EXPECT_REFUSED(veachLoadSceneFile(s, k_cornell.c_str()), VEACH_ERROR_BAD_INPUT, "no such variant");
    veachReleaseScene(s);
    s = veachNewScene(m_device);
    veachSetSceneInt(s, "scene_index", 99);
    EXPECT_REFUSED(veachLoadSceneFile(s, k_cornell.c_str()), VEACH_ERROR_BAD_INPUT, "cornell.gltf");
    veachReleaseScene(s);
    EXPECT_EQ(m_errors.calls, 3);  // each through the callback too
}

TEST_F(CApi, UniformEnvironmentIsSeenDirectlyWithItsStrength) {
    // A camera ray that escapes sees the environment's radiance: colour x strength, exactly (a
    // box filter keeps every sample in its pixel with weight 1), whatever the rotation.
    VeachScene s = veachNewScene(m_device);
    ASSERT_EQ(veachSetSceneString(s, "env_color", "0.5,0.25,1"), VEACH_ERROR_NONE);
    ASSERT_EQ(veachSetSceneFloat(s, "env_strength", 3), VEACH_ERROR_NONE);
    ASSERT_EQ(veachSetSceneFloat(s, "env_rotate", 90), VEACH_ERROR_NONE);
    ASSERT_EQ(veachLoadSceneMemory(s, k_empty_gltf, sizeof(k_empty_gltf) - 1, "gltf", nullptr), VEACH_ERROR_NONE)
        << veachGetLastError();
    VeachRender r = veachNewRender(s);
    veachSetInt(r, "width", 16);
    veachSetInt(r, "height", 8);
    veachSetInt(r, "spp", 2);
    veachSetString(r, "integrator", "pt");
    ASSERT_EQ(veachRender(r), VEACH_ERROR_NONE) << veachGetLastError();
    std::vector<float> px = combined(r);
    const float expected[3] = {1.5f, 0.75f, 3.0f};
    for (size_t i = 0; i < px.size(); i += 4)
        for (int c = 0; c < 3; ++c) ASSERT_NEAR(px[i + c], expected[c], 1e-5f * expected[c]) << "pixel " << i / 4;
    EXPECT_NE(scene_string(s, "features").find("environment"), std::string::npos);
    veachReleaseRender(r);
    veachReleaseScene(s);
}

TEST_F(CApi, TransparentFilmHidesTheEnvironmentAndIsNotSplitIntoParts) {
    // The same empty scene with transparent = 1: every pixel is (0, 0, 0, 0); alpha needs the
    // film's coverage, which part files do not carry, so a sample range is refused.
    VeachScene s = veachNewScene(m_device);
    ASSERT_EQ(veachSetSceneString(s, "env_color", "0.5,0.25,1"), VEACH_ERROR_NONE);
    ASSERT_EQ(veachLoadSceneMemory(s, k_empty_gltf, sizeof(k_empty_gltf) - 1, "gltf", nullptr), VEACH_ERROR_NONE)
        << veachGetLastError();
    VeachRender r = veachNewRender(s);
    veachSetInt(r, "width", 16);
    veachSetInt(r, "height", 8);
    veachSetInt(r, "spp", 2);
    veachSetString(r, "integrator", "pt");
    long long value = -1;
    ASSERT_EQ(veachGetInt(r, "transparent", &value), VEACH_ERROR_NONE);
    EXPECT_EQ(value, 0);
    EXPECT_REFUSED(veachSetInt(r, "transparent", 2), VEACH_ERROR_INVALID_ARGUMENT, "transparent");
    ASSERT_EQ(veachSetInt(r, "transparent", 1), VEACH_ERROR_NONE);
    ASSERT_EQ(veachGetInt(r, "transparent", &value), VEACH_ERROR_NONE);
    EXPECT_EQ(value, 1);
    ASSERT_EQ(veachRender(r), VEACH_ERROR_NONE) << veachGetLastError();
    std::vector<float> px = combined(r);
    for (size_t i = 0; i < px.size(); ++i) ASSERT_EQ(px[i], 0.0f) << "pixel " << i / 4 << " channel " << i % 4;
    veachReleaseRender(r);
    r = veachNewRender(s);
    veachSetInt(r, "transparent", 1);
    veachSetInt(r, "spp", 4);
    veachSetInt(r, "sample_end", 2);
    EXPECT_NE(veachRender(r), VEACH_ERROR_NONE);
    EXPECT_NE(std::string(veachGetLastError()).find("transparent film cannot be rendered in parts"), std::string::npos)
        << veachGetLastError();
    veachReleaseRender(r);
    veachReleaseScene(s);
}

TEST_F(CApi, NewRenderOptionsRefuseBadValuesAndReadBack) {
    VeachScene s = veachNewSceneFromFile(m_device, k_cornell.c_str());
    ASSERT_NE(s, nullptr) << veachGetLastError();
    VeachRender r = veachNewRender(s);
    EXPECT_REFUSED(veachSetString(r, "filter", "lanczos"), VEACH_ERROR_INVALID_ARGUMENT, "blackman-harris");
    EXPECT_REFUSED(veachSetFloat(r, "filter_width", 0), VEACH_ERROR_INVALID_ARGUMENT, "filter_width");
    EXPECT_REFUSED(veachSetString(r, "sampler", "halton"), VEACH_ERROR_INVALID_ARGUMENT, "sobol or random");
    EXPECT_REFUSED(veachSetString(r, "exr_codec", "zip:10"), VEACH_ERROR_INVALID_ARGUMENT, "exr_codec");
    EXPECT_REFUSED(veachSetString(r, "exr_codec", "lzma"), VEACH_ERROR_INVALID_ARGUMENT, "dwab");
    EXPECT_REFUSED(veachSetString(r, "passes", "combined,glossy"), VEACH_ERROR_INVALID_ARGUMENT, "glossy");
    EXPECT_REFUSED(veachSetFloat(r, "noise", -0.1), VEACH_ERROR_INVALID_ARGUMENT, "noise");
    EXPECT_REFUSED(veachSetFloat(r, "noise", INFINITY), VEACH_ERROR_INVALID_ARGUMENT, "finite");
    EXPECT_REFUSED(veachSetInt(r, "bdpt_t", 1001), VEACH_ERROR_INVALID_ARGUMENT, "bdpt_t");
    EXPECT_REFUSED(veachSetInt(r, "resume", 2), VEACH_ERROR_INVALID_ARGUMENT, "resume");
    EXPECT_REFUSED(veachSetFloat(r, "gamma", 0), VEACH_ERROR_INVALID_ARGUMENT, "gamma");
    EXPECT_REFUSED(veachSetFloat(r, "exposure", 100), VEACH_ERROR_INVALID_ARGUMENT, "exposure");
    EXPECT_REFUSED(veachSetString(r, "result_camera", "x"), VEACH_ERROR_INVALID_ARGUMENT, "read-only");
    EXPECT_REFUSED(veachSetFloat(r, "build_seconds", 1), VEACH_ERROR_INVALID_ARGUMENT, "read-only");
    EXPECT_REFUSED(veachGetString(r, "spp", nullptr, 0, nullptr), VEACH_ERROR_INVALID_ARGUMENT, "is an int");
    char small[4];
    EXPECT_REFUSED(veachGetString(r, "filter", nullptr, sizeof(small), nullptr), VEACH_ERROR_INVALID_ARGUMENT, "null");
    EXPECT_EQ(m_errors.calls, 16);

    // Good values read back; passes that need first-hit AOVs switch them on.
    EXPECT_EQ(veachSetString(r, "filter", "gaussian"), VEACH_ERROR_NONE);
    EXPECT_EQ(veachSetString(r, "exr_codec", "dwaa:45"), VEACH_ERROR_NONE);
    EXPECT_EQ(veachSetString(r, "passes", "combined,normal,combined"), VEACH_ERROR_NONE);
    EXPECT_EQ(veachSetFloat(r, "noise", 0.02), VEACH_ERROR_NONE);
    EXPECT_EQ(veachSetString(r, "sampler", "random"), VEACH_ERROR_NONE);
    EXPECT_EQ(render_string(r, "filter"), "gaussian");
    EXPECT_EQ(render_string(r, "exr_codec"), "dwaa:45");
    EXPECT_EQ(render_string(r, "passes"), "combined,normal");
    EXPECT_EQ(render_string(r, "sampler"), "random");
    EXPECT_EQ(get_int(r, "aovs"), 1);
    double noise = 0, interval = 0;
    EXPECT_EQ(veachGetFloat(r, "noise", &noise), VEACH_ERROR_NONE);
    EXPECT_FLOAT_EQ(noise, 0.02);
    EXPECT_EQ(veachGetFloat(r, "checkpoint_interval", &interval), VEACH_ERROR_NONE);
    EXPECT_LT(interval, 0);  // never written unless asked
    // A short buffer gets a truncated, terminated string and the full length.
    size_t length = 0;
    EXPECT_EQ(veachGetString(r, "filter", small, sizeof(small), &length), VEACH_ERROR_NONE);
    EXPECT_STREQ(small, "gau");
    EXPECT_EQ(length, 8u);
    veachReleaseRender(r);
    veachReleaseScene(s);
}

TEST_F(CApi, StatsDescribeTheRender) {
    VeachScene s = veachNewSceneFromFile(m_device, k_cornell.c_str());
    ASSERT_NE(s, nullptr) << veachGetLastError();
    VeachRender r = new_cornell_render(s, 4);
    EXPECT_EQ(get_int(r, "result_complete"), 0);  // nothing rendered yet
    ASSERT_EQ(veachRender(r), VEACH_ERROR_NONE) << veachGetLastError();
    // One camera sample per pixel per sample, and the path tracer traces at least one ray each.
    EXPECT_EQ(get_int(r, "result_camera_samples"), 48 * 48 * 4);
    EXPECT_GE(get_int(r, "result_rays"), 48 * 48 * 4);
    EXPECT_EQ(get_int(r, "result_spp"), 4);
    EXPECT_EQ(get_int(r, "result_complete"), 1);
    EXPECT_EQ(get_int(r, "result_resumed_spp"), 0);
    EXPECT_EQ(get_int(r, "result_nonfinite_samples"), 0);
    EXPECT_EQ(render_string(r, "result_integrator"), "pt");
    EXPECT_EQ(render_string(r, "result_camera"), veachGetSceneCameraName(s, 0));
    double build = -1, seconds = -1;
    EXPECT_EQ(veachGetFloat(r, "build_seconds", &build), VEACH_ERROR_NONE);
    EXPECT_EQ(veachGetFloat(r, "render_seconds", &seconds), VEACH_ERROR_NONE);
    EXPECT_GE(build, 0);
    EXPECT_GT(seconds, 0);
    long long peak = 0;
    EXPECT_EQ(veachGetDeviceInt(m_device, "peak_memory_bytes", &peak), VEACH_ERROR_NONE);
    EXPECT_GT(peak, 1 << 20);  // this process holds at least a megabyte (Linux /proc)
    EXPECT_EQ(veachGetDeviceInt(m_device, "nope", &peak), VEACH_ERROR_INVALID_ARGUMENT);
    veachReleaseRender(r);
    veachReleaseScene(s);
}

TEST_F(CApi, DeviceListsNamesAndTheColourConfig) {
    auto get = [&](const char* name) {
        size_t length = 0;
        EXPECT_EQ(veachGetDeviceString(m_device, name, nullptr, 0, &length), VEACH_ERROR_NONE) << veachGetLastError();
        std::string s(length + 1, '\0');
        veachGetDeviceString(m_device, name, s.data(), s.size(), &length);
        s.resize(length);
        return s;
    };
    EXPECT_EQ(get("integrators").find("auto\nbdpt\npt"), 0u) << get("integrators");
    EXPECT_NE(get("passes").find("variance"), std::string::npos);
    EXPECT_NE(get("color_config"), "");
    std::string displays = get("color_displays");
    ASSERT_NE(displays, "");
    std::string first = displays.substr(0, displays.find('\n'));
    EXPECT_NE(get(("color_views:" + first).c_str()), "");  // every display has a view
    EXPECT_REFUSED(veachGetDeviceString(m_device, "color_views:No Such Display", nullptr, 0, nullptr),
                   VEACH_ERROR_INVALID_ARGUMENT, "No Such Display");
    EXPECT_REFUSED(veachGetDeviceString(nullptr, "integrators", nullptr, 0, nullptr), VEACH_ERROR_INVALID_ARGUMENT,
                   "null device");
}

TEST_F(CApi, CheckpointResumesToTheSameImageAndRefusesAnotherRender) {
    // A checkpoint written after every pass but the last holds fewer than 8 samples; resuming
    // from it to 8 must give exactly the image of an uninterrupted render (pt: each pixel adds
    // its samples in index order, keyed by (seed, pixel, sample)).
    auto dir = std::filesystem::temp_directory_path() / ("veach_capi_cp_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    const std::string state = (dir / "state.checkpoint").string();
    VeachScene s = veachNewSceneFromFile(m_device, k_cornell.c_str());
    ASSERT_NE(s, nullptr) << veachGetLastError();
    VeachRender full = new_cornell_render(s, 8);
    ASSERT_EQ(veachSetString(full, "checkpoint", state.c_str()), VEACH_ERROR_NONE);
    ASSERT_EQ(veachSetFloat(full, "checkpoint_interval", 0), VEACH_ERROR_NONE);
    ASSERT_EQ(veachRender(full), VEACH_ERROR_NONE) << veachGetLastError();
    ASSERT_TRUE(std::filesystem::exists(state)) << "no checkpoint written";

    VeachRender resumed = new_cornell_render(s, 8);
    veachSetString(resumed, "checkpoint", state.c_str());
    veachSetInt(resumed, "resume", 1);
    veachSetInt(resumed, "threads", 1);  // threads may differ
    ASSERT_EQ(veachRender(resumed), VEACH_ERROR_NONE) << veachGetLastError();
    long long from = get_int(resumed, "result_resumed_spp");
    EXPECT_GE(from, 1);
    EXPECT_LT(from, 8);
    EXPECT_EQ(get_int(resumed, "result_spp"), 8);
    EXPECT_EQ(combined(resumed), combined(full));

    VeachRender other = new_cornell_render(s, 8, 99);  // another seed: another image
    veachSetString(other, "checkpoint", state.c_str());
    veachSetInt(other, "resume", 1);
    EXPECT_REFUSED(veachRender(other), VEACH_ERROR_BAD_INPUT, "state.checkpoint");
    EXPECT_EQ(veachGetRenderStatus(other), VEACH_STATUS_FAILED);

    // A checkpoint that cannot be written is an output failure.
    VeachRender unwritable = new_cornell_render(s, 8);
    veachSetString(unwritable, "checkpoint", (dir / "missing" / "state").c_str());
    veachSetFloat(unwritable, "checkpoint_interval", 0);
    EXPECT_REFUSED(veachRender(unwritable), VEACH_ERROR_OUTPUT, "missing");
    for (VeachRender r : {full, resumed, other, unwritable}) veachReleaseRender(r);
    veachReleaseScene(s);
    std::filesystem::remove_all(dir);
}

TEST(CppWrapper, SceneOptionsStatsAndStrings) {
    veach::Device device;
    EXPECT_NE(device.get_string("integrators").find("pt"), std::string::npos);
    veach::Scene scene(device);
    try {
        scene.set("spot_falloff", "cone");
        FAIL() << "no exception";
    } catch (const veach::Error& e) {
        EXPECT_EQ(e.code(), VEACH_ERROR_INVALID_ARGUMENT);
        EXPECT_NE(std::string(e.what()).find("spot_falloff"), std::string::npos);
    }
    scene.set("env_color", "0.25,0.5,2").set("env_strength", 2.0);
    scene.load(k_empty_gltf, sizeof(k_empty_gltf) - 1, "gltf");
    EXPECT_THROW(scene.set("env_strength", 1.0), veach::Error);  // frozen by the load
    EXPECT_EQ(scene.get_int("triangles"), 0);
    veach::Render render(scene);
    render.set("width", 8).set("height", 8).set("spp", 1).set("integrator", "pt");
    EXPECT_TRUE(render.render());
    EXPECT_EQ(render.get_string("result_integrator"), "pt");
    std::vector<float> px = render.pass();
    EXPECT_NEAR(px[0], 0.5f, 1e-6f);  // the environment, 0.25 x 2, seen directly
    EXPECT_NEAR(px[2], 4.0f, 1e-5f);
}

// Waiting on a render from its own progress callback would wait for itself: refused with
// INVALID_OPERATION (the render then finishes normally), from an asynchronous render's thread
// and from a synchronous render's caller alike.
bool wait_from_progress(void* user, double, double) {
    auto* r = static_cast<std::pair<VeachRender, std::atomic<int>>*>(user);
    if (veachWaitRender(r->first, -1) == VEACH_STATUS_FAILED &&
        veachGetLastErrorCode() == VEACH_ERROR_INVALID_OPERATION)
        ++r->second;
    return true;
}

TEST_F(CApi, WaitFromTheRendersOwnCallbackIsRefused) {
    VeachScene s = veachNewSceneFromFile(m_device, k_cornell.c_str());
    ASSERT_NE(s, nullptr);
    VeachRender r = new_cornell_render(s, 2);
    std::pair<VeachRender, std::atomic<int>> state{r, 0};
    veachSetProgressFunction(r, wait_from_progress, &state);
    ASSERT_EQ(veachRenderAsync(r), VEACH_ERROR_NONE);
    EXPECT_EQ(veachWaitRender(r, -1), VEACH_STATUS_DONE);
    EXPECT_GE(state.second.load(), 1);
    state.second = 0;
    EXPECT_EQ(veachRender(r), VEACH_ERROR_NONE);
    EXPECT_GE(state.second.load(), 1);
    veachReleaseRender(r);
    veachReleaseScene(s);
}

// An error callback that itself makes a failing call is not called again for that failure (the
// last error still records it): no recursion without end.
struct Recursion {
    VeachDevice device;
    int depth = 0, calls = 0;
};
void failing_logger(void* user, VeachError, const char*) {
    auto* r = static_cast<Recursion*>(user);
    ++r->calls;
    ++r->depth;
    if (r->depth < 1000) veachNewSceneFromFile(r->device, "/nonexistent/scene.gltf");
    --r->depth;
}

TEST_F(CApi, ErrorCallbackCallingAFailingFunctionDoesNotRecurse) {
    Recursion state{m_device};
    veachSetDeviceErrorFunction(m_device, failing_logger, &state);
    EXPECT_EQ(veachNewSceneFromFile(m_device, "/nonexistent/other.gltf"), nullptr);
    EXPECT_EQ(state.calls, 1);
    EXPECT_EQ(veachGetLastErrorCode(), VEACH_ERROR_BAD_INPUT);
    // Once the callback has returned, the next failure reaches it again.
    EXPECT_EQ(veachNewSceneFromFile(m_device, "/nonexistent/third.gltf"), nullptr);
    EXPECT_EQ(state.calls, 2);
}

}  // namespace

// Outputs are checked before rendering: what veachWriteImage would refuse (format, colour config
// names, folder) is refused by veachCheckOutput on a render that never ran, and nothing is left
// in the folder by the check.
TEST_F(CApi, OutputsCheckedWithoutRendering) {
    auto dir = std::filesystem::temp_directory_path() / ("veach_capi_check_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    VeachScene scene = veachNewSceneFromFile(m_device, k_cornell.c_str());
    ASSERT_NE(scene, nullptr) << veachGetLastError();
    VeachRender r = new_cornell_render(scene);
    const std::string png = (dir / "a.png").string();
    EXPECT_EQ(veachCheckOutput(r, png.c_str()), VEACH_ERROR_NONE) << veachGetLastError();
    EXPECT_EQ(veachCheckOutput(r, (dir / "a.exr").string().c_str()), VEACH_ERROR_NONE) << veachGetLastError();
    EXPECT_EQ(veachCheckOutput(r, (dir / "a.vpart").string().c_str()), VEACH_ERROR_NONE) << veachGetLastError();
    EXPECT_REFUSED(veachCheckOutput(r, (dir / "a.xyz").string().c_str()), VEACH_ERROR_INVALID_ARGUMENT, "'.xyz'");
    EXPECT_REFUSED(veachCheckOutput(r, (dir / "none" / "a.exr").string().c_str()), VEACH_ERROR_OUTPUT, "none");
    EXPECT_REFUSED(veachCheckOutput(r, dir.string().c_str()), VEACH_ERROR_INVALID_ARGUMENT, "unknown image format");
    ASSERT_EQ(veachSetString(r, "view", "No Such View"), VEACH_ERROR_NONE);
    EXPECT_REFUSED(veachCheckOutput(r, png.c_str()), VEACH_ERROR_INVALID_ARGUMENT, "No Such View");
    EXPECT_EQ(veachCheckOutput(r, (dir / "a.exr").string().c_str()), VEACH_ERROR_NONE)  // scene-linear: no view
        << veachGetLastError();
    EXPECT_EQ(veachCheckFile(m_device, (dir / "stats.json").string().c_str()), VEACH_ERROR_NONE);
    EXPECT_EQ(veachCheckFile(m_device, "/dev/null"), VEACH_ERROR_NONE);
    EXPECT_REFUSED(veachCheckFile(m_device, (dir / "none" / "s.json").string().c_str()), VEACH_ERROR_OUTPUT, "none");
    EXPECT_REFUSED(veachCheckFile(m_device, dir.string().c_str()), VEACH_ERROR_OUTPUT, "is a folder");
    EXPECT_TRUE(std::filesystem::is_empty(dir));  // no probe file left, nothing rendered or written
    veachReleaseRender(r);
    veachReleaseScene(scene);
    std::filesystem::remove_all(dir);
}

// Whether a shared object whose path contains `name` is mapped into this process.
bool mapped(const std::string& name) {
    std::ifstream maps("/proc/self/maps");
    for (std::string line; std::getline(maps, line);)
        if (line.find(name) != std::string::npos) return true;
    return false;
}

// OpenImageIO (Debian's pulls in ~260 libraries) is loaded by the first image read or written,
// never by a process that only loads a scene without images, renders and writes a part file: a
// farm part's fixed cost. The first image written opens libveach's image module.
TEST_F(CApi, OpenImageIOIsLoadedOnlyByTheFirstImageReadOrWritten) {
    // CTest runs each case in a process of its own; run with the others, an earlier case's image
    // has opened the module already.
    if (mapped("libveach_image_io")) GTEST_SKIP() << "an image was read or written earlier in this process";
    ASSERT_FALSE(mapped("libOpenImageIO")) << "libveach must not link OpenImageIO";
    auto dir = std::filesystem::temp_directory_path() / ("veach_capi_lazy_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    VeachScene scene = veachNewSceneFromFile(m_device, k_cornell.c_str());
    ASSERT_NE(scene, nullptr) << veachGetLastError();
    VeachRender r = new_cornell_render(scene);
    ASSERT_EQ(veachSetInt(r, "sample_begin", 0), VEACH_ERROR_NONE);
    ASSERT_EQ(veachSetInt(r, "sample_end", 2), VEACH_ERROR_NONE);
    const std::string part = (dir / "a.vpart").string();
    ASSERT_EQ(veachCheckOutput(r, part.c_str()), VEACH_ERROR_NONE) << veachGetLastError();
    ASSERT_EQ(veachRender(r), VEACH_ERROR_NONE) << veachGetLastError();
    ASSERT_EQ(veachWriteImage(r, part.c_str()), VEACH_ERROR_NONE) << veachGetLastError();
    char buffer[4096];
    size_t length = 0;
    ASSERT_EQ(veachReadImageMetadata(m_device, part.c_str(), buffer, sizeof(buffer), &length), VEACH_ERROR_NONE)
        << veachGetLastError();
    EXPECT_FALSE(mapped("libOpenImageIO")) << "a part render loaded OpenImageIO";
    EXPECT_FALSE(mapped("libveach_image_io"));
    const std::string png = (dir / "a.png").string();
    ASSERT_EQ(veachWriteImage(r, png.c_str()), VEACH_ERROR_NONE) << veachGetLastError();
    EXPECT_TRUE(mapped("libveach_image_io.so"));
    EXPECT_TRUE(mapped("libOpenImageIO"));
    ASSERT_EQ(veachReadImageMetadata(m_device, png.c_str(), buffer, sizeof(buffer), &length), VEACH_ERROR_NONE)
        << veachGetLastError();
    EXPECT_NE(std::string(buffer).find("veach:spp=2"), std::string::npos) << buffer;
    veachReleaseRender(r);
    veachReleaseScene(scene);
    std::filesystem::remove_all(dir);
}

// Options that do not apply to the chosen integrator are refused (a bdpt strategy with pt or lt:
// BdptStrategyWithAnotherIntegratorIsRefused) or said: a noise threshold with lt, whose pixels
// hold no estimate of their own, renders every pixel to the samples asked for with a warning
// (Blender's add-on passes Cycles' threshold whatever the integrator, so this is not refused).
TEST_F(CApi, NoiseThresholdWithLightTracingIsWarnedNotDroppedSilently) {
    VeachScene s = veachNewSceneFromFile(m_device, k_cornell.c_str());
    ASSERT_NE(s, nullptr);
    for (const char* integrator : {"lt", "pt"}) {
        VeachRender r = new_cornell_render(s, 8);
        ASSERT_EQ(veachSetString(r, "integrator", integrator), VEACH_ERROR_NONE);
        ASSERT_EQ(veachSetFloat(r, "noise", 0.5), VEACH_ERROR_NONE);
        ASSERT_EQ(veachRender(r), VEACH_ERROR_NONE) << veachGetLastError();
        const std::string warnings = render_string(r, "result_warnings");
        const bool lt = std::string(integrator) == "lt";
        EXPECT_EQ(warnings.find("noise threshold") != std::string::npos, lt) << integrator << ": " << warnings;
        if (lt) {
            std::vector<float> samples(48 * 48 * 4);
            ASSERT_EQ(veachGetPass(r, "samples", samples.data(), samples.size() * sizeof(float), 0), VEACH_ERROR_NONE);
            for (size_t i = 0; i < samples.size(); i += 4) ASSERT_EQ(samples[i], 8.0f) << "pixel " << i / 4;
        }
        veachReleaseRender(r);
    }
    veachReleaseScene(s);
}
