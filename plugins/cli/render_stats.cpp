#include "render_stats.h"

#include <stdexcept>

#include <nlohmann/json.hpp>

#include "cli_options.h"

namespace veach::cli {
namespace {

long long render_int(VeachRender r, const char* name) {
    long long v = 0;
    veachGetInt(r, name, &v);
    return v;
}

std::vector<std::string> lines(const std::string& s) {
    std::vector<std::string> out;
    for (size_t start = 0; start < s.size();) {
        size_t nl = std::min(s.find('\n', start), s.size());
        out.push_back(s.substr(start, nl - start));
        start = nl + 1;
    }
    return out;
}

}  // namespace

SceneFacts scene_facts(VeachScene scene) {
    SceneFacts f;
    veachGetSceneInt(scene, "triangles", &f.triangles);
    for (const char* key : {"invalid_indices", "nonfinite_triangles", "degenerate_triangles", "duplicate_triangles",
                            "normals_replaced", "normals_normalized", "uvs_replaced", "colors_replaced",
                            "lights_dropped"}) {
        long long v = 0;
        veachGetSceneInt(scene, (std::string("repaired_") + key).c_str(), &v);
        f.repaired.emplace_back(key, v);
    }
    f.features = lines(scene_string(scene, "features"));
    return f;
}

std::string stats_json(VeachDevice device, const SceneFacts& scene, VeachRender render, const Timings& t,
                       const StatsContext& context) {
    const double samples = static_cast<double>(render_int(render, "result_camera_samples"));
    const double rays = static_cast<double>(render_int(render, "result_rays"));
    long long peak = 0;
    veachGetDeviceInt(device, "peak_memory_bytes", &peak);
    nlohmann::ordered_json j;
    j["input"] = context.input;
    j["version"] = veachGetVersionString();
    if (context.has_frame) j["frame"] = context.frame;
    j["complete"] = render_int(render, "result_complete") != 0;
    j["width"] = render_int(render, "result_width");
    j["height"] = render_int(render, "result_height");
    j["spp"] = render_int(render, "result_spp");
    j["spp_requested"] = render_int(render, "spp");
    j["integrator"] = render_string(render, "result_integrator");
    j["strategies"] = render_string(render, "result_strategies");
    j["threads"] = render_int(render, "result_threads");
    j["seed"] = static_cast<unsigned long long>(render_int(render, "seed"));
    j["camera"] = render_string(render, "result_camera");
    j["triangles"] = scene.triangles;
    j["seconds"] = {{"load", t.load},         {"build", t.build}, {"render", t.render},
                    {"denoise", t.denoise}, {"write", t.write}, {"total", t.total}};
    j["samples_per_second"] = t.render > 0 ? samples / t.render : 0.0;
    j["rays"] = render_int(render, "result_rays");
    j["rays_per_second"] = t.render > 0 ? rays / t.render : 0.0;
    j["nonfinite_samples"] = render_int(render, "result_nonfinite_samples");
    j["peak_rss_bytes"] = peak;
    j["outputs"] = context.outputs;
    nlohmann::ordered_json repaired = nlohmann::ordered_json::object();
    for (const auto& [key, count] : scene.repaired) repaired[key] = count;
    j["repaired"] = repaired;
    j["features"] = scene.features;
    // File names need not be UTF-8: a byte that is not is written as U+FFFD rather than failing.
    return j.dump(2, ' ', false, nlohmann::ordered_json::error_handler_t::replace) + "\n";
}

void write_stats_json(const std::string& path, VeachDevice device, const SceneFacts& scene, VeachRender render,
                      const Timings& t, const StatsContext& context) {
    const std::string text = stats_json(device, scene, render, t, context);
    // Through the library's atomic writer, as images are: never a torn file under `path`.
    if (veachWriteFile(device, path.c_str(), text.data(), text.size()) != VEACH_ERROR_NONE)
        throw std::runtime_error(veachGetLastError());
}

}  // namespace veach::cli
