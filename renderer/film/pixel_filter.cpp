#include "film/pixel_filter.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace veach {

namespace {
// Bins over the whole support: 4096 keep the tabulated density within 0.3% of the continuous
// profile for any width, far below the noise of any render.
constexpr int k_table_size = 4096;
constexpr int k_subsamples = 8;  // midpoint rule inside each bin for its integral
constexpr double k_pi = 3.14159265358979323846;
}  // namespace

namespace {
struct NamedFilter {
    FilterType type;
    const char* name;
};
constexpr NamedFilter k_filters[] = {
    {FilterType::box, "box"}, {FilterType::gaussian, "gaussian"}, {FilterType::blackman_harris, "blackman-harris"}};
}  // namespace

const char* filter_name(FilterType type) {
    for (const NamedFilter& f : k_filters)
        if (f.type == type) return f.name;
    return "box";
}

bool parse_filter_name(const std::string& name, FilterType* type) {
    for (const NamedFilter& f : k_filters) {
        if (name == f.name) {
            *type = f.type;
            return true;
        }
    }
    if (name != "blackman_harris") return false;  // the enum's spelling, accepted too
    *type = FilterType::blackman_harris;
    return true;
}

const std::vector<std::string>& filter_names() {
    static const std::vector<std::string> names = [] {
        std::vector<std::string> n;
        for (const NamedFilter& f : k_filters) n.push_back(f.name);
        return n;
    }();
    return names;
}

float PixelFilter::support_width(FilterType type, float width) {
    // Blender's "Width" is not the support: Cycles stretches the Gaussian's window to 3 widths
    // (6 sigma) and Blackman-Harris to 2 widths, so that at equal width the filters blur about
    // equally. Matching that keeps our images as soft as Blender's at the same setting.
    switch (type) {
        case FilterType::box: return width;
        case FilterType::gaussian: return 3.0f * width;
        case FilterType::blackman_harris: return 2.0f * width;
    }
    return width;
}

double PixelFilter::profile(FilterType type, float width, double offset) {
    const double support = support_width(type, width);
    if (std::fabs(offset) > 0.5 * support) return 0.0;
    switch (type) {
        case FilterType::box: return 1.0;
        case FilterType::gaussian: {
            // sigma = width / 4: exp(-x^2 / (2 sigma^2)) = exp(-8 x^2 / width^2), cut at 6 sigma.
            const double v = offset / width;
            return std::exp(-8.0 * v * v);
        }
        case FilterType::blackman_harris: {
            // The 4-term Blackman-Harris window (Harris 1978, "On the use of windows for harmonic
            // analysis with the DFT", eq. 33 coefficients), spanning the support with its peak at 0.
            const double x = 2.0 * k_pi * (offset / support + 0.5);
            return 0.35875 - 0.48829 * std::cos(x) + 0.14128 * std::cos(2.0 * x) - 0.01168 * std::cos(3.0 * x);
        }
    }
    return 0.0;
}

PixelFilter::PixelFilter(const FilterSettings& settings) : m_settings(settings) {
    if (!(settings.width > 0.0f && settings.width <= 64.0f))
        throw std::invalid_argument("filter width must be in (0, 64] pixels, not " + std::to_string(settings.width));
    m_radius = 0.5f * support_width(settings.type, settings.width);
    if (settings.type == FilterType::box) return;

    // Piecewise-constant density: each bin's integral of the profile, normalised. Sampling and
    // pdf() both use these bins, so the sampled distribution is exactly the one splats weight by.
    const double r = m_radius, bin = 2.0 * r / k_table_size;
    std::vector<double> mass(k_table_size);
    double total = 0.0;
    for (int i = 0; i < k_table_size; ++i) {
        double m = 0.0;
        for (int k = 0; k < k_subsamples; ++k)
            m += std::max(0.0, profile(settings.type, settings.width, -r + (i + (k + 0.5) / k_subsamples) * bin));
        mass[i] = m * bin / k_subsamples;
        total += mass[i];
    }
    m_density.resize(k_table_size);
    m_cdf.resize(k_table_size + 1);
    m_cdf[0] = 0.0;
    for (int i = 0; i < k_table_size; ++i) {
        m_density[i] = static_cast<float>(mass[i] / (total * bin));
        m_cdf[i + 1] = m_cdf[i] + mass[i] / total;
    }
    m_cdf[k_table_size] = 1.0;
}

float PixelFilter::sample(float u) const {
    if (m_settings.type == FilterType::box) return (u - 0.5f) * m_settings.width;
    // The bin whose CDF interval holds u, then linear inside it (the density is constant there).
    const auto it = std::upper_bound(m_cdf.begin(), m_cdf.end(), static_cast<double>(u));
    int i = static_cast<int>(it - m_cdf.begin()) - 1;
    i = std::clamp(i, 0, k_table_size - 1);
    while (i > 0 && m_cdf[i + 1] <= m_cdf[i]) --i;  // never land in an empty bin
    const double span = m_cdf[i + 1] - m_cdf[i];
    const double t = span > 0.0 ? std::clamp((u - m_cdf[i]) / span, 0.0, 1.0) : 0.5;
    const double bin = 2.0 * m_radius / k_table_size;
    return static_cast<float>(-m_radius + (i + t) * bin);
}

float PixelFilter::pdf(float offset) const {
    if (!(std::fabs(offset) <= m_radius)) return 0.0f;
    if (m_settings.type == FilterType::box) return 1.0f / m_settings.width;
    const double bin = 2.0 * m_radius / k_table_size;
    int i = static_cast<int>(std::floor((offset + m_radius) / bin));
    return m_density[std::clamp(i, 0, k_table_size - 1)];
}

}  // namespace veach
