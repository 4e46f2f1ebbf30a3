#include "scene_info.h"

#include <cstdio>
#include <string>

#include <nlohmann/json.hpp>

namespace veach::cli {
namespace {

std::string names(const nlohmann::json& list) {
    std::string out;
    for (size_t i = 0; i < list.size(); ++i) {
        const std::string name = list[i].get<std::string>();
        out += (i ? ", " : "") + (name.empty() ? "#" + std::to_string(i) : "'" + name + "'");
    }
    return out.empty() ? "none" : out;
}

std::string mib(long long bytes) {
    char text[32];
    std::snprintf(text, sizeof(text), "%.1f MiB", static_cast<double>(bytes) / (1024.0 * 1024.0));
    return text;
}

}  // namespace

int run_info_command(VeachDevice device, const InfoCommand& cmd) {
    VeachScene scene = veachNewScene(device);
    struct Release {
        VeachScene s = nullptr;
        VeachRender r = nullptr;
        ~Release() {
            veachReleaseRender(r);
            veachReleaseScene(s);
        }
    } release{scene};
    for (const ApiOption& o : cmd.scene_options)
        if (apply_scene_option(scene, o) != VEACH_ERROR_NONE) {
            std::fprintf(stderr, "veach: %s: %s\n", cmd.input.c_str(), veachGetLastError());
            return 2;
        }
    if (VeachError e = veachLoadSceneFile(scene, cmd.input.c_str()); e != VEACH_ERROR_NONE) {
        std::fprintf(stderr, "veach: %s\n", veachGetLastError());
        return e == VEACH_ERROR_BAD_INPUT || e == VEACH_ERROR_INVALID_ARGUMENT ? 2 : 3;
    }
    nlohmann::ordered_json info = nlohmann::ordered_json::parse(scene_string(scene, "info"));
    // The memory estimate is the render's own, for this size (the height from the first camera's
    // aspect ratio unless given).
    release.r = veachNewRender(scene);
    long long width = 0, height = 0, bytes = 0;
    if (!release.r || veachSetInt(release.r, "width", cmd.width) != VEACH_ERROR_NONE ||
        veachSetInt(release.r, "height", cmd.height) != VEACH_ERROR_NONE ||
        veachGetInt(release.r, "estimated_memory_bytes", &bytes) != VEACH_ERROR_NONE) {
        std::fprintf(stderr, "veach: %s: %s\n", cmd.input.c_str(), veachGetLastError());
        return 3;
    }
    veachGetInt(release.r, "width", &width);
    veachGetInt(release.r, "height", &height);
    info["render_memory"] = {{"width", width}, {"height", height}, {"bytes", bytes}};
    if (cmd.json) {
        std::printf("%s\n", info.dump(1, ' ', false, nlohmann::ordered_json::error_handler_t::replace).c_str());
        return 0;
    }
    std::printf("%s\n", info["source"].get<std::string>().c_str());
    std::string scenes;
    for (const auto& s : info["scenes"]) {
        const std::string name = s["name"].get<std::string>();
        scenes += (scenes.empty() ? "" : ", ") + std::to_string(s["index"].get<int>()) +
                  (name.empty() ? "" : " '" + name + "'") + (s["default"].get<bool>() ? " (default)" : "");
    }
    std::printf("  scenes:      %s\n", scenes.empty() ? "none" : scenes.c_str());
    std::printf("  variants:    %s\n", names(info["variants"]).c_str());
    std::printf("  animations:  %s\n", names(info["animations"]).c_str());
    std::string cameras;
    for (const auto& c : info["cameras"])
        cameras += (cameras.empty() ? "'" : ", '") + c["name"].get<std::string>() + "' (" +
                   c["type"].get<std::string>() + ")";
    std::printf("  cameras:     %s\n", cameras.empty() ? "none (a default view)" : cameras.c_str());
    const auto& l = info["lights"];
    std::printf("  lights:      %lld point, %lld spot, %lld sun, %lld area, %lld emissive meshes (%lld triangles), "
                "environment %s\n",
                l["point"].get<long long>(), l["spot"].get<long long>(), l["sun"].get<long long>(),
                l["area"].get<long long>(), l["emissive_meshes"].get<long long>(),
                l["emissive_triangles"].get<long long>(), l["environment"].get<std::string>().c_str());
    std::printf("  geometry:    %lld triangles rendered (%lld in %lld meshes), %lld instances, %lld materials\n",
                info["triangles"].get<long long>(), info["mesh_triangles"].get<long long>(),
                info["meshes"].get<long long>(), info["instances"].get<long long>(),
                info["materials"].get<long long>());
    std::printf("  textures:    %zu\n", info["textures"].size());
    for (const auto& t : info["textures"])
        std::printf("    %s %dx%d (%s)\n", t["name"].get<std::string>().empty() ? "(unnamed)" : t["name"].get<std::string>().c_str(),
                    t["width"].get<int>(), t["height"].get<int>(), mib(t["bytes"].get<long long>()).c_str());
    std::string features;
    for (const auto& f : info["features"]) features += (features.empty() ? "" : ", ") + f.get<std::string>();
    std::printf("  features:    %s\n", features.empty() ? "none" : features.c_str());
    std::printf("  render:      %lldx%lld needs about %s beyond the scene\n", width, height, mib(bytes).c_str());
    for (const auto& w : info["warnings"]) std::printf("  warning:     %s\n", w.get<std::string>().c_str());
    return 0;
}

}  // namespace veach::cli
