// Animated glTF against the glTF 2.0 spec (3.11 animations, 3.7.3 skins, 3.7.2.2 morph
// targets): each small file is imported with ImportOptions::animate and posed by pose_scene at a
// time whose result is computed here by hand.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "gltf_test_builder.h"
#include "importers/gltf/gltf_animation_pointer.h"
#include "importers/importer.h"
#include "scene/scene_animation.h"

namespace veach {
namespace {

using namespace gltf_test;

const float k_h = std::sqrt(0.5f);  // sin and cos of 45 degrees

ImportOptions animated(const std::string& animation = "all") {
    ImportOptions o;
    o.animate = true;
    o.animation = animation;
    return o;
}

Scene posed(const GltfBuilder& b, double t, const ImportOptions& options = animated()) {
    Scene s = load(b, options);
    pose_scene(s, t);
    return s;
}

Vec3 translation_of(const Transform& m) { return Vec3(m.m[0][3], m.m[1][3], m.m[2][3]); }

// One animation of one channel on `node`: keys `times`, values `values` of `type`.
void animate(GltfBuilder& b, int node, const char* path, const std::vector<float>& times,
             const std::vector<float>& values, const char* type, const char* interpolation = "LINEAR",
             const std::string& name = "") {
    int input = b.accessor(times, k_float, "SCALAR");
    int output = b.accessor(values, k_float, type);
    json anim = {{"channels", {{{"sampler", 0}, {"target", {{"node", node}, {"path", path}}}}}},
                 {"samplers", {{{"input", input}, {"output", output}, {"interpolation", interpolation}}}}};
    if (!name.empty()) anim["name"] = name;
    b.push("animations", anim);
}

// A triangle placed by node 0, animated by `path`.
GltfBuilder moving_triangle(const char* path, const std::vector<float>& times, const std::vector<float>& values,
                            const char* type, const char* interpolation = "LINEAR") {
    GltfBuilder b = triangle_scene();
    animate(b, 0, path, times, values, type, interpolation);
    return b;
}

// --------------------------------------------------------------------------------------------
// Samplers

TEST(GltfAnimation, LinearTranslationInterpolatesAndClampsOutsideTheKeys) {
    GltfBuilder b = moving_triangle("translation", {1, 3}, {0, 0, 0, 2, 4, 6}, "VEC3");
    expect_vec3(translation_of(posed(b, 2.0).instances[0].object_to_world), 1, 2, 3);    // halfway
    expect_vec3(translation_of(posed(b, 1.5).instances[0].object_to_world), 0.5f, 1, 1.5f);
    expect_vec3(translation_of(posed(b, 0.0).instances[0].object_to_world), 0, 0, 0);    // before: first key
    expect_vec3(translation_of(posed(b, 10.0).instances[0].object_to_world), 2, 4, 6);   // after: last key
}

TEST(GltfAnimation, StepHoldsEachKeyUntilTheNext) {
    GltfBuilder b = moving_triangle("translation", {1, 3}, {0, 0, 0, 2, 4, 6}, "VEC3", "STEP");
    expect_vec3(translation_of(posed(b, 2.99).instances[0].object_to_world), 0, 0, 0);
    expect_vec3(translation_of(posed(b, 3.0).instances[0].object_to_world), 2, 4, 6);
}

TEST(GltfAnimation, ScaleChannelScalesTheNode) {
    GltfBuilder b = moving_triangle("scale", {0, 1}, {1, 1, 1, 3, 3, 3}, "VEC3");
    const Transform m = posed(b, 0.5).instances[0].object_to_world;
    EXPECT_NEAR(m.m[0][0], 2.0f, 1e-6f);
    EXPECT_NEAR(m.m[1][1], 2.0f, 1e-6f);
    EXPECT_NEAR(m.m[2][2], 2.0f, 1e-6f);
}

TEST(GltfAnimation, CubicSplineFollowsTheSpecsHermiteWithTangentsScaledByTheInterval) {
    // Keys at t = 0 and 2 (td = 2); x of (in-tangent, value, out-tangent): key 0 (0, 0, 1),
    // key 1 (3, 4, 0). At t = 0.5, u = 0.25:
    //   h00 = 2u^3 - 3u^2 + 1, h10 = u^3 - 2u^2 + u = 0.140625, h01 = -2u^3 + 3u^2 = 0.15625,
    //   h11 = u^3 - u^2 = -0.046875
    //   x = h00 * 0 + td * h10 * 1 + h01 * 4 + td * h11 * 3 = 0.28125 + 0.625 - 0.28125 = 0.625.
    GltfBuilder b = moving_triangle("translation", {0, 2}, {0, 0, 0, 0, 0, 0, 1, 0, 0, 3, 0, 0, 4, 0, 0, 0, 0, 0},
                                    "VEC3", "CUBICSPLINE");
    expect_vec3(translation_of(posed(b, 0.5).instances[0].object_to_world), 0.625f, 0, 0);
    expect_vec3(translation_of(posed(b, 2.0).instances[0].object_to_world), 4, 0, 0);  // the key's value
    expect_vec3(translation_of(posed(b, 0.0).instances[0].object_to_world), 0, 0, 0);
}

TEST(GltfAnimation, RotationSlerpsOnTheShorterArcAcrossTheSignFlip) {
    // From identity to 90 degrees about +Y written as -q (the same rotation): halfway is 45
    // degrees about +Y, not the 135 degrees the long way round would give.
    GltfBuilder b = moving_triangle("rotation", {0, 1}, {0, 0, 0, 1, 0, -k_h, 0, -k_h}, "VEC4");
    const Transform m = posed(b, 0.5).instances[0].object_to_world;
    expect_vec3(m.vector(Vec3(1, 0, 0)), k_h, 0, -k_h);  // +X turned 45 degrees toward -Z
    // A quarter of the way: 22.5 degrees, uniform in angle (slerp, not a normalised lerp).
    const Transform q = posed(b, 0.25).instances[0].object_to_world;
    const float a = k_pi / 8;
    expect_vec3(q.vector(Vec3(1, 0, 0)), std::cos(a), 0, -std::sin(a));
}

TEST(GltfAnimation, CubicSplineRotationIsNormalised) {
    // Tangents zero: the curve runs between identity and 90 degrees about +Z; every sample is a
    // rotation (unit quaternion), so lengths are kept.
    GltfBuilder b = moving_triangle(
        "rotation", {0, 1}, {0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, k_h, k_h, 0, 0, 0, 0}, "VEC4",
        "CUBICSPLINE");
    const Transform m = posed(b, 0.5).instances[0].object_to_world;
    EXPECT_NEAR(length(m.vector(Vec3(1, 0, 0))), 1.0f, 1e-5f);
    EXPECT_NEAR(m.determinant(), 1.0f, 1e-5f);
}

TEST(GltfAnimation, ChildrenFollowTheirAnimatedParent) {
    GltfBuilder b;
    int mesh = b.triangle_mesh();
    b.push("nodes", {{"children", {1}}});
    b.push("nodes", {{"mesh", mesh}, {"translation", {0, 0, 1}}});
    b.scene({0});
    animate(b, 0, "translation", {0, 1}, {0, 0, 0, 2, 0, 0}, "VEC3");
    expect_vec3(translation_of(posed(b, 0.5).instances[0].object_to_world), 1, 0, 1);
}

TEST(GltfAnimation, CamerasAndLightsMoveWithTheirNodes) {
    GltfBuilder b = light_scene("veach tests");  // nodes 0 (point at 1,2,3), 1 (sun), 2 (spot)
    b.push("cameras", {{"type", "perspective"}, {"perspective", {{"yfov", 0.5}, {"znear", 0.1}}}});
    b.push("nodes", {{"camera", 0}});
    b.doc["scenes"][0]["nodes"].push_back(3);
    animate(b, 0, "translation", {0, 1}, {1, 2, 3, 5, 2, 3}, "VEC3");
    animate(b, 3, "translation", {0, 1}, {0, 0, 0, 0, 0, 8}, "VEC3");
    animate(b, 2, "rotation", {0, 1}, {0, 0, 0, 1, -k_h, 0, 0, k_h}, "VEC4");  // to -90 about X
    Scene s = posed(b, 1.0);
    ASSERT_EQ(s.lights.size(), 3u);
    expect_vec3(s.lights[0].position, 5, 2, 3);
    expect_vec3(s.lights[2].direction, 0, -1, 0);  // -Z turned down
    expect_vec3(translation_of(s.cameras[0].camera_to_world), 0, 0, 8);
    // Time 0 is the keys' start: the file's own pose.
    Scene rest = posed(b, 0.0);
    expect_vec3(rest.lights[0].position, 1, 2, 3);
    expect_vec3(rest.lights[2].direction, 0, 0, -1);
}

TEST(GltfAnimation, WithoutAnimateTheFileIsPlacedAsItStands) {
    GltfBuilder b = moving_triangle("translation", {0, 1}, {5, 5, 5, 6, 6, 6}, "VEC3");
    Scene s = load(b);
    EXPECT_FALSE(s.animation.enabled);
    pose_scene(s, 0.5);  // nothing to evaluate
    expect_vec3(translation_of(s.instances[0].object_to_world), 0, 0, 0);
}

TEST(GltfAnimation, AnimationIsChosenByNameOrIndexAndAnUnknownOneListsTheFilesAnimations) {
    GltfBuilder b = triangle_scene();
    b.place(0);  // a second node
    animate(b, 0, "translation", {0, 1}, {0, 0, 0, 1, 0, 0}, "VEC3", "LINEAR", "slide");
    animate(b, 1, "translation", {0, 1}, {0, 0, 0, 0, 1, 0}, "VEC3", "LINEAR", "lift");
    Scene all = posed(b, 1.0);
    expect_vec3(translation_of(all.instances[0].object_to_world), 1, 0, 0);
    expect_vec3(translation_of(all.instances[1].object_to_world), 0, 1, 0);
    Scene lift = posed(b, 1.0, animated("lift"));
    expect_vec3(translation_of(lift.instances[0].object_to_world), 0, 0, 0);
    expect_vec3(translation_of(lift.instances[1].object_to_world), 0, 1, 0);
    Scene first = posed(b, 1.0, animated("0"));
    expect_vec3(translation_of(first.instances[0].object_to_world), 1, 0, 0);
    expect_vec3(translation_of(first.instances[1].object_to_world), 0, 0, 0);
    std::string message = expect_import_error(b, animated("walk"));
    EXPECT_NE(message.find("no animation 'walk'"), std::string::npos) << message;
    EXPECT_NE(message.find("'slide', 'lift'"), std::string::npos) << message;
    EXPECT_NE(expect_import_error(b, animated("2")).find("no animation '2'"), std::string::npos);
}

// --------------------------------------------------------------------------------------------
// Morph targets

// A 3 x 3 grid in the XZ plane (x = i, z = j), normals +Y, one morph target lifting each vertex
// by i * j and tilting its normal by +X; `weights` on the mesh.
GltfBuilder morph_grid(const json& mesh_weights) {
    GltfBuilder b;
    std::vector<float> p, n, dp, dn;
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i) {
            p.insert(p.end(), {float(i), 0, float(j)});
            n.insert(n.end(), {0, 1, 0});
            dp.insert(dp.end(), {0, float(i * j), 0});
            dn.insert(dn.end(), {1, 0, 0});
        }
    std::vector<uint16_t> idx;
    for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 2; ++i) {
            uint16_t a = uint16_t(j * 3 + i);
            idx.insert(idx.end(), {a, uint16_t(a + 3), uint16_t(a + 1), uint16_t(a + 1), uint16_t(a + 3), uint16_t(a + 4)});
        }
    json prim = {{"attributes", {{"POSITION", b.positions(p)}, {"NORMAL", b.accessor(n, k_float, "VEC3")}}},
                 {"indices", b.accessor(idx, k_ushort, "SCALAR")},
                 {"targets", {{{"POSITION", b.accessor(dp, k_float, "VEC3")}, {"NORMAL", b.accessor(dn, k_float, "VEC3")}}}}};
    json mesh = {{"primitives", {prim}}};
    if (!mesh_weights.is_null()) mesh["weights"] = mesh_weights;
    b.push("meshes", mesh);
    b.place(0);
    return b;
}

void expect_grid_at(const Scene& s, float w) {
    const Mesh& m = s.meshes[s.instances[0].mesh];
    ASSERT_EQ(m.positions.size(), 9u);
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i) {
            expect_vec3(m.positions[size_t(j * 3 + i)], float(i), w * float(i * j), float(j));
            Vec3 n = normalize(Vec3(w, 1, 0));  // (0,1,0) + w (1,0,0), renormalised
            expect_vec3(m.normals[size_t(j * 3 + i)], n.x, n.y, n.z);
        }
}

TEST(GltfAnimation, MorphGridAtHalfWeightIsTheAnalyticMidShape) {
    expect_grid_at(posed(morph_grid(json::array({0.5})), 0.0), 0.5f);
}

TEST(GltfAnimation, MorphWeightsComeFromTheNodeThenTheMeshThenZero) {
    expect_grid_at(posed(morph_grid(nullptr), 0.0), 0.0f);
    GltfBuilder b = morph_grid(json::array({0.5}));
    b.doc["nodes"][0]["weights"] = {0.25};
    expect_grid_at(posed(b, 0.0), 0.25f);
}

TEST(GltfAnimation, AnimatedWeightsDriveTheTargets) {
    GltfBuilder b = morph_grid(json::array({0.0}));
    animate(b, 0, "weights", {0, 2}, {0, 1}, "SCALAR");
    expect_grid_at(posed(b, 1.0), 0.5f);
    expect_grid_at(posed(b, 3.0), 1.0f);
    // The scene can be posed again at another time: it starts from the rest shape each time.
    Scene s = posed(b, 1.0);
    pose_scene(s, 0.5);
    expect_grid_at(s, 0.25f);
}

TEST(GltfAnimation, SparseMorphTargetMovesOnlyItsVertices) {
    GltfBuilder b = morph_grid(json::array({1.0}));
    // Replace the target by a sparse accessor with no bufferView: zeros, vertex 4 lifted by 2.
    std::vector<uint32_t> index = {4};
    std::vector<float> value = {0, 2, 0};
    int iv = b.view(index.data(), 4), vv = b.view(value.data(), 12);
    int sparse = b.push("accessors", {{"componentType", k_float},
                                      {"count", 9},
                                      {"type", "VEC3"},
                                      {"sparse",
                                       {{"count", 1},
                                        {"indices", {{"bufferView", iv}, {"componentType", k_uint}}},
                                        {"values", {{"bufferView", vv}}}}}});
    b.doc["meshes"][0]["primitives"][0]["targets"] = {{{"POSITION", sparse}}};
    Scene s = posed(b, 0.0);
    const Mesh& m = s.meshes[s.instances[0].mesh];
    for (int v = 0; v < 9; ++v)
        expect_vec3(m.positions[size_t(v)], float(v % 3), v == 4 ? 2.0f : 0.0f, float(v / 3));
    expect_vec3(m.normals[0], 0, 1, 0);  // no normal delta
}

// --------------------------------------------------------------------------------------------
// Skins

// A square tube of half-width r along +Y from y = 0 to 2, rings at y = 0, 0.5, 1, 1.5, 2,
// radial normals. Joint 0 (node 0, at the origin) moves the lower half, joint 1 (node 1, its
// child at y = 1) the upper half, the ring at y = 1 half each. The mesh node is node 2.
constexpr float k_r = 0.25f;
const float k_ring_y[5] = {0, 0.5f, 1, 1.5f, 2};
const float k_corner[4][2] = {{k_r, k_r}, {-k_r, k_r}, {-k_r, -k_r}, {k_r, -k_r}};

GltfBuilder bent_tube(const json& mesh_node, std::vector<float> weights = {}, bool byte_joints = false) {
    GltfBuilder b;
    std::vector<float> p, n;
    std::vector<uint16_t> joints;
    bool given = !weights.empty();
    for (int ring = 0; ring < 5; ++ring)
        for (const auto& c : k_corner) {
            p.insert(p.end(), {c[0], k_ring_y[ring], c[1]});
            n.insert(n.end(), {c[0] * k_h / k_r, 0, c[1] * k_h / k_r});
            joints.insert(joints.end(), {0, 1, 0, 0});
            if (!given) {
                float w1 = ring < 2 ? 0.0f : ring == 2 ? 0.5f : 1.0f;
                weights.insert(weights.end(), {1 - w1, w1, 0, 0});
            }
        }
    std::vector<uint16_t> idx;
    for (int ring = 0; ring < 4; ++ring)
        for (int k = 0; k < 4; ++k) {
            uint16_t a = uint16_t(ring * 4 + k), b2 = uint16_t(ring * 4 + (k + 1) % 4);
            idx.insert(idx.end(), {a, b2, uint16_t(a + 4), b2, uint16_t(b2 + 4), uint16_t(a + 4)});
        }
    int joints_accessor = byte_joints ? b.accessor(std::vector<uint8_t>(joints.begin(), joints.end()), k_ubyte, "VEC4")
                                      : b.accessor(joints, k_ushort, "VEC4");
    json prim = {{"attributes",
                  {{"POSITION", b.positions(p)},
                   {"NORMAL", b.accessor(n, k_float, "VEC3")},
                   {"JOINTS_0", joints_accessor},
                   {"WEIGHTS_0", b.accessor(weights, k_float, "VEC4")}}},
                 {"indices", b.accessor(idx, k_ushort, "SCALAR")}};
    b.push("meshes", {{"primitives", {prim}}});
    // Inverse bind matrices, column-major: identity, and translation (0, -1, 0).
    std::vector<float> ibm = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1,
                              1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, -1, 0, 1};
    int ibm_accessor = b.push("accessors", {{"bufferView", b.view(ibm.data(), ibm.size() * 4)},
                                            {"componentType", k_float},
                                            {"count", 2},
                                            {"type", "MAT4"}});
    b.push("skins", {{"joints", {0, 1}}, {"inverseBindMatrices", ibm_accessor}});
    b.push("nodes", {{"children", {1}}});
    b.push("nodes", {{"translation", {0, 1, 0}}});
    json node = mesh_node;
    node["mesh"] = 0;
    node["skin"] = 0;
    b.push("nodes", node);
    b.scene({0, 2});
    // Joint 1 turns from identity to 90 degrees about +Z between t = 0 and 1.
    animate(b, 1, "rotation", {0, 1}, {0, 0, 0, 1, 0, 0, k_h, k_h}, "VEC4");
    return b;
}

// World position of tube vertex (ring, corner) bent by 90 degrees at the joint (0, 1, 0):
// below, unchanged; above, Rz(90) about the joint: (x, y, z) -> (-(y - 1), 1 + x, z); the ring
// at the joint, the average of the two.
Vec3 bent(int ring, int corner) {
    float x = k_corner[corner][0], y = k_ring_y[ring], z = k_corner[corner][1];
    Vec3 rest(x, y, z), turned(-(y - 1), 1 + x, z);
    if (ring < 2) return rest;
    if (ring > 2) return turned;
    return (rest + turned) * 0.5f;
}

void expect_bent(const Scene& s, float offset_x = 0) {
    ASSERT_EQ(s.meshes.size(), 1u);
    const Mesh& m = s.meshes[0];
    const Transform& world = s.instances[0].object_to_world;
    for (int ring = 0; ring < 5; ++ring)
        for (int c = 0; c < 4; ++c) {
            Vec3 want = bent(ring, c);
            Vec3 got = world.point(m.positions[size_t(ring * 4 + c)]);
            expect_vec3(got, want.x + offset_x, want.y, want.z);
        }
}

TEST(GltfAnimation, TwoJointTubeBentNinetyDegreesMatchesHandComputedVertices) {
    Scene rest = posed(bent_tube(json::object()), 0.0);
    const Mesh& m = rest.meshes[0];
    expect_vec3(m.positions[19], k_r, 2, -k_r);  // at t = 0 the bind pose
    Scene s = posed(bent_tube(json::object()), 1.0);
    expect_bent(s);
    // Normals turn with their joint: the top ring's radial (x, 0, z) becomes (0, x, z).
    const Mesh& bentm = s.meshes[0];
    expect_vec3(bentm.normals[16], 0, k_h, k_h);
    expect_vec3(bentm.normals[0], k_h, 0, k_h);  // the bottom ring stays
}

TEST(GltfAnimation, SkinnedMeshNodesOwnTransformIsIgnored) {
    // glTF 3.7.3.1: only the joints place a skinned mesh; the mesh node's translation, however
    // large, moves nothing.
    expect_bent(posed(bent_tube({{"translation", {100, 0, 0}}, {"scale", {3, 3, 3}}}), 1.0));
}

TEST(GltfAnimation, SkinWeightsNotSummingToOneAreNormalised) {
    // Every vertex weighted (2, 2): normalised to (0.5, 0.5), the joint ring's blend everywhere.
    std::vector<float> w;
    for (int v = 0; v < 20; ++v) w.insert(w.end(), {2, 2, 0, 0});
    Scene s = posed(bent_tube(json::object(), w, true), 1.0);
    const Mesh& m = s.meshes[0];
    for (int ring = 0; ring < 5; ++ring)
        for (int c = 0; c < 4; ++c) {
            float x = k_corner[c][0], y = k_ring_y[ring], z = k_corner[c][1];
            Vec3 want = (Vec3(x, y, z) + Vec3(-(y - 1), 1 + x, z)) * 0.5f;
            Vec3 got = m.positions[size_t(ring * 4 + c)];
            expect_vec3(got, want.x, want.y, want.z);
        }
    EXPECT_EQ(count_warnings(s, "do not sum to 1"), 1u);
}

TEST(GltfAnimation, NormalisedUnsignedShortWeightsAndASecondInfluenceSet) {
    // WEIGHTS_0 holds joint 0 at 65535/65535 for the bottom ring only; everything else takes its
    // weight from JOINTS_1/WEIGHTS_1 (joint 1, normalised u16): the top rings follow joint 1.
    GltfBuilder b = bent_tube(json::object());
    std::vector<uint16_t> w0, w1, j1;
    for (int v = 0; v < 20; ++v) {
        bool bottom = v < 4;
        w0.insert(w0.end(), {uint16_t(bottom ? 65535 : 0), 0, 0, 0});
        w1.insert(w1.end(), {uint16_t(bottom ? 0 : 65535), 0, 0, 0});
        j1.insert(j1.end(), {1, 0, 0, 0});
    }
    json& attributes = b.doc["meshes"][0]["primitives"][0]["attributes"];
    attributes["WEIGHTS_0"] = b.accessor(w0, k_ushort, "VEC4", true);
    attributes["WEIGHTS_1"] = b.accessor(w1, k_ushort, "VEC4", true);
    attributes["JOINTS_1"] = b.accessor(j1, k_ushort, "VEC4");
    Scene s = posed(b, 1.0);
    const Mesh& m = s.meshes[0];
    expect_vec3(m.positions[0], k_r, 0, k_r);                  // joint 0: unchanged
    expect_vec3(m.positions[16], -(2 - 1), 1 + k_r, k_r);       // joint 1: turned
    expect_vec3(m.positions[4], -(0.5f - 1), 1 + k_r, k_r);     // joint 1 below the joint too
}

TEST(GltfAnimation, JointIndexPastTheSkinIsBadInput) {
    GltfBuilder b = bent_tube(json::object());
    std::vector<uint16_t> j(80, 0);
    j[0] = 7;
    b.doc["meshes"][0]["primitives"][0]["attributes"]["JOINTS_0"] = b.accessor(j, k_ushort, "VEC4");
    std::string message = expect_import_error(b, animated());
    EXPECT_NE(message.find("is not one of the skin's 2"), std::string::npos) << message;
}

// --------------------------------------------------------------------------------------------
// Morph targets of texture coordinates and colours

TEST(GltfAnimation, TexcoordAndColorDeltasFollowTheWeights) {
    GltfBuilder b;
    int pos = b.positions({0, 0, 0, 1, 0, 0, 0, 1, 0});
    int uv = b.accessor(std::vector<float>{0, 0, 1, 0, 0, 1}, k_float, "VEC2");
    int color = b.accessor(std::vector<float>{0.2f, 0.2f, 0.2f, 1, 0.5f, 0.5f, 0.5f, 1, 0.9f, 0.9f, 0.9f, 1}, k_float, "VEC4");
    int duv = b.accessor(std::vector<float>{0.5f, 0, 0, 0.5f, -1, -1}, k_float, "VEC2");
    int dcolor = b.accessor(std::vector<float>{0.4f, 0, 0, 0, 0.4f, 0, 0, 0, 0.4f}, k_float, "VEC3");
    json prim = {{"attributes", {{"POSITION", pos}, {"TEXCOORD_0", uv}, {"COLOR_0", color}}},
                 {"targets", {{{"TEXCOORD_0", duv}, {"COLOR_0", dcolor}}}}};
    b.push("meshes", {{"primitives", {prim}}, {"weights", {0.5}}});
    b.place(0);
    Scene s = posed(b, 0.0);
    const Mesh& m = s.meshes[s.instances[0].mesh];
    ASSERT_EQ(m.uv0.size(), 3u);
    EXPECT_FLOAT_EQ(m.uv0[0].x, 0.25f);
    EXPECT_FLOAT_EQ(m.uv0[1].y, 0.25f);
    EXPECT_FLOAT_EQ(m.uv0[2].x, -0.5f);
    EXPECT_FLOAT_EQ(m.uv0[2].y, 0.5f);
    ASSERT_EQ(m.colors.size(), 3u);
    EXPECT_FLOAT_EQ(m.colors[0].r, 0.4f);
    EXPECT_FLOAT_EQ(m.colors[1].g, 0.7f);
    EXPECT_FLOAT_EQ(m.colors[2].b, 1.0f);  // 0.9 + 0.2, held to 1 as the import holds COLOR_0
    EXPECT_FLOAT_EQ(m.colors[2].a, 1.0f);  // a VEC3 delta leaves alpha alone
    // Weight 0 is the file's own values again.
    b.doc["meshes"][0]["weights"] = {0.0};
    Scene zero = posed(b, 0.0);
    EXPECT_FLOAT_EQ(zero.meshes[zero.instances[0].mesh].uv0[2].x, 0.0f);
    EXPECT_FLOAT_EQ(zero.meshes[zero.instances[0].mesh].colors[0].r, 0.2f);
}

// --------------------------------------------------------------------------------------------
// Tangents, the weights channel's samplers, normalised byte skin weights

// A normal-mapped material 0 (so the import keeps TANGENT) and `uvs` texture coordinates on
// primitive 0 of mesh 0.
void normal_mapped(GltfBuilder& b, size_t vertices) {
    json& prim = b.doc["meshes"][0]["primitives"][0];
    prim["attributes"]["TEXCOORD_0"] = b.accessor(std::vector<float>(2 * vertices, 0.0f), k_float, "VEC2");
    prim["material"] = 0;
    b.push("materials", {{"normalTexture", {{"index", 0}}}});
    b.push("images", {{"uri", std::string("data:image/png;base64,") + k_png_2x2}});
    b.push("textures", {{"source", 0}});
}

TEST(GltfAnimation, TangentDeltasAddAndSkinnedTangentsTurnWithTheirJoints) {
    // Morph: tangents +X, a TANGENT target of +Z at weight 1: (1, 0, 1), renormalised (glTF
    // 3.7.2.2: the delta is added to the xyz, the handedness w stays).
    GltfBuilder m = morph_grid(json::array({1.0}));
    m.doc["meshes"][0]["primitives"][0]["attributes"]["TANGENT"] =
        m.accessor(std::vector<float>{1, 0, 0, -1, 1, 0, 0, -1, 1, 0, 0, -1, 1, 0, 0, -1, 1, 0, 0, -1, 1, 0, 0, -1, 1, 0,
                                      0, -1, 1, 0, 0, -1, 1, 0, 0, -1},
                   k_float, "VEC4");
    std::vector<float> dt;
    for (int v = 0; v < 9; ++v) dt.insert(dt.end(), {0, 0, 1});
    m.doc["meshes"][0]["primitives"][0]["targets"][0]["TANGENT"] = m.accessor(dt, k_float, "VEC3");
    normal_mapped(m, 9);
    Scene ms = posed(m, 0.0);
    const Mesh& grid = ms.meshes[ms.instances[0].mesh];
    ASSERT_EQ(grid.tangents.size(), 9u);
    for (size_t v = 0; v < 9; ++v) {
        expect_vec3(grid.tangents[v], k_h, 0, k_h);
        EXPECT_EQ(grid.tangent_signs[v], -1.0f);
    }
    // Skin: the tube's tangents run along +Y; bent by 90 degrees about +Z at the joint, the top
    // rings' turn to -X, the joint ring's are the average of the two matrices applied, (-1, 1, 0)
    // renormalised, the bottom rings' stay.
    GltfBuilder b = bent_tube(json::object());
    std::vector<float> t;
    for (int v = 0; v < 20; ++v) t.insert(t.end(), {0, 1, 0, 1});
    b.doc["meshes"][0]["primitives"][0]["attributes"]["TANGENT"] = b.accessor(t, k_float, "VEC4");
    normal_mapped(b, 20);
    Scene s = posed(b, 1.0);
    const Mesh& tube = s.meshes[0];
    ASSERT_EQ(tube.tangents.size(), 20u);
    for (int c = 0; c < 4; ++c) {
        expect_vec3(tube.tangents[size_t(0 * 4 + c)], 0, 1, 0);
        expect_vec3(tube.tangents[size_t(1 * 4 + c)], 0, 1, 0);
        expect_vec3(tube.tangents[size_t(2 * 4 + c)], -k_h, k_h, 0);
        expect_vec3(tube.tangents[size_t(3 * 4 + c)], -1, 0, 0);
        expect_vec3(tube.tangents[size_t(4 * 4 + c)], -1, 0, 0);
    }
}

// morph_grid with a second target lifting every vertex by 10; weights (w0, w1) put vertex
// (i, j) at height w0 i j + 10 w1 with the normal (w0, 1, 0) renormalised.
void expect_two_target_grid_at(const Scene& s, float w0, float w1) {
    const Mesh& m = s.meshes[s.instances[0].mesh];
    ASSERT_EQ(m.positions.size(), 9u);
    Vec3 n = normalize(Vec3(w0, 1, 0));
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i) {
            expect_vec3(m.positions[size_t(j * 3 + i)], float(i), w0 * float(i * j) + 10 * w1, float(j));
            expect_vec3(m.normals[size_t(j * 3 + i)], n.x, n.y, n.z);
        }
}

GltfBuilder two_target_grid() {
    GltfBuilder b = morph_grid(json::array({0.0, 0.0}));
    std::vector<float> lift;
    for (int v = 0; v < 9; ++v) lift.insert(lift.end(), {0, 10, 0});
    b.doc["meshes"][0]["primitives"][0]["targets"].push_back({{"POSITION", b.accessor(lift, k_float, "VEC3")}});
    return b;
}

TEST(GltfAnimation, WeightsChannelStepsAndFollowsTheCubicSplineTargetByTarget) {
    // STEP: each key's weights held until the next key.
    GltfBuilder step = two_target_grid();
    animate(step, 0, "weights", {0, 1}, {0, 0, 1, 0.5f}, "SCALAR", "STEP");
    expect_two_target_grid_at(posed(step, 0.99), 0, 0);
    expect_two_target_grid_at(posed(step, 1.0), 1, 0.5f);
    // CUBICSPLINE (glTF 3.11.2: per key, the in-tangents of every target, then the values, then
    // the out-tangents): keys at t = 0 and 2, target 0 (a, v, b) = (0, 0, 1) then (0, 1, 0),
    // target 1 (0, 0, 0) then (-0.4, 0.2, 0). At t = 1 (u = 0.5, td = 2) the spec's Hermite
    // p = 0.5 v0 + 0.25 b0 + 0.5 v1 - 0.25 a1 gives w0 = 0.75 and w1 = 0.2; reading the values
    // target-major (a, v, b of target 0, then of target 1) would give other weights.
    GltfBuilder cubic = two_target_grid();
    animate(cubic, 0, "weights", {0, 2}, {0, 0, 0, 0, 1, 0, 0, -0.4f, 1, 0.2f, 0, 0}, "SCALAR", "CUBICSPLINE");
    expect_two_target_grid_at(posed(cubic, 1.0), 0.75f, 0.2f);
    expect_two_target_grid_at(posed(cubic, 2.0), 1, 0.2f);
}

TEST(GltfAnimation, NormalisedUnsignedByteWeightsDecodeAsFractionsOf255) {
    // WEIGHTS_0 as normalised unsigned bytes: (255, 0) below the joint, (0, 255) above, and
    // (128, 127) on the joint ring: 128/255 of the rest pose and 127/255 of the turned one.
    GltfBuilder b = bent_tube(json::object());
    std::vector<uint8_t> w;
    for (int ring = 0; ring < 5; ++ring)
        for (int c = 0; c < 4; ++c)
            w.insert(w.end(), {uint8_t(ring < 2 ? 255 : ring == 2 ? 128 : 0), uint8_t(ring < 2 ? 0 : ring == 2 ? 127 : 255),
                               0, 0});
    b.doc["meshes"][0]["primitives"][0]["attributes"]["WEIGHTS_0"] = b.accessor(w, k_ubyte, "VEC4", true);
    Scene s = posed(b, 1.0);
    const Mesh& m = s.meshes[0];
    for (int ring = 0; ring < 5; ++ring)
        for (int c = 0; c < 4; ++c) {
            float x = k_corner[c][0], y = k_ring_y[ring], z = k_corner[c][1];
            Vec3 want = ring == 2 ? Vec3(x, y, z) * (128.0f / 255.0f) + Vec3(-(y - 1), 1 + x, z) * (127.0f / 255.0f)
                                  : bent(ring, c);
            expect_vec3(m.positions[size_t(ring * 4 + c)], want.x, want.y, want.z);
        }
    EXPECT_EQ(count_warnings(s, "do not sum to 1"), 0u);
}

// --------------------------------------------------------------------------------------------
// KHR_animation_pointer

// One animation of one pointer channel: keys `times`, values `values` of `type`.
void animate_pointer(GltfBuilder& b, const std::string& pointer, const std::vector<float>& times,
                     const std::vector<float>& values, const char* type) {
    int input = b.accessor(times, k_float, "SCALAR");
    int output = b.accessor(values, k_float, type);
    json target = {{"path", "pointer"}, {"extensions", {{"KHR_animation_pointer", {{"pointer", pointer}}}}}};
    b.push("animations", {{"channels", {{{"sampler", 0}, {"target", target}}}},
                          {"samplers", {{{"input", input}, {"output", output}}}}});
    if (!b.doc.contains("extensionsUsed")) b.doc["extensionsUsed"] = json::array();
    if (std::find(b.doc["extensionsUsed"].begin(), b.doc["extensionsUsed"].end(), "KHR_animation_pointer") ==
        b.doc["extensionsUsed"].end())
        b.doc["extensionsUsed"].push_back("KHR_animation_pointer");
}

// A triangle wearing material 0: white, rough, emitting (1, 0.5, 0) at strength 2.
GltfBuilder material_triangle() {
    GltfBuilder b;
    int mesh = b.push("meshes", {{"primitives", {{{"attributes", {{"POSITION", b.positions({0, 0, 0, 1, 0, 0, 0, 1, 0})}}},
                                                 {"material", 0}}}}});
    b.push("materials", {{"pbrMetallicRoughness", {{"baseColorFactor", {1, 1, 1, 1}}, {"roughnessFactor", 1.0}}},
                         {"emissiveFactor", {1, 0.5, 0}},
                         {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", 2.0}}}}}});
    b.place(mesh);
    return b;
}

void expect_rgb(const Rgb& c, float r, float g, float b) {
    EXPECT_NEAR(c.r, r, 1e-6f);
    EXPECT_NEAR(c.g, g, 1e-6f);
    EXPECT_NEAR(c.b, b, 1e-6f);
}

TEST(GltfAnimationPointer, MaterialFactorsFollowTheirChannels) {
    GltfBuilder b = material_triangle();
    animate_pointer(b, "/materials/0/pbrMetallicRoughness/baseColorFactor", {0, 1}, {1, 1, 1, 1, 0, 0.5f, 1, 0.5f}, "VEC4");
    animate_pointer(b, "/materials/0/pbrMetallicRoughness/roughnessFactor", {0, 1}, {1, 0}, "SCALAR");
    animate_pointer(b, "/materials/0/extensions/KHR_materials_emissive_strength/emissiveStrength", {0, 1}, {2, 4},
                    "SCALAR");
    animate_pointer(b, "/materials/0/emissiveFactor", {0, 1}, {1, 0.5f, 0, 0, 0.5f, 1}, "VEC3");
    Scene s = posed(b, 0.5);
    ASSERT_EQ(s.materials.size(), 1u);
    const Material& m = s.materials[0];
    expect_rgb(m.base_color, 0.5f, 0.75f, 1.0f);
    EXPECT_NEAR(m.base_alpha, 0.75f, 1e-6f);
    EXPECT_NEAR(m.roughness, 0.5f, 1e-6f);
    expect_rgb(m.emission, 0.5f * 3, 0.5f * 3, 0.5f * 3);  // factor (0.5, 0.5, 0.5) x strength 3
    // At the first key every factor is the file's: bit for bit the material the import made.
    Scene rest = posed(b, 0.0);
    Scene still = load(b);
    EXPECT_EQ(rest.materials[0].base_color.r, still.materials[0].base_color.r);
    EXPECT_EQ(rest.materials[0].roughness, still.materials[0].roughness);
    EXPECT_EQ(rest.materials[0].emission.g, still.materials[0].emission.g);
    EXPECT_TRUE(rest.warnings.empty()) << rest.warnings[0];
}

TEST(GltfAnimationPointer, AnimatedFactorsAreHeldToTheSpecsRanges) {
    GltfBuilder b = material_triangle();
    animate_pointer(b, "/materials/0/pbrMetallicRoughness/metallicFactor", {0, 1}, {-1, 3}, "SCALAR");
    EXPECT_EQ(posed(b, 0.0).materials[0].metallic, 0.0f);
    EXPECT_EQ(posed(b, 1.0).materials[0].metallic, 1.0f);
}

TEST(GltfAnimationPointer, UnlitBaseColourAnimatesWhatIsSeen) {
    GltfBuilder b = material_triangle();
    b.doc["materials"][0]["extensions"] = {{"KHR_materials_unlit", json::object()}};
    animate_pointer(b, "/materials/0/pbrMetallicRoughness/baseColorFactor", {0, 1}, {1, 1, 1, 1, 0, 0.5f, 1, 1}, "VEC4");
    const Scene s = posed(b, 1.0);
    const Material& m = s.materials[0];
    expect_rgb(m.emission, 0.0f, 0.5f, 1.0f);
    expect_rgb(m.base_color, 0.0f, 0.0f, 0.0f);
}

TEST(GltfAnimationPointer, LightColourIntensityAndConeFollowTheirChannels) {
    GltfBuilder b = light_scene("veach tests");  // lights 0 point (colour 1, .5, .25, 2 x 683), 1 sun, 2 spot
    animate_pointer(b, "/extensions/KHR_lights_punctual/lights/0/intensity", {0, 1}, {683 * 2, 683 * 4}, "SCALAR");
    animate_pointer(b, "/extensions/KHR_lights_punctual/lights/1/color", {0, 1}, {1, 1, 1, 0, 1, 0}, "VEC3");
    animate_pointer(b, "/extensions/KHR_lights_punctual/lights/2/spot/outerConeAngle", {0, 1}, {0.5f, 1.0f}, "SCALAR");
    Scene s = posed(b, 0.5);
    ASSERT_EQ(s.lights.size(), 3u);
    expect_rgb(s.lights[0].intensity, 3.0f, 1.5f, 0.75f);  // 683 x 3 cd of colour (1, .5, .25) -> 3 W/sr
    expect_rgb(s.lights[1].intensity, 0.5f, 1.0f, 0.5f);
    EXPECT_NEAR(s.lights[2].cos_outer, std::cos(0.75f), 1e-6f);
    EXPECT_NEAR(s.lights[2].cos_inner, std::cos(0.25f), 1e-6f);
    EXPECT_NEAR(s.lights[2].blend, 1.0f - 0.25f / 0.75f, 1e-6f);
    Scene rest = posed(b, 0.0), still = load(b);
    for (size_t i = 0; i < 3; ++i) {
        EXPECT_EQ(rest.lights[i].intensity.r, still.lights[i].intensity.r);
        EXPECT_EQ(rest.lights[i].cos_outer, still.lights[i].cos_outer);
    }
}

TEST(GltfAnimationPointer, CameraFieldOfViewFollowsItsChannel) {
    GltfBuilder b = triangle_scene();
    b.push("cameras", {{"type", "perspective"}, {"perspective", {{"yfov", 0.5}, {"znear", 0.1}}}});
    b.push("nodes", {{"camera", 0}});
    b.doc["scenes"][0]["nodes"].push_back(1);
    animate_pointer(b, "/cameras/0/perspective/yfov", {0, 1}, {0.5f, 1.0f}, "SCALAR");
    Scene s = posed(b, 0.5);
    ASSERT_EQ(s.cameras.size(), 1u);
    EXPECT_NEAR(s.cameras[0].yfov, 0.75f, 1e-6f);
}

TEST(GltfAnimationPointer, NodePointersAreNodeChannels) {
    GltfBuilder b = triangle_scene();
    animate_pointer(b, "/nodes/0/translation", {0, 1}, {0, 0, 0, 2, 0, 0}, "VEC3");
    expect_vec3(translation_of(posed(b, 0.5).instances[0].object_to_world), 1, 0, 0);
}

TEST(GltfAnimationPointer, PointersThatAreNotEvaluatedAreSkippedWithAWarning) {
    GltfBuilder b = material_triangle();
    animate_pointer(b, "/materials/0/normalTexture/scale", {0, 1}, {1, 2}, "SCALAR");
    animate_pointer(b, "/materials/7/emissiveFactor", {0, 1}, {0, 0, 0, 1, 1, 1}, "VEC3");
    animate_pointer(b, "/materials/0/emissiveFactor", {0, 1}, {0, 1}, "SCALAR");  // wrong type
    Scene s = posed(b, 1.0);
    std::string all;
    for (const std::string& w : s.warnings) all += w + "\n";
    EXPECT_NE(all.find("/materials/0/normalTexture/scale (KHR_animation_pointer) is not evaluated"), std::string::npos)
        << all;
    EXPECT_NE(all.find("/materials/7/emissiveFactor points at something the file does not have"), std::string::npos)
        << all;
    EXPECT_NE(all.find("has 1 values per key for a property of 3"), std::string::npos) << all;
    expect_rgb(s.materials[0].emission, 2.0f, 1.0f, 0.0f);  // untouched
    EXPECT_EQ(all.find("ignoring unsupported extension"), std::string::npos) << all;
}

TEST(GltfAnimationPointer, PointerParsingFollowsJsonPointerRules) {
    using gltf::parse_animation_pointer;
    EXPECT_FALSE(parse_animation_pointer("materials/0/emissiveFactor"));  // not absolute
    EXPECT_FALSE(parse_animation_pointer("/materials/01/emissiveFactor"));  // leading zero
    EXPECT_FALSE(parse_animation_pointer("/materials/-1/emissiveFactor"));
    EXPECT_FALSE(parse_animation_pointer("/nodes/0/matrix"));
    auto t = parse_animation_pointer("/extensions/KHR_lights_punctual/lights/12/spot/innerConeAngle");
    ASSERT_TRUE(t && t->property);
    EXPECT_EQ(*t->property, AnimatedProperty::SpotInnerCone);
    EXPECT_EQ(t->target, 12);
    auto n = parse_animation_pointer("/nodes/3/weights");
    ASSERT_TRUE(n);
    EXPECT_FALSE(n->property);
    EXPECT_EQ(n->node, 3);
    EXPECT_EQ(n->path, AnimatedPath::Weights);
}

}  // namespace
}  // namespace veach
