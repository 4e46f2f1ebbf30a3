// Everything an integrator reads while rendering: the scene, its BVH, its lights and the camera,
// built once per render and shared read-only by all threads.
#pragma once

#include <vector>

#include "accel/embree_accel.h"
#include "camera/camera_model.h"
#include "lights/light_set.h"
#include "scene/scene.h"

namespace veach {

class RenderScene {
public:
    RenderScene(const Scene& scene, const Camera* camera, int width, int height)
        : m_scene(scene), m_accel(scene), m_lights(scene, m_accel), m_camera(camera, scene.bounds(), width, height) {
        m_world_to_object.reserve(scene.instances.size());
        for (const Instance& inst : scene.instances) m_world_to_object.push_back(inverse(inst.object_to_world));
    }

    const Scene& scene() const { return m_scene; }
    const Accel& accel() const { return m_accel; }
    const LightSet& lights() const { return m_lights; }
    const CameraModel& camera() const { return m_camera; }
    // The inverse of an instance's transform: normals transform by its transpose.
    const Transform& world_to_object(uint32_t instance) const { return m_world_to_object[instance]; }

private:
    const Scene& m_scene;
    Accel m_accel;
    LightSet m_lights;
    CameraModel m_camera;
    std::vector<Transform> m_world_to_object;
};

}  // namespace veach
