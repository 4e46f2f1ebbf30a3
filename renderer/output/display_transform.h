// OpenColorIO display transforms. The config comes from $OCIO when set; otherwise a config built
// in code (scene_linear = Linear Rec.709, display sRGB with views Standard and Raw), since
// OpenColorIO 2.1 has no built-in configs. OCIO types stay inside output/.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "film/film.h"
#include "output/image_output.h"

namespace veach {

class DisplayTransform {
public:
    // Throws OutputError naming the display/view/look when the config lacks them.
    explicit DisplayTransform(const DisplaySettings& settings);
    ~DisplayTransform();
    DisplayTransform(const DisplayTransform&) = delete;
    DisplayTransform& operator=(const DisplayTransform&) = delete;

    // Applies the transform in place to RGBA pixels (alpha untouched); the result is
    // display-referred, clamped to [0, 1].
    void apply(Image& image) const;

private:
    struct Impl;
    std::unique_ptr<Impl> m_impl;
};

struct ColorConfigInfo {
    std::string source;  // "$OCIO=/path" or "built-in"
    std::vector<std::string> displays;
    std::vector<std::pair<std::string, std::vector<std::string>>> views;  // per display
    std::vector<std::string> looks;
};
ColorConfigInfo describe_color_config();

// The built-in config as OCIO YAML, e.g. to save it as a starting point for a custom config or
// to hand the same colour pipeline to other OCIO tools.
std::string builtin_color_config_text();

}  // namespace veach
