// `veach info SCENE [--json] [--width N --height N] [scene flags]`: what the scene holds (the
// library's scene query "info": scenes, variants, animations, cameras, lights by kind, meshes,
// triangles, instances, textures with sizes, features) and the memory a render of it at that
// size needs (the render result "estimated_memory_bytes", the job's own estimate).
#pragma once

#include "cli_options.h"

namespace veach::cli {

// The exit code: 0, or 2 for a scene that cannot be loaded (one line).
int run_info_command(VeachDevice device, const InfoCommand& cmd);

}  // namespace veach::cli
