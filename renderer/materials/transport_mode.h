// What a path carries: radiance from the lights (camera subpaths, pt) or importance from the
// camera (light subpaths). BSDFs take it because shading normals and refraction make them
// non-symmetric (Veach's adjoint BSDF).
#pragma once

#include <cstdint>

namespace veach {

enum class TransportMode : uint8_t { Radiance, Importance };

}  // namespace veach
