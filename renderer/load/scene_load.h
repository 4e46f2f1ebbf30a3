// The scene load: the one pipeline from a file (or a host's bytes) to a scene ready to render, so
// that every front end renders the same image from the same input. In order: the import (by
// format, importers/), the repairs (scene_repair), the requested environment, the pose at the
// scene's time and its motion across the shutter, a white world for a scene with no light at all
// (after the environment: an explicit one wins), a far-off scene moved to the origin, and the
// identity that checkpoints and part files carry. The C API only parses options into
// SceneLoadOptions and calls this.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "importers/importer.h"
#include "load/environment_options.h"
#include "scene/scene.h"
#include "scene/scene_changes.h"

namespace veach {

// Every option that changes what a load makes of its input.
struct SceneLoadOptions {
    ImportOptions import;
    EnvironmentOptions environment;
    double time = 0;  // seconds: with import.animate, the animation is evaluated there
    // Motion blur: the shutter in seconds relative to `time`; open < close blurs, equal does not.
    double shutter_open = 0, shutter_close = 0;
    bool motion_blur() const { return shutter_close > shutter_open; }
};

// A loaded scene and what identifies it.
struct LoadedScene {
    Scene scene;
    uint64_t file_hash = 0;     // every file the import read, by content (Scene::content_hash)
    uint64_t env_map_hash = 0;  // the environment map's content, hashed once at the load
    // The file, the map and every load option: a checkpoint or part of another file, variant,
    // environment or time is another render's.
    uint64_t identity = 0;
    // Per instance, the posed object_to_world before the rebase and the bounds of its triangles
    // placed by it (Scene::bounds_of): a re-pose recomputes only the instances that moved or
    // whose mesh deforms, so a sequence's frame does not visit every static triangle to rebase.
    std::vector<Transform> posed_transforms;
    std::vector<Bounds3> posed_bounds;
};

// Throw ImportError (bad input: one line naming the file and the fault) for a file, map or
// animation that cannot be loaded, std::invalid_argument for a bad option.
LoadedScene load_scene_file(const std::string& path, const SceneLoadOptions& options);
// A scene held in memory (e.g. a .glb a host produced); `format` is an extension such as "glb",
// relative URIs resolve against `base_dir`.
LoadedScene load_scene_memory(const std::vector<uint8_t>& bytes, const std::string& format,
                              const std::string& base_dir, const SceneLoadOptions& options);

// A loaded scene posed again at options.time (a sequence's next frame; the file is never read
// again): pose, motion, rebase and identity as the load does them. Returns what changed, for
// PreparedSceneCache::note. On an exception the scene may be partly posed.
SceneChanges repose_scene(LoadedScene& loaded, const SceneLoadOptions& options);

}  // namespace veach
