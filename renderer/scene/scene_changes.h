// What a re-pose changed in a loaded scene, so that what a render prepares from it (the BVH, the
// light tables) is updated instead of rebuilt: a snapshot of everything a pose can move, taken
// before pose_scene (and rebase_scene), compared with the scene after.
#pragma once

#include <cstdint>
#include <vector>

#include "scene/scene.h"

namespace veach {

// The parts of a scene that pose_scene and rebase_scene write.
struct ScenePose {
    std::vector<Transform> instances;                // per instance: object_to_world
    std::vector<std::vector<Vec3>> deforming;        // per SceneAnimation::deforming: its mesh's positions
    std::vector<PunctualLight> lights;               // Scene::lights
    SceneMotion motion;                              // Scene::motion: the shutter's steps
    std::vector<Rgb> emission;                       // per animated material (SceneAnimation::material_rest) in use
};

// Indices in increasing order; compared by exact bits (a pose that yields the same floats changed
// nothing).
struct SceneChanges {
    std::vector<uint32_t> moved_instances;  // object_to_world or its motion steps differ
    std::vector<uint32_t> deformed_meshes;  // Scene::meshes whose positions or motion steps differ
    bool lights_changed = false;            // Scene::lights differ, or an animated material's emission
    bool any() const { return !moved_instances.empty() || !deformed_meshes.empty() || lights_changed; }
    // Adds `later` (changes made after these), keeping the lists sorted and unique.
    void merge(const SceneChanges& later);
};

ScenePose capture_pose(const Scene& scene);
SceneChanges changes_since(const ScenePose& before, const Scene& scene);

// The instances a pose can move or deform (1) and those it never touches (0): placed by a node
// that a selected animation channel (translation, rotation, scale) moves, or under one, or
// deforming (skins, morph targets). All 0 for a scene imported without animation.
std::vector<uint8_t> movable_instances(const Scene& scene);

}  // namespace veach
