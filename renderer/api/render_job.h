// One render from a loaded scene to an image: picks the camera, prepares the BVH and lights,
// runs the integrator and reports timings and stats. The front ends (CLI, C API) are thin layers
// over this.
#pragma once

#include <string>
#include <vector>

#include "film/film.h"
#include "integrators/integrator.h"
#include "scene/scene.h"

namespace veach {

struct RenderJobOptions {
    std::string camera;  // a camera name or index; empty = the scene's first camera
    int width = 0;       // 0 = 1920
    int height = 0;      // 0 = from the camera's aspect ratio
    RenderSettings render;
};

struct RenderResult {
    Image image;
    RenderStats stats;
    std::string camera_name;  // "default" when the scene has none
    double build_seconds = 0;
    double render_seconds = 0;
    size_t triangles = 0;
};

// Throws std::invalid_argument with a one-line message when `spec` names no camera.
const Camera* select_camera(const Scene& scene, const std::string& spec);

// Renders; throws std::invalid_argument for bad settings.
RenderResult render_scene(const Scene& scene, const RenderJobOptions& options, const RenderControl& control = {});

// Peak resident set size of this process in bytes (from /proc), 0 if unknown.
size_t peak_resident_bytes();

}  // namespace veach
