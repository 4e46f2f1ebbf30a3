// Everything an integrator reads while rendering: the scene, its BVH, its lights and the camera,
// shared read-only by all threads. The BVH and lights (PreparedScene) may outlive the render: a
// sequence keeps them across frames.
#pragma once

#include <algorithm>
#include <cstdint>
#include <memory>
#include <vector>

#include "camera/camera_model.h"
#include "core/sobol_sampler.h"
#include "integrators/prepared_scene.h"
#include "scene/scene.h"

namespace veach {

class RenderScene {
public:
    // Prepares the scene for this render alone.
    RenderScene(const Scene& scene, const Camera* camera, int width, int height)
        : RenderScene(std::make_shared<const PreparedScene>(scene), camera, width, height) {}
    // Renders what `prepared` holds (its scene as prepared or last updated).
    RenderScene(std::shared_ptr<const PreparedScene> prepared, const Camera* camera, int width, int height)
        : m_prepared(std::move(prepared)), m_camera(camera, m_prepared->bounds(), width, height) {
        // A camera that moves during the shutter: one model per motion step (scene_motion.h).
        const Scene& scene = m_prepared->scene();
        const size_t index = camera ? static_cast<size_t>(camera - scene.cameras.data()) : SIZE_MAX;
        if (scene.motion.enabled() && index < scene.motion.camera_to_world.size()) {
            for (const Transform& t : scene.motion.camera_to_world[index]) {
                Camera step = *camera;
                step.camera_to_world = t;
                m_camera_steps.emplace_back(&step, m_prepared->bounds(), width, height);
            }
        }
    }

    const Scene& scene() const { return m_prepared->scene(); }
    const Accel& accel() const { return m_prepared->accel(); }
    const LightSet& lights() const { return m_prepared->lights(); }
    // The camera at the frame's time: what a render without motion blur sees.
    const CameraModel& camera() const { return m_camera; }
    // The camera at shutter time u in [0, 1] (Sampler::shutter_time): between the two motion
    // steps around u; the frame's camera when it does not move.
    // A sample's shutter time: drawn only when the scene has a shutter (Sampler::shutter_time
    // consumes nothing, so skipping it changes no other value), 0 otherwise.
    float shutter_time(const Sampler& rng) const { return scene().motion.enabled() ? rng.shutter_time() : 0.0f; }
    // A still camera is returned as it is, a moving one is interpolated into `scratch`: a sample
    // costs no camera copy unless the camera moves.
    const CameraModel& camera_at(float u, CameraModel& scratch) const {
        if (m_camera_steps.empty()) return m_camera;
        const float x = clamp(u, 0.0f, 1.0f) * static_cast<float>(m_camera_steps.size() - 1);
        const size_t k = std::min(static_cast<size_t>(x), m_camera_steps.size() - 2);
        scratch = CameraModel::interpolate(m_camera_steps[k], m_camera_steps[k + 1], x - static_cast<float>(k));
        return scratch;
    }
    // The inverse of an instance's transform: normals transform by its transpose.
    const Transform& world_to_object(uint32_t instance) const { return m_prepared->world_to_object(instance); }
    // A transmissive mesh that encloses no volume (a single plane, an open sheet) is a thin wall
    // (KHR_materials_volume's thin-walled case): light passes through it without refracting into
    // an interior, so without the 1/eta^2 of entering one (README "What it renders").
    bool thin_walled(uint32_t mesh) const { return m_prepared->thin_walled(mesh); }

private:
    std::shared_ptr<const PreparedScene> m_prepared;
    CameraModel m_camera;
    std::vector<CameraModel> m_camera_steps;  // empty: the camera does not move during the shutter
};

}  // namespace veach
