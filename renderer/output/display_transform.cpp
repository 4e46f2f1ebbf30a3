#include "output/display_transform.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <sstream>

#include <OpenColorIO/OpenColorIO.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "core/one_line.h"

namespace OCIO = OCIO_NAMESPACE;

namespace veach {

namespace {

constexpr const char* k_linear_space = "Linear Rec.709";
constexpr const char* k_srgb_space = "sRGB";
constexpr const char* k_raw_space = "Raw";

std::string join(const std::vector<std::string>& items) {
    if (items.empty()) return "(none)";
    std::string out;
    for (const std::string& item : items) {
        if (!out.empty()) out += ", ";
        out += "'" + item + "'";
    }
    return out;
}

// OCIO 2.1 ships no built-in configs, so the default one is assembled here. The sRGB view is
// a plain colour space (not a view transform) so that OCIO v1-era tools read it the same way.
OCIO::ConstConfigRcPtr make_builtin_config() {
    OCIO::ConfigRcPtr config = OCIO::Config::Create();
    config->setMajorVersion(2);
    config->setMinorVersion(0);
    config->setName("veach-builtin");
    config->setDescription("Veach built-in config: scene-linear Rec.709, sRGB display");

    OCIO::ColorSpaceRcPtr linear = OCIO::ColorSpace::Create(OCIO::REFERENCE_SPACE_SCENE);
    linear->setName(k_linear_space);
    linear->setFamily("Linear");
    linear->setDescription("Scene-linear, Rec.709 primaries, D65 white");
    linear->setBitDepth(OCIO::BIT_DEPTH_F32);
    config->addColorSpace(linear);

    // The exact piecewise sRGB curve: the forward ExponentWithLinearTransform decodes, so the
    // encoding direction (linear -> sRGB) is its inverse.
    OCIO::ExponentWithLinearTransformRcPtr curve = OCIO::ExponentWithLinearTransform::Create();
    const double gamma[4] = {2.4, 2.4, 2.4, 1.0};
    const double offset[4] = {0.055, 0.055, 0.055, 0.0};
    curve->setGamma(gamma);
    curve->setOffset(offset);
    curve->setDirection(OCIO::TRANSFORM_DIR_INVERSE);
    OCIO::ColorSpaceRcPtr srgb = OCIO::ColorSpace::Create(OCIO::REFERENCE_SPACE_SCENE);
    srgb->setName(k_srgb_space);
    srgb->setFamily("Display");
    srgb->setDescription("sRGB (IEC 61966-2-1) encoded Rec.709");
    srgb->setTransform(curve, OCIO::COLORSPACE_DIR_FROM_REFERENCE);
    config->addColorSpace(srgb);

    OCIO::ColorSpaceRcPtr raw = OCIO::ColorSpace::Create(OCIO::REFERENCE_SPACE_SCENE);
    raw->setName(k_raw_space);
    raw->setFamily("Utility");
    raw->setDescription("Values passed through unchanged");
    raw->setIsData(true);
    config->addColorSpace(raw);

    config->setRole(OCIO::ROLE_SCENE_LINEAR, k_linear_space);
    config->setRole(OCIO::ROLE_REFERENCE, k_linear_space);
    config->setRole(OCIO::ROLE_DEFAULT, k_linear_space);
    config->setRole(OCIO::ROLE_DATA, k_raw_space);
    config->setRole(OCIO::ROLE_COLOR_PICKING, k_srgb_space);

    config->addDisplayView("sRGB", "Standard", k_srgb_space, "");
    config->addDisplayView("sRGB", "Raw", k_raw_space, "");
    config->setActiveDisplays("sRGB");
    config->setActiveViews("Standard, Raw");

    config->validate();
    return config;
}

struct LoadedConfig {
    OCIO::ConstConfigRcPtr config;
    std::string source;
};

// Reads $OCIO at every call (no global cache) so a changed environment takes effect.
LoadedConfig load_config() {
    const char* env = std::getenv("OCIO");
    if (env && *env) {
        std::string path = env;
        try {
            return {OCIO::Config::CreateFromFile(path.c_str()), "$OCIO=" + path};
        } catch (const OCIO::Exception& e) {
            throw OutputError("$OCIO=" + path + ": cannot load colour config: " + one_line(e.what()));
        }
    }
    try {
        return {make_builtin_config(), "built-in"};
    } catch (const OCIO::Exception& e) {
        throw OutputError("built-in colour config is invalid: " + one_line(e.what()));
    }
}

std::vector<std::string> displays_of(const OCIO::Config& config) {
    std::vector<std::string> out;
    for (int i = 0; i < config.getNumDisplays(); ++i) out.emplace_back(config.getDisplay(i));
    return out;
}

std::vector<std::string> views_of(const OCIO::Config& config, const std::string& display) {
    std::vector<std::string> out;
    for (int i = 0; i < config.getNumViews(display.c_str()); ++i) out.emplace_back(config.getView(display.c_str(), i));
    return out;
}

std::vector<std::string> looks_of(const OCIO::Config& config) {
    std::vector<std::string> out;
    for (int i = 0; i < config.getNumLooks(); ++i) out.emplace_back(config.getLookNameByIndex(i));
    return out;
}

bool contains(const std::vector<std::string>& items, const std::string& item) {
    return std::find(items.begin(), items.end(), item) != items.end();
}

// A look setting may combine looks ("a, -b" or "a:b"), as OCIO allows; each named look must
// exist.
void check_looks(const OCIO::Config& config, const std::string& looks, const std::string& source) {
    const std::vector<std::string> known = looks_of(config);
    std::string list = looks;
    std::replace(list.begin(), list.end(), ':', ',');  // OCIO accepts either separator
    std::string token;
    std::istringstream in(list);
    while (std::getline(in, token, ',')) {
        size_t first = token.find_first_not_of(" \t");
        if (first == std::string::npos) continue;
        size_t last = token.find_last_not_of(" \t");
        std::string name = token.substr(first, last - first + 1);
        if (name[0] == '+' || name[0] == '-') name.erase(0, 1);
        if (!contains(known, name))
            throw OutputError("unknown look '" + name + "' in colour config " + source + "; looks: " + join(known));
    }
}

}  // namespace

struct DisplayTransform::Impl {
    OCIO::ConstCPUProcessorRcPtr cpu;
};

DisplayTransform::DisplayTransform(const DisplaySettings& settings) : m_impl(std::make_unique<Impl>()) {
    if (!std::isfinite(settings.exposure)) throw OutputError("display exposure must be finite");
    if (!(settings.gamma > 0) || !std::isfinite(settings.gamma)) throw OutputError("display gamma must be positive");

    LoadedConfig loaded = load_config();
    const OCIO::Config& config = *loaded.config;

    const std::vector<std::string> displays = displays_of(config);
    std::string display = settings.display.empty() ? config.getDefaultDisplay() : settings.display;
    if (!contains(displays, display))
        throw OutputError("unknown display '" + display + "' in colour config " + loaded.source +
                          "; displays: " + join(displays));
    const std::vector<std::string> views = views_of(config, display);
    std::string view = settings.view.empty() ? config.getDefaultView(display.c_str()) : settings.view;
    if (!contains(views, view))
        throw OutputError("unknown view '" + view + "' for display '" + display + "' in colour config " +
                          loaded.source + "; views: " + join(views));
    if (!settings.look.empty()) check_looks(config, settings.look, loaded.source);

    try {
        OCIO::DisplayViewTransformRcPtr display_view = OCIO::DisplayViewTransform::Create();
        display_view->setSrc(OCIO::ROLE_SCENE_LINEAR);
        display_view->setDisplay(display.c_str());
        display_view->setView(view.c_str());

        // The legacy viewing pipeline orders the pieces the way a viewer does: exposure in
        // scene-linear, then the look, then the view, then a display gamma on the result.
        OCIO::LegacyViewingPipelineRcPtr pipeline = OCIO::LegacyViewingPipeline::Create();
        pipeline->setDisplayViewTransform(display_view);
        if (settings.exposure != 0) {
            // A plain scale is exact; 2^stops on RGB, alpha kept.
            const double gain = std::exp2(static_cast<double>(settings.exposure));
            const double m[16] = {gain, 0, 0, 0, 0, gain, 0, 0, 0, 0, gain, 0, 0, 0, 0, 1};
            OCIO::MatrixTransformRcPtr scale = OCIO::MatrixTransform::Create();
            scale->setMatrix(m);
            pipeline->setLinearCC(scale);
        }
        if (!settings.look.empty()) {
            pipeline->setLooksOverride(settings.look.c_str());
            pipeline->setLooksOverrideEnabled(true);
        }
        if (settings.gamma != 1) {
            const double e = 1.0 / static_cast<double>(settings.gamma);
            const double value[4] = {e, e, e, 1.0};
            OCIO::ExponentTransformRcPtr exponent = OCIO::ExponentTransform::Create();
            exponent->setValue(value);
            pipeline->setDisplayCC(exponent);
        }
        OCIO::ConstProcessorRcPtr processor = pipeline->getProcessor(loaded.config);
        // The default optimisation approximates pow/log; 16-bit output deserves the exact curve.
        const auto optimization =
            static_cast<OCIO::OptimizationFlags>(OCIO::OPTIMIZATION_DEFAULT & ~OCIO::OPTIMIZATION_FAST_LOG_EXP_POW);
        m_impl->cpu = processor->getOptimizedCPUProcessor(OCIO::BIT_DEPTH_F32, OCIO::BIT_DEPTH_F32, optimization);
    } catch (const OCIO::Exception& e) {
        throw OutputError("colour config " + loaded.source + ", display '" + display + "', view '" + view +
                          "': " + one_line(e.what()));
    }
}

DisplayTransform::~DisplayTransform() = default;

void DisplayTransform::apply(Image& image) const {
    if (image.width <= 0 || image.height <= 0) return;
    const OCIO::CPUProcessor& cpu = *m_impl->cpu;
    const size_t row_floats = static_cast<size_t>(image.width) * 4;
    tbb::parallel_for(tbb::blocked_range<int>(0, image.height, 8), [&](const tbb::blocked_range<int>& rows) {
        float* data = image.rgba.data() + rows.begin() * row_floats;
        const size_t count = static_cast<size_t>(rows.size()) * image.width;
        // Alpha is coverage, not colour: keep it bit-exact whatever the config does to it.
        std::vector<float> alpha(count);
        for (size_t i = 0; i < count; ++i) alpha[i] = data[i * 4 + 3];
        OCIO::PackedImageDesc desc(data, image.width, static_cast<long>(rows.size()), 4);
        try {
            cpu.apply(desc);
        } catch (const OCIO::Exception& e) {
            throw OutputError(std::string("display transform failed: ") + one_line(e.what()));
        }
        for (size_t i = 0; i < count; ++i) {
            for (int c = 0; c < 3; ++c) {
                float& v = data[i * 4 + c];
                // Written so that NaN becomes 0 rather than slipping through std::clamp.
                v = v > 0.0f ? (v < 1.0f ? v : 1.0f) : 0.0f;
            }
            data[i * 4 + 3] = alpha[i];
        }
    });
}

ColorConfigInfo describe_color_config() {
    LoadedConfig loaded = load_config();
    const OCIO::Config& config = *loaded.config;
    ColorConfigInfo info;
    info.source = loaded.source;
    info.displays = displays_of(config);
    for (const std::string& display : info.displays) info.views.emplace_back(display, views_of(config, display));
    info.looks = looks_of(config);
    return info;
}

std::string builtin_color_config_text() {
    std::ostringstream out;
    make_builtin_config()->serialize(out);
    return out.str();
}

}  // namespace veach
