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

#include "integrators/pixel_sample_integrator.h"

namespace veach {

struct BdptOptions {
    int only_s = -1, only_t = -1;     // `--bdpt-strategy s,t`: one strategy, unweighted
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

private:
    BdptOptions m_options;
};


}  // namespace veach
