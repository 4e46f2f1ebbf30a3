#include "scene/scene_motion.h"

#include <cmath>
#include <cstring>

#include "scene/scene.h"

namespace veach {
namespace {

bool same_transform(const Transform& a, const Transform& b) { return std::memcmp(a.m, b.m, sizeof(a.m)) == 0; }

// Empties a per-step list whose entries are all the first: nothing to interpolate.
void drop_if_static(std::vector<Transform>& steps) {
    for (const Transform& t : steps)
        if (!same_transform(t, steps.front())) return;
    steps.clear();
}

bool same_vertices(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
    return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(Vec3)) == 0);
}

void drop_if_static(MeshMotion& m) {
    for (size_t k = 1; k < m.positions.size(); ++k)
        if (!same_vertices(m.positions[k], m.positions[0]) || !same_vertices(m.normals[k], m.normals[0]) ||
            !same_vertices(m.tangents[k], m.tangents[0]))
            return;
    m = MeshMotion{};
}

}  // namespace

void capture_motion(Scene& scene, double seconds, double open, double close) {
    SceneMotion& m = scene.motion;
    m = SceneMotion{};
    if (!scene.animation.enabled || !(close > open)) return;
    m.open = open;
    m.close = close;
    m.steps = k_motion_steps;
    m.camera_to_world.assign(scene.cameras.size(), {});
    m.instance_to_world.assign(scene.instances.size(), {});
    m.meshes.assign(scene.meshes.size(), {});
    // Emitters stay at the frame's pose (scene_motion.h); everything else a pose can move is
    // recorded, and dropped below where the steps are all the same.
    auto emits = [&](uint32_t mesh) { return scene.material_of(scene.meshes[mesh]).is_emissive(); };
    std::vector<uint8_t> deforming(scene.meshes.size(), 0);
    for (const DeformingMesh& d : scene.animation.deforming)
        if (!emits(d.mesh)) deforming[d.mesh] = 1;
    for (int k = 0; k < m.steps; ++k) {
        pose_scene(scene, seconds + open + (close - open) * double(k) / double(m.steps - 1));
        for (size_t c = 0; c < scene.cameras.size(); ++c) m.camera_to_world[c].push_back(scene.cameras[c].camera_to_world);
        for (size_t i = 0; i < scene.instances.size(); ++i)
            if (!emits(scene.instances[i].mesh)) m.instance_to_world[i].push_back(scene.instances[i].object_to_world);
        for (size_t j = 0; j < scene.meshes.size(); ++j) {
            if (!deforming[j]) continue;
            const Mesh& mesh = scene.meshes[j];
            m.meshes[j].positions.push_back(mesh.positions);
            m.meshes[j].normals.push_back(mesh.normals);
            m.meshes[j].tangents.push_back(mesh.tangents);
        }
    }
    for (auto& steps : m.camera_to_world) drop_if_static(steps);
    for (auto& steps : m.instance_to_world)
        if (!steps.empty()) drop_if_static(steps);
    for (MeshMotion& mm : m.meshes)
        if (!mm.positions.empty()) drop_if_static(mm);
    pose_scene(scene, seconds);
}

void motion_segment(float u, int steps, int* k, float* f) {
    // Embree's getTimeSegment: time scaled to segments, the segment clamped to the last one.
    const float segments = float(steps - 1);
    const float scaled = u * segments;
    const float kf = std::fmin(std::fmax(std::floor(scaled), 0.0f), segments - 1.0f);
    *k = int(kf);
    *f = scaled - kf;
}

}  // namespace veach
