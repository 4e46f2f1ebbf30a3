#include "importers/gltf/gltf_json_chunk.h"

#include <algorithm>
#include <cstring>
#include <string>

#include "importers/gltf/gltf_accessors.h"

namespace veach::gltf {

namespace {
constexpr size_t k_glb_json_begin = 20;  // header (magic, version, length), JSON chunk length and type
constexpr uint32_t k_chunk_json = 0x4E4F534A;

uint32_t read_u32(std::span<const uint8_t> file, size_t at) {
    uint32_t v;
    std::memcpy(&v, file.data() + at, 4);
    return v;
}

// The bytes the header says the file has (the file's own size when it says more; check_glb_layout
// refuses that).
size_t declared_end(std::span<const uint8_t> file) {
    return file.size() < 12 ? file.size() : std::min<size_t>(read_u32(file, 8), file.size());
}
}  // namespace

void check_glb_layout(std::span<const uint8_t> file) {
    if (file.size() >= 8 && read_u32(file, 4) == 1) return;  // glTF 1.0's binary form, refused by name later
    if (file.size() < k_glb_json_begin)
        throw GltfError("truncated .glb: " + std::to_string(file.size()) +
                        " bytes, less than its header and JSON chunk header");
    const size_t length = read_u32(file, 8);
    if (length > file.size())
        throw GltfError("truncated .glb: its header declares " + std::to_string(length) + " bytes, the file has " +
                        std::to_string(file.size()));
    if (read_u32(file, 16) != k_chunk_json) throw GltfError(".glb: the first chunk is not JSON");
    // Every chunk's length within the declared file: tinygltf 2.7 trusts the BIN chunk's.
    size_t at = 12;
    for (int chunk = 0; at < length; ++chunk) {
        if (length - at < 8)
            throw GltfError("truncated .glb: chunk " + std::to_string(chunk) + "'s header runs past the file's end");
        const uint32_t chunk_length = read_u32(file, at);
        if (chunk_length > length - at - 8)
            throw GltfError("truncated .glb: chunk " + std::to_string(chunk) + " declares " +
                            std::to_string(chunk_length) + " bytes, " + std::to_string(length - at - 8) + " remain");
        at += 8 + size_t(chunk_length);
    }
}

std::string_view json_chunk(std::span<const uint8_t> file, bool binary) {
    const char* data = reinterpret_cast<const char*>(file.data());
    if (!binary) return {data, file.size()};
    if (file.size() < k_glb_json_begin) return {};
    uint32_t length;
    std::memcpy(&length, data + 12, 4);
    return {data + k_glb_json_begin, std::min<size_t>(length, file.size() - k_glb_json_begin)};
}

std::vector<uint8_t> with_json_chunk(std::span<const uint8_t> file, bool binary, std::string json) {
    if (!binary) return std::vector<uint8_t>(json.begin(), json.end());
    file = file.first(declared_end(file));  // bytes past the declared length are not the file's
    size_t rest = k_glb_json_begin + json_chunk(file, binary).size();  // the BIN chunk and after
    while (json.size() % 4) json += ' ';
    std::vector<uint8_t> out;
    auto u32 = [&](uint32_t v) {
        for (int i = 0; i < 4; ++i) out.push_back(uint8_t(v >> (8 * i)));
    };
    out.insert(out.end(), file.begin(), file.begin() + 8);
    u32(uint32_t(k_glb_json_begin + json.size() + (file.size() - rest)));
    u32(uint32_t(json.size()));
    out.insert(out.end(), file.begin() + 16, file.begin() + k_glb_json_begin);
    out.insert(out.end(), json.begin(), json.end());
    out.insert(out.end(), file.begin() + rest, file.end());
    return out;
}

}  // namespace veach::gltf
