// EXT_mesh_gpu_instancing against its specification: a node's TRANSLATION / ROTATION / SCALE
// accessors place one instance each, in the node's space (world = node world x T x R x S), all
// sharing the node's mesh; the accessors are checked like any other.
#include <gtest/gtest.h>

#include <cstring>

#include "gltf_test_builder.h"
#include "importers/importer.h"
#include "scene/scene_animation.h"

namespace veach {
namespace {

using namespace gltf_test;

const float k_h = std::sqrt(0.5f);  // sin and cos of 45 degrees

// Three instances: translations, rotations (the middle one 90 degrees about Z) and scales.
const std::vector<float> k_translations = {1, 0, 0, 0, 2, 0, 0, 0, 3};
const std::vector<float> k_rotations = {0, 0, 0, 1, 0, 0, k_h, k_h, 0, 0, 0, 1};
const std::vector<float> k_scales = {1, 1, 1, 2, 2, 2, 0.5f, 1, 1};

json instancing(int translation, int rotation, int scale) {
    json attributes = json::object();
    if (translation >= 0) attributes["TRANSLATION"] = translation;
    if (rotation >= 0) attributes["ROTATION"] = rotation;
    if (scale >= 0) attributes["SCALE"] = scale;
    return {{"EXT_mesh_gpu_instancing", {{"attributes", attributes}}}};
}

// A triangle mesh placed by a node at `node_translation` carrying the three instances.
GltfBuilder instanced_scene(json node = {{"translation", {10, 0, 0}}}) {
    GltfBuilder b;
    b.doc["extensionsUsed"] = {"EXT_mesh_gpu_instancing"};
    int mesh = b.triangle_mesh();
    node["extensions"] = instancing(b.accessor(k_translations, k_float, "VEC3"),
                                    b.accessor(k_rotations, k_float, "VEC4"), b.accessor(k_scales, k_float, "VEC3"));
    b.place(mesh, node);
    return b;
}

bool same_bits(const Transform& a, const Transform& b) { return std::memcmp(a.m, b.m, sizeof(a.m)) == 0; }

TEST(GltfInstancing, InstancesShareTheMeshAndEqualExplicitChildNodesBitForBit) {
    Scene instanced = load(instanced_scene());
    // The same placements written as child nodes of a node with the same transform.
    GltfBuilder b;
    int mesh = b.triangle_mesh();
    std::vector<int> children;
    for (int i = 0; i < 3; ++i)
        children.push_back(b.push("nodes", {{"mesh", mesh},
                                            {"translation", {k_translations[3 * i], k_translations[3 * i + 1],
                                                             k_translations[3 * i + 2]}},
                                            {"rotation", {k_rotations[4 * i], k_rotations[4 * i + 1],
                                                          k_rotations[4 * i + 2], k_rotations[4 * i + 3]}},
                                            {"scale", {k_scales[3 * i], k_scales[3 * i + 1], k_scales[3 * i + 2]}}}));
    int parent = b.push("nodes", {{"translation", {10, 0, 0}}, {"children", children}});
    b.scene({parent});
    Scene nodes = load(b);

    ASSERT_EQ(instanced.meshes.size(), 1u) << "one mesh, referenced by every instance";
    ASSERT_EQ(instanced.instances.size(), 3u);
    ASSERT_EQ(nodes.instances.size(), 3u);
    EXPECT_TRUE(instanced.features.instancing);
    for (size_t i = 0; i < 3; ++i) {
        EXPECT_EQ(instanced.instances[i].mesh, 0u);
        EXPECT_TRUE(same_bits(instanced.instances[i].object_to_world, nodes.instances[i].object_to_world)) << i;
    }
    // Instance 1: rotated 90 degrees about Z, scaled 2, at (0, 2, 0) in the node's space.
    const Transform& m = instanced.instances[1].object_to_world;
    expect_vec3(m.point(Vec3(1, 0, 0)), 10, 4, 0);
    expect_vec3(instanced.instances[2].object_to_world.point(Vec3(1, 1, 0)), 10.5f, 1, 3);
    EXPECT_TRUE(instanced.warnings.empty()) << instanced.warnings.front();
}

TEST(GltfInstancing, AnyAttributeMayBeAbsentAndNormalizedIntegersDecode) {
    GltfBuilder b;
    int mesh = b.triangle_mesh();
    // ROTATION as normalized shorts (90 degrees about Z), SCALE as normalized unsigned bytes (0.5).
    const int16_t s = int16_t(std::lround(k_h * 32767));
    int rotation = b.accessor(std::vector<int16_t>{0, 0, s, s, 0, 0, 0, 32767}, k_short, "VEC4", true);
    const std::vector<uint8_t> bytes = {255, 255, 255, 0, 0, 0, 0, 0};  // elements aligned to 4 bytes
    int scale = b.push("accessors", {{"bufferView", b.view(bytes.data(), bytes.size(), 4)},
                                     {"componentType", k_ubyte},
                                     {"count", 2},
                                     {"type", "VEC3"},
                                     {"normalized", true}});
    b.place(mesh, {{"extensions", instancing(-1, rotation, scale)}});
    Scene scene = load(b);
    ASSERT_EQ(scene.instances.size(), 2u);
    expect_vec3(scene.instances[0].object_to_world.point(Vec3(1, 0, 0)), 0, 1, 0, 1e-4f);
    expect_vec3(scene.instances[1].object_to_world.point(Vec3(1, 0, 0)), 0, 0, 0);
}

TEST(GltfInstancing, MalformedAccessorsAreBadInputNamingTheNode) {
    {  // counts disagree
        GltfBuilder b;
        int mesh = b.triangle_mesh();
        b.place(mesh, {{"extensions", instancing(b.accessor(k_translations, k_float, "VEC3"), -1,
                                                 b.accessor(std::vector<float>{1, 1, 1}, k_float, "VEC3"))}});
        std::string m = expect_import_error(b);
        EXPECT_NE(m.find("must agree"), std::string::npos) << m;
        EXPECT_NE(m.find("node 0"), std::string::npos) << m;
    }
    {  // TRANSLATION of the wrong type
        GltfBuilder b;
        int mesh = b.triangle_mesh();
        b.place(mesh, {{"extensions", instancing(b.accessor(std::vector<float>{1, 2, 3, 4}, k_float, "VEC2"), -1, -1)}});
        std::string m = expect_import_error(b);
        EXPECT_NE(m.find("TRANSLATION"), std::string::npos) << m;
        EXPECT_NE(m.find("type is VEC2"), std::string::npos) << m;
    }
    {  // ROTATION as unsigned bytes: not one of the extension's types
        GltfBuilder b;
        int mesh = b.triangle_mesh();
        b.place(mesh, {{"extensions", instancing(-1, b.accessor(std::vector<uint8_t>{0, 0, 0, 255}, k_ubyte, "VEC4", true), -1)}});
        std::string m = expect_import_error(b);
        EXPECT_NE(m.find("not allowed"), std::string::npos) << m;
    }
    {  // more elements than the buffer view holds
        GltfBuilder b;
        int mesh = b.triangle_mesh();
        int t = b.accessor(k_translations, k_float, "VEC3");
        b.doc["accessors"][size_t(t)]["count"] = 1000;
        b.place(mesh, {{"extensions", instancing(t, -1, -1)}});
        expect_import_error(b);
    }
    {  // an accessor that does not exist, and no attribute at all
        GltfBuilder b;
        int mesh = b.triangle_mesh();
        b.place(mesh, {{"extensions", instancing(99, -1, -1)}});
        expect_import_error(b);
        GltfBuilder c;
        c.place(c.triangle_mesh(), {{"extensions", instancing(-1, -1, -1)}});
        expect_import_error(c);
    }
    {  // non-finite values
        GltfBuilder b;
        int mesh = b.triangle_mesh();
        b.place(mesh, {{"extensions", instancing(b.accessor(std::vector<float>{0, NAN, 0}, k_float, "VEC3"), -1, -1)}});
        std::string m = expect_import_error(b);
        EXPECT_NE(m.find("not finite"), std::string::npos) << m;
    }
}

TEST(GltfInstancing, AnAnimatedNodeMovesAllItsInstances) {
    GltfBuilder b = instanced_scene({});
    int input = b.accessor(std::vector<float>{0, 1}, k_float, "SCALAR");
    int output = b.accessor(std::vector<float>{0, 0, 0, 0, 0, 5}, k_float, "VEC3");
    b.push("animations", {{"channels", {{{"sampler", 0}, {"target", {{"node", 0}, {"path", "translation"}}}}}},
                          {"samplers", {{{"input", input}, {"output", output}}}}});
    ImportOptions o;
    o.animate = true;
    Scene s = load(b, o);
    ASSERT_EQ(s.instances.size(), 3u);
    pose_scene(s, 0.5);  // the node at (0, 0, 2.5): each instance keeps its offset from it
    expect_vec3(s.instances[0].object_to_world.point(Vec3(0, 0, 0)), 1, 0, 2.5f);
    expect_vec3(s.instances[1].object_to_world.point(Vec3(1, 0, 0)), 0, 4, 2.5f);
    expect_vec3(s.instances[2].object_to_world.point(Vec3(0, 0, 0)), 0, 0, 5.5f);
    pose_scene(s, 1.0);
    expect_vec3(s.instances[2].object_to_world.point(Vec3(0, 0, 0)), 0, 0, 8);
}

}  // namespace
}  // namespace veach
