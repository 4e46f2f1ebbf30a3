// KHR_mesh_quantization: every component type its table allows for POSITION, NORMAL, TANGENT
// and TEXCOORD_n decodes as the glTF spec says (an unnormalized integer is its value; normalized
// unsigned c / max, signed max(c / max, -1)), with each type's extreme values; the types the
// table leaves out are refused with one line.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "gltf_test_builder.h"
#include "importers/importer.h"
#include "scene/scene_repair.h"

namespace veach {
namespace {

using namespace gltf_test;

// The decoded value of c per the glTF 2.0 spec (3.11, "Animations" / accessor normalization).
template <typename T>
float expected(T c, bool normalized) {
    if (!normalized || std::is_floating_point_v<T>) return float(c);
    float max = float(std::numeric_limits<T>::max());
    return std::is_signed_v<T> ? std::max(float(c) / max, -1.0f) : float(c) / max;
}

// Three vertices' `components` values of type T, covering the type's min, max, zero and one.
template <typename T>
std::vector<T> values(int components) {
    std::vector<T> pool = {std::numeric_limits<T>::lowest(), std::numeric_limits<T>::max(), T(0), T(1), T(3)};
    if (std::is_signed_v<T>) pool.push_back(T(-1));
    std::vector<T> v;
    for (int i = 0; i < 3 * components; ++i) v.push_back(pool[i % pool.size()]);
    return v;
}

// A triangle that stays a triangle (the load's repairs drop degenerate ones) with the extremes.
template <typename T>
std::vector<T> corners() {
    T lo = std::numeric_limits<T>::lowest(), hi = std::numeric_limits<T>::max();
    return {lo, T(0), T(0), hi, T(1), T(0), T(0), hi, T(3)};
}

enum class Attr { Position, Normal, Tangent, Texcoord0, Texcoord1 };

const char* name(Attr a) {
    switch (a) {
        case Attr::Position: return "POSITION";
        case Attr::Normal: return "NORMAL";
        case Attr::Tangent: return "TANGENT";
        case Attr::Texcoord0: return "TEXCOORD_0";
        default: return "TEXCOORD_1";
    }
}

int components(Attr a) { return a == Attr::Tangent ? 4 : a == Attr::Position || a == Attr::Normal ? 3 : 2; }

// A triangle whose attribute `a` is stored as T (normalized or not). The other attributes are
// floats; TANGENT is only read for a normal-mapped material, so the primitive gets one.
template <typename T>
GltfBuilder scene_with(Attr a, int component_type, bool normalized) {
    GltfBuilder b;
    int comps = components(a);
    const char* type = comps == 2 ? "VEC2" : comps == 3 ? "VEC3" : "VEC4";
    int acc = b.accessor(a == Attr::Position ? corners<T>() : values<T>(comps), component_type, type, normalized);
    json attributes = {{name(a), acc}};
    if (a != Attr::Position) attributes["POSITION"] = b.positions({0, 0, 0, 1, 0, 0, 0, 1, 0});
    if (a == Attr::Tangent)
        attributes["TEXCOORD_0"] = b.accessor(std::vector<float>{0, 0, 1, 0, 0, 1}, k_float, "VEC2");
    json prim = {{"attributes", attributes}};
    if (a == Attr::Tangent) {
        prim["material"] = 0;
        b.push("materials", {{"normalTexture", {{"index", 0}}}});
        b.push("images", {{"uri", std::string("data:image/png;base64,") + k_png_2x2}});
        b.push("textures", {{"source", 0}});
    }
    b.push("meshes", {{"primitives", json::array({prim})}});
    b.place(0);
    b.doc["extensionsUsed"] = {"KHR_mesh_quantization"};
    b.doc["extensionsRequired"] = {"KHR_mesh_quantization"};
    return b;
}

// The imported values of attribute `a` as floats, vertex-major.
std::vector<float> imported(const Mesh& m, Attr a) {
    std::vector<float> out;
    for (size_t i = 0; i < m.positions.size(); ++i) {
        switch (a) {
            case Attr::Position: out.insert(out.end(), {m.positions[i].x, m.positions[i].y, m.positions[i].z}); break;
            case Attr::Normal: out.insert(out.end(), {m.normals[i].x, m.normals[i].y, m.normals[i].z}); break;
            case Attr::Tangent:  // xyz, and the handedness sign the importer keeps from w
                out.insert(out.end(), {m.tangents[i].x, m.tangents[i].y, m.tangents[i].z, m.tangent_signs[i]});
                break;
            case Attr::Texcoord0: out.insert(out.end(), {m.uv0[i].x, m.uv0[i].y}); break;
            case Attr::Texcoord1: out.insert(out.end(), {m.uv1[i].x, m.uv1[i].y}); break;
        }
    }
    return out;
}

template <typename T>
void expect_decoded(Attr a, int component_type, bool normalized) {
    SCOPED_TRACE(std::string(name(a)) + " componentType " + std::to_string(component_type) +
                 (normalized ? " normalized" : ""));
    Scene s = load(scene_with<T>(a, component_type, normalized));
    ASSERT_EQ(s.meshes.size(), 1u);
    std::vector<float> got = imported(s.meshes[0], a);
    std::vector<T> stored = a == Attr::Position ? corners<T>() : values<T>(components(a));
    ASSERT_EQ(got.size(), stored.size());
    std::vector<float> want(stored.size());
    for (size_t i = 0; i < stored.size(); ++i) want[i] = expected(stored[i], normalized);
    if (a == Attr::Normal) {
        // The load renormalizes normals (scene_repair); the decoded direction is what must
        // survive, and it tells max(c / max, -1) from c / max (-128 / 127 on one axis only turns
        // the vector).
        repair_scene(s);
        got = imported(s.meshes[0], a);
        for (size_t v = 0; v < 3; ++v) {
            float* w = &want[v * 3];
            float len = std::sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
            for (int c = 0; c < 3; ++c) w[c] /= len;
        }
    }
    if (a == Attr::Tangent)
        for (size_t v = 0; v < 3; ++v) want[v * 4 + 3] = want[v * 4 + 3] < 0 ? -1.0f : 1.0f;  // handedness
    for (size_t i = 0; i < got.size(); ++i)
        EXPECT_NEAR(got[i], want[i], 1e-6f * std::max(1.0f, std::fabs(want[i])))
            << "component " << i << " stored " << double(stored[i]);
}

template <typename T>
void expect_refused(Attr a, int component_type, bool normalized) {
    SCOPED_TRACE(std::string(name(a)) + " componentType " + std::to_string(component_type) +
                 (normalized ? " normalized" : ""));
    std::string msg = expect_import_error(scene_with<T>(a, component_type, normalized));
    EXPECT_NE(msg.find(name(a)), std::string::npos) << msg;
    EXPECT_NE(msg.find("not allowed"), std::string::npos) << msg;
}

// The extension's table: POSITION any 8/16-bit integer, normalized or not.
TEST(GltfMeshQuantization, PositionEveryIntegerType) {
    for (bool n : {false, true}) {
        expect_decoded<int8_t>(Attr::Position, k_byte, n);
        expect_decoded<uint8_t>(Attr::Position, k_ubyte, n);
        expect_decoded<int16_t>(Attr::Position, k_short, n);
        expect_decoded<uint16_t>(Attr::Position, k_ushort, n);
    }
}

// NORMAL and TANGENT: normalized signed bytes and shorts only (unit vectors need the sign).
TEST(GltfMeshQuantization, NormalAndTangentSignedNormalized) {
    for (Attr a : {Attr::Normal, Attr::Tangent}) {
        expect_decoded<int8_t>(a, k_byte, true);
        expect_decoded<int16_t>(a, k_short, true);
        expect_refused<int8_t>(a, k_byte, false);
        expect_refused<int16_t>(a, k_short, false);
        expect_refused<uint8_t>(a, k_ubyte, true);
        expect_refused<uint16_t>(a, k_ushort, true);
    }
}

// TEXCOORD_n: signed bytes and shorts normalized or not, unsigned ones unnormalized (the
// extension) and normalized (core glTF), for either UV set.
TEST(GltfMeshQuantization, TexcoordEveryIntegerType) {
    for (Attr a : {Attr::Texcoord0, Attr::Texcoord1})
        for (bool n : {false, true}) {
            expect_decoded<int8_t>(a, k_byte, n);
            expect_decoded<uint8_t>(a, k_ubyte, n);
            expect_decoded<int16_t>(a, k_short, n);
            expect_decoded<uint16_t>(a, k_ushort, n);
        }
}

// UNSIGNED_INT is an index type only, for every attribute.
TEST(GltfMeshQuantization, UnsignedIntIsNoAttributeType) {
    for (Attr a : {Attr::Position, Attr::Normal, Attr::Texcoord0}) expect_refused<uint32_t>(a, k_uint, false);
}

}  // namespace
}  // namespace veach
