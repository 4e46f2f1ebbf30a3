// Which image files a scene never uses. tinygltf reads every external image a file lists before
// the importer sees any of it; an image that no material's texture refers to would be read into
// memory (and hashed) for nothing, however large. The importer lists such files before tinygltf
// parses, and its file callbacks serve them as one zero byte, never opening them.
#pragma once

#include <set>
#include <string>
#include <string_view>

namespace veach::gltf {

// The external URIs (not data: URIs) of the file's images that no texture used by a material
// refers to, leaving out any URI that a used image or a buffer also names. A material uses a
// texture through any textureInfo in it or its extensions (an object under a key ending in
// "Texture" with an integer "index"); a texture refers to its images by "source", in itself or
// in its extensions (KHR_texture_basisu, EXT_texture_webp, ...). Empty when the JSON does not
// parse (tinygltf reports that).
std::set<std::string> unused_image_uris(std::string_view json);

}  // namespace veach::gltf
