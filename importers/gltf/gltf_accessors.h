// Reading glTF accessors into plain arrays, and the per-import state the glTF readers share.
// Every byte an accessor would touch is checked against the bytes actually loaded before
// anything is allocated: a small hostile file gets an error, never a huge allocation or an
// out-of-bounds read.
#pragma once

#include <cstdint>
#include <map>
#include <span>
#include <stdexcept>
#include <string>
#include <unordered_set>
#include <vector>

#include "scene/scene.h"

namespace tinygltf {
class Model;
class Value;
}  // namespace tinygltf

namespace veach::gltf {

// A fault of the file. The importer prefixes the file name and rethrows it as ImportError, so
// messages here say only what is wrong and where in the file.
class GltfError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// What an allocation is charged to. Geometry has to come from the file's bytes (give or take
// u8 indices widened, strips expanded, accessors shared by meshes); decoded images legitimately
// dwarf their compressed files, so they get their own, larger allowance.
enum class Budget : uint8_t { Geometry, Textures };

// State of one import: the scene being filled, warnings said once, and memory budgets that bound
// what a file can make us allocate beyond its own size: a small hostile file gets an error, not
// a multi-gigabyte allocation.
class ImportContext {
public:
    ImportContext(Scene& scene, uint64_t input_bytes);

    void warn(const std::string& message);  // adds to Scene::warnings the first time only
    // Accounts for `bytes` of output; throws GltfError when the budget would be exceeded.
    void charge(uint64_t bytes, const std::string& what, Budget budget = Budget::Geometry);
    // Returns a charge whose memory was freed again (a decoder's temporary buffers).
    void release(uint64_t bytes, Budget budget = Budget::Geometry);

    Scene& scene;

private:
    std::unordered_set<std::string> m_warned;
    uint64_t m_limit[2] = {0, 0};
    uint64_t m_used[2] = {0, 0};
    uint64_t m_available = UINT64_MAX;  // what the process could still take when the import started
};

// A charge for the lifetime of a scope: temporary buffers that are freed before the import ends.
class ScopedCharge {
public:
    ScopedCharge(ImportContext& context, uint64_t bytes, const std::string& what, Budget budget)
        : m_context(context), m_bytes(bytes), m_budget(budget) {
        m_context.charge(bytes, what, budget);
    }
    ~ScopedCharge() { m_context.release(m_bytes, m_budget); }
    ScopedCharge(const ScopedCharge&) = delete;
    ScopedCharge& operator=(const ScopedCharge&) = delete;

private:
    ImportContext& m_context;
    uint64_t m_bytes;
    Budget m_budget;
};

// The encodings an attribute accepts. 32-bit float is always accepted; KHR_mesh_quantization
// adds the integer forms.
struct AttributeFormat {
    int min_components = 1, max_components = 4;
    bool normalized_unsigned = false;  // u8 / u16 with normalized: true
    bool normalized_signed = false;    // s8 / s16 with normalized: true
    bool integer = false;              // s8 / u8 / s16 / u16 with normalized: false
};

struct FloatAccessor {
    std::vector<float> values;  // count * components, element-major
    size_t count = 0;
    int components = 0;
};

// Reads accessor `index` as floats, decoding normalized integers per the glTF spec and applying
// sparse substitution. `what` names the use in error messages ("mesh 'a' primitive 0 NORMAL").
FloatAccessor read_float_accessor(const tinygltf::Model& model, int index, const AttributeFormat& format,
                                  const std::string& what, ImportContext& context);

// An accessor's declared element type and count, without its data: KHR_draco_mesh_compression
// primitives take their data from the decoded stream, which must match this declaration.
struct AccessorInfo {
    std::string where;  // "`what` (accessor N)", for messages
    size_t count = 0;
    int components = 0;
    int component_type = 0;
    bool normalized = false;
};
// Checks the declaration against `format` as read_float_accessor does (type, component type,
// normalized), never touching bufferView, byteOffset or sparse.
AccessorInfo attribute_accessor_info(const tinygltf::Model& model, int index, const AttributeFormat& format,
                                     const std::string& what);
// The same for an index accessor: SCALAR, UNSIGNED_BYTE / SHORT / INT.
AccessorInfo index_accessor_info(const tinygltf::Model& model, int index, const std::string& what);

// One component at `p` of `component_type` as a float, normalized integers per the glTF spec
// (unsigned c / max, signed max(c / max, -1)): the one rule for every attribute source.
float decode_component(const uint8_t* p, int component_type, bool normalized);
const char* component_type_name(int component_type);  // "UNSIGNED_SHORT", ...

// Reads a MAT4 FLOAT accessor (inverseBindMatrices), sparse substitution applied.
std::vector<Transform> read_matrix_accessor(const tinygltf::Model& model, int index, const std::string& what,
                                            ImportContext& context);

// Reads an index accessor (SCALAR u8 / u16 / u32), sparse substitution applied.
std::vector<uint32_t> read_index_accessor(const tinygltf::Model& model, int index, const std::string& what,
                                          ImportContext& context);

// The bytes of bufferView `view`, checked to lie inside its buffer (for images in a GLB).
std::span<const uint8_t> buffer_view_bytes(const tinygltf::Model& model, int view, const std::string& what);

// Small readers for extension JSON (tinygltf::Value), tolerant of absent or mistyped members.
const tinygltf::Value* json_member(const tinygltf::Value* object, const char* key);  // null if absent
const tinygltf::Value* json_extension(const std::map<std::string, tinygltf::Value>& extensions, const char* name);
double json_number(const tinygltf::Value* object, const char* key, double fallback);  // finite or fallback
// An integer member: `fallback` when absent, INT_MIN when malformed (so index checks reject it).
int json_integer(const tinygltf::Value* object, const char* key, int fallback);
// Fills out[0..n) from a JSON array of exactly n finite numbers; false (out untouched) otherwise.
bool json_numbers(const tinygltf::Value* array, double* out, size_t n);

}  // namespace veach::gltf
