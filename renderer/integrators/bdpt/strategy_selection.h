// Which of BDPT's strategy families (strategy_families.h) a render uses: the default integrator
// (`auto`, adaptive_bidirectional.h) asks once, before its first pass, and renders every pass with
// the answer, so each pass's estimator is unbiased given it.
//
// The rule (README "The default, auto", for the numbers behind it). A probe renders full BDPT and
// pt on a sparse grid of pixels, in two groups of samples scrambled independently, with random
// numbers of its own that no pass of the render uses, and adds nothing to the image. BDPT's
// samples keep every strategy's unweighted contribution and the MIS ratio sums of the path by
// family, which give the contribution's power-heuristic weight under any subset of the families,
// and the second moment of that subset's estimator on the path. For each candidate set (the
// emission and light-sample strategies, with or without t = 1 and the connections) it estimates
// the relative variance per sample (as the bench's relMSE weighs pixels) and the cost (the rays
// it traces) and picks the least variance x cost, a set that traces light subpaths needing a
// margin over pt. When the answer is the emission and light-sample strategies alone, the render
// is the path tracer's (the same estimator, without BDPT's vertex storage, its light samples on
// the sampler's stratified dimensions).
//
// The answer depends only on the scene, the camera, the film's size, the seed, the sampler and the
// maximum depth, never on timing, threads, the sample range or the pixels a part renders: a
// resumed render and a farm's parts make the same choice as one uninterrupted render.
#pragma once

#include <string>

#include "film/film.h"
#include "integrators/bdpt/strategy_families.h"
#include "integrators/integrator.h"

namespace veach {

struct StrategyChoice {
    StrategyMask mask = k_all_strategies;
    bool path_tracer = false;  // the emission and light-sample strategies alone: pt renders it
    // What the probe estimated per candidate (for the stats and the bench): relative variance and
    // cost (ray units) per sample, in the order of candidate_masks().
    std::vector<double> variance, cost;
};

// The candidate sets, in a fixed order.
std::vector<StrategyMask> candidate_masks();
// The families that every path of the scene needs, whatever the probe says: all of them when the
// scene has a delta light (a point, spot or sun without size) and a surface that may be smooth.
StrategyMask required_strategies(const RenderScene& rs);

// Runs the probe (in parallel on the calling thread's task arena) and applies the rule.
StrategyChoice choose_strategies(const RenderScene& rs, const RenderSettings& settings, const Film& film);

// "pt", or "bdpt:" and the families' letters (e: emission, n: light sample, c: camera, j: joins).
std::string describe(const StrategyChoice& choice);

}  // namespace veach
