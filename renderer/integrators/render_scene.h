// Everything an integrator reads while rendering: the scene, its BVH, its lights and the camera,
// built once per render and shared read-only by all threads.
#pragma once

#include <vector>

#include "accel/embree_accel.h"
#include "camera/camera_model.h"
#include "lights/light_set.h"
#include "scene/mesh_topology.h"
#include "scene/scene.h"

namespace veach {

class RenderScene {
public:
    RenderScene(const Scene& scene, const Camera* camera, int width, int height)
        : m_scene(scene), m_accel(scene), m_lights(scene, m_accel), m_camera(camera, scene.bounds(), width, height) {
        m_world_to_object.reserve(scene.instances.size());
        for (const Instance& inst : scene.instances) m_world_to_object.push_back(inverse(inst.object_to_world));
        m_thin_walled.resize(scene.meshes.size(), 0);
        for (size_t i = 0; i < scene.meshes.size(); ++i) {
            const Material& m = scene.material_of(scene.meshes[i]);
            if (m.transmission > 0.0f || m.transmission_texture.valid())
                m_thin_walled[i] = is_closed_mesh(scene.meshes[i]) ? 0 : 1;
        }
    }

    const Scene& scene() const { return m_scene; }
    const Accel& accel() const { return m_accel; }
    const LightSet& lights() const { return m_lights; }
    const CameraModel& camera() const { return m_camera; }
    // The inverse of an instance's transform: normals transform by its transpose.
    const Transform& world_to_object(uint32_t instance) const { return m_world_to_object[instance]; }
    // A transmissive mesh that encloses no volume (a single plane, an open sheet) is a thin wall
    // (KHR_materials_volume's thin-walled case): light passes through it without refracting into
    // an interior, so without the 1/eta^2 of entering one (README "What it renders").
    bool thin_walled(uint32_t mesh) const { return m_thin_walled[mesh] != 0; }

private:
    const Scene& m_scene;
    Accel m_accel;
    LightSet m_lights;
    CameraModel m_camera;
    std::vector<Transform> m_world_to_object;
    std::vector<uint8_t> m_thin_walled;  // per mesh
};

}  // namespace veach
