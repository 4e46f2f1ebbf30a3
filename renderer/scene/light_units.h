// The file's light values turned into the renderer's, in one place for the importer and for
// animated lights (KHR_animation_pointer), so that a light animated to its own rest values is
// the light the import made.
#pragma once

#include <algorithm>
#include <cmath>

#include "scene/scene.h"

namespace veach {

// The largest emission strength (KHR_materials_emissive_strength) a material keeps: the spec sets
// no upper bound, and past this a strength would overflow single precision on its way to the
// film. The importer holds the file's value to it, pose_scene an animated one.
constexpr float k_max_emission_strength = 1e9f;

// The largest light intensity (candela, lux) or area-light power (watts) a light keeps: the
// extension sets no upper bound, and past single precision (1.25e43 cd from 2.3e41 W) the light
// would be lost on its way to the film. The importer holds the file's value to it, pose_scene an
// animated one.
constexpr float k_max_light_intensity = 1e30f;

// KHR_lights_punctual's intensity (candela for point and spot, lux for directional) with its
// colour, in Cycles' radiometric units: Blender writes W/(4 pi) x 683 lm/W (point, spot) and
// W/m^2 x 683 (sun).
inline Rgb radiometric_intensity(const Rgb& color, double intensity) { return color * float(intensity / 683.0); }

// A spot's cone from the file's angles (radians): outer held to [0, pi/2], inner to [0, outer];
// Blender exports inner = outer x (1 - blend).
inline void set_spot_cone(PunctualLight& light, double inner_cone, double outer_cone) {
    double outer = std::clamp(outer_cone, 0.0, double(k_pi) / 2);
    double inner = std::clamp(inner_cone, 0.0, outer);
    light.cos_outer = float(std::cos(outer));
    light.cos_inner = float(std::cos(inner));
    light.blend = outer > 0 ? float(1.0 - inner / outer) : 0.0f;
}

}  // namespace veach
