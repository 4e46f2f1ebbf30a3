// The objects behind the C API's opaque handles, and the one function that turns a C++ exception
// into a VeachError. Internal to libveach: hosts see only renderer/include/veach/veach.h.
#pragma once

#include <atomic>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <type_traits>
#include <vector>

#include "integrators/prepared_scene.h"
#include "job/render_job.h"
#include "load/scene_load.h"
#include "options/option_table.h"
#include "output/image_output.h"
#include "scene/scene.h"
#include "veach/veach.h"

namespace veach::capi {

// Intrusive reference count: the C API hands out raw pointers, so the count lives in the object.
// Starts at 1 (the creator's reference).
struct RefCounted {
    std::atomic<int> m_refs{1};
    void retain() { m_refs.fetch_add(1, std::memory_order_relaxed); }
    // True when this was the last reference (the caller deletes).
    bool release() { return m_refs.fetch_sub(1, std::memory_order_acq_rel) == 1; }
};

}  // namespace veach::capi

struct VeachDeviceImpl : veach::capi::RefCounted {
    std::mutex m_mutex;  // guards the callback, which any thread may set or call
    VeachErrorFunction m_error_fn = nullptr;
    void* m_error_user = nullptr;

    // Records `message` as this thread's last error and calls the error callback.
    void report(VeachError code, const std::string& message);
};

struct VeachSceneImpl : veach::capi::RefCounted {
    VeachDeviceImpl* m_device = nullptr;  // retained

    // Before the load: options, guarded by m_mutex. The load happens once; from then on
    // everything below is immutable and renders share it read-only without locking, except for
    // a re-pose at another time (m_renders_running).
    std::mutex m_mutex;
    std::atomic<bool> m_loaded{false};
    veach::SceneLoadOptions m_options;
    std::string m_source;     // the file loaded, "" for a scene from memory
    // After the load, a scene imported with a time may be posed again at another (the scene
    // option "time"): never while a render of it runs. Renders count themselves here, under
    // m_mutex, which the re-pose holds throughout.
    int m_renders_running = 0;
    // The scene and its identity (LoadedScene::identity: a checkpoint of another file, variant or
    // environment is refused).
    veach::LoadedScene m_load;
    // The BVH and light tables of m_load.scene, built by its first render and kept: a re-pose
    // notes what it changed here, and the next render updates only that (docs/ARCHITECTURE.md
    // "Animation"). Declared after m_load, which it refers to, so that it goes first.
    veach::PreparedSceneCache m_prepared;
    ~VeachSceneImpl();
};

struct VeachRenderImpl : veach::capi::RefCounted {
    VeachSceneImpl* m_scene = nullptr;  // retained

    // Options and results, guarded by m_mutex; options change only while no render runs.
    std::mutex m_mutex;
    std::condition_variable m_finished;
    veach::RenderJobOptions m_job;
    veach::OutputSettings m_output;
    VeachProgressFunction m_progress_fn = nullptr;
    void* m_progress_user = nullptr;
    std::shared_ptr<const veach::RenderResult> m_result;  // the last finished or cancelled render
    // While a render runs: the film so far, resolved at the last pass boundary that was asked for
    // one (option "snapshots", or m_snapshot_request: a pass or image asked for during the
    // render), and the options that render runs with.
    std::shared_ptr<const veach::RenderResult> m_snapshot;
    std::atomic<bool> m_snapshot_request{false};
    veach::RenderJobOptions m_running_job;
    veach::RenderJobOptions m_result_job;                 // the options m_result was rendered with
    bool m_result_complete = false;                       // m_result has every requested sample
    VeachError m_failure = VEACH_ERROR_NONE;              // why the last render failed
    std::string m_failure_message;

    bool m_from_parts = false;  // made by veachNewRenderFromParts: a result, no scene to render
    std::atomic<int> m_status{VEACH_STATUS_IDLE};
    std::atomic<bool> m_cancel{false};
    std::atomic<double> m_progress{0}, m_eta{0};
    std::thread m_worker;  // the asynchronous render's thread
    // The thread inside run() (the worker, or veachRender's caller), so that waiting on the
    // render from its own callbacks is refused instead of waiting forever.
    std::atomic<std::thread::id> m_render_thread{};

    ~VeachRenderImpl();
    // Renders on the calling thread; m_status must already be RUNNING. Returns the outcome.
    VeachError run();
};

namespace veach::capi {

// This thread's last error (set by every entry point: cleared on entry, filled on failure).
void clear_last_error();
void set_last_error(VeachError code, const std::string& message);

// Maps the exception being handled to a code and message. Call only inside a catch block.
VeachError code_of_current_exception(std::string& message);

// An error raised by the API layer itself, with its code.
struct ApiError {
    VeachError code;
    std::string message;
};

inline ApiError invalid(const std::string& message) { return ApiError{VEACH_ERROR_INVALID_ARGUMENT, message}; }

// Each option's type is fixed by its name; asking with another type is an error that names the
// right one, so a host binding gets a useful message. Options are the options table's rows
// (options/option_table.h); what a render or a scene reports once it ran or loaded are results,
// read-only, listed here by type. `what` names them in messages ("option", "scene option").
struct ResultNames {
    const char* what;
    veach::OptionObject object;
    std::vector<const char*> ints, floats, strings;
};

// The option row of `name` (nullptr for a result) after checking that it is an option or result
// of type `wanted`. Throws an INVALID_ARGUMENT ApiError otherwise.
inline const veach::OptionSpec* lookup_option(const ResultNames& results, const char* name, veach::OptionKind wanted) {
    using veach::OptionKind;
    if (!name) throw invalid(std::string("null ") + results.what + " name");
    const veach::OptionSpec* spec = veach::find_option(results.object, name);
    OptionKind kind = OptionKind::Int;
    bool found = spec != nullptr;
    if (spec) kind = spec->kind;
    auto in = [&](const std::vector<const char*>& names, OptionKind k) {
        for (const char* n : names)
            if (!found && std::string(name) == n) found = true, kind = k;
    };
    in(results.ints, OptionKind::Int);
    in(results.floats, OptionKind::Float);
    in(results.strings, OptionKind::String);
    if (!found) throw invalid(std::string("unknown ") + results.what + " '" + name + "'");
    static constexpr const char* names[] = {"an int", "a float", "a string"};
    if (kind != wanted)
        throw invalid(std::string(results.what) + " '" + name + "' is " + names[static_cast<int>(kind)] + ", not " +
                      names[static_cast<int>(wanted)]);
    return spec;
}

// Copies `value` into a caller's buffer as veach.h describes (truncated, NUL-terminated, full
// length reported).
void copy_string(const std::string& value, char* buffer, size_t size, size_t* length);

// Runs an entry point's body with the boundary's contract: the last error cleared on entry, and
// any exception caught, reported (callback of `device` if known, last error always) and mapped to
// `on_error` (or, for functions returning a VeachError, to the exception's own code). No exception
// leaves libveach.
template <class R, class Body>
R guarded(VeachDeviceImpl* device, R on_error, Body&& body) noexcept {
    clear_last_error();
    try {
        return body();
    } catch (...) {
        std::string message;
        VeachError code = code_of_current_exception(message);
        if (device)
            device->report(code, message);
        else
            set_last_error(code, message);
        if constexpr (std::is_same_v<R, VeachError>)
            return code;  // the precise code, not the fallback
        else
            return on_error;
    }
}

}  // namespace veach::capi
