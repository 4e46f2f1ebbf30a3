// The C API's version, errors, devices and scenes (renders are in c_api_render.cpp).
//
// The boundary contract: every entry point catches everything (guarded()), reports the failure
// through the device's callback and this thread's last error, and returns a neutral value. The
// last error is thread_local rather than per device so that a host can ask "what went wrong" on
// the thread that made the call, as with errno, even when the call had no device (a null handle).
#include <cstring>
#include <new>
#include <stdexcept>

#include "scene/scene_repair.h"
#include "api/c_api_handles.h"
#include "importers/importer.h"

static_assert(VEACH_VERSION_MAJOR == VEACH_PROJECT_VERSION_MAJOR &&
                  VEACH_VERSION_MINOR == VEACH_PROJECT_VERSION_MINOR &&
                  VEACH_VERSION_PATCH == VEACH_PROJECT_VERSION_PATCH,
              "veach.h's version macros must match project(VERSION) in CMakeLists.txt");

namespace veach::capi {
namespace {

struct LastError {
    VeachError code = VEACH_ERROR_NONE;
    std::string message;
};

LastError& last_error() {
    thread_local LastError error;
    return error;
}

}  // namespace

void clear_last_error() {
    LastError& e = last_error();
    e.code = VEACH_ERROR_NONE;
    e.message.clear();
}

void set_last_error(VeachError code, const std::string& message) {
    LastError& e = last_error();
    e.code = code;
    try {
        e.message = message;
    } catch (...) {
        e.message.clear();  // out of memory: the code still says what happened
    }
}

VeachError code_of_current_exception(std::string& message) {
    try {
        throw;
    } catch (const ApiError& e) {
        message = e.message;
        return e.code;
    } catch (const ImportError& e) {
        message = e.what();
        return VEACH_ERROR_BAD_INPUT;
    } catch (const OutputError& e) {
        message = e.what();
        return VEACH_ERROR_OUTPUT;
    } catch (const std::invalid_argument& e) {
        message = e.what();
        return VEACH_ERROR_INVALID_ARGUMENT;
    } catch (const std::bad_alloc&) {
        message = "out of memory";
        return VEACH_ERROR_OUT_OF_MEMORY;
    } catch (const std::exception& e) {
        message = e.what();
        return VEACH_ERROR_UNKNOWN;
    } catch (...) {
        message = "unknown error";
        return VEACH_ERROR_UNKNOWN;
    }
}

}  // namespace veach::capi

using veach::capi::ApiError;
using veach::capi::guarded;

void VeachDeviceImpl::report(VeachError code, const std::string& message) {
    veach::capi::set_last_error(code, message);
    VeachErrorFunction fn;
    void* user;
    {
        std::lock_guard<std::mutex> lock(m_mutex);
        fn = m_error_fn;
        user = m_error_user;
    }
    // Outside the lock: the callback may call back into the API.
    if (fn) fn(user, code, message.c_str());
}

VeachSceneImpl::~VeachSceneImpl() { veachReleaseDevice(m_device); }

extern "C" {

VEACH_API int veachGetVersion(void) { return VEACH_VERSION; }

VEACH_API const char* veachGetVersionString(void) { return VEACH_VERSION_STRING; }

VEACH_API const char* veachGetLastError(void) { return veach::capi::last_error().message.c_str(); }

VEACH_API VeachError veachGetLastErrorCode(void) { return veach::capi::last_error().code; }

VEACH_API VeachDevice veachNewDevice(void) {
    return guarded<VeachDevice>(nullptr, nullptr, [] { return new VeachDeviceImpl(); });
}

VEACH_API void veachRetainDevice(VeachDevice device) {
    if (device) device->retain();
}

VEACH_API void veachReleaseDevice(VeachDevice device) {
    if (device && device->release()) delete device;
}

VEACH_API void veachSetDeviceErrorFunction(VeachDevice device, VeachErrorFunction fn, void* user) {
    guarded<bool>(nullptr, false, [&] {
        if (!device) throw ApiError{VEACH_ERROR_INVALID_ARGUMENT, "veachSetDeviceErrorFunction: null device"};
        std::lock_guard<std::mutex> lock(device->m_mutex);
        device->m_error_fn = fn;
        device->m_error_user = user;
        return true;
    });
}

namespace {

VeachScene adopt_scene(VeachDevice device, veach::Scene&& scene) {
    // What the CLI does after loading, so every front end renders the same image: a scene with
    // no light gets the uniform white sky glTF viewers use, and a scene far from the origin is
    // moved to it (scene_repair.h).
    veach::light_unlit_scene(scene);
    veach::rebase_scene(scene);
    auto* s = new VeachSceneImpl();
    s->m_scene = std::move(scene);
    veachRetainDevice(device);
    s->m_device = device;
    return s;
}

}  // namespace

VEACH_API VeachScene veachNewSceneFromFile(VeachDevice device, const char* path) {
    return guarded<VeachScene>(device, nullptr, [&] {
        if (!device) throw ApiError{VEACH_ERROR_INVALID_ARGUMENT, "veachNewSceneFromFile: null device"};
        if (!path || !*path) throw ApiError{VEACH_ERROR_INVALID_ARGUMENT, "veachNewSceneFromFile: empty path"};
        return adopt_scene(device, veach::import_scene(path));
    });
}

VEACH_API VeachScene veachNewSceneFromMemory(VeachDevice device, const void* data, size_t size, const char* format,
                                             const char* base_dir) {
    return guarded<VeachScene>(device, nullptr, [&] {
        if (!device) throw ApiError{VEACH_ERROR_INVALID_ARGUMENT, "veachNewSceneFromMemory: null device"};
        if (!data || size == 0) throw ApiError{VEACH_ERROR_INVALID_ARGUMENT, "veachNewSceneFromMemory: empty buffer"};
        if (!format || !*format) throw ApiError{VEACH_ERROR_INVALID_ARGUMENT, "veachNewSceneFromMemory: no format"};
        const auto* bytes = static_cast<const uint8_t*>(data);
        std::vector<uint8_t> copy(bytes, bytes + size);
        return adopt_scene(device, veach::import_scene_from_memory(copy, format, base_dir ? base_dir : ""));
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
        if (!scene) throw ApiError{VEACH_ERROR_INVALID_ARGUMENT, "veachGetSceneCameraCount: null scene"};
        return static_cast<int>(scene->m_scene.cameras.size());
    });
}

VEACH_API const char* veachGetSceneCameraName(VeachScene scene, int index) {
    return guarded<const char*>(scene ? scene->m_device : nullptr, nullptr, [&]() -> const char* {
        if (!scene) throw ApiError{VEACH_ERROR_INVALID_ARGUMENT, "veachGetSceneCameraName: null scene"};
        if (index < 0 || static_cast<size_t>(index) >= scene->m_scene.cameras.size())
            throw ApiError{VEACH_ERROR_INVALID_ARGUMENT,
                           "veachGetSceneCameraName: no camera " + std::to_string(index)};
        return scene->m_scene.cameras[static_cast<size_t>(index)].name.c_str();
    });
}

}  // extern "C"
