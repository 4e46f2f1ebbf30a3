// libFuzzer target on the importer and the scene load after it (repairs, rebase): any byte
// string, as .gltf (JSON) or .glb (binary) by its first four bytes, must either load or throw
// ImportError (the one-line bad-input message).
// Anything else - a crash, a sanitizer report, another exception type, a hang or an allocation
// past libFuzzer's -rss_limit_mb - is a finding. `make fuzz FUZZ_SECONDS=N` runs it; each
// finding becomes a regression test in tests/robustness/data named after the fault.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

#include "load/scene_load.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    std::vector<uint8_t> bytes(data, data + size);
    const bool binary = size >= 4 && std::memcmp(data, "glTF", 4) == 0;
    veach::SceneLoadOptions options;  // external files refused: URIs stay inside the (empty) folder
    try {
        // An empty folder of its own: relative URIs find nothing, data: URIs decode.
        veach::LoadedScene scene =
            veach::load_scene_memory(bytes, binary ? "glb" : "gltf", "/nonexistent-veach-fuzz", options);
        (void)scene;
    } catch (const veach::ImportError&) {
        // Bad input, reported as it should be.
    }
    return 0;
}
