// Tangent-space normal maps: generated tangents follow the UVs as MikkTSpace's do, a flat map
// changes nothing, a constant tilted map tilts the shading normal by the angle it encodes, and no
// map turns the shading normal below the geometric surface.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "integrators/surface_hit.h"
#include "scene/mesh_tangents.h"
#include "test_scenes.h"

namespace veach {
namespace {

// A quad in z = 0 facing +Z with glTF's image-like UVs: u grows along +X, v grows along -Y
// (v = 0 is the image's top row), so the normal map's +X is world +X and its +Y (green) world +Y.
Mesh uv_quad() {
    Mesh m;
    m.positions = {Vec3(-1, -1, 0), Vec3(1, -1, 0), Vec3(1, 1, 0), Vec3(-1, 1, 0)};
    m.normals = {Vec3(0, 0, 1), Vec3(0, 0, 1), Vec3(0, 0, 1), Vec3(0, 0, 1)};
    m.uv0 = {{0, 1}, {1, 1}, {1, 0}, {0, 0}};
    m.indices = {0, 1, 2, 0, 2, 3};
    m.material = 0;
    return m;
}

// The surface hit at the quad's centre, seen from above, with material `m` and its textures.
SurfaceHit quad_hit(const Material& m, const std::vector<Texture>& textures, float tangent_sign = 0.0f) {
    Scene s;
    s.meshes.push_back(uv_quad());
    if (tangent_sign != 0.0f) {  // as a file's TANGENT attribute
        s.meshes[0].tangents.assign(4, Vec3(1, 0, 0));
        s.meshes[0].tangent_signs.assign(4, tangent_sign);
    } else {
        generate_tangents(&s.meshes[0], 0);
    }
    s.materials.push_back(m);
    s.textures = textures;
    s.instances.push_back({0, Transform()});
    s.cameras.push_back(test::camera_at(Vec3(0, 0, 2)));
    RenderScene rs(s, &s.cameras[0], 8, 8);
    RayHit rh;
    EXPECT_TRUE(rs.accel().intersect(Vec3(0.1f, 0.2f, 2), Vec3(0, 0, -1), k_infinity, &rh));
    return make_surface_hit(rs, rh);
}

Texture texel(float r, float g, float b) {
    Texture t;
    t.width = t.height = 1;
    t.texels = {r, g, b, 1};
    return t;
}

// The shading normal at the quad's centre with a 1x1 normal texture of `texel`.
Vec3 shading_normal(float r, float g, float b, float scale = 1.0f, float tangent_sign = 0.0f) {
    Material m = test::lambert(Rgb(0.5f));
    m.normal_texture.texture = 0;
    m.normal_scale = scale;
    return quad_hit(m, {texel(r, g, b)}, tangent_sign).ns;
}

TEST(NormalMap, GeneratedTangentsFollowTheUvs) {
    Mesh m = uv_quad();
    generate_tangents(&m, 0);
    ASSERT_EQ(m.tangents.size(), 4u);
    for (size_t i = 0; i < 4; ++i) {
        EXPECT_NEAR(m.tangents[i].x, 1.0f, 1e-6f);
        EXPECT_NEAR(m.tangents[i].y, 0.0f, 1e-6f);
        EXPECT_EQ(m.tangent_signs[i], 1.0f);  // cross(n, t) = +Y = the direction of decreasing v
    }
    // Mirrored UVs (u grows along -X) flip the handedness, as MikkTSpace's sign does.
    for (Vec2& uv : m.uv0) uv.x = 1 - uv.x;
    generate_tangents(&m, 0);
    for (size_t i = 0; i < 4; ++i) {
        EXPECT_NEAR(m.tangents[i].x, -1.0f, 1e-6f);
        EXPECT_EQ(m.tangent_signs[i], -1.0f);
    }
}

TEST(NormalMap, FlatMapChangesNothing) {
    Vec3 n = shading_normal(0.5f, 0.5f, 1.0f);
    EXPECT_NEAR(n.x, 0.0f, 1e-6f);
    EXPECT_NEAR(n.y, 0.0f, 1e-6f);
    EXPECT_NEAR(n.z, 1.0f, 1e-6f);
}

// A texel encoding (sin a, 0, cos a) tilts the normal by a toward the tangent (+X); green tilts
// toward the bitangent (+Y); normalTexture.scale multiplies x and y, so tan a' = scale tan a.
TEST(NormalMap, ConstantTiltedMapTiltsByTheEncodedAngle) {
    const float a = 0.5f;
    Vec3 n = shading_normal((std::sin(a) + 1) / 2, 0.5f, (std::cos(a) + 1) / 2);
    EXPECT_NEAR(std::acos(n.z), a, 1e-4f);
    EXPECT_NEAR(n.x, std::sin(a), 1e-4f);
    EXPECT_NEAR(n.y, 0.0f, 1e-6f);
    Vec3 g = shading_normal(0.5f, (std::sin(a) + 1) / 2, (std::cos(a) + 1) / 2);
    EXPECT_NEAR(g.y, std::sin(a), 1e-4f);
    Vec3 scaled = shading_normal((std::sin(a) + 1) / 2, 0.5f, (std::cos(a) + 1) / 2, 2.0f);
    EXPECT_NEAR(std::atan2(scaled.x, scaled.z), std::atan(2 * std::tan(a)), 1e-4f);
    // A file's TANGENT with w = -1 turns green toward -Y.
    Vec3 flipped = shading_normal(0.5f, (std::sin(a) + 1) / 2, (std::cos(a) + 1) / 2, 1.0f, -1.0f);
    EXPECT_NEAR(flipped.y, -std::sin(a), 1e-4f);
}

TEST(NormalMap, NeverBelowTheGeometricSurface) {
    Vec3 n = shading_normal(1.0f, 0.5f, 0.0f);  // encodes (1, 0, -1): below the surface
    EXPECT_NEAR(length(n), 1.0f, 1e-5f);
    EXPECT_GE(n.z, 0.019f);
    EXPECT_GT(n.x, 0.99f);  // bent up, keeping its azimuth
}

// KHR_materials_clearcoat: clearcoatNormalTexture tilts the coat's normal (SurfaceHit::ns_coat)
// and leaves the base's; a base normal map does not apply to the coat, whose normal is then the
// vertex normal. Texture 0 encodes a tilt of a toward +X, texture 1 toward +Y.
TEST(NormalMap, ClearcoatHasItsOwnNormal) {
    const float a = 0.5f;
    const float t = (std::sin(a) + 1) / 2, z = (std::cos(a) + 1) / 2;
    auto hit_with = [&](bool base_map, bool coat_map) {
        Material m = test::lambert(Rgb(0.5f));
        m.clearcoat = 1.0f;
        if (base_map) m.normal_texture.texture = 0;
        if (coat_map) m.clearcoat_normal_texture.texture = 1;
        return quad_hit(m, {texel(t, 0.5f, z), texel(0.5f, t, z)});
    };
    SurfaceHit both = hit_with(true, true);
    EXPECT_NEAR(both.ns.x, std::sin(a), 1e-4f);
    EXPECT_NEAR(both.ns_coat.y, std::sin(a), 1e-4f);
    EXPECT_NEAR(both.ns_coat.x, 0.0f, 1e-5f);
    SurfaceHit coat_only = hit_with(false, true);
    EXPECT_NEAR(coat_only.ns.z, 1.0f, 1e-6f);
    EXPECT_NEAR(coat_only.ns_coat.y, std::sin(a), 1e-4f);
    SurfaceHit base_only = hit_with(true, false);
    EXPECT_NEAR(base_only.ns.x, std::sin(a), 1e-4f);
    EXPECT_NEAR(base_only.ns_coat.z, 1.0f, 1e-6f);  // the vertex normal, not the base's map
}

}  // namespace
}  // namespace veach
