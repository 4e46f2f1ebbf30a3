#include "cli_options.h"

#include "animation_options.h"
#include "farm_options.h"

#include <glob.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <limits>

namespace veach::cli {

const char* usage_text() {
    return R"(usage: veach render INPUT... -o OUTPUT [options]
       veach merge PART.vpart... -o OUTPUT [--expect-spp N]   (see veach merge --help)
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
  --threads N             worker threads (default: the CPUs this process may use: its
                          affinity mask and cgroup CPU quota, e.g. taskset or a farm's binding)
  --integrator NAME       auto (default: bidirectional path tracing with the strategies the
                          scene needs, chosen per render), bdpt (every strategy), pt (path
                          tracing) or lt (light tracing alone, for verification)
  --sampler KIND          sobol (default: Owen-scrambled Sobol pairs for the first dimensions)
                          or random (independent numbers)
  --bdpt-strategy S,T     bdpt: render only the strategy with S light and T camera vertices,
                          unweighted (for verification)
  --max-depth N           maximum number of bounces (default 64)
  --noise TARGET          adaptive sampling: stop pixels whose estimated relative error is below
                          TARGET (e.g. 0.01; default 0: off, every pixel gets --spp)
  --camera NAME|INDEX     camera to render (default: the first)
  --scene N               glTF scene index (default: the file's default scene)
  --spot-falloff MODE     auto (default), blender or gltf: the spot cone profile
  --default-material MODE auto (default), blender or gltf: what an object without a material
                          is (blender: Cycles' default surface, Lambertian 0.8; gltf: the
                          spec's white rough metal; auto: blender for Blender's exports)
  --variant NAME          KHR_materials_variants: render with this variant's materials
  --frame N               render the scene at frame N: glTF time N / fps, every animation,
                          skin and morph target evaluated (default: the file's static pose)
  --frames A-B[:STEP]     render frames A to B (every STEP-th) from one load of the scene; the
                          outputs need {frame} or #### (zero-padded: out/f_####.exr)
  --fps F                 frames per second for --frame and --frames (default 24, Blender's)
  --animation NAME|INDEX|all  the animation played (default all: every one at once)
  --animated-seed         mix the frame into --seed, so frames do not share one noise pattern
  --shutter OPEN,CLOSE    motion blur: each camera sample sees the scene at one time between
                          frame + OPEN and frame + CLOSE, in frames (Blender's shutter 0.5 is
                          -0.25,0.25); camera, objects and deforming meshes move (default: off)
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
  --transparent           Cycles' Film > Transparent: camera rays that escape see no
                          environment (which still lights the scene) and alpha is the pixel's
                          fraction of camera samples that hit geometry (EXR, PNG, TIFF keep it;
                          not with --samples or --pixelbounds)
  --denoise               denoise the image (a feature-guided regression on two half images;
                          biased: its error goes to zero as samples grow); with --passes the
                          EXR also gets noisy (the image as rendered) and denoising_normal,
                          denoising_albedo, denoising_depth (not with --samples or --pixelbounds)
  --half                  EXR with half floats
  --exr-codec NAME        EXR compression: none, rle, zips, zip (default), piz, pxr24, b44,
                          b44a, dwaa, dwab (zip:N, dwaa:N set a level)
  --passes LIST           multi-layer EXR with Blender's pass names, from combined, depth,
                          normal, albedo, variance (e.g. combined,depth,normal,albedo), and
                          with --denoise noisy, denoising_normal, denoising_albedo,
                          denoising_depth
  --quality Q             JPEG quality 1-100 (default 95)
  --bits 8|16             PNG/TIFF bit depth (default 8)
  --stats-json FILE       write render statistics as JSON
  --skip-existing         skip inputs whose outputs are complete (veach:complete yes, the
                          same spp, sample range and tile; an interrupted one is rendered again)
  --checkpoint SECONDS    keep OUTPUT.checkpoint up to date (at the first pass boundary after
                          SECONDS; 0 every pass) so that a killed render can resume
  --resume                continue from OUTPUT.checkpoint when it exists (same settings; spp
                          may grow); the result equals an uninterrupted render
  --samples A:B           render only sample indices [A, B) of the --spp N render
                          (0 <= A < B <= N; not with --noise or --time): a part for a farm
  --pixelbounds X0,X1,Y0,Y1  render only pixels [X0,X1) x [Y0,Y1) (pbrt-v4's order); light
                          tracing's splats (bdpt, lt, auto) still land on the whole frame
                          An output ending in .vpart is a part file (exact sums, splats, sample
                          range, bounds, identity) for `veach merge`
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

ApiOption int_option(const std::string& name, long long v) { return {ApiOption::Type::Int, name, v, 0, {}}; }
ApiOption float_option(const std::string& name, double v) { return {ApiOption::Type::Float, name, 0, v, {}}; }
ApiOption string_option(const std::string& name, const std::string& v) {
    return {ApiOption::Type::String, name, 0, 0, v};
}

// A scene (never loaded) and a render of an empty scene on which the parser tries values: the
// library's own checks decide what is valid, the command only words the usage message.
class Probe {
public:
    explicit Probe(VeachDevice device) {
        static const char k_empty_gltf[] = R"({"asset": {"version": "2.0"}, "scenes": [{"nodes": []}], "scene": 0})";
        m_scene = veachNewScene(device);
        VeachScene empty = veachNewSceneFromMemory(device, k_empty_gltf, sizeof(k_empty_gltf) - 1, "gltf", nullptr);
        if (empty) m_render = veachNewRender(empty);
        veachReleaseScene(empty);  // the render holds it
        if (!m_scene || !m_render)
            throw std::runtime_error(std::string("cannot start libveach: ") + veachGetLastError());
    }
    ~Probe() {
        veachReleaseRender(m_render);
        veachReleaseScene(m_scene);
    }
    Probe(const Probe&) = delete;
    Probe& operator=(const Probe&) = delete;
    bool scene_accepts(const ApiOption& o) const { return apply_scene_option(m_scene, o) == VEACH_ERROR_NONE; }
    bool render_accepts(const ApiOption& o) const { return apply_render_option(m_render, o) == VEACH_ERROR_NONE; }

private:
    VeachScene m_scene = nullptr;
    VeachRender m_render = nullptr;
};

// A string the library returns through a caller's buffer.
template <class Getter>
std::string get_string(Getter&& get) {
    size_t length = 0;
    if (get(nullptr, 0, &length) != VEACH_ERROR_NONE) return {};
    std::string s(length + 1, '\0');
    get(s.data(), s.size(), &length);
    s.resize(std::min(length, s.size() - 1));
    return s;
}

// A device list (one name a line) joined with `separator`.
std::string device_list(VeachDevice device, const char* name, const char* separator) {
    std::string s = device_string(device, name);
    for (size_t pos; (pos = s.find('\n')) != std::string::npos;) s.replace(pos, 1, separator);
    return s;
}

// A device list as "a, b or c", for the refusals that name what is accepted.
std::string device_choices(VeachDevice device, const char* name) {
    std::string s = device_list(device, name, ", ");
    size_t last = s.rfind(", ");
    if (last != std::string::npos) s.replace(last, 2, " or ");
    return s;
}

}  // namespace

std::string device_string(VeachDevice d, const char* name) {
    return get_string([&](char* b, size_t n, size_t* l) { return veachGetDeviceString(d, name, b, n, l); });
}
std::string scene_string(VeachScene s, const char* name) {
    return get_string([&](char* b, size_t n, size_t* l) { return veachGetSceneString(s, name, b, n, l); });
}
std::string render_string(VeachRender r, const char* name) {
    return get_string([&](char* b, size_t n, size_t* l) { return veachGetString(r, name, b, n, l); });
}

VeachError apply_scene_option(VeachScene scene, const ApiOption& o) {
    switch (o.type) {
        case ApiOption::Type::Int: return veachSetSceneInt(scene, o.name.c_str(), o.i);
        case ApiOption::Type::Float: return veachSetSceneFloat(scene, o.name.c_str(), o.f);
        default: return veachSetSceneString(scene, o.name.c_str(), o.s.c_str());
    }
}

VeachError apply_render_option(VeachRender render, const ApiOption& o) {
    switch (o.type) {
        case ApiOption::Type::Int: return veachSetInt(render, o.name.c_str(), o.i);
        case ApiOption::Type::Float: return veachSetFloat(render, o.name.c_str(), o.f);
        default: return veachSetString(render, o.name.c_str(), o.s.c_str());
    }
}

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

RenderCommand parse_render_command(const std::vector<std::string>& args, VeachDevice device) {
    RenderCommand cmd;
    Probe probe(device);
    auto scene_opt = [&](ApiOption o, const std::string& refusal) {
        if (!refusal.empty() && !probe.scene_accepts(o)) throw UsageError(refusal);
        cmd.scene_options.push_back(std::move(o));
    };
    auto render_opt = [&](ApiOption o, const std::string& refusal = {}) {
        if (!refusal.empty() && !probe.render_accepts(o)) throw UsageError(refusal);
        cmd.render_options.push_back(std::move(o));
    };
    bool filter_smooth = false, filter_width_given = false, env_map = false;
    std::string env_color;  // the last --env-color, applied after the loop
    std::string integrator = "auto";
    for (size_t i = 0; i < args.size(); ++i) {
        const std::string& a = args[i];
        auto value = [&]() -> const std::string& {
            if (i + 1 >= args.size()) throw UsageError(a + " needs a value");
            return args[++i];
        };
        constexpr long long int_max = std::numeric_limits<int>::max();
        if (parse_farm_render_option(args, i, cmd)) continue;  // --samples, --pixelbounds
        if (parse_animation_option(args, i, cmd)) continue;    // --frame(s), --fps, --animation
        if (a == "-o" || a == "--output")
            cmd.outputs.push_back(value());
        else if (a == "--width")
            render_opt(int_option("width", parse_integer(a, value(), 1, 65536)));
        else if (a == "--height")
            render_opt(int_option("height", parse_integer(a, value(), 1, 65536)));
        else if (a == "--spp")
            render_opt(int_option("spp", parse_integer(a, value(), 1, int_max)));
        else if (a == "--time")
            render_opt(float_option("time_limit", parse_number(a, value(), 0.0, 1e9)));
        else if (a == "--seed")
            render_opt(int_option("seed", parse_integer(a, value(), 0, std::numeric_limits<long long>::max())));
        else if (a == "--threads")
            render_opt(int_option("threads", parse_integer(a, value(), 0, 4096)));
        else if (a == "--integrator")
            integrator = value();
        else if (a == "--bdpt-strategy") {
            const std::string& v = value();
            size_t comma = v.find(',');
            if (comma == std::string::npos) throw UsageError("--bdpt-strategy expects s,t (e.g. 2,2)");
            render_opt(int_option("bdpt_s", parse_integer(a, v.substr(0, comma), 0, 1000)));
            render_opt(int_option("bdpt_t", parse_integer(a, v.substr(comma + 1), 1, 1000)));
        } else if (a == "--sampler") {
            const std::string& v = value();
            render_opt(string_option("sampler", v), "--sampler expects sobol or random, not '" + v + "'");
        } else if (a == "--max-depth")
            render_opt(int_option("max_depth", parse_integer(a, value(), 0, 100000)));
        else if (a == "--noise")
            render_opt(float_option("noise", parse_number(a, value(), 0.0, 1e6)));
        else if (a == "--camera")
            render_opt(string_option("camera", value()));  // checked against the scene
        else if (a == "--scene")
            scene_opt(int_option("scene_index", parse_integer(a, value(), 0, int_max)), {});
        else if (a == "--spot-falloff") {
            const std::string& v = value();
            scene_opt(string_option("spot_falloff", v),
                      "--spot-falloff expects auto, blender or gltf, not '" + v + "'");
        } else if (a == "--default-material") {
            const std::string& v = value();
            scene_opt(string_option("default_material", v),
                      "--default-material expects auto, blender or gltf, not '" + v + "'");
        } else if (a == "--allow-external-files")
            scene_opt(int_option("allow_external_files", 1), {});
        else if (a == "--variant")
            scene_opt(string_option("variant", value()), {});  // checked against the file
        else if (a == "--env") {
            const std::string& v = value();
            env_map = !v.empty();
            scene_opt(string_option("env_map", v), {});
        } else if (a == "--env-color") {
            const std::string& v = value();
            size_t start = 0;
            for (int k = 0; k < 3; ++k) {
                size_t comma = v.find(',', start);
                if ((k < 2) != (comma != std::string::npos))
                    throw UsageError("--env-color expects R,G,B (e.g. 0.8,0.9,1)");
                parse_number(a, v.substr(start, comma - start), 0.0, 1e30);
                start = comma + 1;
            }
            env_color = v;
        } else if (a == "--env-strength")
            scene_opt(float_option("env_strength", parse_number(a, value(), 0.0, 1e30)), {});
        else if (a == "--env-rotate")
            scene_opt(float_option("env_rotate", parse_number(a, value(), -1e6, 1e6)), {});
        else if (a == "--display")
            render_opt(string_option("display", value()));
        else if (a == "--view")
            render_opt(string_option("view", value()));
        else if (a == "--look")
            render_opt(string_option("look", value()));
        else if (a == "--exposure")
            render_opt(float_option("exposure", parse_number(a, value(), -64, 64)));
        else if (a == "--gamma")
            render_opt(float_option("gamma", parse_number(a, value(), 0.01, 100)));
        else if (a == "--half")
            render_opt(int_option("half", 1));
        else if (a == "--transparent")
            render_opt(int_option("transparent", 1));
        else if (a == "--denoise")
            render_opt(int_option("denoise", 1));
        else if (a == "--filter") {
            const std::string& v = value();
            render_opt(string_option("filter", v),
                       "--filter expects " + device_choices(device, "filters") + ", not '" + v + "'");
            filter_smooth = v != "box";
        } else if (a == "--filter-width") {
            render_opt(float_option("filter_width", parse_number(a, value(), 0.01, 64)));
            filter_width_given = true;
        } else if (a == "--exr-codec") {
            const std::string& v = value();
            render_opt(
                string_option("exr_codec", v),
                "--exr-codec expects " + device_choices(device, "exr_codecs") + ", not '" + v + "'");
        } else if (a == "--passes") {
            const std::string v = value();
            for (size_t start = 0; start <= v.size();) {
                size_t comma = std::min(v.find(',', start), v.size());
                std::string name = v.substr(start, comma - start);
                if (name.empty() || !probe.render_accepts(string_option("passes", name)))
                    throw UsageError("--passes: unknown pass '" + name +
                                     "' (known: " + device_list(device, "passes", ", ") + ")");
                start = comma + 1;
            }
            render_opt(string_option("passes", v));
        } else if (a == "--skip-existing")
            cmd.skip_existing = true;
        else if (a == "--checkpoint")
            cmd.checkpoint_seconds = parse_number(a, value(), 0.0, 1e9);
        else if (a == "--resume")
            cmd.resume = true;
        else if (a == "--quality")
            render_opt(int_option("quality", parse_integer(a, value(), 1, 100)));
        else if (a == "--bits") {
            int b = static_cast<int>(parse_integer(a, value(), 8, 16));
            if (b != 8 && b != 16) throw UsageError("--bits expects 8 or 16");
            render_opt(int_option("bits", b));
        } else if (a == "--stats-json")
            cmd.stats_json = value();
        else if (a == "-q" || a == "--quiet")
            cmd.quiet = true;
        else if (!a.empty() && a[0] == '-')
            throw UsageError("unknown option '" + a + "'");
        else
            expand_input(a, cmd.inputs);
    }
    // Blender's width default for its smooth filters; the box stays one pixel.
    if (filter_smooth && !filter_width_given) render_opt(float_option("filter_width", 1.5));
    if (cmd.inputs.empty()) throw UsageError("no input scene given");
    if (env_map && !env_color.empty()) throw UsageError("--env and --env-color exclude each other");
    if (!env_color.empty())
        scene_opt(string_option("env_color", env_color), "--env-color expects R,G,B (e.g. 0.8,0.9,1)");
    if (cmd.outputs.empty()) throw UsageError("no output given (-o FILE)");
    check_animation_options(cmd);  // several frames need {frame} patterns: before {stem}'s check
    for (const std::string& o : cmd.outputs)
        if (cmd.inputs.size() > 1 && o.find("{stem}") == std::string::npos)
            throw UsageError("several inputs need an output pattern with {stem}, e.g. -o out/{stem}.exr");
    render_opt(string_option("integrator", integrator), "unknown integrator '" + integrator + "'");
    check_farm_render_options(cmd);
    return cmd;
}

}  // namespace veach::cli
