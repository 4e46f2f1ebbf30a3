#include "importers/gltf/gltf_accessors.h"

#include <algorithm>
#include <bit>
#include <climits>
#include <cmath>
#include <cstring>

#include <tiny_gltf.h>

#include "core/available_memory.h"

namespace veach::gltf {

// Components are read with memcpy in the host's byte order; glTF data is little-endian.
static_assert(std::endian::native == std::endian::little, "the glTF reader assumes a little-endian host");

namespace {

// Output the file may make us allocate: a fixed allowance plus a multiple of its own size. Real
// geometry expands by a small factor (u8 indices to u32, strips to lists, quantized attributes
// to floats); only contrived files reach the limit. Textures are float RGBA, 16 bytes a texel,
// and a decoder's temporary buffers are charged while they live: the allowance admits one
// 16k x 16k image (the per-image limit) with its decode (4 GiB kept, up to 3 GiB transient)
// whatever the file's size. Both allowances are also bounded by the memory the process can
// still take when the import starts (core/available_memory), so a machine or cgroup without it
// refuses the file with a message instead of being OOM-killed.
constexpr uint64_t k_geometry_base = 512ull << 20;
constexpr uint64_t k_geometry_per_input_byte = 32;
constexpr uint64_t k_texture_base = 7ull << 30;
constexpr uint64_t k_texture_per_input_byte = 64;
// Meshes index vertices with uint32; no accessor we read can usefully be longer.
constexpr uint64_t k_max_count = 1ull << 32;

constexpr int k_byte = TINYGLTF_COMPONENT_TYPE_BYTE;
constexpr int k_ubyte = TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE;
constexpr int k_short = TINYGLTF_COMPONENT_TYPE_SHORT;
constexpr int k_ushort = TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT;
constexpr int k_uint = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
constexpr int k_float = TINYGLTF_COMPONENT_TYPE_FLOAT;

size_t component_size(int type) {
    switch (type) {
        case k_byte:
        case k_ubyte: return 1;
        case k_short:
        case k_ushort: return 2;
        case k_uint:
        case k_float: return 4;
        default: return 0;
    }
}

const char* component_name(int type) {
    switch (type) {
        case k_byte: return "BYTE";
        case k_ubyte: return "UNSIGNED_BYTE";
        case k_short: return "SHORT";
        case k_ushort: return "UNSIGNED_SHORT";
        case k_uint: return "UNSIGNED_INT";
        case k_float: return "FLOAT";
        default: return "an invalid component type";
    }
}

// Matrices are never valid for the attributes we read, so they count as unsupported here.
int type_components(int type) {
    switch (type) {
        case TINYGLTF_TYPE_SCALAR: return 1;
        case TINYGLTF_TYPE_VEC2: return 2;
        case TINYGLTF_TYPE_VEC3: return 3;
        case TINYGLTF_TYPE_VEC4: return 4;
        default: return 0;
    }
}

std::string type_name(int components) {
    return components == 1 ? std::string("SCALAR") : "VEC" + std::to_string(components);
}

template <typename T>
T load(const uint8_t* p) {
    T v;
    std::memcpy(&v, p, sizeof(T));
    return v;
}

// Normalized integers per the glTF spec: unsigned c / max, signed max(c / max, -1).
float decode_float(const uint8_t* p, int type, bool normalized) {
    switch (type) {
        case k_float: return load<float>(p);
        case k_ubyte: return normalized ? load<uint8_t>(p) / 255.0f : load<uint8_t>(p);
        case k_ushort: return normalized ? load<uint16_t>(p) / 65535.0f : load<uint16_t>(p);
        case k_uint:
            return normalized ? static_cast<float>(load<uint32_t>(p) / 4294967295.0)
                              : static_cast<float>(load<uint32_t>(p));
        case k_byte: return normalized ? std::max(load<int8_t>(p) / 127.0f, -1.0f) : load<int8_t>(p);
        case k_short: return normalized ? std::max(load<int16_t>(p) / 32767.0f, -1.0f) : load<int16_t>(p);
        default: return 0.0f;
    }
}

uint32_t decode_index(const uint8_t* p, int type) {
    switch (type) {
        case k_ubyte: return load<uint8_t>(p);
        case k_ushort: return load<uint16_t>(p);
        case k_uint: return load<uint32_t>(p);
        default: return 0;
    }
}

const tinygltf::BufferView& checked_view(const tinygltf::Model& model, int view_index, const std::string& where) {
    if (view_index < 0 || static_cast<size_t>(view_index) >= model.bufferViews.size())
        throw GltfError(where + ": bufferView " + std::to_string(view_index) + " does not exist (the file has " +
                        std::to_string(model.bufferViews.size()) + ")");
    const tinygltf::BufferView& view = model.bufferViews[view_index];
    if (view.buffer < 0 || static_cast<size_t>(view.buffer) >= model.buffers.size())
        throw GltfError(where + ": bufferView " + std::to_string(view_index) + " refers to buffer " +
                        std::to_string(view.buffer) + ", which does not exist");
    size_t size = model.buffers[view.buffer].data.size();
    if (view.byteOffset > size || view.byteLength > size - view.byteOffset)
        throw GltfError(where + ": bufferView " + std::to_string(view_index) + " (bytes " +
                        std::to_string(view.byteOffset) + " + " + std::to_string(view.byteLength) +
                        ") lies outside buffer " + std::to_string(view.buffer) + " (" + std::to_string(size) +
                        " bytes)");
    return view;
}

// `count` elements of `element_size` bytes from `byte_offset` into a bufferView, checked to lie
// inside it. Sparse index and value views are tightly packed (allow_stride false).
struct ByteRun {
    const uint8_t* first = nullptr;
    size_t stride = 0;
};

ByteRun locate(const tinygltf::Model& model, int view_index, uint64_t byte_offset, uint64_t count, size_t element_size,
               bool allow_stride, const std::string& where) {
    const tinygltf::BufferView& view = checked_view(model, view_index, where);
    size_t stride = element_size;
    if (allow_stride && view.byteStride != 0) {
        if (view.byteStride < element_size)
            throw GltfError(where + ": bufferView " + std::to_string(view_index) + " byteStride " +
                            std::to_string(view.byteStride) + " is smaller than the element size " +
                            std::to_string(element_size));
        stride = view.byteStride;
    }
    if (count == 0) return {nullptr, stride};
    uint64_t length = view.byteLength;
    bool fits = byte_offset <= length && element_size <= length - byte_offset &&
                count - 1 <= (length - byte_offset - element_size) / stride;
    if (!fits)
        throw GltfError(where + ": " + std::to_string(count) + " elements of " + std::to_string(element_size) +
                        " bytes (stride " + std::to_string(stride) + ") from byte " + std::to_string(byte_offset) +
                        " run past the end of bufferView " + std::to_string(view_index) + " (" +
                        std::to_string(length) + " bytes)");
    const uint8_t* base = model.buffers[view.buffer].data.data() + view.byteOffset;
    return {base + byte_offset, stride};
}

// An accessor with every reference checked: reading element i component c of `run` and each
// sparse entry stays inside the loaded buffers.
struct Layout {
    std::string where;
    ByteRun run;  // run.first == nullptr: no bufferView, elements start as zeros
    size_t count = 0;
    int components = 0;
    int component_type = 0;
    size_t component_bytes = 0;
    bool normalized = false;
    size_t sparse_count = 0;
    ByteRun sparse_indices, sparse_values;
    int sparse_index_type = 0;

    size_t element_bytes() const { return component_bytes * static_cast<size_t>(components); }
};

// The accessor's declared element type and count, checked, without looking at its data.
Layout declared(const tinygltf::Model& model, int index, const std::string& what, bool allow_mat4 = false) {
    if (index < 0 || static_cast<size_t>(index) >= model.accessors.size())
        throw GltfError(what + ": accessor " + std::to_string(index) + " does not exist (the file has " +
                        std::to_string(model.accessors.size()) + ")");
    const tinygltf::Accessor& a = model.accessors[index];
    Layout l;
    l.where = what + " (accessor " + std::to_string(index) + ")";
    l.components = allow_mat4 && a.type == TINYGLTF_TYPE_MAT4 ? 16 : type_components(a.type);
    if (l.components == 0) throw GltfError(l.where + ": matrix accessors are not valid here");
    if (allow_mat4 && l.components != 16) throw GltfError(l.where + ": expected a MAT4 accessor");
    l.component_type = a.componentType;
    l.component_bytes = component_size(a.componentType);
    if (l.component_bytes == 0) throw GltfError(l.where + ": invalid componentType " + std::to_string(a.componentType));
    if (a.count > k_max_count)
        throw GltfError(l.where + ": count " + std::to_string(a.count) + " is larger than any mesh can use");
    l.count = a.count;
    l.normalized = a.normalized;
    return l;
}

Layout validate(const tinygltf::Model& model, int index, const std::string& what, bool allow_mat4 = false) {
    Layout l = declared(model, index, what, allow_mat4);
    const tinygltf::Accessor& a = model.accessors[index];
    if (a.bufferView >= 0) l.run = locate(model, a.bufferView, a.byteOffset, l.count, l.element_bytes(), true, l.where);

    if (a.sparse.isSparse) {
        if (a.sparse.count < 1 || static_cast<size_t>(a.sparse.count) > l.count)
            throw GltfError(l.where + ": sparse count " + std::to_string(a.sparse.count) +
                            " is not between 1 and the accessor's count " + std::to_string(l.count));
        l.sparse_count = static_cast<size_t>(a.sparse.count);
        l.sparse_index_type = a.sparse.indices.componentType;
        if (l.sparse_index_type != k_ubyte && l.sparse_index_type != k_ushort && l.sparse_index_type != k_uint)
            throw GltfError(l.where + ": sparse indices have component type " + component_name(l.sparse_index_type) +
                            " (expected an unsigned integer type)");
        if (a.sparse.indices.byteOffset < 0 || a.sparse.values.byteOffset < 0)
            throw GltfError(l.where + ": negative sparse byteOffset");
        l.sparse_indices = locate(model, a.sparse.indices.bufferView, a.sparse.indices.byteOffset, l.sparse_count,
                                  component_size(l.sparse_index_type), false, l.where + " sparse indices");
        l.sparse_values = locate(model, a.sparse.values.bufferView, a.sparse.values.byteOffset, l.sparse_count,
                                 l.element_bytes(), false, l.where + " sparse values");
        for (size_t k = 0; k < l.sparse_count; ++k) {
            uint32_t target = decode_index(l.sparse_indices.first + k * l.sparse_indices.stride, l.sparse_index_type);
            if (target >= l.count)
                throw GltfError(l.where + ": sparse index " + std::to_string(target) + " is out of range (count " +
                                std::to_string(l.count) + ")");
        }
    }
    return l;
}

bool format_allows(const AttributeFormat& format, int type, bool normalized) {
    switch (type) {
        case k_float: return true;
        case k_ubyte:
        case k_ushort: return normalized ? format.normalized_unsigned : format.integer;
        case k_byte:
        case k_short: return normalized ? format.normalized_signed : format.integer;
        default: return false;  // UNSIGNED_INT is only valid for indices
    }
}

void check_format(const Layout& l, const AttributeFormat& format) {
    if (l.components < format.min_components || l.components > format.max_components) {
        std::string expected = type_name(format.min_components);
        if (format.max_components != format.min_components) expected += " to " + type_name(format.max_components);
        throw GltfError(l.where + ": type is " + type_name(l.components) + ", expected " + expected);
    }
    if (!format_allows(format, l.component_type, l.normalized))
        throw GltfError(l.where + ": component type " + component_name(l.component_type) +
                        (l.normalized ? " (normalized)" : "") + " is not allowed here");
}

void check_index_type(const Layout& l) {
    if (l.components != 1) throw GltfError(l.where + ": indices must be SCALAR, not " + type_name(l.components));
    if (l.component_type != k_ubyte && l.component_type != k_ushort && l.component_type != k_uint)
        throw GltfError(l.where + ": indices have component type " + component_name(l.component_type) +
                        " (expected UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT)");
}

AccessorInfo info(const Layout& l) { return {l.where, l.count, l.components, l.component_type, l.normalized}; }

}  // namespace

ImportContext::ImportContext(Scene& scene_, uint64_t input_bytes) : scene(scene_) {
    input_bytes = std::min<uint64_t>(input_bytes, 1ull << 40);
    m_limit[0] = k_geometry_base + input_bytes * k_geometry_per_input_byte;
    m_limit[1] = k_texture_base + input_bytes * k_texture_per_input_byte;
    m_available = available_memory_bytes();
}

void ImportContext::warn(const std::string& message) {
    if (m_warned.insert(message).second) scene.warnings.push_back(message);
}

void ImportContext::charge(uint64_t bytes, const std::string& what, Budget budget) {
    size_t b = budget == Budget::Geometry ? 0 : 1;
    if (bytes > m_limit[b] || m_used[b] > m_limit[b] - bytes)
        throw GltfError(what + ": needs " + std::to_string(bytes >> 20) + " MiB more memory, beyond the " +
                        std::to_string(m_limit[b] >> 20) + " MiB of " + (b == 0 ? "geometry" : "textures") +
                        " this file's size can justify");
    const uint64_t used = m_used[0] + m_used[1];
    if (bytes > m_available || used > m_available - bytes)
        throw GltfError(what + ": needs " + std::to_string(bytes >> 20) + " MiB more memory, beyond the " +
                        std::to_string(m_available >> 20) + " MiB this process could take when the import started");
    m_used[b] += bytes;
}

void ImportContext::release(uint64_t bytes, Budget budget) {
    size_t b = budget == Budget::Geometry ? 0 : 1;
    m_used[b] -= std::min(bytes, m_used[b]);
}

float decode_component(const uint8_t* p, int component_type, bool normalized) {
    return decode_float(p, component_type, normalized);
}

const char* component_type_name(int component_type) { return component_name(component_type); }

AccessorInfo attribute_accessor_info(const tinygltf::Model& model, int index, const AttributeFormat& format,
                                     const std::string& what) {
    Layout l = declared(model, index, what);
    check_format(l, format);
    return info(l);
}

AccessorInfo index_accessor_info(const tinygltf::Model& model, int index, const std::string& what) {
    Layout l = declared(model, index, what);
    check_index_type(l);
    return info(l);
}

FloatAccessor read_float_accessor(const tinygltf::Model& model, int index, const AttributeFormat& format,
                                  const std::string& what, ImportContext& context) {
    Layout l = validate(model, index, what);
    check_format(l, format);

    FloatAccessor out;
    out.count = l.count;
    out.components = l.components;
    size_t n = l.count * static_cast<size_t>(l.components);
    context.charge(n * sizeof(float), l.where);
    out.values.assign(n, 0.0f);

    auto decode_element = [&](const uint8_t* p, size_t element) {
        float* dst = out.values.data() + element * static_cast<size_t>(l.components);
        for (int c = 0; c < l.components; ++c)
            dst[c] = decode_float(p + static_cast<size_t>(c) * l.component_bytes, l.component_type, l.normalized);
    };
    if (l.run.first) {
        for (size_t i = 0; i < l.count; ++i) decode_element(l.run.first + i * l.run.stride, i);
    }
    for (size_t k = 0; k < l.sparse_count; ++k) {
        uint32_t target = decode_index(l.sparse_indices.first + k * l.sparse_indices.stride, l.sparse_index_type);
        decode_element(l.sparse_values.first + k * l.sparse_values.stride, target);
    }
    return out;
}

std::vector<Transform> read_matrix_accessor(const tinygltf::Model& model, int index, const std::string& what,
                                           ImportContext& context) {
    Layout l = validate(model, index, what, true);
    if (l.component_type != k_float)
        throw GltfError(l.where + ": component type " + component_name(l.component_type) + " (expected FLOAT)");
    context.charge(l.count * sizeof(Transform), l.where);
    std::vector<float> values(l.count * 16, 0.0f);
    if (l.run.first)
        for (size_t i = 0; i < l.count; ++i) std::memcpy(&values[16 * i], l.run.first + i * l.run.stride, 64);
    for (size_t k = 0; k < l.sparse_count; ++k) {
        uint32_t target = decode_index(l.sparse_indices.first + k * l.sparse_indices.stride, l.sparse_index_type);
        std::memcpy(&values[16 * target], l.sparse_values.first + k * l.sparse_values.stride, 64);
    }
    std::vector<Transform> out(l.count);
    for (size_t i = 0; i < l.count; ++i) {
        double m[16];
        for (int k = 0; k < 16; ++k) m[k] = values[16 * i + size_t(k)];
        out[i] = from_column_major(m);  // glTF matrices are column-major; the last row is (0 0 0 1)
    }
    return out;
}

std::vector<uint32_t> read_index_accessor(const tinygltf::Model& model, int index, const std::string& what,
                                          ImportContext& context) {
    Layout l = validate(model, index, what);
    check_index_type(l);

    context.charge(l.count * sizeof(uint32_t), l.where);
    std::vector<uint32_t> out(l.count, 0);
    if (l.run.first) {
        for (size_t i = 0; i < l.count; ++i) out[i] = decode_index(l.run.first + i * l.run.stride, l.component_type);
    }
    for (size_t k = 0; k < l.sparse_count; ++k) {
        uint32_t target = decode_index(l.sparse_indices.first + k * l.sparse_indices.stride, l.sparse_index_type);
        out[target] = decode_index(l.sparse_values.first + k * l.sparse_values.stride, l.component_type);
    }
    return out;
}

std::span<const uint8_t> buffer_view_bytes(const tinygltf::Model& model, int view, const std::string& what) {
    const tinygltf::BufferView& v = checked_view(model, view, what);
    return {model.buffers[v.buffer].data.data() + v.byteOffset, v.byteLength};
}

const tinygltf::Value* json_member(const tinygltf::Value* object, const char* key) {
    // Value::Get asserts on a non-object, so check first.
    if (!object || !object->IsObject() || !object->Has(key)) return nullptr;
    return &object->Get(key);
}

const tinygltf::Value* json_extension(const std::map<std::string, tinygltf::Value>& extensions, const char* name) {
    auto it = extensions.find(name);
    return it != extensions.end() && it->second.IsObject() ? &it->second : nullptr;
}

double json_number(const tinygltf::Value* object, const char* key, double fallback) {
    const tinygltf::Value* v = json_member(object, key);
    if (!v || !v->IsNumber()) return fallback;
    double d = v->GetNumberAsDouble();
    return std::isfinite(d) ? d : fallback;
}

int json_integer(const tinygltf::Value* object, const char* key, int fallback) {
    const tinygltf::Value* v = json_member(object, key);
    if (!v) return fallback;
    double d = v->IsNumber() ? v->GetNumberAsDouble() : NAN;
    if (!(d >= INT_MIN && d <= INT_MAX) || d != std::floor(d)) return INT_MIN;
    return static_cast<int>(d);
}

bool json_numbers(const tinygltf::Value* array, double* out, size_t n) {
    if (!array || !array->IsArray() || array->ArrayLen() != n) return false;
    for (size_t i = 0; i < n; ++i) {
        const tinygltf::Value& v = array->Get(static_cast<int>(i));
        if (!v.IsNumber() || !std::isfinite(v.GetNumberAsDouble())) return false;
    }
    for (size_t i = 0; i < n; ++i) out[i] = array->Get(static_cast<int>(i)).GetNumberAsDouble();
    return true;
}

}  // namespace veach::gltf
