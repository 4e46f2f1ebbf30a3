#include "denoise/denoise.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "denoise/weighted_regression.h"

namespace veach {

namespace {

// The candidate filters, weakest first: non-local means strengths k (a patch counts as similar
// while its squared difference, less the noise expected in it, is within k^2 times that noise).
// Index 0 of a choice is the unfiltered image, so candidate i is choice i + 1.
constexpr std::array<float, 2> k_strengths = {0.5f, 1.0f};
static_assert(k_strengths.size() <= WindowRegression::k_max_strengths);

// Rows per task: each strip computes its patch distances once for all its pixels.
constexpr int k_strip_rows = 8;

// The noise variance of a half's pixel from the two halves' difference: for independent
// estimates of one value E[(A - B)^2] = var A + var B = 2 var(half), so (A - B)^2 / 2 is an
// unbiased but single-sample estimate, averaged over the (2r + 1)^2 box. The difference has mean
// zero even across an edge (both halves estimate the same pixel), so the box mixes only the noise
// levels of neighbours.
std::vector<float> half_variance(const std::vector<float>& a, const std::vector<float>& b, int w, int h, int r) {
    std::vector<float> d2(a.size());
    for (size_t i = 0; i < a.size(); ++i) {
        const float d = a[i] - b[i];
        d2[i] = 0.5f * d * d;
    }
    return box_filter(d2, w, h, 3, r);
}

}  // namespace

size_t denoise_scratch_bytes(int width, int height) {
    const size_t n = static_cast<size_t>(std::max(width, 0)) * static_cast<size_t>(std::max(height, 0));
    // halves (2 x 3), variance (3), features (9), per candidate two filtered halves (2 x 3) and
    // an error (1), the unfiltered error (1), the output (3) and the choice (1 byte); floats.
    // Besides, each worker thread holds two strips of patch distances: (2 window + 1)^2 x
    // k_strip_rows x width floats each.
    return n * sizeof(float) * (6 + 3 + 9 + k_strengths.size() * 7 + 1 + 3) + n;
}

DenoiseResult denoise(const DenoiseInput& in, const DenoiseSettings& settings) {
    if (in.width < 1 || in.height < 1 || !in.half_a || !in.half_b)
        throw std::invalid_argument("denoise: an image of at least 1x1 with both halves is needed");
    const int w = in.width, h = in.height;
    const size_t n = static_cast<size_t>(w) * h;
    auto finite_copy = [n](const float* src, size_t per_pixel) {
        std::vector<float> out(src, src + n * per_pixel);
        for (float& v : out)
            if (!std::isfinite(v)) v = 0.0f;
        return out;
    };
    const std::vector<float> a = finite_copy(in.half_a, 3), b = finite_copy(in.half_b, 3);
    std::vector<float> var;
    if (!in.variance || in.variance_is_partial) var = half_variance(a, b, w, h, 1);
    if (in.variance) {
        const std::vector<float> given = finite_copy(in.variance, 3);
        if (var.empty())
            var = given;
        else
            for (size_t i = 0; i < var.size(); ++i) var[i] = std::max(var[i], given[i]);
    }

    Features features;
    features.values.assign(n * Features::k_channels, 0.0f);
    auto add_features = [&](const float* src, int first) {
        if (!src) return;
        for (size_t i = 0; i < n; ++i)
            for (int c = 0; c < 3; ++c) {
                const float v = src[i * 3 + c];
                features.values[i * Features::k_channels + first + c] = std::isfinite(v) ? v : 0.0f;
            }
    };
    add_features(in.albedo, 0);
    add_features(in.normal, 3);
    add_features(in.position, 6);

    const int radius = std::max(0, settings.window_radius), patch = std::max(0, settings.patch_radius);
    const size_t candidates = k_strengths.size();
    float inv_k2[k_strengths.size()];
    for (size_t c = 0; c < candidates; ++c) inv_k2[c] = 1.0f / (k_strengths[c] * k_strengths[c]);
    // Per candidate: each half fitted with the weights of the other.
    std::vector<std::vector<float>> fit_a(candidates), fit_b(candidates), error(candidates + 1);
    for (size_t c = 0; c < candidates; ++c) {
        fit_a[c].resize(n * 3);
        fit_b[c].resize(n * 3);
    }
    const int strips = (h + k_strip_rows - 1) / k_strip_rows;
    // Scratch kept per thread: a strip's distances are megabytes, allocated (and the pages
    // faulted in) once per thread rather than once per strip. It holds no result.
    struct Scratch {
        PatchDistances from_a, from_b;
        WindowRegression regression;
    };
    tbb::enumerable_thread_specific<Scratch> scratch([&] {
        return Scratch{PatchDistances(w, h, radius, patch), PatchDistances(w, h, radius, patch), {}};
    });
    tbb::parallel_for(tbb::blocked_range<int>(0, strips, 1), [&](const tbb::blocked_range<int>& range) {
        Scratch& local = scratch.local();
        PatchDistances& from_a = local.from_a;
        PatchDistances& from_b = local.from_b;
        WindowRegression& regression = local.regression;
        for (int strip = range.begin(); strip < range.end(); ++strip) {
            const int y0 = strip * k_strip_rows, y1 = std::min(h, y0 + k_strip_rows);
            from_a.compute(a.data(), var.data(), y0, y1);
            from_b.compute(b.data(), var.data(), y0, y1);
            for (int y = y0; y < y1; ++y) {
                for (int x = 0; x < w; ++x) {
                    const size_t i = static_cast<size_t>(y) * w + x;
                    float* out_a[k_strengths.size()];
                    float* out_b[k_strengths.size()];
                    for (size_t c = 0; c < candidates; ++c) {
                        out_a[c] = &fit_a[c][i * 3];
                        out_b[c] = &fit_b[c][i * 3];
                    }
                    regression.fit(features, x, y, w, h, radius, a.data(), b.data(), from_b, from_a, inv_k2,
                                   static_cast<int>(candidates), out_a, out_b);
                }
            }
        }
    });
    for (size_t c = 0; c < candidates; ++c) {
        // The error of a filtered half against the other half, which is independent of its
        // data: E[(F_A - B)^2] = MSE(F_A) + var(B). Averaged over both halves.
        std::vector<float> e(n);
        for (size_t i = 0; i < n; ++i) {
            double sum = 0.0;
            for (int ch = 0; ch < 3; ++ch) {
                const size_t k = i * 3 + ch;
                const double da = fit_a[c][k] - b[k], db = fit_b[c][k] - a[k];
                sum += 0.5 * (da * da + db * db) - var[k];
            }
            e[i] = static_cast<float>(sum);
        }
        error[c + 1] = box_filter(e, w, h, 1, settings.error_radius);
    }
    // The unfiltered half's error is its variance, averaged over the same box.
    std::vector<float> e0(n);
    for (size_t i = 0; i < n; ++i) e0[i] = var[i * 3] + var[i * 3 + 1] + var[i * 3 + 2];
    error[0] = box_filter(e0, w, h, 1, settings.error_radius);

    DenoiseResult result;
    result.rgb.resize(n * 3);
    result.choice.resize(n);
    for (size_t i = 0; i < n; ++i) {
        size_t best = 0;
        for (size_t c = 1; c <= candidates; ++c)
            if (error[c][i] < error[best][i]) best = c;
        result.choice[i] = static_cast<unsigned char>(best);
        for (int ch = 0; ch < 3; ++ch) {
            const size_t k = i * 3 + ch;
            if (best == 0)
                result.rgb[k] = in.full ? in.full[k] : 0.5f * (a[k] + b[k]);
            else  // a fit may overshoot below zero at an edge; radiance cannot
                result.rgb[k] = std::max(0.0f, 0.5f * (fit_a[best - 1][k] + fit_b[best - 1][k]));
        }
    }
    return result;
}

}  // namespace veach
