#include "cli_options.h"

#include <glob.h>

#include <cerrno>
#include <cstdlib>
#include <limits>

namespace veach::cli {

const char* usage_text() {
    return R"(usage: veach render INPUT... -o OUTPUT [options]
       veach --version | --help

Renders glTF 2.0 scenes (.gltf, .glb) with a physically based path tracer.

  -o, --output FILE       output image; the format comes from the extension (.exr .hdr .png .jpg
                          .tif); with several inputs use a pattern with {stem}; repeat -o to
                          write one render to several files
  --width N               image width (default 1920)
  --height N              image height (default: from the camera's aspect ratio)
  --spp N                 samples per pixel (default 64)
  --time SECONDS          stop after this long (whichever of --spp and --time comes first)
  --seed N                random seed (default 0)
  --threads N             worker threads (default: all cores)
  --integrator NAME       bdpt (default: bidirectional path tracing), pt (path tracing) or
                          lt (light tracing alone, for verification)
  --bdpt-strategy S,T     bdpt: render only the strategy with S light and T camera vertices,
                          unweighted (for verification)
  --max-depth N           maximum number of bounces (default 64)
  --camera NAME|INDEX     camera to render (default: the first)
  --scene N               glTF scene index (default: the file's default scene)
  --spot-falloff MODE     auto (default), blender or gltf: the spot cone profile
  --allow-external-files  let URIs point outside the glTF's folder
  --display NAME          OCIO display for PNG/JPEG/TIFF (default: the config's default)
  --view NAME             OCIO view (default: the display's default, Standard)
  --look NAME             OCIO look
  --exposure STOPS        exposure before the view transform
  --gamma G               display gamma after the view transform
  --half                  EXR with half floats
  --quality Q             JPEG quality 1-100 (default 95)
  --bits 8|16             PNG/TIFF bit depth (default 8)
  --stats-json FILE       write render statistics as JSON
  -q, --quiet             no progress output

Exit codes: 0 done, 1 usage, 2 bad input, 3 render or write failure.
)";
}

namespace {

long long parse_integer(const std::string& option, const std::string& value, long long lo, long long hi) {
    errno = 0;
    char* end = nullptr;
    long long v = std::strtoll(value.c_str(), &end, 10);
    if (value.empty() || *end != '\0' || errno != 0 || v < lo || v > hi)
        throw UsageError(option + " expects an integer from " + std::to_string(lo) + " to " + std::to_string(hi) +
                         ", not '" + value + "'");
    return v;
}

double parse_number(const std::string& option, const std::string& value, double lo, double hi) {
    errno = 0;
    char* end = nullptr;
    double v = std::strtod(value.c_str(), &end);
    if (value.empty() || *end != '\0' || errno != 0 || !(v >= lo && v <= hi))
        throw UsageError(option + " expects a number from " + std::to_string(lo) + " to " + std::to_string(hi) +
                         ", not '" + value + "'");
    return v;
}

void expand_input(const std::string& pattern, std::vector<std::string>& out) {
    if (pattern.find_first_of("*?[") == std::string::npos) {
        out.push_back(pattern);
        return;
    }
    glob_t g{};
    int rc = glob(pattern.c_str(), 0, nullptr, &g);
    if (rc == 0)
        for (size_t i = 0; i < g.gl_pathc; ++i) out.emplace_back(g.gl_pathv[i]);
    globfree(&g);
    if (rc != 0) throw UsageError("no file matches '" + pattern + "'");
}

}  // namespace

std::string output_path_for(const std::string& pattern, const std::string& input) {
    size_t slash = input.find_last_of('/');
    std::string name = slash == std::string::npos ? input : input.substr(slash + 1);
    size_t dot = name.find_last_of('.');
    std::string stem = dot == std::string::npos ? name : name.substr(0, dot);
    std::string out = pattern;
    for (size_t pos; (pos = out.find("{stem}")) != std::string::npos;) out.replace(pos, 6, stem);
    return out;
}

RenderCommand parse_render_command(const std::vector<std::string>& args) {
    RenderCommand cmd;
    for (size_t i = 0; i < args.size(); ++i) {
        const std::string& a = args[i];
        auto value = [&]() -> const std::string& {
            if (i + 1 >= args.size()) throw UsageError(a + " needs a value");
            return args[++i];
        };
        constexpr long long int_max = std::numeric_limits<int>::max();
        if (a == "-o" || a == "--output") cmd.outputs.push_back(value());
        else if (a == "--width") cmd.job.width = static_cast<int>(parse_integer(a, value(), 1, 65536));
        else if (a == "--height") cmd.job.height = static_cast<int>(parse_integer(a, value(), 1, 65536));
        else if (a == "--spp") cmd.job.render.spp = static_cast<int>(parse_integer(a, value(), 1, int_max));
        else if (a == "--time") cmd.job.render.time_limit = parse_number(a, value(), 0.0, 1e9);
        else if (a == "--seed") cmd.job.render.seed = static_cast<uint64_t>(parse_integer(a, value(), 0, std::numeric_limits<long long>::max()));
        else if (a == "--threads") cmd.job.render.threads = static_cast<int>(parse_integer(a, value(), 0, 4096));
        else if (a == "--integrator") cmd.job.render.integrator = value();
        else if (a == "--bdpt-strategy") {
            const std::string& v = value();
            size_t comma = v.find(',');
            if (comma == std::string::npos) throw UsageError("--bdpt-strategy expects s,t (e.g. 2,2)");
            cmd.job.render.bdpt_s = static_cast<int>(parse_integer(a, v.substr(0, comma), 0, 1000));
            cmd.job.render.bdpt_t = static_cast<int>(parse_integer(a, v.substr(comma + 1), 1, 1000));
        }
        else if (a == "--max-depth") cmd.job.render.max_depth = static_cast<int>(parse_integer(a, value(), 0, 100000));
        else if (a == "--camera") cmd.job.camera = value();
        else if (a == "--scene") cmd.import.scene_index = static_cast<int>(parse_integer(a, value(), 0, int_max));
        else if (a == "--spot-falloff") {
            const std::string& v = value();
            if (v == "auto") cmd.import.spot_profile = SpotProfile::Auto;
            else if (v == "blender") cmd.import.spot_profile = SpotProfile::Blender;
            else if (v == "gltf") cmd.import.spot_profile = SpotProfile::Gltf;
            else throw UsageError("--spot-falloff expects auto, blender or gltf, not '" + v + "'");
        }
        else if (a == "--allow-external-files") cmd.import.allow_external_files = true;
        else if (a == "--display") cmd.output_settings.display.display = value();
        else if (a == "--view") cmd.output_settings.display.view = value();
        else if (a == "--look") cmd.output_settings.display.look = value();
        else if (a == "--exposure") cmd.output_settings.display.exposure = static_cast<float>(parse_number(a, value(), -64, 64));
        else if (a == "--gamma") cmd.output_settings.display.gamma = static_cast<float>(parse_number(a, value(), 0.01, 100));
        else if (a == "--half") cmd.output_settings.half = true;
        else if (a == "--quality") cmd.output_settings.quality = static_cast<int>(parse_integer(a, value(), 1, 100));
        else if (a == "--bits") {
            int b = static_cast<int>(parse_integer(a, value(), 8, 16));
            if (b != 8 && b != 16) throw UsageError("--bits expects 8 or 16");
            cmd.output_settings.bits = b;
        }
        else if (a == "--stats-json") cmd.stats_json = value();
        else if (a == "-q" || a == "--quiet") cmd.quiet = true;
        else if (!a.empty() && a[0] == '-') throw UsageError("unknown option '" + a + "'");
        else expand_input(a, cmd.inputs);
    }
    if (cmd.inputs.empty()) throw UsageError("no input scene given");
    if (cmd.outputs.empty()) throw UsageError("no output given (-o FILE)");
    for (const std::string& o : cmd.outputs)
        if (cmd.inputs.size() > 1 && o.find("{stem}") == std::string::npos)
            throw UsageError("several inputs need an output pattern with {stem}, e.g. -o out/{stem}.exr");
    bool known = false;
    for (const std::string& n : integrator_names()) known = known || n == cmd.job.render.integrator;
    if (!known) throw UsageError("unknown integrator '" + cmd.job.render.integrator + "'");
    return cmd;
}

}  // namespace veach::cli
