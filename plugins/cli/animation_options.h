// The `veach` command's animation flags: --frame N (the scene at glTF time N / fps), --fps F,
// --animation NAME|INDEX|all. Kept apart from cli_options.cpp as the farm flags are.
#pragma once

#include <string>
#include <vector>

#include "cli_options.h"

namespace veach::cli {

// Parses one animation flag at args[i] (advancing i past its value); false when it is none.
// Throws UsageError.
bool parse_animation_option(const std::vector<std::string>& args, size_t& i, RenderCommand& cmd);

// Checks the animation flags against each other once all are parsed. Throws UsageError.
void check_animation_options(const RenderCommand& cmd);

// The scene option "time" of a frame: frame / fps, in seconds.
double frame_time(const RenderCommand& cmd, double frame);

}  // namespace veach::cli
