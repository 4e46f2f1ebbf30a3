// Unidirectional path tracing with next-event estimation. Each path vertex combines two
// strategies for direct light by multiple importance sampling (power heuristic, Veach 1997
// chapter 9): a light sampled by power and a point on it, and the BSDF-sampled direction that
// happens to hit an emitter. Russian roulette by throughput keeps long paths unbiased.
#pragma once

#include "integrators/integrator.h"

namespace veach {

class PathTracer final : public Integrator {
public:
    explicit PathTracer(const RenderSettings& settings) : m_settings(settings) {}
    void render_tile(const RenderScene& rs, const Tile& tile, uint32_t sample_begin, uint32_t sample_end, Film& film,
                     ThreadStats& stats) const override;

    // Radiance arriving at the camera along one ray (exposed for tests).
    // `camera` is the sample's (at shutter time `time`): its footprint filters the first hit.
    Rgb trace(const RenderScene& rs, const CameraModel& camera, Vec3 origin, Vec3 dir, float time, class Sampler& rng,
              ThreadStats& stats) const;

private:
    RenderSettings m_settings;
};

}  // namespace veach
