// The `veach` command's animation flags: --frame N (the scene at glTF time N / fps), --frames
// A-B[:STEP] (a sequence from one load), --fps F, --animation NAME|INDEX|all, --animated-seed,
// --shutter OPEN,CLOSE (motion blur, in frames);
// and the frame's part of output patterns ({frame}, Blender's ####). Kept apart from
// cli_options.cpp as the farm flags are.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "cli_options.h"

namespace veach::cli {

// Parses one animation flag at args[i] (advancing i past its value); false when it is none.
// Throws UsageError.
bool parse_animation_option(const std::vector<std::string>& args, size_t& i, RenderCommand& cmd);

// Checks the animation flags against each other and the outputs once all are parsed: several
// frames need every output (and --stats-json) to be a pattern with {frame} or #. Throws UsageError.
void check_animation_options(const RenderCommand& cmd);

// The scene option "time" of a frame: frame / fps, in seconds.
double frame_time(const RenderCommand& cmd, long long frame);

// The scene option "shutter": --shutter's frames in seconds ("OPEN,CLOSE"), "" without it.
std::string shutter_seconds(const RenderCommand& cmd);

// `pattern` for one frame: {frame} becomes the number, each run of # the number zero-padded to
// the run's length (Blender's convention: frame 7 in "f_####.exr" is "f_0007.exr").
std::string with_frame(const std::string& pattern, long long frame);

// The command for one frame: outputs and --stats-json with the frame filled in.
RenderCommand command_for_frame(const RenderCommand& cmd, long long frame);

// Cycles' "animated seed": the seed mixed with the frame, so that frames do not share one noise
// pattern. A 63-bit value (the seed option's range).
uint64_t animated_seed(uint64_t seed, long long frame);

}  // namespace veach::cli
