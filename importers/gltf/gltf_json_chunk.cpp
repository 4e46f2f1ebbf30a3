#include "importers/gltf/gltf_json_chunk.h"

#include <algorithm>
#include <cstring>

namespace veach::gltf {

namespace {
constexpr size_t k_glb_json_begin = 20;  // header (magic, version, length), JSON chunk length and type
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
