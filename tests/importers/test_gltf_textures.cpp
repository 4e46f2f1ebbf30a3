// Texture formats beyond stb (through OpenImageIO), tangent frames for normal maps, and
// KHR_materials_variants.
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <cstdio>
#include <fstream>
#include <iterator>

#include "gltf_test_builder.h"
#include "importers/importer.h"

namespace veach {
namespace {

using namespace gltf_test;

// A 2x1 float EXR, as another tool might embed it; stb cannot read it, OpenImageIO can. Its
// values are linear, so a base colour texture from it is stored linear (srgb = false).
TEST(GltfTextures, ExrTextureIsReadThroughOpenImageIOAsLinear) {
    std::string path = ::testing::TempDir() + "veach_texture_test.exr";
    {
        auto out = OIIO::ImageOutput::create(path);
        ASSERT_TRUE(out);
        OIIO::ImageSpec spec(2, 1, 4, OIIO::TypeDesc::FLOAT);
        ASSERT_TRUE(out->open(path, spec));
        const float pixels[8] = {0.25f, 2.0f, 0.0f, 1.0f, 0.5f, 0.5f, 0.5f, 0.5f};
        ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, pixels));
        out->close();
    }
    std::ifstream f(path, std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
    std::remove(path.c_str());
    GltfBuilder b = material_scene({{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 1}}}}}});
    // In a bufferView, as a .glb holds it (tinygltf keeps data: URIs only for PNG and JPEG).
    int view = b.view(bytes.data(), bytes.size());
    b.doc["images"][0] = {{"bufferView", view}, {"mimeType", "image/x-exr"}};
    Scene s = load(b);
    ASSERT_EQ(s.textures.size(), 1u);
    const Texture& t = s.textures[0];
    ASSERT_EQ(t.width, 2);
    ASSERT_EQ(t.height, 1);
    EXPECT_FALSE(t.srgb);
    EXPECT_FLOAT_EQ(t.texels[0], 0.25f);
    EXPECT_FLOAT_EQ(t.texels[1], 2.0f);  // HDR values survive
    EXPECT_FLOAT_EQ(t.texels[7], 0.5f);  // alpha
}

// Tangents exist only for normal-mapped materials: the file's TANGENT (with its handedness w),
// else generated from the normal texture's UVs.
TEST(GltfTextures, TangentsComeFromTheFileOrAreGeneratedForNormalMapsOnly) {
    Scene plain = load(material_scene({{"pbrMetallicRoughness", json::object()}}));
    EXPECT_TRUE(plain.meshes.at(0).tangents.empty());

    Scene generated = load(material_scene({{"normalTexture", {{"index", 1}}}}));
    const Mesh& g = generated.meshes.at(0);
    ASSERT_EQ(g.tangents.size(), g.positions.size());
    ASSERT_EQ(g.tangent_signs.size(), g.positions.size());
    EXPECT_TRUE(generated.features.normal_maps);

    // A clearcoat normal map needs the tangent frame too (surface_hit.cpp applies it to the coat).
    Scene coat = load(material_scene(
        {{"extensions",
          {{"KHR_materials_clearcoat", {{"clearcoatFactor", 1.0}, {"clearcoatNormalTexture", {{"index", 1}}}}}}}}));
    EXPECT_EQ(coat.meshes.at(0).tangents.size(), coat.meshes.at(0).positions.size());
    EXPECT_TRUE(coat.features.normal_maps);

    GltfBuilder b = material_scene({{"normalTexture", {{"index", 1}}}});
    int tangent = b.accessor(std::vector<float>{0, 1, 0, -1, 0, 1, 0, -1, 0, 1, 0, -1}, k_float, "VEC4");
    b.doc["meshes"][0]["primitives"][0]["attributes"]["TANGENT"] = tangent;
    Scene from_file = load(b);
    const Mesh& m = from_file.meshes.at(0);
    ASSERT_EQ(m.tangents.size(), 3u);
    EXPECT_FLOAT_EQ(m.tangents[1].y, 1.0f);
    EXPECT_EQ(m.tangent_signs[2], -1.0f);
}

}  // namespace
}  // namespace veach

namespace veach {
namespace {

using namespace gltf_test;

// KHR_materials_variants: --variant picks the material a primitive maps to that variant; other
// primitives and the default keep their material; an unknown name is bad input naming the known.
TEST(GltfVariants, VariantReplacesMappedMaterialsAndUnknownNamesAreRefused) {
    GltfBuilder b = material_scene({{"pbrMetallicRoughness", {{"baseColorFactor", {1, 0, 0, 1}}}}});
    b.push("materials", {{"pbrMetallicRoughness", {{"baseColorFactor", {0, 0, 1, 1}}}}});
    b.doc["extensionsUsed"] = {"KHR_materials_variants"};
    b.doc["extensions"]["KHR_materials_variants"] = {{"variants", {{{"name", "red"}}, {{"name", "blue"}}}}};
    b.doc["meshes"][0]["primitives"][0]["extensions"]["KHR_materials_variants"] = {
        {"mappings", {{{"material", 1}, {"variants", {1}}}, {{"material", 0}, {"variants", {0}}}}}};
    auto base_colour = [](const Scene& s) { return s.material_of(s.meshes.at(0)).base_color; };
    EXPECT_EQ(base_colour(load(b)).r, 1.0f);
    ImportOptions blue;
    blue.variant = "blue";
    EXPECT_EQ(base_colour(load(b, blue)).b, 1.0f);
    EXPECT_EQ(base_colour(load(b, blue)).r, 0.0f);
    ImportOptions missing;
    missing.variant = "green";
    try {
        load(b, missing);
        FAIL() << "an unknown variant must be refused";
    } catch (const ImportError& e) {
        EXPECT_NE(std::string(e.what()).find("'green'"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("'blue'"), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace veach
