// Mip pyramids and the trilinear lookup: every level keeps the image's mean (a box filter is
// exact), sRGB images are averaged as light (decoded), the level of detail is log2 of the texels
// a footprint covers, coarse levels wrap as the sampler says, and nothing is built for a texture
// that is never minified.
#include <gtest/gtest.h>

#include <cmath>

#include "core/rng.h"
#include "materials/texture_sampling.h"
#include "textures/mip_pyramid.h"

namespace veach {
namespace {

Texture random_texture(int w, int h, bool srgb, uint64_t seed) {
    Texture t;
    t.width = w;
    t.height = h;
    t.srgb = srgb;
    Rng rng(seed, 7);
    t.texels.resize(static_cast<size_t>(w) * h * 4);
    // Values on the 8-bit grid, as decoded PNGs hold, so the sRGB table path is exercised.
    for (float& v : t.texels) v = static_cast<float>(static_cast<int>(rng.next_float() * 255.999f)) / 255.0f;
    return t;
}

double mean_of(const float* texels, size_t count, int c, bool decode) {
    double sum = 0;
    for (size_t i = 0; i < count; ++i) {
        float v = texels[i * 4 + c];
        sum += decode && c < 3 ? srgb_to_linear(v) : v;
    }
    return sum / static_cast<double>(count);
}

// A texture whose texel (x, y) is f(x, y), linear, grey with alpha 1.
template <typename F>
Texture grey_texture(int w, int h, F f) {
    Texture t;
    t.width = w;
    t.height = h;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            float v = f(x, y);
            t.texels.insert(t.texels.end(), {v, v, v, 1.0f});
        }
    return t;
}

TEST(MipPyramid, EveryLevelKeepsTheImageMean) {
    // Odd sizes use the area-weighted box; a 2x2 box dropping the last row would lose its share.
    const int sizes[][2] = {{64, 64}, {37, 20}, {5, 1}, {1, 7}, {3, 3}, {255, 129}};
    for (bool srgb : {false, true}) {
        for (const auto& size : sizes) {
            Texture t = random_texture(size[0], size[1], srgb, static_cast<uint64_t>(size[0] * 1000 + size[1]));
            std::vector<MipLevel> levels = build_mip_levels(t.width, t.height, t.texels.data(), t.srgb);
            ASSERT_FALSE(levels.empty());
            EXPECT_EQ(levels.back().width, 1);
            EXPECT_EQ(levels.back().height, 1);
            int w = t.width, h = t.height;
            for (const MipLevel& l : levels) {
                EXPECT_EQ(l.width, std::max(1, w / 2));
                EXPECT_EQ(l.height, std::max(1, h / 2));
                w = l.width;
                h = l.height;
                for (int c = 0; c < 4; ++c) {
                    double expected = mean_of(t.texels.data(), static_cast<size_t>(t.width) * t.height, c, srgb);
                    double got = mean_of(l.texels.data(), static_cast<size_t>(l.width) * l.height, c, false);
                    // Float sums over up to 32k texels: a few ulps of 1 per level.
                    EXPECT_NEAR(got, expected, 2e-5) << size[0] << "x" << size[1] << " srgb " << srgb << " level "
                                                     << l.width << "x" << l.height << " channel " << c;
                }
            }
        }
    }
}

TEST(MipPyramid, EvenSizesAreTheTwoByTwoBox) {
    Texture t = random_texture(8, 6, false, 3);
    std::vector<MipLevel> levels = build_mip_levels(t.width, t.height, t.texels.data(), false);
    const MipLevel& l = levels[0];
    ASSERT_EQ(l.width, 4);
    ASSERT_EQ(l.height, 3);
    for (int y = 0; y < 3; ++y)
        for (int x = 0; x < 4; ++x)
            for (int c = 0; c < 4; ++c) {
                auto at = [&](int xx, int yy) { return t.texels[(static_cast<size_t>(yy) * 8 + xx) * 4 + c]; };
                float box =
                    0.25f * (at(2 * x, 2 * y) + at(2 * x + 1, 2 * y) + at(2 * x, 2 * y + 1) + at(2 * x + 1, 2 * y + 1));
                EXPECT_NEAR(l.texels[(static_cast<size_t>(y) * 4 + x) * 4 + c], box, 1e-6f);
            }
}

// A black and white checkerboard reflects half the light: its coarse levels must say 0.5 in
// linear terms, not the decoded mean of the encoded values, srgb_to_linear(0.5) = 0.21.
TEST(MipPyramid, SrgbImagesAverageLightNotEncodedValues) {
    Texture t = grey_texture(16, 16, [](int x, int y) { return ((x + y) & 1) ? 1.0f : 0.0f; });
    t.srgb = true;
    Rgba coarse = sample_texture(t, Vec2{0.3f, 0.6f}, 10.0f);  // past the coarsest level
    EXPECT_NEAR(coarse.r, 0.5f, 1e-6f);
    EXPECT_NEAR(coarse.a, 1.0f, 1e-6f);
}

TEST(TextureSampling, LevelOfDetailIsLog2OfTheTexelsCovered) {
    Texture t = grey_texture(64, 16, [](int, int) { return 0.5f; });  // sqrt(64 x 16) = 32 texels a unit
    EXPECT_NEAR(texture_lod(t, 1.0f / 32.0f), 0.0f, 1e-6f);
    EXPECT_NEAR(texture_lod(t, 4.0f / 32.0f), 2.0f, 1e-6f);
    EXPECT_NEAR(texture_lod(t, 0.25f / 32.0f), -2.0f, 1e-6f);
    EXPECT_EQ(texture_lod(t, 0.0f), 0.0f);
    UvTransform scaled;
    scaled.scale[0] = 4;
    scaled.scale[1] = 0.25f;
    scaled.rotation = 0.7f;
    EXPECT_NEAR(uv_transform_length_scale(scaled), 1.0f, 1e-6f);  // area-preserving
    scaled.scale[1] = 4;
    EXPECT_NEAR(uv_transform_length_scale(scaled), 4.0f, 1e-6f);
}

// Texels 0 and 1 alternate, so level 0 at a texel centre is 0 or 1 and level 1 is 0.5: the LOD
// halfway between blends them halfway.
TEST(TextureSampling, TrilinearBlendsTheTwoLevelsAroundTheLod) {
    Texture t = grey_texture(2, 2, [](int x, int y) { return ((x + y) & 1) ? 1.0f : 0.0f; });
    Vec2 centre_of_texel_00{0.25f, 0.25f};
    auto footprint_for = [](float lod) { return std::exp2(lod) / 2.0f; };  // 2 texels a unit
    EXPECT_NEAR(sample_texture(t, centre_of_texel_00, footprint_for(0.0f)).r, 0.0f, 1e-6f);
    EXPECT_NEAR(sample_texture(t, centre_of_texel_00, footprint_for(0.5f)).r, 0.25f, 1e-6f);
    EXPECT_NEAR(sample_texture(t, centre_of_texel_00, footprint_for(1.0f)).r, 0.5f, 1e-6f);
    EXPECT_NEAR(sample_texture(t, centre_of_texel_00, footprint_for(5.0f)).r, 0.5f, 1e-6f);
    // NEAREST (Blender's "Closest") keeps point sampling at every distance.
    t.nearest = true;
    EXPECT_NEAR(sample_texture(t, Vec2{0.3f, 0.2f}, footprint_for(1.0f)).r, 0.0f, 1e-6f);
    // A minFilter without mip-mapping (LINEAR or NEAREST) reads the image itself when minified.
    t.nearest = false;
    t.mipmaps = false;
    EXPECT_NEAR(sample_texture(t, centre_of_texel_00, footprint_for(1.0f)).r, 0.0f, 1e-6f);
    EXPECT_NEAR(sample_texture(t, centre_of_texel_00, footprint_for(5.0f)).r, 0.0f, 1e-6f);
}

// Level 1 of [0 0 0 0 1 1 1 1] is [0 0 1 1]. At u = 0, between its last and first texels, the
// bilinear tap wraps as the sampler says: repeat blends 1 and 0, clamp and mirror repeat texel 0.
TEST(TextureSampling, CoarseLevelsWrapAsTheSamplerSays) {
    Texture base = grey_texture(8, 1, [](int x, int) { return x >= 4 ? 1.0f : 0.0f; });
    float footprint = 2.0f / std::sqrt(8.0f);  // LOD 1
    struct Case {
        WrapMode mode;
        float at_zero;
    };
    for (Case c :
         {Case{WrapMode::Repeat, 0.5f}, Case{WrapMode::ClampToEdge, 0.0f}, Case{WrapMode::MirroredRepeat, 0.0f}}) {
        Texture t = base;
        t.wrap_s = c.mode;
        EXPECT_NEAR(sample_texture(t, Vec2{0.0f, 0.5f}, footprint).r, c.at_zero, 1e-6f) << static_cast<int>(c.mode);
        EXPECT_NEAR(sample_texture(t, Vec2{0.5f, 0.5f}, footprint).r, 0.5f, 1e-6f);
    }
}

// Unused or magnified textures cost nothing: the pyramid is built by the first lookup that needs
// a coarser level, and a copy of a texture does not share (or copy) it.
TEST(TextureSampling, OnlyAMinifiedLookupBuildsThePyramid) {
    Texture t = random_texture(64, 64, true, 11);
    Rgba full = sample_texture(t, Vec2{0.37f, 0.81f});
    Rgba magnified = sample_texture(t, Vec2{0.37f, 0.81f}, 0.5f / 64.0f);  // half a texel: LOD -1
    EXPECT_EQ(full.r, magnified.r);
    EXPECT_EQ(full.a, magnified.a);
    EXPECT_FALSE(t.mips.built());
    sample_texture(t, Vec2{0.37f, 0.81f}, 4.0f / 64.0f);
    EXPECT_TRUE(t.mips.built());
    Texture copy = t;
    EXPECT_FALSE(copy.mips.built());
}

// An 8-bit image kept as bytes reads exactly as the same image kept as floats k / 255 at level 0
// (the magnified lookup), and within an 8-bit step of it where the pyramid is used, whose levels
// are stored as bytes too (sRGB-encoded for colour images); it holds a quarter of the bytes.
TEST(TextureSampling, EightBitTexturesReadAsTheirFloatCopies) {
    for (bool srgb : {false, true}) {
        Texture f = random_texture(37, 21, srgb, srgb ? 5 : 6);
        Texture b;
        b.width = f.width;
        b.height = f.height;
        b.srgb = srgb;
        for (float v : f.texels) b.texels8.push_back(static_cast<uint8_t>(std::lround(v * 255.0f)));
        EXPECT_EQ(b.stored_bytes() * 4, f.stored_bytes());
        Rng rng(11, 3);
        double worst = 0;
        for (int i = 0; i < 2000; ++i) {
            Vec2 uv{rng.next_float() * 3 - 1, rng.next_float() * 3 - 1};
            Rgba a = sample_texture(f, uv, 0.0f), c = sample_texture(b, uv, 0.0f);
            ASSERT_EQ(a.r, c.r);
            ASSERT_EQ(a.g, c.g);
            ASSERT_EQ(a.b, c.b);
            ASSERT_EQ(a.a, c.a);
            float footprint = 0.02f + 0.3f * rng.next_float();  // minified: levels 1 and up
            Rgba m = sample_texture(f, uv, footprint), n = sample_texture(b, uv, footprint);
            // Half an 8-bit step in the encoded space is at most 1/510 in linear too (the sRGB
            // curve's slope is below 1 above 0.04 encoded, and 1/12.92 below).
            for (float d : {m.r - n.r, m.g - n.g, m.b - n.b, m.a - n.a}) worst = std::max(worst, double(std::fabs(d)));
        }
        EXPECT_LE(worst, 1.0 / 255.0) << "srgb " << srgb;
        EXPECT_GT(worst, 0.0) << "the byte pyramid should round somewhere";
        const std::vector<MipLevel>& levels = b.mips.levels(b.width, b.height, b.texels8.data(), srgb);
        ASSERT_FALSE(levels.empty());
        for (const MipLevel& l : levels) {
            EXPECT_TRUE(l.texels.empty());
            EXPECT_EQ(l.texels8.size(), static_cast<size_t>(l.width) * l.height * 4);
            EXPECT_EQ(l.srgb8, srgb);
        }
    }
}

}  // namespace
}  // namespace veach
