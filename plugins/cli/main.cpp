// The `veach` command: batch rendering of glTF scenes.
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>

#include "api/render_job.h"
#include "cli_options.h"
#include "importers/importer.h"
#include "output/image_output.h"

namespace veach::cli {
namespace {

enum ExitCode { k_ok = 0, k_usage = 1, k_bad_input = 2, k_failure = 3 };

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
       << "  \"integrator\": \"" << json_escape(cmd.job.render.integrator) << "\",\n"
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
    auto t0 = clock::now();
    Scene scene;
    try {
        scene = import_scene(input, cmd.import);
    } catch (const ImportError& e) {
        std::fprintf(stderr, "veach: %s\n", e.what());
        return k_bad_input;
    }
    for (const std::string& w : scene.warnings) std::fprintf(stderr, "veach: warning: %s: %s\n", input.c_str(), w.c_str());
    auto t1 = clock::now();
    t.load = seconds(t0, t1);

    ProgressPrinter progress(cmd.quiet);
    RenderControl control;
    control.progress = [&](double f, double eta) { progress.update(f, eta); };
    RenderResult result;
    try {
        result = render_scene(scene, cmd.job, control);
    } catch (const std::invalid_argument& e) {
        std::fprintf(stderr, "veach: %s: %s\n", input.c_str(), e.what());
        return k_bad_input;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "veach: %s: render failed: %s\n", input.c_str(), e.what());
        return k_failure;
    }
    progress.finish();
    t.build = result.build_seconds;
    t.render = result.render_seconds;

    OutputSettings os = cmd.output_settings;
    os.metadata["Software"] = std::string("veach ") + VEACH_VERSION_STRING;
    os.metadata["veach:scene"] = input;
    os.metadata["veach:camera"] = result.camera_name;
    os.metadata["veach:spp"] = std::to_string(result.stats.spp_done);
    os.metadata["veach:seed"] = std::to_string(cmd.job.render.seed);
    os.metadata["veach:integrator"] = cmd.job.render.integrator;
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
    int worst = k_ok;
    for (const std::string& input : cmd.inputs) worst = std::max(worst, render_one(cmd, input));
    return worst;
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
