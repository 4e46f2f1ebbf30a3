// The scene load is the one pipeline from a file to a scene ready to render: the repairs happen
// there and not in the importer, the environment and the white world of an unlit scene are its,
// and the identity it computes names the content and every option, never the path.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>

#include "../importers/gltf_test_builder.h"
#include "integrators/prepared_scene.h"
#include "load/scene_load.h"
#include "scene/mesh_corners.h"

namespace veach {
namespace {

using namespace gltf_test;

std::string cornell() { return std::string(VEACH_SOURCE_DIR) + "/examples/cornell/cornell.gltf"; }

TEST(SceneLoad, RepairsAreTheLoadsNotTheImporters) {
    GltfBuilder b;
    int pos = b.positions({0, 0, 0, 1, 0, 0, 0, 1, 0});
    // The same face twice, the second time wound the other way.
    int ind = b.accessor(std::vector<uint16_t>{0, 1, 2, 0, 2, 1}, k_ushort, "SCALAR");
    b.push("meshes", {{"primitives", {{{"attributes", {{"POSITION", pos}}}, {"indices", ind}}}}});
    b.place(0);
    TempDir dir;
    const std::string path = dir.write("scene.gltf", b.gltf()).string();
    // The importer keeps the file's faces as they are...
    EXPECT_EQ(import_scene(path).meshes.at(0).indices.size(), 6u);
    // ...and the load drops the duplicate, once, with one warning.
    LoadedScene loaded = load_scene_file(path, {});
    EXPECT_EQ(loaded.scene.meshes.at(0).indices, (std::vector<uint32_t>{0, 1, 2}));
    EXPECT_EQ(loaded.scene.repaired.duplicate_triangles, 1u);
    EXPECT_EQ(count_warnings(loaded.scene, "duplicate faces dropped"), 1u);
}

TEST(SceneLoad, AnUnlitSceneGetsAWhiteWorldUnlessAnEnvironmentIsAsked) {
    GltfBuilder b;
    b.place(b.triangle_mesh());
    TempDir dir;
    const std::string path = dir.write("scene.gltf", b.gltf()).string();
    LoadedScene white = load_scene_file(path, {});
    ASSERT_TRUE(white.scene.environment.enabled);
    EXPECT_EQ(white.scene.environment.color.r, 1.0f);
    EXPECT_EQ(white.scene.environment.strength, 1.0f);
    SceneLoadOptions blue;
    blue.environment.has_color = true;
    blue.environment.color = Rgb(0.1f, 0.2f, 0.8f);
    blue.environment.strength = 0.5f;
    LoadedScene lit = load_scene_file(path, blue);
    ASSERT_TRUE(lit.scene.environment.enabled);
    EXPECT_EQ(lit.scene.environment.color.b, 0.8f);
    EXPECT_EQ(lit.scene.environment.strength, 0.5f);
    EXPECT_NE(lit.identity, white.identity);
}

TEST(SceneLoad, IdentityIsTheContentAndOptionsNotThePath) {
    TempDir dir;
    const std::filesystem::path from(cornell());
    for (const char* name : {"cornell.gltf", "cornell.bin"})
        std::filesystem::copy_file(from.parent_path() / name, dir.path() / name);
    const LoadedScene a = load_scene_file(cornell(), {});
    const LoadedScene b = load_scene_file((dir.path() / "cornell.gltf").string(), {});
    EXPECT_EQ(a.file_hash, b.file_hash);
    EXPECT_EQ(a.identity, b.identity);
    SceneLoadOptions variant;
    variant.import.spot_profile = SpotProfile::Gltf;
    EXPECT_NE(load_scene_file(cornell(), variant).identity, a.identity);
    SceneLoadOptions strength;
    strength.environment.has_color = true;
    EXPECT_NE(load_scene_file(cornell(), strength).identity, a.identity);
}

TEST(SceneLoad, AnUnreadableMapIsBadInputNamingTheFile) {
    SceneLoadOptions options;
    options.environment.map_path = "/nonexistent-veach/sky.hdr";
    try {
        load_scene_file(cornell(), options);
        FAIL() << "loaded with a missing map";
    } catch (const ImportError& e) {
        EXPECT_EQ(std::string(e.what()), "/nonexistent-veach/sky.hdr: file not found");
    }
}

TEST(SceneLoad, ReposeChangesTheIdentityWithTheTimeAndBack) {
    const std::string path = std::string(VEACH_SCENES_DIR) + "/animated/animated.gltf";
    SceneLoadOptions options;
    options.import.animate = true;
    options.time = 1.0 / 24;
    LoadedScene loaded = load_scene_file(path, options);
    const uint64_t first = loaded.identity;
    const uint64_t file = loaded.file_hash;
    options.time = 6.0 / 24;
    const SceneChanges moved = repose_scene(loaded, options);
    EXPECT_TRUE(moved.any());
    EXPECT_NE(loaded.identity, first);
    EXPECT_EQ(loaded.file_hash, file);  // the file is never read again
    options.time = 1.0 / 24;
    repose_scene(loaded, options);
    EXPECT_EQ(loaded.identity, first);
    // A fresh load at that time makes the same identity.
    EXPECT_EQ(load_scene_file(path, options).identity, first);
}


bool same_bits(const void* a, const void* b, size_t bytes) { return std::memcmp(a, b, bytes) == 0; }

void expect_same_placement(const Scene& reposed, const Scene& fresh, double t) {
    ASSERT_EQ(reposed.instances.size(), fresh.instances.size());
    for (size_t i = 0; i < fresh.instances.size(); ++i)
        EXPECT_TRUE(same_bits(reposed.instances[i].object_to_world.m, fresh.instances[i].object_to_world.m,
                              sizeof(Transform::m)))
            << "instance " << i << " at t = " << t;
    for (size_t j = 0; j < fresh.meshes.size(); ++j)
        EXPECT_EQ(reposed.meshes[j].positions.size(), fresh.meshes[j].positions.size());
    for (size_t j = 0; j < fresh.meshes.size(); ++j)
        EXPECT_TRUE(same_bits(reposed.meshes[j].positions.data(), fresh.meshes[j].positions.data(),
                              fresh.meshes[j].positions.size() * sizeof(Vec3)))
            << "mesh " << j << " at t = " << t;
    const Bounds3 a = reposed.bounds(), b = fresh.bounds();
    EXPECT_TRUE(same_bits(&a, &b, sizeof(Bounds3))) << "t = " << t;
}

TEST(SceneLoad, AReposedFarOffSceneIsPlacedExactlyAsAFreshLoadOfEachFrame) {
    // Far from the origin (so the load moves it there) with a box sliding away and a sheet whose
    // morph target lifts a corner: the scene's extent, and so the rebase's offset, changes with
    // every frame, while a static box and the ground keep their pose. A re-pose keeps the static
    // instances' bounds from the frame before; what it moves must be exactly what a fresh load of
    // that frame moves, or every static instance lands elsewhere by the offsets' difference.
    GltfBuilder b;
    const float x0 = 1e5f;
    b.place(b.triangle_mesh("ground"), {{"translation", {x0, 0, 0}}, {"scale", {8, 1, 8}}});
    int box = b.triangle_mesh("box");
    b.place(box, {{"translation", {x0 - 2, 0.5, 0}}});
    int sliding = b.place(box, {{"translation", {x0, 0.5, 0}}});
    int pos = b.positions({0, 0, 0, 1, 0, 0, 0, 0, 1});
    int lift = b.positions({0, 0, 0, 0, 30, 0, 0, 0, 0});
    json prim = {{"attributes", {{"POSITION", pos}}}, {"targets", json::array({{{"POSITION", lift}}})}};
    int sheet = b.push("meshes", {{"primitives", json::array({prim})}, {"weights", {0.0}}});
    int morphing = b.place(sheet, {{"translation", {x0 + 1, 0, 1}}});
    auto animate = [&](int node, const char* path, const std::vector<float>& values, const char* type) {
        int input = b.accessor(std::vector<float>{0, 1}, k_float, "SCALAR");
        int output = b.accessor(values, k_float, type);
        b.push("animations", {{"channels", {{{"sampler", 0}, {"target", {{"node", node}, {"path", path}}}}}},
                              {"samplers", {{{"input", input}, {"output", output}}}}});
    };
    animate(sliding, "translation", {x0, 0.5f, 0, x0 + 60, 0.5f, -20}, "VEC3");
    animate(morphing, "weights", {0, 1}, "SCALAR");
    TempDir dir;
    const std::string path = dir.write("scene.gltf", b.gltf()).string();
    SceneLoadOptions options;
    options.import.animate = true;
    LoadedScene loaded = load_scene_file(path, options);
    PreparedSceneCache cache;
    cache.scene_bounds(loaded.scene);  // kept from here on
    const Transform static_box = loaded.scene.instances[1].object_to_world;
    bool offset_moved = false;
    for (double t : {0.5, 1.0, 0.25, 0.25, 0.0, 0.75}) {
        options.time = t;
        cache.note(repose_scene(loaded, options));
        const LoadedScene fresh = load_scene_file(path, options);
        expect_same_placement(loaded.scene, fresh.scene, t);
        // The render's extent check reads the cache's bounds: those of the scene as it stands.
        const Bounds3 kept = cache.scene_bounds(loaded.scene), full = loaded.scene.bounds();
        EXPECT_TRUE(same_bits(&kept, &full, sizeof(Bounds3))) << "t = " << t;
        offset_moved = offset_moved ||
                       !same_bits(static_box.m, loaded.scene.instances[1].object_to_world.m, sizeof(Transform::m));
    }
    EXPECT_TRUE(offset_moved) << "the rebase's offset never changed: the test shows nothing";
}

TEST(SceneLoad, BoundsFromEachMeshsVerticesOnceAreTheCornersBoundsBitForBit) {
    // Zeros of both signs met in another order than the vertex list's (placed by a translation of
    // -0, which keeps them), a far-off vertex no triangle uses, a non-finite corner and an index
    // past the positions: the bound from the referenced vertices (in order of first use) is the
    // bound over every corner, down to the sign of a zero.
    Scene scene;
    Mesh mesh;
    mesh.positions = {{-0.0f, -1, -1}, {0.0f, -1, -1}, {1e30f, 1e30f, 1e30f}, {0.0f, -1, 2}, {std::nanf(""), 0, 0},
                      {3, -1, -1}};
    mesh.indices = {1, 0, 3, 3, 5, 1, 4, 0, 1, 0, 5, 9};
    scene.meshes.push_back(mesh);
    for (float s : {1.0f, -1.0f}) {
        for (float t : {-0.0f, 0.5f}) {
            Instance inst;
            for (int r = 0; r < 3; ++r) inst.object_to_world.m[r][r] = s, inst.object_to_world.m[r][3] = t;
            scene.instances.push_back(inst);
        }
    }
    MeshCorners corners(scene);
    EXPECT_EQ(corners.of(0), (std::vector<uint32_t>{1, 0, 3, 5, 4}));
    const Bounds3 zero = scene.bounds_of(scene.instances[0]);
    EXPECT_FALSE(std::signbit(zero.lo.x));  // the +0 of vertex 1, met before the -0 of vertex 0
    for (const Instance& inst : scene.instances) {
        const Bounds3 a = corners.bounds_of(inst), b = scene.bounds_of(inst);
        EXPECT_TRUE(same_bits(&a, &b, sizeof(Bounds3)));
    }
    Bounds3 all;
    for (const Instance& inst : scene.instances) all.extend(scene.bounds_of(inst));
    const Bounds3 fast = scene.bounds();
    EXPECT_TRUE(same_bits(&fast, &all, sizeof(Bounds3)));
}

}  // namespace
}  // namespace veach
