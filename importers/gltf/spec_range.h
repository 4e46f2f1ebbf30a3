// A value the file gives, held to the range the glTF spec (or its extension) allows, with one
// warning per kind: a 1e30 base colour would otherwise reach the image as 1e30 times the light,
// a negative colour as negative light, and a light colour or intensity past single precision
// would leave a light that is lost on the way to the film.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <string>

#include "importers/gltf/gltf_accessors.h"

namespace veach::gltf {

inline double in_range(double v, double lo, double hi, const char* kind, ImportContext& context) {
    if (v >= lo && v <= hi) return v;
    char range[64];
    std::snprintf(range, sizeof(range), "[%g, %g]", lo, hi);
    context.warn(std::string(kind) + " outside its range " + range + " clamped");
    return std::isnan(v) ? lo : std::clamp(v, lo, hi);
}

template <size_t N>
void in_range(std::array<double, N>& values, double lo, double hi, const char* kind, ImportContext& context) {
    for (double& v : values) v = in_range(v, lo, hi, kind, context);
}

}  // namespace veach::gltf
