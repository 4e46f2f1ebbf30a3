// One render from a loaded scene to an image: picks the camera, prepares the BVH and lights,
// runs the integrator and reports timings and stats. The C API (api/c_api*.cpp) is a thin layer
// over this, and every front end (the `veach` command included) goes through the C API.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "film/film.h"
#include "film/film_part.h"
#include "integrators/integrator.h"
#include "integrators/prepared_scene.h"
#include "scene/scene.h"

namespace veach {

// Checkpoints let a killed render resume exactly (see film/film_checkpoint.h).
struct CheckpointSettings {
    std::string path;             // the state file; empty: no checkpoints, no resume
    bool write = false;           // keep `path` up to date while rendering
    double interval_seconds = 0;  // at the first pass boundary after this long (0: every pass)
    bool resume = false;          // start from `path` when it exists
    uint64_t scene_hash = 0;      // identifies the scene's content (e.g. a hash of the input file)
};

// A piece of a render for a farm (film/film_part.h): sample indices [sample_begin, sample_end)
// of the pixels in the bounds, so that pieces rendered anywhere merge into the whole render.
struct PartSettings {
    int sample_begin = 0;
    int sample_end = 0;       // 0: spp
    bool has_bounds = false;  // false: the whole frame
    int x0 = 0, x1 = 0, y0 = 0, y1 = 0;
    bool whole() const { return sample_begin == 0 && sample_end == 0 && !has_bounds; }
};

struct RenderJobOptions {
    std::string camera;  // a camera name or index; empty = the scene's first camera
    int width = 0;       // 0 = 1920
    int height = 0;      // 0 = from the camera's aspect ratio
    RenderSettings render;
    FilmSettings film;  // pixel filter and AOV passes
    CheckpointSettings checkpoint;
    PartSettings part;
    double frame = 0;  // the animation frame, for part files' identity
    // Denoise the image (denoise/denoise.h): the film keeps its halves and features, and the
    // result's image is the denoised one, the rendered one kept as its `noisy` pass. Whole
    // renders only (part files carry no halves).
    bool denoise = false;
    bool snapshots = false;  // resolve the film at every pass boundary (SnapshotSink), not only when asked
};

struct RenderResult {
    Image image;
    RenderStats stats;
    std::string camera_name;  // "default" when the scene has none
    double build_seconds = 0;
    double render_seconds = 0;
    size_t triangles = 0;
    int resumed_spp = 0;                // samples per pixel loaded from a checkpoint
    double denoise_seconds = 0;         // denoising, after the render (0 without it)
    std::string integrator;             // the integrator that rendered (see render_scene)
    std::vector<std::string> warnings;  // said once each, for the front end to print
    std::shared_ptr<const Film> film;   // the sums behind `image` (what a part file holds)
    PartInfo part;                      // the piece of the render this is (the whole by default)
};

// Progressive snapshots: at each pass boundary (every pixel holds the pass's samples, no tile
// renders) the job asks `wanted`, and when it says yes resolves the film so far into an image
// and hands `take` a result describing it (image, spp_done, part, camera, integrator, seconds),
// as a finished render's would. Called on the rendering thread.
struct SnapshotSink {
    std::function<bool()> wanted;
    std::function<void(std::shared_ptr<const RenderResult>)> take;
};

// Throws std::invalid_argument with a one-line message when `spec` names no camera.
const Camera* select_camera(const Scene& scene, const std::string& spec);

// A hash of every setting that shapes the image (size, camera, seed, integrator, depth, filter,
// passes, sampler, adaptive noise target, the scene's content and options; numbers exactly) but
// not of spp, time limit, threads or the part of the render: a checkpoint resumes under any of
// those, and parts of one render share it (their identity).
uint64_t render_settings_hash(const RenderJobOptions& options, const std::string& camera_name, int width, int height);

// The key a checkpoint of this render (and of its part: sample start, pixel bounds) carries.
uint64_t checkpoint_key(const RenderJobOptions& options, const std::string& camera_name, int width, int height);

// Renders; throws std::invalid_argument for bad settings, CheckpointError (film/film_checkpoint.h)
// for a checkpoint that cannot be read or written.
// With `prepared`, the BVH and light tables come from (and stay in) that cache: a sequence's
// frames update them instead of building them again.
RenderResult render_scene(const Scene& scene, const RenderJobOptions& options, const RenderControl& control = {},
                          PreparedSceneCache* prepared = nullptr, const SnapshotSink* snapshots = nullptr);

// The memory a render of `options` at width x height allocates beyond the loaded scene (what the
// render checks against the memory available before it starts, and `veach info` reports).
struct RenderMemory {
    uint64_t film = 0;  // the film, its passes, a checkpoint's copy, the encoded output
    uint64_t mips = 0;  // texture mip levels built on first use
    uint64_t total() const { return film + mips; }
};
RenderMemory estimate_render_memory(const Scene& scene, const RenderJobOptions& options, int width, int height);

// The image size a render of `options` has: the width (1920 unless set) and the height (from
// the camera's aspect ratio unless set). Throws std::invalid_argument for an unknown camera.
void resolve_image_size(const Scene& scene, const RenderJobOptions& options, int* width, int* height);

// Replaces image's colour by the denoised one (alpha as it was), keeping the rendered colour as
// its `noisy` pass and the features as its denoising passes. `variance`: how much of the
// image's noise its variance pass (the camera samples') measures.
enum class VarianceSource { whole, partial, none };
void denoise_image(FilmHalves halves, Image* image, VarianceSource variance = VarianceSource::whole);

// Peak resident set size of this process in bytes (from /proc), 0 if unknown.
size_t peak_resident_bytes();

}  // namespace veach
