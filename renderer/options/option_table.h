// The one table of options a host sets on a scene or a render: each row is an option's name,
// type, range (or accepted names), help line, whether it is part of the render's identity (it
// shapes the image, so a checkpoint or part file of another value is another render's), the
// `veach` command's flag, and how the value is stored in and read from the load and job
// settings. The C API validates and stores options through it, the render and scene identities
// hash its identity rows, the command builds its flags and help from it (through the device
// query "options"), and README's option reference is checked against it. Adding an option is
// one row here plus its use where the setting is read.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/content_hash.h"
#include "job/render_job.h"
#include "load/scene_load.h"
#include "output/image_output.h"

namespace veach {

enum class OptionKind { Int, Float, String };
enum class OptionObject { Scene, Render };

struct OptionValue {
    OptionKind kind = OptionKind::Int;
    long long i = 0;
    double f = 0;
    std::string s;
    static OptionValue of_int(long long v) { return {OptionKind::Int, v, 0, {}}; }
    static OptionValue of_float(double v) { return {OptionKind::Float, 0, v, {}}; }
    static OptionValue of_string(std::string v) { return {OptionKind::String, 0, 0, std::move(v)}; }
};

// What options are stored in: a scene's load options, or a render's job and output settings (and
// its loaded scene, against which a camera name is checked). Rows touch only their own object's.
struct OptionTargets {
    SceneLoadOptions* scene = nullptr;
    RenderJobOptions* job = nullptr;
    OutputSettings* output = nullptr;
    const Scene* loaded = nullptr;
};

struct OptionSpec {
    const char* name;
    OptionObject object;
    OptionKind kind;
    // Ints and floats: the accepted values, inclusive (a float must also be finite).
    long long int_min, int_max;
    double float_min, float_max;
    // Strings: the accepted names when they are a fixed list (nullptr: free text, or a form
    // checked by `set`, such as "R,G,B"). Named in help and refusals.
    std::vector<std::string> (*choices)();
    bool choices_form;  // the value is a form built on the names (a codec's level, a list), checked by `set`
    bool identity;  // shapes the image: hashed into the render's identity
    const char* help;
    // The command's flag: nullptr is "--" + the name with '-' for '_'; "" none (the command
    // sets the option itself from a flag of its own, e.g. --samples). `aliases` are other names
    // for it (pbrt-v4's), space-separated; a switch takes no value and sets 1.
    const char* flag;
    const char* metavar;
    const char* aliases;
    bool is_switch;
    // Checked against the loaded scene or the file (a camera name, a variant): a front end
    // cannot check it before the load.
    bool checked_by_scene;
    // Stores a value already within range; may throw std::invalid_argument for a value of the
    // right type and range but the wrong form (a pass list, "R,G,B").
    void (*set)(OptionTargets&, const OptionValue&);
    OptionValue (*get)(const OptionTargets&);
};

const std::vector<OptionSpec>& option_table();
// nullptr when `object` has no option of that name.
const OptionSpec* find_option(OptionObject object, const std::string& name);

// The row's other flags (pbrt-v4's names), e.g. "--nthreads".
std::vector<std::string> option_aliases(const OptionSpec& spec);
// The command's flag for a row ("--max-depth"), "" when it has none.
std::string option_flag(const OptionSpec& spec);

// Checks `value` against the row (type, range, names) and stores it. Throws std::invalid_argument
// with a one-line message that names the option ("spp must be at least 1").
void set_option(const OptionSpec& spec, OptionTargets& targets, const OptionValue& value);
OptionValue get_option(const OptionSpec& spec, const OptionTargets& targets);
// The value a fresh scene or render has.
OptionValue default_option(const OptionSpec& spec);

// Adds every identity row of `object` to `key`, by name and exact value.
void hash_identity_options(HashKey& key, OptionObject object, const OptionTargets& targets);

// The table as JSON (an array of rows: name, object, type, default, min, max, choices, help,
// identity, flag, metavar, aliases, switch, checked_by_scene): the device query "options".
std::string option_table_json();

// "a, b or c".
std::string choice_list(const std::vector<std::string>& items);

}  // namespace veach
