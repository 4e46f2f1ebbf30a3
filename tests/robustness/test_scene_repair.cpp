// scene_repair: each kind of degenerate input is dropped or repaired, counted once, and what
// survives is exactly the valid part of the mesh.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "scene/scene_repair.h"

namespace veach {
namespace {

constexpr float k_nan = std::numeric_limits<float>::quiet_NaN();
constexpr float k_inf = std::numeric_limits<float>::infinity();

// One unit right triangle (0,0,0) (1,0,0) (0,1,0) followed by whatever the test adds.
Scene one_good_triangle() {
    Scene s;
    Mesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    m.indices = {0, 1, 2};
    s.meshes.push_back(m);
    s.instances.push_back({0, Transform()});
    return s;
}

TEST(SceneRepair, ValidMeshIsUntouchedAndNotWarned) {
    Scene s = one_good_triangle();
    s.meshes[0].normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
    RepairCounts c = repair_scene(s);
    EXPECT_EQ(c.total(), 0u);
    EXPECT_TRUE(s.warnings.empty());
    EXPECT_EQ(s.meshes[0].indices, (std::vector<uint32_t>{0, 1, 2}));
}

TEST(SceneRepair, ZeroAreaCollinearAndRepeatedCornerTrianglesAreDropped) {
    Scene s = one_good_triangle();
    Mesh& m = s.meshes[0];
    m.positions.push_back({2, 2, 2});              // 3
    m.positions.push_back({4, 4, 4});              // 4: collinear with 0 and 3
    m.positions.push_back({1, 0, 0});              // 5: the same position as 1 (a repeated vertex)
    m.positions.push_back({0.1f, 0.2f, 0.3f});     // 6
    m.positions.push_back({0.3f, 0.6f, 0.9f});     // 7: collinear with 0 and 6 up to float rounding
    m.indices.insert(m.indices.end(), {0, 3, 4,    // collinear
                                       0, 0, 2,    // repeated index
                                       1, 5, 2,    // repeated position: zero area
                                       0, 6, 7});  // collinear to rounding
    RepairCounts c = repair_scene(s);
    EXPECT_EQ(c.degenerate_triangles, 4u);
    EXPECT_EQ(m.indices, (std::vector<uint32_t>{0, 1, 2}));
    ASSERT_EQ(s.warnings.size(), 1u);  // one summary, not one per triangle
    EXPECT_NE(s.warnings[0].find("4 degenerate"), std::string::npos) << s.warnings[0];
}

TEST(SceneRepair, TinyButWellShapedTrianglesSurvive) {
    // The test is relative: a scene scaled by 1e-30 keeps its triangles.
    Scene s;
    Mesh m;
    m.positions = {{0, 0, 0}, {1e-30f, 0, 0}, {0, 1e-30f, 0}, {1e30f, 0, 0}, {0, 1e30f, 0}};
    m.indices = {0, 1, 2, 0, 3, 4};
    s.meshes.push_back(m);
    EXPECT_EQ(repair_scene(s).total(), 0u);
    EXPECT_EQ(s.meshes[0].triangle_count(), 2u);
}

TEST(SceneRepair, NonFinitePositionsAndBadIndicesDropTheirTriangles) {
    Scene s = one_good_triangle();
    Mesh& m = s.meshes[0];
    m.positions.push_back({k_nan, 0, 0});  // 3
    m.positions.push_back({0, k_inf, 0});  // 4
    m.indices.insert(m.indices.end(), {0, 1, 3, 0, 4, 2, 0, 1, 99});
    RepairCounts c = repair_scene(s);
    EXPECT_EQ(c.nonfinite_triangles, 2u);
    EXPECT_EQ(c.invalid_indices, 1u);
    EXPECT_EQ(m.indices, (std::vector<uint32_t>{0, 1, 2}));
}

TEST(SceneRepair, CoincidentFacesAreDroppedWhateverTheirWinding) {
    Scene s = one_good_triangle();
    Mesh& m = s.meshes[0];
    m.positions.push_back({1, 0, 0});              // 3: a second vertex at the position of 1
    m.positions.push_back({1, 1, 0});              // 4
    m.indices.insert(m.indices.end(), {2, 1, 0,    // same face, other winding
                                       0, 3, 2,    // same positions through another vertex
                                       1, 4, 2});  // a different face sharing an edge: kept
    RepairCounts c = repair_scene(s);
    EXPECT_EQ(c.duplicate_triangles, 2u);
    EXPECT_EQ(m.indices, (std::vector<uint32_t>{0, 1, 2, 1, 4, 2}));
}

TEST(SceneRepair, BadNormalsBecomeTheFaceNormalAndOthersAreNormalised) {
    Scene s = one_good_triangle();
    Mesh& m = s.meshes[0];
    m.normals = {{0, 0, 0}, {k_nan, 0, 1}, {0, 0, 5}};
    RepairCounts c = repair_scene(s);
    EXPECT_EQ(c.normals_replaced, 2u);
    EXPECT_EQ(c.normals_normalized, 1u);
    for (const Vec3& n : m.normals) {
        EXPECT_FLOAT_EQ(n.x, 0.0f);
        EXPECT_FLOAT_EQ(n.y, 0.0f);
        EXPECT_FLOAT_EQ(n.z, 1.0f);  // the face's winding normal, unit length
    }
}

TEST(SceneRepair, NonFiniteUvsColoursAndLightsAreRepairedOrDropped) {
    Scene s = one_good_triangle();
    Mesh& m = s.meshes[0];
    m.uv0 = {{0, 0}, {k_nan, 1}, {1, k_inf}};
    m.colors = {{1, 1, 1, 1}, {k_nan, 0, 0, 1}, {1, 1, 1, 1}};
    PunctualLight good, bad;
    bad.intensity = Rgb(k_inf);
    s.lights = {bad, good};
    RepairCounts c = repair_scene(s);
    EXPECT_EQ(c.uvs_replaced, 2u);
    EXPECT_EQ(c.colors_replaced, 1u);
    EXPECT_EQ(c.lights_dropped, 1u);
    EXPECT_EQ(s.lights.size(), 1u);
    EXPECT_EQ(m.uv0[1].x, 0.0f);
    EXPECT_EQ(m.colors[1].r, 1.0f);
    EXPECT_EQ(s.repaired.total(), c.total());
}

TEST(SceneRepair, UnlitSceneGetsAWhiteEnvironmentOnce) {
    Scene s = one_good_triangle();
    EXPECT_TRUE(light_unlit_scene(s));
    EXPECT_TRUE(s.environment.enabled);
    EXPECT_EQ(s.environment.color.r, 1.0f);
    EXPECT_EQ(s.warnings.size(), 1u);
    EXPECT_FALSE(light_unlit_scene(s));  // already lit: nothing more, no second warning
    EXPECT_EQ(s.warnings.size(), 1u);

    Scene lit = one_good_triangle();
    lit.lights.push_back(PunctualLight{});
    EXPECT_FALSE(light_unlit_scene(lit));
    EXPECT_FALSE(lit.environment.enabled);
}

}  // namespace
}  // namespace veach
