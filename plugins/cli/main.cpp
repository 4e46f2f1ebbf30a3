// The `veach` command: batch rendering of glTF scenes.
#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "api/render_job.h"
#include "cli_options.h"
#include "film/film_checkpoint.h"
#include "importers/importer.h"
#include "output/display_transform.h"
#include "output/image_output.h"
#include "scene/scene_repair.h"

namespace veach::cli {
namespace {

enum ExitCode { k_ok = 0, k_usage = 1, k_bad_input = 2, k_failure = 3, k_interrupted = 130 };

// Interruption. A signal handler may only touch lock-free atomics (or volatile sig_atomic_t),
// so it sets the flag the render loop polls between tiles and nothing else; the render then
// stops, and the image is written as it stands by ordinary code. This is the one piece of
// process-wide state in Veach, and it lives in the command, never in the library.
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
}

const char* signal_name(int sig) {
    switch (sig) {
    case SIGINT: return "SIGINT";
    case SIGTERM: return "SIGTERM";
    case SIGHUP: return "SIGHUP";
    default: return "a signal";
    }
}

// Identifies the scene for checkpoints: the input file's bytes and the options that change the
// scene after loading.
uint64_t scene_hash(const RenderCommand& cmd, const std::string& input) {
    uint64_t h = fnv1a_64(input);
    std::ifstream f(input, std::ios::binary);
    std::vector<char> buffer(1 << 16);
    while (f) {
        f.read(buffer.data(), static_cast<std::streamsize>(buffer.size()));
        h = fnv1a_64(buffer.data(), static_cast<size_t>(f.gcount()), h);
    }
    const EnvironmentOptions& env = cmd.environment;
    h = fnv1a_64("|env=" + env.map_path + "|" + std::to_string(env.has_color) + "|" + std::to_string(env.color.r) + "," +
                     std::to_string(env.color.g) + "," + std::to_string(env.color.b) + "|" +
                     std::to_string(env.strength) + "|" + std::to_string(env.rotate_degrees) + "|scene=" +
                     std::to_string(cmd.import.scene_index),
                 h);
    return h;
}

int list_color_config() {
    ColorConfigInfo info;
    try {
        info = describe_color_config();
    } catch (const std::exception& e) {
        std::fprintf(stderr, "veach: %s\n", e.what());
        return k_bad_input;
    }
    std::printf("config: %s\n", info.source.c_str());
    std::printf("displays:\n");
    for (const auto& [display, views] : info.views) {
        std::printf("  %s\n    views:", display.c_str());
        for (size_t i = 0; i < views.size(); ++i) std::printf("%s %s", i ? "," : "", views[i].c_str());
        std::printf("\n");
    }
    std::printf("looks:");
    for (size_t i = 0; i < info.looks.size(); ++i) std::printf("%s %s", i ? "," : "", info.looks[i].c_str());
    std::printf("%s\n", info.looks.empty() ? " (none)" : "");
    return k_ok;
}

std::string json_escape(const std::string& s) {
    std::string out;
    for (char c : s) {
        if (c == '"' || c == '\\') out += '\\', out += c;
        else if (static_cast<unsigned char>(c) < 0x20) {
            char buf[8];
            std::snprintf(buf, sizeof(buf), "\\u%04x", c);
            out += buf;
        } else out += c;
    }
    return out;
}

// Progress on stderr: a bar with an ETA on a terminal, plain lines otherwise (logs, CI).
class ProgressPrinter {
public:
    explicit ProgressPrinter(bool quiet) : m_quiet(quiet), m_tty(isatty(STDERR_FILENO)) {}
    void update(double fraction, double eta) {
        if (m_quiet) return;
        int percent = static_cast<int>(std::floor(fraction * 100.0));
        if (m_tty) {
            int filled = static_cast<int>(fraction * 30);
            std::fprintf(stderr, "\r[%-30s] %3d%%  ETA %5.1fs", std::string(filled, '#').c_str(), percent, eta);
            std::fflush(stderr);
        } else if (percent != m_last) {
            std::fprintf(stderr, "Progress: %d%%\n", percent);
        }
        m_last = percent;
    }
    void finish() {
        if (!m_quiet && m_tty) std::fprintf(stderr, "\n");
    }

private:
    bool m_quiet, m_tty;
    int m_last = -1;
};

struct Timings {
    double load = 0, build = 0, render = 0, write = 0, total = 0;
};

void write_stats_json(const std::string& path, const RenderCommand& cmd, const std::string& input, const Scene& scene,
                      const RenderResult& r, const Timings& t) {
    std::ostringstream js;
    double samples = static_cast<double>(r.stats.camera_samples);
    js << "{\n"
       << "  \"input\": \"" << json_escape(input) << "\",\n"
       << "  \"width\": " << r.image.width << ",\n"
       << "  \"height\": " << r.image.height << ",\n"
       << "  \"spp\": " << r.stats.spp_done << ",\n"
       << "  \"integrator\": \"" << json_escape(r.integrator) << "\",\n"
       << "  \"threads\": " << cmd.job.render.threads << ",\n"
       << "  \"seed\": " << cmd.job.render.seed << ",\n"
       << "  \"camera\": \"" << json_escape(r.camera_name) << "\",\n"
       << "  \"triangles\": " << r.triangles << ",\n"
       << "  \"seconds\": {\"load\": " << t.load << ", \"build\": " << t.build << ", \"render\": " << t.render
       << ", \"write\": " << t.write << ", \"total\": " << t.total << "},\n"
       << "  \"samples_per_second\": " << (t.render > 0 ? samples / t.render : 0.0) << ",\n"
       << "  \"rays\": " << r.stats.rays << ",\n"
       << "  \"rays_per_second\": " << (t.render > 0 ? r.stats.rays / t.render : 0.0) << ",\n"
       << "  \"nonfinite_samples\": " << r.stats.nonfinite_samples << ",\n"
       << "  \"peak_rss_bytes\": " << peak_resident_bytes() << ",\n"
       << "  \"repaired\": {\"invalid_indices\": " << scene.repaired.invalid_indices
       << ", \"nonfinite_triangles\": " << scene.repaired.nonfinite_triangles
       << ", \"degenerate_triangles\": " << scene.repaired.degenerate_triangles
       << ", \"duplicate_triangles\": " << scene.repaired.duplicate_triangles
       << ", \"normals_replaced\": " << scene.repaired.normals_replaced
       << ", \"normals_normalized\": " << scene.repaired.normals_normalized
       << ", \"uvs_replaced\": " << scene.repaired.uvs_replaced
       << ", \"colors_replaced\": " << scene.repaired.colors_replaced
       << ", \"lights_dropped\": " << scene.repaired.lights_dropped << "},\n"
       << "  \"features\": [";
    std::vector<std::string> features = scene.features.names();
    for (size_t i = 0; i < features.size(); ++i) js << (i ? ", " : "") << "\"" << features[i] << "\"";
    js << "]\n}\n";
    std::string tmp = path + ".tmp";
    {
        std::ofstream f(tmp);
        f << js.str();
        if (!f) throw OutputError(path + ": cannot write the stats file");
    }
    if (std::rename(tmp.c_str(), path.c_str()) != 0) {
        std::remove(tmp.c_str());
        throw OutputError(path + ": cannot write the stats file");
    }
}

int render_one(const RenderCommand& cmd, const std::string& input) {
    using clock = std::chrono::steady_clock;
    auto seconds = [](clock::time_point a, clock::time_point b) { return std::chrono::duration<double>(b - a).count(); };
    Timings t;
    if (cmd.skip_existing) {
        bool all = true;
        std::error_code ec;
        for (const std::string& pattern : cmd.outputs) all = all && std::filesystem::exists(output_path_for(pattern, input), ec);
        if (all) {
            if (!cmd.quiet) std::fprintf(stderr, "veach: %s: skipped, its output exists\n", input.c_str());
            return k_ok;
        }
    }
    auto t0 = clock::now();
    Scene scene;
    try {
        scene = import_scene(input, cmd.import);
    } catch (const ImportError& e) {
        std::fprintf(stderr, "veach: %s\n", e.what());
        return k_bad_input;
    }
    try {
        apply_environment(cmd.environment, &scene);
    } catch (const std::invalid_argument& e) {
        std::fprintf(stderr, "veach: %s\n", e.what());
        return k_bad_input;
    }
    light_unlit_scene(scene);  // after --env: an explicit environment wins
    rebase_scene(scene);       // a scene far from the origin keeps its precision (scene_repair.h)
    for (const std::string& w : scene.warnings) std::fprintf(stderr, "veach: warning: %s: %s\n", input.c_str(), w.c_str());
    auto t1 = clock::now();
    t.load = seconds(t0, t1);

    ProgressPrinter progress(cmd.quiet);
    RenderControl control;
    control.progress = [&](double f, double eta) { progress.update(f, eta); };
    control.cancel = &g_cancel;
    RenderJobOptions job = cmd.job;
    const bool checkpointing = cmd.checkpoint_seconds >= 0 || cmd.resume;
    if (checkpointing) {
        job.checkpoint.path = checkpoint_path_for(cmd, input);
        job.checkpoint.write = cmd.checkpoint_seconds >= 0;
        job.checkpoint.interval_seconds = std::max(0.0, cmd.checkpoint_seconds);
        job.checkpoint.resume = cmd.resume;
        job.checkpoint.scene_hash = scene_hash(cmd, input);
    }
    RenderResult result;
    try {
        result = render_scene(scene, job, control);
    } catch (const CheckpointWriteError& e) {
        std::fprintf(stderr, "veach: %s\n", e.what());
        return k_failure;
    } catch (const CheckpointError& e) {
        std::fprintf(stderr, "veach: %s\n", e.what());
        return k_bad_input;
    } catch (const std::invalid_argument& e) {
        std::fprintf(stderr, "veach: %s: %s\n", input.c_str(), e.what());
        return k_bad_input;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "veach: %s: render failed: %s\n", input.c_str(), e.what());
        return k_failure;
    }
    progress.finish();
    for (const std::string& w : result.warnings) std::fprintf(stderr, "veach: warning: %s: %s\n", input.c_str(), w.c_str());
    // A signal after the last pass leaves a complete image: only fewer samples than asked is an
    // interruption.
    const bool interrupted = result.stats.cancelled && g_cancel.load() &&
                             result.stats.spp_done < std::max(cmd.job.render.spp, result.resumed_spp);
    if (interrupted && result.stats.spp_done == 0) {
        std::fprintf(stderr, "veach: %s: interrupted by %s before the first pass completed; nothing written\n",
                     input.c_str(), signal_name(g_signal));
        return k_interrupted;
    }
    t.build = result.build_seconds;
    t.render = result.render_seconds;

    OutputSettings os = cmd.output_settings;
    os.metadata["Software"] = std::string("veach ") + VEACH_VERSION_STRING;
    os.metadata["veach:scene"] = input;
    os.metadata["veach:camera"] = result.camera_name;
    // The samples per pixel every pixel completed: after an interruption some pixels hold one
    // more pass, which per-pixel averaging keeps unbiased.
    os.metadata["veach:spp"] = std::to_string(result.stats.spp_done);
    os.metadata["veach:spp_requested"] = std::to_string(cmd.job.render.spp);
    os.metadata["veach:complete"] = interrupted ? "no" : "yes";
    char filter[64];
    std::snprintf(filter, sizeof(filter), "%s %g", filter_name(cmd.job.film.filter.type), cmd.job.film.filter.width);
    os.metadata["veach:filter"] = filter;
    if (result.resumed_spp > 0) os.metadata["veach:resumed_spp"] = std::to_string(result.resumed_spp);
    os.metadata["veach:seed"] = std::to_string(cmd.job.render.seed);
    os.metadata["veach:integrator"] = result.integrator;
    os.metadata["veach:render_seconds"] = std::to_string(result.render_seconds);
    auto t2 = clock::now();
    std::string written;
    for (const std::string& pattern : cmd.outputs) {
        std::string out = output_path_for(pattern, input);
        try {
            write_image(result.image, out, os);
        } catch (const std::exception& e) {
            std::fprintf(stderr, "veach: %s\n", e.what());
            return k_failure;
        }
        written += (written.empty() ? "" : ", ") + out;
    }
    // The image is safely in place: the state it was resumable from has served its purpose.
    if (checkpointing && !interrupted) {
        std::error_code ec;
        std::filesystem::remove(job.checkpoint.path, ec);
    }
    auto t3 = clock::now();
    t.write = seconds(t2, t3);
    t.total = seconds(t0, t3);
    if (result.stats.nonfinite_samples > 0)
        std::fprintf(stderr, "veach: warning: %s: %llu non-finite samples dropped\n", input.c_str(),
                     static_cast<unsigned long long>(result.stats.nonfinite_samples));
    if (!cmd.stats_json.empty()) {
        try {
            write_stats_json(output_path_for(cmd.stats_json, input), cmd, input, scene, result, t);
        } catch (const std::exception& e) {
            std::fprintf(stderr, "veach: %s\n", e.what());
            return k_failure;
        }
    }
    if (interrupted) {
        std::fprintf(stderr, "veach: %s: interrupted by %s: wrote %s with %d of %d spp\n", input.c_str(),
                     signal_name(g_signal), written.c_str(), result.stats.spp_done, cmd.job.render.spp);
        return k_interrupted;
    }
    if (!cmd.quiet)
        std::fprintf(stderr, "veach: %s -> %s (%dx%d, %d spp, %.2fs)\n", input.c_str(), written.c_str(), result.image.width,
                     result.image.height, result.stats.spp_done, t.total);
    return k_ok;
}

int run(int argc, char** argv) {
    std::vector<std::string> args(argv + 1, argv + argc);
    if (args.empty() || args[0] == "--help" || args[0] == "-h" || args[0] == "help") {
        std::fputs(usage_text(), args.empty() ? stderr : stdout);
        return args.empty() ? k_usage : k_ok;
    }
    if (args[0] == "--version") {
        std::printf("veach %s\n", VEACH_VERSION_STRING);
        return k_ok;
    }
    if (args[0] == "color" || args[0] == "colour") return list_color_config();
    if (args[0] != "render") {
        std::fprintf(stderr, "veach: unknown command '%s' (try 'veach --help')\n", args[0].c_str());
        return k_usage;
    }
    RenderCommand cmd;
    try {
        cmd = parse_render_command(std::vector<std::string>(args.begin() + 1, args.end()));
    } catch (const UsageError& e) {
        std::fprintf(stderr, "veach: %s (try 'veach --help')\n", e.what());
        return k_usage;
    }
    install_stop_handlers();
    int worst = k_ok;
    for (const std::string& input : cmd.inputs) {
        if (g_cancel.load()) return k_interrupted;
        int rc = render_one(cmd, input);
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
