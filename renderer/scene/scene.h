// The scene as plain data: flat arrays addressed by integer handles, independent of any file
// format and of Embree. Importers fill it; the renderer prepares acceleration structures and
// light tables from it and never changes it.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/math.h"
#include "core/rgb.h"
#include "scene/scene_animation.h"
#include "scene/scene_features.h"
#include "scene/scene_motion.h"
#include "textures/mip_pyramid.h"

namespace veach {

enum class WrapMode : uint8_t { Repeat, ClampToEdge, MirroredRepeat };

// A decoded texture, RGBA. Colour textures (srgb = true) keep their sRGB-encoded values and are
// decoded to linear after filtering: Cycles filters 8-bit sRGB images in the encoded space, and
// filtering in linear space instead makes every edge of a magnified texture visibly brighter
// than Blender's render (5-30% on the textured scene). At texel centres both agree exactly.
//
// Texels keep the precision of their file: an 8-bit image as bytes (k / 255 when read), a 16-bit
// one as 16-bit words (k / 65535), a float one as floats; exactly one of the three vectors holds
// width * height * 4 values, row 0 the top of the image (v = 0). A 4096^2 8-bit texture costs
// 64 MiB, not the 256 MiB of float RGBA. Lookups read all three the same way (texture_sampling).
struct Texture {
    std::string name;
    int width = 0, height = 0;
    std::vector<float> texels;       // float images (EXR, HDR, ...) and textures made in code
    std::vector<uint8_t> texels8;    // 8-bit images (PNG, JPEG: what Blender writes)
    std::vector<uint16_t> texels16;  // 16-bit images
    // Values in the one vector that holds them (0 when the texture has no image).
    size_t stored_values() const { return texels8.size() + texels16.size() + texels.size(); }
    // Stored value i (of stored_values()) as the float a lookup reads before any decoding.
    float stored_value(size_t i) const {
        if (!texels8.empty()) return static_cast<float>(texels8[i]) / 255.0f;
        if (!texels16.empty()) return static_cast<float>(texels16[i]) / 65535.0f;
        return texels[i];
    }
    // Bytes of the stored texels.
    size_t stored_bytes() const {
        return texels8.size() + texels16.size() * sizeof(uint16_t) + texels.size() * sizeof(float);
    }
    bool srgb = false;          // RGB encoded with the sRGB transfer function; alpha always linear
    WrapMode wrap_s = WrapMode::Repeat, wrap_t = WrapMode::Repeat;
    bool nearest = false;  // magnification filter NEAREST; otherwise bilinear
    bool mipmaps = true;   // the sampler's minFilter is a *_MIPMAP_* one or unset: minified lookups may use levels
    MipCache mips;         // coarser levels, built by the first minified lookup
};

// KHR_texture_transform, applied to the texture coordinate before lookup.
struct UvTransform {
    float offset[2] = {0, 0};
    float rotation = 0;
    float scale[2] = {1, 1};
    bool is_identity() const {
        return offset[0] == 0 && offset[1] == 0 && rotation == 0 && scale[0] == 1 && scale[1] == 1;
    }
};

struct TextureRef {
    int32_t texture = -1;  // index into Scene::textures, -1 = none
    int32_t texcoord = 0;  // TEXCOORD_n set
    UvTransform transform;
    bool valid() const { return texture >= 0; }
};

enum class AlphaMode : uint8_t { Opaque, Mask, Blend };

// glTF metallic-roughness material with the extensions Blender writes. Factors multiply the
// textures as the glTF spec says.
struct Material {
    std::string name;
    Rgb base_color{1, 1, 1};
    float base_alpha = 1;
    TextureRef base_color_texture;
    float metallic = 1, roughness = 1;
    TextureRef metallic_roughness_texture;  // roughness in G, metallic in B
    Rgb emission{0, 0, 0};                  // emissiveFactor x KHR_materials_emissive_strength: radiance
    TextureRef emissive_texture;
    float ior = 1.5f;                   // KHR_materials_ior
    float specular = 1;                 // KHR_materials_specular specularFactor
    Rgb specular_color{1, 1, 1};        // KHR_materials_specular specularColorFactor
    TextureRef specular_texture;        // factor in A
    TextureRef specular_color_texture;  // colour in RGB (sRGB)
    float transmission = 0;             // KHR_materials_transmission transmissionFactor
    TextureRef transmission_texture;    // factor in R
    // KHR_materials_volume: Beer-Lambert absorption inside a transmissive closed mesh,
    // sigma_a = -ln(attenuation_color) / attenuation_distance (thicknessFactor is a raster hint).
    Rgb attenuation_color{1, 1, 1};
    float attenuation_distance = 0;  // 0 = infinite: nothing absorbed
    // KHR_materials_clearcoat: a GGX layer (F0 0.04, ior 1.5) over the material.
    float clearcoat = 0, clearcoat_roughness = 0;
    TextureRef clearcoat_texture;            // factor in R
    TextureRef clearcoat_roughness_texture;  // roughness in G
    TextureRef clearcoat_normal_texture;     // the coat's own normal map (surface_hit.cpp)
    float clearcoat_normal_scale = 1;
    // KHR_materials_sheen: Charlie sheen over the material.
    Rgb sheen_color{0, 0, 0};
    float sheen_roughness = 0;
    TextureRef sheen_color_texture;      // colour in RGB (sRGB)
    TextureRef sheen_roughness_texture;  // roughness in A
    // KHR_materials_unlit: converted by the importer into emission of the base colour and a
    // black BSDF (what "shown as is" means in a path tracer).
    bool unlit = false;
    TextureRef normal_texture;
    float normal_scale = 1;
    bool double_sided = false;
    AlphaMode alpha_mode = AlphaMode::Opaque;
    float alpha_cutoff = 0.5f;

    bool is_emissive() const { return !emission.is_black(); }
    bool has_textures() const {
        return base_color_texture.valid() || metallic_roughness_texture.valid() || emissive_texture.valid() ||
               specular_texture.valid() || specular_color_texture.valid() || transmission_texture.valid() ||
               clearcoat_texture.valid() || clearcoat_roughness_texture.valid() || clearcoat_normal_texture.valid() ||
               sheen_color_texture.valid() || sheen_roughness_texture.valid() || normal_texture.valid();
    }
    // sigma_a of KHR_materials_volume per unit length; zero when nothing is absorbed.
    Rgb absorption() const {
        if (!(attenuation_distance > 0.0f)) return Rgb(0.0f);
        auto one = [this](float c) {
            return c > 0.0f ? std::max(0.0f, -std::log(std::min(c, 1.0f))) / attenuation_distance : 1e30f;
        };
        return {one(attenuation_color.r), one(attenuation_color.g), one(attenuation_color.b)};
    }
};

// One glTF primitive: triangles with one material. Attributes are either empty or one per vertex.
struct Mesh {
    std::string name;
    std::vector<Vec3> positions;
    std::vector<Vec3> normals;  // empty: flat shading from the geometric normal
    std::vector<Vec2> uv0, uv1;
    // Tangent frames for normal maps (glTF TANGENT, or generated): only filled when the mesh's
    // material has a normal texture. Bitangent = cross(normal, tangent) * tangent_signs.
    std::vector<Vec3> tangents;
    std::vector<float> tangent_signs;  // +1 or -1 per vertex
    std::vector<Rgba> colors;          // COLOR_0
    std::vector<uint32_t> indices;     // three per triangle
    int32_t material = -1;             // -1: the glTF default material

    size_t triangle_count() const { return indices.size() / 3; }
};

// A placement of a mesh in the world. A glTF mesh used by several nodes becomes several
// instances of the same Mesh entries: stored once, instanced by the accelerator.
struct Instance {
    uint32_t mesh = 0;
    Transform object_to_world;
};

// Point and spot lights with a radius are spheres; a directional light with an angle is a sun
// disc; Area is Blender's area light (a rectangle or an ellipse, one-sided).
enum class LightType : uint8_t { Point, Spot, Directional, Area };
enum class AreaShape : uint8_t { Rectangle, Ellipse };

// How a spot light's intensity falls off inside its cone.
enum class SpotFalloff : uint8_t {
    Gltf,     // the glTF spec's recommended falloff between inner and outer cone
    Blender,  // Cycles 3.4: cos(theta) * smoothstep(t / ((1 - cos(size/2)) * blend))
};

// KHR_lights_punctual (and the shapes of VEACH_lights_blender), converted to Cycles' radiometry:
// point and spot intensity in W/sr, directional irradiance in W/m^2 (the photometric values
// Blender writes divided by 683), area radiance in W/(m^2 sr).
struct PunctualLight {
    std::string name;
    LightType type = LightType::Point;
    Rgb intensity;                         // colour x intensity, radiometric
    Vec3 position;                         // world
    Vec3 direction{0, 0, -1};              // world, the direction light travels (spot axis, sun direction)
    float cos_outer = -1, cos_inner = -1;  // spot cone
    float blend = 0;                       // Blender spot blend, derived from the cone angles
    SpotFalloff falloff = SpotFalloff::Gltf;
    float range = 0;   // 0 = infinite (the range cut-off is a real-time hint we ignore)
    float radius = 0;  // point and spot: the emitting sphere's radius (0: a true point)
    float angle = 0;   // directional: the sun's angular diameter, radians (0: a delta direction)
    // Area: centred on `position`, emitting along `direction`; `axis_u` and `axis_v` are the
    // half-extent vectors of the rectangle (or of the ellipse's bounding rectangle), world space.
    AreaShape shape = AreaShape::Rectangle;
    Vec3 axis_u, axis_v;
    Rgb radiance;  // area: W/(m^2 sr), colour included
};

struct Camera {
    std::string name;
    bool orthographic = false;
    float yfov = 0.8f;              // perspective vertical field of view, radians
    float aspect_ratio = 0;         // 0 = not given: use the image's
    float xmag = 1, ymag = 1;       // orthographic half extents
    float znear = 0.01f, zfar = 0;  // zfar 0 = infinite
    Transform camera_to_world;      // looks down -Z, +Y up (glTF convention)
};

// The world around the scene: glTF carries none, so a front end fills it (--env, --env-color).
// Radiance arriving from direction d is strength x (the map at d, or colour when there is no
// map). The map is equirectangular in Blender's convention (Cycles' direction_to_equirectangular
// with Blender's +Z up = glTF's +Y): row 0 looks up, the image centre looks along +X.
struct Environment {
    bool enabled = false;
    Rgb color{1, 1, 1};         // uniform radiance when there is no map
    int width = 0, height = 0;  // map size, 0 = no map
    std::vector<float> texels;  // linear RGB, width * height * 3, row 0 at the top (+Y)
    float strength = 1;
    float rotation = 0;  // radians about +Y, as a Mapping node's Z rotation in Blender
    std::string source;  // the map's file, for messages
    bool has_map() const { return width > 0 && height > 0; }
};

// What scene_repair (scene/scene_repair.h) changed after import, for the stats and one warning.
struct RepairCounts {
    uint64_t nonfinite_triangles = 0;   // a corner's position is NaN or infinite: dropped
    uint64_t invalid_indices = 0;       // an index past the vertex array: triangle dropped
    uint64_t degenerate_triangles = 0;  // zero area, collinear or repeated corners: dropped
    uint64_t duplicate_triangles = 0;   // the same three corners as another face: dropped
    uint64_t normals_replaced = 0;      // NaN, infinite or zero-length: the face normals' average
    uint64_t normals_normalized = 0;    // finite but not unit length
    uint64_t uvs_replaced = 0;          // NaN or infinite texture coordinates: set to 0
    uint64_t colors_replaced = 0;       // NaN or infinite vertex colours: set to 1
    uint64_t lights_dropped = 0;        // a punctual light with a NaN or infinite parameter
    uint64_t total() const {
        return nonfinite_triangles + invalid_indices + degenerate_triangles + duplicate_triangles + normals_replaced +
               normals_normalized + uvs_replaced + colors_replaced + lights_dropped;
    }
};

struct Scene {
    std::string source_path;
    // Identifies what the import read, by content and never by path: FNV-1a over the bytes of the
    // scene file, then of each buffer and image file in the order they were read. A scene moved
    // or reached through another mount has the same hash; an edited texture or buffer does not.
    uint64_t content_hash = 0;
    std::vector<Mesh> meshes;
    std::vector<Instance> instances;
    std::vector<Material> materials;
    std::vector<Texture> textures;
    std::vector<PunctualLight> lights;
    std::vector<Camera> cameras;
    Environment environment;
    std::vector<std::string> warnings;  // each said once, for the front end to print
    SceneFeatures features;
    SceneCatalog catalog;
    RepairCounts repaired;
    // Nodes, animations, skins and morph targets, when the import was asked for them
    // (ImportOptions::animate); scene_animation.h's pose_scene evaluates them at a time.
    SceneAnimation animation;
    // What moves during the shutter, for motion blur (scene_motion.h's capture_motion).
    SceneMotion motion;

    // World-space bounds of all instanced triangles (their finite corners), the union of
    // bounds_of over the instances: min and max never take a NaN and do not depend on order, so
    // the union of bounds kept per instance is this, bit for bit.
    Bounds3 bounds() const;
    Bounds3 bounds_of(const Instance& inst) const;  // its mesh's finite corners, placed by object_to_world
    size_t triangle_count() const;  // instanced triangles, counted per instance
    const Material& material_of(const Mesh& mesh) const;
    static const Material& default_material();
    // Cycles' default surface (a diffuse BSDF of colour 0.8, roughness 0), as a glTF material:
    // base colour 0.8, metallic 0, KHR_materials_specular 0, which GltfBsdf evaluates as exactly
    // Lambertian.
    static Material blender_default_material();
};

}  // namespace veach
