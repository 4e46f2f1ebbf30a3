#include "option_report.h"

#include <cmath>
#include <cstdio>

#include <nlohmann/json.hpp>

namespace veach::cli {

int print_options(VeachDevice device, bool json, bool markdown) {
    const std::vector<TableOption> table = read_option_table(device);
    if (json) {
        std::printf("%s\n", nlohmann::json::parse(device_string(device, "options")).dump(1).c_str());
        return 0;
    }
    if (markdown) {
        std::fputs(option_reference_markdown(table).c_str(), stdout);
        return 0;
    }
    for (const TableOption& row : table) {
        std::string flag = row.flag.empty() ? "(no flag)" : row.flag;
        std::printf("%-22s %-6s %-6s default %-8s %s  %s\n", row.name.c_str(), row.object.c_str(), row.type.c_str(),
                    row.default_text.empty() ? "\"\"" : row.default_text.c_str(), flag.c_str(), row.help.c_str());
    }
    return 0;
}

int print_dry_run(VeachDevice device, const RenderCommand& cmd) {
    static const char k_empty_gltf[] = R"({"asset": {"version": "2.0"}, "scenes": [{"nodes": []}], "scene": 0})";
    VeachScene scene = veachNewScene(device);
    VeachScene empty = veachNewSceneFromMemory(device, k_empty_gltf, sizeof(k_empty_gltf) - 1, "gltf", nullptr);
    VeachRender render = empty ? veachNewRender(empty) : nullptr;
    veachReleaseScene(empty);
    int rc = 0;
    nlohmann::ordered_json out;
    if (!scene || !render) {
        std::fprintf(stderr, "veach: %s\n", veachGetLastError());
        rc = 3;
    } else {
        for (const ApiOption& o : cmd.scene_options) apply_scene_option(scene, o);
        // Options only a scene can judge (a camera name) stay as the empty scene refuses them.
        for (const ApiOption& o : cmd.render_options) apply_render_option(render, o);
        nlohmann::ordered_json scene_values, render_values;
        for (const TableOption& row : read_option_table(device)) {
            const bool is_scene = row.object == "scene";
            const char* n = row.name.c_str();
            nlohmann::ordered_json& to = is_scene ? scene_values : render_values;
            if (row.type == "int") {
                long long v = 0;
                is_scene ? veachGetSceneInt(scene, n, &v) : veachGetInt(render, n, &v);
                to[row.name] = v;
            } else if (row.type == "float") {
                double v = 0;
                is_scene ? veachGetSceneFloat(scene, n, &v) : veachGetFloat(render, n, &v);
                to[row.name] = std::isfinite(v) ? nlohmann::ordered_json(v) : nlohmann::ordered_json(nullptr);
            } else {
                to[row.name] = is_scene ? scene_string(scene, n) : render_string(render, n);
            }
        }
        out["inputs"] = cmd.inputs;
        out["outputs"] = cmd.outputs;
        out["scene"] = scene_values;
        out["render"] = render_values;
        std::printf("%s\n", out.dump(1).c_str());
    }
    veachReleaseRender(render);
    veachReleaseScene(scene);
    return rc;
}

}  // namespace veach::cli
