// glTF 2.0 (.gltf with separate or embedded buffers, .glb) into a Scene. The only code in the
// project that includes tinygltf.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "importers/importer.h"

namespace veach {

Scene import_gltf_file(const std::string& path, const ImportOptions& options);
Scene import_gltf_memory(const std::vector<uint8_t>& bytes, const std::string& base_dir,
                         const std::string& display_name, bool binary, const ImportOptions& options);

}  // namespace veach
