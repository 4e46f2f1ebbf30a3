#include "materials/alpha.h"

#include "materials/texture_sampling.h"
#include "scene/surface_attributes.h"

namespace veach {

float surface_alpha(const Scene& scene, const Mesh& mesh, const Material& material, uint32_t prim, float b1, float b2) {
    float alpha = material.base_alpha;
    const uint32_t* idx = &mesh.indices[static_cast<size_t>(prim) * 3];
    float b0 = 1.0f - b1 - b2;
    if (!mesh.colors.empty())
        alpha *= barycentric(mesh.colors[idx[0]].a, mesh.colors[idx[1]].a, mesh.colors[idx[2]].a, b0, b1, b2);
    const TextureRef& ref = material.base_color_texture;
    if (ref.valid() && static_cast<size_t>(ref.texture) < scene.textures.size()) {
        const std::vector<Vec2>& uv = ref.texcoord == 1 ? mesh.uv1 : mesh.uv0;
        Vec2 st;
        if (!uv.empty()) st = interpolate_vertices(uv, idx, b0, b1, b2);
        alpha *=
            sample_texture(scene.textures[static_cast<size_t>(ref.texture)], apply_uv_transform(ref.transform, st)).a;
    }
    return alpha;
}

}  // namespace veach
