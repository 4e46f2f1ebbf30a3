#include "importers/gltf/gltf_meshopt.h"

#include <meshoptimizer.h>
#include <tiny_gltf.h>

#include <cstring>
#include <nlohmann/json.hpp>

#include "importers/gltf/gltf_accessors.h"
#include "importers/gltf/gltf_json_chunk.h"

namespace veach::gltf {

namespace {

constexpr const char* k_extension = "EXT_meshopt_compression";

// A fallback buffer is bookkeeping for the decoded data, so its declared size is what decoding
// will allocate; a file declaring more than this is refused before anything is allocated (the
// importer's budgets then bound what the decoded accessors may make of it).
constexpr uint64_t k_max_fallback_bytes = uint64_t(1) << 32;

int64_t integer_field(const tinygltf::Value& object, const char* name, int64_t fallback, const std::string& what) {
    if (!object.Has(name)) return fallback;
    const tinygltf::Value& v = object.Get(name);
    if (!v.IsNumber()) throw GltfError(what + ": " + name + " is not a number");
    double d = v.GetNumberAsDouble();
    if (d != double(int64_t(d)) || d < 0) throw GltfError(what + ": " + name + " must be a non-negative integer");
    return int64_t(d);
}

int64_t required_integer(const tinygltf::Value& object, const char* name, const std::string& what) {
    if (!object.Has(name)) throw GltfError(what + ": " + name + " is required");
    return integer_field(object, name, 0, what);
}

std::string string_field(const tinygltf::Value& object, const char* name, const std::string& fallback,
                         const std::string& what) {
    if (!object.Has(name)) return fallback;
    const tinygltf::Value& v = object.Get(name);
    if (!v.IsString()) throw GltfError(what + ": " + name + " is not a string");
    return v.Get<std::string>();
}

void decode_view(tinygltf::Model& model, size_t view_index, const tinygltf::Value& ext) {
    const std::string what = "bufferView " + std::to_string(view_index) + " (" + k_extension + ")";
    if (!ext.IsObject()) throw GltfError(what + ": the extension is not an object");
    tinygltf::BufferView& view = model.bufferViews[view_index];

    int64_t source_buffer = required_integer(ext, "buffer", what);
    if (size_t(source_buffer) >= model.buffers.size()) throw GltfError(what + ": buffer is out of range");
    uint64_t offset = integer_field(ext, "byteOffset", 0, what);
    uint64_t length = required_integer(ext, "byteLength", what);
    uint64_t stride = required_integer(ext, "byteStride", what);
    uint64_t count = required_integer(ext, "count", what);
    std::string mode = string_field(ext, "mode", "", what);
    std::string filter = string_field(ext, "filter", "NONE", what);
    if (mode.empty()) throw GltfError(what + ": mode is required");
    const std::vector<unsigned char>& source = model.buffers[size_t(source_buffer)].data;
    if (offset > source.size() || length > source.size() - offset)
        throw GltfError(what + ": the compressed bytes lie outside buffer " + std::to_string(source_buffer));

    if (view.buffer < 0 || size_t(view.buffer) >= model.buffers.size())
        throw GltfError(what + ": the view's buffer is out of range");
    std::vector<unsigned char>& target = model.buffers[size_t(view.buffer)].data;
    if (view.byteOffset > target.size() || view.byteLength > target.size() - view.byteOffset)
        throw GltfError(what + ": the view lies outside buffer " + std::to_string(view.buffer));
    if (stride == 0 || count > view.byteLength / stride)
        throw GltfError(what + ": count x byteStride (" + std::to_string(count) + " x " + std::to_string(stride) +
                        ") exceeds the view's byteLength " + std::to_string(view.byteLength));
    if (&source == &target && offset < view.byteOffset + count * stride && view.byteOffset < offset + length)
        throw GltfError(what + ": the compressed bytes overlap the view they decode into");

    unsigned char* destination = target.data() + view.byteOffset;
    const unsigned char* stream = source.data() + offset;
    int status = 0;
    if (mode == "ATTRIBUTES") {
        if (stride % 4 != 0 || stride > 256) throw GltfError(what + ": ATTRIBUTES needs a byteStride of 4..256, x4");
        status = meshopt_decodeVertexBuffer(destination, count, stride, stream, length);
    } else if (mode == "TRIANGLES" || mode == "INDICES") {
        if (stride != 2 && stride != 4) throw GltfError(what + ": " + mode + " needs a byteStride of 2 or 4");
        if (mode == "TRIANGLES" && count % 3 != 0) throw GltfError(what + ": TRIANGLES needs a count divisible by 3");
        if (filter != "NONE") throw GltfError(what + ": filter " + filter + " applies to ATTRIBUTES only");
        status = mode == "TRIANGLES" ? meshopt_decodeIndexBuffer(destination, count, stride, stream, length)
                                     : meshopt_decodeIndexSequence(destination, count, stride, stream, length);
    } else {
        throw GltfError(what + ": unknown mode '" + mode + "'");
    }
    if (status != 0) throw GltfError(what + ": the compressed stream is corrupt");

    if (filter == "NONE") return;
    if (filter == "OCTAHEDRAL") {
        if (stride != 4 && stride != 8) throw GltfError(what + ": OCTAHEDRAL needs a byteStride of 4 or 8");
        meshopt_decodeFilterOct(destination, count, stride);
    } else if (filter == "QUATERNION") {
        if (stride != 8) throw GltfError(what + ": QUATERNION needs a byteStride of 8");
        meshopt_decodeFilterQuat(destination, count, stride);
    } else if (filter == "EXPONENTIAL") {
        meshopt_decodeFilterExp(destination, count, stride);  // stride % 4 == 0: checked above
    } else {
        throw GltfError(what + ": unknown filter '" + filter + "'");
    }
}

}  // namespace

std::optional<std::vector<uint8_t>> give_meshopt_fallbacks_uris(std::span<const uint8_t> file, bool binary,
                                                                std::map<std::string, uint64_t>& zero_files) {
    std::string_view text = json_chunk(file, binary);
    if (text.find(k_extension) == std::string_view::npos) return std::nullopt;
    nlohmann::json doc = nlohmann::json::parse(text, nullptr, false);
    if (doc.is_discarded() || !doc.is_object() || !doc.contains("buffers") || !doc["buffers"].is_array())
        return std::nullopt;
    bool changed = false;
    auto& buffers = doc["buffers"];
    for (size_t k = 0; k < buffers.size(); ++k) {
        auto& buffer = buffers[k];
        if (!buffer.is_object() || buffer.contains("uri") || !buffer.contains("extensions")) continue;
        // A .glb's first buffer without a uri is its BIN chunk, not a fallback.
        if (binary && k == 0) continue;
        const auto& extensions = buffer["extensions"];
        if (!extensions.is_object() || !extensions.contains(k_extension)) continue;
        const auto& ext = extensions[k_extension];
        if (!ext.is_object() || !ext.value("fallback", false)) continue;
        if (!buffer.contains("byteLength") || !buffer["byteLength"].is_number_unsigned()) continue;
        uint64_t bytes = buffer["byteLength"].get<uint64_t>();
        if (bytes > k_max_fallback_bytes)
            throw GltfError("buffer " + std::to_string(k) + ": an EXT_meshopt_compression fallback of " +
                            std::to_string(bytes) + " bytes is over the 4 GiB limit");
        std::string uri = std::string(k_meshopt_fallback_uri) + std::to_string(k) + ".bin";
        buffer["uri"] = uri;
        zero_files[uri] = bytes;
        changed = true;
    }
    if (!changed) return std::nullopt;
    return with_json_chunk(file, binary, doc.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace));
}

void decode_meshopt_buffer_views(tinygltf::Model& model) {
    for (size_t k = 0; k < model.bufferViews.size(); ++k) {
        const tinygltf::Value* ext = json_extension(model.bufferViews[k].extensions, k_extension);
        if (ext) decode_view(model, k, *ext);
    }
}

}  // namespace veach::gltf
