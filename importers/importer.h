// Scene importers, registered by file extension, so the API and the CLI load any registered
// format through one call.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "scene/scene.h"

namespace veach {

// Bad input: the message is one line naming the file and the fault. Front ends map it to exit
// code 2.
class ImportError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

enum class SpotProfile : uint8_t {
    Auto,  // Blender's (Cycles) profile when asset.generator names Blender, glTF's otherwise
    Gltf,
    Blender,
};

// What a primitive without a material renders as.
enum class DefaultMaterial : uint8_t {
    Auto,     // Cycles' default surface when asset.generator names Blender, glTF's otherwise
    Gltf,     // the glTF spec's default: white, metallic 1, roughness 1
    Blender,  // Cycles' default surface: Lambertian, albedo 0.8 (what Blender shows and its importer makes)
};

// The options' names, as front ends spell them (and the scene identity hashes them).
inline const char* spot_profile_name(SpotProfile p) {
    switch (p) {
        case SpotProfile::Blender: return "blender";
        case SpotProfile::Gltf: return "gltf";
        default: return "auto";
    }
}

inline const char* default_material_name(DefaultMaterial m) {
    switch (m) {
        case DefaultMaterial::Blender: return "blender";
        case DefaultMaterial::Gltf: return "gltf";
        default: return "auto";
    }
}

struct ImportOptions {
    int scene_index = -1;  // -1: the file's default scene (or the first)
    std::string variant;   // KHR_materials_variants name, empty = default materials
    SpotProfile spot_profile = SpotProfile::Auto;
    DefaultMaterial default_material = DefaultMaterial::Auto;
    bool allow_external_files = false;  // URIs outside the file's folder
    // Fill Scene::animation (nodes, animations, skins, morph targets) for pose_scene; off, the
    // file's nodes are placed as they stand and skins and morph targets are not applied.
    bool animate = false;
    // With animate: the animation to play, by name or index; "all" (or empty): all at once. A
    // name or index the file lacks is bad input, listing the file's animations.
    std::string animation = "all";
};

// Loads a file by its extension (case-insensitive), as the file has it: the repairs and the rest
// of the pipeline are the scene load's (renderer/load/scene_load.h). Throws ImportError on bad
// input.
Scene import_scene(const std::string& path, const ImportOptions& options = {});

// Loads a scene held in memory (e.g. a .glb a host application produced); `format` is an
// extension such as "glb". Relative URIs resolve against `base_dir`.
Scene import_scene_from_memory(const std::vector<uint8_t>& bytes, const std::string& format,
                               const std::string& base_dir, const ImportOptions& options = {});

// Extensions of the registered formats, lower case without the dot.
std::vector<std::string> registered_scene_formats();

}  // namespace veach
