// The bounds of instanced triangles from each mesh's referenced vertices, found once per mesh:
// an instance of a mesh whose vertices are each shared by ~6 triangles transforms each vertex once
// instead of once per corner (10,000 instances of one tree: the tree's vertex list, transformed
// 10,000 times). Bit for bit the bounds over the corners in index order: the vertices are listed in
// order of first use, and Bounds3::extend keeps the first of equal values (so even the sign of a
// zero bound is the same) and never takes a NaN.
#pragma once

#include <cstdint>
#include <vector>

#include "scene/scene.h"

namespace veach {

class MeshCorners {
public:
    explicit MeshCorners(const Scene& scene) : m_scene(scene), m_corners(scene.meshes.size()), m_known(scene.meshes.size(), 0) {}

    // The vertices mesh `m`'s triangles reference (indices within its positions), each once, in
    // order of first use. Not thread-safe on first use of a mesh.
    const std::vector<uint32_t>& of(uint32_t m) {
        if (!m_known[m]) {
            const Mesh& mesh = m_scene.meshes[m];
            std::vector<uint8_t> seen(mesh.positions.size(), 0);
            for (uint32_t i : mesh.indices)
                if (i < mesh.positions.size() && !seen[i]) {
                    seen[i] = 1;
                    m_corners[m].push_back(i);
                }
            m_known[m] = 1;
        }
        return m_corners[m];
    }

    // Scene::bounds_of(inst), bit for bit.
    Bounds3 bounds_of(const Instance& inst) {
        return placed(m_scene.meshes[inst.mesh].positions, of(inst.mesh), inst.object_to_world);
    }

    // The finite points among positions[corners] placed by to_world (a vertex buffer of the same
    // mesh at another time: its vertices may be non-finite where the rest shape's are not).
    static Bounds3 placed(const std::vector<Vec3>& positions, const std::vector<uint32_t>& corners,
                          const Transform& to_world) {
        Bounds3 b;
        for (uint32_t i : corners)
            if (i < positions.size() && is_finite(positions[i])) b.extend(to_world.point(positions[i]));
        return b;
    }

private:
    const Scene& m_scene;
    std::vector<std::vector<uint32_t>> m_corners;
    std::vector<uint8_t> m_known;
};

}  // namespace veach
