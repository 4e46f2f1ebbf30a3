// The `veach` command: batch rendering of glTF scenes, a client of libveach's public C API
// (veach/veach.h) and nothing else: it links libveach.so and uses only veach* symbols, so every
// capability it has, a host application has too.
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <future>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <stdexcept>
#include <system_error>

#include "cli_options.h"
#include "animation_options.h"
#include "farm_options.h"
#include "option_report.h"
#include "render_stats.h"
#include "scene_info.h"
#include "veach/veach.h"

namespace veach::cli {
namespace {

enum ExitCode { k_ok = 0, k_usage = 1, k_bad_input = 2, k_failure = 3, k_interrupted = 130 };

// Interruption. A signal handler may only touch lock-free atomics (or volatile sig_atomic_t),
// so it sets this flag and nothing else. The render runs asynchronously (veachRenderAsync) and
// the main thread, waiting on it in short slices, sees the flag and calls veachCancelRender from
// ordinary code; the library's tile driver then stops within a tile, and the image is written
// as it stands. This is the one piece of process-wide state in Veach, and it lives in the
// command, never in the library.
static_assert(std::atomic<bool>::is_always_lock_free, "the cancel flag must be async-signal-safe");
std::atomic<bool> g_cancel{false};
volatile sig_atomic_t g_signal = 0;

extern "C" void on_stop_signal(int sig) {
    if (g_cancel.load(std::memory_order_relaxed)) {
        // A second signal: the user insists. Die of it now (default action), as uninterrupted
        // programs do; the atomic writes mean no half-written file is left behind.
        ::signal(sig, SIG_DFL);
        ::raise(sig);
        return;
    }
    g_signal = sig;
    g_cancel.store(true, std::memory_order_relaxed);
}

void install_stop_handlers() {
    struct sigaction sa {};
    sa.sa_handler = on_stop_signal;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = SA_RESTART;
    for (int sig : {SIGINT, SIGTERM, SIGHUP}) sigaction(sig, &sa, nullptr);
    // `veach render ... 2>&1 | head -1`: once the reader is gone, messages to the pipe fail with
    // EPIPE (and are lost) instead of killing the render with SIGPIPE.
    ::signal(SIGPIPE, SIG_IGN);
}

const char* signal_name(int sig) {
    switch (sig) {
        case SIGINT: return "SIGINT";
        case SIGTERM: return "SIGTERM";
        case SIGHUP: return "SIGHUP";
        default: return "a signal";
    }
}

long long render_int(VeachRender r, const char* name) {
    long long v = 0;
    veachGetInt(r, name, &v);
    return v;
}
double render_float(VeachRender r, const char* name) {
    double v = 0;
    veachGetFloat(r, name, &v);
    return v;
}

std::vector<std::string> split_lines(const std::string& s) {
    std::vector<std::string> out;
    if (s.empty()) return out;
    for (size_t start = 0; start <= s.size();) {
        size_t nl = std::min(s.find('\n', start), s.size());
        out.push_back(s.substr(start, nl - start));
        start = nl + 1;
    }
    return out;
}

// Handles released at the end of a scope.
struct SceneRef {
    VeachScene h = nullptr;
    ~SceneRef() { veachReleaseScene(h); }
};
struct RenderRef {
    VeachRender h = nullptr;
    ~RenderRef() { veachReleaseRender(h); }
};

int list_color_config(VeachDevice device) {
    std::string source = device_string(device, "color_config");
    if (veachGetLastErrorCode() != VEACH_ERROR_NONE) {
        std::fprintf(stderr, "veach: %s\n", veachGetLastError());
        return k_bad_input;
    }
    std::printf("config: %s\n", source.c_str());
    std::printf("displays:\n");
    for (const std::string& display : split_lines(device_string(device, "color_displays"))) {
        std::vector<std::string> views = split_lines(device_string(device, ("color_views:" + display).c_str()));
        std::printf("  %s\n    views:", display.c_str());
        for (size_t i = 0; i < views.size(); ++i) std::printf("%s %s", i ? "," : "", views[i].c_str());
        std::printf("\n");
    }
    std::vector<std::string> looks = split_lines(device_string(device, "color_looks"));
    std::printf("looks:");
    for (size_t i = 0; i < looks.size(); ++i) std::printf("%s %s", i ? "," : "", looks[i].c_str());
    std::printf("%s\n", looks.empty() ? " (none)" : "");
    return k_ok;
}

// One line at a time on stderr: a sequence's frame writer reports frame N while frame N+1's
// progress is drawn. On a terminal the line first clears the bar it lands on (the next progress
// update draws the bar again below it).
std::mutex& stderr_mutex() {
    static std::mutex m;
    return m;
}
void print_stderr_line(const std::string& line) {
    std::lock_guard<std::mutex> lock(stderr_mutex());
    std::fprintf(stderr, "%s%s\n", isatty(STDERR_FILENO) ? "\r\033[K" : "", line.c_str());
}
std::string formatted(const char* format, ...) __attribute__((format(printf, 1, 2)));
std::string formatted(const char* format, ...) {
    va_list args, again;
    va_start(args, format);
    va_copy(again, args);
    const int n = std::vsnprintf(nullptr, 0, format, args);
    va_end(args);
    std::string out(n > 0 ? static_cast<size_t>(n) : 0, '\0');
    if (n > 0) std::vsnprintf(out.data(), out.size() + 1, format, again);
    va_end(again);
    return out;
}

// Progress on stderr: a bar with an ETA on a terminal; in logs (farm managers, CI), a plain line
// at every pass and at least every VEACH_PROGRESS_INTERVAL seconds (5) between passes, so that a stall
// detector watching the log sees life even in passes that take minutes:
//   Progress: [2/5] shot_010.gltf 42% elapsed 12.3s ETA 17.0s
// ("[i/n] FILE " only in batches; "ETA -" until the first pass gives an estimate). No line before
// a render has run VEACH_PROGRESS_INTERVAL seconds or finished a pass, so that bad input found as
// the render starts (a checkpoint of another render) is still the one line on stderr. The library
// calls update() on its rendering thread after each pass, the main thread calls heartbeat()
// while it waits; a mutex orders the two.
class ProgressPrinter {
public:
    ProgressPrinter(bool quiet, std::string label)
        : m_quiet(quiet), m_tty(isatty(STDERR_FILENO)), m_label(std::move(label)), m_start(clock::now()),
          m_last_line(m_start) {
        // VEACH_PROGRESS_INTERVAL (seconds, default 5): how long a log may go without a line.
        if (const char* v = std::getenv("VEACH_PROGRESS_INTERVAL")) {
            char* end = nullptr;
            double x = std::strtod(v, &end);
            if (end != v && *end == '\0' && x > 0 && x <= 3600) m_interval = x;
        }
    }
    void update(double fraction, double eta) {
        if (m_quiet) return;
        std::lock_guard<std::mutex> lock(m_mutex);
        m_fraction = fraction;
        m_eta = eta;
        m_estimated = true;
        if (m_tty) {
            std::lock_guard<std::mutex> out(stderr_mutex());
            int filled = static_cast<int>(fraction * 30);
            std::fprintf(stderr, "\r%s[%-30s] %3d%%  ETA %5.1fs", m_label.c_str(), std::string(filled, '#').c_str(),
                         percent(), eta);
            std::fflush(stderr);
        } else {
            print_line();
        }
    }
    void heartbeat() {
        if (m_quiet || m_tty) return;
        std::lock_guard<std::mutex> lock(m_mutex);
        if (seconds_since(m_last_line) >= m_interval) print_line();
    }
    void finish() {
        if (!m_quiet && m_tty) {
            std::lock_guard<std::mutex> out(stderr_mutex());
            std::fprintf(stderr, "\n");
        }
    }

private:
    using clock = std::chrono::steady_clock;
    static double seconds_since(clock::time_point t) { return std::chrono::duration<double>(clock::now() - t).count(); }
    int percent() const { return static_cast<int>(std::floor(std::clamp(m_fraction, 0.0, 1.0) * 100.0)); }
    void print_line() {
        char eta[32] = "-";
        if (m_estimated) std::snprintf(eta, sizeof(eta), "%.1fs", m_eta);
        std::lock_guard<std::mutex> out(stderr_mutex());
        std::fprintf(stderr, "Progress: %s%d%% elapsed %.1fs ETA %s\n", m_label.c_str(), percent(),
                     seconds_since(m_start), eta);
        std::fflush(stderr);
        m_last_line = clock::now();
    }

    bool m_quiet, m_tty;
    std::string m_label;
    std::mutex m_mutex;
    clock::time_point m_start, m_last_line;
    double m_fraction = 0, m_eta = 0;
    bool m_estimated = false;
    double m_interval = 5.0;
};

// Called by the library on its rendering thread after each pass.
extern "C" bool on_progress(void* user, double fraction, double eta) {
    static_cast<ProgressPrinter*>(user)->update(fraction, eta);
    return true;  // cancelling is the main thread's job (render_and_watch), promptly, per tile
}

// Renders on the library's own thread while this one watches for a stop signal: the signal
// handler only sets g_cancel, and veachCancelRender is called here, in ordinary code, within
// 20 ms of it (and as soon as `stop`, when given, is set). Returns the final status (the last error holds a failure's message).
VeachStatus render_and_watch(VeachRender render, ProgressPrinter& progress, const std::atomic<bool>* stop,
                             const std::string& preview = {}, double preview_seconds = 0) {
    if (veachRenderAsync(render) != VEACH_ERROR_NONE) return VEACH_STATUS_FAILED;
    bool cancelled = false, preview_failed = false;
    using clock = std::chrono::steady_clock;
    auto last_preview = clock::now();
    for (;;) {
        VeachStatus status = veachWaitRender(render, 20);
        if (status != VEACH_STATUS_RUNNING) return status;
        progress.heartbeat();
        if (!cancelled && (g_cancel.load() || (stop && stop->load()))) {
            veachCancelRender(render);
            cancelled = true;
        }
        // --preview-every: the film so far (kept at every pass boundary), written atomically as
        // any image is; none before the first pass. A failed write is said once and rendering goes on.
        if (!preview.empty() && !preview_failed &&
            std::chrono::duration<double>(clock::now() - last_preview).count() >= preview_seconds) {
            const VeachError e = veachWriteImage(render, preview.c_str());
            if (e == VEACH_ERROR_NONE)
                last_preview = clock::now();
            else if (e != VEACH_ERROR_INVALID_OPERATION) {
                print_stderr_line(formatted("veach: warning: preview not written: %s", veachGetLastError()));
                preview_failed = true;
            }
        }
    }
}

// Whether `path` already holds what this render would write, complete: its metadata (read back
// by the library, for images and part files alike) says veach:complete yes (a part file holds
// only finished samples), the --spp asked for, and the same sample range and pixel bounds. An
// image a killed or time-limited render left behind is rendered again (and resumed, with
// --resume, from its checkpoint); a file that cannot be read counts as missing.
bool output_complete(VeachDevice device, VeachRender options, const std::string& path) {
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) return false;
    size_t length = 0;
    if (veachReadImageMetadata(device, path.c_str(), nullptr, 0, &length) != VEACH_ERROR_NONE) return false;
    std::string text(length + 1, '\0');
    veachReadImageMetadata(device, path.c_str(), text.data(), text.size(), &length);
    text.resize(length);
    std::map<std::string, std::string> meta;
    for (const std::string& line : split_lines(text)) {
        size_t eq = line.find('=');
        if (eq != std::string::npos) meta[line.substr(0, eq)] = line.substr(eq + 1);
    }
    auto value = [&](const char* key) {
        auto it = meta.find(key);
        return it == meta.end() ? std::string() : it->second;
    };
    const long long spp = render_int(options, "spp");
    const long long begin = render_int(options, "sample_begin");
    const long long end = render_int(options, "sample_end") > 0 ? render_int(options, "sample_end") : spp;
    const bool part_file = path.size() >= 6 && path.compare(path.size() - 6, 6, ".vpart") == 0;
    if (!part_file && value("veach:complete") != "yes") return false;
    // A part another version made would not merge with this one's.
    if (part_file && value("Software") != std::string("veach ") + veachGetVersionString()) return false;
    // Adaptive sampling (veach:spp_mean beside veach:spp) stops pixels early: its veach:spp is what
    // every pixel reached, and veach:complete says whether every pass was rendered.
    const bool adaptive = !value("veach:spp_mean").empty();
    if (value("veach:spp_requested") != std::to_string(spp) ||
        (!adaptive && value("veach:spp") != std::to_string(end - begin)))
        return false;
    if (adaptive) return value("veach:samples").empty() && value("veach:pixelbounds").empty();  // never a part
    const std::string samples = value("veach:samples").empty() ? "0:" + value("veach:spp") : value("veach:samples");
    return samples == std::to_string(begin) + ":" + std::to_string(end) &&
           value("veach:pixelbounds") == render_string(options, "pixelbounds");
}

// A frame whose render has ended, on its way to its files: the render (its image), what its
// files need, and whether a signal cut it short.
struct RenderedFrame {
    std::unique_ptr<RenderRef> render;
    RenderCommand cmd;  // this frame's (outputs and --stats-json with the frame filled in)
    std::string input;
    Timings t;
    std::chrono::steady_clock::time_point t0;
    SceneFacts scene;
    bool interrupted = false, checkpointing = false;
    std::string checkpoint;
    long long spp_done = 0, spp_requested = 0;
    bool has_frame = false;
    long long frame = 0;
};

// Renders one frame of a loaded scene (or the still: no frame). `t` brings the load's time (the
// first frame's), t0 when this frame's work began; `label` prefixes progress lines. Returns k_ok
// with `out` filled when there is an image to write, else the exit code (the message printed).
// `stop` (a sequence's failed write) cancels the render; the frame is then not written.
int render_frame_image(const RenderCommand& cmd, const std::string& input, VeachScene scene, Timings t,
                       std::chrono::steady_clock::time_point t0, const long long* frame, const std::string& label,
                       const std::atomic<bool>* stop, RenderedFrame& out) {
    auto render = std::make_unique<RenderRef>();
    render->h = veachNewRender(scene);
    if (!render->h) {
        std::fprintf(stderr, "veach: %s: %s\n", input.c_str(), veachGetLastError());
        return k_failure;
    }
    VeachRender r = render->h;
    for (const ApiOption& o : cmd.render_options) {
        if (apply_render_option(r, o) != VEACH_ERROR_NONE) {  // e.g. no such camera
            std::fprintf(stderr, "veach: %s: %s\n", input.c_str(), veachGetLastError());
            return k_bad_input;
        }
    }
    if (frame && cmd.animated_seed) {
        const long long seed = render_int(r, "seed");
        veachSetInt(r, "seed", static_cast<long long>(animated_seed(static_cast<uint64_t>(seed), *frame)));
    }
    const bool checkpointing = cmd.checkpoint_seconds >= 0 || cmd.resume;
    const std::string checkpoint = checkpoint_path_for(cmd, input);
    if (checkpointing) {
        veachSetString(r, "checkpoint", checkpoint.c_str());
        veachSetFloat(r, "checkpoint_interval", cmd.checkpoint_seconds);  // < 0: never written
        veachSetInt(r, "resume", cmd.resume ? 1 : 0);
    }
    ProgressPrinter progress(cmd.quiet, label);
    veachSetProgressFunction(r, on_progress, &progress);
    const long long spp_requested = render_int(r, "spp");

    std::string preview;
    if (!cmd.preview_path.empty()) {
        preview = output_path_for(frame ? with_frame(cmd.preview_path, *frame) : cmd.preview_path, input);
        veachSetInt(r, "snapshots", 1);
    }
    VeachStatus status = render_and_watch(r, progress, stop, preview, cmd.preview_seconds);
    if (stop && stop->load()) return k_failure;  // the sequence stops at the write that failed
    if (status == VEACH_STATUS_FAILED) {
        VeachError e = veachGetLastErrorCode();
        const char* message = veachGetLastError();
        // The library's codes, as the command's exit codes: a checkpoint that cannot be read or
        // belongs to another render is bad input (2), one that cannot be written a failure (3).
        if (e == VEACH_ERROR_BAD_INPUT)
            std::fprintf(stderr, "veach: %s\n", message);
        else if (e == VEACH_ERROR_OUTPUT)
            std::fprintf(stderr, "veach: %s\n", message);
        else if (e == VEACH_ERROR_INVALID_ARGUMENT)
            std::fprintf(stderr, "veach: %s: %s\n", input.c_str(), message);
        else
            std::fprintf(stderr, "veach: %s: render failed: %s\n", input.c_str(), message);
        return e == VEACH_ERROR_BAD_INPUT || e == VEACH_ERROR_INVALID_ARGUMENT ? k_bad_input : k_failure;
    }
    progress.finish();
    for (const std::string& w : split_lines(render_string(r, "result_warnings")))
        std::fprintf(stderr, "veach: warning: %s: %s\n", input.c_str(), w.c_str());
    // The library calls a render cancelled only when it has fewer samples than asked: a signal
    // after the last pass leaves a complete image.
    const long long spp_done = render_int(r, "result_spp");
    const bool interrupted = status == VEACH_STATUS_CANCELLED && g_cancel.load();
    if (interrupted && spp_done == 0) {
        std::fprintf(stderr, "veach: %s: interrupted by %s before the first pass completed; nothing written\n",
                     input.c_str(), signal_name(g_signal));
        return k_interrupted;
    }
    t.build = render_float(r, "build_seconds");
    t.render = render_float(r, "render_seconds");
    t.denoise = render_float(r, "denoise_seconds");
    out.render = std::move(render);
    out.cmd = cmd;
    out.input = input;
    out.t = t;
    out.t0 = t0;
    out.scene = scene_facts(scene);
    out.interrupted = interrupted;
    out.checkpointing = checkpointing;
    out.checkpoint = checkpoint;
    out.spp_done = spp_done;
    out.spp_requested = spp_requested;
    out.has_frame = frame != nullptr;
    out.frame = frame ? *frame : 0;
    return k_ok;
}

// Writes a rendered frame's outputs (each atomically: temporary, fsync, rename), removes its
// checkpoint and writes --stats-json; returns the frame's exit code. Touches only the frame's own
// render and the device, so a sequence runs it on a thread of its own while the next frame
// renders. Messages go out whole lines at a time.
int write_frame(VeachDevice device, RenderedFrame& f) {
    using clock = std::chrono::steady_clock;
    const VeachRender r = f.render->h;
    const std::string& input = f.input;
    auto t2 = clock::now();
    std::string written;
    StatsContext context{input, {}, f.has_frame, f.frame};
    for (const std::string& pattern : f.cmd.outputs) {
        std::string out = output_path_for(pattern, input);
        if (veachWriteImage(r, out.c_str()) != VEACH_ERROR_NONE) {
            print_stderr_line(formatted("veach: %s", veachGetLastError()));
            return k_failure;
        }
        written += (written.empty() ? "" : ", ") + out;
        context.outputs.push_back(out);
    }
    // The image is safely in place: the state it was resumable from has served its purpose.
    if (f.checkpointing && !f.interrupted) {
        std::error_code ec;
        std::filesystem::remove(f.checkpoint, ec);
    }
    auto t3 = clock::now();
    Timings t = f.t;
    t.write = std::chrono::duration<double>(t3 - t2).count();
    t.total = std::chrono::duration<double>(t3 - f.t0).count();
    if (long long nonfinite = render_int(r, "result_nonfinite_samples"); nonfinite > 0)
        print_stderr_line(formatted("veach: warning: %s: %llu non-finite samples dropped", input.c_str(),
                                    static_cast<unsigned long long>(nonfinite)));
    if (!f.cmd.stats_json.empty()) {
        try {
            write_stats_json(output_path_for(f.cmd.stats_json, input), device, f.scene, r, t, context);
        } catch (const std::exception& e) {
            print_stderr_line(formatted("veach: %s", e.what()));
            return k_failure;
        }
    }
    if (f.interrupted) {
        print_stderr_line(formatted("veach: %s: interrupted by %s: wrote %s with %lld of %lld spp", input.c_str(),
                                    signal_name(g_signal), written.c_str(), f.spp_done, f.spp_requested));
        return k_interrupted;
    }
    if (!f.cmd.quiet)
        print_stderr_line(formatted("veach: %s -> %s (%lldx%lld, %lld spp, %.2fs)", input.c_str(), written.c_str(),
                                    render_int(r, "result_width"), render_int(r, "result_height"), f.spp_done,
                                    t.total));
    return k_ok;
}

// `index` of `count` inputs (counted from 1), for the batch's progress lines.
int render_one(VeachDevice device, const RenderCommand& cmd, const std::string& input, VeachRender options,
               size_t index, size_t count) {
    using clock = std::chrono::steady_clock;
    auto seconds = [](clock::time_point a, clock::time_point b) {
        return std::chrono::duration<double>(b - a).count();
    };
    Timings t;
    // Each frame has its own outputs (and checkpoint): --skip-existing leaves out the frames whose
    // outputs are all complete, and loads nothing when no frame is left.
    auto complete = [&](const RenderCommand& c) {
        bool all = true;
        for (const std::string& pattern : c.outputs)
            all = all && output_complete(device, options, output_path_for(pattern, input));
        return all;
    };
    std::vector<long long> frames;
    for (long long f : cmd.frames) {
        if (cmd.skip_existing && complete(command_for_frame(cmd, f))) {
            if (!cmd.quiet)
                std::fprintf(stderr, "veach: %s: frame %lld skipped, its outputs are complete\n", input.c_str(), f);
            continue;
        }
        frames.push_back(f);
    }
    const bool animated = !cmd.frames.empty();
    if (animated ? frames.empty() : cmd.skip_existing && complete(cmd)) {
        if (!cmd.quiet && !animated)
            std::fprintf(stderr, "veach: %s: skipped, its outputs are complete\n", input.c_str());
        return k_ok;
    }
    auto t0 = clock::now();
    SceneRef scene{veachNewScene(device)};
    if (!scene.h) {
        std::fprintf(stderr, "veach: %s\n", veachGetLastError());
        return k_failure;
    }
    for (const ApiOption& o : cmd.scene_options) {
        if (apply_scene_option(scene.h, o) != VEACH_ERROR_NONE) {
            std::fprintf(stderr, "veach: %s: %s\n", input.c_str(), veachGetLastError());
            return k_bad_input;
        }
    }
    // The first frame's time and the animation played: the import evaluates them (and refuses an
    // animation the file lacks, listing its animations, before anything is rendered).
    if (animated) {
        bool ok = veachSetSceneFloat(scene.h, "time", frame_time(cmd, frames.front())) == VEACH_ERROR_NONE &&
                  (cmd.animation.empty() || veachSetSceneString(scene.h, "animation", cmd.animation.c_str()) ==
                                                VEACH_ERROR_NONE) &&
                  (!cmd.shutter_given ||
                   veachSetSceneString(scene.h, "shutter", shutter_seconds(cmd).c_str()) == VEACH_ERROR_NONE);
        if (!ok) {
            std::fprintf(stderr, "veach: %s: %s\n", input.c_str(), veachGetLastError());
            return k_bad_input;
        }
    }
    // Import, environment, then the library's repairs (a white world for an unlit scene, a far-off
    // scene moved to the origin), as for every host.
    if (VeachError e = veachLoadSceneFile(scene.h, input.c_str()); e != VEACH_ERROR_NONE) {
        std::fprintf(stderr, "veach: %s\n", veachGetLastError());
        return e == VEACH_ERROR_BAD_INPUT || e == VEACH_ERROR_INVALID_ARGUMENT ? k_bad_input : k_failure;
    }
    for (const std::string& w : split_lines(scene_string(scene.h, "warnings")))
        std::fprintf(stderr, "veach: warning: %s: %s\n", input.c_str(), w.c_str());
    t.load = seconds(t0, clock::now());
    const std::string label =
        count > 1 ? "[" + std::to_string(index) + "/" + std::to_string(count) + "] " + input + " " : std::string();
    if (!animated) {
        RenderedFrame still;
        int rc = render_frame_image(cmd, input, scene.h, t, t0, nullptr, label, nullptr, still);
        return rc == k_ok ? write_frame(device, still) : rc;
    }
    // A sequence from this one load: each later frame poses the loaded scene again (the file is
    // not read again; the scene keeps its BVH and light tables and updates what moved). Frame N's
    // files are written on a thread of their own while frame N+1 renders: a queue of one, so at
    // most one finished frame is held besides the film in progress. A write that fails stops the
    // sequence: the frame rendering meanwhile is cancelled and nothing after the failed frame is
    // written. Every write has ended before this returns (`writing` is declared after the scene,
    // so even an early return waits for it while the scene lives).
    std::atomic<bool> write_failed{false};
    std::future<int> writing;  // the previous frame's write
    auto write_in_background = [&](RenderedFrame frame) {
        auto job = std::make_shared<RenderedFrame>(std::move(frame));
        auto write = [device, job, &write_failed] {
            const int rc = write_frame(device, *job);
            if (rc == k_failure) write_failed.store(true);
            return rc;
        };
        try {
            writing = std::async(std::launch::async, write);
        } catch (const std::system_error&) {  // no thread to be had: write it here, as a still is
            std::promise<int> done;
            done.set_value(write());
            writing = done.get_future();
        }
    };
    auto previous_write = [&] { return writing.valid() ? writing.get() : k_ok; };
    int worst = k_ok;
    for (size_t k = 0; k < frames.size(); ++k) {
        if (k > 0) {
            t0 = clock::now();
            t.load = 0;
            if (veachSetSceneFloat(scene.h, "time", frame_time(cmd, frames[k])) != VEACH_ERROR_NONE) {
                std::fprintf(stderr, "veach: %s: frame %lld: %s\n", input.c_str(), frames[k], veachGetLastError());
                previous_write();
                return k_failure;
            }
        }
        const std::string frame_label =
            frames.size() > 1 ? label + "frame " + std::to_string(frames[k]) + " " : label;
        RenderedFrame rendered;
        int rc = render_frame_image(command_for_frame(cmd, frames[k]), input, scene.h, t, t0, &frames[k], frame_label,
                                    &write_failed, rendered);
        const int written = previous_write();
        if (written == k_failure) return k_failure;  // reported by the writer; this frame is not written
        if (written == k_interrupted || rc == k_interrupted) return k_interrupted;
        if (rc == k_ok) write_in_background(std::move(rendered));
        worst = std::max(worst, rc);
        if (g_cancel.load()) {
            previous_write();
            return k_interrupted;
        }
    }
    const int last = previous_write();
    return last == k_interrupted ? k_interrupted : std::max(worst, last);
}

// A render of an empty scene carrying the command's render options: what the outputs should be
// (format, display transform, spp, sample range) is known before any scene loads. Options the
// empty scene cannot take (a camera name) are left for the real render to refuse.
struct OptionsRender {
    SceneRef scene;
    RenderRef render;
};
bool make_options_render(VeachDevice device, const RenderCommand& cmd, OptionsRender& out) {
    static const char k_empty_gltf[] = R"({"asset": {"version": "2.0"}, "scenes": [{"nodes": []}], "scene": 0})";
    out.scene.h = veachNewSceneFromMemory(device, k_empty_gltf, sizeof(k_empty_gltf) - 1, "gltf", nullptr);
    out.render.h = out.scene.h ? veachNewRender(out.scene.h) : nullptr;
    if (!out.render.h) return false;
    for (const ApiOption& o : cmd.render_options) apply_render_option(out.render.h, o);
    return true;
}

// Every file the command will write, checked before any scene loads: a farm task with a typo in
// an output name, a colour config name or a folder must fail in a second, not after an hour of
// rendering. A sequence's files are checked once per folder: a frame pattern in the file name
// alone (out/f_####.exr) checks one folder for every frame, one in a folder's name
// (out/####/beauty.exr) checks each frame's folder, which must exist as any output's must.
int check_outputs(VeachDevice device, const RenderCommand& cmd, VeachRender check) {
    auto refuse = [](VeachError e) {
        std::fprintf(stderr, "veach: %s\n", veachGetLastError());
        return e == VEACH_ERROR_INVALID_ARGUMENT ? k_usage : k_bad_input;
    };
    const bool checkpointing = cmd.checkpoint_seconds >= 0 || cmd.resume;
    const bool animated = !cmd.frames.empty();
    const std::vector<long long> still{0};
    std::set<std::string> checked;  // what, folder and extension of the files checked
    auto first_in_folder = [&](const std::string& what, const std::string& path) {
        const std::filesystem::path p(path);
        return checked.insert(what + '\n' + p.parent_path().string() + '\n' + p.extension().string()).second;
    };
    for (const std::string& input : cmd.inputs) {
        checked.clear();
        for (long long frame : animated ? cmd.frames : still) {
            auto path = [&](const std::string& pattern) {
                return output_path_for(animated ? with_frame(pattern, frame) : pattern, input);
            };
            for (size_t i = 0; i < cmd.outputs.size(); ++i) {
                const std::string out = path(cmd.outputs[i]);
                if (first_in_folder("output " + std::to_string(i), out))
                    if (VeachError e = veachCheckOutput(check, out.c_str()); e != VEACH_ERROR_NONE) return refuse(e);
            }
            if (!cmd.preview_path.empty())
                if (const std::string preview = path(cmd.preview_path); first_in_folder("preview", preview))
                    if (VeachError e = veachCheckOutput(check, preview.c_str()); e != VEACH_ERROR_NONE) return refuse(e);
            if (!cmd.stats_json.empty())
                if (const std::string stats = path(cmd.stats_json); first_in_folder("stats", stats))
                    if (VeachError e = veachCheckFile(device, stats.c_str()); e != VEACH_ERROR_NONE) return refuse(e);
            if (checkpointing && !cmd.outputs.empty())
                if (const std::string c = path(cmd.outputs.front()) + ".checkpoint"; first_in_folder("checkpoint", c))
                    if (VeachError e = veachCheckFile(device, c.c_str()); e != VEACH_ERROR_NONE) return refuse(e);
        }
    }
    return k_ok;
}

const char* k_usage_text = R"(usage: veach render INPUT... -o OUTPUT [options]   (veach render --help)
       veach merge PART.vpart... -o OUTPUT [--expect-spp N]
       veach info SCENE [--json] [--width N --height N]
       veach color | veach options [--json | --markdown]
       veach --version | --help
)";

int run(int argc, char** argv) {
    if (argc < 2) {
        std::fputs(k_usage_text, stderr);
        return k_usage;
    }
    if (veachGetVersion() / 10000 != VEACH_VERSION_MAJOR || veachGetVersion() < VEACH_VERSION) {
        std::fprintf(stderr, "veach: libveach %s is older than this command needs (%d.%d)\n", veachGetVersionString(),
                     VEACH_VERSION_MAJOR, VEACH_VERSION_MINOR);
        return k_failure;
    }
    struct DeviceRef {
        VeachDevice h = veachNewDevice();
        ~DeviceRef() { veachReleaseDevice(h); }
    } device;
    if (!device.h) {
        std::fprintf(stderr, "veach: %s\n", veachGetLastError());
        return k_failure;
    }
    CommandLine line = parse_command_line(argc, argv, device.h);
    if (line.exit_code >= 0) return line.exit_code;
    switch (line.which) {
        case Subcommand::Merge: return run_merge_command(device.h, line.merge);
        case Subcommand::Color: return list_color_config(device.h);
        case Subcommand::Options: return print_options(device.h, line.options_json, line.options_markdown);
        case Subcommand::Info: return run_info_command(device.h, line.info);
        default: break;
    }
    const RenderCommand& cmd = line.render;
    if (cmd.dry_run) return print_dry_run(device.h, cmd);
    OptionsRender options;
    if (!make_options_render(device.h, cmd, options)) {
        std::fprintf(stderr, "veach: %s\n", veachGetLastError());
        return k_failure;
    }
    if (int rc = check_outputs(device.h, cmd, options.render.h); rc != k_ok) return rc;
    install_stop_handlers();
    int worst = k_ok;
    for (size_t i = 0; i < cmd.inputs.size(); ++i) {
        if (g_cancel.load()) return k_interrupted;
        int rc = render_one(device.h, cmd, cmd.inputs[i], options.render.h, i + 1, cmd.inputs.size());
        if (rc == k_interrupted) return k_interrupted;
        worst = std::max(worst, rc);
    }
    return g_cancel.load() ? k_interrupted : worst;
}

}  // namespace
}  // namespace veach::cli

int main(int argc, char** argv) {
    try {
        return veach::cli::run(argc, argv);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "veach: %s\n", e.what());
        return 3;
    }
}
