// The glTF importer against what the glTF 2.0 spec and Blender's exporter require. Most cases
// build a tiny glTF in the test (JSON + an embedded or separate buffer, or a GLB) so the
// expected values are visible next to the input.
#include <gtest/gtest.h>

#include "materials/texture_sampling.h"

#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <set>
#include <thread>

#include "gltf_test_builder.h"
#include "importers/gltf/gltf_extensions.h"
#include "importers/importer.h"

namespace veach {
namespace {

using namespace gltf_test;

// --------------------------------------------------------------------------------------------
// Hierarchy and instancing

TEST(GltfImporter, TrsHierarchyComposesParentTimesChild) {
    GltfBuilder b;
    int mesh = b.triangle_mesh();
    const float h = std::sqrt(0.5f);  // 90 degrees about +Z
    b.push("nodes", {{"translation", {1, 0, 0}}, {"rotation", {0, 0, h, h}}, {"scale", {2, 2, 2}}, {"children", {1}}});
    b.push("nodes", {{"translation", {0, 1, 0}}, {"mesh", mesh}});
    b.scene({0});
    Scene s = load(b);
    ASSERT_EQ(s.instances.size(), 1u);
    // Vertex (1,0,0): child -> (1,1,0), scale -> (2,2,0), rotate -> (-2,2,0), translate -> (-1,2,0).
    expect_vec3(s.instances[0].object_to_world.point(s.meshes[0].positions[1]), -1, 2, 0);
}

TEST(GltfImporter, MatrixHierarchyIsColumnMajor) {
    GltfBuilder b;
    int mesh = b.triangle_mesh();
    b.push("nodes", {{"matrix", {1, 0, 0, 0, 0, 2, 0, 0, 0, 0, 1, 0, 0, 0, 5, 1}}, {"children", {1}}});
    b.push("nodes", {{"matrix", {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 1, 1, 1, 1}}, {"mesh", mesh}});
    b.scene({0});
    Scene s = load(b);
    ASSERT_EQ(s.instances.size(), 1u);
    expect_vec3(s.instances[0].object_to_world.point(s.meshes[0].positions[1]), 2, 2, 6);
}

TEST(GltfImporter, MeshUsedByTwoNodesIsStoredOnceAndInstancedTwice) {
    GltfBuilder b;
    int mesh = b.triangle_mesh();
    b.place(mesh, {{"translation", {-3, 0, 0}}});
    b.place(mesh, {{"translation", {3, 0, 0}}});
    Scene s = load(b);
    ASSERT_EQ(s.meshes.size(), 1u);
    ASSERT_EQ(s.instances.size(), 2u);
    EXPECT_EQ(s.instances[0].mesh, 0u);
    EXPECT_EQ(s.instances[1].mesh, 0u);
    expect_vec3(s.instances[0].object_to_world.point({0, 0, 0}), -3, 0, 0);
    expect_vec3(s.instances[1].object_to_world.point({0, 0, 0}), 3, 0, 0);
    EXPECT_TRUE(s.features.instancing);
    EXPECT_EQ(s.triangle_count(), 2u);
}

TEST(GltfImporter, EachPrimitiveIsAMeshAndEachPlacementAnInstance) {
    GltfBuilder b;
    int p0 = b.positions({0, 0, 0, 1, 0, 0, 0, 1, 0});
    int p1 = b.positions({0, 0, 1, 1, 0, 1, 0, 1, 1});
    b.push("meshes", {{"name", "two"},
                      {"primitives", {{{"attributes", {{"POSITION", p0}}}}, {{"attributes", {{"POSITION", p1}}}}}}});
    b.place(0);
    b.place(0, {{"translation", {0, 5, 0}}});
    Scene s = load(b);
    EXPECT_EQ(s.meshes.size(), 2u);
    EXPECT_EQ(s.instances.size(), 4u);
    EXPECT_TRUE(s.features.instancing);
}

TEST(GltfImporter, SingleUseMeshIsNotInstancing) {
    Scene s = import_scene(data_dir() + "triangle.gltf");
    ASSERT_EQ(s.meshes.size(), 1u);
    EXPECT_FALSE(s.features.instancing);
    EXPECT_EQ(s.meshes[0].name, "triangle");
    EXPECT_EQ(s.meshes[0].indices, (std::vector<uint32_t>{0, 1, 2}));
    expect_vec3(s.instances[0].object_to_world.point(s.meshes[0].positions[2]), 0, 1, -2);
    EXPECT_TRUE(s.warnings.empty());
}

TEST(GltfImporter, OnlyNodesOfTheSelectedSceneAreBuilt) {
    GltfBuilder b;
    int m0 = b.triangle_mesh("first");
    int m1 = b.triangle_mesh("second");
    b.push("nodes", {{"mesh", m0}});
    b.push("nodes", {{"mesh", m1}});
    b.doc["scenes"] = json::array({{{"nodes", {0}}}, {{"nodes", {1}}}});
    b.doc["scene"] = 1;
    Scene by_default = load(b);
    ASSERT_EQ(by_default.meshes.size(), 1u);
    EXPECT_EQ(by_default.meshes[0].name, "second");
    ImportOptions first;
    first.scene_index = 0;
    Scene chosen = load(b, first);
    ASSERT_EQ(chosen.meshes.size(), 1u);
    EXPECT_EQ(chosen.meshes[0].name, "first");
}

TEST(GltfImporter, NoScenesRendersRootNodesWithAWarning) {
    GltfBuilder b;
    int mesh = b.triangle_mesh();
    b.push("nodes", {{"mesh", mesh}, {"children", {1}}});
    b.push("nodes", {{"mesh", mesh}, {"translation", {0, 0, 1}}});
    Scene s = load(b);
    EXPECT_EQ(s.instances.size(), 2u);  // the root and its child, the child only once
    EXPECT_EQ(count_warnings(s, "no scenes"), 1u);
}

TEST(GltfImporter, EmptySceneIsValidWithAWarning) {
    Scene s = load_text(R"({"asset": {"version": "2.0"}, "scenes": [{"nodes": []}], "scene": 0})");
    EXPECT_TRUE(s.meshes.empty());
    EXPECT_TRUE(s.instances.empty());
    EXPECT_EQ(count_warnings(s, "no geometry"), 1u);
}

// --------------------------------------------------------------------------------------------
// Geometry

TEST(GltfImporter, IndicesOfEveryComponentType) {
    for (int type : {k_ubyte, k_ushort, k_uint}) {
        Scene s = load(indexed_quad(type));
        ASSERT_EQ(s.meshes.size(), 1u) << type;
        EXPECT_EQ(s.meshes[0].indices, (std::vector<uint32_t>{0, 1, 2, 0, 2, 3})) << type;
    }
}

TEST(GltfImporter, NonIndexedTrianglesUseVertexOrder) {
    GltfBuilder b = triangle_scene();
    Scene s = load(b);
    ASSERT_EQ(s.meshes.size(), 1u);
    EXPECT_EQ(s.meshes[0].indices, (std::vector<uint32_t>{0, 1, 2}));
}

TEST(GltfImporter, TriangleStripAlternatesWinding) {
    Scene s = load_mode(5, 5);
    ASSERT_EQ(s.meshes.size(), 1u);
    // glTF 2.0 3.7.2.1: triangle i is (i, i + 1 + i%2, i + 2 - i%2).
    EXPECT_EQ(s.meshes[0].indices, (std::vector<uint32_t>{0, 1, 2, 1, 3, 2, 2, 3, 4}));
}

TEST(GltfImporter, TriangleFanBecomesList) {
    Scene s = load_mode(6, 5);
    ASSERT_EQ(s.meshes.size(), 1u);
    // glTF 2.0 3.7.2.1: triangle i is (i + 1, i + 2, 0).
    EXPECT_EQ(s.meshes[0].indices, (std::vector<uint32_t>{1, 2, 0, 2, 3, 0, 3, 4, 0}));
}

TEST(GltfImporter, PointAndLinePrimitivesAreSkippedWithOneWarning) {
    GltfBuilder b;
    int pos = b.positions({0, 0, 0, 1, 0, 0, 0, 1, 0});
    json prims = json::array();
    for (int mode : {0, 1, 2, 3, 4}) prims.push_back({{"attributes", {{"POSITION", pos}}}, {"mode", mode}});
    b.push("meshes", {{"primitives", prims}});
    b.place(0);
    Scene s = load(b);
    EXPECT_EQ(s.meshes.size(), 1u);  // only the TRIANGLES primitive
    EXPECT_EQ(count_warnings(s, "point/line"), 1u);
    EXPECT_EQ(count_warnings(s, "skipped 4 point/line primitives"), 1u);
}

TEST(GltfImporter, NormalizedTexcoordsFollowTheSpec) {
    GltfBuilder b;
    int uv0 = b.accessor(std::vector<uint8_t>{0, 255, 255, 51, 128, 0}, k_ubyte, "VEC2", true);
    int uv1 = b.accessor(std::vector<int16_t>{-32768, 32767, 0, -16384, 16384, 1}, k_short, "VEC2", true);
    b.triangle_mesh("tri", {{"TEXCOORD_0", uv0}, {"TEXCOORD_1", uv1}});
    b.place(0);
    Scene s = load(b);
    const Mesh& m = s.meshes.at(0);
    ASSERT_EQ(m.uv0.size(), 3u);
    EXPECT_FLOAT_EQ(m.uv0[0].x, 0.0f);
    EXPECT_FLOAT_EQ(m.uv0[0].y, 1.0f);
    EXPECT_FLOAT_EQ(m.uv0[1].y, 0.2f);
    EXPECT_FLOAT_EQ(m.uv0[2].x, 128.0f / 255.0f);
    ASSERT_EQ(m.uv1.size(), 3u);
    EXPECT_FLOAT_EQ(m.uv1[0].x, -1.0f);  // max(-32768 / 32767, -1)
    EXPECT_FLOAT_EQ(m.uv1[0].y, 1.0f);
    EXPECT_FLOAT_EQ(m.uv1[1].y, -16384.0f / 32767.0f);
}

TEST(GltfImporter, QuantizedPositionsAndNormals) {
    GltfBuilder b;
    int pos = b.accessor(std::vector<int16_t>{0, 0, 0, 100, 0, 0, 0, -7, 0, 0, 0, 0}, k_short, "VEC3");
    b.doc["accessors"][pos]["count"] = 3;
    int nrm = b.accessor(std::vector<int8_t>{0, 0, 127, 0, 0, 127, 0, 0, -128, 0, 0, 0}, k_byte, "VEC3", true);
    b.doc["accessors"][nrm]["count"] = 3;
    b.push("meshes", {{"primitives", {{{"attributes", {{"POSITION", pos}, {"NORMAL", nrm}}}}}}});
    b.place(0);
    b.doc["extensionsUsed"] = {"KHR_mesh_quantization"};
    b.doc["extensionsRequired"] = {"KHR_mesh_quantization"};
    Scene s = load(b);
    const Mesh& m = s.meshes.at(0);
    expect_vec3(m.positions[1], 100, 0, 0);
    expect_vec3(m.positions[2], 0, -7, 0);
    expect_vec3(m.normals[0], 0, 0, 1);
    expect_vec3(m.normals[2], 0, 0, -1);
    EXPECT_TRUE(s.warnings.empty());
}

TEST(GltfImporter, InterleavedAttributesHonourByteStride) {
    GltfBuilder b;
    // x y z u v per vertex: 20-byte stride.
    std::vector<float> interleaved = {0, 0, 0, 0.1f, 0.2f, 1, 0, 0, 0.3f, 0.4f, 0, 1, 0, 0.5f, 0.6f};
    int view = b.view(interleaved.data(), interleaved.size() * 4, 20);
    int pos = b.push("accessors", {{"bufferView", view}, {"componentType", k_float}, {"count", 3}, {"type", "VEC3"}});
    int uv =
        b.push("accessors",
               {{"bufferView", view}, {"byteOffset", 12}, {"componentType", k_float}, {"count", 3}, {"type", "VEC2"}});
    b.push("meshes", {{"primitives", {{{"attributes", {{"POSITION", pos}, {"TEXCOORD_0", uv}}}}}}});
    b.place(0);
    Scene s = load(b);
    const Mesh& m = s.meshes.at(0);
    expect_vec3(m.positions[2], 0, 1, 0);
    EXPECT_FLOAT_EQ(m.uv0[1].x, 0.3f);
    EXPECT_FLOAT_EQ(m.uv0[2].y, 0.6f);
}

TEST(GltfImporter, SparseAccessorReplacesValues) {
    GltfBuilder b;
    int pos = b.positions({0, 0, 0, 1, 0, 0, 0, 1, 0});
    std::vector<uint16_t> sparse_indices = {1};
    std::vector<float> sparse_values = {5, 6, 7};
    int iv = b.view(sparse_indices.data(), 2);
    int vv = b.view(sparse_values.data(), 12);
    b.doc["accessors"][pos]["sparse"] = {
        {"count", 1}, {"indices", {{"bufferView", iv}, {"componentType", k_ushort}}}, {"values", {{"bufferView", vv}}}};
    // Sparse over zeros: no bufferView.
    std::vector<uint8_t> zi = {2};
    std::vector<float> zv = {0.5f, 0.25f};
    int ziv = b.view(zi.data(), 1);
    int zvv = b.view(zv.data(), 8);
    int uv = b.push("accessors", {{"componentType", k_float},
                                  {"count", 3},
                                  {"type", "VEC2"},
                                  {"sparse",
                                   {{"count", 1},
                                    {"indices", {{"bufferView", ziv}, {"componentType", k_ubyte}}},
                                    {"values", {{"bufferView", zvv}}}}}});
    b.push("meshes", {{"primitives", {{{"attributes", {{"POSITION", pos}, {"TEXCOORD_0", uv}}}}}}});
    b.place(0);
    Scene s = load(b);
    const Mesh& m = s.meshes.at(0);
    expect_vec3(m.positions[0], 0, 0, 0);
    expect_vec3(m.positions[1], 5, 6, 7);
    expect_vec3(m.positions[2], 0, 1, 0);
    EXPECT_FLOAT_EQ(m.uv0[0].x, 0.0f);
    EXPECT_FLOAT_EQ(m.uv0[2].x, 0.5f);
    EXPECT_FLOAT_EQ(m.uv0[2].y, 0.25f);
}

TEST(GltfImporter, MissingNormalsMeanFlatShading) {
    GltfBuilder b;
    int n = b.accessor(std::vector<float>{0, 0, 1, 0, 0, 1, 0, 0, 1}, k_float, "VEC3");
    b.triangle_mesh("flat");
    b.triangle_mesh("smooth", {{"NORMAL", n}});
    b.place(0);
    b.place(1);
    Scene s = load(b);
    ASSERT_EQ(s.meshes.size(), 2u);
    EXPECT_TRUE(s.meshes[0].normals.empty());
    ASSERT_EQ(s.meshes[1].normals.size(), 3u);
    expect_vec3(s.meshes[1].normals[1], 0, 0, 1);
}

TEST(GltfImporter, VertexColorsVec3GetOpaqueAlpha) {
    GltfBuilder b;
    int c = b.accessor(std::vector<uint8_t>{255, 0, 0, 0, 255, 0, 0, 0, 51, 0, 0, 0}, k_ubyte, "VEC3", true);
    b.doc["accessors"][c]["count"] = 3;
    b.triangle_mesh("tri", {{"COLOR_0", c}});
    b.place(0);
    Scene s = load(b);
    const Mesh& m = s.meshes.at(0);
    ASSERT_EQ(m.colors.size(), 3u);
    EXPECT_FLOAT_EQ(m.colors[0].r, 1.0f);
    EXPECT_FLOAT_EQ(m.colors[2].b, 0.2f);
    EXPECT_FLOAT_EQ(m.colors[1].a, 1.0f);
    EXPECT_TRUE(s.features.vertex_colors);
}

TEST(GltfImporter, TrianglesWithNonFiniteCornersAreDropped) {
    GltfBuilder b;
    float nan = std::numeric_limits<float>::quiet_NaN();
    int pos = b.positions({0, 0, 0, 1, 0, 0, 0, 1, 0, nan, 0, 0});
    int ind = b.accessor(std::vector<uint16_t>{0, 1, 2, 0, 3, 2}, k_ushort, "SCALAR");
    b.push("meshes", {{"primitives", {{{"attributes", {{"POSITION", pos}}}, {"indices", ind}}}}});
    b.place(0);
    Scene s = load(b);
    EXPECT_EQ(s.meshes.at(0).indices, (std::vector<uint32_t>{0, 1, 2}));
    EXPECT_EQ(count_warnings(s, "dropped 1 triangles with non-finite"), 1u);
}

// --------------------------------------------------------------------------------------------
// Cameras and lights

TEST(GltfImporter, PerspectiveAndOrthographicCameras) {
    GltfBuilder b;
    b.push("cameras",
           {{"type", "perspective"}, {"perspective", {{"yfov", 0.7}, {"aspectRatio", 1.5}, {"znear", 0.05}}}});
    b.push("cameras", {{"type", "orthographic"},
                       {"name", "ortho"},
                       {"orthographic", {{"xmag", 2}, {"ymag", 3}, {"znear", 0.5}, {"zfar", 50}}}});
    b.push("nodes", {{"name", "persp node"}, {"camera", 0}, {"translation", {0, 0, 5}}});
    b.push("nodes", {{"camera", 1}});
    b.push("nodes", {{"camera", 0}});  // not in the scene
    b.scene({0, 1});
    Scene s = load(b);
    ASSERT_EQ(s.cameras.size(), 2u);
    const Camera& p = s.cameras[0];
    EXPECT_EQ(p.name, "persp node");  // the camera has no name
    EXPECT_FALSE(p.orthographic);
    EXPECT_FLOAT_EQ(p.yfov, 0.7f);
    EXPECT_FLOAT_EQ(p.aspect_ratio, 1.5f);
    EXPECT_FLOAT_EQ(p.znear, 0.05f);
    EXPECT_EQ(p.zfar, 0.0f);  // absent: infinite
    expect_vec3(p.camera_to_world.point({0, 0, 0}), 0, 0, 5);
    const Camera& o = s.cameras[1];
    EXPECT_EQ(o.name, "ortho");
    EXPECT_TRUE(o.orthographic);
    EXPECT_FLOAT_EQ(o.xmag, 2.0f);
    EXPECT_FLOAT_EQ(o.ymag, 3.0f);
    EXPECT_FLOAT_EQ(o.znear, 0.5f);
    EXPECT_FLOAT_EQ(o.zfar, 50.0f);
}

TEST(GltfImporter, PunctualLightsAreConvertedToRadiometricUnits) {
    Scene s = load(light_scene("Khronos glTF Blender I/O v3.4.50"));
    ASSERT_EQ(s.lights.size(), 3u);
    EXPECT_TRUE(s.features.punctual_lights);
    const PunctualLight& point = s.lights[0];
    EXPECT_EQ(point.name, "bulb");
    EXPECT_EQ(point.type, LightType::Point);
    EXPECT_FLOAT_EQ(point.intensity.r, 2.0f);  // 683 x 2 cd -> 2 W/sr
    EXPECT_FLOAT_EQ(point.intensity.g, 1.0f);
    EXPECT_FLOAT_EQ(point.intensity.b, 0.5f);
    expect_vec3(point.position, 1, 2, 3);
    const PunctualLight& sun = s.lights[1];
    EXPECT_EQ(sun.type, LightType::Directional);
    EXPECT_FLOAT_EQ(sun.intensity.g, 1.0f);  // 683 lux -> 1 W/m^2
    expect_vec3(sun.direction, 0, -1, 0);
    const PunctualLight& spot = s.lights[2];
    EXPECT_EQ(spot.name, "spotty");
    EXPECT_EQ(spot.type, LightType::Spot);
    EXPECT_FLOAT_EQ(spot.cos_outer, std::cos(0.5f));
    EXPECT_FLOAT_EQ(spot.cos_inner, std::cos(0.25f));
    EXPECT_FLOAT_EQ(spot.blend, 0.5f);
    expect_vec3(spot.direction, 0, 0, -1);
}

// VEACH_lights_blender: Blender's area lights, light radius and sun angle, in Blender's quantities.
TEST(GltfImporter, BlenderLightExtensionGivesAreaLightsRadiusAndSunAngle) {
    GltfBuilder b = light_scene("Khronos glTF Blender I/O v3.4.50");
    auto& lights = b.doc["extensions"]["KHR_lights_punctual"]["lights"];
    lights[0]["extensions"]["VEACH_lights_blender"] = {{"shape", "point"}, {"radius", 0.25}, {"power", 10}};
    lights[1]["extensions"]["VEACH_lights_blender"] = {{"shape", "sun"}, {"angle", 0.2}};
    lights.push_back(
        {{"type", "point"},
         {"color", {1, 1, 1}},
         {"intensity", 1},
         {"extensions",
          {{"VEACH_lights_blender", {{"shape", "ellipse"}, {"size", {2, 0.5}}, {"power", 100}, {"spread", 1.0}}}}}});
    lights.push_back({{"type", "point"},
                      {"extensions", {{"VEACH_lights_blender", {{"shape", "square"}, {"size", {3}}, {"power", 36}}}}}});
    b.push(
        "nodes",
        {{"translation", {0, 4, 0}}, {"scale", {2, 1, 1}}, {"extensions", {{"KHR_lights_punctual", {{"light", 3}}}}}});
    b.push("nodes", {{"extensions", {{"KHR_lights_punctual", {{"light", 4}}}}}});
    b.scene({0, 1, 2, 3, 4});
    Scene s = load(b);
    ASSERT_EQ(s.lights.size(), 5u);
    EXPECT_FLOAT_EQ(s.lights[0].radius, 0.25f);
    EXPECT_FLOAT_EQ(s.lights[0].intensity.r, 2.0f);  // the KHR intensity stays
    EXPECT_FLOAT_EQ(s.lights[1].angle, 0.2f);
    const PunctualLight& ellipse = s.lights[3];
    EXPECT_EQ(ellipse.type, LightType::Area);
    EXPECT_EQ(ellipse.shape, AreaShape::Ellipse);
    expect_vec3(ellipse.axis_u, 2, 0, 0);  // half of 2 m, times the node's X scale of 2
    expect_vec3(ellipse.axis_v, 0, 0.25f, 0);
    expect_vec3(ellipse.direction, 0, 0, -1);
    // Cycles: P / (4 A), A the ellipse's world area pi x 2 x 0.25.
    EXPECT_NEAR(ellipse.radiance.g, 100.0f / (4.0f * k_pi * 2.0f * 0.25f), 1e-4f);
    const PunctualLight& square = s.lights[4];
    EXPECT_EQ(square.shape, AreaShape::Rectangle);
    expect_vec3(square.axis_v, 0, 1.5f, 0);  // a square's size is its one number
    EXPECT_NEAR(square.radiance.g, 36.0f / (4.0f * 9.0f), 1e-5f);
    EXPECT_EQ(count_warnings(s, "spread of 57 degrees is not supported"), 1u);
}

// A primitive without a material: Cycles' default surface (Lambertian 0.8) in Blender's exports,
// as Blender shows the object; the spec's default (white, metallic 1, roughness 1) otherwise.
TEST(GltfImporter, DefaultMaterialFollowsGeneratorUnlessForced) {
    auto scene = [](const std::string& generator) {
        GltfBuilder b;
        b.doc["asset"]["generator"] = generator;
        b.place(b.triangle_mesh());
        b.place(b.triangle_mesh());
        return b;
    };
    auto is_cycles_default = [](const Scene& s, const Mesh& m) {
        const Material& mat = s.material_of(m);
        return mat.base_color.r == 0.8f && mat.base_color.g == 0.8f && mat.base_color.b == 0.8f &&
               mat.metallic == 0.0f && mat.specular == 0.0f && !mat.is_emissive() && mat.transmission == 0.0f;
    };
    auto is_gltf_default = [](const Scene& s, const Mesh& m) {
        const Material& mat = s.material_of(m);
        return m.material == -1 && mat.base_color.r == 1.0f && mat.metallic == 1.0f && mat.roughness == 1.0f &&
               mat.specular == 1.0f;
    };
    Scene blender = load(scene("Khronos glTF Blender I/O v3.4.50"));
    ASSERT_EQ(blender.meshes.size(), 2u);
    EXPECT_TRUE(is_cycles_default(blender, blender.meshes[0]));
    EXPECT_EQ(blender.meshes[0].material, blender.meshes[1].material);  // one material for all of them
    EXPECT_EQ(blender.materials.size(), 1u);
    Scene other = load(scene("Some Other Tool"));
    EXPECT_TRUE(is_gltf_default(other, other.meshes[0]));
    EXPECT_TRUE(other.materials.empty());
    ImportOptions forced;
    forced.default_material = DefaultMaterial::Gltf;
    Scene b_gltf = load(scene("Khronos glTF Blender I/O"), forced);
    EXPECT_TRUE(is_gltf_default(b_gltf, b_gltf.meshes[0]));
    forced.default_material = DefaultMaterial::Blender;
    Scene o_blender = load(scene("Some Other Tool"), forced);
    EXPECT_TRUE(is_cycles_default(o_blender, o_blender.meshes[0]));
}

TEST(GltfImporter, SpotFalloffFollowsGeneratorUnlessForced) {
    EXPECT_EQ(load(light_scene("Khronos glTF Blender I/O v3.4.50")).lights.at(2).falloff, SpotFalloff::Blender);
    EXPECT_EQ(load(light_scene("Some Other Tool")).lights.at(2).falloff, SpotFalloff::Gltf);
    ImportOptions forced;
    forced.spot_profile = SpotProfile::Gltf;
    EXPECT_EQ(load(light_scene("Khronos glTF Blender I/O"), forced).lights.at(2).falloff, SpotFalloff::Gltf);
    forced.spot_profile = SpotProfile::Blender;
    EXPECT_EQ(load(light_scene("Some Other Tool"), forced).lights.at(2).falloff, SpotFalloff::Blender);
}

// --------------------------------------------------------------------------------------------
// Materials and textures

TEST(GltfImporter, EmissiveStrengthMultipliesEmissiveFactor) {
    Scene s = load(material_scene({{"emissiveFactor", {1, 0.5, 0}},
                                   {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", 10}}}}}}));
    ASSERT_EQ(s.materials.size(), 1u);
    const Rgb& e = s.materials[0].emission;
    EXPECT_FLOAT_EQ(e.r, 10.0f);
    EXPECT_FLOAT_EQ(e.g, 5.0f);
    EXPECT_FLOAT_EQ(e.b, 0.0f);
    EXPECT_TRUE(s.features.emissive_meshes);
    EXPECT_TRUE(s.textures.empty());  // no texture referenced: none decoded
}

TEST(GltfImporter, PbrFactorsAndAlpha) {
    json pbr = {{"baseColorFactor", {0.5, 0.25, 1, 0.75}}, {"metallicFactor", 0}, {"roughnessFactor", 0.3}};
    Scene s = load(material_scene({{"pbrMetallicRoughness", pbr},
                                   {"alphaMode", "MASK"},
                                   {"alphaCutoff", 0.4},
                                   {"doubleSided", true},
                                   {"extensions", {{"KHR_materials_ior", {{"ior", 1.33}}}}}}));
    const Material& m = s.materials.at(0);
    EXPECT_FLOAT_EQ(m.base_color.g, 0.25f);
    EXPECT_FLOAT_EQ(m.base_alpha, 0.75f);
    EXPECT_FLOAT_EQ(m.metallic, 0.0f);
    EXPECT_FLOAT_EQ(m.roughness, 0.3f);
    EXPECT_EQ(m.alpha_mode, AlphaMode::Mask);
    EXPECT_FLOAT_EQ(m.alpha_cutoff, 0.4f);
    EXPECT_TRUE(m.double_sided);
    EXPECT_FLOAT_EQ(m.ior, 1.33f);
    EXPECT_TRUE(s.features.alpha);
    EXPECT_FALSE(s.features.emissive_meshes);
}

TEST(GltfImporter, BaseColorTextureIsDecodedFromSrgbWithSampler) {
    Scene s = load(material_scene({{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}));
    ASSERT_EQ(s.textures.size(), 1u);
    const Texture& t = s.textures[0];
    ASSERT_EQ(t.width, 2);
    ASSERT_EQ(t.height, 2);
    // Row 0 is the image's top row: red, then green with alpha 128 (alpha stays linear).
    EXPECT_FLOAT_EQ(t.stored_value(0), 1.0f);
    EXPECT_FLOAT_EQ(t.stored_value(1), 0.0f);
    EXPECT_FLOAT_EQ(t.stored_value(5), 1.0f);
    EXPECT_FLOAT_EQ(t.stored_value(7), 128.0f / 255.0f);
    // Colour textures keep sRGB-encoded values; the lookup decodes exactly at texel centres.
    EXPECT_TRUE(t.srgb);
    EXPECT_FLOAT_EQ(t.stored_value(12), 188.0f / 255.0f);  // bottom-right grey
    EXPECT_NEAR(sample_texture(t, Vec2{0.75f, 0.75f}).r, srgb_to_linear(188.0f / 255.0f), 1e-6f);
    EXPECT_FLOAT_EQ(t.stored_value(15), 0.0f);
    EXPECT_TRUE(t.nearest);
    EXPECT_EQ(t.wrap_s, WrapMode::ClampToEdge);
    EXPECT_EQ(t.wrap_t, WrapMode::MirroredRepeat);
    EXPECT_EQ(s.materials.at(0).base_color_texture.texture, 0);
    EXPECT_TRUE(s.features.textures);
}

// The sampler's minFilter: NEAREST or LINEAR means no mip-mapping, a *_MIPMAP_* filter or none
// given leaves it to the renderer (levels when minified).
TEST(GltfImporter, MinFilterWithoutMipmapTurnsMipMappingOff) {
    json pbr = {{"baseColorTexture", {{"index", 0}}}};
    for (auto [filter, mipmaps] : {std::pair{9728, false}, std::pair{9729, false}, std::pair{9984, true},
                                   std::pair{9987, true}, std::pair{-1, true}}) {
        GltfBuilder b = material_scene({{"pbrMetallicRoughness", pbr}});
        if (filter >= 0) b.doc["samplers"][0]["minFilter"] = filter;
        Scene s = load(b);
        EXPECT_EQ(s.textures.at(s.materials.at(0).base_color_texture.texture).mipmaps, mipmaps) << filter;
    }
}

TEST(GltfImporter, DataTexturesStayLinearAndTexturesAreSharedPerColourSpace) {
    json pbr = {{"baseColorTexture", {{"index", 0}}}, {"metallicRoughnessTexture", {{"index", 0}}}};
    Scene s = load(material_scene({{"pbrMetallicRoughness", pbr},
                                   {"emissiveTexture", {{"index", 0}}},
                                   {"normalTexture", {{"index", 1}, {"scale", 0.5}}}}));
    // (texture 0, sRGB) shared by base colour and emissive; (0, linear); (1, linear).
    ASSERT_EQ(s.textures.size(), 3u);
    const Material& m = s.materials.at(0);
    EXPECT_EQ(m.base_color_texture.texture, m.emissive_texture.texture);
    ASSERT_NE(m.base_color_texture.texture, m.metallic_roughness_texture.texture);
    const Texture& linear = s.textures.at(m.metallic_roughness_texture.texture);
    EXPECT_NEAR(linear.stored_value(12), 188.0f / 255.0f, 1e-6f);
    EXPECT_FALSE(s.textures.at(m.normal_texture.texture).nearest);  // texture 1 has no sampler
    EXPECT_FLOAT_EQ(m.normal_scale, 0.5f);
    EXPECT_TRUE(s.features.normal_maps);
}

TEST(GltfImporter, UnusedMaterialsDecodeNoTextures) {
    GltfBuilder b = material_scene(json::object());
    b.push("materials", {{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}});
    b.doc["images"][0]["uri"] = "data:image/png;base64,bm90IGFuIGltYWdl";  // "not an image", never decoded
    Scene s = load(b);
    EXPECT_EQ(s.materials.size(), 1u);
    EXPECT_TRUE(s.textures.empty());
    EXPECT_FALSE(s.features.textures);
}

TEST(GltfImporter, SpecularExtension) {
    Scene s = load(material_scene({{"extensions",
                                    {{"KHR_materials_specular",
                                      {{"specularFactor", 0.3},
                                       {"specularColorFactor", {0.5, 0.6, 0.7}},
                                       {"specularTexture", {{"index", 0}}},
                                       {"specularColorTexture", {{"index", 0}, {"texCoord", 1}}}}}}}}));
    const Material& m = s.materials.at(0);
    EXPECT_FLOAT_EQ(m.specular, 0.3f);
    EXPECT_FLOAT_EQ(m.specular_color.r, 0.5f);
    EXPECT_FLOAT_EQ(m.specular_color.b, 0.7f);
    ASSERT_TRUE(m.specular_texture.valid());
    ASSERT_TRUE(m.specular_color_texture.valid());
    EXPECT_EQ(m.specular_color_texture.texcoord, 1);
    // specularTexture is data (linear), specularColorTexture colour (sRGB).
    EXPECT_NEAR(s.textures.at(m.specular_texture.texture).stored_value(12), 188.0f / 255.0f, 1e-6f);
    EXPECT_TRUE(s.textures.at(m.specular_color_texture.texture).srgb);
    EXPECT_FALSE(s.textures.at(m.specular_texture.texture).srgb);
}

// KHR_materials_transmission, _volume, _clearcoat and _sheen as their specs name the fields;
// sheen colour is sRGB, clearcoat and roughness textures data.
TEST(GltfImporter, LayerAndTransmissionExtensions) {
    Scene s = load(material_scene(
        {{"extensions",
          {{"KHR_materials_transmission", {{"transmissionFactor", 0.8}}},
           {"KHR_materials_volume",
            {{"thicknessFactor", 0.1}, {"attenuationDistance", 2.0}, {"attenuationColor", {0.5, 0.25, 1.0}}}},
           {"KHR_materials_clearcoat",
            {{"clearcoatFactor", 0.6},
             {"clearcoatRoughnessFactor", 0.2},
             {"clearcoatNormalTexture", {{"index", 0}, {"scale", 0.5}}}}},
           {"KHR_materials_sheen",
            {{"sheenColorFactor", {0.9, 0.8, 0.7}},
             {"sheenRoughnessFactor", 0.4},
             {"sheenColorTexture", {{"index", 0}}}}}}}}));
    const Material& m = s.materials.at(0);
    EXPECT_FLOAT_EQ(m.transmission, 0.8f);
    EXPECT_FLOAT_EQ(m.clearcoat, 0.6f);
    EXPECT_FLOAT_EQ(m.clearcoat_roughness, 0.2f);
    ASSERT_TRUE(m.clearcoat_normal_texture.valid());
    EXPECT_FLOAT_EQ(m.clearcoat_normal_scale, 0.5f);
    EXPECT_FLOAT_EQ(m.sheen_color.g, 0.8f);
    EXPECT_FLOAT_EQ(m.sheen_roughness, 0.4f);
    EXPECT_TRUE(s.textures.at(m.sheen_color_texture.texture).srgb);
    // Beer-Lambert: white light crossing attenuationDistance comes out as attenuationColor.
    Rgb sigma = m.absorption();
    EXPECT_NEAR(std::exp(-sigma.r * 2.0f), 0.5f, 1e-6f);
    EXPECT_NEAR(std::exp(-sigma.g * 2.0f), 0.25f, 1e-6f);
    EXPECT_EQ(sigma.b, 0.0f);
    EXPECT_TRUE(s.features.transmission && s.features.volume && s.features.clearcoat && s.features.sheen);
}

// KHR_materials_unlit: the base colour is shown as is, i.e. emitted, and nothing is scattered.
TEST(GltfImporter, UnlitBecomesEmissionOfBaseColour) {
    Scene s = load(material_scene({{"pbrMetallicRoughness", {{"baseColorFactor", {0.2, 0.4, 0.6, 1.0}}}},
                                   {"extensions", {{"KHR_materials_unlit", json::object()}}}}));
    const Material& m = s.materials.at(0);
    EXPECT_TRUE(m.unlit);
    EXPECT_FLOAT_EQ(m.emission.g, 0.4f);
    EXPECT_TRUE(m.base_color.is_black());
    EXPECT_EQ(m.metallic, 0.0f);
    EXPECT_EQ(m.specular, 0.0f);
}

TEST(GltfImporter, TextureTransformExtension) {
    json transform = {{"offset", {0.5, 0.25}}, {"rotation", 0.3}, {"scale", {2, 3}}, {"texCoord", 1}};
    Scene s = load(material_scene(
        {{"pbrMetallicRoughness",
          {{"baseColorTexture", {{"index", 0}, {"extensions", {{"KHR_texture_transform", transform}}}}}}}}));
    const TextureRef& ref = s.materials.at(0).base_color_texture;
    ASSERT_TRUE(ref.valid());
    EXPECT_EQ(ref.texcoord, 1);
    EXPECT_FLOAT_EQ(ref.transform.offset[0], 0.5f);
    EXPECT_FLOAT_EQ(ref.transform.offset[1], 0.25f);
    EXPECT_FLOAT_EQ(ref.transform.rotation, 0.3f);
    EXPECT_FLOAT_EQ(ref.transform.scale[0], 2.0f);
    EXPECT_FLOAT_EQ(ref.transform.scale[1], 3.0f);
}

TEST(GltfImporter, SixteenBitPngIsNormalizedBy65535) {
    GltfBuilder b = material_scene({{"pbrMetallicRoughness", {{"metallicRoughnessTexture", {{"index", 0}}}}}});
    b.doc["images"][0]["uri"] = std::string("data:image/png;base64,") + k_png_16bit_grey;
    Scene s = load(b);
    ASSERT_EQ(s.textures.size(), 1u);
    EXPECT_FLOAT_EQ(s.textures[0].stored_value(0), 32768.0f / 65535.0f);  // grey 0x8000
    EXPECT_FLOAT_EQ(s.textures[0].stored_value(3), 1.0f);
}

// --------------------------------------------------------------------------------------------
// Containers and extensions

TEST(GltfImporter, GlbRoundTripMatchesGltf) {
    GltfBuilder b = material_scene({{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}});
    // Move the image into the binary chunk, as exporters do for .glb.
    std::vector<uint8_t> png_bytes = unbase64(k_png_2x2);
    int view = b.view(png_bytes.data(), png_bytes.size());
    b.doc["images"][0] = {{"bufferView", view}, {"mimeType", "image/png"}};
    TempDir dir;
    fs::path glb = dir.write("scene.glb", b.glb());
    Scene from_glb = import_scene(glb.string());
    Scene from_gltf = load(material_scene({{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}));
    ASSERT_EQ(from_glb.meshes.size(), 1u);
    EXPECT_EQ(from_glb.meshes[0].indices, from_gltf.meshes[0].indices);
    expect_vec3(from_glb.meshes[0].positions[1], 1, 0, 0);
    ASSERT_EQ(from_glb.textures.size(), 1u);
    EXPECT_EQ(from_glb.textures[0].texels8, from_gltf.textures[0].texels8);
    EXPECT_FALSE(from_gltf.textures[0].texels8.empty());

    Scene from_memory = import_scene_from_memory(b.glb(), "glb", dir.path().string());
    EXPECT_EQ(from_memory.meshes.size(), 1u);
    EXPECT_EQ(from_memory.textures.size(), 1u);
}

TEST(GltfImporter, SeparateBinFileInTheSameFolder) {
    GltfBuilder b = triangle_scene();
    TempDir dir;
    dir.write("sub/data.bin", b.bin);
    fs::path path = dir.write("sub/scene.gltf", b.with_buffer("data.bin").dump());
    Scene s = import_scene(path.string());
    EXPECT_EQ(s.meshes.size(), 1u);
}

TEST(GltfImporter, UnknownOptionalExtensionWarnsOnce) {
    GltfBuilder b = triangle_scene();
    b.doc["extensionsUsed"] = {"EXT_made_up", "EXT_made_up", "KHR_materials_transmission", "KHR_materials_ior"};
    Scene s = load(b);
    EXPECT_EQ(count_warnings(s, "EXT_made_up"), 1u);
    EXPECT_EQ(s.warnings.size(), 1u);  // known and planned extensions are silent
}

// --------------------------------------------------------------------------------------------
// Malformed input: ImportError, one line, naming the file

TEST(GltfImporterErrors, MissingFile) {
    std::string msg = expect_import_error(fs::path(data_dir()) / "does_not_exist.gltf");
    EXPECT_NE(msg.find("not found"), std::string::npos) << msg;
}

TEST(GltfImporterErrors, BadJson) { expect_import_error(fs::path(data_dir()) / "bad_json.gltf"); }

TEST(GltfImporterErrors, TruncatedGlb) {
    GltfBuilder b;
    b.triangle_mesh();
    std::vector<uint8_t> glb = b.glb();
    glb.resize(glb.size() - 20);
    TempDir dir;
    expect_import_error(dir.write("cut.glb", glb));
}

// A .glb whose BIN chunk declares more bytes than the file has: refused by name before tinygltf
// (2.7 copies the chunk by its declared length, reading past the file), whether the header's own
// length says so too (a file cut short) or was left consistent.
TEST(GltfImporterErrors, GlbChunkLongerThanTheFile) {
    GltfBuilder b = triangle_scene();
    const std::vector<uint8_t> whole = b.glb();
    TempDir dir;
    std::vector<uint8_t> cut(whole.begin(), whole.end() - 5);
    std::string msg = expect_import_error(dir.write("cut.glb", cut));
    EXPECT_NE(msg.find("truncated .glb"), std::string::npos) << msg;
    std::vector<uint8_t> consistent = cut;
    const uint32_t length = uint32_t(consistent.size());
    std::memcpy(consistent.data() + 8, &length, 4);
    msg = expect_import_error(dir.write("consistent.glb", consistent));
    EXPECT_NE(msg.find("truncated .glb: chunk 1 declares"), std::string::npos) << msg;
    // Bytes past the declared length are not the file's: ignored, as the format says.
    std::vector<uint8_t> trailing = whole;
    trailing.insert(trailing.end(), {1, 2, 3});
    EXPECT_EQ(import_scene(dir.write("trailing.glb", trailing).string()).meshes.size(), 1u);
}

TEST(GltfImporterErrors, AccessorPastBufferEnd) {
    GltfBuilder b = triangle_scene();
    b.doc["accessors"][0]["byteOffset"] = 4;
    std::string msg = expect_import_error(b);
    EXPECT_NE(msg.find("accessor 0"), std::string::npos) << msg;
}

TEST(GltfImporterErrors, BufferViewOutsideBuffer) {
    GltfBuilder b = triangle_scene();
    b.doc["bufferViews"][0]["byteOffset"] = 1000;
    expect_import_error(b);
}

TEST(GltfImporterErrors, IndexOutOfRangeNamesMeshAndAccessor) {
    GltfBuilder b;
    int pos = b.positions({0, 0, 0, 1, 0, 0, 0, 1, 0});
    int ind = b.accessor(std::vector<uint16_t>{0, 1, 3}, k_ushort, "SCALAR");
    b.push("meshes", {{"name", "broken"}, {"primitives", {{{"attributes", {{"POSITION", pos}}}, {"indices", ind}}}}});
    b.place(0);
    std::string msg = expect_import_error(b);
    EXPECT_NE(msg.find("broken"), std::string::npos) << msg;
    EXPECT_NE(msg.find("accessor " + std::to_string(ind)), std::string::npos) << msg;
}

TEST(GltfImporterErrors, HugeCountInATinyFile) {
    expect_import_error(fs::path(data_dir()) / "huge_count.gltf");
    // No bufferView: the elements would be zeros, but a billion of them is not what 1 KB means.
    GltfBuilder b = triangle_scene();
    b.doc["accessors"][0].erase("bufferView");
    b.doc["accessors"][0]["count"] = 1000000000;
    std::string msg = expect_import_error(b);
    EXPECT_NE(msg.find("MiB"), std::string::npos) << msg;
}

TEST(GltfImporterErrors, SparseIndexOutOfRange) {
    GltfBuilder b;
    int pos = b.positions({0, 0, 0, 1, 0, 0, 0, 1, 0});
    std::vector<uint16_t> si = {3};
    std::vector<float> sv = {5, 6, 7};
    int iv = b.view(si.data(), 2), vv = b.view(sv.data(), 12);
    b.doc["accessors"][pos]["sparse"] = {
        {"count", 1}, {"indices", {{"bufferView", iv}, {"componentType", k_ushort}}}, {"values", {{"bufferView", vv}}}};
    b.push("meshes", {{"primitives", {{{"attributes", {{"POSITION", pos}}}}}}});
    b.place(0);
    expect_import_error(b);
}

TEST(GltfImporterErrors, WrongAccessorType) {
    GltfBuilder b;
    int pos = b.accessor(std::vector<float>{0, 0, 1, 0, 0, 1}, k_float, "VEC2");
    b.push("meshes", {{"primitives", {{{"attributes", {{"POSITION", pos}}}}}}});
    b.place(0);
    std::string msg = expect_import_error(b);
    EXPECT_NE(msg.find("VEC2"), std::string::npos) << msg;
}

TEST(GltfImporterErrors, RecursiveNodes) {
    std::string msg = expect_import_error(fs::path(data_dir()) / "recursive_nodes.gltf");
    EXPECT_NE(msg.find("node 1 is its own ancestor"), std::string::npos) << msg;
}

TEST(GltfImporterErrors, NonFiniteTransform) {
    GltfBuilder b;
    b.place(b.triangle_mesh(), {{"scale", {1e39, 1, 1}}});  // overflows float
    expect_import_error(b);
}

TEST(GltfImporterErrors, UnknownRequiredExtension) {
    std::string msg = expect_import_error(fs::path(data_dir()) / "unknown_required_extension.gltf");
    EXPECT_NE(msg.find("requires unsupported extension VENDOR_unknown_extension"), std::string::npos) << msg;
}

// One list decides what a file may require: every extension the importer reads is accepted in
// extensionsRequired (today's implemented-but-unlisted ones were refused), and README's table
// marks exactly those "yes".
TEST(GltfImporter, EverySupportedExtensionMayBeRequired) {
    for (std::string_view name : gltf::supported_extensions()) {
        GltfBuilder b = triangle_scene();
        b.doc["extensionsUsed"] = {std::string(name)};
        b.doc["extensionsRequired"] = {std::string(name)};
        EXPECT_EQ(load(b).meshes.size(), 1u) << name;
    }
    EXPECT_TRUE(gltf::is_supported_extension("KHR_materials_transmission"));
    EXPECT_FALSE(gltf::is_supported_extension("VENDOR_unknown_extension"));
}

TEST(GltfImporter, ReadmeExtensionTableIsTheSupportedList) {
    std::ifstream readme(VEACH_SOURCE_DIR "/README.md");
    ASSERT_TRUE(readme.good());
    std::set<std::string> yes, listed;
    std::string line;
    while (std::getline(readme, line)) {
        // Rows of the extension table: "  | KHR_x | yes | note |" (README indents it in a list).
        // Veach's own (VEACH_) are listed there too.
        size_t start = line.find("| KHR_"), ext = line.find("| EXT_"), own = line.find("| VEACH_");
        if (start == std::string::npos) start = ext;
        if (start == std::string::npos) start = own;
        if (start == std::string::npos || line.find_first_not_of(' ') != start) continue;
        size_t name_end = line.find('|', start + 1);
        size_t support_end = line.find('|', name_end + 1);
        ASSERT_NE(support_end, std::string::npos) << line;
        auto trim = [](std::string t) {
            t.erase(0, t.find_first_not_of(' '));
            t.erase(t.find_last_not_of(' ') + 1);
            return t;
        };
        std::string name = trim(line.substr(start + 1, name_end - start - 1));
        std::string support = trim(line.substr(name_end + 1, support_end - name_end - 1));
        EXPECT_TRUE(support == "yes" || support == "no") << line;
        listed.insert(name);
        if (support == "yes") yes.insert(name);
    }
    std::set<std::string> supported(gltf::supported_extensions().begin(), gltf::supported_extensions().end());
    EXPECT_EQ(yes, supported);
    EXPECT_GE(listed.size(), 20u) << "README lists the ratified extensions, supported or not";
}

TEST(GltfImporterErrors, MissingBin) { expect_import_error(fs::path(data_dir()) / "missing_bin.gltf"); }

TEST(GltfImporterErrors, UriEscapingTheFolderIsRefusedUnlessAllowed) {
    GltfBuilder b = triangle_scene();
    TempDir dir;
    dir.write("x.bin", b.bin);
    fs::path path = dir.write("scenes/escaping.gltf", b.with_buffer("../x.bin").dump());
    std::string msg = expect_import_error(path);
    EXPECT_NE(msg.find("../x.bin"), std::string::npos) << msg;
    ImportOptions allow;
    allow.allow_external_files = true;
    EXPECT_EQ(import_scene(path.string(), allow).meshes.size(), 1u);

    fs::path absolute = dir.write("scenes/absolute.gltf", b.with_buffer((dir.path() / "x.bin").string()).dump());
    expect_import_error(absolute);
    EXPECT_EQ(import_scene(absolute.string(), allow).meshes.size(), 1u);
}

TEST(GltfImporterErrors, BadSceneIndex) {
    for (int index : {1, 7, -2}) {
        ImportOptions options;
        options.scene_index = index;
        std::string msg = expect_import_error(fs::path(data_dir()) / "triangle.gltf", options);
        EXPECT_NE(msg.find("scene"), std::string::npos) << msg;
    }
}

TEST(GltfImporterErrors, UndecodableUsedTexture) {
    GltfBuilder b = material_scene({{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}});
    b.doc["images"][0]["uri"] = "data:image/png;base64,bm90IGFuIGltYWdl";
    std::string msg = expect_import_error(b);
    EXPECT_NE(msg.find("image 0"), std::string::npos) << msg;
}

TEST(GltfImporterErrors, BadReferences) {
    GltfBuilder material = material_scene(json::object());
    material.doc["meshes"][0]["primitives"][0]["material"] = 9;
    expect_import_error(material);
    GltfBuilder texture = material_scene({{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 9}}}}}});
    expect_import_error(texture);
    GltfBuilder node;
    node.triangle_mesh();
    node.push("nodes", {{"mesh", 3}});
    node.scene({0, 4});
    expect_import_error(node);
    GltfBuilder light = light_scene("x");
    light.doc["nodes"][0]["extensions"]["KHR_lights_punctual"]["light"] = 5;
    expect_import_error(light);
}

// --------------------------------------------------------------------------------------------
// Blender's exports of the reference scenes

std::string public_scene(const std::string& name) {
    return std::string(VEACH_SCENES_DIR) + "/" + name + "/" + name + ".gltf";
}

TEST(GltfImporterBlender, Cornell) {
    Scene s = import_scene(public_scene("cornell"));
    EXPECT_EQ(s.instances.size(), 8u);
    EXPECT_EQ(s.meshes.size(), 8u);
    ASSERT_EQ(s.cameras.size(), 1u);
    EXPECT_NEAR(s.cameras[0].yfov, 1.024779f, 1e-5f);
    EXPECT_FLOAT_EQ(s.cameras[0].aspect_ratio, 1.0f);
    expect_vec3(s.cameras[0].camera_to_world.point({0, 0, 0}), 0, 1, 3.3f);
    EXPECT_TRUE(s.features.emissive_meshes);
    EXPECT_FALSE(s.features.textures);
    EXPECT_TRUE(s.lights.empty());
    EXPECT_TRUE(s.warnings.empty());
    bool found_light = false;
    for (const Material& m : s.materials) {
        if (m.name != "light") continue;
        found_light = true;
        EXPECT_NEAR(m.emission.r, 15.0f, 1e-4f);
        EXPECT_NEAR(m.emission.g, 12.75f, 1e-4f);
        EXPECT_NEAR(m.ior, 1.45f, 1e-6f);
        EXPECT_FLOAT_EQ(m.specular_color.r, 0.0f);
    }
    EXPECT_TRUE(found_light);
}

TEST(GltfImporterBlender, LightsMatchBlenderWatts) {
    Scene s = import_scene(public_scene("lights"));
    ASSERT_EQ(s.lights.size(), 3u);
    const float four_pi = 4 * k_pi;
    const PunctualLight& point = s.lights[0];
    EXPECT_EQ(point.type, LightType::Point);
    // 150 W Blender point light, colour (0.7, 1, 0.7): intensity x 4 pi = 150 x colour.
    EXPECT_NEAR(point.intensity.r * four_pi / (150 * 0.7f), 1.0f, 1e-3f);
    EXPECT_NEAR(point.intensity.g * four_pi / 150, 1.0f, 1e-3f);
    expect_vec3(point.position, 1, 1.8f, 0.5f);
    const PunctualLight& spot = s.lights[1];
    EXPECT_EQ(spot.type, LightType::Spot);
    EXPECT_NEAR(spot.intensity.r * four_pi / 800, 1.0f, 1e-3f);
    EXPECT_EQ(spot.falloff, SpotFalloff::Blender);
    EXPECT_NEAR(spot.blend, 0.1f, 1e-4f);
    EXPECT_NEAR(spot.cos_outer, std::cos(0.30543262f), 1e-6f);
    const PunctualLight& sun = s.lights[2];
    EXPECT_EQ(sun.type, LightType::Directional);
    EXPECT_NEAR(sun.intensity.b, 1.0f, 1e-6f);  // 1 W/m^2, colour (0.9, 0.9, 1)
    EXPECT_NEAR(sun.intensity.r, 0.9f, 1e-6f);
    EXPECT_NEAR(length(sun.direction), 1.0f, 1e-5f);
    EXPECT_LT(sun.direction.y, 0.0f);  // shines downwards
    EXPECT_TRUE(s.features.punctual_lights);
    EXPECT_EQ(s.instances.size(), 4u);
    EXPECT_EQ(s.cameras.size(), 1u);
}

TEST(GltfImporterBlender, TexturedCheckerKeepsImageRowOrder) {
    Scene s = import_scene(public_scene("textured"));
    EXPECT_TRUE(s.features.textures);
    ASSERT_EQ(s.textures.size(), 1u);
    const Texture& t = s.textures[0];
    ASSERT_EQ(t.width, 64);
    ASSERT_EQ(t.height, 64);
    // checker.png has a red marker in its bottom-left 8x8 block, i.e. the last rows, which is
    // glTF uv (0, 1) (Blender's uv (0, 0)); its top-left texel is yellow.
    auto texel = [&](int x, int y, int c) { return t.stored_value((size_t(y) * t.width + x) * 4 + c); };
    EXPECT_TRUE(t.srgb);
    EXPECT_NEAR(texel(0, 63, 0), 230 / 255.0f, 1e-6f);
    EXPECT_NEAR(texel(0, 63, 1), 26 / 255.0f, 1e-6f);
    EXPECT_NEAR(texel(0, 63, 2), 26 / 255.0f, 1e-6f);
    EXPECT_NEAR(texel(0, 0, 1), 191 / 255.0f, 1e-6f);
    // The lookup at the centre of the marker's corner texel decodes sRGB exactly.
    Rgba red = sample_texture(t, Vec2{0.5f / 64, 63.5f / 64});
    EXPECT_NEAR(red.r, srgb_to_linear(230 / 255.0f), 1e-6f);
    EXPECT_NEAR(red.g, srgb_to_linear(26 / 255.0f), 1e-6f);
    // The floor's front-left corner (-1, 0, 1) has uv (0, 1): the red marker.
    const Mesh* floor = nullptr;
    for (const Mesh& m : s.meshes)
        if (m.name == "floor") floor = &m;
    ASSERT_NE(floor, nullptr);
    int corners = 0;
    for (size_t i = 0; i < floor->positions.size(); ++i) {
        if (floor->positions[i].x > -0.5f || floor->positions[i].z < 0.5f) continue;
        ++corners;
        EXPECT_FLOAT_EQ(floor->uv0[i].x, 0.0f);
        EXPECT_FLOAT_EQ(floor->uv0[i].y, 1.0f);
    }
    EXPECT_GT(corners, 0);
}

TEST(GltfImporterBlender, ConcurrentImportsAgree) {
    // No global state: imports on several threads give the same scene as one on its own.
    Scene alone = import_scene(public_scene("textured"));
    std::vector<Scene> results(4);
    std::vector<std::thread> threads;
    for (Scene& r : results) threads.emplace_back([&r] { r = import_scene(public_scene("textured")); });
    for (std::thread& t : threads) t.join();
    for (const Scene& r : results) {
        ASSERT_EQ(r.textures.size(), 1u);
        EXPECT_EQ(r.textures[0].texels8, alone.textures[0].texels8);
        EXPECT_EQ(r.triangle_count(), alone.triangle_count());
    }
}

TEST(GltfImporterBlender, SpheresAndCorridorLoad) {
    Scene spheres = import_scene(public_scene("spheres"));
    EXPECT_EQ(spheres.instances.size(), 5u);
    EXPECT_EQ(spheres.cameras.size(), 1u);
    EXPECT_TRUE(spheres.features.emissive_meshes);
    EXPECT_GT(spheres.triangle_count(), 1000u);
    EXPECT_TRUE(spheres.warnings.empty());
    Scene corridor = import_scene(public_scene("corridor"));
    EXPECT_EQ(corridor.instances.size(), 12u);
    EXPECT_EQ(corridor.cameras.size(), 1u);
    EXPECT_TRUE(corridor.features.emissive_meshes);
}

}  // namespace
}  // namespace veach
