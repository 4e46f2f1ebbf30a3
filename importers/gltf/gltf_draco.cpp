#include "importers/gltf/gltf_draco.h"

#include "importers/gltf/gltf_json_chunk.h"

#include <algorithm>
#include <climits>
#include <cstring>
#include <map>
#include <string_view>

#include <nlohmann/json.hpp>

#include <draco/compression/decode.h>
#include <draco/compression/mesh/mesh_edgebreaker_decoder.h>
#include <draco/compression/mesh/mesh_sequential_decoder.h>
#include <draco/core/decoder_buffer.h>
#include <draco/mesh/mesh.h>
#include <tiny_gltf.h>

namespace veach::gltf {
namespace {

constexpr const char* k_extension = "KHR_draco_mesh_compression";

// Draco's accessors trust the decoded storage; check it once so every later read stays inside:
// each point maps to an entry below size(), and every entry lies inside the attribute's buffer.
void check_storage(const draco::PointAttribute& att, size_t points, const std::string& where) {
    int components = att.num_components();
    int64_t element = int64_t(draco::DataTypeLength(att.data_type())) * components;
    if (components < 1 || components > 4 || element <= 0)
        throw GltfError(where + ": the Draco stream stores " + std::to_string(components) +
                        " components of data type " + std::to_string(int(att.data_type())));
    const draco::DataBuffer* buffer = att.buffer();
    uint64_t entries = att.size();
    if (points == 0) return;
    if (!buffer || entries == 0) throw GltfError(where + ": the Draco stream holds no values for it");
    if (!att.is_mapping_identity() && att.indices_map_size() < points)
        throw GltfError(where + ": the Draco stream maps " + std::to_string(att.indices_map_size()) + " of " +
                        std::to_string(points) + " points");
    int64_t stride = att.byte_stride(), offset = att.byte_offset();
    uint64_t size = buffer->data_size();
    bool fits = offset >= 0 && stride >= element && uint64_t(offset) <= size && uint64_t(element) <= size - offset &&
                entries - 1 <= (size - offset - element) / uint64_t(stride);
    if (!fits) throw GltfError(where + ": the Draco stream's values run past their storage");
    for (size_t p = 0; p < points; ++p) {
        uint32_t entry = att.mapped_index(draco::PointIndex(uint32_t(p))).value();
        if (entry >= entries)
            throw GltfError(where + ": point " + std::to_string(p) + " maps to value " + std::to_string(entry) +
                            " of " + std::to_string(entries));
    }
}

// One decoded value in the accessor's component type (the stream's own type for integers), then
// decoded by the same rule as uncompressed data (decode_component), so normalized means what the
// accessor says.
template <typename T>
bool fetch(const draco::PointAttribute& att, draco::AttributeValueIndex entry, int components, int component_type,
           bool normalized, float* out) {
    T values[4] = {};
    if (!att.ConvertValue<T>(entry, int8_t(components), values)) return false;
    for (int c = 0; c < components; ++c) {
        uint8_t bytes[sizeof(T)];
        std::memcpy(bytes, &values[c], sizeof(T));
        out[c] = decode_component(bytes, component_type, normalized);
    }
    return true;
}

bool fetch_as(const draco::PointAttribute& att, draco::AttributeValueIndex entry, int components, int component_type,
              bool normalized, float* out) {
    switch (component_type) {
        case TINYGLTF_COMPONENT_TYPE_FLOAT:
            return fetch<float>(att, entry, components, component_type, normalized, out);
        case TINYGLTF_COMPONENT_TYPE_BYTE:
            return fetch<int8_t>(att, entry, components, component_type, normalized, out);
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
            return fetch<uint8_t>(att, entry, components, component_type, normalized, out);
        case TINYGLTF_COMPONENT_TYPE_SHORT:
            return fetch<int16_t>(att, entry, components, component_type, normalized, out);
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
            return fetch<uint16_t>(att, entry, components, component_type, normalized, out);
        default: return false;  // attribute_accessor_info admits no other type
    }
}

draco::DataType draco_type(int component_type) {
    switch (component_type) {
        case TINYGLTF_COMPONENT_TYPE_BYTE: return draco::DT_INT8;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return draco::DT_UINT8;
        case TINYGLTF_COMPONENT_TYPE_SHORT: return draco::DT_INT16;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return draco::DT_UINT16;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: return draco::DT_UINT32;
        case TINYGLTF_COMPONENT_TYPE_FLOAT: return draco::DT_FLOAT32;
        default: return draco::DT_INVALID;
    }
}

std::string draco_type_name(draco::DataType type) {
    switch (type) {
        case draco::DT_INT8: return "INT8";
        case draco::DT_UINT8: return "UINT8";
        case draco::DT_INT16: return "INT16";
        case draco::DT_UINT16: return "UINT16";
        case draco::DT_INT32: return "INT32";
        case draco::DT_UINT32: return "UINT32";
        case draco::DT_INT64: return "INT64";
        case draco::DT_UINT64: return "UINT64";
        case draco::DT_FLOAT32: return "FLOAT32";
        case draco::DT_FLOAT64: return "FLOAT64";
        case draco::DT_BOOL: return "BOOL";
        default: return "data type " + std::to_string(int(type));
    }
}

// Bytes that decoding an attribute of `components` values of `type` a point costs at its peak:
// the final values, the portable (quantized or integer) copy Draco decodes them from, and the
// prediction scheme's corrections, each 32 bits a component.
uint64_t decoded_bytes_per_point(int components, draco::DataType type) {
    return uint64_t(components) * (uint64_t(std::max<int64_t>(draco::DataTypeLength(type), 1)) + 8);
}

// Draco decodes every attribute of a stream, those the extension does not name included, and
// sizes them from the stream alone: a small stream can declare millions of points with a
// 127-component attribute. This decoder stops between the attribute descriptions and their
// values, when the point count and every attribute's shape are known, and charges what the values
// will take before any is allocated. The budget's error cannot be thrown through Draco's frames;
// it is kept and rethrown once Draco has unwound.
template <class MeshDecoderBase>
class BudgetedDecoder : public MeshDecoderBase {
public:
    BudgetedDecoder(ImportContext& context, const std::map<std::string, uint32_t>& ids, const std::string& where)
        : m_context(context), m_ids(ids), m_where(where) {}

    std::optional<GltfError> refusal;           // set when the budget refused the values
    std::unique_ptr<ScopedCharge> values_charge;  // what the decoded values hold until released

protected:
    bool DecodeAllAttributes() override {
        const draco::PointCloud& cloud = *this->point_cloud();
        uint64_t points = uint64_t(cloud.num_points()), bytes = 0;
        std::string largest;
        uint64_t largest_bytes = 0;
        for (int32_t a = 0; a < cloud.num_attributes(); ++a) {
            const draco::PointAttribute& att = *cloud.attribute(a);
            uint64_t per_point = decoded_bytes_per_point(att.num_components(), att.data_type());
            uint64_t att_bytes = per_point > UINT64_MAX / std::max<uint64_t>(points, 1) ? UINT64_MAX : per_point * points;
            bytes = att_bytes > UINT64_MAX - bytes ? UINT64_MAX : bytes + att_bytes;
            if (att_bytes >= largest_bytes) {
                largest_bytes = att_bytes;
                largest = attribute_name(att.unique_id()) + " (" + std::to_string(int(att.num_components())) +
                          " components x " + std::to_string(points) + " points)";
            }
        }
        try {
            values_charge = std::make_unique<ScopedCharge>(m_context, bytes, m_where + " " + largest, Budget::Geometry);
        } catch (const GltfError& e) {
            refusal = e;
            return false;
        }
        return MeshDecoderBase::DecodeAllAttributes();
    }

private:
    std::string attribute_name(uint32_t id) const {
        for (const auto& [name, mapped] : m_ids)
            if (mapped == id) return "attribute " + name;
        return "Draco attribute " + std::to_string(id) + " that no glTF attribute names";
    }

    ImportContext& m_context;
    const std::map<std::string, uint32_t>& m_ids;
    const std::string& m_where;
};

template <class MeshDecoderBase>
draco::Status decode_budgeted(draco::DecoderBuffer& buffer, draco::Mesh& mesh, ImportContext& context,
                              const std::map<std::string, uint32_t>& ids, const std::string& where,
                              std::unique_ptr<ScopedCharge>& charge) {
    BudgetedDecoder<MeshDecoderBase> decoder(context, ids, where);
    draco::DecoderOptions options;
    draco::Status status = decoder.Decode(options, &buffer, &mesh);
    if (decoder.refusal) throw *decoder.refusal;
    charge = std::move(decoder.values_charge);
    return status;
}

}  // namespace

std::optional<std::vector<uint8_t>> patch_draco_index_accessors(std::span<const uint8_t> file, bool binary,
                                                                std::set<int>& patched) {
    std::string_view text = json_chunk(file, binary);
    if (text.find(k_extension) == std::string_view::npos) return std::nullopt;
    nlohmann::json doc = nlohmann::json::parse(text, nullptr, false);
    if (doc.is_discarded() || !doc.is_object()) return std::nullopt;

    auto* meshes = doc.contains("meshes") ? &doc["meshes"] : nullptr;
    auto* accessors = doc.contains("accessors") ? &doc["accessors"] : nullptr;
    if (!meshes || !meshes->is_array() || !accessors || !accessors->is_array()) return std::nullopt;
    int64_t view_count = doc.contains("bufferViews") && doc["bufferViews"].is_array() ? doc["bufferViews"].size() : 0;
    for (auto& mesh : *meshes) {
        if (!mesh.is_object() || !mesh.contains("primitives") || !mesh["primitives"].is_array()) continue;
        for (auto& primitive : mesh["primitives"]) {
            if (!primitive.is_object() || !primitive.contains("indices") || !primitive.contains("extensions")) continue;
            const auto& extensions = primitive["extensions"];
            if (!extensions.is_object() || !extensions.contains(k_extension)) continue;
            const auto& ext = extensions[k_extension];
            const auto& indices = primitive["indices"];
            if (!ext.is_object() || !ext.contains("bufferView") || !ext["bufferView"].is_number_integer() ||
                !indices.is_number_integer())
                continue;  // malformed: left for tinygltf and DracoPrimitive::decode to report
            auto index = indices.get<int64_t>();
            if (index < 0 || size_t(index) >= accessors->size()) continue;
            auto& accessor = (*accessors)[size_t(index)];
            if (!accessor.is_object() || accessor.contains("bufferView")) continue;
            // Any existing view will do; the extension's own, when it exists, or else view 0, so
            // that a bad one is reported by DracoPrimitive::decode, by name.
            auto view = ext["bufferView"].get<int64_t>();
            if (view < 0 || view >= view_count) view = 0;
            if (view >= view_count) continue;
            accessor["bufferView"] = view;
            patched.insert(int(index));
        }
    }
    if (patched.empty()) return std::nullopt;

    // Invalid UTF-8 would have failed the parse; replace keeps dump from throwing regardless.
    return with_json_chunk(file, binary, doc.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace));
}

struct DracoPrimitive::Impl {
    std::unique_ptr<ScopedCharge> values_charge;  // released after the mesh (declared first)
    std::unique_ptr<draco::Mesh> mesh;
    std::map<std::string, uint32_t> ids;  // glTF attribute name -> Draco unique id
    std::string where;                    // "mesh 'a' primitive 0 KHR_draco_mesh_compression"
};

DracoPrimitive::DracoPrimitive(std::unique_ptr<Impl> impl) : m(std::move(impl)) {}
DracoPrimitive::~DracoPrimitive() = default;

std::unique_ptr<DracoPrimitive> DracoPrimitive::decode(const tinygltf::Model& model,
                                                       const tinygltf::Primitive& primitive, const std::string& what,
                                                       ImportContext& context) {
    auto found = primitive.extensions.find(k_extension);
    if (found == primitive.extensions.end()) return nullptr;
    auto impl = std::make_unique<Impl>();
    impl->where = what + " " + k_extension;
    const tinygltf::Value* ext = found->second.IsObject() ? &found->second : nullptr;
    if (!ext) throw GltfError(impl->where + ": not a JSON object");

    const tinygltf::Value* attributes = json_member(ext, "attributes");
    if (!attributes || !attributes->IsObject()) throw GltfError(impl->where + ": no 'attributes' object");
    for (const std::string& name : attributes->Keys()) {
        int id = json_integer(attributes, name.c_str(), INT_MIN);
        if (id < 0) throw GltfError(impl->where + ": attribute " + name + " has no valid Draco id");
        impl->ids[name] = uint32_t(id);
    }
    int view = json_integer(ext, "bufferView", INT_MIN);
    std::span<const uint8_t> bytes = buffer_view_bytes(model, view, impl->where);

    draco::DecoderBuffer buffer;
    buffer.Init(reinterpret_cast<const char*>(bytes.data()), bytes.size());
    // What draco::Decoder::DecodeMeshFromBuffer does, with the budgeted decoder in its place.
    draco::DracoHeader header{};
    draco::DecoderBuffer peek(buffer);
    draco::Status status = draco::PointCloudDecoder::DecodeHeader(&peek, &header);
    if (status.ok() && header.encoder_type != draco::TRIANGULAR_MESH)
        status = draco::Status(draco::Status::DRACO_ERROR, "not a triangle mesh");
    impl->mesh = std::make_unique<draco::Mesh>();
    if (status.ok()) {
        if (header.encoder_method == draco::MESH_EDGEBREAKER_ENCODING)
            status = decode_budgeted<draco::MeshEdgebreakerDecoder>(buffer, *impl->mesh, context, impl->ids,
                                                                    impl->where, impl->values_charge);
        else if (header.encoder_method == draco::MESH_SEQUENTIAL_ENCODING)
            status = decode_budgeted<draco::MeshSequentialDecoder>(buffer, *impl->mesh, context, impl->ids,
                                                                   impl->where, impl->values_charge);
        else
            status = draco::Status(draco::Status::DRACO_ERROR,
                                   "unknown encoder method " + std::to_string(int(header.encoder_method)));
    }
    if (!status.ok())
        throw GltfError(impl->where + ": cannot decode the Draco stream in bufferView " + std::to_string(view) + " (" +
                        status.error_msg_string() + ")");

    size_t points = impl->mesh->num_points();
    for (const auto& [name, id] : impl->ids) {
        const draco::PointAttribute* att = impl->mesh->GetAttributeByUniqueId(id);
        if (!att)
            throw GltfError(impl->where + ": attribute " + name + " names Draco id " + std::to_string(id) +
                            ", which the stream does not have");
        check_storage(*att, points, impl->where + " " + name);
    }
    for (uint32_t f = 0; f < impl->mesh->num_faces(); ++f) {
        const draco::Mesh::Face& face = impl->mesh->face(draco::FaceIndex(f));
        for (int k = 0; k < 3; ++k)
            if (face[k].value() >= points)
                throw GltfError(impl->where + ": face " + std::to_string(f) + " uses point " +
                                std::to_string(face[k].value()) + " of " + std::to_string(points));
    }
    return std::unique_ptr<DracoPrimitive>(new DracoPrimitive(std::move(impl)));
}

bool DracoPrimitive::has(const std::string& name) const { return m->ids.count(name) != 0; }

size_t DracoPrimitive::points() const { return m->mesh->num_points(); }

FloatAccessor DracoPrimitive::read(const tinygltf::Model& model, int accessor, const std::string& name,
                                   const AttributeFormat& format, const std::string& what,
                                   ImportContext& context) const {
    AccessorInfo info = attribute_accessor_info(model, accessor, format, what + " " + name);
    const draco::PointAttribute& att = *m->mesh->GetAttributeByUniqueId(m->ids.at(name));
    size_t points = this->points();
    if (info.count != points)
        throw GltfError(info.where + ": count " + std::to_string(info.count) + ", but the Draco stream decodes " +
                        std::to_string(points) + " points");
    if (att.num_components() != info.components)
        throw GltfError(info.where + ": " + std::to_string(info.components) + " components, but the Draco stream has " +
                        std::to_string(att.num_components()));
    // An integer accessor declares the integers themselves (KHR_mesh_quantization's types), so
    // the stream must hold that type; a FLOAT accessor takes whatever Draco decodes to floats
    // (dequantized positions, normals and texcoords are float32).
    if (info.component_type != TINYGLTF_COMPONENT_TYPE_FLOAT && att.data_type() != draco_type(info.component_type))
        throw GltfError(info.where + ": componentType " + component_type_name(info.component_type) +
                        ", but the Draco stream stores " + draco_type_name(att.data_type()));

    FloatAccessor out;
    out.count = points;
    out.components = info.components;
    context.charge(uint64_t(points) * info.components * sizeof(float), info.where);
    out.values.resize(points * size_t(info.components));
    for (size_t p = 0; p < points; ++p) {
        draco::AttributeValueIndex entry = att.mapped_index(draco::PointIndex(uint32_t(p)));
        if (!fetch_as(att, entry, info.components, info.component_type, info.normalized,
                      &out.values[p * size_t(info.components)]))
            throw GltfError(info.where + ": Draco value " + std::to_string(entry.value()) + " does not fit " +
                            component_type_name(info.component_type));
    }
    return out;
}

std::vector<uint32_t> DracoPrimitive::triangles(const tinygltf::Model& model, int indices_accessor, bool check_count,
                                                const std::string& what, ImportContext& context) const {
    size_t faces = m->mesh->num_faces();
    uint64_t largest = 0;
    if (indices_accessor != -1) {
        AccessorInfo info = index_accessor_info(model, indices_accessor, what + " indices");
        if (check_count && info.count != 3 * faces)
            throw GltfError(info.where + ": count " + std::to_string(info.count) + ", but the Draco stream decodes " +
                            std::to_string(faces) + " triangles (" + std::to_string(3 * faces) + " indices)");
        largest = info.component_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE    ? 0xffu
                  : info.component_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ? 0xffffu
                                                                                  : 0xffffffffu;
        // An index the declared type cannot hold would not survive as uncompressed data either.
        if (points() > 0 && points() - 1 > largest)
            for (uint32_t f = 0; f < faces; ++f)
                for (int k = 0; k < 3; ++k)
                    if (m->mesh->face(draco::FaceIndex(f))[k].value() > largest)
                        throw GltfError(info.where + ": Draco index " +
                                        std::to_string(m->mesh->face(draco::FaceIndex(f))[k].value()) +
                                        " does not fit " + component_type_name(info.component_type));
    }
    context.charge(uint64_t(faces) * 3 * sizeof(uint32_t), m->where);
    std::vector<uint32_t> out(3 * faces);
    for (uint32_t f = 0; f < faces; ++f) {
        const draco::Mesh::Face& face = m->mesh->face(draco::FaceIndex(f));
        for (int k = 0; k < 3; ++k) out[3 * size_t(f) + k] = face[k].value();
    }
    return out;
}

}  // namespace veach::gltf
