#include "materials/texture_sampling.h"

#include <array>
#include <cmath>

#include "textures/texel_codec.h"

namespace veach {

Vec2 apply_uv_transform(const UvTransform& t, Vec2 uv) {
    if (t.is_identity()) return uv;
    float c = std::cos(t.rotation), s = std::sin(t.rotation);
    float x = uv.x * t.scale[0], y = uv.y * t.scale[1];
    // Translation * rotation * scale, the rotation turning UVs clockwise in the image as the
    // angle grows: x' = c x + s y, y' = -s x + c y. The extension's GLSL listing reads the other
    // way (a known erratum), but its own worked example (offset [0, 1], rotation pi/2, scale 0.5
    // shows only the lower left quadrant), its sample model, three.js, Babylon.js and Blender's
    // exporter and importer all use this direction.
    return {c * x + s * y + t.offset[0], -s * x + c * y + t.offset[1]};
}

float uv_transform_length_scale(const UvTransform& t) {
    float s = std::sqrt(std::fabs(t.scale[0] * t.scale[1]));
    return std::isfinite(s) ? s : 1.0f;
}

float texture_lod(const Texture& tex, float footprint) {
    if (!(footprint > 0.0f) || tex.width <= 0 || tex.height <= 0) return 0.0f;
    float texels = footprint * std::sqrt(static_cast<float>(tex.width) * static_cast<float>(tex.height));
    return std::isfinite(texels) ? std::log2(texels) : 0.0f;
}

namespace {

int wrap_index(int i, int n, WrapMode mode) {
    switch (mode) {
        case WrapMode::ClampToEdge: return i < 0 ? 0 : (i >= n ? n - 1 : i);
        case WrapMode::MirroredRepeat: {
            int period = 2 * n;
            int m = i % period;
            if (m < 0) m += period;
            return m < n ? m : period - 1 - m;
        }
        case WrapMode::Repeat:
        default: {
            int m = i % n;
            return m < 0 ? m + n : m;
        }
    }
}

// One level of a texture: the image itself or a level of its pyramid, with the sampler's wraps,
// in whichever precision it is stored. Integer texels read as the floats k / 255 or k / 65535
// (by table for bytes), exactly what a float copy would hold; `srgb8` bytes (mip levels of 8-bit
// colour images) are decoded to linear per texel, as the float levels are linear.
struct LevelView {
    int width, height;
    TexelSource texels;
    bool srgb8;
    WrapMode wrap_s, wrap_t;

    Rgba texel(int x, int y) const {
        x = wrap_index(x, width, wrap_s);
        y = wrap_index(y, height, wrap_t);
        const size_t i = (static_cast<size_t>(y) * width + x) * 4;
        if (texels.u8) {
            const Unorm8Tables& t = unorm8_tables();
            const uint8_t* p = texels.u8 + i;
            const std::array<float, 256>& rgb = srgb8 ? t.srgb_linear : t.unorm;
            return {rgb[p[0]], rgb[p[1]], rgb[p[2]], t.unorm[p[3]]};
        }
        if (texels.u16) {
            const uint16_t* p = texels.u16 + i;
            return {p[0] / 65535.0f, p[1] / 65535.0f, p[2] / 65535.0f, p[3] / 65535.0f};
        }
        const float* p = texels.f32 + i;
        return {p[0], p[1], p[2], p[3]};
    }
};

TexelSource level0_texels(const Texture& tex) {
    TexelSource s;
    if (!tex.texels8.empty())
        s.u8 = tex.texels8.data();
    else if (!tex.texels16.empty())
        s.u16 = tex.texels16.data();
    else
        s.f32 = tex.texels.data();
    return s;
}

// Texel centres sit at half-integers: texel i covers [i, i+1) / n in texture coordinates, so a
// level's texels cover exactly the level-0 texels they average.
Rgba bilinear(const LevelView& l, Vec2 uv, bool nearest) {
    // Keep the coordinates in a range where float->int conversion is defined.
    float fx = std::fmod(uv.x, 4096.0f) * l.width - 0.5f;
    float fy = std::fmod(uv.y, 4096.0f) * l.height - 0.5f;
    if (nearest) return l.texel(static_cast<int>(std::floor(fx + 0.5f)), static_cast<int>(std::floor(fy + 0.5f)));
    float x0f = std::floor(fx), y0f = std::floor(fy);
    float tx = fx - x0f, ty = fy - y0f;
    int x0 = static_cast<int>(x0f), y0 = static_cast<int>(y0f);
    Rgba a = l.texel(x0, y0), b = l.texel(x0 + 1, y0);
    Rgba c = l.texel(x0, y0 + 1), d = l.texel(x0 + 1, y0 + 1);
    auto mix = [&](float va, float vb, float vc, float vd) {
        return (va * (1 - tx) + vb * tx) * (1 - ty) + (vc * (1 - tx) + vd * tx) * ty;
    };
    return {mix(a.r, b.r, c.r, d.r), mix(a.g, b.g, c.g, d.g), mix(a.b, b.b, c.b, d.b), mix(a.a, b.a, c.a, d.a)};
}

// Level 0, decoded to linear after filtering when the texels are sRGB-encoded.
Rgba level0(const Texture& tex, Vec2 uv) {
    LevelView l{tex.width, tex.height, level0_texels(tex), false, tex.wrap_s, tex.wrap_t};
    Rgba c = bilinear(l, uv, tex.nearest);
    if (tex.srgb) {
        c.r = srgb_to_linear(c.r);
        c.g = srgb_to_linear(c.g);
        c.b = srgb_to_linear(c.b);
    }
    return c;
}

Rgba lerp(const Rgba& a, const Rgba& b, float t) {
    return {a.r + (b.r - a.r) * t, a.g + (b.g - a.g) * t, a.b + (b.b - a.b) * t, a.a + (b.a - a.a) * t};
}

}  // namespace

Rgba sample_texture(const Texture& tex, Vec2 uv, float footprint) {
    if (tex.width <= 0 || tex.height <= 0 || !std::isfinite(uv.x) || !std::isfinite(uv.y) ||
        tex.stored_values() < static_cast<size_t>(tex.width) * tex.height * 4)
        return {1, 1, 1, 1};
    float lod = texture_lod(tex, footprint);
    if (!(lod > 0.0f) || tex.nearest || !tex.mipmaps) return level0(tex, uv);
    const std::vector<MipLevel>& levels = tex.mips.levels(tex.width, tex.height, level0_texels(tex), tex.srgb);
    int coarsest = static_cast<int>(levels.size());  // level n is levels[n - 1]
    if (coarsest == 0) return level0(tex, uv);
    auto at = [&](int k) {
        if (k == 0) return level0(tex, uv);
        const MipLevel& m = levels[static_cast<size_t>(k - 1)];
        TexelSource src;
        if (!m.texels8.empty())
            src.u8 = m.texels8.data();
        else
            src.f32 = m.texels.data();
        return bilinear(LevelView{m.width, m.height, src, m.srgb8, tex.wrap_s, tex.wrap_t}, uv, false);
    };
    if (lod >= static_cast<float>(coarsest)) return at(coarsest);
    int k = static_cast<int>(lod);
    float t = lod - static_cast<float>(k);
    return lerp(at(k), at(k + 1), t);
}

}  // namespace veach
