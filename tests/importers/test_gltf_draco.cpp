// KHR_draco_mesh_compression: a Draco-compressed primitive imports as its uncompressed twin does
// (same triangles, positions within the quantization the stream was written with, the same image
// within noise), the extension's attribute ids pick the attributes, the accessors' componentType
// and normalized flag decide how integer values are read, and corrupt streams are clean errors.
// Streams come from two tools other than Veach (Debian's draco_transcoder, made by
// tests/data/gltf/make_draco_twins.py, and COLLADA2GLTF in assimp-testmodels) and from Draco's
// encoder called here, for exact control of attribute types.
#include <gtest/gtest.h>

#include <draco/compression/encode.h>
#include <draco/mesh/triangle_soup_mesh_builder.h>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cmath>
#include <cstring>
#include <fstream>
#include <random>

#include "../render/render_helpers.h"
#include "gltf_test_builder.h"
#include "importers/importer.h"
#include "scene/scene_repair.h"

namespace veach {
namespace {

using namespace gltf_test;

// The bits make_draco_twins.py passes to draco_transcoder (-qp -qn -qt -qc).
constexpr int k_qp = 14, k_qn = 12, k_qt = 12, k_qc = 10;

// Draco quantizes a float attribute on a uniform grid of 2^bits - 1 steps over the largest
// extent of its components, rounding to the nearest: the error is at most half a step.
float half_step(float range, int bits) { return 0.5f * range / float((1 << bits) - 1) * 1.0001f + 1e-7f; }

struct Corner {
    Vec3 p, n;
    Vec2 uv;
    Rgba c;
};

Corner corner(const Mesh& m, uint32_t i) {
    return {m.positions[i], m.normals.empty() ? Vec3() : m.normals[i], m.uv0.empty() ? Vec2{} : m.uv0[i],
            m.colors.empty() ? Rgba{} : m.colors[i]};
}

struct Tolerance {
    float p, n, uv, c;
};

bool close(const Corner& a, const Corner& b, const Tolerance& t) {
    auto near3 = [](Vec3 x, Vec3 y, float e) {
        return std::fabs(x.x - y.x) <= e && std::fabs(x.y - y.y) <= e && std::fabs(x.z - y.z) <= e;
    };
    return near3(a.p, b.p, t.p) && near3(a.n, b.n, t.n) && std::fabs(a.uv.x - b.uv.x) <= t.uv &&
           std::fabs(a.uv.y - b.uv.y) <= t.uv && std::fabs(a.c.r - b.c.r) <= t.c && std::fabs(a.c.g - b.c.g) <= t.c &&
           std::fabs(a.c.b - b.c.b) <= t.c;
}

// How many triangles of `got` match no distinct triangle of `want` corner by corner (any
// rotation, the same winding) within `t`; Draco reorders vertices and faces, never the shapes.
size_t unmatched_triangles(const Mesh& got, const Mesh& want, const Tolerance& t) {
    size_t n = std::min(got.indices.size(), want.indices.size()) / 3;
    std::vector<uint8_t> used(n, 0);
    size_t unmatched = 0;
    for (size_t g = 0; g < n; ++g) {
        Corner a[3] = {corner(got, got.indices[3 * g]), corner(got, got.indices[3 * g + 1]),
                       corner(got, got.indices[3 * g + 2])};
        bool found = false;
        for (size_t w = 0; w < n && !found; ++w) {
            if (used[w]) continue;
            for (int r = 0; r < 3 && !found; ++r) {
                bool all = true;
                for (int k = 0; k < 3 && all; ++k)
                    all = close(a[k], corner(want, want.indices[3 * w + (k + r) % 3]), t);
                if (all) {
                    found = true;
                    used[w] = 1;
                }
            }
        }
        unmatched += !found;
    }
    return unmatched;
}

Scene twin(bool draco) { return import_scene(data_dir() + (draco ? "draco_twin_draco.glb" : "draco_twin.glb")); }

TEST(GltfDraco, TranscodedTwinHasTheSameTrianglesWithinTheDeclaredQuantization) {
    Scene plain = twin(false), packed = twin(true);
    ASSERT_EQ(plain.meshes.size(), 1u);
    ASSERT_EQ(packed.meshes.size(), 1u);
    const Mesh& want = plain.meshes[0];
    const Mesh& got = packed.meshes[0];
    EXPECT_EQ(got.indices.size(), 864u);  // 288 triangles
    ASSERT_EQ(got.normals.size(), got.positions.size());
    ASSERT_EQ(got.uv0.size(), got.positions.size());
    ASSERT_EQ(got.colors.size(), got.positions.size());
    // Ranges: the largest per-axis extent of each attribute in the uncompressed twin.
    auto extent = [&](auto get, int dims) {
        float lo[4] = {1e30f, 1e30f, 1e30f, 1e30f}, hi[4] = {-1e30f, -1e30f, -1e30f, -1e30f}, r = 0;
        for (size_t i = 0; i < want.positions.size(); ++i)
            for (int d = 0; d < dims; ++d) lo[d] = std::min(lo[d], get(i, d)), hi[d] = std::max(hi[d], get(i, d));
        for (int d = 0; d < dims; ++d) r = std::max(r, hi[d] - lo[d]);
        return r;
    };
    float rp = extent([&](size_t i, int d) { return want.positions[i][d]; }, 3);
    float rt = extent([&](size_t i, int d) { return d == 0 ? want.uv0[i].x : want.uv0[i].y; }, 2);
    float rc = extent(
        [&](size_t i, int d) { return d == 0   ? want.colors[i].r
                                      : d == 1 ? want.colors[i].g
                                               : want.colors[i].b; }, 3);
    // Normals are octahedral: qn bits per coordinate on [-1, 1]^2, which the unfolding stretches
    // by at most a factor two in any component.
    Tolerance t{half_step(rp, k_qp), 2 * 2 * half_step(2, k_qn), half_step(rt, k_qt), half_step(rc, k_qc)};
    EXPECT_EQ(unmatched_triangles(got, want, t), 0u) << "of 288";
    // And the bounds mean something: moved by two quantization steps, no triangle matches.
    Mesh shifted = got;
    for (Vec3& p : shifted.positions) p.x += 4 * t.p;
    EXPECT_EQ(unmatched_triangles(shifted, want, t), 288u);
}

// The same scene through the same integrator: the means agree within the noise of the two
// independent renders (z-score of the mean difference, from the per-pixel differences).
TEST(GltfDraco, TranscodedTwinRendersTheSameImage) {
    Scene plain = twin(false), packed = twin(true);
    ASSERT_EQ(plain.cameras.size(), 1u);
    packed.cameras = plain.cameras;  // draco_transcoder drops cameras
    ASSERT_EQ(packed.lights.size(), 1u);
    const int size = 40, spp = test::spp(16);
    Image a = test::render(plain, size, spp, "pt", 8, 0, 1);
    Image b = test::render(packed, size, spp, "pt", 8, 0, 2);
    for (int c = 0; c < 3; ++c) {
        double sum = 0, sum2 = 0;
        size_t n = a.rgba.size() / 4;
        for (size_t i = 0; i < n; ++i) {
            double d = double(a.rgba[4 * i + c]) - b.rgba[4 * i + c];
            sum += d;
            sum2 += d * d;
        }
        double mean = sum / n, var = sum2 / n - mean * mean;
        double se = std::sqrt(var / n);
        EXPECT_GT(test::channel_mean(a, c), 0.05) << "the lit sphere fills part of the frame";
        EXPECT_LT(std::fabs(mean), 4.5 * se + 1e-4) << "channel " << c << " mean difference " << mean << " se " << se;
    }
}

// COLLADA2GLTF's Draco export of the two-cylinder engine against the uncompressed GLB of the
// same model, both in Debian's assimp-testmodels.
TEST(GltfDraco, AssimpEngineMatchesItsUncompressedTwin) {
    const std::string dir = "/usr/share/assimp/models/glTF2/";
    ASSERT_TRUE(fs::exists(dir + "draco/2CylinderEngine.gltf")) << "assimp-testmodels is not installed (scripts/install-deps.sh installs it)";
    Scene packed = import_scene(dir + "draco/2CylinderEngine.gltf");
    Scene plain = import_scene(dir + "2CylinderEngine-glTF-Binary/2CylinderEngine.glb");
    ASSERT_EQ(packed.meshes.size(), plain.meshes.size());
    // What renders: the load's repairs drop degenerate triangles, and quantization makes a few
    // near-degenerate ones degenerate or not: counts agree to a few triangles in thousands.
    repair_scene(packed);
    repair_scene(plain);
    size_t tp = 0, tu = 0;
    for (size_t i = 0; i < plain.meshes.size(); ++i) {
        double np = packed.meshes[i].indices.size() / 3.0, nu = plain.meshes[i].indices.size() / 3.0;
        tp += size_t(np);
        tu += size_t(nu);
        EXPECT_LE(std::fabs(np - nu), 3 + 0.002 * nu) << "mesh " << i;
        // Each mesh's bounding box: the file does not say its bits; 2^-10 of the extent bounds any
        // quantization of 11 bits (Draco's default) or more.
        const float big = 1e30f;
        Vec3 lo[2] = {Vec3(big, big, big), Vec3(big, big, big)};
        Vec3 hi[2] = {Vec3(-big, -big, -big), Vec3(-big, -big, -big)};
        const Mesh* ms[2] = {&packed.meshes[i], &plain.meshes[i]};
        for (int k = 0; k < 2; ++k)
            for (const Vec3& p : ms[k]->positions) lo[k] = min(lo[k], p), hi[k] = max(hi[k], p);
        float ext = std::max({hi[1].x - lo[1].x, hi[1].y - lo[1].y, hi[1].z - lo[1].z});
        for (int d = 0; d < 3; ++d) {
            EXPECT_NEAR(lo[0][d], lo[1][d], ext / 1024) << "mesh " << i;
            EXPECT_NEAR(hi[0][d], hi[1][d], ext / 1024) << "mesh " << i;
        }
    }
    EXPECT_NEAR(double(tp), double(tu), 0.001 * tu);
    EXPECT_GT(tp, 30000u);
}

// --------------------------------------------------------------------------------------------
// Streams encoded here: a few triangles with distinct per-corner values of chosen Draco types.

struct DracoAttribute {
    draco::GeometryAttribute::Type type;
    draco::DataType data_type;
    int components;
    bool normalized;
    std::vector<double> values;  // per corner, components each
};

template <typename T>
void set_corners(draco::TriangleSoupMeshBuilder& mb, int id, const DracoAttribute& a, int faces) {
    for (int f = 0; f < faces; ++f) {
        T v[3][4] = {};
        for (int k = 0; k < 3; ++k)
            for (int c = 0; c < a.components; ++c) v[k][c] = T(a.values[(3 * f + k) * a.components + c]);
        mb.SetAttributeValuesForFace(id, draco::FaceIndex(f), v[0], v[1], v[2]);
    }
}

// Returns the stream and each attribute's unique id.
std::vector<uint8_t> encode(const std::vector<DracoAttribute>& attributes, int faces, std::vector<int>* ids,
                            int method = draco::MESH_EDGEBREAKER_ENCODING) {
    draco::TriangleSoupMeshBuilder mb;
    mb.Start(faces);
    for (const DracoAttribute& a : attributes) {
        int id = mb.AddAttribute(a.type, int8_t(a.components), a.data_type, a.normalized);
        switch (a.data_type) {
            case draco::DT_FLOAT32: set_corners<float>(mb, id, a, faces); break;
            case draco::DT_INT8: set_corners<int8_t>(mb, id, a, faces); break;
            case draco::DT_UINT8: set_corners<uint8_t>(mb, id, a, faces); break;
            case draco::DT_INT16: set_corners<int16_t>(mb, id, a, faces); break;
            case draco::DT_UINT16: set_corners<uint16_t>(mb, id, a, faces); break;
            default: ADD_FAILURE() << "type not used here";
        }
    }
    std::unique_ptr<draco::Mesh> mesh = mb.Finalize();
    EXPECT_TRUE(mesh);
    for (int i = 0; i < mesh->num_attributes(); ++i) ids->push_back(int(mesh->attribute(i)->unique_id()));
    draco::Encoder encoder;
    encoder.SetEncodingMethod(method);
    draco::EncoderBuffer buffer;
    draco::Status status = encoder.EncodeMeshToBuffer(*mesh, &buffer);
    EXPECT_TRUE(status.ok()) << status.error_msg_string();
    return std::vector<uint8_t>(buffer.data(), buffer.data() + buffer.size());
}

struct GltfAttribute {
    std::string name;
    int component_type;
    const char* type;
    bool normalized;
};

// A glTF whose one primitive takes `attrs` (paired with the stream's attributes in order) from
// `stream`; its accessors have counts `points` and `3 * faces`.
GltfBuilder draco_scene(const std::vector<uint8_t>& stream, const std::vector<GltfAttribute>& attrs,
                        const std::vector<int>& ids, size_t points, int faces, int index_type = k_ubyte) {
    GltfBuilder b;
    int view = b.view(stream.data(), stream.size());
    json attributes = json::object(), ext_attributes = json::object();
    for (size_t i = 0; i < attrs.size(); ++i) {
        json a = {{"componentType", attrs[i].component_type}, {"count", points}, {"type", attrs[i].type}};
        if (attrs[i].normalized) a["normalized"] = true;
        attributes[attrs[i].name] = b.push("accessors", a);
        ext_attributes[attrs[i].name] = ids.at(i);
    }
    int indices = b.push("accessors", {{"componentType", index_type}, {"count", 3 * faces}, {"type", "SCALAR"}});
    json prim = {
        {"attributes", attributes},
        {"indices", indices},
        {"extensions", {{"KHR_draco_mesh_compression", {{"bufferView", view}, {"attributes", ext_attributes}}}}}};
    b.push("meshes", {{"name", "packed"}, {"primitives", json::array({prim})}});
    b.place(0);
    b.doc["extensionsUsed"] = {"KHR_draco_mesh_compression", "KHR_mesh_quantization"};
    b.doc["extensionsRequired"] = {"KHR_draco_mesh_compression", "KHR_mesh_quantization"};
    return b;
}

// Two triangles (a quad split, six distinct corners) of distinct values per attribute.
std::vector<double> ramp(int corners, int components, double first, double step) {
    std::vector<double> v;
    for (int i = 0; i < corners * components; ++i) v.push_back(first + step * i);
    return v;
}

std::vector<double> quad_positions() { return {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 0, 0.5, 1, 1, 0.5, 0, 1, 0.5}; }

// Finds the imported vertex at position `p` (positions are distinct and exact: no quantization).
size_t vertex_at(const Mesh& m, Vec3 p) {
    for (size_t i = 0; i < m.positions.size(); ++i)
        if (m.positions[i].x == p.x && m.positions[i].y == p.y && m.positions[i].z == p.z) return i;
    ADD_FAILURE() << "no vertex at " << p.x << " " << p.y << " " << p.z;
    return 0;
}

// Each attribute is found by its unique id, whatever the order of names in the JSON, and integer
// types decode as the accessor says: u16 normalized / 65535, s8 normalized max(c / 127, -1),
// u8 normalized / 255; s16 POSITION unnormalized (KHR_mesh_quantization) as the integer itself.
TEST(GltfDraco, AttributesMapByUniqueIdAndDecodeByComponentType) {
    using draco::GeometryAttribute;
    std::vector<double> pos = {0, 0, 0, 1000, 0, 0, 1000, -300, 0, 0, 0, 7, 1000, -300, 7, 0, -300, 7};
    std::vector<DracoAttribute> da = {
        {GeometryAttribute::POSITION, draco::DT_INT16, 3, false, pos},
        {GeometryAttribute::NORMAL,
         draco::DT_INT8,
         3,
         true,
         {0, 0, 127, 0, 0, 127, 0, 0, 127, 0, -128, 0, 0, -128, 0, 0, -128, 0}},
        {GeometryAttribute::TEX_COORD, draco::DT_UINT16, 2, true, ramp(6, 2, 0, 5000)},
        {GeometryAttribute::TEX_COORD, draco::DT_INT8, 2, true, ramp(6, 2, -128, 20)},
        {GeometryAttribute::COLOR, draco::DT_UINT8, 4, true, ramp(6, 4, 5, 10)},
    };
    std::vector<int> ids;
    std::vector<uint8_t> stream = encode(da, 2, &ids);
    ASSERT_EQ(ids.size(), 5u);
    GltfBuilder b = draco_scene(stream,
                                {{"POSITION", k_short, "VEC3", false},
                                 {"NORMAL", k_byte, "VEC3", true},
                                 {"TEXCOORD_0", k_ushort, "VEC2", true},
                                 {"TEXCOORD_1", k_byte, "VEC2", true},
                                 {"COLOR_0", k_ubyte, "VEC4", true}},
                                ids, 6, 2);
    Scene s = load(b);
    ASSERT_EQ(s.meshes.size(), 1u);
    const Mesh& m = s.meshes[0];
    ASSERT_EQ(m.positions.size(), 6u);
    ASSERT_EQ(m.indices.size(), 6u);
    for (int v = 0; v < 6; ++v) {
        size_t i = vertex_at(m, Vec3(float(pos[3 * v]), float(pos[3 * v + 1]), float(pos[3 * v + 2])));
        EXPECT_FLOAT_EQ(m.normals[i].z, v < 3 ? 1.0f : 0.0f);
        EXPECT_FLOAT_EQ(m.normals[i].y, v < 3 ? 0.0f : -1.0f);  // max(-128 / 127, -1)
        EXPECT_FLOAT_EQ(m.uv0[i].x, float(5000 * (2 * v)) / 65535.0f);
        EXPECT_FLOAT_EQ(m.uv0[i].y, float(5000 * (2 * v + 1)) / 65535.0f);
        EXPECT_FLOAT_EQ(m.uv1[i].x, std::max(float(-128 + 20 * (2 * v)) / 127.0f, -1.0f));
        EXPECT_FLOAT_EQ(m.colors[i].r, float(5 + 10 * (4 * v)) / 255.0f);
        EXPECT_FLOAT_EQ(m.colors[i].a, float(5 + 10 * (4 * v + 3)) / 255.0f);
    }
    // Each decoded triangle is one of the two encoded ones, with its winding.
    for (int t = 0; t < 2; ++t) {
        Vec3 p0 = m.positions[m.indices[3 * t]], p1 = m.positions[m.indices[3 * t + 1]],
             p2 = m.positions[m.indices[3 * t + 2]];
        Vec3 n = cross(p1 - p0, p2 - p0);
        EXPECT_GT(std::fabs(n.z), 0.0f);
        EXPECT_TRUE(p0.z == p1.z && p1.z == p2.z);
    }
}

// Float attributes without quantization survive exactly, including TANGENT (read for a
// normal-mapped material) and the sequential encoding, which keeps Draco's other code path.
TEST(GltfDraco, FloatTangentsAndSequentialEncoding) {
    using draco::GeometryAttribute;
    std::vector<DracoAttribute> da = {
        {GeometryAttribute::POSITION, draco::DT_FLOAT32, 3, false, quad_positions()},
        {GeometryAttribute::TEX_COORD, draco::DT_FLOAT32, 2, false, ramp(6, 2, 0.0, 0.125)},
        {GeometryAttribute::GENERIC, draco::DT_FLOAT32, 4, false, {1, 0, 0, 1,  1, 0, 0, 1,  1, 0, 0, 1,
                                                                   0, 1, 0, -1, 0, 1, 0, -1, 0, 1, 0, -1}},
    };
    std::vector<int> ids;
    std::vector<uint8_t> stream = encode(da, 2, &ids, draco::MESH_SEQUENTIAL_ENCODING);
    GltfBuilder b = draco_scene(stream,
                                {{"POSITION", k_float, "VEC3", false},
                                 {"TEXCOORD_0", k_float, "VEC2", false},
                                 {"TANGENT", k_float, "VEC4", false}},
                                ids, 6, 2);
    b.doc["meshes"][0]["primitives"][0]["material"] = 0;
    b.push("materials", {{"normalTexture", {{"index", 0}}}});
    b.push("images", {{"uri", std::string("data:image/png;base64,") + k_png_2x2}});
    b.push("textures", {{"source", 0}});
    Scene s = load(b);
    const Mesh& m = s.meshes.at(0);
    ASSERT_EQ(m.tangents.size(), 6u);
    std::vector<double> pos = quad_positions();
    for (int v = 0; v < 6; ++v) {
        size_t i = vertex_at(m, Vec3(float(pos[3 * v]), float(pos[3 * v + 1]), float(pos[3 * v + 2])));
        EXPECT_EQ(m.uv0[i].x, float(0.125 * 2 * v));
        expect_vec3(m.tangents[i], v < 3 ? 1.0f : 0.0f, v < 3 ? 0.0f : 1.0f, 0.0f, 0.0f);
        EXPECT_EQ(m.tangent_signs[i], v < 3 ? 1.0f : -1.0f);
    }
}

// --------------------------------------------------------------------------------------------
// Malformed: one-line ImportError naming the file, never a crash.

struct SmallStream {
    std::vector<uint8_t> bytes;
    std::vector<int> ids;
};

SmallStream small_stream() {
    using draco::GeometryAttribute;
    SmallStream s;
    s.bytes = encode({{GeometryAttribute::POSITION, draco::DT_FLOAT32, 3, false, quad_positions()},
                      {GeometryAttribute::NORMAL, draco::DT_FLOAT32, 3, false, ramp(6, 3, -0.5, 0.05)}},
                     2, &s.ids);
    return s;
}

GltfBuilder small_scene(const SmallStream& s) {
    return draco_scene(s.bytes, {{"POSITION", k_float, "VEC3", false}, {"NORMAL", k_float, "VEC3", false}}, s.ids, 6,
                       2);
}

TEST(GltfDracoErrors, TruncatedStream) {
    SmallStream s = small_stream();
    ASSERT_NO_THROW(load(small_scene(s)));
    for (size_t keep : {size_t(0), size_t(4), s.bytes.size() / 2, s.bytes.size() - 1}) {
        SmallStream cut = s;
        cut.bytes.resize(keep);
        std::string msg = expect_import_error(small_scene(cut));
        EXPECT_NE(msg.find("KHR_draco_mesh_compression"), std::string::npos) << msg;
    }
}

// The same cut through a .glb, where the importer rewrites the JSON (Draco's index accessors get
// a placeholder view) before tinygltf reads the file: the rewrite must not make a cut file look
// whole (the fuzzer's finding: tinygltf then read the BIN chunk past the file's end).
TEST(GltfDracoErrors, CutGlbIsRefusedThroughTheJsonRewrite) {
    std::vector<uint8_t> glb = small_scene(small_stream()).glb();
    glb.resize(glb.size() - 5);
    TempDir dir;
    std::string msg = expect_import_error(dir.write("cut.glb", glb));
    EXPECT_NE(msg.find("truncated .glb"), std::string::npos) << msg;
}

// Random corruption of the stream: whatever Draco makes of it, the import either succeeds with
// indices inside the mesh or fails with an ImportError (sanitizer builds check the reads).
TEST(GltfDracoErrors, CorruptedStreamsNeverCrash) {
    SmallStream s = small_stream();
    std::mt19937 rng(7);
    int failed = 0, loaded = 0;
    for (int trial = 0; trial < 300; ++trial) {
        SmallStream bad = s;
        int flips = 1 + int(rng() % 4);
        for (int f = 0; f < flips; ++f) bad.bytes[rng() % bad.bytes.size()] ^= uint8_t(1u << (rng() % 8));
        TempDir dir;
        fs::path path = dir.write("corrupt.gltf", small_scene(bad).gltf());
        try {
            Scene scene = import_scene(path.string());
            for (const Mesh& m : scene.meshes)
                for (uint32_t i : m.indices) ASSERT_LT(i, m.positions.size());
            ++loaded;
        } catch (const ImportError& e) {
            EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
            ++failed;
        }
    }
    EXPECT_GT(failed, 0);  // the corruption reaches the decoder's checks
    EXPECT_EQ(failed + loaded, 300);
}

TEST(GltfDracoErrors, DeclarationsMustMatchTheStream) {
    SmallStream s = small_stream();
    auto message = [&](auto edit) {
        GltfBuilder b = small_scene(s);
        edit(b);
        return expect_import_error(b);
    };
    auto ext = [](GltfBuilder& b) -> json& {
        return b.doc["meshes"][0]["primitives"][0]["extensions"]["KHR_draco_mesh_compression"];
    };
    std::string m;
    m = message([](GltfBuilder& b) { b.doc["accessors"][0]["count"] = 7; });
    EXPECT_NE(m.find("decodes 6 points"), std::string::npos) << m;
    m = message([](GltfBuilder& b) { b.doc["accessors"][2]["count"] = 9; });
    EXPECT_NE(m.find("2 triangles"), std::string::npos) << m;
    m = message([&](GltfBuilder& b) { ext(b)["attributes"]["NORMAL"] = 17; });
    EXPECT_NE(m.find("Draco id 17"), std::string::npos) << m;
    m = message([&](GltfBuilder& b) { ext(b)["bufferView"] = 5; });
    EXPECT_NE(m.find("bufferView 5"), std::string::npos) << m;
    m = message([&](GltfBuilder& b) { ext(b).erase("attributes"); });
    EXPECT_NE(m.find("attributes"), std::string::npos) << m;
    m = message([](GltfBuilder& b) { b.doc["accessors"][1]["type"] = "VEC4"; });
    EXPECT_NE(m.find("NORMAL"), std::string::npos) << m;
    m = message([](GltfBuilder& b) { b.doc["meshes"][0]["primitives"][0]["mode"] = 6; });
    EXPECT_NE(m.find("TRIANGLE_FAN"), std::string::npos) << m;
    // A float stream declared as normalized bytes (which POSITION may be): the types disagree.
    m = message([](GltfBuilder& b) {
        b.doc["accessors"][0]["componentType"] = k_ubyte;
        b.doc["accessors"][0]["normalized"] = true;
    });
    EXPECT_NE(m.find("stores FLOAT32"), std::string::npos) << m;
}

// UNSIGNED_BYTE indices cannot hold the index 300 of a 301-point stream.
TEST(GltfDracoErrors, IndexTypeMustHoldEveryIndex) {
    using draco::GeometryAttribute;
    const int faces = 101;
    std::vector<double> pos;
    for (int f = 0; f < faces; ++f)
        for (int k = 0; k < 3; ++k) pos.insert(pos.end(), {double(f), double(k == 1), double(k == 2)});
    std::vector<int> ids;
    std::vector<uint8_t> stream =
        encode({{GeometryAttribute::POSITION, draco::DT_FLOAT32, 3, false, pos}}, faces, &ids);
    GltfBuilder b = draco_scene(stream, {{"POSITION", k_float, "VEC3", false}}, ids, 303, faces, k_ubyte);
    std::string m = expect_import_error(b);
    EXPECT_NE(m.find("does not fit UNSIGNED_BYTE"), std::string::npos) << m;
    b.doc["accessors"][1]["componentType"] = k_ushort;
    EXPECT_EQ(load(b).meshes.at(0).indices.size(), size_t(3 * faces));
}

// A primitive without the extension cannot borrow a Draco primitive's index accessor (which has
// no bufferView of its own; the importer lends tinygltf one).
TEST(GltfDracoErrors, PlainPrimitiveCannotUseADracoIndexAccessor) {
    SmallStream s = small_stream();
    GltfBuilder b = small_scene(s);
    json plain = {{"attributes", {{"POSITION", b.positions({0, 0, 0, 1, 0, 0, 0, 1, 0})}}}, {"indices", 2}};
    b.doc["meshes"][0]["primitives"].push_back(plain);
    std::string m = expect_import_error(b);
    EXPECT_NE(m.find("no bufferView"), std::string::npos) << m;
}

// A grid of n x n points carrying, besides POSITION, a GENERIC attribute of `extra_components`
// unsigned bytes a point that the glTF does not name (zeros, so the stream stays small however
// many points it declares). Built as a draco::Mesh directly: the soup builder would hold every
// corner's 127 values.
struct GridStream {
    std::vector<uint8_t> bytes;
    int position_id = -1;
    size_t points = 0;
    int faces = 0;
};

GridStream grid_with_unnamed_attribute(int n, int extra_components) {
    using draco::GeometryAttribute;
    draco::Mesh mesh;
    GridStream g;
    g.points = size_t(n) * n;
    mesh.set_num_points(uint32_t(g.points));
    GeometryAttribute pos, extra;
    pos.Init(GeometryAttribute::POSITION, nullptr, 3, draco::DT_FLOAT32, false, 12, 0);
    extra.Init(GeometryAttribute::GENERIC, nullptr, int8_t(extra_components), draco::DT_UINT8, false,
               extra_components, 0);
    int p = mesh.AddAttribute(pos, true, uint32_t(g.points));
    mesh.AddAttribute(extra, true, uint32_t(g.points));  // values zero-filled
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            float xyz[3] = {float(x), float(y), 0};
            mesh.attribute(p)->SetAttributeValue(draco::AttributeValueIndex(uint32_t(y * n + x)), xyz);
        }
    for (int y = 0; y + 1 < n; ++y)
        for (int x = 0; x + 1 < n; ++x) {
            auto v = [n](int i, int j) { return draco::PointIndex(uint32_t(j * n + i)); };
            mesh.AddFace({v(x, y), v(x + 1, y), v(x + 1, y + 1)});
            mesh.AddFace({v(x, y), v(x + 1, y + 1), v(x, y + 1)});
        }
    g.faces = int(mesh.num_faces());
    g.position_id = int(mesh.attribute(p)->unique_id());
    draco::Encoder encoder;
    encoder.SetAttributeQuantization(GeometryAttribute::POSITION, 14);
    draco::EncoderBuffer buffer;
    draco::Status status = encoder.EncodeMeshToBuffer(mesh, &buffer);
    EXPECT_TRUE(status.ok()) << status.error_msg_string();
    g.bytes.assign(buffer.data(), buffer.data() + buffer.size());
    return g;
}

GltfBuilder grid_scene(const GridStream& g) {
    return draco_scene(g.bytes, {{"POSITION", k_float, "VEC3", false}}, {g.position_id}, g.points, g.faces, k_uint);
}

// An attribute the extension does not name is decoded by Draco all the same, so it is charged to
// the import's budget like a named one: a small one is ignored and the mesh imports.
TEST(GltfDraco, UnnamedAttributeIsIgnored) {
    GridStream g = grid_with_unnamed_attribute(8, 127);
    Scene scene = load(grid_scene(g));
    ASSERT_EQ(scene.meshes.size(), size_t(1));
    EXPECT_EQ(scene.meshes[0].positions.size(), g.points);
    EXPECT_EQ(scene.meshes[0].indices.size(), size_t(3 * g.faces));
}

// A 0.2 MB stream declaring 102,400 points with an unnamed 127-component attribute: its values
// (and the decoder's 32-bit working copies) would take about 120 MB. Imported by a child process
// whose address space has 64 MiB to spare, the import must be refused by its budget, naming the
// attribute, before Draco allocates the values (without the charge, the decode itself runs out).
TEST(GltfDracoErrors, UnnamedAttributeIsChargedBeforeItIsDecoded) {
    GridStream g = grid_with_unnamed_attribute(320, 127);
    ASSERT_LT(g.bytes.size(), size_t(1) << 20);
    TempDir dir;
    fs::path file = dir.write("large_unnamed.gltf", grid_scene(g).gltf());

    std::ifstream status("/proc/self/status");
    uint64_t vm_kib = 0;
    for (std::string line; std::getline(status, line);)
        if (line.rfind("VmSize:", 0) == 0) vm_kib = std::stoull(line.substr(7));
    ASSERT_GT(vm_kib, 0u);

    int out[2];
    ASSERT_EQ(pipe(out), 0);
    pid_t child = fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
        ::close(out[0]);
        rlimit as{rlim_t(vm_kib * 1024 + (64ull << 20)), rlim_t(vm_kib * 1024 + (64ull << 20))};
        setrlimit(RLIMIT_AS, &as);
        std::string message = "imported";
        try {
            import_scene(file.string());
        } catch (const std::exception& e) {
            message = e.what();
        }
        ssize_t written = write(out[1], message.data(), message.size());
        _exit(written == ssize_t(message.size()) ? 0 : 1);
    }
    ::close(out[1]);
    std::string message;
    char chunk[512];
    for (ssize_t got; (got = read(out[0], chunk, sizeof chunk)) > 0;) message.append(chunk, size_t(got));
    ::close(out[0]);
    int wstatus = 0;
    waitpid(child, &wstatus, 0);
    ASSERT_TRUE(WIFEXITED(wstatus)) << "the importing child died, signal " << WTERMSIG(wstatus);
    EXPECT_NE(message.find("Draco attribute"), std::string::npos) << message;
    EXPECT_NE(message.find("Draco attribute 1 that no glTF attribute names"), std::string::npos) << message;
    EXPECT_NE(message.find("127 components x 102400 points"), std::string::npos) << message;
    EXPECT_NE(message.find("needs"), std::string::npos) << message;
}

}  // namespace
}  // namespace veach
