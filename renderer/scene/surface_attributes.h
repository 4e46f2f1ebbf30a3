// What a mesh carries at a point on one of its triangles: per-vertex values interpolated by
// barycentrics, and the texture coordinates and colour a material is evaluated with.
#pragma once

#include <cstdint>
#include <vector>

#include "core/math.h"
#include "core/rgb.h"
#include "scene/scene.h"

namespace veach {

// b0 a + b1 b + b2 c, summed in that order (the order every caller has always used, so images
// stay bit-identical).
inline float barycentric(float a, float b, float c, float b0, float b1, float b2) { return b0 * a + b1 * b + b2 * c; }
inline Vec2 barycentric(const Vec2& a, const Vec2& b, const Vec2& c, float b0, float b1, float b2) {
    return {barycentric(a.x, b.x, c.x, b0, b1, b2), barycentric(a.y, b.y, c.y, b0, b1, b2)};
}
inline Vec3 barycentric(const Vec3& a, const Vec3& b, const Vec3& c, float b0, float b1, float b2) {
    return a * b0 + b * b1 + c * b2;
}
inline Rgba barycentric(const Rgba& a, const Rgba& b, const Rgba& c, float b0, float b1, float b2) {
    return {barycentric(a.r, b.r, c.r, b0, b1, b2), barycentric(a.g, b.g, c.g, b0, b1, b2),
            barycentric(a.b, b.b, c.b, b0, b1, b2), barycentric(a.a, b.a, c.a, b0, b1, b2)};
}

// A per-vertex array (positions, normals, UVs, colours) at barycentrics (b0, b1, b2) of the
// triangle whose three vertex indices are `idx`.
template <class T>
T interpolate_vertices(const std::vector<T>& values, const uint32_t* idx, float b0, float b1, float b2) {
    return barycentric(values[idx[0]], values[idx[1]], values[idx[2]], b0, b1, b2);
}

struct SurfaceAttributes {
    Vec2 uv[2];
    Rgba color{1, 1, 1, 1};
    // Width of the ray's footprint in each UV set's units, for choosing mip levels
    // (materials/texture_sampling.h); 0, the default, looks up the full-resolution image. Set by
    // make_surface_hit from a ray cone (integrators/surface_hit.h).
    float uv_footprint[2] = {0, 0};
};

// TEXCOORD_0/1 of triangle `idx` (three vertex indices) at barycentrics (b0, b1, b2); a set the
// mesh lacks keeps (0, 0).
inline void interpolate_uvs(const Mesh& mesh, const uint32_t* idx, float b0, float b1, float b2,
                            SurfaceAttributes* attr) {
    for (int set = 0; set < 2; ++set) {
        const std::vector<Vec2>& uv = set == 0 ? mesh.uv0 : mesh.uv1;
        if (!uv.empty()) attr->uv[set] = interpolate_vertices(uv, idx, b0, b1, b2);
    }
}

}  // namespace veach
