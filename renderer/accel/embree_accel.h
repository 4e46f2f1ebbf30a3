// Ray queries against the scene's geometry. The only place that includes Embree: meshes placed
// once are baked to world space and put in the top-level BVH directly; meshes placed several
// times are built once and referenced by Embree instances.
//
// A scene whose pose can change (scene/scene_changes.h movable_instances) gets a layout that can
// follow it without rebuilding what never moves: the baked static geometry sits in one BVH of
// its own, referenced from the top level by an identity instance (exact: the ray is multiplied by
// the identity), each movable rigid instance is an Embree instance of its mesh's BVH, and each
// deforming mesh has its own BVH with an Embree-owned vertex buffer, refitted when it deforms.
// update() then sets transforms, copies vertices, refits and recommits the small top level.
//
// Motion blur (scene/scene_motion.h): an instance that moves during the shutter gets one
// transform per time step, given to Embree as a quaternion decomposition (T R S: translation and
// the upper-triangular scale/shear interpolated linearly, the rotation by slerp), so a turn within
// the shutter is a turn, not a shrinking blend of two matrices; a deforming mesh gets one vertex
// buffer per time step, interpolated linearly. Whatever turns a hit into world space (positions,
// normals, tangents, the triangle's world vertices) asks the accel for the same interpolation at
// the hit's time: object_to_world() returns the transform Embree itself traced against.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "core/math.h"
#include "scene/scene.h"
#include "scene/scene_changes.h"

namespace veach {

struct RayHit {
    float t = 0;
    uint32_t instance = 0;  // index into Scene::instances
    uint32_t prim = 0;      // triangle index within the instance's mesh
    float u = 0, v = 0;     // barycentrics of vertices 1 and 2
    float time = 0;         // the ray's shutter time: where moving geometry was when it was hit
};

class Accel {
public:
    explicit Accel(const Scene& scene);
    ~Accel();
    Accel(const Accel&) = delete;
    Accel& operator=(const Accel&) = delete;

    // Closest hit along origin + t * dir for t in (0, t_max); dir need not be normalised. `time`
    // is the camera sample's shutter time in [0, 1] (Embree's ray time): moving geometry is
    // where it is then; static geometry ignores it.
    bool intersect(const Vec3& origin, const Vec3& dir, float t_max, RayHit* hit, float time = 0.0f) const;
    // Any hit in (0, t_max).
    bool occluded(const Vec3& origin, const Vec3& dir, float t_max, float time = 0.0f) const;

    // Rays Embree cannot take (an origin or direction component past k_max_ray_coordinate or
    // not finite, a NaN t_max) never reach it: it asserts on them and aborts the process.
    // intersect() reports a miss, occluded() a blocked ray, and the calling thread's count
    // grows; integrators drop the sample during which it grew, as they drop non-finite samples.
    static uint64_t rejected_rays_on_this_thread();

    // World-space vertex positions of a triangle (baked or transformed on the fly) at shutter
    // time `time`: a moving instance's interpolated transform, a deforming mesh's interpolated
    // vertices; still geometry ignores the time.
    void triangle_world(uint32_t instance, uint32_t prim, Vec3* p0, Vec3* p1, Vec3* p2, float time = 0.0f) const;

    // Whether the instance moves during the shutter (its transform has time steps), and its
    // transform at shutter time `time` as Embree interpolates it. False (nothing written) for an
    // instance that stands still: its Instance::object_to_world is the one.
    bool moving_transform(uint32_t instance, float time, Transform* object_to_world) const;
    // Whether mesh `mesh` deforms during the shutter (its vertices have time steps).
    bool mesh_deforms(uint32_t mesh) const;

    // Follows the scene (the one given to the constructor, re-posed since) after `changes`:
    // moved instances get their new transform (their new time steps), deformed meshes their new
    // vertices (the BVH refitted, or rebuilt when its number of time steps changed), and the top
    // level is recommitted. False, with nothing to rely on, when a change
    // touches geometry that was baked into world space: the caller builds a new Accel. Not while
    // rays are traced.
    bool update(const SceneChanges& changes);

private:
    struct Impl;
    std::unique_ptr<Impl> m_impl;
};

}  // namespace veach
