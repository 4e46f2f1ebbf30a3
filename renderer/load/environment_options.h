// The environment a front end asks for (glTF carries none): a lat-long map file or a uniform
// colour, a strength and a rotation about the up axis. apply_environment fills Scene::environment.
#pragma once

#include <string>

#include "core/rgb.h"
#include "scene/scene.h"

namespace veach {

struct EnvironmentOptions {
    std::string map_path;    // equirectangular HDR/EXR (anything OpenImageIO reads)
    bool has_color = false;  // a uniform environment of `color`
    Rgb color{1, 1, 1};
    float strength = 1;
    float rotate_degrees = 0;  // about +Y, as a Mapping node's Z rotation in Blender's world
    bool requested() const { return !map_path.empty() || has_color; }
};

// Loads the map (if any) into scene->environment and sets SceneFeatures::environment. Throws
// std::invalid_argument with a one-line "FILE: fault" message for an unreadable map.
void apply_environment(const EnvironmentOptions& options, Scene* scene);

}  // namespace veach
