// glTF materials and textures into Scene::materials and Scene::textures. Both are converted on
// first use, so a file's unused materials cost nothing and only images that a rendered
// material samples are ever decoded.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "importers/gltf/gltf_accessors.h"

namespace tinygltf {
class Value;
}

namespace veach::gltf {

enum class ColorSpace : uint8_t {
    Srgb,    // colour data (base colour, emissive, specular colour): decoded to linear
    Linear,  // non-colour data (metallic-roughness, normals, specular factor): c / max
};

class MaterialConverter {
public:
    MaterialConverter(const tinygltf::Model& model, ImportContext& context);

    // The Scene::materials index of glTF material `index`, converting it the first time.
    int32_t material(int index);

    // What KHR_animation_pointer channels on glTF material `index` start from: its factors as
    // converted (clamped to the spec's ranges) and its Scene::materials index, -1 when no
    // primitive used it.
    MaterialRest rest(int index) const;

    // Image files that exist but could not be read (uri -> why: a FIFO, a device, a folder), so
    // that a texture using one is refused with the reason.
    void set_unreadable_images(std::map<std::string, std::string> why_by_uri) { m_unreadable = std::move(why_by_uri); }

private:
    // A textureInfo's fields, from tinygltf's structs or from an extension's JSON value.
    struct TextureInfoFields {
        int index = -1;
        int tex_coord = 0;
        const tinygltf::Value* transform = nullptr;  // KHR_texture_transform, or null
    };

    Material convert(int index);
    TextureRef texture_ref(const TextureInfoFields& info, ColorSpace space, const std::string& what);
    int32_t texture(int index, ColorSpace space, const std::string& what);
    // The image a texture shows: EXT_texture_webp's when it has one (OpenImageIO decodes WebP),
    // else `source`, which is KHR_texture_basisu's fallback (Debian has no BasisU transcoder).
    // -1 when there is none; a BasisU-only texture in a file that requires the extension is bad
    // input.
    int image_source(int texture_index, const std::string& what) const;
    Texture decode(int texture_index, int image_index, ColorSpace space, const std::string& what);

    const tinygltf::Model& m_model;
    ImportContext& m_context;
    std::vector<int32_t> m_material_slots;                     // glTF material -> scene index, -1 = not yet
    std::vector<std::pair<Rgb, float>> m_emissive;             // glTF material -> emissiveFactor, strength
    std::map<std::pair<int, ColorSpace>, int32_t> m_textures;  // (glTF texture, space) -> scene index
    std::map<std::string, std::string> m_unreadable;           // image uri -> why it could not be read
};

}  // namespace veach::gltf
