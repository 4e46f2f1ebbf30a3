// The JSON of a .gltf or .glb file as text, and the same file with its JSON replaced: for the
// fix-ups the importer makes before tinygltf parses a file (Draco index accessors, meshopt
// fallback buffers), which tinygltf 2.7 would otherwise refuse.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace veach::gltf {

// Refuses (GltfError) a .glb whose header or chunks declare more bytes than it has: tinygltf 2.7
// checks the header's length but trusts the BIN chunk's, and the rewrites below must not hide a
// truncated file from it. glTF 1.0's binary form is left to the version check.
void check_glb_layout(std::span<const uint8_t> file);

// The file's JSON: all of a .gltf, the first chunk of a .glb (empty when the header is short;
// clamped to the file when the chunk length overruns it, for tinygltf to report).
std::string_view json_chunk(std::span<const uint8_t> file, bool binary);

// The file with its JSON replaced by `json`; a .glb keeps its header fields and every chunk
// after the JSON, with the lengths updated and the JSON padded to 4 bytes with spaces.
std::vector<uint8_t> with_json_chunk(std::span<const uint8_t> file, bool binary, std::string json);

}  // namespace veach::gltf
