// Progressive snapshots through the C API: during an asynchronous render veachGetPass returns the
// film so far, resolved at a pass boundary (every pixel holds that pass's samples, so the
// "samples" pass is uniform and each pass agrees with the others of its snapshot); snapshots
// only ever gain samples, and the one taken at the last pass boundary is the final image bit for
// bit (path tracing: the same sums resolved the same way).
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <string>
#include <thread>
#include <vector>

#include "veach/veach.h"

namespace {

const std::string k_cornell = std::string(VEACH_EXAMPLES_DIR) + "/cornell/cornell.gltf";
constexpr int k_size = 24, k_spp = 40;

struct Snapshot {
    std::vector<float> combined, samples;
};

struct Collector {
    VeachRender render = nullptr;
    std::vector<Snapshot> taken;
    std::vector<VeachError> refusals;
};

// On the rendering thread, right after a pass: the snapshot of that pass (option "snapshots").
bool take_snapshot(void* user, double, double) {
    auto* c = static_cast<Collector*>(user);
    Snapshot s;
    s.combined.resize(k_size * k_size * 4);
    s.samples.resize(k_size * k_size * 4);
    VeachError a = veachGetPass(c->render, "combined", s.combined.data(), s.combined.size() * sizeof(float), 0);
    VeachError b = veachGetPass(c->render, "samples", s.samples.data(), s.samples.size() * sizeof(float), 0);
    if (a == VEACH_ERROR_NONE && b == VEACH_ERROR_NONE)
        c->taken.push_back(std::move(s));
    else
        c->refusals.push_back(a != VEACH_ERROR_NONE ? a : b);
    return true;
}

VeachRender cornell_render(VeachScene scene) {
    VeachRender r = veachNewRender(scene);
    veachSetInt(r, "width", k_size);
    veachSetInt(r, "height", k_size);
    veachSetInt(r, "spp", k_spp);
    veachSetString(r, "integrator", "pt");
    return r;
}

TEST(Snapshots, MonotoneInSamplesAndTheLastIsTheFinalImage) {
    VeachDevice device = veachNewDevice();
    VeachScene scene = veachNewSceneFromFile(device, k_cornell.c_str());
    ASSERT_NE(scene, nullptr) << veachGetLastError();
    VeachRender r = cornell_render(scene);
    ASSERT_EQ(veachSetInt(r, "snapshots", 1), VEACH_ERROR_NONE);
    Collector c;
    c.render = r;
    veachSetProgressFunction(r, take_snapshot, &c);
    ASSERT_EQ(veachRenderAsync(r), VEACH_ERROR_NONE);
    ASSERT_EQ(veachWaitRender(r, -1), VEACH_STATUS_DONE) << veachGetLastError();
    EXPECT_TRUE(c.refusals.empty());
    ASSERT_GE(c.taken.size(), 4u);  // passes of 1, 2, 4, 8, 16 ... samples
    float previous = 0;
    for (const Snapshot& s : c.taken) {
        const float n = s.samples[0];
        for (size_t i = 0; i < s.samples.size(); i += 4) ASSERT_EQ(s.samples[i], n);  // one pass in every pixel
        EXPECT_GT(n, previous);
        previous = n;
        for (float v : s.combined) ASSERT_TRUE(std::isfinite(v));
    }
    EXPECT_EQ(previous, static_cast<float>(k_spp));
    std::vector<float> final_image(k_size * k_size * 4);
    ASSERT_EQ(veachGetPass(r, "combined", final_image.data(), final_image.size() * sizeof(float), 0), VEACH_ERROR_NONE);
    EXPECT_EQ(c.taken.back().combined, final_image);
    // An earlier snapshot is another (noisier) image of the same scene, not the final one.
    EXPECT_NE(c.taken.front().combined, final_image);
    veachReleaseRender(r);
    veachReleaseScene(scene);
    veachReleaseDevice(device);
}

TEST(Snapshots, AskingDuringTheRenderKeepsTheNextPassWithoutTheOption) {
    VeachDevice device = veachNewDevice();
    VeachScene scene = veachNewSceneFromFile(device, k_cornell.c_str());
    ASSERT_NE(scene, nullptr) << veachGetLastError();
    VeachRender r = cornell_render(scene);
    veachSetInt(r, "spp", 4000);  // long enough to be asked several times from this thread
    std::vector<float> pixels(k_size * k_size * 4);
    ASSERT_EQ(veachRenderAsync(r), VEACH_ERROR_NONE);
    int got = 0;
    long long last_spp = 0;
    bool monotone = true;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    while (got < 3 && std::chrono::steady_clock::now() < deadline) {
        const VeachError e = veachGetPass(r, "samples", pixels.data(), pixels.size() * sizeof(float), 0);
        if (e == VEACH_ERROR_NONE) {
            const long long spp = static_cast<long long>(pixels[0]);
            monotone = monotone && spp >= last_spp;
            got += spp > last_spp ? 1 : 0;
            last_spp = spp;
        } else {
            EXPECT_EQ(e, VEACH_ERROR_INVALID_OPERATION);  // no pass since the first ask: nothing yet
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    veachCancelRender(r);
    veachWaitRender(r, -1);
    EXPECT_GE(got, 3);
    EXPECT_TRUE(monotone);
    veachReleaseRender(r);
    veachReleaseScene(scene);
    veachReleaseDevice(device);
}

}  // namespace
