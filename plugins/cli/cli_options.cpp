#include "cli_options.h"

#include <glob.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <limits>

namespace veach::cli {

const char* usage_text() {
    return R"(usage: veach render INPUT... -o OUTPUT [options]
       veach color     (the colour config's displays, views and looks)
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
  --sampler KIND          sobol (default: Owen-scrambled Sobol pairs for the first dimensions)
                          or random (independent numbers)
  --bdpt-strategy S,T     bdpt: render only the strategy with S light and T camera vertices,
                          unweighted (for verification)
  --max-depth N           maximum number of bounces (default 64)
  --camera NAME|INDEX     camera to render (default: the first)
  --scene N               glTF scene index (default: the file's default scene)
  --spot-falloff MODE     auto (default), blender or gltf: the spot cone profile
  --variant NAME          KHR_materials_variants: render with this variant's materials
  --allow-external-files  let URIs point outside the glTF's folder
  --env FILE              environment map: equirectangular (lat-long) HDR/EXR, Blender's mapping
  --env-color R,G,B       a uniform environment of this linear radiance instead
  --env-strength S        multiplies the environment (default 1)
  --env-rotate DEGREES    rotates the environment about the up axis (+Y), as a Mapping node's
                          Z rotation in Blender's world shader
  --display NAME          OCIO display for PNG/JPEG/TIFF (default: the config's default)
  --view NAME             OCIO view (default: the display's default, Standard)
  --look NAME             OCIO look
  --exposure STOPS        exposure before the view transform
  --gamma G               display gamma after the view transform
  --filter NAME           pixel filter: box (default), gaussian or blackman-harris (Blender's
                          default); light-tracing splats use the same filter
  --filter-width PIXELS   filter width as Blender's (default 1 for box, 1.5 otherwise)
  --half                  EXR with half floats
  --exr-codec NAME        EXR compression: none, rle, zips, zip (default), piz, pxr24, b44,
                          b44a, dwaa, dwab (zip:N, dwaa:N set a level)
  --passes LIST           multi-layer EXR with Blender's pass names, from combined, depth,
                          normal, albedo, variance (e.g. combined,depth,normal,albedo)
  --quality Q             JPEG quality 1-100 (default 95)
  --bits 8|16             PNG/TIFF bit depth (default 8)
  --stats-json FILE       write render statistics as JSON
  --skip-existing         skip inputs whose outputs all exist (batch reruns)
  --checkpoint SECONDS    keep OUTPUT.checkpoint up to date (at the first pass boundary after
                          SECONDS; 0 every pass) so that a killed render can resume
  --resume                continue from OUTPUT.checkpoint when it exists (same settings; spp
                          may grow); the result equals an uninterrupted render
  -q, --quiet             no progress output

SIGINT, SIGTERM and SIGHUP stop sampling and write the image as it stands, with the samples
per pixel reached in its metadata (exit 130); a second signal ends the process at once.

Exit codes: 0 done, 1 usage, 2 bad input, 3 render or write failure, 130 interrupted.
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

std::string checkpoint_path_for(const RenderCommand& cmd, const std::string& input) {
    return cmd.outputs.empty() ? std::string() : output_path_for(cmd.outputs.front(), input) + ".checkpoint";
}

RenderCommand parse_render_command(const std::vector<std::string>& args) {
    RenderCommand cmd;
    bool filter_named = false, filter_width_given = false;
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
        else if (a == "--sampler") {
            const std::string& v = value();
            if (v == "sobol") cmd.job.render.sampler = SamplerKind::Sobol;
            else if (v == "random") cmd.job.render.sampler = SamplerKind::Random;
            else throw UsageError("--sampler expects sobol or random, not '" + v + "'");
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
        else if (a == "--variant") cmd.import.variant = value();
        else if (a == "--env") cmd.environment.map_path = value();
        else if (a == "--env-color") {
            const std::string& v = value();
            float c[3];
            size_t start = 0;
            for (int k = 0; k < 3; ++k) {
                size_t comma = v.find(',', start);
                if ((k < 2) != (comma != std::string::npos)) throw UsageError("--env-color expects R,G,B (e.g. 0.8,0.9,1)");
                c[k] = static_cast<float>(parse_number(a, v.substr(start, comma - start), 0.0, 1e30));
                start = comma + 1;
            }
            cmd.environment.has_color = true;
            cmd.environment.color = Rgb(c[0], c[1], c[2]);
        }
        else if (a == "--env-strength") cmd.environment.strength = static_cast<float>(parse_number(a, value(), 0.0, 1e30));
        else if (a == "--env-rotate") cmd.environment.rotate_degrees = static_cast<float>(parse_number(a, value(), -1e6, 1e6));
        else if (a == "--display") cmd.output_settings.display.display = value();
        else if (a == "--view") cmd.output_settings.display.view = value();
        else if (a == "--look") cmd.output_settings.display.look = value();
        else if (a == "--exposure") cmd.output_settings.display.exposure = static_cast<float>(parse_number(a, value(), -64, 64));
        else if (a == "--gamma") cmd.output_settings.display.gamma = static_cast<float>(parse_number(a, value(), 0.01, 100));
        else if (a == "--half") cmd.output_settings.half = true;
        else if (a == "--filter") {
            const std::string& v = value();
            if (!parse_filter_name(v, &cmd.job.film.filter.type))
                throw UsageError("--filter expects box, gaussian or blackman-harris, not '" + v + "'");
            filter_named = true;
        }
        else if (a == "--filter-width") {
            cmd.job.film.filter.width = static_cast<float>(parse_number(a, value(), 0.01, 64));
            filter_width_given = true;
        }
        else if (a == "--exr-codec") {
            cmd.output_settings.exr_codec = value();
            if (!is_exr_codec(cmd.output_settings.exr_codec))
                throw UsageError("--exr-codec expects none, rle, zips, zip, piz, pxr24, b44, b44a, dwaa or dwab, not '" +
                                 cmd.output_settings.exr_codec + "'");
        }
        else if (a == "--passes") {
            const std::string v = value();
            cmd.output_settings.passes.clear();
            for (size_t start = 0; start <= v.size();) {
                size_t comma = std::min(v.find(',', start), v.size());
                std::string name = v.substr(start, comma - start);
                const auto& known = known_passes();
                if (std::find(known.begin(), known.end(), name) == known.end())
                    throw UsageError("--passes: unknown pass '" + name + "' (known: combined, depth, normal, albedo, variance)");
                if (std::find(cmd.output_settings.passes.begin(), cmd.output_settings.passes.end(), name) ==
                    cmd.output_settings.passes.end())
                    cmd.output_settings.passes.push_back(name);
                cmd.job.film.aovs = cmd.job.film.aovs || pass_needs_aovs(name);
                start = comma + 1;
            }
        }
        else if (a == "--skip-existing") cmd.skip_existing = true;
        else if (a == "--checkpoint") cmd.checkpoint_seconds = parse_number(a, value(), 0.0, 1e9);
        else if (a == "--resume") cmd.resume = true;
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
    // Blender's width default for its smooth filters; the box stays one pixel.
    if (filter_named && !filter_width_given && cmd.job.film.filter.type != FilterType::box)
        cmd.job.film.filter.width = 1.5f;
    if (cmd.inputs.empty()) throw UsageError("no input scene given");
    if (!cmd.environment.map_path.empty() && cmd.environment.has_color)
        throw UsageError("--env and --env-color exclude each other");
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
