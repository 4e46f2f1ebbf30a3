// Veach: a header-only C++ wrapper over the C API (veach.h). RAII handles that retain and release,
// and exceptions on the C++ side: every failing call throws veach::Error with the library's code
// and message. Nothing C++ crosses the library boundary, so this header works with any compiler
// that can call the C ABI.
//
//   veach::Device device;
//   veach::Scene scene(device, "cornell.gltf");
//   (or veach::Scene scene(device); scene.set("env_color", "1,1,1").set("variant", "red"); scene.load(path);)
//   veach::Render render(scene);
//   render.set("width", 512).set("spp", 64).set("integrator", "pt");
//   render.on_progress([](double f, double eta) { return true; });
//   render.render();
//   render.write_image("out.png");
#pragma once

#include <cstddef>
#include <functional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "veach/veach.h"

namespace veach {

class Error : public std::runtime_error {
public:
    Error(VeachError code, const std::string& message) : std::runtime_error(message), m_code(code) {}
    VeachError code() const { return m_code; }

private:
    VeachError m_code;
};

namespace detail {

[[noreturn]] inline void throw_last_error(VeachError fallback = VEACH_ERROR_UNKNOWN) {
    VeachError code = veachGetLastErrorCode();
    throw Error(code != VEACH_ERROR_NONE ? code : fallback, veachGetLastError());
}

inline void check(VeachError code) {
    if (code != VEACH_ERROR_NONE) throw_last_error(code);
}

// A string the library copies into a caller's buffer (veach.h): ask for the length, then copy.
template <class Get>
std::string get_string(Get&& get) {
    size_t length = 0;
    check(get(nullptr, 0, &length));
    std::string s(length + 1, '\0');
    check(get(s.data(), s.size(), &length));
    s.resize(length < s.size() ? length : s.size() - 1);
    return s;
}

// A reference-counted handle: copies retain, destruction releases.
template <class H, void (*Retain)(H), void (*Release)(H)>
class Handle {
public:
    Handle() = default;
    explicit Handle(H h) : m_h(h) {}
    Handle(const Handle& o) : m_h(o.m_h) {
        if (m_h) Retain(m_h);
    }
    Handle(Handle&& o) noexcept : m_h(std::exchange(o.m_h, nullptr)) {}
    Handle& operator=(Handle o) noexcept {
        std::swap(m_h, o.m_h);
        return *this;
    }
    ~Handle() {
        if (m_h) Release(m_h);
    }
    H get() const { return m_h; }
    explicit operator bool() const { return m_h != nullptr; }

protected:
    H m_h = nullptr;
};

}  // namespace detail

inline int version() { return veachGetVersion(); }
inline const char* version_string() { return veachGetVersionString(); }

class Device : public detail::Handle<VeachDevice, veachRetainDevice, veachReleaseDevice> {
public:
    Device() : Handle(veachNewDevice()) {
        if (!m_h) detail::throw_last_error();
    }
    // The callback runs on the thread where the error happened; it must outlive the device.
    void set_error_function(VeachErrorFunction fn, void* user) { veachSetDeviceErrorFunction(m_h, fn, user); }
    long long get_int(const char* name) const {
        long long v = 0;
        detail::check(veachGetDeviceInt(m_h, name, &v));
        return v;
    }
    // Throws when `path` could not be written as veachWriteFile writes (folder missing or not writable).
    void check_file(const std::string& path) const { detail::check(veachCheckFile(m_h, path.c_str())); }
    // e.g. "integrators", "color_displays": one item a line.
    std::string get_string(const char* name) const {
        return detail::get_string(
            [&](char* b, size_t n, size_t* l) { return veachGetDeviceString(m_h, name, b, n, l); });
    }
};

class Scene : public detail::Handle<VeachScene, veachRetainScene, veachReleaseScene> {
public:
    Scene(const Device& device, const std::string& path) : Handle(veachNewSceneFromFile(device.get(), path.c_str())) {
        if (!m_h) detail::throw_last_error(VEACH_ERROR_BAD_INPUT);
    }
    Scene(const Device& device, const void* data, size_t size, const std::string& format,
          const std::string& base_dir = "")
        : Handle(veachNewSceneFromMemory(device.get(), data, size, format.c_str(), base_dir.c_str())) {
        if (!m_h) detail::throw_last_error(VEACH_ERROR_BAD_INPUT);
    }
    // An empty scene, for options that shape it: set(...), then load(...) once.
    explicit Scene(const Device& device) : Handle(veachNewScene(device.get())) {
        if (!m_h) detail::throw_last_error();
    }
    Scene& set(const char* name, int value) { return set(name, static_cast<long long>(value)); }
    Scene& set(const char* name, long long value) {
        detail::check(veachSetSceneInt(m_h, name, value));
        return *this;
    }
    Scene& set(const char* name, double value) {
        detail::check(veachSetSceneFloat(m_h, name, value));
        return *this;
    }
    Scene& set(const char* name, const std::string& value) { return set(name, value.c_str()); }
    Scene& set(const char* name, const char* value) {
        detail::check(veachSetSceneString(m_h, name, value));
        return *this;
    }
    void load(const std::string& path) { detail::check(veachLoadSceneFile(m_h, path.c_str())); }
    void load(const void* data, size_t size, const std::string& format, const std::string& base_dir = "") {
        detail::check(veachLoadSceneMemory(m_h, data, size, format.c_str(), base_dir.c_str()));
    }
    long long get_int(const char* name) const {
        long long v = 0;
        detail::check(veachGetSceneInt(m_h, name, &v));
        return v;
    }
    double get_float(const char* name) const {
        double v = 0;
        detail::check(veachGetSceneFloat(m_h, name, &v));
        return v;
    }
    std::string get_string(const char* name) const {
        return detail::get_string(
            [&](char* b, size_t n, size_t* l) { return veachGetSceneString(m_h, name, b, n, l); });
    }
    std::vector<std::string> camera_names() const {
        std::vector<std::string> names;
        int n = veachGetSceneCameraCount(m_h);
        for (int i = 0; i < n; ++i) names.emplace_back(veachGetSceneCameraName(m_h, i));
        return names;
    }
};

class Render : public detail::Handle<VeachRender, veachRetainRender, veachReleaseRender> {
public:
    explicit Render(const Scene& scene) : Handle(veachNewRender(scene.get())) {
        if (!m_h) detail::throw_last_error();
    }
    Render(const Render&) = delete;  // owns the progress callback's storage
    Render& operator=(const Render&) = delete;
    // A running render may still call the progress callback: stop it before m_progress dies.
    ~Render() {
        if (m_h && veachGetRenderStatus(m_h) == VEACH_STATUS_RUNNING) {
            veachCancelRender(m_h);
            veachWaitRender(m_h, -1);
        }
    }

    Render& set(const char* name, int value) { return set(name, static_cast<long long>(value)); }
    Render& set(const char* name, long long value) {
        detail::check(veachSetInt(m_h, name, value));
        return *this;
    }
    Render& set(const char* name, double value) {
        detail::check(veachSetFloat(m_h, name, value));
        return *this;
    }
    Render& set(const char* name, const std::string& value) { return set(name, value.c_str()); }
    Render& set(const char* name, const char* value) {
        detail::check(veachSetString(m_h, name, value));
        return *this;
    }
    long long get_int(const char* name) const {
        long long v = 0;
        detail::check(veachGetInt(m_h, name, &v));
        return v;
    }
    double get_float(const char* name) const {
        double v = 0;
        detail::check(veachGetFloat(m_h, name, &v));
        return v;
    }

    std::string get_string(const char* name) const {
        return detail::get_string([&](char* b, size_t n, size_t* l) { return veachGetString(m_h, name, b, n, l); });
    }
    // Called on the rendering thread after each pass; return false to cancel.
    void on_progress(std::function<bool(double fraction, double eta_seconds)> fn) {
        m_progress = std::move(fn);
        veachSetProgressFunction(m_h, m_progress ? &Render::progress_trampoline : nullptr, this);
    }

    // Renders on this thread. Returns false when cancelled (the partial image is available).
    bool render() {
        VeachError e = veachRender(m_h);
        if (e == VEACH_ERROR_CANCELLED) return false;
        detail::check(e);
        return true;
    }
    void render_async() { detail::check(veachRenderAsync(m_h)); }
    // Throws when the render failed.
    VeachStatus wait(int timeout_ms = -1) {
        VeachStatus s = veachWaitRender(m_h, timeout_ms);
        if (s == VEACH_STATUS_FAILED) detail::throw_last_error();
        return s;
    }
    void cancel() { veachCancelRender(m_h); }
    VeachStatus status() const { return veachGetRenderStatus(m_h); }

    int width() const { return static_cast<int>(get_int("result_width")); }
    int height() const { return static_cast<int>(get_int("result_height")); }
    // The pass as float RGBA, rows top to bottom.
    std::vector<float> pass(const char* name = "combined") const {
        std::vector<float> pixels(static_cast<size_t>(width()) * height() * 4);
        detail::check(veachGetPass(m_h, name, pixels.data(), pixels.size() * sizeof(float), 0));
        return pixels;
    }
    void write_image(const std::string& path) const { detail::check(veachWriteImage(m_h, path.c_str())); }
    // Throws when write_image(path) could not write it with these options (format, colour
    // config names, folder): checked before rendering.
    void check_output(const std::string& path) const { detail::check(veachCheckOutput(m_h, path.c_str())); }

private:
    static bool progress_trampoline(void* user, double fraction, double eta) {
        try {
            return static_cast<Render*>(user)->m_progress(fraction, eta);
        } catch (...) {
            return false;  // an exception must not unwind through the C library: cancel instead
        }
    }
    std::function<bool(double, double)> m_progress;
};

}  // namespace veach
