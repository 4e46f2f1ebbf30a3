#include "importers/gltf/gltf_materials.h"

#include "textures/texel_codec.h"

#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>

#include <tiny_gltf.h>

// libtinygltf.so takes stb_image from libstb.so, which we don't link; a private copy with
// internal linkage (STB_IMAGE_STATIC) cannot clash with it. Core glTF images are PNG or JPEG.
#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#define STBI_ONLY_PNG
#define STBI_ONLY_JPEG
#define STBI_NO_STDIO
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Wsign-compare"
#include <stb/stb_image.h>
#pragma GCC diagnostic pop

#include "importers/gltf/spec_range.h"
#include "scene/light_units.h"
#include "textures/image_reader.h"

namespace veach::gltf {
namespace {

// 2^28 texels is 1 GiB as 8-bit RGBA and 4 GiB as float RGBA (OpenImageIO images).
constexpr uint64_t k_max_texels = 1ull << 28;

template <size_t N>
bool numbers(const tinygltf::Value* array, std::array<double, N>& out) {
    return json_numbers(array, out.data(), N);
}

template <size_t N>
bool numbers(const std::vector<double>& values, std::array<double, N>& out) {
    if (values.size() != N) return false;
    for (double v : values)
        if (!std::isfinite(v)) return false;
    std::copy(values.begin(), values.end(), out.begin());
    return true;
}

Rgb to_rgb(const std::array<double, 3>& c) {
    return {static_cast<float>(c[0]), static_cast<float>(c[1]), static_cast<float>(c[2])};
}

WrapMode wrap_mode(int gl_wrap) {
    switch (gl_wrap) {
        case TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE: return WrapMode::ClampToEdge;
        case TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT: return WrapMode::MirroredRepeat;
        default: return WrapMode::Repeat;
    }
}

std::string stb_reason() {
    const char* reason = stbi_failure_reason();  // thread-local in stb_image
    return reason ? reason : "unknown error";
}

// Factors are held to the spec's ranges (spec_range.h); emission strength to
// k_max_emission_strength (scene/light_units.h).

struct StbFree {
    void operator()(void* p) const { stbi_image_free(p); }
};

}  // namespace

MaterialConverter::MaterialConverter(const tinygltf::Model& model, ImportContext& context)
    : m_model(model),
      m_context(context),
      m_material_slots(model.materials.size(), -1),
      m_emissive(model.materials.size(), {Rgb(0.0f), 1.0f}) {}

int32_t MaterialConverter::material(int index) {
    if (index < 0 || static_cast<size_t>(index) >= m_model.materials.size())
        throw GltfError("material " + std::to_string(index) + " does not exist (the file has " +
                        std::to_string(m_model.materials.size()) + ")");
    if (m_material_slots[index] < 0) {
        Material converted = convert(index);
        m_material_slots[index] = static_cast<int32_t>(m_context.scene.materials.size());
        m_context.scene.materials.push_back(std::move(converted));
    }
    return m_material_slots[index];
}

MaterialRest MaterialConverter::rest(int index) const {
    MaterialRest r;
    if (index < 0 || size_t(index) >= m_material_slots.size() || m_material_slots[size_t(index)] < 0) return r;
    r.material = m_material_slots[size_t(index)];
    const Material& m = m_context.scene.materials[size_t(r.material)];
    r.unlit = m.unlit;
    r.base_color = m.unlit ? m.emission : m.base_color;  // unlit moved its base colour into the emission
    r.base_alpha = m.base_alpha;
    r.metallic = m.metallic;
    r.roughness = m.roughness;
    r.emissive_factor = m_emissive[size_t(index)].first;
    r.emissive_strength = m_emissive[size_t(index)].second;
    r.alpha_cutoff = m.alpha_cutoff;
    return r;
}

Material MaterialConverter::convert(int index) {
    const tinygltf::Material& src = m_model.materials[index];
    const tinygltf::PbrMetallicRoughness& pbr = src.pbrMetallicRoughness;
    std::string what = "material " + std::to_string(index) + (src.name.empty() ? "" : " '" + src.name + "'");
    auto info = [](const auto& texture_info) {
        return TextureInfoFields{texture_info.index, texture_info.texCoord,
                                 json_extension(texture_info.extensions, "KHR_texture_transform")};
    };
    auto json_info = [](const tinygltf::Value* v) {
        TextureInfoFields f;
        if (!v) return f;
        f.index = json_integer(v, "index", -1);
        f.tex_coord = json_integer(v, "texCoord", 0);
        f.transform = json_member(json_member(v, "extensions"), "KHR_texture_transform");
        return f;
    };

    Material m;
    m.name = src.name.empty() ? "material " + std::to_string(index) : src.name;

    std::array<double, 4> base{1, 1, 1, 1};
    if (!numbers(pbr.baseColorFactor, base)) m_context.warn(what + ": invalid baseColorFactor, using white");
    in_range(base, 0.0, 1.0, "baseColorFactor", m_context);
    m.base_color = to_rgb({base[0], base[1], base[2]});
    m.base_alpha = static_cast<float>(base[3]);
    m.base_color_texture = texture_ref(info(pbr.baseColorTexture), ColorSpace::Srgb, what + " baseColorTexture");
    m.metallic = std::isfinite(pbr.metallicFactor)
                     ? static_cast<float>(in_range(pbr.metallicFactor, 0.0, 1.0, "metallicFactor", m_context))
                     : 1.0f;
    m.roughness = std::isfinite(pbr.roughnessFactor)
                      ? static_cast<float>(in_range(pbr.roughnessFactor, 0.0, 1.0, "roughnessFactor", m_context))
                      : 1.0f;
    m.metallic_roughness_texture =
        texture_ref(info(pbr.metallicRoughnessTexture), ColorSpace::Linear, what + " metallicRoughnessTexture");

    // Blender writes emission brighter than 1 as emissiveFactor x emissiveStrength.
    std::array<double, 3> emissive{0, 0, 0};
    if (!src.emissiveFactor.empty() && !numbers(src.emissiveFactor, emissive))
        m_context.warn(what + ": invalid emissiveFactor, using black");
    const tinygltf::Value* strength_ext = json_extension(src.extensions, "KHR_materials_emissive_strength");
    in_range(emissive, 0.0, 1.0, "emissiveFactor", m_context);
    double strength = in_range(json_number(strength_ext, "emissiveStrength", 1.0), 0.0,
                               double(k_max_emission_strength), "emissiveStrength", m_context);
    m.emission = to_rgb(emissive) * static_cast<float>(strength);
    m_emissive[size_t(index)] = {to_rgb(emissive), static_cast<float>(strength)};
    m.emissive_texture = texture_ref(info(src.emissiveTexture), ColorSpace::Srgb, what + " emissiveTexture");

    m.normal_texture = texture_ref(info(src.normalTexture), ColorSpace::Linear, what + " normalTexture");
    m.normal_scale = std::isfinite(src.normalTexture.scale) ? static_cast<float>(src.normalTexture.scale) : 1.0f;

    m.ior = static_cast<float>(json_number(json_extension(src.extensions, "KHR_materials_ior"), "ior", 1.5));

    if (const tinygltf::Value* spec = json_extension(src.extensions, "KHR_materials_specular")) {
        m.specular = static_cast<float>(
            in_range(json_number(spec, "specularFactor", 1.0), 0.0, 1.0, "specularFactor", m_context));
        std::array<double, 3> color{1, 1, 1};
        if (json_member(spec, "specularColorFactor") && !numbers(json_member(spec, "specularColorFactor"), color))
            m_context.warn(what + ": invalid specularColorFactor, using white");
        // No upper bound in KHR_materials_specular (F0 is clamped to 1 where it is used).
        in_range(color, 0.0, double(k_max_emission_strength), "specularColorFactor", m_context);
        m.specular_color = to_rgb(color);
        m.specular_texture =
            texture_ref(json_info(json_member(spec, "specularTexture")), ColorSpace::Linear, what + " specularTexture");
        m.specular_color_texture = texture_ref(json_info(json_member(spec, "specularColorTexture")), ColorSpace::Srgb,
                                               what + " specularColorTexture");
    }

    if (const tinygltf::Value* tr = json_extension(src.extensions, "KHR_materials_transmission")) {
        m.transmission = static_cast<float>(
            in_range(json_number(tr, "transmissionFactor", 0.0), 0.0, 1.0, "transmissionFactor", m_context));
        m.transmission_texture = texture_ref(json_info(json_member(tr, "transmissionTexture")), ColorSpace::Linear,
                                             what + " transmissionTexture");
    }

    if (const tinygltf::Value* vol = json_extension(src.extensions, "KHR_materials_volume")) {
        std::array<double, 3> color{1, 1, 1};
        if (json_member(vol, "attenuationColor") && !numbers(json_member(vol, "attenuationColor"), color))
            m_context.warn(what + ": invalid attenuationColor, using white");
        in_range(color, 0.0, 1.0, "attenuationColor", m_context);
        m.attenuation_color = to_rgb(color);
        double distance = json_number(vol, "attenuationDistance", 0.0);  // absent: infinite
        m.attenuation_distance = std::isfinite(distance) && distance > 0.0 ? static_cast<float>(distance) : 0.0f;
    }
    if (const tinygltf::Value* cc = json_extension(src.extensions, "KHR_materials_clearcoat")) {
        m.clearcoat = static_cast<float>(
            in_range(json_number(cc, "clearcoatFactor", 0.0), 0.0, 1.0, "clearcoatFactor", m_context));
        m.clearcoat_roughness = static_cast<float>(in_range(json_number(cc, "clearcoatRoughnessFactor", 0.0), 0.0, 1.0,
                                                            "clearcoatRoughnessFactor", m_context));
        m.clearcoat_texture =
            texture_ref(json_info(json_member(cc, "clearcoatTexture")), ColorSpace::Linear, what + " clearcoatTexture");
        m.clearcoat_roughness_texture = texture_ref(json_info(json_member(cc, "clearcoatRoughnessTexture")),
                                                    ColorSpace::Linear, what + " clearcoatRoughnessTexture");
        const tinygltf::Value* normal = json_member(cc, "clearcoatNormalTexture");
        m.clearcoat_normal_texture =
            texture_ref(json_info(normal), ColorSpace::Linear, what + " clearcoatNormalTexture");
        m.clearcoat_normal_scale = static_cast<float>(json_number(normal, "scale", 1.0));
    }
    if (const tinygltf::Value* sh = json_extension(src.extensions, "KHR_materials_sheen")) {
        std::array<double, 3> color{0, 0, 0};
        if (json_member(sh, "sheenColorFactor") && !numbers(json_member(sh, "sheenColorFactor"), color))
            m_context.warn(what + ": invalid sheenColorFactor, using black");
        in_range(color, 0.0, 1.0, "sheenColorFactor", m_context);
        m.sheen_color = to_rgb(color);
        m.sheen_roughness = static_cast<float>(
            in_range(json_number(sh, "sheenRoughnessFactor", 0.0), 0.0, 1.0, "sheenRoughnessFactor", m_context));
        m.sheen_color_texture =
            texture_ref(json_info(json_member(sh, "sheenColorTexture")), ColorSpace::Srgb, what + " sheenColorTexture");
        m.sheen_roughness_texture = texture_ref(json_info(json_member(sh, "sheenRoughnessTexture")), ColorSpace::Linear,
                                                what + " sheenRoughnessTexture");
    }
    if (json_extension(src.extensions, "KHR_materials_unlit")) {
        // Unlit: the base colour is what the viewer sees, whatever the lighting. In a path
        // tracer that is a surface emitting its base colour as radiance and scattering nothing:
        // it shows exactly its colour to the camera (and, consistently, lights its surroundings).
        m.unlit = true;
        m.emission = m.base_color;
        m.emissive_texture = m.base_color_texture;
        m.base_color = Rgb(0.0f);
        m.base_color_texture = TextureRef{};
        m.metallic = 0.0f;
        m.specular = 0.0f;
        m.transmission = 0.0f;
        m.transmission_texture = TextureRef{};
        m.clearcoat = 0.0f;
        m.sheen_color = Rgb(0.0f);
    }

    m.double_sided = src.doubleSided;
    if (src.alphaMode == "MASK") {
        m.alpha_mode = AlphaMode::Mask;
    } else if (src.alphaMode == "BLEND") {
        m.alpha_mode = AlphaMode::Blend;
    } else if (src.alphaMode != "OPAQUE" && !src.alphaMode.empty()) {
        m_context.warn(what + ": unknown alphaMode '" + src.alphaMode + "', treated as OPAQUE");
    }
    m.alpha_cutoff = std::isfinite(src.alphaCutoff) ? static_cast<float>(src.alphaCutoff) : 0.5f;

    SceneFeatures& features = m_context.scene.features;
    for (const TextureRef* ref : {&m.base_color_texture, &m.metallic_roughness_texture, &m.emissive_texture,
                                  &m.normal_texture, &m.specular_texture, &m.specular_color_texture,
                                  &m.transmission_texture, &m.clearcoat_texture, &m.clearcoat_roughness_texture,
                                  &m.clearcoat_normal_texture, &m.sheen_color_texture, &m.sheen_roughness_texture})
        features.textures |= ref->valid();
    features.normal_maps |= m.normal_texture.valid() || (m.clearcoat > 0.0f && m.clearcoat_normal_texture.valid());
    features.alpha |= m.alpha_mode != AlphaMode::Opaque;
    features.transmission |= m.transmission > 0.0f || m.transmission_texture.valid();
    features.volume |= (m.transmission > 0.0f || m.transmission_texture.valid()) && m.attenuation_distance > 0.0f;
    features.clearcoat |= m.clearcoat > 0.0f;
    features.sheen |= !m.sheen_color.is_black();
    return m;
}

TextureRef MaterialConverter::texture_ref(const TextureInfoFields& info, ColorSpace space, const std::string& what) {
    TextureRef ref;
    if (info.index == -1) return ref;  // absent
    ref.texture = texture(info.index, space, what);
    if (!ref.valid()) return ref;
    ref.texcoord = info.tex_coord;
    if (const tinygltf::Value* t = info.transform) {
        std::array<double, 2> offset{0, 0}, scale{1, 1};
        numbers(json_member(t, "offset"), offset);
        numbers(json_member(t, "scale"), scale);
        ref.transform.offset[0] = static_cast<float>(offset[0]);
        ref.transform.offset[1] = static_cast<float>(offset[1]);
        ref.transform.scale[0] = static_cast<float>(scale[0]);
        ref.transform.scale[1] = static_cast<float>(scale[1]);
        ref.transform.rotation = static_cast<float>(json_number(t, "rotation", 0.0));
        // The extension may redirect the lookup to another TEXCOORD set.
        ref.texcoord = json_integer(t, "texCoord", ref.texcoord);
    }
    if (ref.texcoord < 0) throw GltfError(what + ": invalid texCoord");
    if (ref.texcoord > 1)
        m_context.warn(what + " uses TEXCOORD_" + std::to_string(ref.texcoord) +
                       "; only TEXCOORD_0 and TEXCOORD_1 are loaded");
    return ref;
}

int32_t MaterialConverter::texture(int index, ColorSpace space, const std::string& what) {
    if (index < 0 || static_cast<size_t>(index) >= m_model.textures.size())
        throw GltfError(what + ": texture " + std::to_string(index) + " does not exist (the file has " +
                        std::to_string(m_model.textures.size()) + ")");
    auto key = std::make_pair(index, space);
    if (auto it = m_textures.find(key); it != m_textures.end()) return it->second;

    int32_t slot = -1;
    int source = image_source(index, what);
    if (source < 0) {
        // Typically the image is only given through an image-format extension we don't support.
        m_context.warn(what + ": texture " + std::to_string(index) + " has no image we can load; ignored");
    } else {
        Texture decoded = decode(index, source, space, what);
        slot = static_cast<int32_t>(m_context.scene.textures.size());
        m_context.scene.textures.push_back(std::move(decoded));
    }
    m_textures.emplace(key, slot);
    return slot;
}

int MaterialConverter::image_source(int texture_index, const std::string& what) const {
    const tinygltf::Texture& src = m_model.textures[texture_index];
    if (const tinygltf::Value* webp = json_extension(src.extensions, "EXT_texture_webp")) {
        int image = json_integer(webp, "source", -1);
        if (image >= 0) return image;
    }
    if (src.source < 0 && json_extension(src.extensions, "KHR_texture_basisu")) {
        const auto& required = m_model.extensionsRequired;
        if (std::find(required.begin(), required.end(), "KHR_texture_basisu") != required.end())
            throw GltfError(what + ": texture " + std::to_string(texture_index) +
                            " is KHR_texture_basisu (KTX2) only: Veach cannot transcode BasisU (Debian has no "
                            "transcoder) and the texture has no fallback source");
    }
    return src.source;
}

Texture MaterialConverter::decode(int texture_index, int image_index, ColorSpace space, const std::string& what) {
    const tinygltf::Texture& src = m_model.textures[texture_index];
    if (static_cast<size_t>(image_index) >= m_model.images.size())
        throw GltfError(what + ": texture " + std::to_string(texture_index) + " uses image " +
                        std::to_string(image_index) + ", which does not exist");
    const tinygltf::Image& image = m_model.images[image_index];
    std::string where = what + ": image " + std::to_string(image_index) +
                        (image.uri.empty() || image.uri.starts_with("data:") ? "" : " '" + image.uri + "'");

    // Checked before decoding so a bad reference doesn't cost a decode.
    const tinygltf::Sampler* sampler = nullptr;
    if (src.sampler >= 0 && static_cast<size_t>(src.sampler) < m_model.samplers.size())
        sampler = &m_model.samplers[src.sampler];
    else if (src.sampler != -1)
        throw GltfError(what + ": texture " + std::to_string(texture_index) + " uses sampler " +
                        std::to_string(src.sampler) + ", which does not exist");

    // The loader kept the encoded bytes (see keep_encoded_image in gltf_importer.cpp); images
    // in a bufferView are read straight from the checked view.
    std::span<const uint8_t> bytes(image.image.data(), image.image.size());
    if (image.bufferView >= 0) bytes = buffer_view_bytes(m_model, image.bufferView, where);
    if (bytes.empty()) {
        if (auto why = m_unreadable.find(image.uri); why != m_unreadable.end())
            throw GltfError(where + ": " + why->second);
        throw GltfError(where + ": no image data (missing or unreadable file?)");
    }
    if (bytes.size() > static_cast<size_t>(INT_MAX)) throw GltfError(where + ": image data too large");
    int size = static_cast<int>(bytes.size());

    int width = 0, height = 0, channels = 0;
    if (!stbi_info_from_memory(bytes.data(), size, &width, &height, &channels)) {
        // Not PNG or JPEG (what Blender writes) but perhaps EXR, TIFF, ... from another tool:
        // OpenImageIO. Float images hold linear values, so a colour texture from one is stored
        // linear (srgb = false); integer images keep their encoded values, as from stb.
        ImageData img;
        std::string name = !image.uri.empty() && !image.uri.starts_with("data:") ? image.uri : "image";
        if (image.mimeType == "image/x-exr" || image.mimeType == "image/exr")
            name += ".exr";
        else if (image.mimeType == "image/tiff")
            name += ".tif";
        else if (image.mimeType == "image/webp")
            name += ".webp";
        try {
            // The decoded size is charged from the header, before OpenImageIO allocates it.
            img = read_image_memory(bytes.data(), bytes.size(), name, [&](int w, int h) {
                uint64_t count = static_cast<uint64_t>(w) * static_cast<uint64_t>(h);
                if (count > k_max_texels)
                    throw GltfError(where + ": image size " + std::to_string(w) + "x" + std::to_string(h) +
                                    " is out of range");
                m_context.charge(count * 4 * sizeof(float), where, Budget::Textures);
            });
        } catch (const ImageReadError& e) {
            // stb said only that it is not PNG or JPEG; OpenImageIO's reason is the one that tells.
            std::string reason = e.what();
            if (reason.starts_with(name + ": ")) reason = reason.substr(name.size() + 2);
            throw GltfError(where + ": cannot decode (" + reason + ")");
        }
        Texture tex;
        tex.name = !image.name.empty() ? image.name : "image " + std::to_string(image_index);
        tex.width = img.width;
        tex.height = img.height;
        if (img.eight_bit) {
            // Back to the bytes the file holds (8-bit WebP, TIFF, ...): a quarter of the floats,
            // and the same texels stb would have given for a PNG of them.
            tex.texels8.resize(img.rgba.size());
            for (size_t i = 0; i < img.rgba.size(); ++i) tex.texels8[i] = encode_unorm8(img.rgba[i]);
            std::vector<float>().swap(img.rgba);
        } else {
            tex.texels = std::move(img.rgba);
        }
        tex.srgb = space == ColorSpace::Srgb && img.srgb_encoded;
        if (sampler) {
            tex.wrap_s = wrap_mode(sampler->wrapS);
            tex.wrap_t = wrap_mode(sampler->wrapT);
            tex.nearest = sampler->magFilter == TINYGLTF_TEXTURE_FILTER_NEAREST;
            // minFilter NEAREST or LINEAR asks for no mip-mapping (Blender writes LINEAR_MIPMAP_LINEAR
            // for Linear, NEAREST_MIPMAP_NEAREST for Closest).
            tex.mipmaps = sampler->minFilter != TINYGLTF_TEXTURE_FILTER_NEAREST &&
                          sampler->minFilter != TINYGLTF_TEXTURE_FILTER_LINEAR;
        }
        return tex;
    }
    uint64_t texels = static_cast<uint64_t>(width) * static_cast<uint64_t>(height);
    if (width <= 0 || height <= 0 || texels > k_max_texels)
        throw GltfError(where + ": image size " + std::to_string(width) + "x" + std::to_string(height) +
                        " is out of range");
    bool sixteen = stbi_is_16_bit_from_memory(bytes.data(), size) != 0;
    // The texels are kept at the file's precision (Texture in scene/scene.h): 4 bytes a texel
    // for 8-bit images, 8 for 16-bit ones.
    m_context.charge(texels * 4 * (sixteen ? 2 : 1), where, Budget::Textures);
    // stb's own buffers while it decodes, gone when it returns: the image as stored (up to 4
    // channels), the same expanded to RGBA, and for PNG the inflated rows before unfiltering.
    // Charged for the decode and released after, so that a small file declaring a huge image is
    // refused before stb allocates, not after.
    const uint64_t stb_scratch = texels * 4 * (sixteen ? 2 : 1) * 3;
    ScopedCharge scratch(m_context, stb_scratch, where + " (decoding)", Budget::Textures);

    std::unique_ptr<void, StbFree> pixels;
    int w = 0, h = 0;
    if (sixteen)
        pixels.reset(stbi_load_16_from_memory(bytes.data(), size, &w, &h, &channels, 4));
    else
        pixels.reset(stbi_load_from_memory(bytes.data(), size, &w, &h, &channels, 4));
    if (!pixels) throw GltfError(where + ": cannot decode (" + stb_reason() + ")");
    if (w != width || h != height) throw GltfError(where + ": inconsistent image header");

    Texture tex;
    tex.name = !image.name.empty()                                     ? image.name
               : !image.uri.empty() && !image.uri.starts_with("data:") ? image.uri
                                                                       : "image " + std::to_string(image_index);
    tex.width = width;
    tex.height = height;
    // stb_image returns rows top first, which is Texture's layout; glTF's v = 0 is the top row.
    size_t n = static_cast<size_t>(texels) * 4;
    // Colour textures keep their sRGB-encoded values: the lookup filters them and decodes the
    // result, as Cycles does with 8-bit images (texture.h explains the choice).
    tex.srgb = space == ColorSpace::Srgb;
    if (sixteen) {
        const uint16_t* p = static_cast<const uint16_t*>(pixels.get());
        tex.texels16.assign(p, p + n);
    } else {
        const uint8_t* p = static_cast<const uint8_t*>(pixels.get());
        tex.texels8.assign(p, p + n);
    }

    if (sampler) {
        tex.wrap_s = wrap_mode(sampler->wrapS);
        tex.wrap_t = wrap_mode(sampler->wrapT);
        tex.nearest = sampler->magFilter == TINYGLTF_TEXTURE_FILTER_NEAREST;
        tex.mipmaps = sampler->minFilter != TINYGLTF_TEXTURE_FILTER_NEAREST &&
                      sampler->minFilter != TINYGLTF_TEXTURE_FILTER_LINEAR;
    }
    return tex;
}

}  // namespace veach::gltf
