// The `veach` command line: parsing into options, with one-line usage errors.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

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
    OutputSettings output_settings;
    std::string stats_json;
    bool quiet = false;
};

// Parses the arguments after "render". Throws UsageError.
RenderCommand parse_render_command(const std::vector<std::string>& args);

// The output path for one input: {stem} replaced by the input's file name without extension.
std::string output_path_for(const std::string& pattern, const std::string& input);

const char* usage_text();

}  // namespace veach::cli
