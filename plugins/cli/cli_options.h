// The `veach` command line (CLI11): subcommands, and the render command's flags built from the
// library's options table (the device query "options"), with one-line usage errors. The command
// is a client of libveach like any host: it knows the library only through veach.h, so every
// flag maps to a named scene or render option, checked by the library itself.
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

// One row of the library's options table, as the device query "options" describes it.
struct TableOption {
    std::string name, object, type, help, flag, metavar;
    std::vector<std::string> choices, aliases;
    std::string default_text;  // the default as the flag would take it ("" for none)
    long long int_min = 0, int_max = 0;
    double float_min = 0, float_max = 0;
    bool identity = false, is_switch = false, checked_by_scene = false, choices_form = false;
};
std::vector<TableOption> read_option_table(VeachDevice device);

struct RenderCommand {
    std::vector<std::string> inputs;        // after glob expansion
    std::vector<std::string> outputs;       // files or patterns with {stem}; -o may repeat
    std::vector<ApiOption> scene_options;   // veachSetScene*: before each input is loaded
    std::vector<ApiOption> render_options;  // veachSet*: on each input's render
    std::string stats_json;
    bool quiet = false;
    bool skip_existing = false;      // skip inputs whose outputs are all complete
    bool dry_run = false;
    // --preview-every SECONDS FILE: the film so far written to FILE (a pattern like the outputs)
    // at most every SECONDS while rendering.
    double preview_seconds = 0;
    std::string preview_path;            // --dry-run: print the options as the library took them, render nothing
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

struct MergeCommand {
    std::vector<std::string> parts, outputs;
    std::vector<ApiOption> options;
    long long expect_spp = 0;
    bool quiet = false;
};

struct InfoCommand {
    std::string input;
    std::vector<ApiOption> scene_options;
    bool json = false;
    long long width = 1920, height = 0;  // the resolution the memory estimate is for
};

enum class Subcommand { None, Render, Merge, Color, Options, Info };

// The parsed command line. `exit_code` >= 0 when parsing already ended the command (help or
// --version printed: 0; a usage error printed: 1).
struct CommandLine {
    Subcommand which = Subcommand::None;
    RenderCommand render;
    MergeCommand merge;
    InfoCommand info;
    bool options_json = false, options_markdown = false;
    int exit_code = -1;
};

// Parses argv with CLI11: `veach render|merge|info|color|options ...`, -h/--help and --version
// anywhere, `--opt=value` and `--opt value`, a suggestion for a mistyped flag, pbrt-v4's
// aliases, and `--config FILE` (TOML or INI: flag names as keys, before the command line's own
// flags, which win). Values are checked by the library itself, on a probe scene and render of
// `device`, so the command accepts exactly what the API accepts; a refused value becomes the
// command's usage message naming the flag.
CommandLine parse_command_line(int argc, char** argv, VeachDevice device);

// String queries through the C API's caller-buffer convention ("" when the query fails).
std::string device_string(VeachDevice device, const char* name);
std::string scene_string(VeachScene scene, const char* name);
std::string render_string(VeachRender render, const char* name);

// Sets one option through the C API; returns its VeachError.
VeachError apply_scene_option(VeachScene scene, const ApiOption& option);
VeachError apply_render_option(VeachRender render, const ApiOption& option);

// A library message with option names turned into the command's flags ("spp must be at least
// 1" -> "--spp must be at least 1").
std::string with_flags(const std::string& message, const std::vector<TableOption>& table);

// The checkpoint file for one input: beside its first output.
std::string checkpoint_path_for(const RenderCommand& cmd, const std::string& input);

// The output path for one input: {stem} replaced by the input's file name without extension.
std::string output_path_for(const std::string& pattern, const std::string& input);

// `veach options`: the options table as a reference (Markdown: what README's option reference
// holds) or as JSON.
std::string option_reference_markdown(const std::vector<TableOption>& table);

}  // namespace veach::cli
