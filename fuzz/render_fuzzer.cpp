// libFuzzer target on the whole path a host takes: any byte string, as .gltf or .glb by its first
// four bytes, is loaded through the C API and, when it loads, rendered for a few samples of a tiny
// image with one of the three integrators. Loading may fail only with VEACH_ERROR_BAD_INPUT and
// rendering must succeed; anything else - a crash, a sanitizer report, another error code, a
// non-finite pixel, a hang or an allocation past -rss_limit_mb - is a finding. The importer
// target cannot see what goes wrong after the import: scene repair, the accel's ray guard, light
// tables, camera construction, the integrators' handling of what a hostile file can still
// contain. `make fuzz FUZZ_TARGETS=render FUZZ_SECONDS=N` runs it.
#include <veach/veach.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

namespace {

[[noreturn]] void finding(const char* what) {
    std::fprintf(stderr, "veach render fuzzer: %s: %s\n", what, veachGetLastError());
    std::abort();
}

// The same input always renders the same way; the choices come from its bytes, not from its
// content, so the fuzzer's mutations explore both.
uint64_t fnv1a(const uint8_t* data, size_t size) {
    uint64_t h = 1469598103934665603ull;
    for (size_t i = 0; i < size; ++i) h = (h ^ data[i]) * 1099511628211ull;
    return h;
}

VeachDevice device() {
    static VeachDevice d = veachNewDevice();
    return d;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const bool binary = size >= 4 && std::memcmp(data, "glTF", 4) == 0;
    const uint64_t h = fnv1a(data, size);

    VeachScene scene = veachNewScene(device());
    if (!scene) finding("veachNewScene");
    if (h & 8) veachSetSceneFloat(scene, "time", double((h >> 8) % 48) / 24.0);  // animations, skins, morphs
    if (h & 16) veachSetSceneString(scene, "env_color", "0.5,0.4,0.3");         // a light at infinity
    // An empty folder of its own: relative URIs find nothing, data: URIs decode.
    VeachError loaded = veachLoadSceneMemory(scene, data, size, binary ? "glb" : "gltf", "/nonexistent-veach-fuzz");
    if (loaded != VEACH_ERROR_NONE) {
        // An empty buffer is an argument the API refuses as such (libFuzzer always tries one).
        const bool empty_refused = size == 0 && loaded == VEACH_ERROR_INVALID_ARGUMENT;
        if (loaded != VEACH_ERROR_BAD_INPUT && !empty_refused) finding("load failed with an error other than bad input");
        veachReleaseScene(scene);
        return 0;
    }

    static const char* const integrators[] = {"pt", "bdpt", "lt"};
    VeachRender render = veachNewRender(scene);
    if (!render) finding("veachNewRender");
    veachSetInt(render, "width", 8);
    veachSetInt(render, "height", 6);
    veachSetInt(render, "spp", 2);
    veachSetInt(render, "max_depth", 6);
    veachSetInt(render, "threads", 1);
    veachSetInt(render, "aovs", (h >> 2) & 1);
    veachSetString(render, "integrator", integrators[h % 3]);
    VeachError rendered = veachRender(render);
    // A file can be valid and still give no usable camera, or need more memory than the process
    // may take: those are refused as bad input or out of memory before rendering.
    if (rendered != VEACH_ERROR_NONE && rendered != VEACH_ERROR_BAD_INPUT && rendered != VEACH_ERROR_OUT_OF_MEMORY)
        finding("render failed");
    if (rendered == VEACH_ERROR_NONE) {
        std::vector<float> rgba(8 * 6 * 4);
        if (veachGetPass(render, "combined", rgba.data(), rgba.size() * sizeof(float), 0) != VEACH_ERROR_NONE)
            finding("veachGetPass");
        for (float v : rgba)
            if (!std::isfinite(v)) finding("non-finite pixel");
    }
    veachReleaseRender(render);
    veachReleaseScene(scene);
    return 0;
}
