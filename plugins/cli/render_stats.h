// `--stats-json FILE`: what one render did, as JSON (nlohmann-json, so every string is escaped
// and every number is a JSON number), written through the library's atomic writer.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "veach/veach.h"

namespace veach::cli {

struct Timings {
    double load = 0, build = 0, render = 0, denoise = 0, write = 0, total = 0;
};

// What --stats-json reports of the scene, read when the frame's render ends: a sequence writes
// frame N's file while the scene is already posed for frame N+1.
struct SceneFacts {
    long long triangles = 0;
    std::vector<std::pair<const char*, long long>> repaired;
    std::vector<std::string> features;
};
SceneFacts scene_facts(VeachScene scene);

// What the command knows of the render beside the library: the input, the files written, the
// frame (when animated).
struct StatsContext {
    std::string input;
    std::vector<std::string> outputs;
    bool has_frame = false;
    long long frame = 0;
};

// The stats as JSON text: input, version, frame, complete, width, height, spp (every pixel
// reached), spp_requested, integrator, threads (the worker threads the render ran on), seed,
// camera, triangles, seconds {load, build, render, denoise, write, total}, samples and rays per second,
// rays, nonfinite_samples, peak_rss_bytes, outputs, repaired {...}, features [...].
std::string stats_json(VeachDevice device, const SceneFacts& scene, VeachRender render, const Timings& t,
                       const StatsContext& context);

// Writes stats_json to `path` atomically; throws std::runtime_error with the library's message.
void write_stats_json(const std::string& path, VeachDevice device, const SceneFacts& scene, VeachRender render,
                      const Timings& t, const StatsContext& context);

}  // namespace veach::cli
