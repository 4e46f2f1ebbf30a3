// Adaptive sampling (--noise TARGET): after a pilot of equal samples in every pixel, each pixel
// gets a budget of samples large enough for its estimated relative error to fall to the target;
// pixels that reach their budget take no more samples.
//
// Unbiased by construction: a pixel's budget is computed from its NEIGHBOURS' pilot samples
// only (the 3x3 window without its centre), never from its own. Each pixel's random numbers are
// keyed by (seed, pixel, sample) and independent of every other pixel's, so its sample count is
// independent of its sample values and the plain average of its samples stays an unbiased
// estimate, exactly, for any count. (Deciding from the pixel's own samples, as a stopping rule
// on the running estimate does, correlates the count with the values: e.g. stopping when the
// samples so far happen to agree favours low estimates on skewed pixels.) The neighbours stand in
// for the pixel because noise varies smoothly across most of an image; the largest budget in the
// window is taken, so an edge between a smooth and a noisy region gets the noisy side's budget.
//
// The error measure, per pixel with channel means mu_c and per-sample standard deviations
// sigma_c: mu = mean of mu_c, sigma = mean of sigma_c (an upper bound of the standard deviation
// of the channel average), and the relative error of an n-sample mean is sigma / (sqrt(n) d)
// with d = max(mu, 0.001): relative error, as the target promises, except below a thousandth of
// scene white, where it becomes an absolute error of target x 0.001 (black pixels with a stray
// sample must not take the whole budget). The budget is n = (sigma / (target d))^2, at least the
// pilot's samples: every pixel aims at the same error (the target), which is what the user asks
// for, rather than at the allocation that minimises the image's total relMSE (n ~ sigma / d).
// (A square-root scale for dark pixels, as Cycles' threshold uses, was measured on cornell: at
// equal time it gave 20% higher relMSE than uniform sampling, the relative measure the same.)
#pragma once

#include <cstdint>
#include <vector>

#include "film/film.h"

namespace veach {

// The relative-error denominator d for a pixel of (channel-mean) value mu.
inline constexpr double k_adaptive_black = 1e-3;
double adaptive_error_scale(double mu);

// Per-pixel budgets (row-major) from the film's current sums, which must hold the same
// `pilot_spp` samples in every pixel (the budgets are at least that). target > 0. A pixel without usable neighbours (a
// 1x1 film, neighbours with fewer than two finite samples) gets UINT32_MAX: it never stops early.
std::vector<uint32_t> plan_adaptive_samples(const Film& film, double target, int pilot_spp);

}  // namespace veach
