// The t = 1 strategies of bidirectional path tracing, and all of light tracing: a light subpath
// vertex joined to the camera, its contribution landing on the pixel it projects to (a splat).
#pragma once

#include <vector>

#include "integrators/bdpt/subpaths.h"

namespace veach {

struct CameraConnection {
    float px = 0, py = 0;  // film position the vertex projects to
    Rgb value;             // the strategy's unweighted contribution
    // The vertex was shaded again as the camera sees it (its textures read with the pixel's
    // footprint, README "Textures"): `seen` holds it, and the MIS weight must use it in place of
    // light[s - 1], so that every strategy estimates one integrand with one set of densities.
    bool reshaded = false;
};

// Joins light[s - 1] to camera vertex `z` (the camera's position at the sample's time); false
// when the strategy gives nothing (no importance, off the film, a delta, occluded). `seen` is
// scratch for the reshaded vertex.
bool connect_to_camera(const SubpathContext& ctx, const std::vector<PathVertex>& light, int s, const PathVertex& z,
                       PathVertex& seen, CameraConnection* out);

}  // namespace veach
