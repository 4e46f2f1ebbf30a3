// Unidirectional path tracing with next-event estimation. Each path vertex combines two
// strategies for direct light by multiple importance sampling (power heuristic, Veach 1997
// chapter 9): a light sampled by power and a point on it, and the BSDF-sampled direction that
// happens to hit an emitter. Russian roulette by throughput keeps long paths unbiased.
#pragma once

#include "integrators/pixel_sample_integrator.h"

namespace veach {

class PathTracer;
// The loop is instantiated once, in path_tracer.cpp, where trace() is defined.
extern template class PixelSampleIntegrator<PathTracer>;

class PathTracer final : public PixelSampleIntegrator<PathTracer> {
public:
    explicit PathTracer(const RenderSettings& settings) : PixelSampleIntegrator(settings) {}

    struct TileState {};  // nothing kept across samples
    TileState begin_tile(const RenderScene&, ThreadStats&) const { return {}; }
    // The radiance along the camera ray through film position (fx, fy).
    Rgb evaluate_pixel_sample(TileState&, const RenderScene& rs, const CameraModel& camera, float fx, float fy,
                              float time, Sampler& rng, Film& film, ThreadStats& stats) const {
        Vec3 o, d;
        camera.generate_ray(fx, fy, &o, &d);
        return trace(rs, camera, o, d, time, rng, stats);
    }

    // Radiance arriving at the camera along one ray (exposed for tests).
    // `camera` is the sample's (at shutter time `time`): its footprint filters the first hit.
    Rgb trace(const RenderScene& rs, const CameraModel& camera, Vec3 origin, Vec3 dir, float time, class Sampler& rng,
              ThreadStats& stats) const;
};


}  // namespace veach
