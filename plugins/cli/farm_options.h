// The `veach` command's farm features: render flags that split one frame into parts
// (--samples, --pixelbounds), and `veach merge`, which sums part files into the image.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "cli_options.h"

namespace veach::cli {

// Parses one farm render flag at args[i] (advancing i past its value); false when `a` is none.
// Throws UsageError.
bool parse_farm_render_option(const std::vector<std::string>& args, size_t& i, RenderCommand& cmd);

// Checks the farm flags against the rest of the command (--samples within --spp, not with
// --noise or --time). Throws UsageError.
void check_farm_render_options(const RenderCommand& cmd);

// `veach merge PART... -o OUTPUT [-o ...] [--expect-spp N] [output options]`, parsed: the exit code.
int run_merge_command(VeachDevice device, const MergeCommand& cmd);

}  // namespace veach::cli
