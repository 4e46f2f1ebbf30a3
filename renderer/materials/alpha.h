// Alpha coverage (glTF 2.0 section 3.9.4, alphaMode): which ray hits on a surface count.
// OPAQUE surfaces ignore alpha. MASK surfaces exist where alpha >= alphaCutoff. BLEND surfaces
// are treated as stochastic opacity: a ray hits with probability alpha and passes through
// otherwise, so on average a fraction alpha of light is stopped, as with Cycles' transparent
// BSDF mixed in by alpha, and the rest continues unchanged.
#pragma once

#include <cstdint>

#include "scene/scene.h"

namespace veach {

// True when hits on this material need an alpha test (MASK or BLEND).
inline bool needs_alpha_test(const Material& m) { return m.alpha_mode != AlphaMode::Opaque; }

// baseColorFactor.a x baseColorTexture.a x COLOR_0.a at barycentrics (b1, b2) of triangle
// `prim` of `mesh`, as the spec multiplies them.
float surface_alpha(const Scene& scene, const Mesh& mesh, const Material& material, uint32_t prim, float b1, float b2);

// Whether a hit with coverage `alpha` counts. `u` in [0, 1) decides BLEND: the hit counts when
// u < alpha.
inline bool alpha_accepts(const Material& m, float alpha, float u) {
    switch (m.alpha_mode) {
        case AlphaMode::Mask: return alpha >= m.alpha_cutoff;
        case AlphaMode::Blend: return u < alpha;
        case AlphaMode::Opaque:
        default: return true;
    }
}

}  // namespace veach
