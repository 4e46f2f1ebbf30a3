// The `veach` command line: parsing into options of the public C API (veach/veach.h), with
// one-line usage errors. The command is a client of libveach like any host: it knows the
// library only through veach.h, so every flag maps to a named scene or render option.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

#include "veach/veach.h"

namespace veach::cli {

class UsageError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// One typed option of the C API, as the command line asked for it.
struct ApiOption {
    enum class Type { Int, Float, String } type;
    std::string name;
    long long i = 0;
    double f = 0;
    std::string s;
};

struct RenderCommand {
    std::vector<std::string> inputs;        // after glob expansion
    std::vector<std::string> outputs;       // files or patterns with {stem}; -o may repeat
    std::vector<ApiOption> scene_options;   // veachSetScene*: before each input is loaded
    std::vector<ApiOption> render_options;  // veachSet*: on each input's render
    std::string stats_json;
    bool quiet = false;
    bool skip_existing = false;      // skip inputs whose outputs are all complete
    double checkpoint_seconds = -1;  // --checkpoint: < 0 none, else the interval (0: every pass)
    bool resume = false;             // --resume: continue from the checkpoint when there is one
    // Animation (animation_options.h): the frames to render (empty: the file's static pose),
    // frames per second (time = frame / fps) and the animation played ("" = all).
    std::vector<long long> frames;
    bool frames_given = false;
    std::string frames_flag;  // --frame or --frames
    double fps = 24;
    bool fps_given = false;
    std::string animation;
    bool animated_seed = false;  // --animated-seed: the seed mixed with each frame
    // --shutter OPEN,CLOSE: motion blur over [frame + OPEN, frame + CLOSE] in frames (open <= close; equal: no blur).
    bool shutter_given = false;
    double shutter_open = 0, shutter_close = 0;
};

// String queries through the C API's caller-buffer convention ("" when the query fails).
std::string device_string(VeachDevice device, const char* name);
std::string scene_string(VeachScene scene, const char* name);
std::string render_string(VeachRender render, const char* name);

// Sets one option through the C API; returns its VeachError.
VeachError apply_scene_option(VeachScene scene, const ApiOption& option);
VeachError apply_render_option(VeachRender render, const ApiOption& option);

// The checkpoint file for one input: beside its first output.
std::string checkpoint_path_for(const RenderCommand& cmd, const std::string& input);

// Parses the arguments after "render". Values are checked by the library itself, on a probe
// scene and render of `device`, so that the command accepts exactly what the API accepts; a
// refused value becomes the command's usage message. Throws UsageError.
RenderCommand parse_render_command(const std::vector<std::string>& args, VeachDevice device);

// The output path for one input: {stem} replaced by the input's file name without extension.
std::string output_path_for(const std::string& pattern, const std::string& input);

const char* usage_text();

}  // namespace veach::cli
