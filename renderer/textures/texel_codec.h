// 8-bit texel values and floats: decoding by table (k / 255, and the sRGB decoding of k / 255),
// encoding by rounding to the nearest byte. Texture lookups and mip levels of 8-bit images use
// these, so an 8-bit texture reads exactly the floats a float copy of it would hold.
#pragma once

#include <array>
#include <cstdint>

namespace veach {

struct Unorm8Tables {
    std::array<float, 256> unorm{};        // k / 255.0f, bit for bit what the division gives
    std::array<float, 256> srgb_linear{};  // srgb_to_linear(k / 255.0f)
};

// Built once, on first use (thread-safe), then read-only.
const Unorm8Tables& unorm8_tables();

// The byte nearest to v in [0, 1] (clamped; NaN gives 0).
uint8_t encode_unorm8(float v);
// The byte whose sRGB decoding is nearest to the linear value (clamped to [0, 1]).
uint8_t encode_srgb8(float linear);

}  // namespace veach
