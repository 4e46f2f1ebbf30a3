// The C API's version, errors and devices (scenes are in c_api_scene.cpp, renders in
// c_api_render.cpp).
//
// The boundary contract: every entry point catches everything (guarded()), reports the failure
// through the device's callback and this thread's last error, and returns a neutral value. The
// last error is thread_local rather than per device so that a host can ask "what went wrong" on
// the thread that made the call, as with errno, even when the call had no device (a null handle).
#include <algorithm>
#include <cstring>
#include <new>
#include <stdexcept>

#include "api/c_api_handles.h"
#include "job/render_job.h"
#include "film/film_checkpoint.h"
#include "film/film_part.h"
#include "importers/importer.h"
#include "integrators/integrator.h"
#include "options/option_table.h"
#include "output/atomic_file.h"
#include "output/display_transform.h"
#include "scene/scene_content_error.h"

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
    } catch (const CheckpointWriteError& e) {
        // Before CheckpointError, its base: failing to write is an output fault (the CLI's exit 3),
        // a checkpoint that cannot be read or belongs to another render is bad input (exit 2).
        message = e.what();
        return VEACH_ERROR_OUTPUT;
    } catch (const PartError& e) {
        message = e.what();
        return VEACH_ERROR_BAD_INPUT;
    } catch (const CheckpointError& e) {
        message = e.what();
        return VEACH_ERROR_BAD_INPUT;
    } catch (const OutputError& e) {
        message = e.what();
        return VEACH_ERROR_OUTPUT;
    } catch (const SceneContentError& e) {  // before invalid_argument, its base
        message = e.what();
        return VEACH_ERROR_BAD_INPUT;
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

void copy_string(const std::string& value, char* buffer, size_t size, size_t* length) {
    if (length) *length = value.size();
    if (!buffer || size == 0) return;
    size_t n = std::min(value.size(), size - 1);
    std::memcpy(buffer, value.data(), n);
    buffer[n] = '\0';
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
    // Outside the lock: the callback may call back into the API. A call of its that fails
    // again is not reported to it (the last error still holds it): a callback that logs through
    // a failing call would otherwise recurse until the stack ends.
    thread_local bool in_callback = false;
    if (!fn || in_callback) return;
    in_callback = true;
    struct Reset {
        ~Reset() { in_callback = false; }
    } reset;
    fn(user, code, message.c_str());
}

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

VEACH_API VeachError veachGetDeviceInt(VeachDevice device, const char* name, long long* value) {
    return guarded<VeachError>(device, VEACH_ERROR_INVALID_ARGUMENT, [&] {
        if (!device) throw veach::capi::invalid("veachGetDeviceInt: null device");
        if (!value) throw veach::capi::invalid("veachGetDeviceInt: null value pointer");
        std::string n = name ? name : "";
        if (n == "peak_memory_bytes")
            *value = static_cast<long long>(veach::peak_resident_bytes());
        else
            throw veach::capi::invalid("unknown device int '" + n + "' (known: peak_memory_bytes)");
        return VEACH_ERROR_NONE;
    });
}

namespace {

std::string lines(const std::vector<std::string>& items) {
    std::string out;
    for (const std::string& i : items) out += (out.empty() ? "" : "\n") + i;
    return out;
}

}  // namespace

VEACH_API VeachError veachGetDeviceString(VeachDevice device, const char* name, char* buffer, size_t size,
                                          size_t* length) {
    return guarded<VeachError>(device, VEACH_ERROR_INVALID_ARGUMENT, [&] {
        if (!device) throw veach::capi::invalid("veachGetDeviceString: null device");
        if (!buffer && size > 0) throw veach::capi::invalid("veachGetDeviceString: null buffer");
        std::string n = name ? name : "";
        std::string value;
        if (n == "integrators")
            value = lines(veach::integrator_names());
        else if (n == "filters")
            value = lines(veach::filter_names());
        else if (n == "passes")
            value = lines(veach::known_passes());
        else if (n == "exr_codecs")
            value = lines(veach::exr_codec_names());
        else if (n == "options")
            value = veach::option_table_json();
        else if (n.rfind("color_", 0) == 0) {
            // Read on every call: $OCIO may change between calls, and listing is rare.
            veach::ColorConfigInfo info;
            try {
                info = veach::describe_color_config();
            } catch (const std::exception& e) {
                throw ApiError{VEACH_ERROR_BAD_INPUT, e.what()};
            }
            if (n == "color_config")
                value = info.source;
            else if (n == "color_displays")
                value = lines(info.displays);
            else if (n == "color_looks")
                value = lines(info.looks);
            else if (n.rfind("color_views:", 0) == 0) {
                std::string display = n.substr(12);
                bool found = false;
                for (const auto& [d, views] : info.views)
                    if (d == display) value = lines(views), found = true;
                if (!found) throw veach::capi::invalid("no display '" + display + "' in the colour config");
            } else
                throw veach::capi::invalid("unknown device string '" + n + "'");
        } else
            throw veach::capi::invalid("unknown device string '" + n +
                                       "' (known: integrators, filters, passes, exr_codecs, options, color_config, "
                                       "color_displays, color_looks, color_views:DISPLAY)");
        veach::capi::copy_string(value, buffer, size, length);
        return VEACH_ERROR_NONE;
    });
}

VEACH_API VeachError veachWriteFile(VeachDevice device, const char* path, const void* data, size_t size) {
    return guarded<VeachError>(device, VEACH_ERROR_OUTPUT, [&] {
        if (!device) throw veach::capi::invalid("veachWriteFile: null device");
        if (!path || !*path) throw veach::capi::invalid("veachWriteFile: empty path");
        if (!data && size > 0) throw veach::capi::invalid("veachWriteFile: null data");
        veach::write_file_atomically(path, data ? data : "", size);
        return VEACH_ERROR_NONE;
    });
}

VEACH_API VeachError veachCheckFile(VeachDevice device, const char* path) {
    return guarded<VeachError>(device, VEACH_ERROR_OUTPUT, [&] {
        if (!device) throw veach::capi::invalid("veachCheckFile: null device");
        if (!path || !*path) throw veach::capi::invalid("veachCheckFile: empty path");
        veach::check_writable(path);
        return VEACH_ERROR_NONE;
    });
}

}  // extern "C"
