// Motion blur's view of an animated scene: the scene posed at evenly spaced times across the
// shutter, kept as what each step places (cameras now; instances and deformed vertices for
// Embree's time steps). A camera sample's shutter time in [0, 1] picks a point between two
// steps; the integrators trace every vertex of its path at that time.
//
// Why steps and not the animation itself: Embree interpolates geometry between time steps, so
// the camera is interpolated between the same steps (position linearly, rotation by slerp) and a
// camera riding on a moving object stays where the object is at every time.
#pragma once

#include <vector>

#include "core/math.h"

namespace veach {

struct Scene;

struct SceneMotion {
    // Steps across the shutter: 0 when the scene has no motion blur (no shutter, or an empty
    // one), else at least 2, step k at shutter time k / (steps - 1).
    int steps = 0;
    double open = 0, close = 0;  // the shutter in seconds, relative to the time the scene is posed at
    // Per camera: its transform at each step, or empty when it does not move during the shutter.
    std::vector<std::vector<Transform>> camera_to_world;
    bool enabled() const { return steps >= 2; }
};

// Steps across a shutter: open, middle and close. Three so that a motion that turns within the
// shutter bends the camera's and the geometry's path through the middle pose.
constexpr int k_motion_steps = 3;

// Poses `scene` (scene_animation.h's pose_scene) at k_motion_steps times from seconds + open to
// seconds + close, records into scene.motion what moves, and leaves the scene posed at
// `seconds`. An empty shutter (open == close) or a scene without animation clears the motion.
void capture_motion(Scene& scene, double seconds, double open, double close);

}  // namespace veach
