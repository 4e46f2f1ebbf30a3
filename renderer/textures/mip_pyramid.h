// A texture's mip pyramid: each level the previous one box-filtered to half size, down to 1x1,
// so a lookup whose footprint covers many texels reads a few texels of a coarser level instead
// (materials/texture_sampling.h chooses the level from a ray cone).
//
// Built lazily, by the first lookup that needs a level coarser than the image itself: a texture
// that is never minified (or never looked up) costs no time and no memory, which keeps loading
// free of work for textures a render may not need.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

namespace veach {

// A level's texels: linear floats for float and 16-bit images; for 8-bit images, bytes at the
// image's own precision (RGB sRGB-encoded when the image is, `srgb8`; alpha linear), so a
// pyramid costs a third of its image whatever the image's type.
struct MipLevel {
    int width = 0, height = 0;
    std::vector<float> texels;     // width * height * 4, row 0 at the top, linear
    std::vector<uint8_t> texels8;  // or this, for 8-bit images
    bool srgb8 = false;            // texels8's RGB are sRGB-encoded (decoded by table at lookup)
    size_t stored_bytes() const { return texels.size() * sizeof(float) + texels8.size(); }
};

// Level 0's texels, in whichever of the three precisions the texture keeps (one pointer set).
struct TexelSource {
    TexelSource() = default;
    TexelSource(const float* p) : f32(p) {}  // NOLINT: implicit, a float image is the common case
    TexelSource(const uint8_t* p) : u8(p) {}
    TexelSource(const uint16_t* p) : u16(p) {}
    const float* f32 = nullptr;
    const uint8_t* u8 = nullptr;
    const uint16_t* u16 = nullptr;
    bool empty() const { return !f32 && !u8 && !u16; }
};

// Levels 1, 2, ... of the pyramid of a width x height RGBA image (level 0 is the image itself).
// Each halves both sizes (rounding down, never below 1); a texel of level k+1 is the area-weighted
// mean of the level-k texels under it: exactly the 2x2 box for even sizes, and for an odd size
// a box of n/floor(n/2) texels with the edge texels weighted by how much of them it covers, so
// every level has exactly the image's mean (a 2x2 box that drops the last row or column would
// not). The box never reaches past the image, so wrap modes do not enter the downsampling; they
// apply when a level is looked up.
//
// For sRGB-encoded images (`srgb`) the levels hold decoded, linear values: a minified texture
// must show the mean radiance of what it covers, and the mean of encoded values is darker (a
// black and white checkerboard would give 0.21 instead of 0.5). Only level 0, the magnified
// image, is filtered in the encoded space (Cycles' choice; see Texture in scene/scene.h).
// An 8-bit image's levels are each computed in float from the previous level's floats (so the
// rounding never accumulates down the pyramid) and stored as bytes, re-encoded to sRGB when the
// image is sRGB: a level texel is within half an 8-bit step (in the encoded space) of the float
// pyramid's.
std::vector<MipLevel> build_mip_levels(int width, int height, const TexelSource& texels, bool srgb);

// The pyramid of one texture, built on first use and then read by every thread. Copying gives an
// empty cache (the copy's texels may be changed before it is used); a moved-from cache is empty.
class MipCache {
public:
    MipCache();
    MipCache(const MipCache&);
    MipCache& operator=(const MipCache&);
    MipCache(MipCache&&) noexcept;
    MipCache& operator=(MipCache&&) noexcept;
    ~MipCache();

    // Levels 1.. of the image, built by the first caller (the others wait for it). Serial on
    // purpose: a parallel build inside a TBB task could let the waiting thread steal a task that
    // waits on the same cache, a deadlock. Empty for an empty image.
    const std::vector<MipLevel>& levels(int width, int height, const TexelSource& texels, bool srgb) const;
    // Whether the pyramid exists (tests: an unminified texture never builds one).
    bool built() const;

private:
    struct State;
    std::unique_ptr<State> m_state;
};

}  // namespace veach
