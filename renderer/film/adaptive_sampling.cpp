#include "film/adaptive_sampling.h"

#include <algorithm>
#include <cmath>

namespace veach {

double adaptive_error_scale(double mu) { return std::max(mu, k_adaptive_black); }

namespace {

// The samples pixel (x, y) alone would need, as a double (may be huge or infinite).
double samples_needed(const Film::PixelSums& p, double target) {
    const double n = p.weight;
    if (n < 2.0) return HUGE_VAL;  // no variance estimate: assume the worst
    double mu = 0.0, sigma = 0.0;
    for (int c = 0; c < 3; ++c) {
        const double mean = p.sum[c] / n;
        mu += mean / 3.0;
        sigma += std::sqrt(std::max(0.0, (p.sum_sq[c] - n * mean * mean) / (n - 1.0))) / 3.0;
    }
    if (sigma == 0.0) return 0.0;  // constant samples: any count is exact
    const double d = adaptive_error_scale(mu);
    if (!(d > 0.0)) return HUGE_VAL;
    const double r = sigma / (target * d);
    return r * r;
}

}  // namespace

std::vector<uint32_t> plan_adaptive_samples(const Film& film, double target, int pilot_spp) {
    const int w = film.width(), h = film.height();
    std::vector<double> need(static_cast<size_t>(w) * h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            need[static_cast<size_t>(y) * w + x] = samples_needed(film.pixel_sums(x, y), target);
    std::vector<uint32_t> plan(need.size());
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            double budget = -1.0;  // stays negative without neighbours
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const int nx = x + dx, ny = y + dy;
                    if ((dx == 0 && dy == 0) || nx < 0 || ny < 0 || nx >= w || ny >= h) continue;
                    budget = std::max(budget, need[static_cast<size_t>(ny) * w + nx]);
                }
            uint32_t b = UINT32_MAX;
            if (budget >= 0.0 && budget < 4.0e9)
                b = static_cast<uint32_t>(std::max(std::ceil(budget), static_cast<double>(pilot_spp)));
            plan[static_cast<size_t>(y) * w + x] = b;
        }
    }
    return plan;
}

}  // namespace veach
