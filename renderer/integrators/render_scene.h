// Everything an integrator reads while rendering: the scene, its BVH, its lights and the camera,
// shared read-only by all threads. The BVH and lights (PreparedScene) may outlive the render: a
// sequence keeps them across frames.
#pragma once

#include <memory>

#include "camera/camera_model.h"
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
        : m_prepared(std::move(prepared)), m_camera(camera, m_prepared->bounds(), width, height) {}

    const Scene& scene() const { return m_prepared->scene(); }
    const Accel& accel() const { return m_prepared->accel(); }
    const LightSet& lights() const { return m_prepared->lights(); }
    const CameraModel& camera() const { return m_camera; }
    // The inverse of an instance's transform: normals transform by its transpose.
    const Transform& world_to_object(uint32_t instance) const { return m_prepared->world_to_object(instance); }
    // A transmissive mesh that encloses no volume (a single plane, an open sheet) is a thin wall
    // (KHR_materials_volume's thin-walled case): light passes through it without refracting into
    // an interior, so without the 1/eta^2 of entering one (README "What it renders").
    bool thin_walled(uint32_t mesh) const { return m_prepared->thin_walled(mesh); }

private:
    std::shared_ptr<const PreparedScene> m_prepared;
    CameraModel m_camera;
};

}  // namespace veach
