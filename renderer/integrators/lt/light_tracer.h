// Light tracing (particle tracing with next-event connections to the camera): for each pixel
// sample one light subpath is traced and each of its vertices is joined to the camera (BDPT's
// t = 1 strategies, bdpt/camera_connection.h), unweighted, landing as splats wherever they
// project. The one path no particle can reach, a camera ray escaping to a light at infinity (a
// particle from infinity meets the pinhole with probability zero), is the pixel's own value.
// Built on BDPT's pieces: the random walk and light start (bdpt/subpaths.h).
#pragma once

#include "integrators/pixel_sample_integrator.h"

namespace veach {

class LightTracer;
// The loop is instantiated once, in light_tracer.cpp, where TileState is complete.
extern template class PixelSampleIntegrator<LightTracer>;

class LightTracer final : public PixelSampleIntegrator<LightTracer> {
public:
    explicit LightTracer(const RenderSettings& settings) : PixelSampleIntegrator(settings) {}

    // The pixels hold no camera-sample values but the escaped rays' (every other contribution is
    // a splat): nothing for adaptive sampling to judge.
    bool pixels_hold_estimates() const override { return false; }

    struct TileState;  // the light subpath's storage, kept across a tile's samples
    TileState begin_tile(const RenderScene& rs, ThreadStats& stats) const;
    // Traces one light subpath and splats its connections to the camera; returns what the camera
    // ray sees of the lights at infinity.
    Rgb evaluate_pixel_sample(TileState& state, const RenderScene& rs, const CameraModel& camera, float fx, float fy,
                              float time, Sampler& rng, Film& film, ThreadStats& stats) const;
};

}  // namespace veach
