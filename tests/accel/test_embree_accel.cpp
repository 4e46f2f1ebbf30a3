// The accel wrapper: a mesh placed several times (Embree instances) is hit where each placement
// puts it, with the instance's index and barycentrics that locate the hit on the triangle the
// accel reports in world space; a mesh placed once (baked into world space) the same; and the
// alpha filters (glTF alphaMode) decide which hits count, on instances as on baked geometry,
// for closest hits and shadow rays alike.
#include <gtest/gtest.h>

#include <cmath>

#include "accel/embree_accel.h"
#include "core/rng.h"

namespace veach {
namespace {

// A 2 x 2 square in the plane z = 0 facing +z, u running along x and v down y as glTF images do.
Mesh square(int material) {
    Mesh m;
    m.name = "square";
    m.positions = {Vec3(-1, -1, 0), Vec3(1, -1, 0), Vec3(1, 1, 0), Vec3(-1, 1, 0)};
    m.uv0 = {{0, 1}, {1, 1}, {1, 0}, {0, 0}};
    m.indices = {0, 1, 2, 0, 2, 3};
    m.material = material;
    return m;
}

Material opaque() {
    Material m;
    m.name = "opaque";
    return m;
}

Transform turned_about_y(float radians) {
    return rotation_quaternion(0.0f, std::sin(radians / 2), 0.0f, std::cos(radians / 2));
}

// The hit point o + t d against the barycentric combination of the triangle's world vertices.
void expect_hit_on_triangle(const Accel& accel, const Vec3& o, const Vec3& d, const RayHit& h) {
    Vec3 p0, p1, p2;
    accel.triangle_world(h.instance, h.prim, &p0, &p1, &p2);
    const Vec3 at = p0 * (1.0f - h.u - h.v) + p1 * h.u + p2 * h.v;
    const Vec3 hit = o + d * h.t;
    EXPECT_NEAR(at.x, hit.x, 1e-4f);
    EXPECT_NEAR(at.y, hit.y, 1e-4f);
    EXPECT_NEAR(at.z, hit.z, 1e-4f);
}

TEST(EmbreeAccel, EachPlacementOfAnInstancedMeshIsHitWhereItStands) {
    Scene s;
    s.materials.push_back(opaque());
    s.meshes.push_back(square(0));  // placed twice: an Embree instance per placement
    s.meshes.push_back(square(0));  // placed once: baked into world space
    s.instances.push_back({0, translation(Vec3(-4, 0, 0))});
    // Turned 60 degrees about y and stretched along its own x: the plane through (4, 0, 0) with
    // normal (sin 60, 0, cos 60), 4 wide along x' and 2 tall.
    s.instances.push_back({0, translation(Vec3(4, 0, 0)) * turned_about_y(k_pi / 3) * scaling(Vec3(2, 1, 1))});
    s.instances.push_back({1, translation(Vec3(0, 4, -1))});
    Accel accel(s);

    // Straight down -z onto the first placement, with a direction of length 2: t in its units.
    Vec3 o(-4.5f, 0.25f, 5.0f), d(0, 0, -2);
    RayHit h;
    ASSERT_TRUE(accel.intersect(o, d, k_infinity, &h));
    EXPECT_EQ(h.instance, 0u);
    EXPECT_NEAR(h.t, 2.5f, 1e-5f);
    expect_hit_on_triangle(accel, o, d, h);

    // Onto the turned one: the plane n . (p - (4, 0, 0)) = 0 meets x = 4.5 at z = -0.5 tan 60.
    o = Vec3(4.5f, -0.5f, 5.0f);
    d = Vec3(0, 0, -1);
    ASSERT_TRUE(accel.intersect(o, d, k_infinity, &h));
    EXPECT_EQ(h.instance, 1u);
    EXPECT_NEAR(h.t, 5.0f + 0.5f * std::tan(k_pi / 3), 1e-4f);
    expect_hit_on_triangle(accel, o, d, h);
    // Its stretch: 2 units along x' reach x = 4 + 2 cos 60 = 5 still on it, 2.2 units not.
    EXPECT_TRUE(accel.occluded(Vec3(4.0f + 1.9f * std::cos(k_pi / 3), 0, 5), d, k_infinity));
    EXPECT_FALSE(accel.occluded(Vec3(4.0f + 2.2f * std::cos(k_pi / 3), 0, 5), d, k_infinity));

    // The baked mesh.
    o = Vec3(0.3f, 4.6f, 5.0f);
    ASSERT_TRUE(accel.intersect(o, d, k_infinity, &h));
    EXPECT_EQ(h.instance, 2u);
    EXPECT_NEAR(h.t, 6.0f, 1e-5f);
    expect_hit_on_triangle(accel, o, d, h);

    // Between the placements nothing, and t_max is respected.
    EXPECT_FALSE(accel.intersect(Vec3(0, 0, 5), d, k_infinity, &h));
    EXPECT_FALSE(accel.occluded(Vec3(-4, 0, 5), d, 4.9f));
    EXPECT_TRUE(accel.occluded(Vec3(-4, 0, 5), d, 5.1f));
}

// A MASK square whose texture's alpha is 0 on the left half and 1 on the right, placed twice in
// front of an opaque wall at z = -2, and once more on its own.
Scene masked_squares(AlphaMode mode, float base_alpha) {
    Scene s;
    Material m = opaque();
    m.alpha_mode = mode;
    m.alpha_cutoff = 0.5f;
    m.base_alpha = base_alpha;
    if (mode == AlphaMode::Mask) m.base_color_texture.texture = 0;
    s.materials.push_back(m);
    s.materials.push_back(opaque());
    Texture t;
    t.width = 2;
    t.height = 1;
    t.texels = {1, 1, 1, 0, 1, 1, 1, 1};  // RGBA: left texel alpha 0, right texel alpha 1
    t.nearest = true;
    t.wrap_s = t.wrap_t = WrapMode::ClampToEdge;
    s.textures.push_back(t);
    s.meshes.push_back(square(0));  // twice: instanced
    s.meshes.push_back(square(0));  // once: baked
    Mesh wall = square(1);
    for (Vec3& p : wall.positions) p = p * 20.0f;
    s.meshes.push_back(wall);
    s.instances.push_back({0, translation(Vec3(-3, 0, 0))});
    s.instances.push_back({0, translation(Vec3(3, 0, 0))});
    s.instances.push_back({1, translation(Vec3(0, 3, 0))});
    s.instances.push_back({2, translation(Vec3(0, 0, -2))});
    s.features.alpha = s.features.textures = true;
    return s;
}

TEST(EmbreeAccel, MaskFilterLetsRaysThroughWhereAlphaIsBelowTheCutoff) {
    Scene s = masked_squares(AlphaMode::Mask, 1.0f);
    Accel accel(s);
    const Vec3 d(0, 0, -1);
    for (Vec3 centre : {Vec3(-3, 0, 0), Vec3(3, 0, 0), Vec3(0, 3, 0)}) {
        RayHit h;
        // Left half: through to the wall (instance 3) 2 further down.
        Vec3 left = centre + Vec3(-0.5f, 0.3f, 5.0f);
        ASSERT_TRUE(accel.intersect(left, d, k_infinity, &h));
        EXPECT_EQ(h.instance, 3u);
        EXPECT_NEAR(h.t, 7.0f, 1e-5f);
        EXPECT_FALSE(accel.occluded(left, d, 6.5f));
        // Right half: stopped by the square.
        Vec3 right = centre + Vec3(0.5f, 0.3f, 5.0f);
        ASSERT_TRUE(accel.intersect(right, d, k_infinity, &h));
        EXPECT_NE(h.instance, 3u);
        EXPECT_NEAR(h.t, 5.0f, 1e-5f);
        EXPECT_TRUE(accel.occluded(right, d, 6.5f));
    }
}

TEST(EmbreeAccel, BlendFilterStopsAFractionAlphaOfRays) {
    const float alpha = 0.3f;
    Scene s = masked_squares(AlphaMode::Blend, alpha);
    Accel accel(s);
    const Vec3 d(0, 0, -1);
    Rng rng(11, 3);
    for (Vec3 centre : {Vec3(-3, 0, 0), Vec3(0, 3, 0)}) {
        const int n = 20000;
        int stopped = 0, agree = 0;
        for (int i = 0; i < n; ++i) {
            Vec3 o = centre + Vec3(rng.next_float() * 1.8f - 0.9f, rng.next_float() * 1.8f - 0.9f, 5.0f);
            RayHit h;
            ASSERT_TRUE(accel.intersect(o, d, k_infinity, &h));
            const bool on_square = h.instance != 3u;
            stopped += on_square;
            // The decision is the ray's: a shadow ray along it decides the same.
            agree += accel.occluded(o, d, 6.5f) == on_square;
        }
        const double p = static_cast<double>(stopped) / n;
        const double sigma = std::sqrt(alpha * (1.0 - alpha) / n);
        EXPECT_LT(std::fabs(p - alpha) / sigma, 4.5) << "fraction stopped " << p;
        EXPECT_EQ(agree, n);
    }
}

}  // namespace
}  // namespace veach
