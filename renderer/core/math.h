// Small vector and matrix types used everywhere in the renderer. Floats for geometry and
// radiance (what Embree and the film use), doubles only where accumulation needs them.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

namespace veach {

inline constexpr float k_pi = 3.14159265358979323846f;
inline constexpr float k_inv_pi = 1.0f / k_pi;
inline constexpr float k_inv_two_pi = 0.5f / k_pi;
inline constexpr float k_inv_four_pi = 0.25f / k_pi;
inline constexpr float k_infinity = std::numeric_limits<float>::infinity();
// The largest ray origin coordinate the renderer traces: Embree asserts every origin and
// direction component lies within 1.844e18 (its FLT_LARGE), and a ray past it would abort.
inline constexpr float k_max_ray_coordinate = 1e18f;

struct Vec2 {
    float x = 0, y = 0;
};

struct Vec3 {
    float x = 0, y = 0, z = 0;

    constexpr Vec3() = default;
    constexpr Vec3(float x_, float y_, float z_) : x(x_), y(y_), z(z_) {}
    float operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
    float& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }
    Vec3 operator-() const { return {-x, -y, -z}; }
    Vec3& operator+=(const Vec3& b) {
        x += b.x;
        y += b.y;
        z += b.z;
        return *this;
    }
    Vec3& operator-=(const Vec3& b) {
        x -= b.x;
        y -= b.y;
        z -= b.z;
        return *this;
    }
    Vec3& operator*=(float s) {
        x *= s;
        y *= s;
        z *= s;
        return *this;
    }
};

inline Vec3 operator+(const Vec3& a, const Vec3& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline Vec3 operator-(const Vec3& a, const Vec3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline Vec3 operator*(const Vec3& a, float s) { return {a.x * s, a.y * s, a.z * s}; }
inline Vec3 operator*(float s, const Vec3& a) { return {a.x * s, a.y * s, a.z * s}; }
inline Vec3 operator/(const Vec3& a, float s) { return a * (1.0f / s); }
inline float dot(const Vec3& a, const Vec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline float abs_dot(const Vec3& a, const Vec3& b) { return std::fabs(dot(a, b)); }
inline Vec3 cross(const Vec3& a, const Vec3& b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline float length_squared(const Vec3& a) { return dot(a, a); }
inline float length(const Vec3& a) { return std::sqrt(dot(a, a)); }
inline Vec3 normalize(const Vec3& a) { return a / length(a); }
inline Vec3 abs(const Vec3& a) { return {std::fabs(a.x), std::fabs(a.y), std::fabs(a.z)}; }
inline Vec3 min(const Vec3& a, const Vec3& b) { return {std::min(a.x, b.x), std::min(a.y, b.y), std::min(a.z, b.z)}; }
inline Vec3 max(const Vec3& a, const Vec3& b) { return {std::max(a.x, b.x), std::max(a.y, b.y), std::max(a.z, b.z)}; }
inline float max_component(const Vec3& a) { return std::max(a.x, std::max(a.y, a.z)); }
inline bool is_finite(const Vec3& a) { return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z); }
inline Vec3 face_forward(const Vec3& n, const Vec3& v) { return dot(n, v) < 0.0f ? -n : n; }

// An axis-aligned box; empty when lo > hi.
struct Bounds3 {
    Vec3 lo{k_infinity, k_infinity, k_infinity};
    Vec3 hi{-k_infinity, -k_infinity, -k_infinity};

    void extend(const Vec3& p) {
        lo = min(lo, p);
        hi = max(hi, p);
    }
    void extend(const Bounds3& b) {
        lo = min(lo, b.lo);
        hi = max(hi, b.hi);
    }
    bool empty() const { return lo.x > hi.x || lo.y > hi.y || lo.z > hi.z; }
    Vec3 center() const { return (lo + hi) * 0.5f; }
    Vec3 diagonal() const { return hi - lo; }
};

// Orthonormal frame around a unit normal (Duff et al. 2017, "Building an Orthonormal Basis,
// Revisited"): no branch on a threshold, continuous except at n.z = -1 exactly.
struct Frame {
    Vec3 s, t, n;

    Frame() : s(1, 0, 0), t(0, 1, 0), n(0, 0, 1) {}
    explicit Frame(const Vec3& normal) : n(normal) {
        float sign = std::copysign(1.0f, n.z);
        float a = -1.0f / (sign + n.z);
        float b = n.x * n.y * a;
        s = Vec3(1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x);
        t = Vec3(b, sign + n.y * n.y * a, -n.y);
    }
    Vec3 to_local(const Vec3& v) const { return {dot(v, s), dot(v, t), dot(v, n)}; }
    Vec3 to_world(const Vec3& v) const { return s * v.x + t * v.y + n * v.z; }
};

// Affine 4x4 transform, row-major: p' = M * [p 1].
struct Transform {
    float m[3][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}};

    Vec3 point(const Vec3& p) const {
        return {m[0][0] * p.x + m[0][1] * p.y + m[0][2] * p.z + m[0][3],
                m[1][0] * p.x + m[1][1] * p.y + m[1][2] * p.z + m[1][3],
                m[2][0] * p.x + m[2][1] * p.y + m[2][2] * p.z + m[2][3]};
    }
    Vec3 vector(const Vec3& v) const {
        return {m[0][0] * v.x + m[0][1] * v.y + m[0][2] * v.z, m[1][0] * v.x + m[1][1] * v.y + m[1][2] * v.z,
                m[2][0] * v.x + m[2][1] * v.y + m[2][2] * v.z};
    }
    // Normals transform by the inverse transpose: n' = (M^-1)^T n. Callers pass the inverse.
    Vec3 normal_by_inverse(const Vec3& n) const {
        return {m[0][0] * n.x + m[1][0] * n.y + m[2][0] * n.z, m[0][1] * n.x + m[1][1] * n.y + m[2][1] * n.z,
                m[0][2] * n.x + m[1][2] * n.y + m[2][2] * n.z};
    }
    bool is_identity() const {
        static const Transform identity;
        return std::memcmp(m, identity.m, sizeof(m)) == 0;
    }
    float determinant() const {
        return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
               m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    }
};

Transform operator*(const Transform& a, const Transform& b);
Transform inverse(const Transform& t);  // of the affine part; a singular matrix gives identity
Transform translation(const Vec3& t);
Transform scaling(const Vec3& s);
Transform rotation_quaternion(float x, float y, float z, float w);
// Unit quaternions as (x, y, z, w), glTF's order. normalise_quaternion makes q unit length (a
// zero or non-finite q becomes the identity); slerp_quaternion interpolates on the shorter arc (b
// negated when the two point apart: q and -q are the same rotation), normalised.
void normalise_quaternion(float* q);
void slerp_quaternion(const float* a, const float* b, double s, float* out);
// The unit quaternion of the rotation in r's 3x3 part (which must be a rotation).
std::array<float, 4> quaternion_of_rotation(const Transform& r);
// From a column-major 4x4 array (glTF's matrix layout).
Transform from_column_major(const double m[16]);

inline float clamp(float v, float lo, float hi) { return std::min(hi, std::max(lo, v)); }
inline float sqr(float v) { return v * v; }
inline float safe_sqrt(float v) { return std::sqrt(std::max(0.0f, v)); }
inline float smoothstep01(float x) {
    x = clamp(x, 0.0f, 1.0f);
    return x * x * (3.0f - 2.0f * x);
}

inline uint32_t float_bits(float f) {
    uint32_t u;
    std::memcpy(&u, &f, 4);
    return u;
}
inline float bits_float(uint32_t u) {
    float f;
    std::memcpy(&f, &u, 4);
    return f;
}
// The next representable float away from zero in the direction of `dir`'s sign.
inline float next_float_up(float v) {
    if (std::isinf(v) && v > 0.0f) return v;
    if (v == -0.0f) v = 0.0f;
    uint32_t ui = float_bits(v);
    ui = v >= 0.0f ? ui + 1 : ui - 1;
    return bits_float(ui);
}
inline float next_float_down(float v) {
    if (std::isinf(v) && v < 0.0f) return v;
    if (v == 0.0f) v = -0.0f;
    uint32_t ui = float_bits(v);
    ui = v > 0.0f ? ui - 1 : ui + 1;
    return bits_float(ui);
}

}  // namespace veach
