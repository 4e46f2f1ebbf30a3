// Integrators and the driver that runs them: TBB over 16x16 tiles inside a task_arena sized to
// the caller's thread count, in progressive passes of samples so that a time limit or a cancel
// stops at a clean point. Randomness is keyed by (seed, pixel, sample index), so the image does
// not depend on the thread count or on scheduling.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "core/sobol_sampler.h"
#include "film/film.h"
#include "integrators/render_scene.h"

namespace veach {

struct RenderSettings {
    int spp = 64;
    double time_limit = 0;  // seconds, 0 = none: stop at whichever of spp and time comes first
    uint64_t seed = 0;
    int max_depth = 64;                        // maximum number of scattering events on a path
    int threads = 0;                           // 0 = the CPUs the process may use (core/available_cpus)
    std::string integrator = "auto";           // auto (bdpt's strategies as the scene needs), bdpt, pt or lt
    int bdpt_s = -1, bdpt_t = -1;              // bdpt: render only strategy (s, t), unweighted
    SamplerKind sampler = SamplerKind::Sobol;  // Owen-scrambled Sobol pairs, or independent
    // Adaptive sampling (film/adaptive_sampling.h): 0 = off; else the relative error at which a
    // pixel stops taking samples (spp stays the most any pixel takes). After a pilot of min_spp
    // samples in every pixel, each pixel gets a budget from its neighbours' pilot noise. Ignored
    // by lt, whose pixels hold no camera-sample values to judge (every contribution is a splat).
    float noise_target = 0;
    int min_spp = 0;  // samples of the pilot; 0 = automatic (16)
    // Cycles' Film > Transparent: a camera ray that escapes sees no light at infinity (the
    // environment and sun discs still light the scene through every other ray), so background
    // pixels are black; the film's alpha (FilmSettings::alpha) says how much of each pixel is covered.
    bool transparent = false;
};

struct Tile {
    int x0, y0, x1, y1;
};

struct RenderControl {
    // Called on the calling thread after each pass: fraction done in [0, 1], seconds left.
    std::function<void(double fraction, double eta_seconds)> progress;
    const std::atomic<bool>* cancel = nullptr;  // set from anywhere to stop soon
    // Resuming: the film already holds samples [0, first_sample) of every pixel (a checkpoint;
    // with adaptive sampling, [0, min(first_sample, its budget)), the budgets in the film);
    // rendering continues with sample index first_sample, so the sums equal an uninterrupted run.
    int first_sample = 0;
    // Called on the calling thread after each complete pass, while no tile renders (the film is
    // consistent: every pixel holds exactly `spp_done` samples, or its adaptive budget if
    // smaller): the moment to checkpoint.
    std::function<void(int spp_done)> pass_done;
    // A part of a render (film/film_part.h): the sample index it starts at (progress and camera
    // sample counts start there), and the pixels to render; an empty rectangle: the whole film.
    int sample_origin = 0;
    Tile bounds{0, 0, 0, 0};
};

struct RenderStats {
    uint64_t camera_samples = 0;
    uint64_t rays = 0;
    uint64_t nonfinite_samples = 0;
    int spp_done = 0;     // samples per pixel completed in every pixel (adaptive: or its budget)
    double mean_spp = 0;  // camera samples per pixel actually taken, averaged over the image
    double seconds = 0;
    bool cancelled = false;
    int threads = 0;  // the worker threads the render ran on
    std::string strategies;  // what the default integrator chose (Integrator::strategies)
};

// Per-thread counters, merged once per tile.
struct ThreadStats {
    uint64_t rays = 0;
    uint64_t nonfinite = 0;
};

// What the driver (render_image) asks of an integrator. Integrators that start their paths at
// the camera derive from PixelSampleIntegrator (pixel_sample_integrator.h), which owns the pixel x
// sample loop, and write only the estimate of one pixel sample.
class Integrator {
public:
    virtual ~Integrator() = default;
    // Renders samples [sample_begin, sample_end) of every pixel in `tile` into the film, on any
    // worker thread, tiles concurrently. With adaptive sampling the driver passes one-row runs of
    // pixels that share a sample range.
    virtual void render_tile(const RenderScene& rs, const Tile& tile, uint32_t sample_begin, uint32_t sample_end,
                             Film& film, ThreadStats& stats) const = 0;
    // Called on the driver's thread before and after each pass of samples [begin, end), while no
    // tile renders: where a structure every tile of a pass shares is built or updated (a
    // light-vertex cache, a guiding distribution). Nothing by default.
    virtual void begin_pass(const RenderScene& rs, uint32_t begin, uint32_t end, Film& film) {}
    virtual void end_pass(const RenderScene& rs, uint32_t begin, uint32_t end, Film& film) {}
    // Whether each pixel's camera samples carry its estimate (false when every contribution is a
    // splat): adaptive sampling judges pixels by them, and is skipped otherwise.
    virtual bool pixels_hold_estimates() const { return true; }
    // What an integrator that chooses its strategies per render chose, once it has (for the
    // stats: "pt", "bdpt:encj"); empty otherwise.
    virtual std::string strategies() const { return {}; }
};

// Throws std::invalid_argument for an unknown name.
std::unique_ptr<Integrator> make_integrator(const RenderSettings& settings);
std::vector<std::string> integrator_names();

RenderStats render_image(const RenderScene& rs, Integrator& integrator, const RenderSettings& settings,
                         Film& film, const RenderControl& control = {});

}  // namespace veach
