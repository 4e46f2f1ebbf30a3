// A glTF material at one surface point: textures combined with factors into ShadingInputs, the
// parameters the BSDF (gltf_bsdf.h) is built from.
#pragma once

#include "core/rgb.h"
#include "scene/scene.h"
#include "scene/surface_attributes.h"

namespace veach {

// A material's parameters at one surface point, after textures.
struct ShadingInputs {
    Rgb base_color{1, 1, 1};
    float opacity = 1;
    float metallic = 0;
    float alpha = 1;  // GGX alpha = roughness^2
    Rgb dielectric_f0{0.04f, 0.04f, 0.04f};
    float dielectric_f90 = 1;
    float transmission = 0;     // KHR_materials_transmission
    float ior = 1.5f;           // KHR_materials_ior: the relative index of a transmissive interior
    // A thin wall (no interior, KHR_materials_volume's thin-walled case): transmission passes
    // straight through, the reflection lobe mirrored to the far side, with no 1/eta^2; both sides
    // are air, so the index is ior from either side. Set from SurfaceHit::thin_walled.
    bool thin_walled = false;
    float clearcoat = 0;        // KHR_materials_clearcoat factor
    float clearcoat_alpha = 0;  // its GGX alpha = clearcoat roughness^2
    Rgb sheen_color{0, 0, 0};   // KHR_materials_sheen
    float sheen_roughness = 0;
    Rgb emission;
};

// One texture of a material at a surface point: the TextureRef's UV set, KHR_texture_transform
// and the ray's footprint in that set (mip level). `ref` must name a texture of `scene`.
Rgba lookup_texture(const TextureRef& ref, const Scene& scene, const SurfaceAttributes& attr);

// Looks up the material's textures and combines them with its factors.
ShadingInputs evaluate_material(const Material& m, const Scene& scene, const SurfaceAttributes& attr);
// Only the emitted radiance (cheaper, for light sampling).
Rgb evaluate_emission(const Material& m, const Scene& scene, const SurfaceAttributes& attr);

}  // namespace veach
