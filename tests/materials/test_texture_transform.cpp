// KHR_texture_transform: the direction of its rotation is the one of the extension's own example,
// "offset [0, 1], rotation pi/2, scale 0.5 shows only the lower left quadrant" of the image
// (glTF's UVs put (0, 0) at the image's top left, so the lower left quadrant is u < 0.5, v > 0.5).
#include <gtest/gtest.h>

#include <cmath>

#include "materials/texture_sampling.h"

namespace veach {
namespace {

// A 2x2 image, one colour a quadrant: red top left, green top right, blue bottom left, white
// bottom right; nearest-texel lookups read back exactly one quadrant's colour.
Texture quadrants() {
    Texture t;
    t.width = t.height = 2;
    t.nearest = true;
    t.wrap_s = t.wrap_t = WrapMode::ClampToEdge;
    t.texels = {1, 0, 0, 1, 0, 1, 0, 1, 0, 0, 1, 1, 1, 1, 1, 1};
    return t;
}

UvTransform extension_example() {
    UvTransform t;
    t.offset[0] = 0.0f;
    t.offset[1] = 1.0f;
    t.rotation = k_pi / 2.0f;
    t.scale[0] = t.scale[1] = 0.5f;
    return t;
}

TEST(TextureTransform, ExtensionExampleShowsOnlyTheLowerLeftQuadrant) {
    Texture tex = quadrants();
    UvTransform t = extension_example();
    for (int j = 0; j < 16; ++j)
        for (int i = 0; i < 16; ++i) {
            Vec2 uv{(i + 0.5f) / 16.0f, (j + 0.5f) / 16.0f};
            Vec2 st = apply_uv_transform(t, uv);
            EXPECT_GE(st.x, 0.0f) << uv.x << " " << uv.y;
            EXPECT_LE(st.x, 0.5f) << uv.x << " " << uv.y;
            EXPECT_GE(st.y, 0.5f) << uv.x << " " << uv.y;
            EXPECT_LE(st.y, 1.0f) << uv.x << " " << uv.y;
            Rgba c = sample_texture(tex, st);
            EXPECT_EQ(c.r, 0.0f);
            EXPECT_EQ(c.g, 0.0f);
            EXPECT_EQ(c.b, 1.0f);  // blue: the lower left quadrant
        }
}

// The quadrant's corners: x' = c x + s y, y' = -s x + c y, then the offset. With rotation pi/2
// the surface's u runs up the image and its v to the right.
TEST(TextureTransform, RotationTurnsUvsAsTheExtensionsExampleDoes) {
    UvTransform t = extension_example();
    auto expect_at = [&](Vec2 uv, Vec2 want) {
        Vec2 st = apply_uv_transform(t, uv);
        EXPECT_NEAR(st.x, want.x, 1e-6f) << uv.x << " " << uv.y;
        EXPECT_NEAR(st.y, want.y, 1e-6f) << uv.x << " " << uv.y;
    };
    expect_at({0, 0}, {0.0f, 1.0f});
    expect_at({1, 0}, {0.0f, 0.5f});
    expect_at({0, 1}, {0.5f, 1.0f});
    expect_at({1, 1}, {0.5f, 0.5f});
    // Rotation alone preserves lengths.
    UvTransform r;
    r.rotation = 0.7f;
    Vec2 st = apply_uv_transform(r, {0.3f, 0.4f});
    EXPECT_NEAR(std::sqrt(st.x * st.x + st.y * st.y), 0.5f, 1e-6f);
    EXPECT_NEAR(st.x, std::cos(0.7f) * 0.3f + std::sin(0.7f) * 0.4f, 1e-6f);
}

}  // namespace
}  // namespace veach
