// Scenes built in code for tests whose answer is known in closed form.
#pragma once

#include <cmath>

#include "scene/scene.h"

namespace veach::test {

// A closed UV sphere of `radius` around `center`, flat-shaded (no normals): every face exactly
// Lambertian, so furnace arguments hold exactly.
inline Mesh make_sphere(float radius, Vec3 center, int segments, int rings) {
    Mesh m;
    m.name = "sphere";
    for (int r = 0; r <= rings; ++r) {
        float theta = k_pi * r / rings;
        // Exactly 0 at the poles (sin of float pi is not), so the pole's corners coincide and the
        // sphere is closed by position (scene/mesh_topology.h).
        float sin_theta = r == 0 || r == rings ? 0.0f : std::sin(theta);
        for (int s = 0; s < segments; ++s) {
            float phi = 2.0f * k_pi * s / segments;
            m.positions.push_back(
                center + Vec3(sin_theta * std::cos(phi), std::cos(theta), sin_theta * std::sin(phi)) * radius);
        }
    }
    auto at = [&](int r, int s) { return static_cast<uint32_t>(r * segments + (s % segments)); };
    for (int r = 0; r < rings; ++r) {
        for (int s = 0; s < segments; ++s) {
            if (r != 0) m.indices.insert(m.indices.end(), {at(r, s), at(r, s + 1), at(r + 1, s)});
            if (r != rings - 1) m.indices.insert(m.indices.end(), {at(r, s + 1), at(r + 1, s + 1), at(r + 1, s)});
        }
    }
    return m;
}

// A square of side `size` centred at `center` in the plane z = center.z, facing +z: one sheet
// with a boundary, so a transmissive material on it is a thin wall.
inline Mesh make_quad(float size, Vec3 center) {
    Mesh m;
    m.name = "quad";
    float h = size / 2;
    m.positions = {center + Vec3(-h, -h, 0), center + Vec3(h, -h, 0), center + Vec3(h, h, 0),
                   center + Vec3(-h, h, 0)};
    m.indices = {0, 1, 2, 0, 2, 3};
    return m;
}

// A purely Lambertian material (KHR_materials_specular factor 0).
inline Material lambert(Rgb albedo, Rgb emission = Rgb(0.0f)) {
    Material mat;
    mat.name = "lambert";
    mat.base_color = albedo;
    mat.metallic = 0;
    mat.roughness = 1;
    mat.specular = 0;
    mat.emission = emission;
    mat.double_sided = true;
    return mat;
}

inline Camera camera_at(Vec3 position, float yfov = 1.0f) {
    Camera c;
    c.name = "test";
    c.yfov = yfov;
    c.aspect_ratio = 1;
    c.camera_to_world = translation(position);
    return c;
}

}  // namespace veach::test
