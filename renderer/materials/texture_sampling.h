// Texture lookups: wrap modes, KHR_texture_transform, bilinear filtering.
#pragma once

#include "core/rgb.h"
#include "scene/scene.h"

namespace veach {

// The texture coordinate after KHR_texture_transform (translation * rotation * scale, as the
// extension defines the matrix).
Vec2 apply_uv_transform(const UvTransform& t, Vec2 uv);

// Bilinear (or nearest) lookup; uv in glTF's convention, (0, 0) the top-left of the image.
Rgba sample_texture(const Texture& tex, Vec2 uv);

}  // namespace veach
