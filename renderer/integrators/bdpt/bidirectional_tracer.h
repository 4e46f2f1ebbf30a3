// Bidirectional path tracing (Veach 1997, chapter 10; Veach and Guibas 1995). For each pixel
// sample a camera subpath and a light subpath are traced, and every prefix pair (s light
// vertices, t camera vertices) is joined into a full path:
//   s = 0        the camera subpath hits an emitter;
//   s = 1        a freshly sampled point on a light (next-event estimation);
//   t = 1        a light subpath vertex connected to the camera, splatted onto the film;
//   s, t >= 2    a deterministic connection of the two subpaths' end vertices.
// Each strategy's contribution is weighted by the power heuristic over all strategies that could
// have produced the same path (Veach's multiple importance sampling), computed with the ratio
// recurrence p_{i+1}/p_i = pdf_rev/pdf_fwd of the vertex that changes sides (pbrt-v3 section
// 16.3.4), O(s + t) per strategy.
//
// Russian roulette: subpaths are terminated with probability 1 - min(1, max(beta) / max(beta_0))
// after a few vertices (beta_0 the throughput the subpath started with: 1 for the camera, the
// emitted power's scale for a light) and survivors divide their throughput by the survival
// probability, so each strategy's estimate stays unbiased. The MIS weights use the densities *without* the roulette
// factor. This is unbiased too: weights only need to sum to one over the strategies for every path, and they do,
// because every strategy evaluates the same deterministic function of the path (the roulette-free densities); only the
// weights' optimality is slightly affected.
#pragma once

#include <memory>

#include "integrators/pixel_sample_integrator.h"

namespace veach {

struct BdptOptions {
    bool light_tracing_only = false;  // `lt`: only the t = 1 strategies, unweighted
    int only_s = -1, only_t = -1;     // `--bdpt-strategy s,t`: one strategy, unweighted
};

class BidirectionalTracer;
// The loop is instantiated once, in bidirectional_tracer.cpp, where TileState is complete.
extern template class PixelSampleIntegrator<BidirectionalTracer>;

class BidirectionalTracer final : public PixelSampleIntegrator<BidirectionalTracer> {
public:
    BidirectionalTracer(const RenderSettings& settings, const BdptOptions& options)
        : PixelSampleIntegrator(settings), m_options(options) {}

    // lt's pixels hold no camera-sample values (every contribution is a splat): nothing for
    // adaptive sampling to judge.
    bool pixels_hold_estimates() const override { return !m_options.light_tracing_only; }

    struct TileState;  // subpath storage and the tracer, kept across a tile's samples
    TileState begin_tile(const RenderScene& rs, ThreadStats& stats) const;
    // Traces both subpaths of one sample, splats the light-tracing strategies and returns the
    // camera-side estimate.
    Rgb evaluate_pixel_sample(TileState& state, const RenderScene& rs, const CameraModel& camera, float fx, float fy,
                              float time, Sampler& rng, Film& film, ThreadStats& stats) const;

private:
    BdptOptions m_options;
};


}  // namespace veach
