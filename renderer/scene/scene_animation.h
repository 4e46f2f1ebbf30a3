// Animation as plain data (node hierarchy, keyframed channels, skins, morph targets) and the one
// evaluator that poses a Scene at a time t. Importers fill SceneAnimation (the glTF importer
// does, from `animations`, `skins` and mesh `targets`) and keep no file-format type in it; front
// ends call pose_scene once per frame on the loaded scene, so a sequence reads its file once.
//
// Why the evaluator lives here and not in importers/: the scene is re-posed after the import is
// over (tinygltf's model is gone by then), after scene_repair, and by front ends that know
// nothing of glTF; the data it needs is a handful of arrays any format can fill.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/math.h"
#include "core/rgb.h"

namespace veach {

struct Scene;
struct PunctualLight;

// A node's local transform: a matrix (never animated, as glTF says), or translation, rotation
// (unit quaternion x, y, z, w) and scale, composed T * R * S.
struct NodePose {
    Vec3 translation{0, 0, 0};
    std::array<float, 4> rotation{0, 0, 0, 1};
    Vec3 scale{1, 1, 1};
    bool has_matrix = false;
    Transform matrix;
    Transform local() const;
};

enum class Interpolation : uint8_t { Linear, Step, CubicSpline };
enum class AnimatedPath : uint8_t { Translation, Rotation, Scale, Weights };

// Keyframes: `times` strictly increasing (seconds); `values` holds `components` floats per key,
// and for CubicSpline three elements per key (in-tangent, value, out-tangent), as glTF stores them.
struct AnimationSampler {
    std::vector<float> times;
    std::vector<float> values;
    int components = 0;
    Interpolation interpolation = Interpolation::Linear;
};

// Evaluates `s` at `t` into out[0..components): times before the first key take the first
// value, after the last the last one; rotations (path Rotation) are interpolated on the shorter
// arc and normalised.
void sample_animation(const AnimationSampler& s, double t, bool rotation, float* out);

struct AnimationChannel {
    int node = 0;
    AnimatedPath path = AnimatedPath::Translation;
    int sampler = 0;
};

// KHR_animation_pointer: a property other than a node's transform or weights, by the file's
// index of what holds it (a material, a KHR_lights_punctual light, a camera). The sampler's
// components are the property's (4 for a base colour, 3 for colours, 1 for scalars).
enum class AnimatedProperty : uint8_t {
    BaseColor,         // /materials/M/pbrMetallicRoughness/baseColorFactor (RGBA)
    Metallic,          // .../metallicFactor
    Roughness,         // .../roughnessFactor
    EmissiveFactor,    // /materials/M/emissiveFactor (RGB)
    EmissiveStrength,  // /materials/M/extensions/KHR_materials_emissive_strength/emissiveStrength
    AlphaCutoff,       // /materials/M/alphaCutoff
    LightColor,        // /extensions/KHR_lights_punctual/lights/L/color (RGB)
    LightIntensity,    // .../intensity
    SpotInnerCone,     // .../spot/innerConeAngle
    SpotOuterCone,     // .../spot/outerConeAngle
    CameraYfov,        // /cameras/C/perspective/yfov
    CameraXmag,        // /cameras/C/orthographic/xmag
    CameraYmag,        // /cameras/C/orthographic/ymag
};
int animated_property_components(AnimatedProperty p);

struct PropertyChannel {
    AnimatedProperty property = AnimatedProperty::BaseColor;
    int target = 0;  // the file's material, light or camera index
    int sampler = 0;
};

struct Animation {
    std::string name;
    std::vector<AnimationSampler> samplers;
    std::vector<AnimationChannel> channels;
    std::vector<PropertyChannel> properties;
};

// What property channels start from, by the file's index: the factors as the file gives them
// (an emission is emissiveFactor x emissiveStrength, so both are kept), and where the material
// ended up in Scene::materials (-1: no primitive uses it).
struct MaterialRest {
    int32_t material = -1;
    Rgb base_color{1, 1, 1};
    float base_alpha = 1, metallic = 1, roughness = 1;
    Rgb emissive_factor{0, 0, 0};
    float emissive_strength = 1;
    float alpha_cutoff = 0.5f;
    bool unlit = false;  // KHR_materials_unlit: the base colour is the emission
};

struct LightRest {
    Rgb color{1, 1, 1};
    float intensity = 1;                  // the file's (candela, lux)
    float inner_cone = 0, outer_cone = 0; // spot: radians
};

struct CameraRest {
    int source = -1;  // the file's camera placed as this Scene::cameras entry
    float yfov = 0, xmag = 0, ymag = 0;
};

struct SkinData {
    std::vector<int> joints;              // node indices
    std::vector<Transform> inverse_bind;  // one per joint (identity when the file has none)
};

// One morph target's per-vertex deltas; an empty array means no delta for that attribute.
struct MorphTarget {
    std::vector<Vec3> positions, normals, tangents;
    std::vector<Vec2> uv0, uv1;  // TEXCOORD_0, TEXCOORD_1
    std::vector<Rgba> colors;    // COLOR_0 (held to [0, 1] after the deltas, as the import holds it)
};

// A mesh that changes shape: morph targets and/or a skin. Each node placing a deforming mesh
// gets its own Scene::Mesh (the weights are the node's, the skin is the node's).
struct DeformingMesh {
    uint32_t mesh = 0;      // Scene::meshes
    uint32_t instance = 0;  // Scene::instances: world-space vertices when skinned (identity transform)
    int placement = 0;      // SceneAnimation::placements: whose weights and transform
    int skin = -1;          // SceneAnimation::skins, -1: rigid
    std::shared_ptr<const std::vector<MorphTarget>> targets;  // shared by the nodes placing it
    // Influences per vertex, `influences` each (4 per JOINTS_n/WEIGHTS_n set): indices into the
    // skin's joints and weights, normalised to sum to 1 where they did not.
    int influences = 0;
    std::vector<uint16_t> joints;
    std::vector<float> weights;
    // The shape before any deformation, taken from the Scene the first time it is posed (after
    // scene_repair, so repaired normals are what gets deformed).
    bool captured = false;
    std::vector<Vec3> rest_positions, rest_normals, rest_tangents;
    std::vector<Vec2> rest_uv0, rest_uv1;  // only when a target moves them
    std::vector<Rgba> rest_colors;
};

// A light in its node's space: `local` is the light as placed by an identity transform (at the
// origin, shining along -Z, area axes unscaled); Area radiance = area_power / (world area).
struct LocalLight {
    std::shared_ptr<const PunctualLight> local;
    Rgb area_power;
    int source = -1;  // the file's KHR_lights_punctual index (SceneAnimation::light_rest)
};

// One visit of a node by the scene's traversal (a node reached twice is placed twice), in the
// order of the traversal: a parent comes before its children.
struct NodePlacement {
    int node = 0;
    int parent = -1;                  // placement index
    std::vector<uint32_t> instances;  // rigid Scene::instances placed by this node
    int camera = -1;                  // Scene::cameras
    int light = -1;                   // SceneAnimation::lights
    // EXT_mesh_gpu_instancing: per entry of `instances`, the instance's transform in the node's
    // space (placed at world x offset); empty when the node places its mesh once.
    std::vector<Transform> instance_offsets;
};

struct SceneAnimation {
    bool enabled = false;  // filled by an importer asked to (ImportOptions::animate)
    std::vector<NodePose> rest;                      // per node
    std::vector<int> parents;                        // per node, -1 for a root
    std::vector<std::vector<float>> rest_weights;    // per node: node.weights, else its mesh's
    std::vector<NodePlacement> placements;
    std::vector<LocalLight> lights;  // Scene::lights is rebuilt from these, in this order
    std::vector<DeformingMesh> deforming;
    std::vector<SkinData> skins;
    std::vector<Animation> animations;
    // Rest values of what PropertyChannels animate, by the file's index (empty without any).
    std::vector<MaterialRest> material_rest;
    std::vector<LightRest> light_rest;
    std::vector<CameraRest> camera_rest;  // per Scene::cameras entry
    int selected = -1;  // the animation played, -1: all of them at once
    std::vector<std::string> warnings;  // found while posing, said once by the front end
};

// Poses `scene` at time `seconds` from scene.animation (nothing when it is not enabled): node
// transforms from the selected animations' channels (rest values elsewhere), instances, cameras
// and lights placed by their nodes, morph targets and skins applied. Can be called again for
// another time; the scene's rest shape is kept in scene.animation.
void pose_scene(Scene& scene, double seconds);

}  // namespace veach
