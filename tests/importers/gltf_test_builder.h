// Test helpers for the glTF importer tests: a glTF builder (JSON + one binary buffer, written as
// .gltf with a data: URI or as .glb), temporary folders, and expectations on ImportError.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "importers/importer.h"

namespace veach::gltf_test {

namespace fs = std::filesystem;
using json = nlohmann::json;

inline constexpr int k_byte = 5120, k_ubyte = 5121, k_short = 5122, k_ushort = 5123, k_uint = 5125, k_float = 5126;

// 1x1 16-bit grey PNG, value 0x8000.
inline constexpr const char* k_png_16bit_grey =
    "iVBORw0KGgoAAAANSUhEUgAAAAEAAAABEAAAAABq7kcWAAAAC0lEQVR4nGNoYAAAAQMAgT5MxZMAAAAASUVORK5CYII=";
// 2x2 RGBA8 PNG: top row red (255,0,0,255), green (0,255,0,128); bottom row blue, grey 188 alpha 0.
inline constexpr const char* k_png_2x2 =
    "iVBORw0KGgoAAAANSUhEUgAAAAIAAAACCAYAAABytg0kAAAAGElEQVR4nGP4z8DwHwgbGID0/z179jAAAEF4B7Cj4GXBAAAAAElFTkSuQmCC";

inline std::string base64(const std::vector<uint8_t>& bytes) {
    static const char* table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    for (size_t i = 0; i < bytes.size(); i += 3) {
        uint32_t v = uint32_t(bytes[i]) << 16;
        if (i + 1 < bytes.size()) v |= uint32_t(bytes[i + 1]) << 8;
        if (i + 2 < bytes.size()) v |= bytes[i + 2];
        out += table[(v >> 18) & 63];
        out += table[(v >> 12) & 63];
        out += i + 1 < bytes.size() ? table[(v >> 6) & 63] : '=';
        out += i + 2 < bytes.size() ? table[v & 63] : '=';
    }
    return out;
}

inline std::vector<uint8_t> unbase64(const std::string& text) {
    static const std::string table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::vector<uint8_t> out;
    uint32_t acc = 0;
    int bits = 0;
    for (char c : text) {
        if (c == '=') break;
        acc = (acc << 6) | uint32_t(table.find(c));
        bits += 6;
        if (bits >= 8) {
            bits -= 8;
            out.push_back(uint8_t(acc >> bits));
        }
    }
    return out;
}

class TempDir {
public:
    TempDir() {
        static std::atomic<int> counter{0};
        path_ = fs::temp_directory_path() /
                ("veach_gltf_test_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
        fs::create_directories(path_);
    }
    ~TempDir() {
        std::error_code ec;
        fs::remove_all(path_, ec);
    }
    fs::path write(const std::string& name, const std::string& text) const {
        fs::path p = path_ / name;
        fs::create_directories(p.parent_path());
        std::ofstream(p, std::ios::binary) << text;
        return p;
    }
    fs::path write(const std::string& name, const std::vector<uint8_t>& bytes) const {
        return write(name, std::string(bytes.begin(), bytes.end()));
    }
    const fs::path& path() const { return path_; }

private:
    fs::path path_;
};

// A glTF under construction: one binary buffer grown by the add_* calls, JSON via nlohmann.
class GltfBuilder {
public:
    json doc = {{"asset", {{"version", "2.0"}, {"generator", "veach tests"}}}};
    std::vector<uint8_t> bin;

    int view(const void* data, size_t bytes, int stride = 0) {
        while (bin.size() % 4) bin.push_back(0);
        json v = {{"buffer", 0}, {"byteOffset", bin.size()}, {"byteLength", bytes}};
        if (stride) v["byteStride"] = stride;
        const auto* p = static_cast<const uint8_t*>(data);
        bin.insert(bin.end(), p, p + bytes);
        return push("bufferViews", v);
    }
    template <typename T>
    int accessor(const std::vector<T>& values, int component_type, const char* type, bool normalized = false) {
        int comps = std::string(type) == "SCALAR" ? 1 : type[3] - '0';
        json a = {{"bufferView", view(values.data(), values.size() * sizeof(T))},
                  {"componentType", component_type},
                  {"count", values.size() / comps},
                  {"type", type}};
        if (normalized) a["normalized"] = true;
        return push("accessors", a);
    }
    int positions(const std::vector<float>& xyz) { return accessor(xyz, k_float, "VEC3"); }
    int triangle_mesh(const std::string& name = "tri", json extra_attributes = json::object()) {
        json attributes = {{"POSITION", positions({0, 0, 0, 1, 0, 0, 0, 1, 0})}};
        attributes.update(extra_attributes);
        return push("meshes", {{"name", name}, {"primitives", json::array({{{"attributes", attributes}}})}});
    }
    int push(const char* array, const json& value) {
        doc[array].push_back(value);
        return static_cast<int>(doc[array].size()) - 1;
    }
    // A node placing `mesh`, added to the default scene.
    int place(int mesh, json node = json::object()) {
        node["mesh"] = mesh;
        int index = push("nodes", node);
        if (!doc.contains("scenes")) scene({});
        doc["scenes"][0]["nodes"].push_back(index);
        return index;
    }
    void scene(std::vector<int> nodes) {
        doc["scenes"] = json::array({{{"nodes", nodes}}});
        doc["scene"] = 0;
    }
    json with_buffer(const std::string& uri) const {
        json d = doc;
        if (!bin.empty()) {
            d["buffers"] = json::array({{{"byteLength", bin.size()}}});
            if (!uri.empty()) d["buffers"][0]["uri"] = uri;
        }
        return d;
    }
    std::string gltf() const { return with_buffer("data:application/octet-stream;base64," + base64(bin)).dump(); }
    std::vector<uint8_t> glb() const {
        std::string text = with_buffer("").dump();
        while (text.size() % 4) text += ' ';
        std::vector<uint8_t> payload = bin;
        while (payload.size() % 4) payload.push_back(0);
        std::vector<uint8_t> out = {'g', 'l', 'T', 'F'};
        auto u32 = [&](uint32_t v) {
            for (int i = 0; i < 4; ++i) out.push_back(uint8_t(v >> (8 * i)));
        };
        u32(2);
        u32(uint32_t(12 + 8 + text.size() + (payload.empty() ? 0 : 8 + payload.size())));
        u32(uint32_t(text.size()));
        u32(0x4E4F534A);  // JSON
        out.insert(out.end(), text.begin(), text.end());
        if (!payload.empty()) {
            u32(uint32_t(payload.size()));
            u32(0x004E4942);  // BIN
            out.insert(out.end(), payload.begin(), payload.end());
        }
        return out;
    }
};

inline Scene load(const GltfBuilder& b, const ImportOptions& options = {}) {
    TempDir dir;
    return import_scene(dir.write("scene.gltf", b.gltf()).string(), options);
}

inline Scene load_text(const std::string& text, const ImportOptions& options = {}) {
    TempDir dir;
    return import_scene(dir.write("scene.gltf", text).string(), options);
}

// Expects ImportError with a one-line message naming the file; returns the message.
inline std::string expect_import_error(const fs::path& path, const ImportOptions& options = {}) {
    try {
        import_scene(path.string(), options);
    } catch (const ImportError& e) {
        std::string message = e.what();
        EXPECT_EQ(message.find('\n'), std::string::npos) << message;
        EXPECT_NE(message.find(path.filename().string()), std::string::npos) << message;
        return message;
    } catch (const std::exception& e) {
        ADD_FAILURE() << "not an ImportError: " << e.what();
        return {};
    }
    ADD_FAILURE() << path << " loaded without error";
    return {};
}

inline std::string expect_import_error(const GltfBuilder& b, const ImportOptions& options = {}) {
    TempDir dir;
    return expect_import_error(dir.write("broken.gltf", b.gltf()), options);
}

inline size_t count_warnings(const Scene& s, const std::string& needle) {
    size_t n = 0;
    for (const std::string& w : s.warnings) n += w.find(needle) != std::string::npos;
    return n;
}

inline void expect_vec3(const Vec3& v, float x, float y, float z, float tol = 1e-5f) {
    EXPECT_NEAR(v.x, x, tol);
    EXPECT_NEAR(v.y, y, tol);
    EXPECT_NEAR(v.z, z, tol);
}

inline std::string data_dir() { return std::string(VEACH_TEST_DATA_DIR) + "/gltf/"; }

// One triangle mesh placed by one node in the default scene.
inline GltfBuilder triangle_scene() {
    GltfBuilder b;
    b.place(b.triangle_mesh());
    return b;
}

// Three KHR_lights_punctual lights (point, directional, spot) written by `generator`.
inline GltfBuilder light_scene(const std::string& generator) {
    GltfBuilder b;
    b.doc["asset"]["generator"] = generator;
    b.doc["extensionsUsed"] = {"KHR_lights_punctual"};
    b.doc["extensions"]["KHR_lights_punctual"]["lights"] = {
        {{"type", "point"}, {"color", {1, 0.5, 0.25}}, {"intensity", 683 * 2}, {"name", "bulb"}},
        {{"type", "directional"}, {"intensity", 683}},
        {{"type", "spot"}, {"intensity", 683}, {"spot", {{"innerConeAngle", 0.25}, {"outerConeAngle", 0.5}}}}};
    const float h = std::sqrt(0.5f);  // -90 degrees about X: -Z turns to -Y
    b.push("nodes", {{"translation", {1, 2, 3}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
    b.push("nodes", {{"rotation", {-h, 0, 0, h}}, {"extensions", {{"KHR_lights_punctual", {{"light", 1}}}}}});
    b.push("nodes", {{"name", "spotty"}, {"extensions", {{"KHR_lights_punctual", {{"light", 2}}}}}});
    b.scene({0, 1, 2});
    return b;
}

// A triangle with TEXCOORD_0 and material 0, the 2x2 PNG as image 0, texture 0 with a nearest /
// clamp / mirror sampler and texture 1 without sampler.
inline GltfBuilder material_scene(const json& material, const json& extra_attributes = json::object()) {
    GltfBuilder b;
    int uv = b.accessor(std::vector<float>{0, 0, 1, 0, 0, 1}, k_float, "VEC2");
    json attributes = {{"TEXCOORD_0", uv}};
    attributes.update(extra_attributes);
    b.triangle_mesh("tri", attributes);
    b.doc["meshes"][0]["primitives"][0]["material"] = 0;
    b.push("materials", material);
    b.push("images", {{"uri", std::string("data:image/png;base64,") + k_png_2x2}});
    b.push("samplers", {{"magFilter", 9728}, {"wrapS", 33071}, {"wrapT", 33648}});
    b.push("textures", {{"source", 0}, {"sampler", 0}});
    b.push("textures", {{"source", 0}});
    b.place(0);
    return b;
}

// A quad of two triangles indexed with `component_type` indices.
inline GltfBuilder indexed_quad(int component_type) {
    GltfBuilder b;
    int pos = b.positions({0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0});
    std::vector<uint32_t> idx = {0, 1, 2, 0, 2, 3};
    int ind = -1;
    if (component_type == k_ubyte) ind = b.accessor(std::vector<uint8_t>(idx.begin(), idx.end()), k_ubyte, "SCALAR");
    if (component_type == k_ushort) ind = b.accessor(std::vector<uint16_t>(idx.begin(), idx.end()), k_ushort, "SCALAR");
    if (component_type == k_uint) ind = b.accessor(idx, k_uint, "SCALAR");
    b.push("meshes", {{"primitives", {{{"attributes", {{"POSITION", pos}}}, {"indices", ind}}}}});
    b.place(0);
    return b;
}

// One primitive of `vertices` vertices, not indexed, drawn with `mode`.
inline Scene load_mode(int mode, int vertices) {
    GltfBuilder b;
    std::vector<float> xyz;
    for (int i = 0; i < vertices; ++i) xyz.insert(xyz.end(), {float(i), float(i % 2), 0});
    int pos = b.positions(xyz);
    b.push("meshes", {{"primitives", {{{"attributes", {{"POSITION", pos}}}, {"mode", mode}}}}});
    b.place(0);
    return load(b);
}

}  // namespace veach::gltf_test
