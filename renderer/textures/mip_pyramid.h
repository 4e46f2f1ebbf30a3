// A texture's mip pyramid: each level the previous one box-filtered to half size, down to 1x1,
// so a lookup whose footprint covers many texels reads a few texels of a coarser level instead
// (materials/texture_sampling.h chooses the level from a ray cone).
//
// Built lazily, by the first lookup that needs a level coarser than the image itself: a texture
// that is never minified (or never looked up) costs no time and no memory, which keeps loading
// free of work for textures a render may not need.
#pragma once

#include <memory>
#include <vector>

namespace veach {

struct MipLevel {
    int width = 0, height = 0;
    std::vector<float> texels;  // width * height * 4, row 0 at the top, always linear
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
std::vector<MipLevel> build_mip_levels(int width, int height, const float* texels, bool srgb);

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
    const std::vector<MipLevel>& levels(int width, int height, const float* texels, bool srgb) const;
    // Whether the pyramid exists (tests: an unminified texture never builds one).
    bool built() const;

private:
    struct State;
    std::unique_ptr<State> m_state;
};

}  // namespace veach
