// The C API's scenes: options that shape a scene before it is loaded (glTF scene index, variant,
// spot profile, default material, environment, time, shutter) parsed into SceneLoadOptions, the
// load and re-pose (load/scene_load.h does both), and what the load found (triangles, repairs,
// features, warnings).
//
// Why the options belong to the scene and not to a render: a scene is imported once and shared
// read-only by any number of renders, and every one of these options changes what is imported
// (materials, lights) or what lights it (the environment is a light in the LightSet). Putting
// them on a render would mean copying the scene per render.
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <stdexcept>

#include "api/c_api_handles.h"

using veach::capi::ApiError;
using veach::capi::guarded;
using veach::capi::invalid;
using veach::capi::OptionKind;
using veach::capi::OptionTable;

VeachSceneImpl::~VeachSceneImpl() { veachReleaseDevice(m_device); }

namespace {

void check_scene(VeachScene scene, const char* function) {
    if (!scene) throw invalid(std::string(function) + ": null scene");
}

void check_not_loaded(VeachScene scene, const char* function) {
    if (scene->m_loaded)
        throw ApiError{VEACH_ERROR_INVALID_OPERATION,
                       std::string(function) + ": the scene is loaded; set scene options before veachLoadScene*"};
}

void check_loaded(VeachScene scene, const char* function) {
    if (!scene->m_loaded)
        throw ApiError{VEACH_ERROR_INVALID_OPERATION, std::string(function) + ": the scene is not loaded"};
}

// The options' names by type (OptionTable, c_api_handles.h).
const OptionTable k_options{"scene option",
                            {"scene_index", "allow_external_files", "triangles", "cameras", "repaired_invalid_indices",
                             "repaired_nonfinite_triangles", "repaired_degenerate_triangles",
                             "repaired_duplicate_triangles", "repaired_normals_replaced", "repaired_normals_normalized",
                             "repaired_uvs_replaced", "repaired_colors_replaced", "repaired_lights_dropped"},
                            {"env_strength", "env_rotate", "time"},
                            {"variant", "spot_falloff", "default_material", "env_map", "env_color", "animation", "shutter",
                             "source", "features", "warnings"}};

void check_kind(const char* name, OptionKind wanted) { k_options.check(name, wanted); }

bool is_result(const std::string& n) {
    return n == "triangles" || n == "cameras" || n.rfind("repaired_", 0) == 0 || n == "source" || n == "features" ||
           n == "warnings";
}

// "R,G,B" with three finite numbers >= 0.
veach::Rgb parse_color(const std::string& v) {
    float c[3];
    const char* p = v.c_str();
    for (int k = 0; k < 3; ++k) {
        char* end = nullptr;
        double x = std::strtod(p, &end);
        if (end == p || !std::isfinite(x) || x < 0 || x > 1e30 || *end != (k < 2 ? ',' : '\0'))
            throw invalid("scene option 'env_color' expects R,G,B with numbers >= 0 (e.g. 0.8,0.9,1), not '" + v + "'");
        c[k] = static_cast<float>(x);
        p = end + 1;
    }
    return veach::Rgb(c[0], c[1], c[2]);
}

// "OPEN,CLOSE": two finite numbers of seconds, open <= close (equal: no motion blur).
void parse_shutter(const std::string& v, double* open, double* close) {
    double x[2];
    const char* p = v.c_str();
    for (int k = 0; k < 2; ++k) {
        char* end = nullptr;
        x[k] = std::strtod(p, &end);
        if (end == p || !std::isfinite(x[k]) || std::abs(x[k]) > 1e9 || *end != (k == 0 ? ',' : '\0'))
            throw invalid("scene option 'shutter' expects OPEN,CLOSE in seconds relative to 'time' (e.g. "
                          "-0.0104,0.0104), not '" + v + "'");
        p = end + 1;
    }
    if (x[0] > x[1]) throw invalid("scene option 'shutter': it opens after it closes ('" + v + "')");
    *open = x[0];
    *close = x[1];
}

template <class Load>
VeachError load(VeachScene scene, const char* function, Load&& body) {
    check_scene(scene, function);
    std::lock_guard<std::mutex> lock(scene->m_mutex);
    check_not_loaded(scene, function);
    // Before the import spends its time.
    if (scene->m_options.motion_blur() && !scene->m_options.import.animate)
        throw ApiError{VEACH_ERROR_INVALID_OPERATION,
                       std::string(function) + ": scene option 'shutter' needs 'time' (motion blur is the animation "
                                               "across the shutter)"};
    body();
    return VEACH_ERROR_NONE;
}

VeachError load_file(VeachScene scene, const char* path) {
    return load(scene, "veachLoadSceneFile", [&] {
        if (!path || !*path) throw invalid("veachLoadSceneFile: empty path");
        scene->m_load = veach::load_scene_file(path, scene->m_options);
        scene->m_source = path;
        scene->m_loaded = true;
    });
}

VeachError load_memory(VeachScene scene, const void* data, size_t size, const char* format, const char* base_dir) {
    return load(scene, "veachLoadSceneMemory", [&] {
        if (!data || size == 0) throw invalid("veachLoadSceneMemory: empty buffer");
        if (!format || !*format) throw invalid("veachLoadSceneMemory: no format");
        const auto* bytes = static_cast<const uint8_t*>(data);
        std::vector<uint8_t> copy(bytes, bytes + size);
        std::string base = base_dir ? base_dir : "";
        scene->m_load = veach::load_scene_memory(copy, format, base, scene->m_options);
        scene->m_loaded = true;
    });
}

VeachScene new_scene(VeachDevice device) {
    auto* s = new VeachSceneImpl();
    veachRetainDevice(device);
    s->m_device = device;
    return s;
}

}  // namespace

extern "C" {

VEACH_API VeachScene veachNewScene(VeachDevice device) {
    return guarded<VeachScene>(device, nullptr, [&] {
        if (!device) throw invalid("veachNewScene: null device");
        return new_scene(device);
    });
}

VEACH_API VeachScene veachNewSceneFromFile(VeachDevice device, const char* path) {
    return guarded<VeachScene>(device, nullptr, [&]() -> VeachScene {
        if (!device) throw invalid("veachNewSceneFromFile: null device");
        if (!path || !*path) throw invalid("veachNewSceneFromFile: empty path");
        VeachScene s = new_scene(device);
        try {
            load_file(s, path);
        } catch (...) {
            veachReleaseScene(s);
            throw;
        }
        return s;
    });
}

VEACH_API VeachScene veachNewSceneFromMemory(VeachDevice device, const void* data, size_t size, const char* format,
                                             const char* base_dir) {
    return guarded<VeachScene>(device, nullptr, [&]() -> VeachScene {
        if (!device) throw invalid("veachNewSceneFromMemory: null device");
        if (!data || size == 0) throw invalid("veachNewSceneFromMemory: empty buffer");
        if (!format || !*format) throw invalid("veachNewSceneFromMemory: no format");
        VeachScene s = new_scene(device);
        try {
            load_memory(s, data, size, format, base_dir);
        } catch (...) {
            veachReleaseScene(s);
            throw;
        }
        return s;
    });
}

VEACH_API VeachError veachLoadSceneFile(VeachScene scene, const char* path) {
    return guarded<VeachError>(scene ? scene->m_device : nullptr, VEACH_ERROR_BAD_INPUT,
                               [&] { return load_file(scene, path); });
}

VEACH_API VeachError veachLoadSceneMemory(VeachScene scene, const void* data, size_t size, const char* format,
                                          const char* base_dir) {
    return guarded<VeachError>(scene ? scene->m_device : nullptr, VEACH_ERROR_BAD_INPUT,
                               [&] { return load_memory(scene, data, size, format, base_dir); });
}

VEACH_API VeachError veachSetSceneInt(VeachScene scene, const char* name, long long value) {
    return guarded<VeachError>(scene ? scene->m_device : nullptr, VEACH_ERROR_INVALID_ARGUMENT, [&] {
        check_scene(scene, "veachSetSceneInt");
        check_kind(name, OptionKind::Int);
        std::string n = name;
        if (is_result(n)) throw invalid("scene option '" + n + "' is read-only");
        std::lock_guard<std::mutex> lock(scene->m_mutex);
        check_not_loaded(scene, "veachSetSceneInt");
        if (n == "scene_index") {
            if (value < -1 || value > std::numeric_limits<int>::max())
                throw invalid("scene option 'scene_index' must be -1 (the file's default) or a scene index");
            scene->m_options.import.scene_index = static_cast<int>(value);
        } else if (n == "allow_external_files") {
            if (value != 0 && value != 1) throw invalid("scene option 'allow_external_files' must be 0 or 1");
            scene->m_options.import.allow_external_files = value == 1;
        }
        return VEACH_ERROR_NONE;
    });
}

VEACH_API VeachError veachSetSceneFloat(VeachScene scene, const char* name, double value) {
    return guarded<VeachError>(scene ? scene->m_device : nullptr, VEACH_ERROR_INVALID_ARGUMENT, [&] {
        check_scene(scene, "veachSetSceneFloat");
        check_kind(name, OptionKind::Float);
        std::string n = name;
        if (!std::isfinite(value)) throw invalid("scene option '" + n + "' must be finite");
        std::lock_guard<std::mutex> lock(scene->m_mutex);
        if (n == "time" && scene->m_loaded) {
            // A sequence: the loaded scene posed at another time, its file never read again.
            if (std::abs(value) > 1e9) throw invalid("scene option 'time' must be in [-1e9, 1e9] seconds");
            if (!scene->m_options.import.animate)
                throw ApiError{VEACH_ERROR_INVALID_OPERATION,
                               "veachSetSceneFloat: the scene was loaded without a time; set 'time' before the load "
                               "to pose it at other times"};
            if (scene->m_renders_running > 0)
                throw ApiError{VEACH_ERROR_INVALID_OPERATION,
                               "veachSetSceneFloat: a render of this scene is running; set 'time' once it is done"};
            const double before = scene->m_options.time;
            scene->m_options.time = value;
            try {
                scene->m_prepared.note(veach::repose_scene(scene->m_load, scene->m_options));
            } catch (...) {
                scene->m_options.time = before;
                throw;
            }
            return VEACH_ERROR_NONE;
        }
        check_not_loaded(scene, "veachSetSceneFloat");
        if (n == "env_strength") {
            if (value < 0 || value > 1e30) throw invalid("scene option 'env_strength' must be in [0, 1e30]");
            scene->m_options.environment.strength = static_cast<float>(value);
        } else if (n == "env_rotate") {
            if (std::abs(value) > 1e6) throw invalid("scene option 'env_rotate' must be in [-1e6, 1e6] degrees");
            scene->m_options.environment.rotate_degrees = static_cast<float>(value);
        } else if (n == "time") {
            if (std::abs(value) > 1e9) throw invalid("scene option 'time' must be in [-1e9, 1e9] seconds");
            scene->m_options.import.animate = true;
            scene->m_options.time = value;
        }
        return VEACH_ERROR_NONE;
    });
}

VEACH_API VeachError veachSetSceneString(VeachScene scene, const char* name, const char* value) {
    return guarded<VeachError>(scene ? scene->m_device : nullptr, VEACH_ERROR_INVALID_ARGUMENT, [&] {
        check_scene(scene, "veachSetSceneString");
        check_kind(name, OptionKind::String);
        std::string n = name, v = value ? value : "";
        if (is_result(n)) throw invalid("scene option '" + n + "' is read-only");
        std::lock_guard<std::mutex> lock(scene->m_mutex);
        check_not_loaded(scene, "veachSetSceneString");
        veach::EnvironmentOptions& env = scene->m_options.environment;
        if (n == "variant")
            scene->m_options.import.variant = v;
        else if (n == "spot_falloff") {
            if (v == "auto")
                scene->m_options.import.spot_profile = veach::SpotProfile::Auto;
            else if (v == "blender")
                scene->m_options.import.spot_profile = veach::SpotProfile::Blender;
            else if (v == "gltf")
                scene->m_options.import.spot_profile = veach::SpotProfile::Gltf;
            else
                throw invalid("scene option 'spot_falloff' expects auto, blender or gltf, not '" + v + "'");
        } else if (n == "default_material") {
            if (v == "auto")
                scene->m_options.import.default_material = veach::DefaultMaterial::Auto;
            else if (v == "blender")
                scene->m_options.import.default_material = veach::DefaultMaterial::Blender;
            else if (v == "gltf")
                scene->m_options.import.default_material = veach::DefaultMaterial::Gltf;
            else
                throw invalid("scene option 'default_material' expects auto, blender or gltf, not '" + v + "'");
        } else if (n == "env_map") {
            if (!v.empty() && env.has_color)
                throw invalid("scene options 'env_map' and 'env_color' exclude each other");
            env.map_path = v;
        } else if (n == "env_color") {
            if (v.empty()) {
                env.has_color = false;
                env.color = veach::Rgb(1.0f);
            } else {
                if (!env.map_path.empty()) throw invalid("scene options 'env_map' and 'env_color' exclude each other");
                env.color = parse_color(v);
                env.has_color = true;
            }
            scene->m_env_color = v;
        } else if (n == "animation") {
            scene->m_options.import.animation = v.empty() ? "all" : v;  // checked against the file by the load
        } else if (n == "shutter") {
            double open = 0, close = 0;
            if (!v.empty()) parse_shutter(v, &open, &close);
            scene->m_options.shutter_open = open;
            scene->m_options.shutter_close = close;
            scene->m_shutter = v;
        }
        return VEACH_ERROR_NONE;
    });
}

VEACH_API VeachError veachGetSceneInt(VeachScene scene, const char* name, long long* value) {
    return guarded<VeachError>(scene ? scene->m_device : nullptr, VEACH_ERROR_INVALID_ARGUMENT, [&] {
        check_scene(scene, "veachGetSceneInt");
        check_kind(name, OptionKind::Int);
        if (!value) throw invalid("veachGetSceneInt: null value pointer");
        std::string n = name;
        std::lock_guard<std::mutex> lock(scene->m_mutex);
        if (n == "scene_index")
            *value = scene->m_options.import.scene_index;
        else if (n == "allow_external_files")
            *value = scene->m_options.import.allow_external_files ? 1 : 0;
        else {
            check_loaded(scene, "veachGetSceneInt");
            const veach::Scene& s = scene->m_load.scene;
            const veach::RepairCounts& r = s.repaired;
            auto count = [](uint64_t c) { return static_cast<long long>(c); };
            if (n == "triangles")
                *value = count(s.triangle_count());
            else if (n == "cameras")
                *value = count(s.cameras.size());
            else if (n == "repaired_invalid_indices")
                *value = count(r.invalid_indices);
            else if (n == "repaired_nonfinite_triangles")
                *value = count(r.nonfinite_triangles);
            else if (n == "repaired_degenerate_triangles")
                *value = count(r.degenerate_triangles);
            else if (n == "repaired_duplicate_triangles")
                *value = count(r.duplicate_triangles);
            else if (n == "repaired_normals_replaced")
                *value = count(r.normals_replaced);
            else if (n == "repaired_normals_normalized")
                *value = count(r.normals_normalized);
            else if (n == "repaired_uvs_replaced")
                *value = count(r.uvs_replaced);
            else if (n == "repaired_colors_replaced")
                *value = count(r.colors_replaced);
            else if (n == "repaired_lights_dropped")
                *value = count(r.lights_dropped);
        }
        return VEACH_ERROR_NONE;
    });
}

VEACH_API VeachError veachGetSceneFloat(VeachScene scene, const char* name, double* value) {
    return guarded<VeachError>(scene ? scene->m_device : nullptr, VEACH_ERROR_INVALID_ARGUMENT, [&] {
        check_scene(scene, "veachGetSceneFloat");
        check_kind(name, OptionKind::Float);
        if (!value) throw invalid("veachGetSceneFloat: null value pointer");
        std::string n = name;
        std::lock_guard<std::mutex> lock(scene->m_mutex);
        if (n == "env_strength")
            *value = scene->m_options.environment.strength;
        else if (n == "env_rotate")
            *value = scene->m_options.environment.rotate_degrees;
        else if (n == "time")
            *value = scene->m_options.import.animate ? scene->m_options.time : std::numeric_limits<double>::quiet_NaN();
        return VEACH_ERROR_NONE;
    });
}

VEACH_API VeachError veachGetSceneString(VeachScene scene, const char* name, char* buffer, size_t size,
                                         size_t* length) {
    return guarded<VeachError>(scene ? scene->m_device : nullptr, VEACH_ERROR_INVALID_ARGUMENT, [&] {
        check_scene(scene, "veachGetSceneString");
        check_kind(name, OptionKind::String);
        if (!buffer && size > 0) throw invalid("veachGetSceneString: null buffer");
        std::string n = name, value;
        std::lock_guard<std::mutex> lock(scene->m_mutex);
        if (n == "variant")
            value = scene->m_options.import.variant;
        else if (n == "spot_falloff")
            value = veach::spot_profile_name(scene->m_options.import.spot_profile);
        else if (n == "default_material")
            value = veach::default_material_name(scene->m_options.import.default_material);
        else if (n == "env_map")
            value = scene->m_options.environment.map_path;
        else if (n == "env_color")
            value = scene->m_env_color;
        else if (n == "animation")
            value = scene->m_options.import.animation;
        else if (n == "shutter")
            value = scene->m_shutter;
        else {
            check_loaded(scene, "veachGetSceneString");
            if (n == "source")
                value = scene->m_source;
            else if (n == "features") {
                for (const std::string& f : scene->m_load.scene.features.names()) value += (value.empty() ? "" : "\n") + f;
            } else if (n == "warnings") {
                for (const std::string& w : scene->m_load.scene.warnings) value += (value.empty() ? "" : "\n") + w;
            }
        }
        veach::capi::copy_string(value, buffer, size, length);
        return VEACH_ERROR_NONE;
    });
}

VEACH_API void veachRetainScene(VeachScene scene) {
    if (scene) scene->retain();
}

VEACH_API void veachReleaseScene(VeachScene scene) {
    if (scene && scene->release()) delete scene;
}

VEACH_API int veachGetSceneCameraCount(VeachScene scene) {
    return guarded<int>(nullptr, -1, [&] {
        check_scene(scene, "veachGetSceneCameraCount");
        return scene->m_loaded ? static_cast<int>(scene->m_load.scene.cameras.size()) : 0;
    });
}

VEACH_API const char* veachGetSceneCameraName(VeachScene scene, int index) {
    return guarded<const char*>(scene ? scene->m_device : nullptr, nullptr, [&]() -> const char* {
        check_scene(scene, "veachGetSceneCameraName");
        check_loaded(scene, "veachGetSceneCameraName");
        if (index < 0 || static_cast<size_t>(index) >= scene->m_load.scene.cameras.size())
            throw invalid("veachGetSceneCameraName: no camera " + std::to_string(index));
        return scene->m_load.scene.cameras[static_cast<size_t>(index)].name.c_str();
    });
}

}  // extern "C"
