// The fixture the C API tests share: a device whose error callback records what it is told, a
// small Cornell render, and reading back the combined pass.
#pragma once

#include <gtest/gtest.h>

#include <atomic>
#include <string>
#include <vector>

#include "veach/veach.h"

// A named namespace, not an anonymous one: every test file must see the one CApi class, or
// googletest refuses a suite whose tests use two fixture classes of one name.
namespace capi_test {

inline const std::string k_cornell = std::string(VEACH_EXAMPLES_DIR) + "/cornell/cornell.gltf";

struct ErrorLog {
    std::atomic<int> calls{0};
    VeachError last_code = VEACH_ERROR_NONE;
    std::string last_message;
};

inline void record_error(void* user, VeachError code, const char* message) {
    auto* log = static_cast<ErrorLog*>(user);
    log->last_code = code;
    log->last_message = message;
    ++log->calls;
}

class CApi : public ::testing::Test {
protected:
    void SetUp() override {
        m_device = veachNewDevice();
        ASSERT_NE(m_device, nullptr);
        veachSetDeviceErrorFunction(m_device, record_error, &m_errors);
    }
    void TearDown() override { veachReleaseDevice(m_device); }

    // A small render of the Cornell box: the path tracer, a fixed seed.
    VeachRender new_cornell_render(VeachScene scene, int spp = 4, long long seed = 7) {
        VeachRender r = veachNewRender(scene);
        EXPECT_EQ(veachSetInt(r, "width", 48), VEACH_ERROR_NONE);
        EXPECT_EQ(veachSetInt(r, "height", 48), VEACH_ERROR_NONE);
        EXPECT_EQ(veachSetInt(r, "spp", spp), VEACH_ERROR_NONE);
        EXPECT_EQ(veachSetInt(r, "seed", seed), VEACH_ERROR_NONE);
        EXPECT_EQ(veachSetString(r, "integrator", "pt"), VEACH_ERROR_NONE);
        return r;
    }

    static std::vector<float> combined(VeachRender r) {
        long long w = 0, h = 0;
        veachGetInt(r, "result_width", &w);
        veachGetInt(r, "result_height", &h);
        std::vector<float> px(static_cast<size_t>(w * h * 4));
        EXPECT_EQ(veachGetPass(r, "combined", px.data(), px.size() * sizeof(float), 0), VEACH_ERROR_NONE) << veachGetLastError();
        return px;
    }

    static double mean_rgb(const std::vector<float>& rgba) {
        double sum = 0;
        for (size_t i = 0; i < rgba.size(); i += 4) sum += rgba[i] + rgba[i + 1] + rgba[i + 2];
        return sum / (3.0 * static_cast<double>(rgba.size() / 4));
    }

    VeachDevice m_device = nullptr;
    ErrorLog m_errors;
};

// An error code and a last-error message that names `needle`.
#define EXPECT_REFUSED(call, code, needle)                                                                  \
    do {                                                                                                    \
        EXPECT_EQ((call), (code));                                                                          \
        EXPECT_EQ(veachGetLastErrorCode(), (code));                                                         \
        EXPECT_NE(std::string(veachGetLastError()).find(needle), std::string::npos) << veachGetLastError(); \
    } while (0)

}  // namespace capi_test

using namespace capi_test;  // NOLINT: the tests name the fixture as CApi
