// EXT_mesh_gpu_instancing: a node's TRANSLATION / ROTATION / SCALE attribute accessors read into
// one local transform per instance (T * R * S, in the node's space, before the node's own
// transform), which the importer turns into Scene instances sharing the node's mesh.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "importers/gltf/gltf_accessors.h"

namespace veach::gltf {

// The instance transforms of node `node`, or nothing when it does not carry the extension. The
// accessors are checked as any attribute (type, component type, bounds), must agree on their
// count and hold finite values; a fault is a GltfError naming the node and the accessor.
std::optional<std::vector<Transform>> read_gpu_instances(const tinygltf::Model& model, int node,
                                                         const std::string& what, ImportContext& context);

}  // namespace veach::gltf
