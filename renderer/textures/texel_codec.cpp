#include "textures/texel_codec.h"

#include <cmath>

#include "core/rgb.h"

namespace veach {

const Unorm8Tables& unorm8_tables() {
    static const Unorm8Tables tables = [] {
        Unorm8Tables t;
        for (int k = 0; k < 256; ++k) {
            t.unorm[k] = static_cast<float>(k) / 255.0f;
            t.srgb_linear[k] = srgb_to_linear(t.unorm[k]);
        }
        return t;
    }();
    return tables;
}

uint8_t encode_unorm8(float v) {
    if (!(v > 0.0f)) return 0;
    if (v >= 1.0f) return 255;
    return static_cast<uint8_t>(v * 255.0f + 0.5f);
}

// Rounding in the encoded space can miss the nearest decoded value by one step where the curve
// bends; the two neighbours are compared in linear.
uint8_t encode_srgb8(float linear) {
    if (!(linear > 0.0f)) return 0;
    if (linear >= 1.0f) return 255;
    const Unorm8Tables& t = unorm8_tables();
    int k = static_cast<int>(linear_to_srgb(linear) * 255.0f + 0.5f);
    if (k > 255) k = 255;
    int best = k;
    for (int c = k - 1; c <= k + 1; c += 2)
        if (c >= 0 && c <= 255 && std::fabs(t.srgb_linear[c] - linear) < std::fabs(t.srgb_linear[best] - linear))
            best = c;
    return static_cast<uint8_t>(best);
}

}  // namespace veach
