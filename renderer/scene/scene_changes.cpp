#include "scene/scene_changes.h"

#include <algorithm>
#include <cstring>

namespace veach {

namespace {

bool same_bits(const Transform& a, const Transform& b) { return std::memcmp(a.m, b.m, sizeof(a.m)) == 0; }

bool same_bits(const Vec3& a, const Vec3& b) { return a.x == b.x && a.y == b.y && a.z == b.z; }

bool same_bits(const std::vector<Transform>& a, const std::vector<Transform>& b) {
    if (a.size() != b.size()) return false;
    for (size_t k = 0; k < a.size(); ++k)
        if (!same_bits(a[k], b[k])) return false;
    return true;
}

bool same_bits(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
    return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(Vec3)) == 0);
}

bool same_bits(const MeshMotion& a, const MeshMotion& b) {
    if (a.positions.size() != b.positions.size()) return false;
    for (size_t k = 0; k < a.positions.size(); ++k)
        if (!same_bits(a.positions[k], b.positions[k]) || !same_bits(a.normals[k], b.normals[k]) ||
            !same_bits(a.tangents[k], b.tangents[k]))
            return false;
    return true;
}

bool same_rgb(const Rgb& a, const Rgb& b) { return a.r == b.r && a.g == b.g && a.b == b.b; }

// What pose_scene writes of a light: its placement, and its colour, intensity and cone
// (KHR_animation_pointer); the rest comes from the file and never changes.
bool same_placement(const PunctualLight& a, const PunctualLight& b) {
    return a.type == b.type && same_bits(a.position, b.position) && same_bits(a.direction, b.direction) &&
           same_bits(a.axis_u, b.axis_u) && same_bits(a.axis_v, b.axis_v) && same_rgb(a.radiance, b.radiance) &&
           same_rgb(a.intensity, b.intensity) && a.cos_outer == b.cos_outer && a.cos_inner == b.cos_inner &&
           a.blend == b.blend;
}

void merge_sorted(std::vector<uint32_t>& into, const std::vector<uint32_t>& more) {
    std::vector<uint32_t> out;
    std::set_union(into.begin(), into.end(), more.begin(), more.end(), std::back_inserter(out));
    into = std::move(out);
}

}  // namespace

void SceneChanges::merge(const SceneChanges& later) {
    merge_sorted(moved_instances, later.moved_instances);
    merge_sorted(deformed_meshes, later.deformed_meshes);
    lights_changed = lights_changed || later.lights_changed;
}

ScenePose capture_pose(const Scene& scene) {
    ScenePose p;
    p.instances.reserve(scene.instances.size());
    for (const Instance& inst : scene.instances) p.instances.push_back(inst.object_to_world);
    for (const DeformingMesh& d : scene.animation.deforming) p.deforming.push_back(scene.meshes[d.mesh].positions);
    p.lights = scene.lights;
    p.motion = scene.motion;
    for (const MaterialRest& m : scene.animation.material_rest)
        if (m.material >= 0) p.emission.push_back(scene.materials[size_t(m.material)].emission);
    return p;
}

SceneChanges changes_since(const ScenePose& before, const Scene& scene) {
    SceneChanges c;
    // Motion steps count as the pose: an instance can keep its frame's transform while its
    // path through the shutter changes.
    static const std::vector<Transform> no_steps;
    auto instance_steps = [](const SceneMotion& m, size_t i) -> const std::vector<Transform>& {
        return i < m.instance_to_world.size() ? m.instance_to_world[i] : no_steps;
    };
    for (size_t i = 0; i < scene.instances.size(); ++i)
        if (i >= before.instances.size() || !same_bits(before.instances[i], scene.instances[i].object_to_world) ||
            !same_bits(instance_steps(before.motion, i), instance_steps(scene.motion, i)))
            c.moved_instances.push_back(uint32_t(i));
    static const MeshMotion no_mesh_steps;
    auto mesh_steps = [](const SceneMotion& m, size_t j) -> const MeshMotion& {
        return j < m.meshes.size() ? m.meshes[j] : no_mesh_steps;
    };
    const auto& deforming = scene.animation.deforming;
    for (size_t k = 0; k < deforming.size(); ++k) {
        const std::vector<Vec3>& now = scene.meshes[deforming[k].mesh].positions;
        if (k >= before.deforming.size() || before.deforming[k].size() != now.size() ||
            (!now.empty() && std::memcmp(before.deforming[k].data(), now.data(), now.size() * sizeof(Vec3)) != 0) ||
            !same_bits(mesh_steps(before.motion, deforming[k].mesh), mesh_steps(scene.motion, deforming[k].mesh)))
            c.deformed_meshes.push_back(deforming[k].mesh);
    }
    std::sort(c.deformed_meshes.begin(), c.deformed_meshes.end());
    c.deformed_meshes.erase(std::unique(c.deformed_meshes.begin(), c.deformed_meshes.end()), c.deformed_meshes.end());
    c.lights_changed = before.lights.size() != scene.lights.size();
    for (size_t i = 0; !c.lights_changed && i < scene.lights.size(); ++i)
        c.lights_changed = !same_placement(before.lights[i], scene.lights[i]);
    // An animated emission changes what the light tables hold of the meshes that wear it.
    size_t k = 0;
    for (const MaterialRest& m : scene.animation.material_rest) {
        if (m.material < 0) continue;
        c.lights_changed = c.lights_changed || k >= before.emission.size() ||
                           !same_rgb(before.emission[k], scene.materials[size_t(m.material)].emission);
        ++k;
    }
    return c;
}

std::vector<uint8_t> movable_instances(const Scene& scene) {
    std::vector<uint8_t> movable(scene.instances.size(), 0);
    const SceneAnimation& a = scene.animation;
    if (!a.enabled) return movable;
    std::vector<uint8_t> animated_node(a.rest.size(), 0);
    for (size_t i = 0; i < a.animations.size(); ++i) {
        if (a.selected >= 0 && size_t(a.selected) != i) continue;
        for (const AnimationChannel& ch : a.animations[i].channels)
            if (ch.path != AnimatedPath::Weights && ch.node >= 0 && size_t(ch.node) < animated_node.size())
                animated_node[size_t(ch.node)] = 1;
    }
    // Placements come parents first: a placement moves when its node or its parent's does.
    std::vector<uint8_t> moves(a.placements.size(), 0);
    for (size_t p = 0; p < a.placements.size(); ++p) {
        const NodePlacement& pl = a.placements[p];
        moves[p] = animated_node[size_t(pl.node)] || (pl.parent >= 0 && moves[size_t(pl.parent)]);
        if (moves[p])
            for (uint32_t inst : pl.instances) movable[inst] = 1;
    }
    for (const DeformingMesh& d : a.deforming) movable[d.instance] = 1;
    return movable;
}

}  // namespace veach
