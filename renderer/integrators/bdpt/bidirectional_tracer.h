// Bidirectional path tracing (Veach 1997, chapter 10; Veach and Guibas 1995). For each pixel
// sample a camera subpath and a light subpath are traced, and every prefix pair (s light
// vertices, t camera vertices) is joined into a full path:
//   s = 0        the camera subpath hits an emitter;
//   s = 1        a freshly sampled point on a light (next-event estimation);
//   t = 1        a light subpath vertex connected to the camera, splatted onto the film;
//   s, t >= 2    a deterministic connection of the two subpaths' end vertices.
// Each strategy's contribution is weighted by the power heuristic over all strategies that could
// have produced the same path (mis_weight.h). The pieces live beside it: the subpaths' random walk
// (subpaths.h), the density conversions (vertex_densities.h), the t = 1 connection to the camera
// (camera_connection.h), which lt (lt/light_tracer.h) uses alone.
#pragma once

#include <memory>

#include <functional>
#include <utility>
#include <vector>

#include "integrators/bdpt/strategy_families.h"
#include "integrators/pixel_sample_integrator.h"

namespace veach {

struct BdptOptions {
    int only_s = -1, only_t = -1;  // `--bdpt-strategy s,t`: one strategy, unweighted
    // The strategy families in use, weighted over each other alone (the default integrator's
    // choice, strategy_selection.h); without the t = 1 and connection families no light subpath
    // is traced.
    StrategyMask strategies = k_all_strategies;
};

// One sample of the strategy selection's probe: every strategy's unweighted contribution with the
// path's MIS ratio sums by family (mis_ratio_sums), and the rays each part of the sample traced.
struct ProbeContribution {
    Rgb value;
    double ratio_squares[k_strategy_families] = {}, ratio_cubes[k_strategy_families] = {};
    uint8_t family = 0;
    bool splat = false;  // a t = 1 contribution, landing at film position (px, py)
    float px = 0, py = 0;
};
struct ProbeSample {
    std::vector<ProbeContribution> contributions;
    uint64_t camera_rays = 0, light_rays = 0;
    uint64_t shadow_rays[k_strategy_families] = {};
};

class BidirectionalTracer;
// The loop is instantiated once, in bidirectional_tracer.cpp, where TileState is complete.
extern template class PixelSampleIntegrator<BidirectionalTracer>;

class BidirectionalTracer final : public PixelSampleIntegrator<BidirectionalTracer> {
public:
    BidirectionalTracer(const RenderSettings& settings, const BdptOptions& options)
        : PixelSampleIntegrator(settings), m_options(options) {}

    struct TileState;  // subpath storage and the tracer, kept across a tile's samples
    TileState begin_tile(const RenderScene& rs, ThreadStats& stats) const;
    // Traces both subpaths of one sample, splats the light-tracing strategies and returns the
    // camera-side estimate.
    Rgb evaluate_pixel_sample(TileState& state, const RenderScene& rs, const CameraModel& camera, float fx, float fy,
                              float time, Sampler& rng, Film& film, ThreadStats& stats) const;
    // The strategy selection's probe (strategy_selection.h): samples [0, samples) of each pixel
    // pixels[i], i in [begin, end), with the sampler keyed by (seed, pixel, sample), every
    // strategy recorded rather than weighed and added (nothing reaches a film); visit(i, sample,
    // record) sees each.
    void probe(const RenderScene& rs, const Film& film, uint64_t seed, const std::vector<std::pair<int, int>>& pixels,
               size_t begin, size_t end, int samples,
               const std::function<void(size_t, int, const ProbeSample&)>& visit) const;

private:
    BdptOptions m_options;
};


}  // namespace veach
