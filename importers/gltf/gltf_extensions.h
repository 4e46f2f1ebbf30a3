// The glTF extensions the importer reads: one list, which decides both what a file may require
// and what README's extension table says is supported (a test keeps the two equal).
#pragma once

#include <span>
#include <string_view>

namespace veach::gltf {

// Every extension whose data the importer reads and renders. A file may list any of them in
// extensionsRequired; any other required extension is refused, and any other used one is
// ignored with a warning (its fallback is what renders).
std::span<const std::string_view> supported_extensions();

bool is_supported_extension(std::string_view name);

}  // namespace veach::gltf
