#include "farm_options.h"

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <limits>

namespace veach::cli {

namespace {

enum ExitCode { k_ok = 0, k_usage = 1, k_bad_input = 2, k_failure = 3 };

long long whole_number(const std::string& option, const std::string& text, long long lo, long long hi) {
    errno = 0;
    char* end = nullptr;
    long long v = std::strtoll(text.c_str(), &end, 10);
    if (text.empty() || *end != '\0' || errno != 0 || v < lo || v > hi)
        throw UsageError(option + " expects whole numbers from " + std::to_string(lo) + " to " + std::to_string(hi) +
                         ", not '" + text + "'");
    return v;
}

const ApiOption* find_option(const std::vector<ApiOption>& options, const char* name) {
    const ApiOption* found = nullptr;
    for (const ApiOption& o : options)
        if (o.name == name) found = &o;  // the last one given wins, as the library applies them in order
    return found;
}

}  // namespace

bool parse_farm_render_option(const std::vector<std::string>& args, size_t& i, RenderCommand& cmd) {
    const std::string& a = args[i];
    if (a != "--samples" && a != "--pixelbounds") return false;
    if (i + 1 >= args.size()) throw UsageError(a + " needs a value");
    const std::string& v = args[++i];
    constexpr long long int_max = std::numeric_limits<int>::max();
    if (a == "--samples") {
        const size_t colon = v.find(':');
        if (colon == std::string::npos) throw UsageError("--samples expects A:B (sample indices [A, B), e.g. 0:16)");
        const long long begin = whole_number(a, v.substr(0, colon), 0, int_max - 1);
        const long long end = whole_number(a, v.substr(colon + 1), 1, int_max);
        if (begin >= end) throw UsageError("--samples A:B needs A < B, not '" + v + "'");
        cmd.render_options.push_back({ApiOption::Type::Int, "sample_begin", begin, 0, {}});
        cmd.render_options.push_back({ApiOption::Type::Int, "sample_end", end, 0, {}});
        return true;
    }
    // X0,X1,Y0,Y1 as pbrt-v4 orders them.
    long long b[4];
    size_t start = 0;
    for (int k = 0; k < 4; ++k) {
        const size_t comma = k < 3 ? v.find(',', start) : v.size();
        if (comma == std::string::npos) throw UsageError("--pixelbounds expects X0,X1,Y0,Y1 (e.g. 0,256,0,128)");
        b[k] = whole_number(a, v.substr(start, comma - start), 0, 65536);
        start = comma + 1;
    }
    if (b[0] >= b[1] || b[2] >= b[3]) throw UsageError("--pixelbounds X0,X1,Y0,Y1 needs X0 < X1 and Y0 < Y1");
    cmd.render_options.push_back({ApiOption::Type::String, "pixelbounds", 0, 0, v});
    return true;
}

void check_farm_render_options(const RenderCommand& cmd) {
    const ApiOption* begin = find_option(cmd.render_options, "sample_begin");
    const ApiOption* bounds = find_option(cmd.render_options, "pixelbounds");
    const ApiOption* transparent = find_option(cmd.render_options, "transparent");
    // Part files hold no coverage: merged, a transparent render would come back opaque.
    if ((begin || bounds) && transparent && transparent->i != 0)
        throw UsageError("--transparent cannot be rendered in parts (--samples, --pixelbounds): part files hold no alpha");
    if (!begin) return;
    const ApiOption* end = find_option(cmd.render_options, "sample_end");
    const ApiOption* spp = find_option(cmd.render_options, "spp");
    const long long n = spp ? spp->i : 64;
    if (end->i > n)
        throw UsageError("--samples " + std::to_string(begin->i) + ":" + std::to_string(end->i) +
                         " reaches past --spp " + std::to_string(n) + " (0 <= A < B <= spp)");
    const ApiOption* noise = find_option(cmd.render_options, "noise");
    const ApiOption* time = find_option(cmd.render_options, "time_limit");
    if ((noise && noise->f != 0) || (time && time->f != 0))
        throw UsageError("--samples cannot be combined with --noise or --time (a part must hold exactly its samples)");
}

int run_merge_command(VeachDevice device, const MergeCommand& cmd) {
    const std::vector<std::string>& parts = cmd.parts;
    const std::vector<std::string>& outputs = cmd.outputs;
    const std::vector<ApiOption>& options = cmd.options;
    const long long expect_spp = cmd.expect_spp;
    const bool quiet = cmd.quiet;
    std::vector<const char*> paths;
    for (const std::string& p : parts) paths.push_back(p.c_str());
    VeachRender render = veachNewRenderFromParts(device, paths.data(), paths.size(), expect_spp);
    if (!render) {
        VeachError e = veachGetLastErrorCode();
        std::fprintf(stderr, "veach merge: %s\n", veachGetLastError());
        return e == VEACH_ERROR_BAD_INPUT || e == VEACH_ERROR_INVALID_ARGUMENT ? k_bad_input : k_failure;
    }
    struct Release {
        VeachRender r;
        ~Release() { veachReleaseRender(r); }
    } release{render};
    for (const ApiOption& o : options) {
        if (apply_render_option(render, o) != VEACH_ERROR_NONE) {
            std::fprintf(stderr, "veach merge: %s\n", veachGetLastError());
            return k_usage;
        }
    }
    // All outputs checked before the first is written: a typo in the second never leaves the
    // first written alone.
    for (const std::string& out : outputs) {
        if (VeachError e = veachCheckOutput(render, out.c_str()); e != VEACH_ERROR_NONE) {
            std::fprintf(stderr, "veach merge: %s\n", veachGetLastError());
            return e == VEACH_ERROR_INVALID_ARGUMENT ? k_usage : k_bad_input;
        }
    }
    for (const std::string& out : outputs) {
        if (veachWriteImage(render, out.c_str()) != VEACH_ERROR_NONE) {
            VeachError e = veachGetLastErrorCode();
            std::fprintf(stderr, "veach merge: %s\n", veachGetLastError());
            return e == VEACH_ERROR_INVALID_OPERATION ? k_bad_input : k_failure;
        }
    }
    if (!quiet) {
        long long spp = 0, complete = 0;
        veachGetInt(render, "result_spp", &spp);
        veachGetInt(render, "result_complete", &complete);
        std::string written;
        for (const std::string& o : outputs) written += (written.empty() ? "" : ", ") + o;
        std::fprintf(stderr, "veach merge: %zu parts -> %s (%lld spp%s)\n", parts.size(), written.c_str(), spp,
                     complete ? "" : ", incomplete");
    }
    return k_ok;
}

}  // namespace veach::cli
