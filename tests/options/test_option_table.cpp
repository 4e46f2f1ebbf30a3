// The options table's identity column is what the render's identity hashes: changing any option
// marked as shaping the image gives another render (checkpoints and part files refuse each
// other), changing any other option (spp, threads, time limit, outputs, the part of the render)
// leaves the identity alone, so a checkpoint resumes under it and parts of one render merge.
#include <gtest/gtest.h>

#include "options/option_table.h"

namespace veach {
namespace {

// A valid value of `spec` other than its default, or false when there is none to try.
bool other_value(const OptionSpec& spec, OptionValue* out) {
    const OptionValue d = default_option(spec);
    switch (spec.kind) {
        case OptionKind::Int:
            *out = OptionValue::of_int(d.i != spec.int_min ? spec.int_min : spec.int_max);
            if (std::string(spec.name) == "bits") out->i = 16;
            return true;
        case OptionKind::Float: *out = OptionValue::of_float(d.f != spec.float_min ? spec.float_min : spec.float_max);
            return true;
        case OptionKind::String:
            if (!spec.choices) return false;
            for (const std::string& c : spec.choices())
                if (c != d.s) {
                    *out = OptionValue::of_string(c);
                    return true;
                }
            return false;
    }
    return false;
}

TEST(OptionTableIdentity, TheRenderIdentityHashesExactlyTheIdentityRows) {
    const RenderJobOptions base;
    const uint64_t identity = render_settings_hash(base, "camera", 64, 48);
    int identity_rows = 0, other_rows = 0;
    for (const OptionSpec& spec : option_table()) {
        if (spec.object != OptionObject::Render) continue;
        // The render hashes the size and camera it resolved, passed beside the options.
        const std::string name = spec.name;
        if (name == "width" || name == "height" || name == "camera") continue;
        OptionValue v;
        if (name == "passes")
            v = OptionValue::of_string("combined");  // no pass that turns aovs on
        else if (!other_value(spec, &v))
            continue;
        RenderJobOptions job;
        OutputSettings output;
        OptionTargets targets{nullptr, &job, &output, nullptr};
        set_option(spec, targets, v);
        const bool changed = render_settings_hash(job, "camera", 64, 48) != identity;
        EXPECT_EQ(changed, spec.identity) << name;
        (spec.identity ? identity_rows : other_rows)++;
    }
    EXPECT_GE(identity_rows, 10);
    EXPECT_GE(other_rows, 10);
    // And what is passed beside: the resolved size and camera.
    EXPECT_NE(render_settings_hash(base, "camera", 65, 48), identity);
    EXPECT_NE(render_settings_hash(base, "other", 64, 48), identity);
}

TEST(OptionTableIdentity, RefusalsNameTheOptionAndValuesStayUnchanged) {
    RenderJobOptions job;
    OutputSettings output;
    OptionTargets targets{nullptr, &job, &output, nullptr};
    const OptionSpec* spp = find_option(OptionObject::Render, "spp");
    ASSERT_NE(spp, nullptr);
    try {
        set_option(*spp, targets, OptionValue::of_int(0));
        FAIL() << "spp 0 accepted";
    } catch (const std::invalid_argument& e) {
        EXPECT_STREQ(e.what(), "spp must be at least 1");
    }
    EXPECT_EQ(job.render.spp, 64);
    EXPECT_EQ(find_option(OptionObject::Scene, "spp"), nullptr);  // a render option only
    EXPECT_EQ(option_flag(*find_option(OptionObject::Render, "time_limit")), "--time");
    EXPECT_EQ(option_flag(*find_option(OptionObject::Render, "max_depth")), "--max-depth");
}

}  // namespace
}  // namespace veach
