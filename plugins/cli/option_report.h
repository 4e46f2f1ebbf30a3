// What the command says about options: `veach options` (the table as a reference, Markdown or
// JSON) and `veach render ... --dry-run` (every option as the library took it, read back through
// the C API, as JSON: what a test compares with the table).
#pragma once

#include <string>

#include "cli_options.h"

namespace veach::cli {

// `veach options [--json | --markdown]`: the exit code.
int print_options(VeachDevice device, bool json, bool markdown);

// `veach render ... --dry-run`: the command's options applied to a scene (not loaded) and a render
// of an empty scene, then every table option read back; the exit code.
int print_dry_run(VeachDevice device, const RenderCommand& cmd);

}  // namespace veach::cli
