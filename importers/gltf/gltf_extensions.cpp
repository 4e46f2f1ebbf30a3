#include "importers/gltf/gltf_extensions.h"

#include <algorithm>

namespace veach::gltf {

namespace {

// Add a name here in the same change that makes the importer read the extension, and mark it
// "yes" in README's table of glTF extensions.
constexpr std::string_view k_supported[] = {
    "KHR_draco_mesh_compression", "KHR_lights_punctual",
    "KHR_materials_clearcoat",    "KHR_materials_emissive_strength",
    "KHR_materials_ior",          "KHR_materials_sheen",
    "KHR_materials_specular",     "KHR_materials_transmission",
    "KHR_materials_unlit",        "KHR_materials_variants",
    "KHR_materials_volume",       "KHR_mesh_quantization",
    "KHR_texture_basisu",  // its fallback `source` renders; a BasisU-only texture is refused
    "KHR_texture_transform",      "EXT_mesh_gpu_instancing",
    "EXT_meshopt_compression",
    "EXT_texture_webp",           "VEACH_lights_blender",
    "KHR_animation_pointer",  // material factors, light colour and intensity, camera fields (README)
};

}  // namespace

std::span<const std::string_view> supported_extensions() { return k_supported; }

bool is_supported_extension(std::string_view name) {
    return std::find(std::begin(k_supported), std::end(k_supported), name) != std::end(k_supported);
}

}  // namespace veach::gltf
