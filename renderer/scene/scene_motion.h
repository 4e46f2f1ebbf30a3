// Motion blur's view of an animated scene: the scene posed at evenly spaced times across the
// shutter, kept as what each step places: cameras, rigid instances (Embree instances with one
// transform per time step) and deforming meshes (one vertex buffer per time step). A camera
// sample's shutter time in [0, 1] picks a point between two steps; the integrators trace every
// vertex of its path at that time.
//
// Why steps and not the animation itself: Embree interpolates geometry between time steps, so
// the camera and the shading of a hit are interpolated between the same steps, the way Embree
// does it (accel/embree_accel.h: rigid instances by quaternion decomposition, vertices
// linearly), and a camera riding on a moving object stays where the object is at every time.
//
// Emitters stay out of motion: an instance whose material emits (and a deforming mesh that
// emits) stands at the frame's pose for the whole shutter, as punctual lights do. Light
// sampling and the geometry rays find then agree at every time; a light drawn at the frame's
// pose while rays find it elsewhere would be biased.
#pragma once

#include <vector>

#include "core/math.h"

namespace veach {

struct Scene;

// A deforming mesh's vertices at each step; per step, arrays as long as the mesh's (normals and
// tangents empty when the mesh has none).
struct MeshMotion {
    std::vector<std::vector<Vec3>> positions, normals, tangents;
};

struct SceneMotion {
    // Steps across the shutter: 0 when the scene has no motion blur (no shutter, or an empty
    // one), else at least 2, step k at shutter time k / (steps - 1).
    int steps = 0;
    double open = 0, close = 0;  // the shutter in seconds, relative to the time the scene is posed at
    // Per camera: its transform at each step, or empty when it does not move during the shutter.
    std::vector<std::vector<Transform>> camera_to_world;
    // Per instance: its object_to_world at each step, or empty when it does not move during the
    // shutter (or emits light: above).
    std::vector<std::vector<Transform>> instance_to_world;
    // Per mesh: its vertices at each step, or empty when it does not deform during the shutter
    // (or emits).
    std::vector<MeshMotion> meshes;
    bool enabled() const { return steps >= 2; }
    bool instance_moves(size_t instance) const {
        return instance < instance_to_world.size() && !instance_to_world[instance].empty();
    }
    bool mesh_deforms(size_t mesh) const { return mesh < meshes.size() && !meshes[mesh].positions.empty(); }
};

// Steps across a shutter: open, middle and close. Three so that a motion that turns within the
// shutter bends the camera's and the geometry's path through the middle pose.
constexpr int k_motion_steps = 3;

// Poses `scene` (scene_animation.h's pose_scene) at k_motion_steps times from seconds + open to
// seconds + close, records into scene.motion what moves, and leaves the scene posed at
// `seconds`. An empty shutter (open == close) or a scene without animation clears the motion.
void capture_motion(Scene& scene, double seconds, double open, double close);

// Where shutter time u in [0, 1] falls between `steps` steps: segment k (0 <= k < steps - 1)
// and the fraction f in [0, 1] within it, computed as Embree computes it for its time steps.
void motion_segment(float u, int steps, int* k, float* f);

}  // namespace veach
