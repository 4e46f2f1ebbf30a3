#include "load/scene_info.h"

#include <cmath>

#include <nlohmann/json.hpp>

namespace veach {

std::string scene_info_json(const Scene& scene) {
    using json = nlohmann::ordered_json;
    json j;
    j["source"] = scene.source_path;
    const SceneCatalog& c = scene.catalog;
    json scenes = json::array();
    for (size_t i = 0; i < c.scenes.size(); ++i)
        scenes.push_back({{"index", i}, {"name", c.scenes[i]}, {"default", static_cast<int>(i) == c.default_scene}});
    j["scenes"] = scenes;
    j["variants"] = c.variants;
    j["animations"] = c.animations;
    json cameras = json::array();
    for (const Camera& cam : scene.cameras) {
        json o = {{"name", cam.name}, {"type", cam.orthographic ? "orthographic" : "perspective"}};
        if (cam.orthographic)
            o["xmag"] = cam.xmag, o["ymag"] = cam.ymag;
        else
            o["yfov_degrees"] = cam.yfov * 180.0 / M_PI;
        if (cam.aspect_ratio > 0) o["aspect_ratio"] = cam.aspect_ratio;
        cameras.push_back(std::move(o));
    }
    j["cameras"] = cameras;
    long long point = 0, spot = 0, sun = 0, area = 0, emissive = 0;
    for (const PunctualLight& l : scene.lights) {
        switch (l.type) {
            case LightType::Point: ++point; break;
            case LightType::Spot: ++spot; break;
            case LightType::Directional: ++sun; break;
            case LightType::Area: ++area; break;
        }
    }
    long long emissive_triangles = 0;
    for (const Instance& inst : scene.instances) {
        const Mesh& mesh = scene.meshes[inst.mesh];
        if (!scene.material_of(mesh).is_emissive()) continue;
        ++emissive;
        emissive_triangles += static_cast<long long>(mesh.indices.size() / 3);
    }
    j["lights"] = {{"point", point},
                   {"spot", spot},
                   {"sun", sun},
                   {"area", area},
                   {"emissive_meshes", emissive},
                   {"emissive_triangles", emissive_triangles},
                   {"environment", scene.environment.enabled
                                       ? (scene.environment.has_map() ? "map" : "uniform")
                                       : "none"}};
    long long mesh_triangles = 0;
    for (const Mesh& m : scene.meshes) mesh_triangles += static_cast<long long>(m.indices.size() / 3);
    j["meshes"] = scene.meshes.size();
    j["instances"] = scene.instances.size();
    j["triangles"] = scene.triangle_count();
    j["mesh_triangles"] = mesh_triangles;
    j["materials"] = scene.materials.size();
    json textures = json::array();
    for (const Texture& t : scene.textures)
        textures.push_back({{"name", t.name},
                            {"width", t.width},
                            {"height", t.height},
                            {"bytes", t.stored_bytes()},
                            {"srgb", t.srgb}});
    j["textures"] = textures;
    j["features"] = scene.features.names();
    j["warnings"] = scene.warnings;
    const RepairCounts& r = scene.repaired;
    j["repaired"] = {{"invalid_indices", r.invalid_indices},
                     {"nonfinite_triangles", r.nonfinite_triangles},
                     {"degenerate_triangles", r.degenerate_triangles},
                     {"duplicate_triangles", r.duplicate_triangles},
                     {"normals_replaced", r.normals_replaced},
                     {"normals_normalized", r.normals_normalized},
                     {"uvs_replaced", r.uvs_replaced},
                     {"colors_replaced", r.colors_replaced},
                     {"lights_dropped", r.lights_dropped}};
    return j.dump(1, ' ', false, json::error_handler_t::replace);
}

}  // namespace veach
