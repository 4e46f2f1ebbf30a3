// Linear Rec.709 RGB radiometric quantities (radiance, throughput, reflectance).
#pragma once

#include <cmath>

namespace veach {

struct Rgb {
    float r = 0, g = 0, b = 0;

    static float fmax_inline(float x, float y) { return (x > y || y != y) ? x : y; }

    constexpr Rgb() = default;
    constexpr Rgb(float r_, float g_, float b_) : r(r_), g(g_), b(b_) {}
    constexpr explicit Rgb(float v) : r(v), g(v), b(v) {}
    Rgb& operator+=(const Rgb& o) {
        r += o.r;
        g += o.g;
        b += o.b;
        return *this;
    }
    Rgb& operator*=(const Rgb& o) {
        r *= o.r;
        g *= o.g;
        b *= o.b;
        return *this;
    }
    Rgb& operator*=(float s) {
        r *= s;
        g *= s;
        b *= s;
        return *this;
    }
    bool is_black() const { return r == 0.0f && g == 0.0f && b == 0.0f; }
    // fmax's semantics (a NaN channel is ignored), written out: std::fmax is a libm call unless
    // the compiler may assume no NaNs, and this runs several times per bounce.
    float max() const { return fmax_inline(r, fmax_inline(g, b)); }
    float luminance() const { return 0.2126f * r + 0.7152f * g + 0.0722f * b; }
    float average() const { return (r + g + b) * (1.0f / 3.0f); }
    bool is_finite() const { return std::isfinite(r) && std::isfinite(g) && std::isfinite(b); }
};

inline Rgb operator+(const Rgb& a, const Rgb& b) { return {a.r + b.r, a.g + b.g, a.b + b.b}; }
inline Rgb operator-(const Rgb& a, const Rgb& b) { return {a.r - b.r, a.g - b.g, a.b - b.b}; }
inline Rgb operator*(const Rgb& a, const Rgb& b) { return {a.r * b.r, a.g * b.g, a.b * b.b}; }
inline Rgb operator*(const Rgb& a, float s) { return {a.r * s, a.g * s, a.b * s}; }
inline Rgb operator*(float s, const Rgb& a) { return {a.r * s, a.g * s, a.b * s}; }
inline Rgb operator/(const Rgb& a, float s) { return a * (1.0f / s); }
inline Rgb lerp(const Rgb& a, const Rgb& b, float t) { return a * (1.0f - t) + b * t; }

// sRGB transfer function (IEC 61966-2-1), exact piecewise form.
inline float srgb_to_linear(float v) {
    return v <= 0.04045f ? v * (1.0f / 12.92f) : std::pow((v + 0.055f) * (1.0f / 1.055f), 2.4f);
}
inline float linear_to_srgb(float v) {
    return v <= 0.0031308f ? v * 12.92f : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
}

}  // namespace veach

namespace veach {

struct Rgba {
    float r = 0, g = 0, b = 0, a = 1;
    Rgb rgb() const { return {r, g, b}; }
};

}  // namespace veach
