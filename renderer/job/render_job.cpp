#include "job/render_job.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "core/available_memory.h"
#include "core/content_hash.h"
#include "scene/scene_content_error.h"
#include "denoise/denoise.h"
#include "film/film_checkpoint.h"
#include "options/option_table.h"

namespace veach {

const Camera* select_camera(const Scene& scene, const std::string& spec) {
    if (spec.empty()) return scene.cameras.empty() ? nullptr : &scene.cameras[0];
    for (const Camera& c : scene.cameras)
        if (c.name == spec) return &c;
    char* end = nullptr;
    long index = std::strtol(spec.c_str(), &end, 10);
    if (end && *end == '\0' && index >= 0 && static_cast<size_t>(index) < scene.cameras.size())
        return &scene.cameras[static_cast<size_t>(index)];
    std::string known;
    for (size_t i = 0; i < scene.cameras.size(); ++i)
        known += (i ? ", " : "") + std::to_string(i) + " '" + scene.cameras[i].name + "'";
    throw std::invalid_argument("no camera '" + spec +
                                "' in the scene (cameras: " + (known.empty() ? std::string("none") : known) + ")");
}

namespace {

// Every hit point starts a ray, and Embree cannot take an origin past k_max_ray_coordinate: a
// scene reaching beyond it (after the front end moved a far-off scene to the origin) is refused
// before anything is built, rather than rendered with its far parts silently dropped.
void check_scene_extent(const Scene& scene, PreparedSceneCache* prepared) {
    // A sequence's cache keeps the bounds per instance: a frame visits only what moved.
    const Bounds3 b = prepared ? prepared->scene_bounds(scene) : scene.bounds();
    if (b.empty()) return;
    const float reach = std::max({std::fabs(b.lo.x), std::fabs(b.lo.y), std::fabs(b.lo.z), std::fabs(b.hi.x),
                                  std::fabs(b.hi.y), std::fabs(b.hi.z)});
    if (!(reach <= k_max_ray_coordinate)) {
        char text[32];
        std::snprintf(text, sizeof(text), "%.3g", double(reach));
        throw SceneContentError(std::string("the scene's geometry reaches ") + text +
                                    " from its centre; coordinates over 1e18 cannot be ray traced");
    }
}

// A render too large for the memory the process may still take is refused before anything is
// allocated: a 16384x16384 film needs about 4 GiB, and an OOM kill says nothing.
void check_render_memory(const Scene& scene, const RenderJobOptions& options, int width, int height) {
    const RenderMemory need = estimate_render_memory(scene, options, width, height);
    const uint64_t available = available_memory_bytes();
    if (need.total() > available) {
        auto mib = [](uint64_t b) { return std::to_string(b >> 20) + " MiB"; };
        throw std::invalid_argument("a " + std::to_string(width) + "x" + std::to_string(height) + " render needs " +
                                    mib(need.total()) + " (film " + mib(need.film) + ", texture mip levels " +
                                    mib(need.mips) + "), more than the " + mib(available) + " of memory available");
    }
}

}  // namespace

// The memory a render allocates beyond the loaded scene: the film's per-pixel sums, splats,
// adaptive-sampling plan, AOV sums, the resolved image and its passes, a checkpoint's copy of the
// state and the encoded output; then the mip pyramids textures build lazily (a third of each
// texture).
RenderMemory estimate_render_memory(const Scene& scene, const RenderJobOptions& options, int width, int height) {
    uint64_t per_pixel = sizeof(Film::PixelSums) + 3 * sizeof(double)  // sums, splats
                         + sizeof(uint32_t) + 3 * sizeof(double)       // adaptive plan, pilot splats
                         + (4 + 3 + 1) * sizeof(float)                 // resolved RGBA, variance, counts
                         + 4 * sizeof(float);                          // the encoded output
    if (options.film.aovs) per_pixel += 8 * sizeof(double) + 7 * sizeof(float);
    if (options.film.alpha) per_pixel += sizeof(double);
    // The halves and features (film.h: odd sums and weight, odd splats, feature sums: 112 bytes;
    // the odd pilot splats with a plan), and while denoising the resolved halves and features
    // (5 x 3 + 1 floats), the noisy copy and the variance (2 x 3) and the denoiser's own.
    if (options.denoise)
        per_pixel += (4 + 3 + 3) * sizeof(double) + 8 * sizeof(float) +
                     (options.render.noise_target != 0 ? 3 * sizeof(double) : 0) + (5 * 3 + 1 + 2 * 3) * sizeof(float) +
                     denoise_scratch_bytes(1, 1);
    if (options.checkpoint.write)
        per_pixel += (7 + 3 + (options.film.aovs ? 8 : 0) + (options.film.alpha ? 1 : 0)) * sizeof(double);
    if (options.snapshots) per_pixel += (4 + 3 + 1) * sizeof(float);  // the snapshot's resolved image
    RenderMemory m;
    m.film = per_pixel * static_cast<uint64_t>(width) * static_cast<uint64_t>(height);
    for (const Texture& t : scene.textures)
        if (t.mipmaps && !t.nearest)  // only what can be built: a third of the image, 8-bit levels for 8-bit images
            m.mips += (t.texels8.empty() ? t.stored_values() * sizeof(float) : t.texels8.size()) / 3;
    return m;
}

void resolve_image_size(const Scene& scene, const RenderJobOptions& options, int* width, int* height) {
    const Camera* camera = select_camera(scene, options.camera);
    *width = options.width > 0 ? options.width : 1920;
    *height = options.height > 0 ? options.height : CameraModel::default_height(camera, *width);
}

void denoise_image(FilmHalves halves, Image* image, VarianceSource variance) {
    const size_t n = static_cast<size_t>(image->width) * image->height;
    std::vector<float> noisy(n * 3);
    for (size_t i = 0; i < n; ++i)
        for (int c = 0; c < 3; ++c) noisy[i * 3 + c] = image->rgba[i * 4 + c];
    DenoiseInput in;
    in.width = image->width;
    in.height = image->height;
    in.half_a = halves.even.data();
    in.half_b = halves.odd.data();
    in.full = noisy.data();
    // A half holds half the samples: twice the variance of the whole image's pixel mean.
    std::vector<float> half_variance(image->variance.size());
    for (size_t i = 0; i < half_variance.size(); ++i) half_variance[i] = 2.0f * image->variance[i];
    if (variance != VarianceSource::none && !half_variance.empty()) in.variance = half_variance.data();
    in.variance_is_partial = variance == VarianceSource::partial;
    in.albedo = halves.albedo.data();
    in.normal = halves.normal.data();
    in.position = halves.position.data();
    const DenoiseResult r = denoise(in);
    for (size_t i = 0; i < n; ++i)
        for (int c = 0; c < 3; ++c) image->rgba[i * 4 + c] = r.rgb[i * 3 + c];  // alpha as rendered
    image->noisy = std::move(noisy);
    image->denoising_albedo = std::move(halves.albedo);
    image->denoising_normal = std::move(halves.normal);
    image->denoising_depth = std::move(halves.depth);
}

RenderResult render_scene(const Scene& scene, const RenderJobOptions& options, const RenderControl& control,
                          PreparedSceneCache* prepared, const SnapshotSink* snapshots) {
    using clock = std::chrono::steady_clock;
    const Camera* camera = select_camera(scene, options.camera);
    int width = options.width > 0 ? options.width : 1920;
    int height = options.height > 0 ? options.height : CameraModel::default_height(camera, width);
    if (width > 65536 || height > 65536) throw std::invalid_argument("image size over 65536 pixels");
    if (options.render.spp < 1) throw std::invalid_argument("spp must be at least 1");
    if (options.render.max_depth < 0) throw std::invalid_argument("max_depth must not be negative");
    const PartSettings& part = options.part;
    const int sample_end = part.sample_end > 0 ? part.sample_end : options.render.spp;
    if (part.sample_begin < 0 || part.sample_begin >= sample_end || sample_end > options.render.spp)
        throw std::invalid_argument("sample_begin:sample_end " + std::to_string(part.sample_begin) + ":" +
                                    std::to_string(sample_end) + " is not within spp " +
                                    std::to_string(options.render.spp) + " (0 <= begin < end <= spp)");
    const bool sample_range = part.sample_begin > 0 || sample_end < options.render.spp;
    if (sample_range && (options.render.noise_target != 0 || options.render.time_limit > 0))
        throw std::invalid_argument("a sample range (sample_begin, sample_end) cannot be combined with noise or time_limit");
    if (part.has_bounds && options.render.noise_target != 0)
        throw std::invalid_argument("pixelbounds cannot be combined with noise");
    // Part files hold no halves: the denoiser needs both, and a part is not an image.
    if (options.denoise && (sample_range || part.has_bounds))
        throw std::invalid_argument(
            "denoise cannot be combined with parts (sample_begin, sample_end, pixelbounds): part files do not carry "
            "the half images the denoiser needs; denoise the merged image's render instead");
    // Part files hold no coverage: a merged transparent render would come back opaque.
    if ((sample_range || part.has_bounds) && (options.render.transparent || options.film.alpha))
        throw std::invalid_argument("a transparent film cannot be rendered in parts (sample_begin, sample_end, pixelbounds)");
    if (part.has_bounds &&
        (part.x0 < 0 || part.x0 >= part.x1 || part.x1 > width || part.y0 < 0 || part.y0 >= part.y1 || part.y1 > height))
        throw std::invalid_argument("pixelbounds " + std::to_string(part.x0) + "," + std::to_string(part.x1) + "," +
                                    std::to_string(part.y0) + "," + std::to_string(part.y1) + " is not within the " +
                                    std::to_string(width) + "x" + std::to_string(height) +
                                    " image (0 <= X0 < X1 <= width, 0 <= Y0 < Y1 <= height)");
    const Tile bounds = part.has_bounds ? Tile{part.x0, part.y0, part.x1, part.y1} : Tile{0, 0, width, height};
    RenderResult result;
    // Every integrator tracks the media of KHR_materials_volume (pt, bdpt and lt alike).
    RenderSettings chosen = options.render;
    result.integrator = chosen.integrator;
    std::unique_ptr<Integrator> integrator = make_integrator(chosen);
    // Adaptive sampling stops a pixel once its own estimate has converged; light tracing's pixels
    // hold no estimate of their own (every light path lands anywhere on the film), so a noise
    // threshold does not apply there. Said, not dropped silently (a host such as Blender passes
    // Cycles' threshold whatever the integrator).
    if (chosen.noise_target > 0 && !integrator->pixels_hold_estimates())
        result.warnings.push_back("the noise threshold (adaptive sampling) does not apply to the " + chosen.integrator +
                                  " integrator, whose light paths land anywhere on the film: every pixel gets the "
                                  "full samples");

    result.camera_name = camera ? camera->name : "default";
    result.triangles = scene.triangle_count();
    check_scene_extent(scene, prepared);
    check_render_memory(scene, options, width, height);
    auto t0 = clock::now();
    RenderScene rs(prepared ? prepared->get(scene) : std::make_shared<const PreparedScene>(scene), camera, width,
                   height);
    auto t1 = clock::now();
    FilmSettings film_settings = options.film;
    film_settings.halves = film_settings.halves || options.denoise;
    auto film_ptr = std::make_shared<Film>(width, height, film_settings);
    Film& film = *film_ptr;
    RenderSettings settings = chosen;
    settings.spp = sample_end;
    RenderControl session = control;
    session.first_sample = part.sample_begin;
    session.sample_origin = part.sample_begin;
    session.bounds = bounds;
    const CheckpointSettings& cp = options.checkpoint;
    const uint64_t identity = render_settings_hash(options, result.camera_name, width, height);
    const uint64_t hash = checkpoint_key(options, result.camera_name, width, height);
    std::error_code ec;
    if (cp.resume && !cp.path.empty() && std::filesystem::exists(cp.path, ec)) {
        result.resumed_spp = read_film_checkpoint(cp.path, film, hash);
        if (result.resumed_spp < part.sample_begin)
            throw CheckpointError(cp.path + ": corrupt checkpoint (fewer samples than the part starts at)");
        // The film cannot drop samples: a checkpoint past the requested spp is the image.
        settings.spp = std::max(settings.spp, result.resumed_spp);
        session.first_sample = result.resumed_spp;
    }
    // Each camera sample traced one light path (bdpt, lt), an estimate of the whole light image:
    // splats average over the paths per pixel of the frame, which for the whole render is spp.
    auto splat_spp = [&](int spp_done) {
        const double samples = static_cast<double>(spp_done - part.sample_begin);
        return part.whole() ? spp_done
                            : samples * static_cast<double>(static_cast<uint64_t>(bounds.x1 - bounds.x0) *
                                                            static_cast<uint64_t>(bounds.y1 - bounds.y0)) /
                                  (static_cast<double>(width) * height);
    };
    const bool checkpointing = cp.write && !cp.path.empty();
    if (checkpointing || snapshots || control.pass_done) {
        auto last = clock::now();
        session.pass_done = [&, last](int spp_done) mutable {
            if (control.pass_done) control.pass_done(spp_done);
            if (snapshots && snapshots->wanted && snapshots->take && snapshots->wanted()) {
                auto snap = std::make_shared<RenderResult>();
                snap->image = film.resolve(splat_spp(spp_done));
                snap->stats.spp_done = spp_done;
                snap->camera_name = result.camera_name;
                snap->integrator = result.integrator;
                snap->resumed_spp = result.resumed_spp;
                snap->render_seconds = std::chrono::duration<double>(clock::now() - t1).count();
                snap->part.width = width, snap->part.height = height;
                snap->part.sample_begin = part.sample_begin;
                snap->part.x0 = bounds.x0, snap->part.x1 = bounds.x1, snap->part.y0 = bounds.y0, snap->part.y1 = bounds.y1;
                snapshots->take(std::move(snap));
            }
            // The finished image is written right after the last pass: no state to keep then.
            if (!checkpointing || spp_done >= settings.spp) return;
            if (std::chrono::duration<double>(clock::now() - last).count() < cp.interval_seconds) return;
            write_film_checkpoint(cp.path, film, hash, spp_done);
            last = clock::now();
        };
    }
    result.stats = render_image(rs, *integrator, settings, film, session);
    auto t2 = clock::now();
    result.build_seconds = std::chrono::duration<double>(t1 - t0).count();
    result.render_seconds = std::chrono::duration<double>(t2 - t1).count();
    PartInfo& info = result.part;
    info.identity = identity;
    info.version = VEACH_VERSION_STRING;
    info.width = width;
    info.height = height;
    info.aovs = options.film.aovs;
    info.sample_begin = part.sample_begin;
    info.sample_end = result.stats.spp_done;
    info.spp = options.render.spp;
    info.x0 = bounds.x0, info.x1 = bounds.x1, info.y0 = bounds.y0, info.y1 = bounds.y1;
    info.frame = options.frame;
    info.seed = options.render.seed;
    info.camera = result.camera_name;
    info.integrator = result.integrator;
    info.filter = options.film.filter;
    info.render_seconds = result.render_seconds;
    result.image = film.resolve(splat_spp(result.stats.spp_done));
    if (options.denoise) {
        const auto t3 = clock::now();
        // The variance pass is the camera samples': all of pt's noise, part of bdpt's (not its
        // splats), none of lt's (its pixels hold no camera samples).
        const VarianceSource variance = !film.has_splats()                      ? VarianceSource::whole
                                        : integrator->pixels_hold_estimates() ? VarianceSource::partial
                                                                              : VarianceSource::none;
        denoise_image(film.resolve_halves(splat_spp(result.stats.spp_done)), &result.image, variance);
        result.denoise_seconds = std::chrono::duration<double>(clock::now() - t3).count();
    }
    result.film = std::move(film_ptr);
    return result;
}

uint64_t render_settings_hash(const RenderJobOptions& options, const std::string& camera_name, int width, int height) {
    // The options table's identity rows (options/option_table.h), with the size and camera the
    // render resolved (a default width and the camera's aspect are the same render as asking
    // for them), then what is not an option: the version (another may sample differently: its
    // checkpoints and parts are another render), the scene's identity and the adaptive pilot.
    RenderJobOptions resolved = options;
    resolved.width = width;
    resolved.height = height;
    resolved.camera = camera_name;
    OptionTargets targets{nullptr, &resolved, nullptr, nullptr};
    HashKey key("veach-render-v3");
    key.field("version", VEACH_VERSION_STRING);
    hash_identity_options(key, OptionObject::Render, targets);
    return key.field("scene", options.checkpoint.scene_hash).field("min_spp", options.render.min_spp).value();
}

uint64_t checkpoint_key(const RenderJobOptions& options, const std::string& camera_name, int width, int height) {
    // A checkpoint holds one piece of the render: its sample start and pixels are part of its key.
    const PartSettings& part = options.part;
    const Tile b = part.has_bounds ? Tile{part.x0, part.y0, part.x1, part.y1} : Tile{0, 0, width, height};
    return HashKey("veach-checkpoint-v2")
        .field("identity", render_settings_hash(options, camera_name, width, height))
        .field("sample_begin", part.sample_begin)
        .field("x0", b.x0)
        .field("x1", b.x1)
        .field("y0", b.y0)
        .field("y1", b.y1)
        .value();
}

size_t peak_resident_bytes() {
    std::ifstream f("/proc/self/status");
    std::string line;
    while (std::getline(f, line)) {
        if (line.rfind("VmHWM:", 0) == 0)
            return static_cast<size_t>(std::strtoull(line.c_str() + 6, nullptr, 10)) * 1024;
    }
    return 0;
}

}  // namespace veach
