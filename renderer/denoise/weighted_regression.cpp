#include "denoise/weighted_regression.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace veach {

std::vector<float> box_filter(const std::vector<float>& in, int w, int h, int channels, int r) {
    std::vector<float> across(in.size()), out(in.size());
    const size_t stride = static_cast<size_t>(channels);
    tbb::parallel_for(tbb::blocked_range<int>(0, h, 8), [&](const tbb::blocked_range<int>& rows) {
        for (int y = rows.begin(); y < rows.end(); ++y) {
            for (int x = 0; x < w; ++x) {
                const int x0 = std::max(0, x - r), x1 = std::min(w - 1, x + r);
                for (size_t c = 0; c < stride; ++c) {
                    double sum = 0.0;
                    for (int qx = x0; qx <= x1; ++qx) sum += in[(static_cast<size_t>(y) * w + qx) * stride + c];
                    across[(static_cast<size_t>(y) * w + x) * stride + c] = static_cast<float>(sum / (x1 - x0 + 1));
                }
            }
        }
    });
    tbb::parallel_for(tbb::blocked_range<int>(0, h, 8), [&](const tbb::blocked_range<int>& rows) {
        for (int y = rows.begin(); y < rows.end(); ++y) {
            const int y0 = std::max(0, y - r), y1 = std::min(h - 1, y + r);
            for (int x = 0; x < w; ++x) {
                for (size_t c = 0; c < stride; ++c) {
                    double sum = 0.0;
                    for (int qy = y0; qy <= y1; ++qy) sum += across[(static_cast<size_t>(qy) * w + x) * stride + c];
                    out[(static_cast<size_t>(y) * w + x) * stride + c] = static_cast<float>(sum / (y1 - y0 + 1));
                }
            }
        }
    });
    return out;
}

void PatchDistances::compute(const float* guide, const float* var, int y0, int y1) {
    m_y0 = y0;
    m_rows = y1 - y0;
    const int side = 2 * m_window + 1, p = m_patch;
    const int margin_rows = m_rows + 2 * p, margin_cols = m_w + 2 * p;
    m_d.resize(static_cast<size_t>(side) * side * m_rows * m_w);
    m_term.resize(static_cast<size_t>(margin_rows) * margin_cols);
    m_across.resize(static_cast<size_t>(margin_rows) * m_w);
    const float inv_patch = 1.0f / static_cast<float>(3 * (2 * p + 1) * (2 * p + 1));
    for (int dy = -m_window; dy <= m_window; ++dy) {
        for (int dx = -m_window; dx <= m_window; ++dx) {
            // The terms of every pixel of the strip and its margin against its (dx, dy)
            // neighbour, both clamped to the image (a patch reaching past the border repeats it).
            for (int ty = 0; ty < margin_rows; ++ty) {
                const int ay = std::clamp(y0 - p + ty, 0, m_h - 1), by = std::clamp(y0 - p + ty + dy, 0, m_h - 1);
                const float* ga = guide + static_cast<size_t>(ay) * m_w * 3;
                const float* gb = guide + static_cast<size_t>(by) * m_w * 3;
                const float* va = var + static_cast<size_t>(ay) * m_w * 3;
                const float* vb = var + static_cast<size_t>(by) * m_w * 3;
                float* t = &m_term[static_cast<size_t>(ty) * margin_cols];
                for (int tx = 0; tx < margin_cols; ++tx) {
                    const int ax = std::clamp(tx - p, 0, m_w - 1) * 3, bx = std::clamp(tx - p + dx, 0, m_w - 1) * 3;
                    float sum = 0.0f;
                    for (int c = 0; c < 3; ++c) {
                        const float d = ga[ax + c] - gb[bx + c];
                        const float v1 = va[ax + c], v2 = vb[bx + c];
                        sum += (d * d - (v1 + std::min(v1, v2))) / (1e-10f + v1 + v2);
                    }
                    t[tx] = sum;
                }
            }
            // Summed over the patch: across, then down.
            for (int ty = 0; ty < margin_rows; ++ty) {
                const float* t = &m_term[static_cast<size_t>(ty) * margin_cols];
                float* o = &m_across[static_cast<size_t>(ty) * m_w];
                for (int x = 0; x < m_w; ++x) {
                    float sum = 0.0f;
                    for (int k = 0; k <= 2 * p; ++k) sum += t[x + k];
                    o[x] = sum;
                }
            }
            const int o = (dy + m_window) * side + (dx + m_window);
            for (int y = 0; y < m_rows; ++y) {
                float* out = &m_d[(static_cast<size_t>(o) * m_rows + y) * m_w];
                for (int x = 0; x < m_w; ++x) {
                    float sum = 0.0f;
                    for (int k = 0; k <= 2 * p; ++k) sum += m_across[static_cast<size_t>(y + k) * m_w + x];
                    out[x] = sum * inv_patch;
                }
            }
        }
    }
}

void WindowRegression::fit(const Features& f, int x, int y, int w, int h, int r, const float* a, const float* b,
                           const PatchDistances& from_b, const PatchDistances& from_a, const float* inv_k2,
                           int strengths, float* const* out_a, float* const* out_b) {
    const int ns = std::min(strengths, k_max_strengths);
    std::memset(m_sums, 0, sizeof(float) * k_packed * 2 * ns);
    const float* center = &f.values[(static_cast<size_t>(y) * w + x) * Features::k_channels];
    float xq[k_terms];
    xq[0] = 1.0f;
    // A neighbour's terms: x x^T's upper triangle and x y^T for each half's colour.
    alignas(32) float terms_a[k_packed], terms_b[k_packed];
    // Per fit, the range of the colours it leaned on (weight over 0.1): a first-order fit can
    // overshoot at an edge no feature explains, and is kept within what it saw.
    float lo[2 * k_max_strengths][3], hi[2 * k_max_strengths][3];
    for (int s = 0; s < 2 * ns; ++s)
        for (int c = 0; c < 3; ++c) lo[s][c] = INFINITY, hi[s][c] = -INFINITY;
    const int y0 = std::max(0, y - r), y1 = std::min(h - 1, y + r);
    const int x0 = std::max(0, x - r), x1 = std::min(w - 1, x + r);
    for (int qy = y0; qy <= y1; ++qy) {
        for (int qx = x0; qx <= x1; ++qx) {
            const float db = from_b.at(x, y, qx - x, qy - y), da = from_a.at(x, y, qx - x, qy - y);
            float weights[2 * k_max_strengths];
            bool any = false;
            for (int s = 0; s < ns; ++s) {
                weights[2 * s] = db <= 0.0f ? 1.0f : std::exp(-db * inv_k2[s]);
                weights[2 * s + 1] = da <= 0.0f ? 1.0f : std::exp(-da * inv_k2[s]);
                any = any || weights[2 * s] > 1e-6f || weights[2 * s + 1] > 1e-6f;
            }
            // Weights this small change a fit by less than float rounding of its value.
            if (!any) continue;
            const size_t q = static_cast<size_t>(qy) * w + qx;
            const float* fq = &f.values[q * Features::k_channels];
            for (int j = 0; j < Features::k_channels; ++j) xq[j + 1] = fq[j] - center[j];
            int k = 0;
            for (int i = 0; i < k_terms; ++i)
                for (int j = i; j < k_terms; ++j) terms_a[k++] = xq[i] * xq[j];
            for (int i = 0; i < k_terms; ++i)
                for (int c = 0; c < 3; ++c) {
                    terms_a[k_upper + i * 3 + c] = xq[i] * a[q * 3 + c];
                    terms_b[k_upper + i * 3 + c] = xq[i] * b[q * 3 + c];
                }
            for (int s = 0; s < 2 * ns; ++s) {
                const float wq = weights[s];
                if (!(wq > 1e-6f)) continue;
                float* sums = m_sums[s];
                for (int i = 0; i < k_upper; ++i) sums[i] += wq * terms_a[i];
                const float* t = (s & 1) ? terms_b : terms_a;
                for (int i = k_upper; i < k_packed; ++i) sums[i] += wq * t[i];
                if (wq > 0.1f) {
                    const float* yq = (s & 1) ? &b[q * 3] : &a[q * 3];
                    for (int c = 0; c < 3; ++c) {
                        lo[s][c] = std::min(lo[s][c], yq[c]);
                        hi[s][c] = std::max(hi[s][c], yq[c]);
                    }
                }
            }
        }
    }
    float floors[Features::k_channels];
    for (int j = 0; j < Features::k_channels; ++j) floors[j] = f.floor(center, j);
    for (int s = 0; s < ns; ++s) {
        solve(m_sums[2 * s], floors, out_a[s]);
        solve(m_sums[2 * s + 1], floors, out_b[s]);
        for (int c = 0; c < 3; ++c) {  // the pixel itself always counts (weight 1): the range is not empty
            out_a[s][c] = std::clamp(out_a[s][c], lo[2 * s][c], hi[2 * s][c]);
            out_b[s][c] = std::clamp(out_b[s][c], lo[2 * s + 1][c], hi[2 * s + 1][c]);
        }
    }
}

void WindowRegression::solve(const float* sums, const float* floors, float* out) {
    // Unpacked: the full symmetric matrix and the right-hand sides.
    double full[k_terms][k_terms], right[k_terms][3];
    for (int i = 0, k = 0; i < k_terms; ++i)
        for (int j = i; j < k_terms; ++j, ++k) full[i][j] = full[j][i] = sums[k];
    for (int i = 0; i < k_terms; ++i)
        for (int c = 0; c < 3; ++c) right[i][c] = sums[k_upper + i * 3 + c];
    const double total = full[0][0];  // > 0: the pixel's own weight is 1
    // Which slopes are fitted, and their scale: the weighted spread of the feature about the
    // pixel's value over the window.
    int kept[k_terms], nk = 0;
    double scale[k_terms];
    kept[nk] = 0;
    scale[nk++] = 1.0;
    for (int j = 1; j < k_terms; ++j) {
        const double spread = std::sqrt(std::max(0.0, full[j][j]) / total);
        if (spread > floors[j - 1]) {
            kept[nk] = j;
            scale[nk++] = spread;
        }
    }
    // The normal equations on unit-spread columns, with a small ridge on the slopes only (the
    // constant term, the answer, is not pulled toward zero).
    constexpr double k_ridge = 1e-3;
    double m[k_terms][k_terms], rhs[k_terms][3];
    for (int i = 0; i < nk; ++i) {
        for (int j = 0; j < nk; ++j) m[i][j] = full[kept[i]][kept[j]] / (scale[i] * scale[j]);
        if (i > 0) m[i][i] += k_ridge * total;
        for (int c = 0; c < 3; ++c) rhs[i][c] = right[kept[i]][c] / scale[i];
    }
    // Cholesky factorisation m = L L^T in place (lower triangle).
    for (int j = 0; j < nk; ++j) {
        double d = m[j][j];
        for (int k = 0; k < j; ++k) d -= m[j][k] * m[j][k];
        if (!(d > 1e-9 * total)) {  // degenerate: the weighted mean
            for (int c = 0; c < 3; ++c) out[c] = static_cast<float>(right[0][c] / total);
            return;
        }
        m[j][j] = std::sqrt(d);
        for (int i = j + 1; i < nk; ++i) {
            double v = m[i][j];
            for (int k = 0; k < j; ++k) v -= m[i][k] * m[j][k];
            m[i][j] = v / m[j][j];
        }
    }
    for (int c = 0; c < 3; ++c) {
        double z[k_terms];
        for (int i = 0; i < nk; ++i) {
            double v = rhs[i][c];
            for (int k = 0; k < i; ++k) v -= m[i][k] * z[k];
            z[i] = v / m[i][i];
        }
        for (int i = nk - 1; i >= 0; --i) {
            double v = z[i];
            for (int k = i + 1; k < nk; ++k) v -= m[k][i] * z[k];
            z[i] = v / m[i][i];
        }
        out[c] = static_cast<float>(z[0]);
    }
}

}  // namespace veach
