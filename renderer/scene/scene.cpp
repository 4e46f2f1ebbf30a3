#include "scene/scene.h"

#include "scene/mesh_corners.h"

namespace veach {

Bounds3 Scene::bounds_of(const Instance& inst) const {
    Bounds3 b;
    // The triangles' corners only: repair leaves unreferenced and non-finite vertices in place.
    const Mesh& mesh = meshes[inst.mesh];
    for (uint32_t i : mesh.indices)
        if (i < mesh.positions.size() && is_finite(mesh.positions[i]))
            b.extend(inst.object_to_world.point(mesh.positions[i]));
    return b;
}

Bounds3 Scene::bounds() const {
    Bounds3 b;
    MeshCorners corners(*this);
    for (const Instance& inst : instances) b.extend(corners.bounds_of(inst));
    return b;
}

size_t Scene::triangle_count() const {
    size_t n = 0;
    for (const Instance& inst : instances) n += meshes[inst.mesh].triangle_count();
    return n;
}

const Material& Scene::default_material() {
    // The glTF spec's default material: white, metallic 1, roughness 1, single-sided.
    static const Material m = [] {
        Material d;
        d.name = "default";
        return d;
    }();
    return m;
}

Material Scene::blender_default_material() {
    Material m;
    m.name = "Cycles default surface";
    m.base_color = Rgb(0.8f);
    m.metallic = 0;
    m.roughness = 1;
    m.specular = 0;
    return m;
}

const Material& Scene::material_of(const Mesh& mesh) const {
    if (mesh.material >= 0 && static_cast<size_t>(mesh.material) < materials.size()) return materials[mesh.material];
    return default_material();
}

std::vector<std::string> SceneFeatures::names() const {
    std::vector<std::string> out;
    auto add = [&](bool on, const char* name) {
        if (on) out.emplace_back(name);
    };
    add(textures, "textures");
    add(normal_maps, "normal_maps");
    add(alpha, "alpha");
    add(transmission, "transmission");
    add(volume, "volume");
    add(clearcoat, "clearcoat");
    add(sheen, "sheen");
    add(punctual_lights, "punctual_lights");
    add(emissive_meshes, "emissive_meshes");
    add(environment, "environment");
    add(instancing, "instancing");
    add(vertex_colors, "vertex_colors");
    return out;
}

}  // namespace veach
