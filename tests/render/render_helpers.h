// Rendering a scene in a test and summarising the image statistically.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <vector>

#include "job/render_job.h"

namespace veach::test {

// Sanitizer builds make rays about ten times dearer: VEACH_TEST_SPP_DIVISOR=N (make
// test-sanitize sets it) divides the statistical tests' sample counts, and their tolerances widen
// by sqrt(N), the growth of the noise.
inline int spp_divisor() {
    const char* e = std::getenv("VEACH_TEST_SPP_DIVISOR");
    int d = e ? std::atoi(e) : 1;
    return d > 1 ? d : 1;
}
inline int spp(int n) { return std::max(1, n / spp_divisor()); }
inline double tol(double t) { return t * std::sqrt(static_cast<double>(spp_divisor())); }

inline Image render(const Scene& scene, int size, int spp, const std::string& integrator = "pt", int max_depth = 64,
                    int threads = 0, uint64_t seed = 1, RenderStats* stats = nullptr, int bdpt_s = -1, int bdpt_t = -1,
                    int height = 0) {
    RenderJobOptions o;
    o.width = size;
    o.height = height > 0 ? height : size;
    o.render.bdpt_s = bdpt_s;
    o.render.bdpt_t = bdpt_t;
    o.render.spp = spp;
    o.render.integrator = integrator;
    o.render.max_depth = max_depth;
    o.render.threads = threads;
    o.render.seed = seed;
    RenderResult r = render_scene(scene, o);
    if (stats) *stats = r.stats;
    return r.image;
}

// Mean of one channel over the image.
inline double channel_mean(const Image& img, int c) {
    double sum = 0;
    for (size_t i = 0; i < img.rgba.size(); i += 4) sum += img.rgba[i + c];
    return sum / (img.rgba.size() / 4);
}

// Means of `block` x `block` pixel blocks, channel-averaged.
// Per quantity k, the mean over independent runs of runs[r][k] and its standard error (the
// runs' sample standard deviation over sqrt(runs)): what the paired z-tests compare.
struct RunEstimate {
    std::vector<double> mean, se;
};
inline RunEstimate mean_and_standard_error(const std::vector<std::vector<double>>& runs) {
    RunEstimate e;
    const double n = static_cast<double>(runs.size());
    for (size_t k = 0; k < runs[0].size(); ++k) {
        double sum = 0, sum2 = 0;
        for (const std::vector<double>& run : runs) {
            sum += run[k];
            sum2 += run[k] * run[k];
        }
        const double m = sum / n;
        e.mean.push_back(m);
        e.se.push_back(std::sqrt(std::max(0.0, (sum2 / n - m * m) * n / (n - 1)) / n));
    }
    return e;
}

inline std::vector<double> block_means(const Image& img, int block) {
    std::vector<double> out;
    for (int by = 0; by + block <= img.height; by += block)
        for (int bx = 0; bx + block <= img.width; bx += block) {
            double s = 0;
            for (int y = by; y < by + block; ++y)
                for (int x = bx; x < bx + block; ++x) {
                    const float* p = img.pixel(x, y);
                    s += (p[0] + p[1] + p[2]) / 3.0;
                }
            out.push_back(s / (block * block));
        }
    return out;
}

}  // namespace veach::test

namespace veach::test {

// How far image `x` is from image `r`, in the measures of tests/tools/image_compare.py: the
// per-channel mean ratio, and the worst relative difference of block means among blocks brighter
// than 5% of the mean block.
struct ImageComparison {
    double mean_ratio[3] = {1, 1, 1};
    double worst_block = 0;
};

inline ImageComparison compare_images(const Image& x, const Image& r, int block) {
    ImageComparison c;
    for (int ch = 0; ch < 3; ++ch) {
        double mr = channel_mean(r, ch);
        c.mean_ratio[ch] = mr > 0 ? channel_mean(x, ch) / mr : (channel_mean(x, ch) == 0 ? 1.0 : 1e9);
    }
    std::vector<double> bx = block_means(x, block), br = block_means(r, block);
    double mean = 0;
    for (double b : br) mean += b;
    mean /= br.empty() ? 1 : br.size();
    for (size_t i = 0; i < br.size(); ++i)
        if (br[i] > 0.05 * mean) c.worst_block = std::max(c.worst_block, std::fabs(bx[i] - br[i]) / br[i]);
    return c;
}

}  // namespace veach::test
