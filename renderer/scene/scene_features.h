// What a scene uses, recorded at load, so the renderer skips what a scene doesn't need and the
// stats say what was found.
#pragma once

#include <string>
#include <vector>

namespace veach {

struct SceneFeatures {
    bool textures = false;
    bool normal_maps = false;
    bool alpha = false;  // a rendered material with alphaMode MASK or BLEND
    bool transmission = false;
    bool volume = false;
    bool clearcoat = false;
    bool sheen = false;
    bool punctual_lights = false;
    bool emissive_meshes = false;
    bool environment = false;
    bool instancing = false;  // a mesh placed more than once
    bool vertex_colors = false;

    // Names of the features in use, for stats and logs.
    std::vector<std::string> names() const;
};

// What the file offers besides what was loaded, for a front end to list (`veach info`): its
// scenes, KHR_materials_variants variants and animations, by name ("" for an unnamed one), in
// the file's order; the scene the file names as its default (-1: none).
struct SceneCatalog {
    std::vector<std::string> scenes, variants, animations;
    int default_scene = -1;
};

}  // namespace veach
