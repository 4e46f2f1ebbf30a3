// EXT_meshopt_compression (what `gltfpack -c` writes): a bufferView's bytes are a meshoptimizer
// stream in another buffer, decoded with Debian's libmeshoptimizer into the view's place in
// its own buffer, which the file may leave without data (a "fallback" buffer, no uri).
//
// Two steps around tinygltf, which refuses a buffer without a uri: before it parses the file,
// each data-less fallback buffer gets a synthetic uri that the importer's file callbacks serve
// as that many zero bytes; after it, every compressed view is decoded over those zeros. Every
// count, stride and range is checked before libmeshoptimizer sees it (its asserts abort).
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace tinygltf {
class Model;
}

namespace veach::gltf {

// The prefix of the synthetic uris; a file's own uri never matches an entry the importer made.
inline constexpr std::string_view k_meshopt_fallback_uri = "veach-meshopt-fallback-";

// When the file uses the extension and has fallback buffers without a uri: the file with those
// buffers given synthetic uris, whose byte lengths are added to `zero_files` (uri -> bytes).
// Empty when nothing needed it or the JSON does not parse (tinygltf reports that).
std::optional<std::vector<uint8_t>> give_meshopt_fallbacks_uris(std::span<const uint8_t> file, bool binary,
                                                                std::map<std::string, uint64_t>& zero_files);

// Decodes every bufferView's EXT_meshopt_compression stream into the view's bytes. Throws
// GltfError naming the view when the extension's fields or the stream are malformed.
void decode_meshopt_buffer_views(tinygltf::Model& model);

}  // namespace veach::gltf
