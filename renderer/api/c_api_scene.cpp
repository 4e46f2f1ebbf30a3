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
#include "load/scene_info.h"

using veach::capi::ApiError;
using veach::capi::guarded;
using veach::capi::invalid;

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

// What a loaded scene reports, read-only; its options are the options table's scene rows.
const veach::capi::ResultNames k_results{"scene option",
                                         veach::OptionObject::Scene,
                                         {"triangles", "cameras", "repaired_invalid_indices",
                                          "repaired_nonfinite_triangles", "repaired_degenerate_triangles",
                                          "repaired_duplicate_triangles", "repaired_normals_replaced",
                                          "repaired_normals_normalized", "repaired_uvs_replaced",
                                          "repaired_colors_replaced", "repaired_lights_dropped"},
                                         {},
                                         {"source", "features", "warnings", "info"}};

const veach::OptionSpec* option(const char* name, veach::OptionKind wanted) {
    return veach::capi::lookup_option(k_results, name, wanted);
}

// Sets a scene row before the load (the scene's mutex held).
void set_scene_option(VeachScene scene, const veach::OptionSpec* spec, const veach::OptionValue& value,
                      const char* function) {
    check_not_loaded(scene, function);
    veach::OptionTargets targets{&scene->m_options, nullptr, nullptr, nullptr};
    try {
        veach::set_option(*spec, targets, value);
    } catch (const std::invalid_argument& e) {
        throw invalid(e.what());
    }
}

veach::OptionValue get_scene_option(VeachScene scene, const veach::OptionSpec& spec) {
    veach::OptionTargets targets{&scene->m_options, nullptr, nullptr, nullptr};
    return veach::get_option(spec, targets);
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
        const veach::OptionSpec* spec = option(name, veach::OptionKind::Int);
        if (!spec) throw invalid("scene option '" + std::string(name) + "' is read-only");
        std::lock_guard<std::mutex> lock(scene->m_mutex);
        set_scene_option(scene, spec, veach::OptionValue::of_int(value), "veachSetSceneInt");
        return VEACH_ERROR_NONE;
    });
}

VEACH_API VeachError veachSetSceneFloat(VeachScene scene, const char* name, double value) {
    return guarded<VeachError>(scene ? scene->m_device : nullptr, VEACH_ERROR_INVALID_ARGUMENT, [&] {
        check_scene(scene, "veachSetSceneFloat");
        const veach::OptionSpec* spec = option(name, veach::OptionKind::Float);
        if (!spec) throw invalid("scene option '" + std::string(name) + "' is read-only");
        std::string n = name;
        std::lock_guard<std::mutex> lock(scene->m_mutex);
        if (n == "time" && scene->m_loaded) {
            // A sequence: the loaded scene posed at another time, its file never read again.
            veach::SceneLoadOptions probe = scene->m_options;
            veach::OptionTargets targets{&probe, nullptr, nullptr, nullptr};
            try {
                veach::set_option(*spec, targets, veach::OptionValue::of_float(value));  // the range
            } catch (const std::invalid_argument& e) {
                throw invalid(e.what());
            }
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
        set_scene_option(scene, spec, veach::OptionValue::of_float(value), "veachSetSceneFloat");
        return VEACH_ERROR_NONE;
    });
}

VEACH_API VeachError veachSetSceneString(VeachScene scene, const char* name, const char* value) {
    return guarded<VeachError>(scene ? scene->m_device : nullptr, VEACH_ERROR_INVALID_ARGUMENT, [&] {
        check_scene(scene, "veachSetSceneString");
        const veach::OptionSpec* spec = option(name, veach::OptionKind::String);
        if (!spec) throw invalid("scene option '" + std::string(name) + "' is read-only");
        std::lock_guard<std::mutex> lock(scene->m_mutex);
        set_scene_option(scene, spec, veach::OptionValue::of_string(value ? value : ""), "veachSetSceneString");
        return VEACH_ERROR_NONE;
    });
}

VEACH_API VeachError veachGetSceneInt(VeachScene scene, const char* name, long long* value) {
    return guarded<VeachError>(scene ? scene->m_device : nullptr, VEACH_ERROR_INVALID_ARGUMENT, [&] {
        check_scene(scene, "veachGetSceneInt");
        const veach::OptionSpec* spec = option(name, veach::OptionKind::Int);
        if (!value) throw invalid("veachGetSceneInt: null value pointer");
        std::string n = name;
        std::lock_guard<std::mutex> lock(scene->m_mutex);
        if (spec) {
            *value = get_scene_option(scene, *spec).i;
        } else {
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
        const veach::OptionSpec* spec = option(name, veach::OptionKind::Float);
        if (!value) throw invalid("veachGetSceneFloat: null value pointer");
        std::lock_guard<std::mutex> lock(scene->m_mutex);
        *value = get_scene_option(scene, *spec).f;  // every scene float is an option
        return VEACH_ERROR_NONE;
    });
}

VEACH_API VeachError veachGetSceneString(VeachScene scene, const char* name, char* buffer, size_t size,
                                         size_t* length) {
    return guarded<VeachError>(scene ? scene->m_device : nullptr, VEACH_ERROR_INVALID_ARGUMENT, [&] {
        check_scene(scene, "veachGetSceneString");
        const veach::OptionSpec* spec = option(name, veach::OptionKind::String);
        if (!buffer && size > 0) throw invalid("veachGetSceneString: null buffer");
        std::string n = name, value;
        std::lock_guard<std::mutex> lock(scene->m_mutex);
        if (spec)
            value = get_scene_option(scene, *spec).s;
        else {
            check_loaded(scene, "veachGetSceneString");
            if (n == "source")
                value = scene->m_source;
            else if (n == "features") {
                for (const std::string& f : scene->m_load.scene.features.names()) value += (value.empty() ? "" : "\n") + f;
            } else if (n == "info") {
                value = veach::scene_info_json(scene->m_load.scene);
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
