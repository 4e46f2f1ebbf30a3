// The denoiser as a function on buffers (denoise/denoise.h): what it must leave alone (a noise-free
// image, a constant one), that it is a pure function of its input at any thread count, and that on
// a synthetic noisy image whose texture the albedo explains it removes most of the error without
// moving the image's local means or blurring the texture's edges.
#include "denoise/denoise.h"

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>

namespace veach {
namespace {

// A scene-like test image: a checker albedo (8-pixel squares, two colours) times a smooth shading
// ramp, with unit normals and positions on a plane; `noise` the standard deviation of each
// half's Gaussian noise relative to the value (0: both halves exact).
struct Synthetic {
    int w, h;
    std::vector<float> truth, a, b, albedo, normal, position, variance;
    Synthetic(int w_, int h_, double noise, uint32_t seed) : w(w_), h(h_) {
        const size_t n = static_cast<size_t>(w) * h;
        truth.resize(n * 3), a.resize(n * 3), b.resize(n * 3), albedo.resize(n * 3), normal.resize(n * 3),
            position.resize(n * 3), variance.resize(n * 3);
        std::mt19937 rng(seed);
        std::normal_distribution<double> gauss(0.0, 1.0);
        for (int y = 0; y < h; ++y) {
            for (int x = 0; x < w; ++x) {
                const size_t i = static_cast<size_t>(y) * w + x;
                const bool dark = ((x / 8) + (y / 8)) % 2 == 1;
                const float alb[3] = {dark ? 0.1f : 0.8f, dark ? 0.1f : 0.7f, dark ? 0.12f : 0.5f};
                const double shade = 0.4 + 0.6 * x / w + 0.3 * y / h;
                for (int c = 0; c < 3; ++c) {
                    albedo[i * 3 + c] = alb[c];
                    const double v = alb[c] * shade;
                    truth[i * 3 + c] = static_cast<float>(v);
                    variance[i * 3 + c] = static_cast<float>(noise * noise * v * v);
                    a[i * 3 + c] = static_cast<float>(v * (1.0 + noise * gauss(rng)));
                    b[i * 3 + c] = static_cast<float>(v * (1.0 + noise * gauss(rng)));
                }
                normal[i * 3 + 0] = 0.0f, normal[i * 3 + 1] = 0.0f, normal[i * 3 + 2] = 1.0f;
                position[i * 3 + 0] = 0.01f * x, position[i * 3 + 1] = 0.01f * y, position[i * 3 + 2] = 2.0f;
            }
        }
    }
    DenoiseInput input() const {
        DenoiseInput in;
        in.width = w, in.height = h;
        in.half_a = a.data(), in.half_b = b.data(), in.variance = variance.data();
        in.albedo = albedo.data(), in.normal = normal.data(), in.position = position.data();
        return in;
    }
};

double rel_mse(const std::vector<float>& x, const std::vector<float>& ref) {
    double sum = 0.0;
    for (size_t i = 0; i < x.size(); ++i) sum += (x[i] - ref[i]) * (x[i] - ref[i]) / (ref[i] * ref[i] + 0.01);
    return sum / x.size();
}

std::vector<float> average(const std::vector<float>& a, const std::vector<float>& b) {
    std::vector<float> out(a.size());
    for (size_t i = 0; i < a.size(); ++i) out[i] = 0.5f * (a[i] + b[i]);
    return out;
}

TEST(Denoise, NoiseFreeInputIsReturnedUnchanged) {
    const Synthetic s(48, 40, 0.0, 1);
    const DenoiseResult r = denoise(s.input());
    ASSERT_EQ(r.rgb.size(), s.truth.size());
    for (size_t i = 0; i < r.rgb.size(); ++i) ASSERT_NEAR(r.rgb[i], s.truth[i], 1e-6f * (1.0f + s.truth[i])) << i;
}

TEST(Denoise, AConstantImageStaysConstant) {
    Synthetic s(40, 32, 0.0, 2);
    for (float& v : s.a) v = 0.37f;
    s.b = s.a;
    // Features that vary (a checker, a ramp) must not put a pattern into a constant colour.
    const DenoiseResult r = denoise(s.input());
    for (float v : r.rgb) ASSERT_NEAR(v, 0.37f, 1e-6f);
}

TEST(Denoise, TheSameImageAtAnyThreadCount) {
    const Synthetic s(64, 48, 0.5, 3);
    auto run = [&](int threads) {
        tbb::task_arena arena(threads);
        DenoiseResult r;
        arena.execute([&] { r = denoise(s.input()); });
        return r.rgb;
    };
    const std::vector<float> one = run(1), two = run(2), three = run(3);
    ASSERT_EQ(0, std::memcmp(one.data(), two.data(), one.size() * sizeof(float)));
    ASSERT_EQ(0, std::memcmp(one.data(), three.data(), one.size() * sizeof(float)));
}

// Noise of 20% per half (as a render of some 16 samples per pixel): the regression on the albedo keeps the checker
// while averaging the noise away.
TEST(Denoise, RemovesMostOfTheErrorAndKeepsTextureEdgesAndMeans) {
    const Synthetic s(96, 64, 0.2, 4);
    const DenoiseResult r = denoise(s.input());
    const std::vector<float> noisy = average(s.a, s.b);
    const double before = rel_mse(noisy, s.truth), after = rel_mse(r.rgb, s.truth);
    EXPECT_LT(after, before / 4.0) << "relMSE " << before << " -> " << after;
    // 8x8 blocks (one checker square each): the mean within 2% of the noisy image's, and the
    // error of each block's mean against the truth within 5%.
    for (int by = 0; by < s.h / 8; ++by) {
        for (int bx = 0; bx < s.w / 8; ++bx) {
            double d = 0.0, n = 0.0, t = 0.0;
            for (int y = by * 8; y < by * 8 + 8; ++y)
                for (int x = bx * 8; x < bx * 8 + 8; ++x)
                    for (int c = 0; c < 3; ++c) {
                        const size_t k = (static_cast<size_t>(y) * s.w + x) * 3 + c;
                        d += r.rgb[k], n += noisy[k], t += s.truth[k];
                    }
            EXPECT_NEAR(d / n, 1.0, 0.02) << "block " << bx << "," << by;
            EXPECT_NEAR(d / t, 1.0, 0.05) << "block " << bx << "," << by;
        }
    }
    // Edges: across every vertical checker edge the step survives (the pixels either side
    // differ as in the truth, within 10%).
    double step_truth = 0.0, step_out = 0.0;
    for (int y = 0; y < s.h; ++y)
        for (int x = 8; x < s.w; x += 8) {
            const size_t l = (static_cast<size_t>(y) * s.w + x - 1) * 3, rr = (static_cast<size_t>(y) * s.w + x) * 3;
            step_truth += std::fabs(s.truth[l] - s.truth[rr]);
            step_out += std::fabs(r.rgb[l] - r.rgb[rr]);
        }
    EXPECT_NEAR(step_out / step_truth, 1.0, 0.1);
}

// Images smaller than the window and the patches: every value finite and within the range of
// the halves (a fit never leaves the colours it saw).
TEST(Denoise, TinyImagesStayWithinTheirValues) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(0.0f, 2.0f);
    for (auto [w, h] : {std::pair{1, 1}, {2, 1}, {1, 5}, {3, 2}}) {
        const size_t n = static_cast<size_t>(w) * h * 3;
        std::vector<float> a(n), b(n), f(n);
        for (size_t i = 0; i < n; ++i) a[i] = u(rng), b[i] = u(rng), f[i] = u(rng);
        DenoiseInput in;
        in.width = w, in.height = h, in.half_a = a.data(), in.half_b = b.data();
        in.albedo = f.data(), in.normal = f.data(), in.position = f.data();
        const DenoiseResult r = denoise(in);
        const float lo = std::min(*std::min_element(a.begin(), a.end()), *std::min_element(b.begin(), b.end()));
        const float hi = std::max(*std::max_element(a.begin(), a.end()), *std::max_element(b.begin(), b.end()));
        for (float v : r.rgb) {
            ASSERT_TRUE(std::isfinite(v)) << w << "x" << h;
            EXPECT_GE(v, lo);
            EXPECT_LE(v, hi);
        }
    }
}

TEST(Denoise, RefusesAMissingHalf) {
    DenoiseInput in;
    in.width = 4, in.height = 4;
    EXPECT_THROW(denoise(in), std::invalid_argument);
}

}  // namespace
}  // namespace veach
