#include "animation_options.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace veach::cli {
namespace {

double number(const std::string& option, const std::string& value, double lo, double hi, bool integer) {
    errno = 0;
    char* end = nullptr;
    double v = std::strtod(value.c_str(), &end);
    bool ok = !value.empty() && *end == '\0' && errno == 0 && v >= lo && v <= hi && (!integer || v == std::floor(v));
    if (!ok) {
        char range[64];
        std::snprintf(range, sizeof(range), "%.10g to %.10g", lo, hi);
        throw UsageError(option + " expects " + (integer ? "an integer" : "a number") + " from " + range + ", not '" +
                         value + "'");
    }
    return v;
}

}  // namespace

bool parse_animation_option(const std::vector<std::string>& args, size_t& i, RenderCommand& cmd) {
    const std::string& a = args[i];
    if (a != "--frame" && a != "--fps" && a != "--animation") return false;
    if (i + 1 >= args.size()) throw UsageError(a + " needs a value");
    const std::string& v = args[++i];
    if (a == "--frame") {
        // Blender's frames are integers; its frame range is -1048574 .. 1048574.
        cmd.frames = {number(a, v, -1048574, 1048574, true)};
    } else if (a == "--fps") {
        cmd.fps = number(a, v, 0.001, 1e6, false);
        cmd.fps_given = true;
    } else {
        if (v.empty()) throw UsageError("--animation expects a name, an index or all");
        cmd.animation = v;
    }
    return true;
}

void check_animation_options(const RenderCommand& cmd) {
    if (cmd.frames.empty() && (cmd.fps_given || !cmd.animation.empty()))
        throw UsageError(std::string(cmd.fps_given ? "--fps" : "--animation") + " needs --frame");
}

double frame_time(const RenderCommand& cmd, double frame) { return frame / cmd.fps; }

}  // namespace veach::cli
