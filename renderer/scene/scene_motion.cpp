#include "scene/scene_motion.h"

#include "scene/scene.h"

namespace veach {
namespace {

bool same_transform(const Transform& a, const Transform& b) {
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c)
            if (a.m[r][c] != b.m[r][c]) return false;
    return true;
}

// Empties a per-step list whose entries are all the first: nothing to interpolate.
void drop_if_static(std::vector<Transform>& steps) {
    for (const Transform& t : steps)
        if (!same_transform(t, steps.front())) return;
    steps.clear();
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
    for (int k = 0; k < m.steps; ++k) {
        pose_scene(scene, seconds + open + (close - open) * double(k) / double(m.steps - 1));
        for (size_t c = 0; c < scene.cameras.size(); ++c) m.camera_to_world[c].push_back(scene.cameras[c].camera_to_world);
    }
    for (auto& steps : m.camera_to_world) drop_if_static(steps);
    pose_scene(scene, seconds);
}

}  // namespace veach
