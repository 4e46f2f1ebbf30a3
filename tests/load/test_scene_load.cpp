// The scene load is the one pipeline from a file to a scene ready to render: the repairs happen
// there and not in the importer, the environment and the white world of an unlit scene are its,
// and the identity it computes names the content and every option, never the path.
#include <gtest/gtest.h>

#include <filesystem>

#include "../importers/gltf_test_builder.h"
#include "load/scene_load.h"

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

}  // namespace
}  // namespace veach
