// glTF `animations`, `skins`, node poses and morph `targets` read into SceneAnimation
// (scene/scene_animation.h): plain arrays, checked here, evaluated by pose_scene. Nothing of
// tinygltf is kept.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "importers/gltf/gltf_accessors.h"
#include "importers/gltf/gltf_animation_pointer.h"
#include "scene/scene_animation.h"

namespace tinygltf {
struct Primitive;
}

namespace veach::gltf {

// Rest poses, parents (the first parent of a node listed twice; a cycle is an error) and morph
// weights (node.weights, else its mesh's weights, else zeros) of every node.
void read_nodes(const tinygltf::Model& model, SceneAnimation& out, ImportContext& context);

// Every skin: joints (checked node indices) and inverse bind matrices (identity when absent).
void read_skins(const tinygltf::Model& model, SceneAnimation& out, ImportContext& context);

// Every animation, and the one `selection` names ("all" or empty: -1, all at once; else a name,
// then an index). A selection the file lacks is a GltfError listing its animations. A channel
// that cannot be evaluated (no node, a matrix node, keys out of order, too few values, a
// pointer to something not evaluated) is skipped with a warning. `pointers` are the file's
// KHR_animation_pointer channels (gltf_animation_pointer.h); `light_count` its
// KHR_lights_punctual lights.
void read_animations(const tinygltf::Model& model, const std::string& selection,
                     const std::vector<PointerChannel>& pointers, size_t light_count, SceneAnimation& out,
                     ImportContext& context);

// The morph targets of a primitive of `vertices` vertices (POSITION, NORMAL, TANGENT deltas;
// sparse accessors as any); null when it has none.
std::shared_ptr<const std::vector<MorphTarget>> read_morph_targets(const tinygltf::Model& model,
                                                                   const tinygltf::Primitive& prim, size_t vertices,
                                                                   const std::string& what, ImportContext& context);

// JOINTS_n / WEIGHTS_n of a skinned primitive into d (influences, joints, weights), each vertex's
// weights normalised to sum 1 (warned once when a file's do not). `joint_count` is the skin's.
void read_skin_influences(const tinygltf::Model& model, const tinygltf::Primitive& prim, size_t vertices,
                          size_t joint_count, const std::string& what, ImportContext& context, DeformingMesh& d);

}  // namespace veach::gltf
