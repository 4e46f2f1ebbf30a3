#include "load/scene_load.h"

#include <cstring>
#include <stdexcept>
#include <utility>

#include "core/content_hash.h"
#include "options/option_table.h"
#include "scene/mesh_corners.h"
#include "scene/scene_animation.h"
#include "scene/scene_motion.h"
#include "scene/scene_repair.h"

namespace veach {
namespace {

// The environment map's content, never its path: a checkpoint resumes with the same map reached
// through another folder.
uint64_t environment_map_hash(const EnvironmentOptions& env) {
    uint64_t map = k_fnv_offset;
    if (!env.map_path.empty() && !hash_file_content(env.map_path, &map))
        throw ImportError(env.map_path + ": cannot read the environment map");
    return map;
}

// Every identity row of the options table (options/option_table.h) by exact bytes, after the
// content of what was read (core/content_hash.h); the map's path is not one, its content is.
uint64_t scene_identity(const SceneLoadOptions& options, uint64_t file_hash, uint64_t env_map_hash) {
    SceneLoadOptions copy = options;
    OptionTargets targets{&copy, nullptr, nullptr, nullptr};
    HashKey key("veach-scene-v3");
    key.field("content", file_hash).field("env_map", !options.environment.map_path.empty());
    hash_identity_options(key, OptionObject::Scene, targets);
    key.field("env_map_content", env_map_hash);
    return key.value();
}

// What changes with the time: the pose, the motion across the shutter, the rebase that follows
// the posed geometry.
void pose_at_time(Scene& scene, const SceneLoadOptions& options) {
    pose_scene(scene, options.time);  // a scene imported without animation stays as it is
    capture_motion(scene, options.time, options.shutter_open, options.shutter_close);
}

bool same_transform(const Transform& a, const Transform& b) { return std::memcmp(a.m, b.m, sizeof(a.m)) == 0; }

// The posed scene's bounds before the rebase, exactly Scene::bounds(): each instance's bounds are
// kept with the transform they were computed for, and recomputed when that transform's bits
// differ or the instance's mesh deforms (the pose rewrites its vertices).
Bounds3 posed_bounds(LoadedScene& loaded) {
    const Scene& scene = loaded.scene;
    const size_t n = scene.instances.size();
    std::vector<uint8_t> deforms(scene.meshes.size(), 0);
    for (const DeformingMesh& d : scene.animation.deforming) deforms[d.mesh] = 1;
    MeshCorners corners(scene);
    const bool known = loaded.posed_transforms.size() == n && loaded.posed_bounds.size() == n;
    loaded.posed_transforms.resize(n);
    loaded.posed_bounds.resize(n);
    Bounds3 b;
    for (size_t i = 0; i < n; ++i) {
        const Instance& inst = scene.instances[i];
        if (!known || deforms[inst.mesh] || !same_transform(inst.object_to_world, loaded.posed_transforms[i])) {
            loaded.posed_transforms[i] = inst.object_to_world;
            loaded.posed_bounds[i] = corners.bounds_of(inst);
        }
        b.extend(loaded.posed_bounds[i]);
    }
    return b;
}

LoadedScene finish_load(Scene&& imported, const SceneLoadOptions& options) {
    LoadedScene loaded;
    // The bytes of every file the import read, never the path: a checkpoint or part resumes or
    // merges the same content reached through another folder or mount.
    loaded.file_hash = imported.content_hash;
    // Repaired once, before anything is built from it or posed (the rest shapes deform).
    repair_scene(imported);
    try {
        apply_environment(options.environment, &imported);
    } catch (const std::invalid_argument& e) {
        throw ImportError(e.what());  // "FILE: fault": an unreadable map
    }
    pose_at_time(imported, options);
    light_unlit_scene(imported);
    loaded.scene = std::move(imported);
    rebase_scene(loaded.scene, posed_bounds(loaded));
    loaded.env_map_hash = environment_map_hash(options.environment);
    loaded.identity = scene_identity(options, loaded.file_hash, loaded.env_map_hash);
    return loaded;
}

}  // namespace

LoadedScene load_scene_file(const std::string& path, const SceneLoadOptions& options) {
    return finish_load(import_scene(path, options.import), options);
}

LoadedScene load_scene_memory(const std::vector<uint8_t>& bytes, const std::string& format,
                              const std::string& base_dir, const SceneLoadOptions& options) {
    return finish_load(import_scene_from_memory(bytes, format, base_dir, options.import), options);
}

SceneChanges repose_scene(LoadedScene& loaded, const SceneLoadOptions& options) {
    const ScenePose before = capture_pose(loaded.scene);
    pose_at_time(loaded.scene, options);
    rebase_scene(loaded.scene, posed_bounds(loaded));
    loaded.identity = scene_identity(options, loaded.file_hash, loaded.env_map_hash);
    return changes_since(before, loaded.scene);
}

}  // namespace veach
