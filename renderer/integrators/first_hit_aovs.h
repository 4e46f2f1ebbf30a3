// Camera samples with their first-hit AOVs (depth, normal, albedo) for Blender-style render
// passes. Kept apart from the integrators' transport code: when the film records AOVs, the
// camera ray of the sample is traced once more to its first hit, which costs one ray per sample
// only in renders that ask for the passes and leaves the light transport code untouched.
#pragma once

#include "core/rgb.h"
#include "film/film.h"
#include "integrators/render_scene.h"

namespace veach {

// What the ray of `camera` (the sample's, at shutter time `time`) through film position (fx, fy)
// first hits.
PixelAovs first_hit_aovs(const RenderScene& rs, const CameraModel& camera, float fx, float fy, float time);

// Adds a camera sample placed at (fx, fy) and shutter time `time` (seen by `camera`) for pixel
// (x, y), with its AOVs and coverage (alpha) when the film records them.
inline void add_camera_sample(Film& film, const RenderScene& rs, const CameraModel& camera, int x, int y, float fx,
                              float fy, float time, const Rgb& radiance) {
    if (!film.wants_first_hit()) {
        film.add_sample(x, y, radiance);
        return;
    }
    const PixelAovs aovs = first_hit_aovs(rs, camera, fx, fy, time);
    film.add_sample(x, y, radiance, &aovs);
}

}  // namespace veach
