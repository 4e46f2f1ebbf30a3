// The pixel x sample loop that every integrator starting its paths at the camera shares (pbrt-v4's
// ImageTileIntegrator and EvaluatePixelSample): per sample, the sampler keyed by (seed, pixel,
// sample index), a film position drawn from the pixel filter, the shutter time and the camera
// at it, the integrator's estimate, and the sample added to the film unless it is not finite or
// one of its rays was refused by the accel (dropped, counted). An integrator writes only
// evaluate_pixel_sample and, if it keeps scratch per tile, its TileState.
//
// A template over the integrator (the curiously recurring template pattern) rather than a
// virtual call per sample: the estimate is inlined into the loop as it was when each integrator
// had its own copy, so the base costs nothing per sample.
#pragma once

#include "core/sobol_sampler.h"
#include "integrators/first_hit_aovs.h"
#include "integrators/integrator.h"

namespace veach {

// Derived provides:
//   struct TileState;                                   (scratch kept across a tile's samples)
//   TileState begin_tile(const RenderScene&, ThreadStats&) const;
//   Rgb evaluate_pixel_sample(TileState&, const RenderScene&, const CameraModel& camera,
//                             float fx, float fy, float time, Sampler&, Film&, ThreadStats&) const;
template <class Derived>
class PixelSampleIntegrator : public Integrator {
public:
    explicit PixelSampleIntegrator(const RenderSettings& settings) : m_settings(settings) {}

    void render_tile(const RenderScene& rs, const Tile& tile, uint32_t sample_begin, uint32_t sample_end, Film& film,
                     ThreadStats& stats) const final;

protected:
    RenderSettings m_settings;
};

// Out of the class body, so not inline: an integrator's `extern template` keeps every includer
// from instantiating it, and its own .cpp instantiates it where the estimate is defined.
template <class Derived>
void PixelSampleIntegrator<Derived>::render_tile(const RenderScene& rs, const Tile& tile, uint32_t sample_begin,
                                                 uint32_t sample_end, Film& film, ThreadStats& stats) const {
    const Derived& self = static_cast<const Derived&>(*this);
    typename Derived::TileState state = self.begin_tile(rs, stats);
    CameraModel moving_camera = rs.camera();  // a moving camera's pose at each sample's time
    for (int y = tile.y0; y < tile.y1; ++y) {
        for (int x = tile.x0; x < tile.x1; ++x) {
            const uint64_t pixel = static_cast<uint64_t>(y) * film.width() + x;
            for (uint32_t s = sample_begin; s < sample_end; ++s) {
                Sampler rng(m_settings.sampler, m_settings.seed, pixel, s);
                auto [fx, fy] = film.sample_position(x, y, rng.next_2d());  // drawn from the pixel filter
                // One shutter time for the whole sample: the camera and every ray (a light
                // subpath's too) see the scene then.
                const float time = rs.shutter_time(rng);
                const CameraModel& camera = rs.camera_at(time, moving_camera);
                const uint64_t rejected = Accel::rejected_rays_on_this_thread();
                const Rgb l = self.evaluate_pixel_sample(state, rs, camera, fx, fy, time, rng, film, stats);
                if (!l.is_finite() || Accel::rejected_rays_on_this_thread() != rejected) {
                    ++stats.nonfinite;  // dropped, never written
                    continue;
                }
                // The denoiser's features pick a glass lobe with one more number of the sample.
                const float u_lobe = film.wants_halves() ? rng.next_1d() : 0.5f;
                add_camera_sample(film, rs, camera, x, y, fx, fy, time, l, s, u_lobe);
            }
        }
    }
}

}  // namespace veach
