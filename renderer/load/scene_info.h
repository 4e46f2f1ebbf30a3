// What a loaded scene holds, as JSON for a front end to list (`veach info`, the scene query
// "info"): the file's scenes, variants and animations (SceneCatalog), cameras, lights by kind,
// meshes, triangles and instances, materials, textures with their sizes, features, warnings and
// repairs.
#pragma once

#include <string>

#include "scene/scene.h"

namespace veach {

std::string scene_info_json(const Scene& scene);

}  // namespace veach
