// The C API's renders: typed options by name, synchronous and asynchronous rendering with
// progress and cancel, passes copied into the host's buffers, and writing through the output
// driver.
//
// Cancel latency: veachCancelRender only sets an atomic flag. The tile driver
// (integrators/integrator.cpp) reads it before every 16x16 tile, so a render stops after at most
// the tiles already running finish their current pass (up to 16 samples per pixel of one tile
// per worker thread); tests/api measures it. Building the BVH is not interruptible.
#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <map>
#include <stdexcept>

#include "api/c_api_handles.h"
#include "image_io/image_module.h"
#include "output/atomic_file.h"
#include "output/display_transform.h"

using veach::capi::ApiError;
using veach::capi::guarded;
using veach::capi::invalid;

VeachRenderImpl::~VeachRenderImpl() {
    m_cancel = true;
    if (m_worker.joinable()) m_worker.join();
    veachReleaseScene(m_scene);
}

VeachError VeachRenderImpl::run() {
    m_render_thread = std::this_thread::get_id();
    struct Leave {
        std::atomic<std::thread::id>& id;
        // Only if still ours: once the status is published, the next render may have begun
        // on another thread (a synchronous render right after an asynchronous one finished).
        ~Leave() {
            std::thread::id self = std::this_thread::get_id();
            id.compare_exchange_strong(self, std::thread::id());
        }
    } leave{m_render_thread};
    veach::RenderJobOptions job;
    std::string denoise_pass;  // a pass only a denoised render has, asked for without denoising
    VeachProgressFunction progress_fn;
    void* progress_user;
    {
        std::lock_guard<std::mutex> lock(m_mutex);
        job = m_job;
        job.checkpoint.scene_hash = m_scene->m_load.identity;
        for (const std::string& p : m_output.passes)
            if (veach::pass_needs_denoise(p) && !job.denoise) denoise_pass = p;
        m_running_job = job;
        m_snapshot.reset();
        progress_fn = m_progress_fn;
        progress_user = m_progress_user;
        m_failure = VEACH_ERROR_NONE;
        m_failure_message.clear();
    }
    m_progress = 0;
    m_eta = 0;

    veach::RenderControl control;
    control.cancel = &m_cancel;
    control.progress = [&](double fraction, double eta) {
        m_progress = fraction;
        m_eta = eta;
        if (progress_fn && !progress_fn(progress_user, fraction, eta)) m_cancel = true;
    };

    // The film so far, at pass boundaries: every pass with the option "snapshots", else the next
    // one after a host asked (veachGetPass or veachWriteImage during the render).
    m_snapshot_request = false;
    veach::SnapshotSink snapshots;
    snapshots.wanted = [this, every = job.snapshots] { return m_snapshot_request.exchange(false) || every; };
    snapshots.take = [this](std::shared_ptr<const veach::RenderResult> snapshot) {
        std::lock_guard<std::mutex> lock(m_mutex);
        m_snapshot = std::move(snapshot);
    };

    VeachError outcome = VEACH_ERROR_NONE;
    std::string message;
    VeachStatus status = VEACH_STATUS_DONE;
    try {
        if (!denoise_pass.empty())
            throw std::invalid_argument("the pass '" + denoise_pass + "' needs denoising (--denoise, option 'denoise')");
        auto result = std::make_shared<veach::RenderResult>(
            veach::render_scene(m_scene->m_load.scene, job, control, &m_scene->m_prepared, &snapshots));
        // A time limit shorter than the first pass leaves no image at all: an error, never an
        // empty image presented as the render.
        if (result->stats.spp_done == 0 && !result->stats.cancelled && job.render.time_limit > 0) {
            char limit[32];
            std::snprintf(limit, sizeof(limit), "%g", job.render.time_limit);
            throw std::invalid_argument(std::string("the time limit (") + limit +
                                        " s) ran out before the first sample pass; nothing was rendered");
        }
        // A cancel that came after the last pass leaves a complete image: only fewer samples than
        // asked (or than a checkpoint already held) is a cancelled render.
        const int target = job.part.sample_end > 0 ? job.part.sample_end : job.render.spp;
        if (result->stats.cancelled && result->stats.spp_done < std::max(target, result->resumed_spp)) {
            status = VEACH_STATUS_CANCELLED;
            outcome = VEACH_ERROR_CANCELLED;
            message = "render cancelled after " + std::to_string(result->stats.spp_done) + " samples per pixel";
        } else {
            m_progress = 1;
            m_eta = 0;
        }
        std::lock_guard<std::mutex> lock(m_mutex);
        m_result = std::move(result);
        m_result_job = job;
        // A time limit may stop a render short of its samples: done, but not complete.
        m_result_complete =
            status == VEACH_STATUS_DONE && m_result->stats.spp_done >= std::max(job.render.spp, m_result->resumed_spp);
    } catch (...) {
        outcome = veach::capi::code_of_current_exception(message);
        status = VEACH_STATUS_FAILED;
        std::lock_guard<std::mutex> lock(m_mutex);
        m_failure = outcome;
        m_failure_message = message;
    }
    {
        std::lock_guard<std::mutex> lock(m_scene->m_mutex);
        --m_scene->m_renders_running;  // claim() counted this render
    }
    if (status == VEACH_STATUS_FAILED)
        m_scene->m_device->report(outcome, message);
    else if (status == VEACH_STATUS_CANCELLED)
        veach::capi::set_last_error(outcome, message);
    {
        // Publish under the mutex so that a waiter cannot miss the notification.
        std::lock_guard<std::mutex> lock(m_mutex);
        m_status = status;
        m_snapshot.reset();  // the result is the image now
    }
    m_finished.notify_all();
    return outcome;
}

namespace {

VeachDeviceImpl* device_of(VeachRender render) { return render ? render->m_scene->m_device : nullptr; }

void check_render(VeachRender render, const char* function) {
    if (!render) throw invalid(std::string(function) + ": null render");
}

void check_not_running(VeachRender render, const char* function) {
    if (render->m_status == VEACH_STATUS_RUNNING)
        throw ApiError{VEACH_ERROR_INVALID_OPERATION, std::string(function) + ": a render is running"};
}

constexpr long long k_int_max = std::numeric_limits<int>::max();

// What a render reports once it ran, read-only; its options are the options table's render rows.
const veach::capi::ResultNames k_results{
    "option",
    veach::OptionObject::Render,
    {"result_width", "result_height", "result_spp", "result_resumed_spp", "result_complete", "result_camera_samples",
     "result_rays", "result_nonfinite_samples", "result_threads", "estimated_memory_bytes"},
    {"progress", "eta_seconds", "render_seconds", "build_seconds", "denoise_seconds"},
    {"result_camera", "result_integrator", "result_strategies", "result_warnings"}};

const veach::OptionSpec* option(const char* name, veach::OptionKind wanted) {
    return veach::capi::lookup_option(k_results, name, wanted);
}

// Sets a render row (the render's mutex held): checked and stored by the options table.
void set_render_option(VeachRender render, const veach::OptionSpec* spec, const char* name,
                       const veach::OptionValue& value) {
    if (!spec) throw invalid("option '" + std::string(name) + "' is read-only");
    veach::OptionTargets targets{nullptr, &render->m_job, &render->m_output, &render->m_scene->m_load.scene};
    try {
        veach::set_option(*spec, targets, value);
    } catch (const std::invalid_argument& e) {
        throw invalid(e.what());
    }
}

veach::OptionValue get_render_option(VeachRender render, const veach::OptionSpec& spec) {
    veach::OptionTargets targets{nullptr, &render->m_job, &render->m_output, &render->m_scene->m_load.scene};
    return veach::get_option(spec, targets);
}

std::string join(const std::vector<std::string>& items, const char* separator) {
    std::string out;
    for (const std::string& i : items) out += (out.empty() ? "" : separator) + i;
    return out;
}

bool is_part_path(const std::string& path) {
    return path.size() >= 6 && path.compare(path.size() - 6, 6, ".vpart") == 0;
}

}  // namespace

extern "C" {

VEACH_API VeachRender veachNewRender(VeachScene scene) {
    return guarded<VeachRender>(scene ? scene->m_device : nullptr, nullptr, [&] {
        if (!scene) throw invalid("veachNewRender: null scene");
        if (!scene->m_loaded)
            throw ApiError{VEACH_ERROR_INVALID_OPERATION,
                           "veachNewRender: the scene is not loaded (veachLoadSceneFile)"};
        auto* r = new VeachRenderImpl();
        veachRetainScene(scene);
        r->m_scene = scene;
        return r;
    });
}

VEACH_API VeachRender veachNewRenderFromParts(VeachDevice device, const char* const* paths, size_t count,
                                              long long expect_spp) {
    return guarded<VeachRender>(device, nullptr, [&] {
        if (!device) throw invalid("veachNewRenderFromParts: null device");
        if (!paths || count == 0) throw invalid("veachNewRenderFromParts: no part files");
        if (expect_spp < 0 || expect_spp > k_int_max)
            throw invalid("veachNewRenderFromParts: expect_spp outside [0, " + std::to_string(k_int_max) + "]");
        std::vector<std::string> files;
        for (size_t i = 0; i < count; ++i) {
            if (!paths[i] || !*paths[i]) throw invalid("veachNewRenderFromParts: empty path");
            files.emplace_back(paths[i]);
        }
        veach::MergedParts merged = veach::merge_film_parts(files, static_cast<int>(expect_spp));
        const veach::PartInfo& info = merged.info;
        auto result = std::make_shared<veach::RenderResult>();
        result->image = merged.film->resolve(merged.splat_spp);
        result->camera_name = info.camera;
        result->integrator = info.integrator;
        result->render_seconds = info.render_seconds;
        result->part = info;
        if (merged.single_piece) {
            result->stats.spp_done = info.sample_end;  // the metadata says sample_end - sample_begin
            result->film = merged.film;
        } else {
            // Several ranges or rectangles: the image holds what every pixel has.
            result->part.sample_begin = 0;
            result->part.x0 = result->part.y0 = 0;
            result->part.x1 = info.width;
            result->part.y1 = info.height;
            result->stats.spp_done = merged.min_spp;
        }
        result->stats.camera_samples = 0;
        for (int y = 0; y < info.height; ++y)
            for (int x = 0; x < info.width; ++x)
                result->stats.camera_samples += static_cast<uint64_t>(merged.film->pixel_sums(x, y).weight);

        // A render of no scene, holding the merged result: written like any other, never rendered.
        auto* scene = new VeachSceneImpl();
        veachRetainDevice(device);
        scene->m_device = device;
        scene->m_source = info.scene;
        scene->m_loaded = true;
        auto* r = new VeachRenderImpl();
        r->m_scene = scene;
        r->m_from_parts = true;
        r->m_job.render.spp = info.spp;
        r->m_job.render.seed = info.seed;
        r->m_job.render.integrator = info.integrator;
        r->m_job.film.filter = info.filter;
        r->m_job.film.aovs = info.aovs;
        r->m_job.width = info.width;
        r->m_job.height = info.height;
        r->m_result_job = r->m_job;
        r->m_result = std::move(result);
        r->m_result_complete = merged.min_spp >= info.spp;
        r->m_status = VEACH_STATUS_DONE;
        return r;
    });
}

VEACH_API void veachRetainRender(VeachRender render) {
    if (render) render->retain();
}

VEACH_API void veachReleaseRender(VeachRender render) {
    if (render && render->release()) delete render;
}

VEACH_API VeachError veachSetInt(VeachRender render, const char* name, long long value) {
    return guarded<VeachError>(device_of(render), VEACH_ERROR_INVALID_ARGUMENT, [&] {
        check_render(render, "veachSetInt");
        const veach::OptionSpec* spec = option(name, veach::OptionKind::Int);
        check_not_running(render, "veachSetInt");
        std::lock_guard<std::mutex> lock(render->m_mutex);
        set_render_option(render, spec, name, veach::OptionValue::of_int(value));
        return VEACH_ERROR_NONE;
    });
}

VEACH_API VeachError veachSetFloat(VeachRender render, const char* name, double value) {
    return guarded<VeachError>(device_of(render), VEACH_ERROR_INVALID_ARGUMENT, [&] {
        check_render(render, "veachSetFloat");
        const veach::OptionSpec* spec = option(name, veach::OptionKind::Float);
        check_not_running(render, "veachSetFloat");
        std::lock_guard<std::mutex> lock(render->m_mutex);
        set_render_option(render, spec, name, veach::OptionValue::of_float(value));
        return VEACH_ERROR_NONE;
    });
}

VEACH_API VeachError veachSetString(VeachRender render, const char* name, const char* value) {
    return guarded<VeachError>(device_of(render), VEACH_ERROR_INVALID_ARGUMENT, [&] {
        check_render(render, "veachSetString");
        const veach::OptionSpec* spec = option(name, veach::OptionKind::String);
        check_not_running(render, "veachSetString");
        std::lock_guard<std::mutex> lock(render->m_mutex);
        set_render_option(render, spec, name, veach::OptionValue::of_string(value ? value : ""));
        return VEACH_ERROR_NONE;
    });
}

VEACH_API VeachError veachGetInt(VeachRender render, const char* name, long long* value) {
    return guarded<VeachError>(device_of(render), VEACH_ERROR_INVALID_ARGUMENT, [&] {
        check_render(render, "veachGetInt");
        const veach::OptionSpec* spec = option(name, veach::OptionKind::Int);
        if (!value) throw invalid("veachGetInt: null value pointer");
        std::string n = name;
        std::lock_guard<std::mutex> lock(render->m_mutex);
        if (spec) {
            *value = get_render_option(render, *spec).i;
            return VEACH_ERROR_NONE;
        }
        // While a render runs, its results are the film so far (the last snapshot, if any).
        const bool running = render->m_status == VEACH_STATUS_RUNNING;
        const veach::RenderResult* r = running ? render->m_snapshot.get() : render->m_result.get();
        if (n == "result_width")
            *value = r ? r->image.width : 0;
        else if (n == "result_height")
            *value = r ? r->image.height : 0;
        else if (n == "result_spp")
            *value = r ? r->stats.spp_done - r->part.sample_begin : 0;  // the samples each pixel holds
        else if (n == "result_resumed_spp")
            *value = r ? r->resumed_spp : 0;
        else if (n == "result_complete")
            *value = r && !running && render->m_result_complete ? 1 : 0;
        else if (n == "result_camera_samples")
            *value = r ? static_cast<long long>(r->stats.camera_samples) : 0;
        else if (n == "result_rays")
            *value = r ? static_cast<long long>(r->stats.rays) : 0;
        else if (n == "result_nonfinite_samples")
            *value = r ? static_cast<long long>(r->stats.nonfinite_samples) : 0;
        else if (n == "result_threads")
            *value = r ? r->stats.threads : 0;
        else if (n == "estimated_memory_bytes") {
            // What a render with the current options would allocate beyond the scene.
            int width = 0, height = 0;
            const veach::Scene& scene = render->m_scene->m_load.scene;
            veach::resolve_image_size(scene, render->m_job, &width, &height);
            *value = static_cast<long long>(veach::estimate_render_memory(scene, render->m_job, width, height).total());
        }
        return VEACH_ERROR_NONE;
    });
}

VEACH_API VeachError veachGetFloat(VeachRender render, const char* name, double* value) {
    return guarded<VeachError>(device_of(render), VEACH_ERROR_INVALID_ARGUMENT, [&] {
        check_render(render, "veachGetFloat");
        const veach::OptionSpec* spec = option(name, veach::OptionKind::Float);
        if (!value) throw invalid("veachGetFloat: null value pointer");
        std::string n = name;
        if (n == "progress")
            *value = render->m_progress.load();
        else if (n == "eta_seconds")
            *value = render->m_eta.load();
        else {
            std::lock_guard<std::mutex> lock(render->m_mutex);
            if (spec)
                *value = get_render_option(render, *spec).f;
            else if (n == "render_seconds")
                *value = render->m_result ? render->m_result->render_seconds : 0.0;
            else if (n == "build_seconds")
                *value = render->m_result ? render->m_result->build_seconds : 0.0;
            else if (n == "denoise_seconds")
                *value = render->m_result ? render->m_result->denoise_seconds : 0.0;
        }
        return VEACH_ERROR_NONE;
    });
}

VEACH_API VeachError veachGetString(VeachRender render, const char* name, char* buffer, size_t size, size_t* length) {
    return guarded<VeachError>(device_of(render), VEACH_ERROR_INVALID_ARGUMENT, [&] {
        check_render(render, "veachGetString");
        const veach::OptionSpec* spec = option(name, veach::OptionKind::String);
        if (!buffer && size > 0) throw invalid("veachGetString: null buffer");
        std::string n = name, value;
        std::lock_guard<std::mutex> lock(render->m_mutex);
        const veach::RenderResult* r = render->m_result.get();
        if (spec)
            value = get_render_option(render, *spec).s;
        else if (n == "result_camera")
            value = r ? r->camera_name : "";
        else if (n == "result_integrator")
            value = r ? r->integrator : "";
        else if (n == "result_strategies")
            value = r ? r->stats.strategies : "";
        else if (n == "result_warnings")
            value = r ? join(r->warnings, "\n") : "";
        veach::capi::copy_string(value, buffer, size, length);
        return VEACH_ERROR_NONE;
    });
}

VEACH_API void veachSetProgressFunction(VeachRender render, VeachProgressFunction fn, void* user) {
    guarded<VeachError>(device_of(render), VEACH_ERROR_INVALID_ARGUMENT, [&] {
        check_render(render, "veachSetProgressFunction");
        check_not_running(render, "veachSetProgressFunction");
        std::lock_guard<std::mutex> lock(render->m_mutex);
        render->m_progress_fn = fn;
        render->m_progress_user = user;
        return VEACH_ERROR_NONE;
    });
}

namespace {

// Moves the render from not-running to RUNNING, atomically, so two starts cannot both win.
void claim(VeachRender render, const char* function) {
    if (render->m_from_parts)
        throw ApiError{VEACH_ERROR_INVALID_OPERATION,
                       std::string(function) + ": a render of merged parts has no scene"};
    int expected = render->m_status.load();
    do {
        if (expected == VEACH_STATUS_RUNNING)
            throw ApiError{VEACH_ERROR_INVALID_OPERATION, std::string(function) + ": a render is already running"};
    } while (!render->m_status.compare_exchange_weak(expected, VEACH_STATUS_RUNNING));
    render->m_cancel = false;
    std::lock_guard<std::mutex> lock(render->m_scene->m_mutex);  // waits for a re-pose to finish
    ++render->m_scene->m_renders_running;
}

// The render claimed by claim() is over (or never started): its scene may be posed again.
void release_scene(VeachRender render) {
    std::lock_guard<std::mutex> lock(render->m_scene->m_mutex);
    --render->m_scene->m_renders_running;
}

}  // namespace

VEACH_API VeachError veachRender(VeachRender render) {
    return guarded<VeachError>(device_of(render), VEACH_ERROR_INVALID_ARGUMENT, [&] {
        check_render(render, "veachRender");
        claim(render, "veachRender");
        // run() reports its own failures (callback + this thread's last error).
        return render->run();
    });
}

VEACH_API VeachError veachRenderAsync(VeachRender render) {
    return guarded<VeachError>(device_of(render), VEACH_ERROR_INVALID_ARGUMENT, [&] {
        check_render(render, "veachRenderAsync");
        claim(render, "veachRenderAsync");
        try {
            if (render->m_worker.joinable()) render->m_worker.join();  // the previous render, finished
            render->m_worker = std::thread([render] { render->run(); });
        } catch (...) {
            release_scene(render);
            render->m_status = VEACH_STATUS_FAILED;
            throw;
        }
        return VEACH_ERROR_NONE;
    });
}

VEACH_API VeachStatus veachWaitRender(VeachRender render, int timeout_ms) {
    return guarded<VeachStatus>(device_of(render), VEACH_STATUS_FAILED, [&] {
        check_render(render, "veachWaitRender");
        if (render->m_render_thread.load() == std::this_thread::get_id())
            throw ApiError{VEACH_ERROR_INVALID_OPERATION,
                           "veachWaitRender: called from the render's own thread (its progress or error callback); "
                           "it would wait for itself"};
        std::unique_lock<std::mutex> lock(render->m_mutex);
        auto finished = [&] { return render->m_status != VEACH_STATUS_RUNNING; };
        if (timeout_ms < 0)
            render->m_finished.wait(lock, finished);
        else
            render->m_finished.wait_for(lock, std::chrono::milliseconds(timeout_ms), finished);
        auto status = static_cast<VeachStatus>(render->m_status.load());
        if (status == VEACH_STATUS_FAILED) veach::capi::set_last_error(render->m_failure, render->m_failure_message);
        return status;
    });
}

VEACH_API VeachStatus veachGetRenderStatus(VeachRender render) {
    return render ? static_cast<VeachStatus>(render->m_status.load()) : VEACH_STATUS_FAILED;
}

VEACH_API void veachCancelRender(VeachRender render) {
    if (render) render->m_cancel = true;
}

namespace {

// SIZE_MAX for dst_bytes: the caller vouches for result_height rows (libveach 0.5's contract).
VeachError copy_pass(VeachRender render, const char* pass, float* dst, size_t dst_bytes, size_t row_stride_bytes) {
    return guarded<VeachError>(device_of(render), VEACH_ERROR_INVALID_ARGUMENT, [&] {
        check_render(render, "veachGetPass");
        std::string p = pass ? pass : "";
        if (!dst) throw invalid("veachGetPass: null destination");
        std::shared_ptr<const veach::RenderResult> result;
        {
            std::lock_guard<std::mutex> lock(render->m_mutex);
            if (render->m_status == VEACH_STATUS_RUNNING) {
                // The film so far, as resolved at a pass boundary; the next boundary resolves it anew.
                result = render->m_snapshot;
                render->m_snapshot_request = true;
                if (!result)
                    throw ApiError{VEACH_ERROR_INVALID_OPERATION,
                                   "veachGetPass: no pass has finished yet; the film so far is kept from the next "
                                   "pass boundary on (the option 'snapshots' keeps it at every one)"};
            } else
                result = render->m_result;
        }
        if (!result) throw ApiError{VEACH_ERROR_INVALID_OPERATION, "veachGetPass: nothing rendered yet"};
        const veach::Image& image = result->image;
        // Every pass leaves as 4 floats per pixel so that one buffer layout serves them all.
        const std::vector<float>* source = nullptr;
        int channels = 4;
        if (p == "combined" || p == "color")
            source = &image.rgba;
        else if (p == "depth")
            source = &image.depth, channels = 1;
        else if (p == "normal")
            source = &image.normal, channels = 3;
        else if (p == "albedo")
            source = &image.albedo, channels = 3;
        else if (p == "variance")
            source = &image.variance, channels = 3;
        else if (p == "samples")
            source = &image.sample_count, channels = 1;
        else if (p == "noisy")
            source = &image.noisy, channels = 3;
        else if (p == "denoising_normal")
            source = &image.denoising_normal, channels = 3;
        else if (p == "denoising_albedo")
            source = &image.denoising_albedo, channels = 3;
        else if (p == "denoising_depth")
            source = &image.denoising_depth, channels = 1;
        else
            throw invalid("veachGetPass: unknown pass '" + p +
                          "' (known: combined, depth, normal, albedo, variance, samples, noisy, denoising_normal, "
                          "denoising_albedo, denoising_depth)");
        const size_t pixels = static_cast<size_t>(image.width) * image.height;
        if (source->size() != pixels * channels)
            throw ApiError{VEACH_ERROR_INVALID_OPERATION,
                           "veachGetPass: pass '" + p + "' was not recorded (set the int option '" +
                               (veach::pass_needs_denoise(p) ? "denoise" : "aovs") + "' to 1)"};
        size_t row_bytes = static_cast<size_t>(image.width) * 4 * sizeof(float);
        if (row_stride_bytes == 0) row_stride_bytes = row_bytes;
        if (row_stride_bytes < row_bytes) throw invalid("veachGetPass: row stride smaller than a row");
        if (row_stride_bytes % sizeof(float) != 0) throw invalid("veachGetPass: row stride not a multiple of 4 bytes");
        // The last row needs only its own bytes, not a whole stride.
        const size_t needed = image.height > 0 ? (static_cast<size_t>(image.height) - 1) * row_stride_bytes + row_bytes : 0;
        if (dst_bytes < needed)
            throw invalid("veachGetPass: destination of " + std::to_string(dst_bytes) + " bytes, the " +
                          std::to_string(image.width) + "x" + std::to_string(image.height) + " pass needs " +
                          std::to_string(needed));
        auto* out = reinterpret_cast<unsigned char*>(dst);
        for (int y = 0; y < image.height; ++y) {
            float* row = reinterpret_cast<float*>(out + static_cast<size_t>(y) * row_stride_bytes);
            const float* in = source->data() + static_cast<size_t>(y) * image.width * channels;
            if (channels == 4) {
                std::memcpy(row, in, row_bytes);
                continue;
            }
            for (int x = 0; x < image.width; ++x) {
                const float* px = in + static_cast<size_t>(x) * channels;
                float* o = row + static_cast<size_t>(x) * 4;
                o[0] = px[0];
                o[1] = channels == 3 ? px[1] : px[0];
                o[2] = channels == 3 ? px[2] : px[0];
                o[3] = 1.0f;
            }
        }
        return VEACH_ERROR_NONE;
    });
}

}  // namespace

VEACH_API VeachError veachGetPass(VeachRender render, const char* pass, float* dst, size_t dst_bytes,
                                  size_t row_stride_bytes) {
    return copy_pass(render, pass, dst, dst_bytes, row_stride_bytes);
}

// libveach 0.5 and earlier: veachGetPass without the destination's size. Programs linked against
// those keep running on this library: their calls bind to this symbol version (VEACH_0 in
// cmake/libveach.map), while programs built from today's veach.h bind to VEACH_0.6, the checked one.
extern "C" __attribute__((visibility("default"))) VeachError compat_get_pass_without_size(VeachRender render,
                                                                                          const char* pass, float* dst,
                                                                                          size_t row_stride_bytes) {
    return copy_pass(render, pass, dst, SIZE_MAX, row_stride_bytes);
}
__asm__(".symver compat_get_pass_without_size, veachGetPass@VEACH_0");

VEACH_API VeachError veachReadImageMetadata(VeachDevice device, const char* path, char* buffer, size_t size,
                                            size_t* length) {
    return guarded<VeachError>(device, VEACH_ERROR_BAD_INPUT, [&] {
        if (!device) throw invalid("veachReadImageMetadata: null device");
        if (!path || !*path) throw invalid("veachReadImageMetadata: empty path");
        std::map<std::string, std::string> meta;
        const std::string p(path);
        if (is_part_path(p)) {
            // The keys an image of the same part would carry (veachWriteImage's rules), so that a
            // host compares a part file and an image alike.
            const veach::PartInfo info = veach::read_film_part_info(p);
            meta["veach:spp"] = std::to_string(info.sample_end - info.sample_begin);
            meta["veach:spp_requested"] = std::to_string(info.spp);
            const bool full_frame = info.x0 == 0 && info.y0 == 0 && info.x1 == info.width && info.y1 == info.height;
            if (info.sample_begin != 0 || !full_frame)
                meta["veach:samples"] = std::to_string(info.sample_begin) + ":" + std::to_string(info.sample_end);
            if (!full_frame)
                meta["veach:pixelbounds"] = std::to_string(info.x0) + "," + std::to_string(info.x1) + "," +
                                            std::to_string(info.y0) + "," + std::to_string(info.y1);
            if (!info.version.empty()) meta["Software"] = "veach " + info.version;
            meta["veach:seed"] = std::to_string(info.seed);
            meta["veach:camera"] = info.camera;
            meta["veach:integrator"] = info.integrator;
            if (!info.scene.empty()) meta["veach:scene"] = info.scene;
        } else {
            std::string error;
            if (!veach::read_image_metadata(p, meta, error)) throw ApiError{VEACH_ERROR_BAD_INPUT, error};
        }
        std::string text;
        for (auto [key, value] : meta) {
            std::replace(value.begin(), value.end(), '\n', ' ');
            std::replace(value.begin(), value.end(), '\r', ' ');
            text += (text.empty() ? "" : "\n") + key + "=" + value;
        }
        veach::capi::copy_string(text, buffer, size, length);
        return VEACH_ERROR_NONE;
    });
}

VEACH_API VeachError veachCheckOutput(VeachRender render, const char* path) {
    return guarded<VeachError>(device_of(render), VEACH_ERROR_OUTPUT, [&] {
        check_render(render, "veachCheckOutput");
        if (!path || !*path) throw invalid("veachCheckOutput: empty path");
        veach::OutputSettings settings;
        {
            std::lock_guard<std::mutex> lock(render->m_mutex);
            settings = render->m_output;
        }
        const std::string p(path);
        if (!is_part_path(p)) {
            if (!veach::is_known_image_format(p)) {
                const size_t slash = p.find_last_of('/'), dot = p.find_last_of('.');
                const bool has_ext = dot != std::string::npos && (slash == std::string::npos || dot > slash);
                throw invalid(p + ": unknown image format " +
                              (has_ext ? "'" + p.substr(dot) + "'" : std::string("(no extension)")) +
                              " (known: .exr .hdr .png .jpg .tif .vpart)");
            }
            // Every image format is encoded by the image module: opening it now makes a missing or
            // broken installation fail before the render, not after it.
            try {
                veach::image_codec();
            } catch (const veach::ImageModuleError& e) {
                throw veach::OutputError(p + ": " + e.what());
            }
            // The display transform is what veachWriteImage builds for these formats: building it
            // now finds a display, view or look the colour config lacks.
            if (!veach::is_scene_linear_format(p)) {
                try {
                    veach::DisplayTransform transform(settings.display);
                } catch (const veach::OutputError& e) {
                    throw invalid(p + ": " + e.what());
                }
            }
        }
        veach::check_writable(p);
        return VEACH_ERROR_NONE;
    });
}

VEACH_API VeachError veachWriteImage(VeachRender render, const char* path) {
    return guarded<VeachError>(device_of(render), VEACH_ERROR_OUTPUT, [&] {
        check_render(render, "veachWriteImage");
        if (!path || !*path) throw invalid("veachWriteImage: empty path");
        std::shared_ptr<const veach::RenderResult> result;
        veach::OutputSettings settings;
        veach::RenderJobOptions job;  // the options the result was rendered with
        bool complete;
        bool partial = false;
        {
            std::lock_guard<std::mutex> lock(render->m_mutex);
            if (render->m_status == VEACH_STATUS_RUNNING) {
                // A preview: the film so far, written like any image and tagged incomplete.
                result = render->m_snapshot;
                job = render->m_running_job;
                complete = false;
                partial = true;
                render->m_snapshot_request = true;
                if (!result)
                    throw ApiError{VEACH_ERROR_INVALID_OPERATION,
                                   std::string(path) + ": no pass has finished yet, nothing to write"};
            } else {
                result = render->m_result;
                job = render->m_result_job;
                complete = render->m_result_complete;
            }
            settings = render->m_output;
        }
        if (!result) throw ApiError{VEACH_ERROR_INVALID_OPERATION, "veachWriteImage: nothing rendered yet"};
        if (partial && is_part_path(path))
            throw ApiError{VEACH_ERROR_INVALID_OPERATION,
                           std::string(path) + ": a part file holds a finished render's sums, not a preview"};
        if (is_part_path(path)) {
            if (!result->film)
                throw ApiError{VEACH_ERROR_INVALID_OPERATION,
                               std::string(path) +
                                   ": these merged parts are not one sample range over one rectangle, "
                                   "which a part file holds"};
            veach::PartInfo info = result->part;
            if (info.sample_end <= info.sample_begin)
                throw ApiError{VEACH_ERROR_INVALID_OPERATION,
                               std::string(path) + ": no sample was completed, nothing to write"};
            info.scene = render->m_scene->m_source;
            veach::write_film_part(path, *result->film, info);
            return VEACH_ERROR_NONE;
        }
        auto& meta = settings.metadata;
        meta["Software"] = std::string("veach ") + VEACH_VERSION_STRING;
        if (!render->m_scene->m_source.empty()) meta["veach:scene"] = render->m_scene->m_source;
        meta["veach:camera"] = result->camera_name;
        // The samples per pixel every pixel completed: after a cancel some pixels hold one more
        // pass, which per-pixel averaging keeps unbiased.
        const veach::PartInfo& part = result->part;
        const bool full_frame =
            part.x0 == 0 && part.y0 == 0 && part.x1 == result->image.width && part.y1 == result->image.height;
        meta["veach:spp"] = std::to_string(result->stats.spp_done - part.sample_begin);
        if (part.sample_begin != 0 || !full_frame)
            meta["veach:samples"] = std::to_string(part.sample_begin) + ":" + std::to_string(result->stats.spp_done);
        if (!full_frame)
            meta["veach:pixelbounds"] = std::to_string(part.x0) + "," + std::to_string(part.x1) + "," +
                                        std::to_string(part.y0) + "," + std::to_string(part.y1);
        meta["veach:spp_requested"] = std::to_string(job.render.spp);
        meta["veach:complete"] = complete ? "yes" : "no";
        meta["veach:seed"] = std::to_string(job.render.seed);
        meta["veach:integrator"] = result->integrator;
        char filter[64];
        std::snprintf(filter, sizeof(filter), "%s %g", veach::filter_name(job.film.filter.type), job.film.filter.width);
        meta["veach:filter"] = filter;
        meta["veach:render_seconds"] = std::to_string(result->render_seconds);
        if (result->resumed_spp > 0) meta["veach:resumed_spp"] = std::to_string(result->resumed_spp);
        // Adaptive sampling stops pixels early: veach:spp is then what every pixel reached, with the
        // mean and the most any pixel took beside it (the samples pass holds each pixel's count).
        const std::vector<float>& counts = result->image.sample_count;
        if (job.render.noise_target > 0 && !counts.empty()) {
            double low = counts[0], high = counts[0], sum = 0;
            for (float n : counts) {
                low = std::min<double>(low, n);
                high = std::max<double>(high, n);
                sum += n;
            }
            char mean[32];
            std::snprintf(mean, sizeof(mean), "%.6g", sum / static_cast<double>(counts.size()));
            meta["veach:spp"] = std::to_string(static_cast<long long>(low));
            meta["veach:spp_mean"] = mean;
            meta["veach:spp_max"] = std::to_string(static_cast<long long>(high));
        }
        for (const auto& [name, value] : settings.user_attributes) meta[name] = value;
        veach::write_image(result->image, path, settings);
        return VEACH_ERROR_NONE;
    });
}

}  // extern "C"
