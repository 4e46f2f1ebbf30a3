#include "materials/texture_sampling.h"

#include <cmath>

namespace veach {

Vec2 apply_uv_transform(const UvTransform& t, Vec2 uv) {
    if (t.is_identity()) return uv;
    float c = std::cos(t.rotation), s = std::sin(t.rotation);
    float x = uv.x * t.scale[0], y = uv.y * t.scale[1];
    // The extension's matrix is translation * rotation * scale with the rotation given in GLSL's
    // column-major form as columns (cos, sin) and (-sin, cos).
    return {c * x - s * y + t.offset[0], s * x + c * y + t.offset[1]};
}

namespace {

int wrap_index(int i, int n, WrapMode mode) {
    switch (mode) {
    case WrapMode::ClampToEdge:
        return i < 0 ? 0 : (i >= n ? n - 1 : i);
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

Rgba texel(const Texture& tex, int x, int y) {
    x = wrap_index(x, tex.width, tex.wrap_s);
    y = wrap_index(y, tex.height, tex.wrap_t);
    const float* p = &tex.texels[(static_cast<size_t>(y) * tex.width + x) * 4];
    return {p[0], p[1], p[2], p[3]};
}

}  // namespace

namespace {
Rgba filtered(const Texture& tex, Vec2 uv);
}

Rgba sample_texture(const Texture& tex, Vec2 uv) {
    Rgba c = filtered(tex, uv);
    if (tex.srgb) {
        c.r = srgb_to_linear(c.r);
        c.g = srgb_to_linear(c.g);
        c.b = srgb_to_linear(c.b);
    }
    return c;
}

namespace {

Rgba filtered(const Texture& tex, Vec2 uv) {
    if (tex.width <= 0 || tex.height <= 0 || !std::isfinite(uv.x) || !std::isfinite(uv.y))
        return {1, 1, 1, 1};
    // Keep the coordinates in a range where float->int conversion is defined.
    float fx = std::fmod(uv.x, 4096.0f) * tex.width - 0.5f;
    float fy = std::fmod(uv.y, 4096.0f) * tex.height - 0.5f;
    if (tex.nearest) return texel(tex, static_cast<int>(std::floor(fx + 0.5f)), static_cast<int>(std::floor(fy + 0.5f)));
    float x0f = std::floor(fx), y0f = std::floor(fy);
    float tx = fx - x0f, ty = fy - y0f;
    int x0 = static_cast<int>(x0f), y0 = static_cast<int>(y0f);
    Rgba a = texel(tex, x0, y0), b = texel(tex, x0 + 1, y0);
    Rgba c = texel(tex, x0, y0 + 1), d = texel(tex, x0 + 1, y0 + 1);
    auto mix = [&](float va, float vb, float vc, float vd) {
        return (va * (1 - tx) + vb * tx) * (1 - ty) + (vc * (1 - tx) + vd * tx) * ty;
    };
    return {mix(a.r, b.r, c.r, d.r), mix(a.g, b.g, c.g, d.g), mix(a.b, b.b, c.b, d.b), mix(a.a, b.a, c.a, d.a)};
}

}  // namespace

}  // namespace veach
