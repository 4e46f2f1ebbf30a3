// KHR_draco_mesh_compression: a primitive's attributes and indices come from a Draco stream in a
// bufferView instead of from its accessors' bufferViews. The accessors still declare what the
// decoded data must be (count, type, componentType, normalized); the stream is decoded with
// Debian's libdraco and checked against those declarations, so a corrupt or mismatched stream is
// a GltfError naming the primitive, never an out-of-bounds read.
//
// Why not tinygltf's own TINYGLTF_ENABLE_DRACO: Veach links Debian's prebuilt libtinygltf.so,
// which is compiled without it, and that code indexes bufferViews and accessors unchecked.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <set>
#include <span>
#include <string>
#include <vector>

#include "importers/gltf/gltf_accessors.h"

namespace tinygltf {
struct Primitive;
}

namespace veach::gltf {

// tinygltf 2.7 (Debian 12) refuses a file whose index accessor has no bufferView, and the index
// accessor of a Draco-only primitive has none (the spec forbids one). When the file uses the
// extension, this returns the file with each such accessor given the primitive's Draco
// bufferView, which nothing reads (decoding ignores the accessors' views), and adds their
// indices to `patched` so a primitive without the extension can't read it as index data. Empty
// when nothing needed patching or the JSON does not parse (tinygltf then reports the fault).
std::optional<std::vector<uint8_t>> patch_draco_index_accessors(std::span<const uint8_t> file, bool binary,
                                                                std::set<int>& patched);

class DracoPrimitive {
public:
    // Decodes the primitive's KHR_draco_mesh_compression stream; nullptr when it has none.
    // Throws GltfError when the extension's JSON or the stream is malformed.
    static std::unique_ptr<DracoPrimitive> decode(const tinygltf::Model& model, const tinygltf::Primitive& primitive,
                                                  const std::string& what, ImportContext& context);
    ~DracoPrimitive();

    // Whether attribute `name` (POSITION, NORMAL, ...) is in the extension's `attributes`; the
    // others are read from their accessors as usual (the spec allows the mix).
    bool has(const std::string& name) const;

    // Attribute `name`, declared by accessor `accessor`, as read_float_accessor would return it
    // for uncompressed data: the accessor's type, componentType and normalized flag must pass
    // `format`, its count must equal the decoded point count, and integer component types are
    // decoded with the same normalization rule.
    FloatAccessor read(const tinygltf::Model& model, int accessor, const std::string& name,
                       const AttributeFormat& format, const std::string& what, ImportContext& context) const;

    // The decoded faces as a triangle list (three indices each, all below the point count).
    // `indices_accessor` (-1: none) must declare an index type that holds every index and, when
    // `check_count`, a count of three per face.
    std::vector<uint32_t> triangles(const tinygltf::Model& model, int indices_accessor, bool check_count,
                                    const std::string& what, ImportContext& context) const;

    size_t points() const;

private:
    struct Impl;
    explicit DracoPrimitive(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> m;
};

}  // namespace veach::gltf
