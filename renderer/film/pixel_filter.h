// Pixel reconstruction filters as Blender's Cycles offers them: box, Gaussian and
// Blackman-Harris, each separable (f(dx, dy) = f1(dx) f1(dy)) and normalised to integrate to 1.
//
// Camera samples use filter importance sampling: a sample for pixel (x, y) is placed at an
// offset drawn from the filter's own density and then counts with weight 1 in that pixel alone.
// The pixel mean then estimates the filtered image I(x, y) = integral of f(p - c) L(p) dp
// without bias, and each pixel keeps a single owner (no atomics between tiles). Light-tracing
// splats, which arrive at positions nobody chose, must use the same f: a splat at p adds
// f(p - c) times its value to every pixel centre c whose support covers p.
//
// Gaussian and Blackman-Harris are tabulated (4096 bins over their support), and both the
// sampling and pdf() use the same piecewise-constant density, so camera samples and splats
// see one and the same filter exactly.
#pragma once

#include <string>
#include <vector>

namespace veach {

enum class FilterType { box, gaussian, blackman_harris };

struct FilterSettings {
    FilterType type = FilterType::box;
    float width = 1.0f;  // pixels, as Blender's "Width" (1.5 for its default Blackman-Harris)
};

// "box", "gaussian", "blackman-harris".
const char* filter_name(FilterType type);
// Accepts the names above (and "blackman_harris"); false for anything else.
bool parse_filter_name(const std::string& name, FilterType* type);
// The names above, in that order: what the C API lists and its messages quote.
const std::vector<std::string>& filter_names();

class PixelFilter {
public:
    // Throws std::invalid_argument for a width outside (0, 64].
    explicit PixelFilter(const FilterSettings& settings = {});

    const FilterSettings& settings() const { return m_settings; }
    // Half the extent of the support: |offset| <= radius() where pdf() > 0.
    float radius() const { return m_radius; }
    // True for the 1-pixel box: offsets are exactly u - 0.5, so a pixel's samples stay inside it.
    bool is_unit_box() const { return m_settings.type == FilterType::box && m_settings.width == 1.0f; }

    // A 1D offset from the pixel centre, distributed with density pdf(offset), from u in [0, 1).
    float sample(float u) const;
    // The normalised 1D filter (a density: it integrates to 1 over the support).
    float pdf(float offset) const;

    // The continuous 1D filter function before normalisation and tabulation (peak 1), as Cycles
    // defines it; for tests and documentation.
    static double profile(FilterType type, float width, double offset);
    // The full support extent a width maps to: Cycles spans the Gaussian over 3 widths and
    // Blackman-Harris over 2.
    static float support_width(FilterType type, float width);

private:
    FilterSettings m_settings;
    float m_radius = 0.5f;
    // Tabulated filters: bin densities (normalised) and the CDF at bin edges.
    std::vector<float> m_density;
    std::vector<double> m_cdf;
};

}  // namespace veach
