// The multiple importance sampling weight of one bidirectional strategy (Veach 1997 chapter 10,
// Veach and Guibas 1995): the power heuristic over every strategy (s', t') that could have
// produced the same path, computed with the ratio recurrence p_{i+1}/p_i = pdf_rev / pdf_fwd of the
// vertex that changes sides (pbrt-v3 section 16.3.4), O(s + t) per strategy. Only the four
// vertices next to the connection have densities that depend on the strategy; they are computed
// here, the others are the subpaths' stored pdf_fwd and pdf_rev.
#pragma once

#include <vector>

#include "camera/camera_model.h"
#include "integrators/bdpt/path_vertex.h"
#include "lights/light_set.h"

namespace veach {

// The weight of strategy (s, t): light[0..s) joined to camera[0..t). `sampled_light`, for s = 1,
// is the light point next-event estimation sampled (it replaces light[0]); null otherwise.
float mis_weight(const LightSet& lights, const CameraModel& camera, const std::vector<PathVertex>& light, int s,
                 const std::vector<PathVertex>& camera_path, int t, const PathVertex* sampled_light);

}  // namespace veach
