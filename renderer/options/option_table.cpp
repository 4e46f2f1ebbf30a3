#include "options/option_table.h"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cstdio>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "film/pixel_filter.h"
#include "integrators/integrator.h"

namespace veach {
namespace {

constexpr long long k_int = std::numeric_limits<int>::max();
constexpr long long k_long = std::numeric_limits<long long>::max();

std::invalid_argument refused(const std::string& message) { return std::invalid_argument(message); }

// The shortest text that reads back as the same number ("0.8", "-0.0104").
template <class T>
std::string shortest(T v) {
    char buf[64];
    auto [end, ec] = std::to_chars(buf, buf + sizeof(buf), v);
    return ec == std::errc() ? std::string(buf, end) : std::string("nan");
}

std::string join(const std::vector<std::string>& items, const char* separator) {
    std::string out;
    for (const std::string& i : items) out += (out.empty() ? "" : separator) + i;
    return out;
}

std::vector<std::string> auto_blender_gltf() { return {"auto", "blender", "gltf"}; }
std::vector<std::string> samplers() { return {"sobol", "random"}; }
std::vector<std::string> filters() { return filter_names(); }
std::vector<std::string> codecs() { return exr_codec_names(); }
std::vector<std::string> passes() { return known_passes(); }

void expect_choice(const char* name, const std::string& v, const std::vector<std::string>& choices) {
    if (std::find(choices.begin(), choices.end(), v) == choices.end())
        throw refused(std::string(name) + " expects " + choice_list(choices) + ", not '" + v + "'");
}

// "combined,depth": each a known pass, once, in the order given.
std::vector<std::string> parse_passes(const std::string& v) {
    std::vector<std::string> out;
    if (v.empty()) return out;
    const auto& known = known_passes();
    for (size_t start = 0; start <= v.size();) {
        size_t comma = std::min(v.find(',', start), v.size());
        std::string name = v.substr(start, comma - start);
        if (std::find(known.begin(), known.end(), name) == known.end())
            throw refused("passes: unknown pass '" + name + "' (known: " + join(known, ", ") + ")");
        if (std::find(out.begin(), out.end(), name) == out.end()) out.push_back(name);
        start = comma + 1;
    }
    return out;
}

// "X0,X1,Y0,Y1" (pbrt's order), or "" for the whole frame. The image size is known only when
// rendering, which checks the bounds against it.
void parse_pixel_bounds(const std::string& v, PartSettings* part) {
    if (v.empty()) {
        part->has_bounds = false;
        return;
    }
    long long b[4];
    const char* p = v.c_str();
    for (int k = 0; k < 4; ++k) {
        char* end = nullptr;
        errno = 0;
        b[k] = std::strtoll(p, &end, 10);
        if (end == p || errno != 0 || b[k] < 0 || b[k] > 65536 || *end != (k < 3 ? ',' : '\0'))
            throw refused("pixelbounds expects X0,X1,Y0,Y1 (whole numbers, X0 < X1, Y0 < Y1), not '" + v + "'");
        p = end + 1;
    }
    if (b[0] >= b[1] || b[2] >= b[3])
        throw refused("pixelbounds expects X0,X1,Y0,Y1 with X0 < X1 and Y0 < Y1, not '" + v + "'");
    part->has_bounds = true;
    part->x0 = static_cast<int>(b[0]);
    part->x1 = static_cast<int>(b[1]);
    part->y0 = static_cast<int>(b[2]);
    part->y1 = static_cast<int>(b[3]);
}

// "NAME=VALUE" lines: a name without '=', not one the writer sets itself; later lines win.
std::vector<std::pair<std::string, std::string>> parse_attributes(const std::string& text) {
    std::vector<std::pair<std::string, std::string>> out;
    for (size_t start = 0; start < text.size();) {
        const size_t nl = std::min(text.find('\n', start), text.size());
        const std::string line = text.substr(start, nl - start);
        start = nl + 1;
        if (line.empty()) continue;
        const size_t eq = line.find('=');
        const std::string name = eq == std::string::npos ? line : line.substr(0, eq);
        if (eq == std::string::npos || name.empty() || name.find_first_of(" \t\r;") != std::string::npos)
            throw refused("attributes expects NAME=VALUE lines (a name without spaces, '=' or ';'), not '" + line +
                          "'");
        if (name.rfind("veach:", 0) == 0 || name.rfind("oiio:", 0) == 0 || name == "Software" ||
            name == "compression" || name == "Compression" || name == "ImageDescription")
            throw refused("attributes: '" + name + "' is written by veach itself");
        std::string value = line.substr(eq + 1);
        if (value.find_first_of("\r;") != std::string::npos)
            throw refused("attributes: the value of '" + name + "' holds ';' or a carriage return");
        auto same = std::find_if(out.begin(), out.end(), [&](const auto& a) { return a.first == name; });
        if (same != out.end()) out.erase(same);
        out.emplace_back(name, std::move(value));
    }
    return out;
}

// `count` finite numbers separated by commas, each within [lo, hi]; false otherwise.
bool parse_numbers(const std::string& v, int count, double lo, double hi, double* out) {
    const char* p = v.c_str();
    for (int k = 0; k < count; ++k) {
        char* end = nullptr;
        out[k] = std::strtod(p, &end);
        if (end == p || !std::isfinite(out[k]) || out[k] < lo || out[k] > hi || *end != (k + 1 < count ? ',' : '\0'))
            return false;
        p = end + 1;
    }
    return true;
}

OptionValue I(long long v) { return OptionValue::of_int(v); }
OptionValue F(double v) { return OptionValue::of_float(v); }
OptionValue S(std::string v) { return OptionValue::of_string(std::move(v)); }

// Row helpers: the columns every row has, then its storage.
using Set = void (*)(OptionTargets&, const OptionValue&);
using Get = OptionValue (*)(const OptionTargets&);

OptionSpec int_row(const char* name, OptionObject object, long long lo, long long hi, bool identity, const char* help,
                   Set set, Get get, const char* flag = nullptr, const char* metavar = "N", bool is_switch = false,
                   const char* aliases = "") {
    return {name, object, OptionKind::Int, lo, hi, 0, 0, nullptr, false, identity, help, flag, metavar, aliases,
            is_switch, false, set, get};
}

OptionSpec float_row(const char* name, OptionObject object, double lo, double hi, bool identity, const char* help,
                     Set set, Get get, const char* flag = nullptr, const char* metavar = "X") {
    return {name, object, OptionKind::Float, 0, 0, lo, hi, nullptr, false, identity, help, flag, metavar, "", false,
            false, set, get};
}

OptionSpec string_row(const char* name, OptionObject object, std::vector<std::string> (*choices)(), bool identity,
                      const char* help, Set set, Get get, const char* flag = nullptr, const char* metavar = "NAME",
                      bool checked_by_scene = false, bool choices_form = false) {
    return {name, object, OptionKind::String, 0, 0, 0, 0, choices, choices_form, identity, help, flag, metavar, "",
            false, checked_by_scene, set, get};
}

constexpr OptionObject R = OptionObject::Render;
constexpr OptionObject SC = OptionObject::Scene;

std::vector<OptionSpec> make_table() {
    std::vector<OptionSpec> t;
    // ---- Render options (veachSetInt/Float/String on a render) ----
    t.push_back(int_row("width", R, 1, 65536, true, "image width in pixels",
        [](OptionTargets& o, const OptionValue& v) { o.job->width = static_cast<int>(v.i); },
        [](const OptionTargets& o) { return I(o.job->width > 0 ? o.job->width : 1920); }));
    t.push_back(int_row("height", R, 0, 65536, true, "image height in pixels (0: from the camera's aspect ratio)",
        [](OptionTargets& o, const OptionValue& v) { o.job->height = static_cast<int>(v.i); },
        [](const OptionTargets& o) { return I(o.job->height); }));
    t.push_back(int_row("spp", R, 1, k_int, false, "samples per pixel (the most any pixel takes)",
        [](OptionTargets& o, const OptionValue& v) { o.job->render.spp = static_cast<int>(v.i); },
        [](const OptionTargets& o) { return I(o.job->render.spp); }));
    t.push_back(float_row("time_limit", R, 0, 1e9, false,
        "stop after this many seconds, at whichever of spp and time comes first (0: none)",
        [](OptionTargets& o, const OptionValue& v) { o.job->render.time_limit = v.f; },
        [](const OptionTargets& o) { return F(o.job->render.time_limit); }, "--time", "SECONDS"));
    t.push_back(int_row("seed", R, 0, k_long, true, "random seed",
        [](OptionTargets& o, const OptionValue& v) { o.job->render.seed = static_cast<uint64_t>(v.i); },
        [](const OptionTargets& o) { return I(static_cast<long long>(o.job->render.seed)); }));
    t.push_back(int_row("threads", R, 0, 4096, false,
        "worker threads (0: the CPUs this process may use: its affinity mask and cgroup CPU quota)",
        [](OptionTargets& o, const OptionValue& v) { o.job->render.threads = static_cast<int>(v.i); },
        [](const OptionTargets& o) { return I(o.job->render.threads); }, nullptr, "N", false, "--nthreads"));
    t.push_back(string_row("integrator", R, integrator_names, true,
        "auto (bidirectional path tracing with the strategies the scene needs, chosen per render), bdpt (every "
        "strategy), pt (path tracing) or lt (light tracing alone, for verification)",
        [](OptionTargets& o, const OptionValue& v) { o.job->render.integrator = v.s; },
        [](const OptionTargets& o) { return S(o.job->render.integrator); }));
    t.push_back(string_row("sampler", R, samplers, true,
        "sobol (Owen-scrambled Sobol pairs for the first dimensions) or random (independent numbers)",
        [](OptionTargets& o, const OptionValue& v) {
            o.job->render.sampler = v.s == "random" ? SamplerKind::Random : SamplerKind::Sobol;
        },
        [](const OptionTargets& o) { return S(o.job->render.sampler == SamplerKind::Random ? "random" : "sobol"); },
        nullptr, "KIND"));
    t.push_back(int_row("max_depth", R, 0, 100000, true, "maximum number of bounces",
        [](OptionTargets& o, const OptionValue& v) { o.job->render.max_depth = static_cast<int>(v.i); },
        [](const OptionTargets& o) { return I(o.job->render.max_depth); }));
    t.push_back(int_row("bdpt_s", R, -1, 1000, true,
        "bdpt: render only the strategy with this many light vertices, unweighted (-1: all)",
        [](OptionTargets& o, const OptionValue& v) { o.job->render.bdpt_s = static_cast<int>(v.i); },
        [](const OptionTargets& o) { return I(o.job->render.bdpt_s); }, ""));
    t.push_back(int_row("bdpt_t", R, -1, 1000, true,
        "bdpt: render only the strategy with this many camera vertices, unweighted (-1: all)",
        [](OptionTargets& o, const OptionValue& v) { o.job->render.bdpt_t = static_cast<int>(v.i); },
        [](const OptionTargets& o) { return I(o.job->render.bdpt_t); }, ""));
    t.push_back(float_row("noise", R, 0, 1e6, true,
        "adaptive sampling: stop pixels whose estimated relative error is below this (0: off)",
        [](OptionTargets& o, const OptionValue& v) { o.job->render.noise_target = static_cast<float>(v.f); },
        [](const OptionTargets& o) { return F(o.job->render.noise_target); }, nullptr, "TARGET"));
    t.push_back(string_row("camera", R, nullptr, true, "the camera to render, a name or an index (\"\": the first)",
        [](OptionTargets& o, const OptionValue& v) {
            if (o.loaded) select_camera(*o.loaded, v.s);  // throws naming the scene's cameras
            o.job->camera = v.s;
        },
        [](const OptionTargets& o) { return S(o.job->camera); }, nullptr, "NAME|INDEX", true));
    t.push_back(string_row("filter", R, filters, true, "pixel filter, as Cycles' (light-tracing splats use it too)",
        [](OptionTargets& o, const OptionValue& v) { parse_filter_name(v.s, &o.job->film.filter.type); },
        [](const OptionTargets& o) { return S(filter_name(o.job->film.filter.type)); }));
    t.push_back(float_row("filter_width", R, 0.01, 64, true, "pixel filter width as Blender's, in pixels",
        [](OptionTargets& o, const OptionValue& v) { o.job->film.filter.width = static_cast<float>(v.f); },
        [](const OptionTargets& o) { return F(o.job->film.filter.width); }, nullptr, "PIXELS"));
    t.push_back(int_row("transparent", R, 0, 1, true,
        "Cycles' Film > Transparent: escaping camera rays see no environment, alpha is coverage",
        [](OptionTargets& o, const OptionValue& v) { o.job->render.transparent = o.job->film.alpha = v.i != 0; },
        [](const OptionTargets& o) { return I(o.job->render.transparent ? 1 : 0); }, nullptr, "", true));
    t.push_back(int_row("denoise", R, 0, 1, true,
        "denoise the image (a feature-guided regression on two half images; biased: its error goes to zero as "
        "samples grow); the passes noisy, denoising_normal, denoising_albedo, denoising_depth come with it; not "
        "in parts",
        [](OptionTargets& o, const OptionValue& v) { o.job->denoise = v.i != 0; },
        [](const OptionTargets& o) { return I(o.job->denoise ? 1 : 0); }, nullptr, "", true));
    t.push_back(int_row("aovs", R, 0, 1, true, "record the depth, normal and albedo passes",
        [](OptionTargets& o, const OptionValue& v) { o.job->film.aovs = v.i != 0; },
        [](const OptionTargets& o) { return I(o.job->film.aovs ? 1 : 0); }, ""));
    t.push_back(string_row("display", R, nullptr, false, "OpenColorIO display for PNG/JPEG/TIFF (\"\": the config's)",
        [](OptionTargets& o, const OptionValue& v) { o.output->display.display = v.s; },
        [](const OptionTargets& o) { return S(o.output->display.display); }));
    t.push_back(string_row("view", R, nullptr, false, "OpenColorIO view (\"\": the display's default)",
        [](OptionTargets& o, const OptionValue& v) { o.output->display.view = v.s; },
        [](const OptionTargets& o) { return S(o.output->display.view); }));
    t.push_back(string_row("look", R, nullptr, false, "OpenColorIO look (\"\": none)",
        [](OptionTargets& o, const OptionValue& v) { o.output->display.look = v.s; },
        [](const OptionTargets& o) { return S(o.output->display.look); }));
    t.push_back(float_row("exposure", R, -64, 64, false, "exposure in stops before the view transform",
        [](OptionTargets& o, const OptionValue& v) { o.output->display.exposure = static_cast<float>(v.f); },
        [](const OptionTargets& o) { return F(o.output->display.exposure); }, nullptr, "STOPS"));
    t.push_back(float_row("gamma", R, 0.01, 100, false, "display gamma after the view transform",
        [](OptionTargets& o, const OptionValue& v) { o.output->display.gamma = static_cast<float>(v.f); },
        [](const OptionTargets& o) { return F(o.output->display.gamma); }, nullptr, "G"));
    t.push_back(string_row("exr_codec", R, codecs, false, "EXR compression (zip:N and dwaa:N set a level)",
        [](OptionTargets& o, const OptionValue& v) {
            if (!is_exr_codec(v.s))
                throw refused("exr_codec expects " + choice_list(exr_codec_names()) + ", not '" + v.s + "'");
            o.output->exr_codec = v.s;
        },
        [](const OptionTargets& o) { return S(o.output->exr_codec); }, nullptr, "NAME", false, true));
    t.push_back(string_row("passes", R, passes, false,
        "multi-layer EXR with Blender's pass names, a comma-separated list (depth, normal, albedo turn aovs on)",
        [](OptionTargets& o, const OptionValue& v) {
            o.output->passes = parse_passes(v.s);
            for (const std::string& p : o.output->passes)
                if (pass_needs_aovs(p)) o.job->film.aovs = true;
        },
        [](const OptionTargets& o) { return S(join(o.output->passes, ",")); }, nullptr, "LIST", false, true));
    t.push_back(int_row("half", R, 0, 1, false, "EXR with half floats",
        [](OptionTargets& o, const OptionValue& v) { o.output->half = v.i != 0; },
        [](const OptionTargets& o) { return I(o.output->half ? 1 : 0); }, nullptr, "", true));
    t.push_back(int_row("quality", R, 1, 100, false, "JPEG quality",
        [](OptionTargets& o, const OptionValue& v) { o.output->quality = static_cast<int>(v.i); },
        [](const OptionTargets& o) { return I(o.output->quality); }, nullptr, "Q"));
    t.push_back(int_row("bits", R, 8, 16, false, "PNG/TIFF bits per channel: 8 or 16",
        [](OptionTargets& o, const OptionValue& v) {
            if (v.i != 8 && v.i != 16) throw refused("bits must be 8 or 16");
            o.output->bits = static_cast<int>(v.i);
        },
        [](const OptionTargets& o) { return I(o.output->bits); }, nullptr, "8|16"));
    t.push_back(string_row("attributes", R, nullptr, false,
        "the host's own image metadata, NAME=VALUE lines (numbers written as numbers; names veach:*, oiio:*, "
        "Software, compression and ImageDescription are the writer's)",
        [](OptionTargets& o, const OptionValue& v) { o.output->user_attributes = parse_attributes(v.s); },
        [](const OptionTargets& o) {
            std::string out;
            for (const auto& [name, value] : o.output->user_attributes)
                out += (out.empty() ? "" : "\n") + name + "=" + value;
            return S(out);
        },
        "", "NAME=VALUE"));
    t.push_back(int_row("snapshots", R, 0, 1, false,
        "while rendering, keep the film so far at every pass boundary for veachGetPass and veachWriteImage (0: "
        "only after one of them asked during the render)",
        [](OptionTargets& o, const OptionValue& v) { o.job->snapshots = v.i != 0; },
        [](const OptionTargets& o) { return I(o.job->snapshots ? 1 : 0); }, ""));
    t.push_back(string_row("checkpoint", R, nullptr, false,
        "the file holding the film's state between passes, so that a killed render resumes (\"\": none)",
        [](OptionTargets& o, const OptionValue& v) { o.job->checkpoint.path = v.s; },
        [](const OptionTargets& o) { return S(o.job->checkpoint.path); }, "", "FILE"));
    t.push_back(float_row("checkpoint_interval", R, -1e9, 1e9, false,
        "keep the checkpoint up to date at the first pass boundary after this many seconds (0: every pass, "
        "negative: never)",
        [](OptionTargets& o, const OptionValue& v) {
            o.job->checkpoint.write = v.f >= 0;
            o.job->checkpoint.interval_seconds = v.f;
        },
        [](const OptionTargets& o) {
            const CheckpointSettings& c = o.job->checkpoint;
            return F(c.write || c.interval_seconds < 0 ? c.interval_seconds : -1.0);
        },
        ""));
    t.push_back(int_row("resume", R, 0, 1, false, "start from the checkpoint file when it exists",
        [](OptionTargets& o, const OptionValue& v) { o.job->checkpoint.resume = v.i != 0; },
        [](const OptionTargets& o) { return I(o.job->checkpoint.resume ? 1 : 0); }, ""));
    t.push_back(int_row("sample_begin", R, 0, k_int - 1, false, "render only sample indices from this one on",
        [](OptionTargets& o, const OptionValue& v) { o.job->part.sample_begin = static_cast<int>(v.i); },
        [](const OptionTargets& o) { return I(o.job->part.sample_begin); }, ""));
    t.push_back(int_row("sample_end", R, 0, k_int, false, "render only sample indices before this one (0: spp)",
        [](OptionTargets& o, const OptionValue& v) { o.job->part.sample_end = static_cast<int>(v.i); },
        [](const OptionTargets& o) { return I(o.job->part.sample_end); }, ""));
    t.push_back(string_row("pixelbounds", R, nullptr, false,
        "render only pixels [X0,X1) x [Y0,Y1), pbrt-v4's order (\"\": the whole frame)",
        [](OptionTargets& o, const OptionValue& v) { parse_pixel_bounds(v.s, &o.job->part); },
        [](const OptionTargets& o) {
            const PartSettings& p = o.job->part;
            return S(p.has_bounds ? std::to_string(p.x0) + "," + std::to_string(p.x1) + "," + std::to_string(p.y0) +
                                        "," + std::to_string(p.y1)
                                  : "");
        },
        "", "X0,X1,Y0,Y1"));

    // ---- Scene options (veachSetSceneInt/Float/String before the load) ----
    t.push_back(int_row("scene_index", SC, -1, k_int, true, "glTF scene index (-1: the file's default scene)",
        [](OptionTargets& o, const OptionValue& v) { o.scene->import.scene_index = static_cast<int>(v.i); },
        [](const OptionTargets& o) { return I(o.scene->import.scene_index); }, "--scene"));
    t.push_back(int_row("allow_external_files", SC, 0, 1, false, "let URIs point outside the glTF's folder",
        [](OptionTargets& o, const OptionValue& v) { o.scene->import.allow_external_files = v.i != 0; },
        [](const OptionTargets& o) { return I(o.scene->import.allow_external_files ? 1 : 0); }, nullptr, "", true));
    t.push_back(string_row("variant", SC, nullptr, true, "KHR_materials_variants: render with this variant's materials",
        [](OptionTargets& o, const OptionValue& v) { o.scene->import.variant = v.s; },
        [](const OptionTargets& o) { return S(o.scene->import.variant); }, nullptr, "NAME", true));
    t.push_back(string_row("spot_falloff", SC, auto_blender_gltf, true,
        "the spot cone profile (auto: Blender's for Blender's exports)",
        [](OptionTargets& o, const OptionValue& v) {
            o.scene->import.spot_profile =
                v.s == "blender" ? SpotProfile::Blender : v.s == "gltf" ? SpotProfile::Gltf : SpotProfile::Auto;
        },
        [](const OptionTargets& o) { return S(spot_profile_name(o.scene->import.spot_profile)); }, nullptr, "MODE"));
    t.push_back(string_row("default_material", SC, auto_blender_gltf, true,
        "what an object without a material is (blender: Lambertian 0.8; gltf: the spec's; auto: blender for "
        "Blender's exports)",
        [](OptionTargets& o, const OptionValue& v) {
            o.scene->import.default_material = v.s == "blender" ? DefaultMaterial::Blender
                                               : v.s == "gltf"  ? DefaultMaterial::Gltf
                                                                : DefaultMaterial::Auto;
        },
        [](const OptionTargets& o) { return S(default_material_name(o.scene->import.default_material)); }, nullptr,
        "MODE"));
    // The map's path is not the identity: its content is (LoadedScene::env_map_hash).
    t.push_back(string_row("env_map", SC, nullptr, false,
        "environment map: an equirectangular (lat-long) image, Blender's mapping",
        [](OptionTargets& o, const OptionValue& v) {
            if (!v.s.empty() && o.scene->environment.has_color)
                throw refused("env_map and env_color exclude each other");
            o.scene->environment.map_path = v.s;
        },
        [](const OptionTargets& o) { return S(o.scene->environment.map_path); }, "--env", "FILE"));
    t.push_back(string_row("env_color", SC, nullptr, true, "a uniform environment of this linear radiance, \"R,G,B\"",
        [](OptionTargets& o, const OptionValue& v) {
            EnvironmentOptions& env = o.scene->environment;
            if (v.s.empty()) {
                env.has_color = false;
                env.color = Rgb(1.0f);
                return;
            }
            if (!env.map_path.empty()) throw refused("env_map and env_color exclude each other");
            double c[3];
            if (!parse_numbers(v.s, 3, 0, 1e30, c))
                throw refused("env_color expects R,G,B with numbers >= 0 (e.g. 0.8,0.9,1), not '" + v.s + "'");
            env.color = Rgb(static_cast<float>(c[0]), static_cast<float>(c[1]), static_cast<float>(c[2]));
            env.has_color = true;
        },
        [](const OptionTargets& o) {
            const EnvironmentOptions& env = o.scene->environment;
            return S(env.has_color ? shortest(env.color.r) + "," + shortest(env.color.g) + "," + shortest(env.color.b)
                                   : "");
        },
        nullptr, "R,G,B"));
    t.push_back(float_row("env_strength", SC, 0, 1e30, true, "multiplies the environment",
        [](OptionTargets& o, const OptionValue& v) { o.scene->environment.strength = static_cast<float>(v.f); },
        [](const OptionTargets& o) { return F(o.scene->environment.strength); }, nullptr, "S"));
    t.push_back(float_row("env_rotate", SC, -1e6, 1e6, true,
        "rotates the environment about the up axis (+Y), as a Mapping node's Z rotation",
        [](OptionTargets& o, const OptionValue& v) { o.scene->environment.rotate_degrees = static_cast<float>(v.f); },
        [](const OptionTargets& o) { return F(o.scene->environment.rotate_degrees); }, nullptr, "DEGREES"));
    t.push_back(float_row("time", SC, -1e9, 1e9, true,
        "seconds: the animations, skins and morph targets evaluated there (unset: the file's static pose)",
        [](OptionTargets& o, const OptionValue& v) {
            o.scene->import.animate = true;
            o.scene->time = v.f;
        },
        [](const OptionTargets& o) {
            return F(o.scene->import.animate ? o.scene->time : std::numeric_limits<double>::quiet_NaN());
        },
        ""));
    t.push_back(string_row("animation", SC, nullptr, true,
        "with time: the animation played, a name or an index (all: every one at once)",
        [](OptionTargets& o, const OptionValue& v) { o.scene->import.animation = v.s.empty() ? "all" : v.s; },
        [](const OptionTargets& o) { return S(o.scene->import.animation); }, "", "NAME", true));
    t.push_back(string_row("shutter", SC, nullptr, true,
        "with time: motion blur, \"OPEN,CLOSE\" in seconds relative to time (\"\": none)",
        [](OptionTargets& o, const OptionValue& v) {
            double x[2] = {0, 0};
            if (!v.s.empty() && !parse_numbers(v.s, 2, -1e9, 1e9, x))
                throw refused("shutter expects OPEN,CLOSE in seconds relative to 'time' (e.g. -0.0104,0.0104), not '" +
                              v.s + "'");
            if (x[0] > x[1]) throw refused("shutter: it opens after it closes ('" + v.s + "')");
            o.scene->shutter_open = x[0];
            o.scene->shutter_close = x[1];
        },
        [](const OptionTargets& o) {
            const SceneLoadOptions& s = *o.scene;
            return S(s.shutter_open == 0 && s.shutter_close == 0 ? ""
                                                                 : shortest(s.shutter_open) + "," +
                                                                       shortest(s.shutter_close));
        },
        "", "OPEN,CLOSE"));
    return t;
}

const char* kind_name(OptionKind k) {
    return k == OptionKind::Int ? "int" : k == OptionKind::Float ? "float" : "string";
}

std::string number_text(double v) {
    if (std::abs(v) >= 1e6 && std::floor(v) == v) {
        char buf[32];
        std::snprintf(buf, sizeof(buf), "%g", v);
        return buf;
    }
    return shortest(v);
}

}  // namespace

std::string choice_list(const std::vector<std::string>& items) {
    std::string out;
    for (size_t i = 0; i < items.size(); ++i) out += (i == 0 ? "" : i + 1 == items.size() ? " or " : ", ") + items[i];
    return out;
}

const std::vector<OptionSpec>& option_table() {
    static const std::vector<OptionSpec> table = make_table();
    return table;
}

const OptionSpec* find_option(OptionObject object, const std::string& name) {
    for (const OptionSpec& s : option_table())
        if (s.object == object && name == s.name) return &s;
    return nullptr;
}

std::vector<std::string> option_aliases(const OptionSpec& spec) {
    std::vector<std::string> out;
    std::string word;
    for (const char* c = spec.aliases; ; ++c) {
        if (*c == ' ' || *c == '\0') {
            if (!word.empty()) out.push_back(word);
            word.clear();
            if (*c == '\0') break;
        } else
            word += *c;
    }
    return out;
}

std::string option_flag(const OptionSpec& spec) {
    if (spec.flag) return spec.flag;
    std::string flag = std::string("--") + spec.name;
    std::replace(flag.begin(), flag.end(), '_', '-');
    return flag;
}

void set_option(const OptionSpec& spec, OptionTargets& targets, const OptionValue& value) {
    const std::string name = spec.name;
    switch (spec.kind) {
        case OptionKind::Int:
            if (value.i < spec.int_min || value.i > spec.int_max) {
                if (spec.int_min == 0 && spec.int_max == 1) throw refused(name + " must be 0 or 1");
                if (spec.int_max == k_int || spec.int_max == k_long)
                    throw refused(name + " must be at least " + std::to_string(spec.int_min));
                throw refused(name + " must be in [" + std::to_string(spec.int_min) + ", " +
                              std::to_string(spec.int_max) + "], not " + std::to_string(value.i));
            }
            break;
        case OptionKind::Float:
            if (!std::isfinite(value.f)) throw refused(name + " must be finite");
            if (value.f < spec.float_min || value.f > spec.float_max)
                throw refused(name + " must be in [" + number_text(spec.float_min) + ", " +
                              number_text(spec.float_max) + "], not " + number_text(value.f));
            break;
        case OptionKind::String:
            // Forms built on the names (a codec's level, a list of passes) are checked by their rows.
            if (spec.choices && !spec.choices_form) expect_choice(spec.name, value.s, spec.choices());
            break;
    }
    spec.set(targets, value);
}

OptionValue get_option(const OptionSpec& spec, const OptionTargets& targets) { return spec.get(targets); }

OptionValue default_option(const OptionSpec& spec) {
    SceneLoadOptions scene;
    RenderJobOptions job;
    OutputSettings output;
    OptionTargets targets{&scene, &job, &output, nullptr};
    return spec.get(targets);
}

void hash_identity_options(HashKey& key, OptionObject object, const OptionTargets& targets) {
    for (const OptionSpec& s : option_table()) {
        if (s.object != object || !s.identity) continue;
        const OptionValue v = s.get(targets);
        switch (s.kind) {
            case OptionKind::Int: key.field(s.name, static_cast<int64_t>(v.i)); break;
            case OptionKind::Float: key.field(s.name, v.f); break;
            case OptionKind::String: key.field(s.name, v.s); break;
        }
    }
}

std::string option_table_json() {
    nlohmann::ordered_json rows = nlohmann::ordered_json::array();
    for (const OptionSpec& s : option_table()) {
        nlohmann::ordered_json row;
        row["name"] = s.name;
        row["object"] = s.object == OptionObject::Scene ? "scene" : "render";
        row["type"] = kind_name(s.kind);
        const OptionValue d = default_option(s);
        if (s.kind == OptionKind::Int) {
            row["default"] = d.i;
            row["min"] = s.int_min;
            row["max"] = s.int_max;
        } else if (s.kind == OptionKind::Float) {
            row["default"] = std::isfinite(d.f) ? nlohmann::ordered_json(d.f) : nlohmann::ordered_json(nullptr);
            row["min"] = s.float_min;
            row["max"] = s.float_max;
        } else {
            row["default"] = d.s;
        }
        if (s.choices) {
            row["choices"] = s.choices();
            row["choices_form"] = s.choices_form;
        }
        row["help"] = s.help;
        row["identity"] = s.identity;
        row["flag"] = option_flag(s);
        row["metavar"] = s.metavar;
        row["aliases"] = option_aliases(s);
        row["switch"] = s.is_switch;
        row["checked_by_scene"] = s.checked_by_scene;
        rows.push_back(std::move(row));
    }
    return rows.dump(1);
}

}  // namespace veach
