// The multiple importance sampling weight of one bidirectional strategy (Veach 1997 chapter 10,
// Veach and Guibas 1995): the power heuristic over every strategy (s', t') in use that could have
// produced the same path, computed with the ratio recurrence p_{i+1}/p_i = pdf_rev / pdf_fwd of
// the vertex that changes sides (pbrt-v3 section 16.3.4), O(s + t) per strategy. Only the four
// vertices next to the connection have densities that depend on the strategy; they are computed
// here, the others are the subpaths' stored pdf_fwd and pdf_rev. The strategies in use are a set
// of families (strategy_families.h): a render that leaves a family out weighs over the others
// alone, so the weights of every path still sum to one over the strategies that can make it.
#pragma once

#include <vector>

#include "camera/camera_model.h"
#include "integrators/bdpt/path_vertex.h"
#include "integrators/bdpt/strategy_families.h"
#include "lights/light_set.h"

namespace veach {

// The weight of strategy (s, t): light[0..s) joined to camera[0..t), over the strategies of
// `strategies`. `sampled_light`, for s = 1, is the light point next-event estimation sampled (it
// replaces light[0]); null otherwise.
float mis_weight(const LightSet& lights, const CameraModel& camera, const std::vector<PathVertex>& light, int s,
                 const std::vector<PathVertex>& camera_path, int t, const PathVertex* sampled_light,
                 StrategyMask strategies = k_all_strategies);

// The same path's density ratios r = p(s', t') / p(s, t), squared and cubed, summed by the family of
// (s', t') (the strategy's own term, 1, left out): the weight under any set of families S
// containing (s, t)'s is 1 / (1 + the squares of S's families); the cubes give the second moment
// of S's estimator on this path (strategy_selection.cpp).
void mis_ratio_sums(const LightSet& lights, const CameraModel& camera, const std::vector<PathVertex>& light, int s,
                    const std::vector<PathVertex>& camera_path, int t, const PathVertex* sampled_light,
                    double squares[k_strategy_families], double cubes[k_strategy_families]);

}  // namespace veach
