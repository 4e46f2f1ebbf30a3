// KHR_materials_volume for a path tracer: a homogeneous, purely absorbing medium inside a closed
// transmissive mesh. Transmittance over a distance d is Beer-Lambert's exp(-sigma_a d) per
// channel, with sigma_a = -ln(attenuationColor) / attenuationDistance, so that white light
// travelling attenuationDistance inside comes out as attenuationColor (the extension's
// definition). The extension's thicknessFactor only approximates path lengths for rasterisers;
// a path tracer measures them, so it is ignored.
#pragma once

#include "core/rgb.h"

namespace veach {

inline Rgb beer_lambert(const Rgb& sigma_a, float distance) {
    if (sigma_a.is_black()) return Rgb(1.0f);
    return {std::exp(-sigma_a.r * distance), std::exp(-sigma_a.g * distance), std::exp(-sigma_a.b * distance)};
}

}  // namespace veach
