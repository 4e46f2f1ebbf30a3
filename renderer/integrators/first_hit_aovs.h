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

// The denoiser's features of the same ray: its first hit, or where that is a mirror or smooth
// glass (every lobe a Dirac delta), the first surface seen through it (up to 8 such bounces;
// `u_lobe` picks reflection or refraction at glass, in proportion to Fresnel), with the albedo
// tinted by what the delta bounces multiplied. First-hit features say nothing of what a mirror
// shows; these let the denoiser tell its reflected edges apart.
DenoiseFeatures denoise_features(const RenderScene& rs, const CameraModel& camera, float fx, float fy, float time,
                                 float u_lobe);

// Adds camera sample `sample_index` placed at (fx, fy) and shutter time `time` (seen by `camera`)
// for pixel (x, y), with its AOVs and coverage (alpha) when the film records them, and the
// denoiser's features when it keeps halves (`u_lobe` as denoise_features()).
inline void add_camera_sample(Film& film, const RenderScene& rs, const CameraModel& camera, int x, int y, float fx,
                              float fy, float time, const Rgb& radiance, uint32_t sample_index = 0,
                              float u_lobe = 0.5f) {
    if (!film.wants_first_hit() && !film.wants_halves()) {
        film.add_sample(x, y, radiance);
        return;
    }
    const PixelAovs aovs = film.wants_first_hit() ? first_hit_aovs(rs, camera, fx, fy, time) : PixelAovs{};
    const DenoiseFeatures features =
        film.wants_halves() ? denoise_features(rs, camera, fx, fy, time, u_lobe) : DenoiseFeatures{};
    film.add_sample(x, y, radiance, film.wants_first_hit() ? &aovs : nullptr, sample_index, &features);
}

}  // namespace veach
