// What a render prepares from a scene (the BVH, the light tables, instance inverses, thin walls),
// kept across the renders of one loaded scene: a sequence re-poses the scene and only what moved
// is updated (docs/ARCHITECTURE.md "Animation").
#pragma once

#include <memory>
#include <mutex>
#include <vector>

#include "accel/embree_accel.h"
#include "lights/light_set.h"
#include "scene/scene.h"
#include "scene/scene_changes.h"

namespace veach {

class MeshCorners;

class PreparedScene {
public:
    // Builds everything from `scene` as it stands; `scene` must outlive this.
    explicit PreparedScene(const Scene& scene);
    PreparedScene(const PreparedScene&) = delete;
    PreparedScene& operator=(const PreparedScene&) = delete;

    // Follows the scene after a re-pose that made `changes`: the accel's transforms, vertices
    // and refits (Accel::update), the inverses of moved instances, thin walls of deformed meshes,
    // and the light tables only when a light or an emitter moved or the scene's bounds (which
    // size the lights at infinity) changed. False when the accel cannot follow (geometry baked
    // into world space moved): build a new PreparedScene then. Never while a render uses it.
    bool update(const SceneChanges& changes);

    const Scene& scene() const { return m_scene; }
    const Accel& accel() const { return *m_accel; }
    const LightSet& lights() const { return *m_lights; }
    // Scene::bounds() when built or last updated, widened by the path through the shutter of
    // whatever moves during it (motion blur).
    const Bounds3& bounds() const { return m_bounds; }
    const Transform& world_to_object(uint32_t instance) const { return m_world_to_object[instance]; }
    bool thin_walled(uint32_t mesh) const { return m_thin_walled[mesh] != 0; }
    // How often the light tables were built (1 after construction): for tests and stats.
    int light_builds() const { return m_light_builds; }

private:
    void set_thin_walled(size_t mesh);
    Bounds3 instance_bounds(size_t instance, MeshCorners& corners) const;

    const Scene& m_scene;
    // Per instance, then their union: what Scene::bounds() computes (min and max are exact in
    // any grouping), kept so that a frame recomputes only the instances that moved.
    std::vector<Bounds3> m_instance_bounds;
    Bounds3 m_bounds;
    std::unique_ptr<Accel> m_accel;
    std::unique_ptr<LightSet> m_lights;
    std::vector<Transform> m_world_to_object;
    std::vector<uint8_t> m_thin_walled;  // per mesh
    int m_light_builds = 0;
};

// The PreparedScene of one loaded scene, shared by its renders: built by the first, updated by the
// first after a re-pose with every change noted since, rebuilt when an update is not possible.
class PreparedSceneCache {
public:
    // The prepared scene for `scene` as it stands now. Thread-safe; a second caller waits for
    // the first's build.
    std::shared_ptr<const PreparedScene> get(const Scene& scene);
    // A re-pose changed the scene (no render of it may be running).
    void note(const SceneChanges& changes);
    // scene.bounds() as it stands now, bit for bit, from per-instance bounds kept between calls:
    // only the instances the noted changes moved or deformed are visited again. Thread-safe.
    Bounds3 scene_bounds(const Scene& scene);

private:
    std::mutex m_mutex;
    std::shared_ptr<PreparedScene> m_prepared;
    SceneChanges m_pending;
    const Scene* m_bounds_scene = nullptr;
    std::vector<Bounds3> m_instance_bounds;  // Scene::bounds_of per instance of m_bounds_scene
    SceneChanges m_bounds_pending;           // noted since m_instance_bounds was brought up to date
};

}  // namespace veach
