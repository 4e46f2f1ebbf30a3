#include "integrators/prepared_scene.h"

#include <algorithm>
#include <cstring>

#include "scene/mesh_corners.h"
#include "scene/mesh_topology.h"

namespace veach {

namespace {

bool same_bounds(const Bounds3& a, const Bounds3& b) {
    return std::memcmp(&a, &b, sizeof(Bounds3)) == 0;
}

}  // namespace

Bounds3 PreparedScene::instance_bounds(size_t instance, MeshCorners& corners) const {
    const Instance& inst = m_scene.instances[instance];
    const Mesh& mesh = m_scene.meshes[inst.mesh];
    const std::vector<uint32_t>& used = corners.of(inst.mesh);
    Bounds3 b;
    auto extend = [&](const std::vector<Vec3>& positions, const Transform& to_world) {
        b.extend(MeshCorners::placed(positions, used, to_world));
    };
    extend(mesh.positions, inst.object_to_world);
    // Moving geometry: its path through the shutter. Deformed vertices move on straight lines
    // between steps (the steps' bounds hold them); a slerped rotation bends between steps, so its
    // transform is taken at several times per step as well (a bound within a small fraction of
    // the object's distance from its centre of rotation).
    const SceneMotion& motion = m_scene.motion;
    const bool deforms = m_accel->mesh_deforms(inst.mesh);
    Transform moving;
    const bool moves = m_accel->moving_transform(uint32_t(instance), 0.0f, &moving);
    if (!deforms && !moves) return b;
    const int per_step = moves ? 8 : 1;
    const int samples = (motion.steps - 1) * per_step;
    for (int j = 0; j <= samples; ++j) {
        const float u = float(j) / float(samples);
        const Transform& to_world = moves && m_accel->moving_transform(uint32_t(instance), u, &moving) ? moving
                                                                                                  : inst.object_to_world;
        if (deforms) {
            // Between samples, vertices interpolate within one step's segment: the sampled steps
            // are every step (j a multiple of per_step) plus the rotation's extra times.
            int k;
            float f;
            motion_segment(u, motion.steps, &k, &f);
            extend(motion.meshes[inst.mesh].positions[size_t(k)], to_world);
            extend(motion.meshes[inst.mesh].positions[size_t(k) + 1], to_world);
        } else {
            extend(mesh.positions, to_world);
        }
    }
    return b;
}

PreparedScene::PreparedScene(const Scene& scene)
    : m_scene(scene), m_accel(std::make_unique<Accel>(scene)) {
    m_instance_bounds.reserve(scene.instances.size());
    MeshCorners corners(scene);
    for (size_t i = 0; i < scene.instances.size(); ++i) m_instance_bounds.push_back(instance_bounds(i, corners));
    for (const Bounds3& b : m_instance_bounds) m_bounds.extend(b);
    m_lights = std::make_unique<LightSet>(scene, *m_accel, &m_bounds);
    m_light_builds = 1;
    m_world_to_object.reserve(scene.instances.size());
    for (const Instance& inst : scene.instances) m_world_to_object.push_back(inverse(inst.object_to_world));
    m_thin_walled.resize(scene.meshes.size(), 0);
    for (size_t i = 0; i < scene.meshes.size(); ++i) set_thin_walled(i);
}

void PreparedScene::set_thin_walled(size_t mesh) {
    const Material& m = m_scene.material_of(m_scene.meshes[mesh]);
    if (m.transmission > 0.0f || m.transmission_texture.valid())
        m_thin_walled[mesh] = is_closed_mesh(m_scene.meshes[mesh]) ? 0 : 1;
}

bool PreparedScene::update(const SceneChanges& changes) {
    if (!changes.any()) return true;
    if (!m_accel->update(changes)) return false;
    for (uint32_t i : changes.moved_instances) m_world_to_object[i] = inverse(m_scene.instances[i].object_to_world);
    for (uint32_t m : changes.deformed_meshes) set_thin_walled(m);
    MeshCorners corners(m_scene);
    for (uint32_t i : changes.moved_instances) m_instance_bounds[i] = instance_bounds(i, corners);
    if (!changes.deformed_meshes.empty())
        for (size_t i = 0; i < m_scene.instances.size(); ++i)
            if (std::binary_search(changes.deformed_meshes.begin(), changes.deformed_meshes.end(),
                                   m_scene.instances[i].mesh))
                m_instance_bounds[i] = instance_bounds(i, corners);
    Bounds3 bounds;
    for (const Bounds3& b : m_instance_bounds) bounds.extend(b);
    bool relight = changes.lights_changed || !same_bounds(bounds, m_bounds);
    m_bounds = bounds;
    // Emissive triangles are lights: one that moved or deformed changes the tables.
    auto emits = [&](uint32_t mesh) { return m_scene.material_of(m_scene.meshes[mesh]).is_emissive(); };
    for (uint32_t i : changes.moved_instances) relight = relight || emits(m_scene.instances[i].mesh);
    for (uint32_t m : changes.deformed_meshes) relight = relight || emits(m);
    if (relight) {
        m_lights = std::make_unique<LightSet>(m_scene, *m_accel, &m_bounds);
        ++m_light_builds;
    }
    return true;
}

std::shared_ptr<const PreparedScene> PreparedSceneCache::get(const Scene& scene) {
    std::lock_guard<std::mutex> lock(m_mutex);
    if (m_prepared && &m_prepared->scene() != &scene) m_prepared.reset();
    try {
        if (m_prepared && !m_prepared->update(m_pending)) m_prepared.reset();
    } catch (...) {
        m_prepared.reset();  // half updated: never used again
        m_pending = {};
        throw;
    }
    m_pending = {};
    if (!m_prepared) m_prepared = std::make_shared<PreparedScene>(scene);
    return m_prepared;
}

void PreparedSceneCache::note(const SceneChanges& changes) {
    std::lock_guard<std::mutex> lock(m_mutex);
    m_pending.merge(changes);
    m_bounds_pending.merge(changes);
}

Bounds3 PreparedSceneCache::scene_bounds(const Scene& scene) {
    std::lock_guard<std::mutex> lock(m_mutex);
    const size_t n = scene.instances.size();
    MeshCorners corners(scene);
    if (m_bounds_scene != &scene || m_instance_bounds.size() != n) {
        m_instance_bounds.resize(n);
        for (size_t i = 0; i < n; ++i) m_instance_bounds[i] = corners.bounds_of(scene.instances[i]);
        m_bounds_scene = &scene;
    } else {
        const SceneChanges& c = m_bounds_pending;
        for (uint32_t i : c.moved_instances)
            if (i < n) m_instance_bounds[i] = corners.bounds_of(scene.instances[i]);
        if (!c.deformed_meshes.empty())
            for (size_t i = 0; i < n; ++i)
                if (std::binary_search(c.deformed_meshes.begin(), c.deformed_meshes.end(), scene.instances[i].mesh))
                    m_instance_bounds[i] = corners.bounds_of(scene.instances[i]);
    }
    m_bounds_pending = {};
    Bounds3 b;
    for (const Bounds3& ib : m_instance_bounds) b.extend(ib);
    return b;
}

}  // namespace veach
