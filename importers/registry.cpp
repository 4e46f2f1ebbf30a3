// The table of importers by file extension.
#include <algorithm>
#include <cctype>

#include "importers/gltf/gltf_importer.h"
#include "importers/importer.h"

namespace veach {
namespace {

std::string lower_extension(const std::string& path) {
    size_t dot = path.find_last_of('.');
    size_t slash = path.find_last_of('/');
    if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
    std::string ext = path.substr(dot + 1);
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
    return ext;
}

}  // namespace

std::vector<std::string> registered_scene_formats() { return {"gltf", "glb"}; }

Scene import_scene(const std::string& path, const ImportOptions& options) {
    std::string ext = lower_extension(path);
    if (ext == "gltf" || ext == "glb") return import_gltf_file(path, options);
    throw ImportError(path + ": unknown scene format '" + ext + "' (known: .gltf, .glb)");
}

Scene import_scene_from_memory(const std::vector<uint8_t>& bytes, const std::string& format,
                               const std::string& base_dir, const ImportOptions& options) {
    std::string ext = lower_extension("x." + format);
    if (ext == "gltf" || ext == "glb")
        return import_gltf_memory(bytes, base_dir, "<memory>." + ext, ext == "glb", options);
    throw ImportError("<memory>: unknown scene format '" + format + "' (known: gltf, glb)");
}

}  // namespace veach
