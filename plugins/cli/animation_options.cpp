#include "animation_options.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace veach::cli {
namespace {

// Blender's frame range.
constexpr long long k_min_frame = -1048574, k_max_frame = 1048574;

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

long long frame_number(const std::string& option, const std::string& value) {
    return static_cast<long long>(number(option, value, double(k_min_frame), double(k_max_frame), true));
}

// "A-B" or "A-B:STEP", A and B possibly negative ("-10--2").
std::vector<long long> parse_range(const std::string& v) {
    const std::string usage = "--frames expects A-B or A-B:STEP (e.g. 1-250 or 1-250:10), not '" + v + "'";
    size_t dash = v.find('-', v.empty() || v[0] != '-' ? 0 : 1);
    if (dash == std::string::npos || dash == 0) throw UsageError(usage);
    size_t colon = v.find(':', dash);
    std::string a = v.substr(0, dash), b = v.substr(dash + 1, colon == std::string::npos ? colon : colon - dash - 1);
    long long first = frame_number("--frames", a), last = frame_number("--frames", b), step = 1;
    if (colon != std::string::npos)
        step = static_cast<long long>(number("--frames step", v.substr(colon + 1), 1, double(k_max_frame), true));
    if (last < first) throw UsageError("--frames " + v + ": the last frame comes before the first");
    std::vector<long long> frames;
    for (long long f = first; f <= last; f += step) frames.push_back(f);
    return frames;
}

bool has_frame_pattern(const std::string& pattern) {
    return pattern.find("{frame}") != std::string::npos || pattern.find('#') != std::string::npos;
}

}  // namespace

bool parse_animation_option(const std::vector<std::string>& args, size_t& i, RenderCommand& cmd) {
    const std::string& a = args[i];
    if (a == "--animated-seed") {
        cmd.animated_seed = true;
        return true;
    }
    if (a != "--frame" && a != "--frames" && a != "--fps" && a != "--animation" && a != "--shutter") return false;
    if (i + 1 >= args.size()) throw UsageError(a + " needs a value");
    const std::string& v = args[++i];
    if (a == "--frame" || a == "--frames") {
        if (cmd.frames_given && cmd.frames_flag != a)
            throw UsageError("--frame and --frames exclude each other");
        cmd.frames = a == "--frame" ? std::vector<long long>{frame_number(a, v)} : parse_range(v);
        cmd.frames_given = true;
        cmd.frames_flag = a;
    } else if (a == "--shutter") {
        const std::string usage = "--shutter expects OPEN,CLOSE in frames relative to the frame (e.g. -0.25,0.25), not '" +
                                  v + "'";
        size_t comma = v.find(',');
        if (comma == std::string::npos) throw UsageError(usage);
        // A shutter longer than Blender's (its motion_blur_shutter goes up to 1000 frames) is a typo.
        cmd.shutter_open = number("--shutter", v.substr(0, comma), -1000, 1000, false);
        cmd.shutter_close = number("--shutter", v.substr(comma + 1), -1000, 1000, false);
        if (cmd.shutter_open > cmd.shutter_close)
            throw UsageError("--shutter " + v + ": the shutter opens after it closes");
        cmd.shutter_given = true;
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
    if (cmd.frames.empty() && (cmd.fps_given || !cmd.animation.empty() || cmd.animated_seed || cmd.shutter_given))
        throw UsageError(std::string(cmd.fps_given              ? "--fps"
                                     : !cmd.animation.empty() ? "--animation"
                                     : cmd.animated_seed      ? "--animated-seed"
                                                              : "--shutter") +
                         " needs --frame or --frames");
    if (cmd.frames.size() > 1) {
        for (const std::string& o : cmd.outputs)
            if (!has_frame_pattern(o))
                throw UsageError("several frames need an output pattern with {frame} or #### (e.g. -o out/frame_####.exr), "
                                 "not '" + o + "'");
        if (!cmd.stats_json.empty() && !has_frame_pattern(cmd.stats_json))
            throw UsageError("several frames need a --stats-json pattern with {frame} or ####, not '" + cmd.stats_json +
                             "'");
    }
}

double frame_time(const RenderCommand& cmd, long long frame) { return double(frame) / cmd.fps; }

std::string shutter_seconds(const RenderCommand& cmd) {
    if (!cmd.shutter_given) return "";
    char v[64];
    std::snprintf(v, sizeof(v), "%.17g,%.17g", cmd.shutter_open / cmd.fps, cmd.shutter_close / cmd.fps);
    return v;
}

std::string with_frame(const std::string& pattern, long long frame) {
    std::string out;
    for (size_t i = 0; i < pattern.size();) {
        if (pattern.compare(i, 7, "{frame}") == 0) {
            out += std::to_string(frame);
            i += 7;
        } else if (pattern[i] == '#') {
            size_t run = pattern.find_first_not_of('#', i);
            if (run == std::string::npos) run = pattern.size();
            char digits[64];
            std::snprintf(digits, sizeof(digits), "%0*lld", int(std::min<size_t>(run - i, 20)), frame);
            out += digits;
            i = run;
        } else {
            out += pattern[i++];
        }
    }
    return out;
}

RenderCommand command_for_frame(const RenderCommand& cmd, long long frame) {
    RenderCommand f = cmd;
    for (std::string& o : f.outputs) o = with_frame(o, frame);
    if (!f.stats_json.empty()) f.stats_json = with_frame(f.stats_json, frame);
    return f;
}

uint64_t animated_seed(uint64_t seed, long long frame) {
    // SplitMix64's finaliser over the seed and the frame: nearby frames get unrelated seeds.
    uint64_t z = seed ^ (static_cast<uint64_t>(frame) * 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return (z ^ (z >> 31)) & 0x7FFFFFFFFFFFFFFFull;
}

}  // namespace veach::cli
