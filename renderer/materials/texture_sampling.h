// Texture lookups: wrap modes, KHR_texture_transform, bilinear filtering, and trilinear
// filtering over the mip pyramid (textures/mip_pyramid.h) when a ray cone says the lookup's
// footprint covers more than one texel.
#pragma once

#include "core/rgb.h"
#include "scene/scene.h"

namespace veach {

// The texture coordinate after KHR_texture_transform (translation * rotation * scale; the
// rotation's direction is the one of the extension's example, not of its listing).
Vec2 apply_uv_transform(const UvTransform& t, Vec2 uv);
// How KHR_texture_transform scales lengths in texture space: the square root of the area scale
// (rotation and offset preserve lengths and areas).
float uv_transform_length_scale(const UvTransform& t);

// The level of detail of a lookup whose footprint is `footprint` wide in texture-coordinate
// units: log2 of its width in texels, using sqrt(width * height) texels per unit so a
// non-square image gets the level whose texels have the footprint's area. <= 0 for the image
// itself (magnification).
float texture_lod(const Texture& tex, float footprint);

// Filtered lookup; uv in glTF's convention, (0, 0) the top-left of the image. `footprint` is the
// width of the ray's footprint in texture-coordinate units (0: none, the image itself). At level
// of detail <= 0 the image is filtered bilinearly (or by nearest texel for a NEAREST sampler) as
// the sampler says; sRGB texels are filtered encoded and then decoded, as Cycles does with 8-bit
// images. Above 0 the two levels around the LOD are filtered bilinearly and blended
// (trilinear), in linear values; a NEAREST texture keeps its point sampling at every distance, as
// Blender's "Closest" interpolation does.
Rgba sample_texture(const Texture& tex, Vec2 uv, float footprint = 0.0f);

}  // namespace veach
