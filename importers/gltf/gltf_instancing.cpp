#include "importers/gltf/gltf_instancing.h"

#include <climits>
#include <cmath>

#include <tiny_gltf.h>

namespace veach::gltf {

namespace {

// The extension's accessor types: TRANSLATION and SCALE VEC3, float or (KHR_mesh_quantization's
// forms) integer and normalized integer; ROTATION VEC4, float or normalized signed byte/short.
const AttributeFormat k_vec3_format{3, 3, true, true, true};
const AttributeFormat k_rotation_format{4, 4, false, true, false};

bool all_finite(const std::vector<float>& values) {
    for (float v : values)
        if (!std::isfinite(v)) return false;
    return true;
}

}  // namespace

std::optional<std::vector<Transform>> read_gpu_instances(const tinygltf::Model& model, int node,
                                                         const std::string& what, ImportContext& context) {
    const tinygltf::Value* ext = json_extension(model.nodes[size_t(node)].extensions, "EXT_mesh_gpu_instancing");
    if (!ext) return std::nullopt;
    const std::string where = what + " EXT_mesh_gpu_instancing";
    const tinygltf::Value* attributes = json_member(ext, "attributes");
    if (!attributes || !attributes->IsObject()) throw GltfError(where + ": no attributes object");
    const char* names[3] = {"TRANSLATION", "ROTATION", "SCALE"};
    FloatAccessor read[3];
    bool present[3] = {false, false, false};
    size_t count = 0;
    int first = -1;
    for (int k = 0; k < 3; ++k) {
        const int index = json_integer(attributes, names[k], -1);
        if (index == -1 && !json_member(attributes, names[k])) continue;
        if (index < 0 || size_t(index) >= model.accessors.size())
            throw GltfError(where + " " + names[k] + ": " +
                            (index == INT_MIN ? std::string("malformed accessor index")
                                              : "accessor " + std::to_string(index) + " does not exist"));
        read[k] = read_float_accessor(model, index, k == 1 ? k_rotation_format : k_vec3_format,
                                      where + " " + names[k], context);
        if (!all_finite(read[k].values)) throw GltfError(where + " " + names[k] + ": values are not finite");
        if (first >= 0 && read[k].count != count)
            throw GltfError(where + ": " + names[k] + " has " + std::to_string(read[k].count) + " elements but " +
                            names[first] + " has " + std::to_string(count) + " (they must agree)");
        count = read[k].count;
        if (first < 0) first = k;
        present[k] = true;
    }
    if (first < 0) throw GltfError(where + ": none of TRANSLATION, ROTATION, SCALE");
    context.charge(count * sizeof(Transform), where);
    std::vector<Transform> out(count);
    for (size_t i = 0; i < count; ++i) {
        // Composed as a node's TRS is (translation, then rotation, then scale), so that an
        // instance and a child node with the same values get the same transform, bit for bit.
        Transform t;
        if (present[0]) {
            const float* v = &read[0].values[3 * i];
            t = translation(Vec3(v[0], v[1], v[2]));
        }
        if (present[1]) {
            const float* q = &read[1].values[4 * i];
            t = t * rotation_quaternion(q[0], q[1], q[2], q[3]);
        }
        if (present[2]) {
            const float* s = &read[2].values[3 * i];
            t = t * scaling(Vec3(s[0], s[1], s[2]));
        }
        out[i] = t;
    }
    return out;
}

}  // namespace veach::gltf
