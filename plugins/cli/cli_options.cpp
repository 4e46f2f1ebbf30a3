#include "cli_options.h"

#include "animation_options.h"
#include "farm_options.h"

#include <glob.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <map>
#include <memory>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

namespace veach::cli {

namespace {

const char* k_footer = R"(
SIGINT, SIGTERM and SIGHUP stop sampling and write the image as it stands, with the samples
per pixel reached in its metadata (exit 130); a second signal ends the process at once.
Exit codes: 0 done, 1 usage, 2 bad input, 3 render or write failure, 130 interrupted.)";

std::string number_text(double v) {
    char buf[32];
    std::snprintf(buf, sizeof(buf), "%.10g", v);
    return buf;
}

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
        throw UsageError(option + " expects a number from " + number_text(lo) + " to " + number_text(hi) + ", not '" +
                         value + "'");
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

std::string choice_list(const std::vector<std::string>& items) {
    std::string out;
    for (size_t i = 0; i < items.size(); ++i) out += (i == 0 ? "" : i + 1 == items.size() ? " or " : ", ") + items[i];
    return out;
}

// A scene (never loaded) and a render of an empty scene on which values are tried: the
// library's own checks decide what is valid, the command only words the usage message. Each
// scene option is tried on a scene of its own (env_map and env_color exclude each other).
class Probe {
public:
    explicit Probe(VeachDevice device) : m_device(device) {
        static const char k_empty_gltf[] = R"({"asset": {"version": "2.0"}, "scenes": [{"nodes": []}], "scene": 0})";
        VeachScene empty = veachNewSceneFromMemory(device, k_empty_gltf, sizeof(k_empty_gltf) - 1, "gltf", nullptr);
        if (empty) m_render = veachNewRender(empty);
        veachReleaseScene(empty);  // the render holds it
        if (!m_render) throw std::runtime_error(std::string("cannot start libveach: ") + veachGetLastError());
    }
    ~Probe() { veachReleaseRender(m_render); }
    Probe(const Probe&) = delete;
    Probe& operator=(const Probe&) = delete;
    // "" when the library takes the value, else its message.
    std::string scene_refusal(const ApiOption& o) const {
        VeachScene scene = veachNewScene(m_device);
        const bool ok = apply_scene_option(scene, o) == VEACH_ERROR_NONE;
        std::string message = ok ? "" : veachGetLastError();
        veachReleaseScene(scene);
        return message;
    }
    std::string render_refusal(const ApiOption& o) const {
        return apply_render_option(m_render, o) == VEACH_ERROR_NONE ? "" : veachGetLastError();
    }

private:
    VeachDevice m_device;
    VeachRender m_render = nullptr;
};

// The typed option a flag's text makes, within the row's range (a usage error otherwise).
ApiOption typed_option(const TableOption& row, const std::string& flag, const std::string& text) {
    if (row.type == "int") return int_option(row.name, parse_integer(flag, text, row.int_min, row.int_max));
    if (row.type == "float") return float_option(row.name, parse_number(flag, text, row.float_min, row.float_max));
    return string_option(row.name, text);
}

// The refusal a row's value gets from the command: a fixed list of names is quoted, anything
// else is the library's own message with flags for option names.
std::string refusal_message(const TableOption& row, const std::string& text, const std::string& library,
                            const std::vector<TableOption>& table) {
    if (!row.choices.empty() && !row.choices_form) {
        std::string what = row.name;
        std::replace(what.begin(), what.end(), '_', ' ');
        return "unknown " + what + " '" + text + "' (" + row.flag + " expects " + choice_list(row.choices) + ")";
    }
    return with_flags(library, table);
}

// --config FILE (TOML or INI): its keys become flags placed before the command line's own, which
// therefore win; `input` keys are scenes. A [render] section is the render command's.
std::vector<std::string> config_arguments(const std::string& path) {
    std::vector<CLI::ConfigItem> items;
    try {
        items = CLI::ConfigTOML().from_file(path);
    } catch (const CLI::ParseError& e) {
        throw std::invalid_argument(path + ": " + e.what());
    }
    std::vector<std::string> args;
    for (const CLI::ConfigItem& item : items) {
        if (item.name == "++" || item.name == "--") continue;  // section markers
        if (!item.parents.empty() && !(item.parents.size() == 1 && item.parents[0] == "render"))
            throw UsageError(path + ": unknown section '" + item.parents[0] + "' (only [render])");
        std::string name = item.name;
        std::replace(name.begin(), name.end(), '_', '-');
        if (name == "input" || name == "inputs") {
            args.insert(args.end(), item.inputs.begin(), item.inputs.end());
            continue;
        }
        const std::string flag = (name.size() == 1 ? "-" : "--") + name;
        if (item.inputs.size() == 1 && (item.inputs[0] == "true" || item.inputs[0] == "false")) {
            if (item.inputs[0] == "true") args.push_back(flag);
            continue;
        }
        for (const std::string& v : item.inputs) args.push_back(flag + "=" + v);
    }
    return args;
}

// The flag in `flags` nearest to `typo` (edit distance at most a third of its length), "" for none.
std::string suggestion(const std::string& typo, const std::vector<std::string>& flags) {
    std::string word = typo.substr(0, typo.find('='));
    std::string best;
    size_t best_distance = std::max<size_t>(2, word.size() / 3) + 1;
    for (const std::string& f : flags) {
        std::vector<size_t> prev(f.size() + 1), cur(f.size() + 1);
        for (size_t j = 0; j <= f.size(); ++j) prev[j] = j;
        for (size_t i = 1; i <= word.size(); ++i) {
            cur[0] = i;
            for (size_t j = 1; j <= f.size(); ++j)
                cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + (word[i - 1] == f[j - 1] ? 0 : 1)});
            std::swap(prev, cur);
        }
        if (prev[f.size()] < best_distance) best_distance = prev[f.size()], best = f;
    }
    return best;
}

std::vector<std::string> long_names(const CLI::App& app) {
    std::vector<std::string> names;
    for (const CLI::Option* o : app.get_options()) {
        for (const std::string& n : o->get_lnames()) names.push_back("--" + n);
        for (const std::string& n : o->get_snames()) names.push_back("-" + n);
    }
    return names;
}

void refuse_extras(const CLI::App& app, const char* what) {
    for (const std::string& extra : app.remaining()) {
        if (extra.empty() || extra[0] != '-') continue;
        std::string near = suggestion(extra, long_names(app));
        throw UsageError(std::string("unknown ") + what + " '" + extra + "'" +
                         (near.empty() ? "" : "; did you mean '" + near + "'?"));
    }
}

// The render command's flags: the table's rows with a flag, then the command's own.
class RenderFlags {
public:
    RenderFlags(CLI::App& app, std::vector<TableOption> table) : m_app(app), m_table(std::move(table)) {
        app.add_option("inputs", m_inputs, "scenes: .gltf or .glb, globs too")->type_name("INPUT...");
        app.add_option("-o,--output,--outfile", m_cmd.outputs,
                       "output image, the format from the extension (.exr .hdr .png .jpg .tif .vpart); with several "
                       "inputs a pattern with {stem}; repeat to write one render to several files")
            ->type_name("FILE")
            ->expected(1)
            ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll)
            ->group("Output");
        m_values.resize(m_table.size());
        for (size_t k = 0; k < m_table.size(); ++k) {
            const TableOption& row = m_table[k];
            if (row.flag.empty()) continue;
            std::string names = row.flag;
            for (const std::string& a : row.aliases) names += "," + a;
            const std::string help =
                row.help + (!row.is_switch && !row.default_text.empty() ? " (default " + row.default_text + ")" : "");
            const char* group = row.object == "scene" ? "Scene" : "Render";
            CLI::Option* o = row.is_switch ? app.add_flag(names, help)
                                           : app.add_option(names, m_values[k], help)
                                                 ->type_name(row.metavar)
                                                 ->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
            o->group(group);
            m_options.emplace_back(k, o);
        }
        own_flags();
    }

    RenderCommand finish(VeachDevice device) {
        refuse_extras(m_app, "option");
        Probe probe(device);
        RenderCommand& cmd = m_cmd;
        for (const std::string& in : m_inputs) expand_input(in, cmd.inputs);
        for (auto [k, o] : m_options) {
            if (o->count() == 0) continue;
            const TableOption& row = m_table[k];
            const std::string text = row.is_switch ? "1" : m_values[k];
            ApiOption option = typed_option(row, row.flag, text);
            if (!row.checked_by_scene) {
                const std::string refused =
                    row.object == "scene" ? probe.scene_refusal(option) : probe.render_refusal(option);
                if (!refused.empty()) throw UsageError(refusal_message(row, text, refused, m_table));
            }
            (row.object == "scene" ? cmd.scene_options : cmd.render_options).push_back(std::move(option));
        }
        if (given("--env") && given("--env-color")) throw UsageError("--env and --env-color exclude each other");
        // Blender's width default for its smooth filters; the box stays one pixel.
        if (given("--filter") && value_of("--filter") != "box" && !given("--filter-width"))
            cmd.render_options.push_back(float_option("filter_width", 1.5));
        if (!m_bdpt_strategy.empty()) {
            const std::string& v = m_bdpt_strategy;
            size_t comma = v.find(',');
            if (comma == std::string::npos) throw UsageError("--bdpt-strategy expects s,t (e.g. 2,2)");
            cmd.render_options.push_back(int_option("bdpt_s", parse_integer("--bdpt-strategy", v.substr(0, comma), 0, 1000)));
            cmd.render_options.push_back(
                int_option("bdpt_t", parse_integer("--bdpt-strategy", v.substr(comma + 1), 1, 1000)));
        }
        if (!m_checkpoint.empty()) cmd.checkpoint_seconds = parse_number("--checkpoint", m_checkpoint, 0.0, 1e9);
        if (!m_attrib.empty()) {
            std::string lines;
            for (size_t i = 0; i + 1 < m_attrib.size(); i += 2) {
                if (m_attrib[i].find('=') != std::string::npos || m_attrib[i + 1].find('\n') != std::string::npos)
                    throw UsageError("--attrib expects NAME VALUE (a name without '='), not '" + m_attrib[i] + "'");
                lines += m_attrib[i] + "=" + m_attrib[i + 1] + "\n";
            }
            ApiOption option = string_option("attributes", lines);
            if (const std::string refused = probe.render_refusal(option); !refused.empty())
                throw UsageError(with_flags(refused, m_table));
            cmd.render_options.push_back(std::move(option));
        }
        if (!m_preview.empty()) {
            cmd.preview_seconds = parse_number("--preview-every", m_preview[0], 0.0, 1e9);
            cmd.preview_path = m_preview[1];
            if (cmd.preview_path.size() >= 6 && cmd.preview_path.compare(cmd.preview_path.size() - 6, 6, ".vpart") == 0)
                throw UsageError("--preview-every writes an image, not a part file (.vpart)");
        }
        // The animation and farm flags keep their own parsers (animation_options, farm_options).
        std::vector<std::string> own;
        for (const auto& [flag, value] : m_own)
            if (m_app.get_option(flag)->count() > 0) own.insert(own.end(), {flag, *value});
        if (m_animated_seed) own.push_back("--animated-seed");
        for (size_t i = 0; i < own.size(); ++i)
            if (!parse_animation_option(own, i, cmd) && !parse_farm_render_option(own, i, cmd))
                throw UsageError("unknown option '" + own[i] + "'");
        if (cmd.inputs.empty()) throw UsageError("no input scene given");
        if (cmd.outputs.empty()) throw UsageError("no output given (-o FILE)");
        check_animation_options(cmd);  // several frames need {frame} patterns: before {stem}'s check
        for (const std::string& o : cmd.outputs)
            if (cmd.inputs.size() > 1 && o.find("{stem}") == std::string::npos)
                throw UsageError("several inputs need an output pattern with {stem}, e.g. -o out/{stem}.exr");
        check_farm_render_options(cmd);
        return cmd;
    }

private:
    void own_flags() {
        CLI::App& a = m_app;
        a.add_option("--bdpt-strategy", m_bdpt_strategy,
                     "bdpt: render only the strategy with S light and T camera vertices, unweighted (for "
                     "verification)")
            ->type_name("S,T")
            ->group("Render");
        a.add_option("--stats-json", m_cmd.stats_json, "write render statistics as JSON")->type_name("FILE")->group("Output");
        a.add_flag("-q,--quiet", m_cmd.quiet, "no progress output")->group("Output");
        a.add_option("--attrib", m_attrib,
                     "add NAME with VALUE to every image's metadata (numbers are written as numbers); repeat for "
                     "several")
            ->type_name("NAME VALUE")
            ->expected(2)
            ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll)
            ->group("Output");
        a.add_option("--preview-every", m_preview,
                     "while rendering, write the image so far to FILE (atomically, any format -o takes) at most "
                     "every SECONDS")
            ->type_name("SECONDS FILE")
            ->expected(2)
            ->group("Output");
        a.add_flag("--dry-run", m_cmd.dry_run,
                   "check the command line and print the options as the library took them (JSON); render nothing")
            ->group("Output");
        a.add_option("--config", m_config,
                     "read flags from a TOML or INI file (key = value, the flags' names; the command line's own win)")
            ->type_name("FILE")
            ->group("Output");
        a.add_flag("--skip-existing", m_cmd.skip_existing,
                   "skip inputs whose outputs are complete (veach:complete yes, the same spp, sample range and tile)")
            ->group("Farm");
        a.add_option("--checkpoint", m_checkpoint,
                     "keep OUTPUT.checkpoint up to date (at the first pass boundary after SECONDS; 0 every pass)")
            ->type_name("SECONDS")
            ->group("Farm");
        a.add_flag("--resume", m_cmd.resume, "continue from OUTPUT.checkpoint when it exists")->group("Farm");
        own_value("--samples", "A:B", "render only sample indices [A, B) of the --spp N render (a part for a farm)",
                  "Farm");
        own_value("--pixelbounds", "X0,X1,Y0,Y1",
                  "render only pixels [X0,X1) x [Y0,Y1) (pbrt-v4's order); .vpart outputs are part files for "
                  "`veach merge`",
                  "Farm");
        own_value("--frame", "N", "render the scene at frame N: glTF time N / fps", "Animation");
        own_value("--frames", "A-B[:STEP]", "render frames A to B from one load; outputs need {frame} or ####",
                  "Animation");
        own_value("--fps", "F", "frames per second for --frame and --frames (default 24)", "Animation");
        own_value("--animation", "NAME|INDEX|all", "the animation played (default all)", "Animation");
        own_value("--shutter", "OPEN,CLOSE", "motion blur between frame + OPEN and frame + CLOSE, in frames",
                  "Animation");
        a.add_flag("--animated-seed", m_animated_seed, "mix the frame into --seed")->group("Animation");
    }
    void own_value(const char* flag, const char* metavar, const char* help, const char* group) {
        auto value = std::make_unique<std::string>();
        m_app.add_option(flag, *value, help)
            ->type_name(metavar)
            ->multi_option_policy(CLI::MultiOptionPolicy::TakeLast)
            ->group(group);
        m_own.emplace_back(flag, value.get());
        m_own_storage.push_back(std::move(value));
    }
    bool given(const std::string& flag) const {
        for (auto [k, o] : m_options)
            if (m_table[k].flag == flag) return o->count() > 0;
        return false;
    }
    std::string value_of(const std::string& flag) const {
        for (auto [k, o] : m_options)
            if (m_table[k].flag == flag) return m_values[k];
        return {};
    }

    CLI::App& m_app;
    std::vector<TableOption> m_table;
    std::vector<std::string> m_values, m_inputs;
    std::vector<std::pair<size_t, CLI::Option*>> m_options;
    std::vector<std::pair<std::string, std::string*>> m_own;
    std::vector<std::unique_ptr<std::string>> m_own_storage;
    std::string m_bdpt_strategy, m_checkpoint, m_config;
    std::vector<std::string> m_preview, m_attrib;
    bool m_animated_seed = false;
    RenderCommand m_cmd;
};

// `veach merge`'s output flags: the table's rows of these names.
class MergeFlags {
public:
    MergeFlags(CLI::App& app, const std::vector<TableOption>& table) : m_app(app) {
        app.add_option("parts", m_cmd.parts, "part files (.vpart)")->type_name("PART...");
        app.add_option("-o,--output,--outfile", m_cmd.outputs, "the merged image (repeat for several files)")
            ->type_name("FILE")
            ->expected(1)
            ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
        app.add_option("--expect-spp", m_expect,
                       "refuse unless the parts cover samples 0..N-1 of every pixel exactly")
            ->type_name("N");
        app.add_flag("-q,--quiet", m_cmd.quiet, "no summary line");
        for (const char* name : {"display", "view", "look", "exposure", "gamma", "half", "exr_codec", "passes",
                                 "quality", "bits"}) {
            for (const TableOption& row : table) {
                if (row.name != name || row.object != "render") continue;
                m_rows.push_back(row);
            }
        }
        m_values.resize(m_rows.size());
        for (size_t k = 0; k < m_rows.size(); ++k) {
            const TableOption& row = m_rows[k];
            m_opts.push_back(row.is_switch ? app.add_flag(row.flag, row.help)
                                           : app.add_option(row.flag, m_values[k], row.help)
                                                 ->type_name(row.metavar)
                                                 ->multi_option_policy(CLI::MultiOptionPolicy::TakeLast));
        }
    }
    MergeCommand finish() {
        refuse_extras(m_app, "option");
        if (!m_expect.empty())
            m_cmd.expect_spp = parse_integer("--expect-spp", m_expect, 1, std::numeric_limits<int>::max());
        for (size_t k = 0; k < m_rows.size(); ++k)
            if (m_opts[k]->count() > 0)
                m_cmd.options.push_back(
                    typed_option(m_rows[k], m_rows[k].flag, m_rows[k].is_switch ? "1" : m_values[k]));
        if (m_cmd.parts.empty()) throw UsageError("no part files given");
        if (m_cmd.outputs.empty()) throw UsageError("no output given (-o FILE)");
        return m_cmd;
    }

private:
    CLI::App& m_app;
    std::vector<TableOption> m_rows;
    std::vector<std::string> m_values;
    std::vector<CLI::Option*> m_opts;
    std::string m_expect;
    MergeCommand m_cmd;
};

}  // namespace

std::vector<TableOption> read_option_table(VeachDevice device) {
    const std::string text = device_string(device, "options");
    std::vector<TableOption> table;
    const nlohmann::json rows = nlohmann::json::parse(text);
    for (const nlohmann::json& r : rows) {
        TableOption o;
        o.name = r.at("name");
        o.object = r.at("object");
        o.type = r.at("type");
        o.help = r.at("help");
        o.flag = r.at("flag");
        o.metavar = r.at("metavar");
        o.identity = r.at("identity");
        o.is_switch = r.at("switch");
        o.checked_by_scene = r.at("checked_by_scene");
        o.aliases = r.at("aliases").get<std::vector<std::string>>();
        if (r.contains("choices")) {
            o.choices = r.at("choices").get<std::vector<std::string>>();
            o.choices_form = r.at("choices_form");
        }
        const nlohmann::json& d = r.at("default");
        if (o.type == "int") {
            o.int_min = r.at("min");
            o.int_max = r.at("max");
            o.default_text = std::to_string(d.get<long long>());
        } else if (o.type == "float") {
            o.float_min = r.at("min");
            o.float_max = r.at("max");
            o.default_text = d.is_null() ? "" : number_text(d.get<double>());
        } else {
            o.default_text = d.get<std::string>();
        }
        table.push_back(std::move(o));
    }
    return table;
}

std::string with_flags(const std::string& message, const std::vector<TableOption>& table) {
    for (const TableOption& row : table) {
        std::string flag = row.flag;
        if (flag.empty()) {
            if (row.name == "sample_begin" || row.name == "sample_end") flag = "--samples";
            else if (row.name == "pixelbounds") flag = "--pixelbounds";
            else if (row.name == "attributes") flag = "--attrib";
            else continue;
        }
        // The forms the library's messages use: a leading name, "option 'NAME'", "scene option 'NAME'".
        std::string out = message;
        for (const std::string& quoted : {"scene option '" + row.name + "'", "option '" + row.name + "'"})
            for (size_t pos; (pos = out.find(quoted)) != std::string::npos;) out.replace(pos, quoted.size(), flag);
        if (out.rfind(row.name, 0) == 0 && out.size() > row.name.size() &&
            (out[row.name.size()] == ' ' || out[row.name.size()] == ':'))
            out.replace(0, row.name.size(), flag);
        if (out != message) return out;
    }
    return message;
}

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

CommandLine parse_command_line(int argc, char** argv, VeachDevice device) {
    CommandLine line;
    std::vector<std::string> args(argv + 1, argv + argc);
    const std::string version = std::string("veach ") + veachGetVersionString();
    CLI::App app{"Renders glTF 2.0 scenes (.gltf, .glb) with a physically based path tracer.", "veach"};
    app.set_version_flag("--version", version);
    app.allow_extras();
    // A flag given twice takes its last value, as the hand-written parser did: farm templates
    // append the user's flags after their own (veach-part.sbatch's --checkpoint 60 ... --checkpoint 0).
    // The subcommands copy these defaults when they are added; -o and --attrib keep every value.
    app.option_defaults()->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
    app.footer(k_footer);
    const std::vector<TableOption> table = read_option_table(device);

    CLI::App* render = app.add_subcommand("render", "render scenes to images (veach render INPUT... -o OUTPUT)");
    CLI::App* merge = app.add_subcommand("merge", "sum part files (.vpart) into the image one machine would make");
    CLI::App* info = app.add_subcommand("info", "what a scene holds, and the memory a render of it needs");
    CLI::App* color = app.add_subcommand("color", "the colour config's displays, views and looks");
    color->alias("colour");
    CLI::App* options = app.add_subcommand("options", "the render and scene options: names, types, ranges, flags");
    for (CLI::App* sub : {render, merge, info, color, options}) {
        sub->set_version_flag("--version", version);
        sub->allow_extras();
        sub->footer(k_footer);
    }
    RenderFlags render_flags(*render, table);
    MergeFlags merge_flags(*merge, table);
    std::vector<std::string> info_values(table.size());
    info->add_option("input", line.info.input, "the scene (.gltf, .glb)")->type_name("INPUT")->required();
    info->add_flag("--json", line.info.json, "as JSON");
    std::string info_width, info_height;
    info->add_option("--width", info_width, "the width the memory estimate is for (default 1920)")->type_name("N");
    info->add_option("--height", info_height, "the height (default: from the camera's aspect ratio)")->type_name("N");
    std::vector<std::pair<size_t, CLI::Option*>> info_options;
    for (size_t k = 0; k < table.size(); ++k) {
        const TableOption& row = table[k];
        if (row.object != "scene" || row.flag.empty()) continue;
        info_options.emplace_back(k, row.is_switch ? info->add_flag(row.flag, row.help)
                                                   : info->add_option(row.flag, info_values[k], row.help)
                                                         ->type_name(row.metavar));
    }
    options->add_flag("--json", line.options_json, "the table as JSON");
    options->add_flag("--markdown", line.options_markdown, "the table as README's option reference");

    try {
        // --config FILE: its flags go first, so that the command line's own win.
        if (!args.empty() && args[0] == "render") {
            for (size_t i = 1; i < args.size(); ++i) {
                std::string path;
                if (args[i] == "--config" && i + 1 < args.size())
                    path = args[i + 1];
                else if (args[i].rfind("--config=", 0) == 0)
                    path = args[i].substr(9);
                if (path.empty()) continue;
                std::vector<std::string> from_file;
                try {
                    from_file = config_arguments(path);
                } catch (const std::invalid_argument& e) {
                    std::fprintf(stderr, "veach: %s\n", e.what());
                    line.exit_code = 2;
                    return line;
                }
                args.insert(args.begin() + 1, from_file.begin(), from_file.end());
                break;
            }
        }
        std::vector<std::string> reversed(args.rbegin(), args.rend());  // CLI11 takes them last first
        app.parse(reversed);
        if (*render) {
            line.which = Subcommand::Render;
            line.render = render_flags.finish(device);
        } else if (*merge) {
            line.which = Subcommand::Merge;
            line.merge = merge_flags.finish();
        } else if (*info) {
            refuse_extras(*info, "option");
            line.which = Subcommand::Info;
            if (!info_width.empty()) line.info.width = parse_integer("--width", info_width, 1, 65536);
            if (!info_height.empty()) line.info.height = parse_integer("--height", info_height, 0, 65536);
            for (auto [k, o] : info_options)
                if (o->count() > 0)
                    line.info.scene_options.push_back(
                        typed_option(table[k], table[k].flag, table[k].is_switch ? "1" : info_values[k]));
        } else if (*color) {
            line.which = Subcommand::Color;
        } else if (*options) {
            line.which = Subcommand::Options;
        } else {
            for (const std::string& extra : app.remaining()) {
                std::vector<std::string> names = {"render", "merge", "info", "color", "options"};
                std::string near = suggestion(extra, names);
                throw UsageError("unknown command '" + extra + "'" +
                                 (near.empty() ? "" : "; did you mean '" + near + "'?"));
            }
            throw UsageError("no command given");
        }
    } catch (const CLI::CallForHelp&) {
        std::fputs(app.help().c_str(), stdout);
        line.exit_code = 0;
    } catch (const CLI::CallForAllHelp&) {
        std::fputs(app.help("", CLI::AppFormatMode::All).c_str(), stdout);
        line.exit_code = 0;
    } catch (const CLI::CallForVersion&) {
        std::printf("%s\n", version.c_str());
        line.exit_code = 0;
    } catch (const CLI::ParseError& e) {
        std::fprintf(stderr, "veach: %s (try 'veach %s--help')\n", e.what(),
                     *render ? "render " : *merge ? "merge " : *info ? "info " : "");
        line.exit_code = 1;
    } catch (const UsageError& e) {
        std::fprintf(stderr, "veach: %s (try 'veach %s--help')\n", e.what(),
                     *render ? "render " : *merge ? "merge " : *info ? "info " : "");
        line.exit_code = 1;
    }
    return line;
}

std::string option_reference_markdown(const std::vector<TableOption>& table) {
    std::string out = "| option | object | type | default | range | flag | identity | what |\n"
                      "|---|---|---|---|---|---|---|---|\n";
    for (const TableOption& row : table) {
        std::string range;
        if (row.type == "int")
            range = std::to_string(row.int_min) + " to " + std::to_string(row.int_max);
        else if (row.type == "float")
            range = number_text(row.float_min) + " to " + number_text(row.float_max);
        else if (!row.choices.empty())
            range = (row.choices_form ? "from " : "") + choice_list(row.choices);
        std::string flag = row.flag.empty() ? "" : "`" + row.flag + (row.is_switch ? "" : " " + row.metavar) + "`";
        for (const std::string& a : row.aliases) flag += ", `" + a + "`";
        std::string def = row.default_text.empty() ? (row.type == "string" ? "\"\"" : "unset") : row.default_text;
        out += "| `" + row.name + "` | " + row.object + " | " + row.type + " | " + def + " | " + range + " | " + flag +
               " | " + (row.identity ? "yes" : "") + " | " + row.help + " |\n";
    }
    return out;
}

}  // namespace veach::cli
