// The `veach` command line: parsing into options, with one-line usage errors.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

#include "api/environment_options.h"
#include "api/render_job.h"
#include "importers/importer.h"
#include "output/image_output.h"

namespace veach::cli {

class UsageError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

struct RenderCommand {
    std::vector<std::string> inputs;  // after glob expansion
    std::vector<std::string> outputs;  // files or patterns with {stem}; -o may repeat
    ImportOptions import;
    RenderJobOptions job;
    EnvironmentOptions environment;
    OutputSettings output_settings;
    std::string stats_json;
    bool quiet = false;
    bool skip_existing = false;       // skip inputs whose outputs all exist
    double checkpoint_seconds = -1;   // --checkpoint: < 0 none, else the interval (0: every pass)
    bool resume = false;              // --resume: continue from the checkpoint when there is one
};

// The checkpoint file for one input: beside its first output.
std::string checkpoint_path_for(const RenderCommand& cmd, const std::string& input);

// Parses the arguments after "render". Throws UsageError.
RenderCommand parse_render_command(const std::vector<std::string>& args);

// The output path for one input: {stem} replaced by the input's file name without extension.
std::string output_path_for(const std::string& pattern, const std::string& input);

const char* usage_text();

}  // namespace veach::cli
