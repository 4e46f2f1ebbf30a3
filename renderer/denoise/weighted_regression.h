// The denoiser's building blocks (denoise/denoise.h): a box average, the patch distances of
// non-local means over a strip of rows, and the weighted first-order fits of one pixel's window.
#pragma once

#include <cstddef>
#include <vector>

namespace veach {

// The average of each channel over the (2r + 1)^2 box around each pixel, the box clipped to the
// image (border pixels average fewer values). Separable; parallel over rows, the same result at
// any thread count.
std::vector<float> box_filter(const std::vector<float>& in, int w, int h, int channels, int r);

// Up to nine feature channels per pixel (albedo, normal, position), stored nine to a pixel
// (absent ones 0: a constant channel is left out of every fit).
struct Features {
    static constexpr int k_channels = 9;
    std::vector<float> values;  // 9 per pixel
    // Below this spread over a window a channel says nothing (it is constant there up to
    // rounding) and is left out of the fit rather than fitted to noise. Positions: relative to
    // their magnitude (floats are exact to about 1e-7 of it).
    float floor(const float* at_pixel, int channel) const {
        if (channel < 6) return 1e-4f;
        const float* p = at_pixel + 6;
        return 1e-4f * ((p[0] < 0 ? -p[0] : p[0]) + (p[1] < 0 ? -p[1] : p[1]) + (p[2] < 0 ? -p[2] : p[2]) + 1e-3f);
    }
};

// Non-local means patch distances for the pixels of rows [y0, y1) to every neighbour within the
// window radius: distance(x, y, dx, dy) is the mean over the patch (radius `patch`) and the three
// channels of (d^2 - (v_p + min(v_p, v_q))) / (v_p + v_q), with d the difference of the guide's
// values and v their noise variances (Rousselle et al. 2012: the variance cancellation keeps two
// noisy copies of one value near zero). A weight for strength k is exp(-max(0, distance / k^2)).
// Computed a whole offset at a time and box-filtered over the patch (the usual fast form).
class PatchDistances {
public:
    PatchDistances(int w, int h, int window, int patch) : m_w(w), m_h(h), m_window(window), m_patch(patch) {}
    void compute(const float* guide, const float* var, int y0, int y1);
    float at(int x, int y, int dx, int dy) const {
        const int o = (dy + m_window) * (2 * m_window + 1) + (dx + m_window);
        return m_d[(static_cast<size_t>(o) * m_rows + (y - m_y0)) * m_w + x];
    }

private:
    int m_w, m_h, m_window, m_patch;
    int m_y0 = 0, m_rows = 0;
    std::vector<float> m_d;        // per offset, per row of the strip, per column
    std::vector<float> m_term;     // one offset's per-pixel terms over the strip and its margin
    std::vector<float> m_across;   // the same after the horizontal box
};

// One pixel's weighted first-order regressions: over the window around (x, y), each half's
// colour fitted as an affine function of the features, weighted by the other half's patch
// distances at each candidate strength; the fits' values at the pixel itself are the outputs.
// Features are centred on the pixel, so that value is the fit's constant term; the slopes are
// scaled to unit spread and lightly ridge-regularised (collinear features, such as the three
// channels of a grey albedo, share one slope).
class WindowRegression {
public:
    static constexpr int k_terms = Features::k_channels + 1;
    static constexpr int k_max_strengths = 4;
    // out_a[s] and out_b[s]: 3 floats each, half A's and half B's fit at strength s.
    void fit(const Features& f, int x, int y, int w, int h, int r, const float* a, const float* b,
             const PatchDistances& from_b, const PatchDistances& from_a, const float* inv_k2, int strengths,
             float* const* out_a, float* const* out_b);

private:
    // The sums of a fit, packed so that adding a neighbour is one contiguous multiply-add: the
    // upper triangle of sum w x x^T (row by row), then sum w x y^T (term by term, three colours).
    static constexpr int k_upper = k_terms * (k_terms + 1) / 2;
    static constexpr int k_packed = k_upper + 3 * k_terms;
    using Sums = float[k_packed];
    static void solve(const float* sums, const float* floors, float* out);
    alignas(32) Sums m_sums[2 * k_max_strengths];
};

}  // namespace veach
