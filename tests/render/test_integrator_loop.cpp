// The integrator loop: PixelSampleIntegrator evaluates every sample of every pixel exactly once,
// keyed by (pixel, sample index) whatever the tiles and threads; drops and counts estimates
// that are not finite; and the driver brackets each pass with the integrator's hooks, which see
// the sample ranges of the passes in order, covering [0, spp) without a gap.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <mutex>
#include <utility>
#include <vector>

#include "importers/importer.h"
#include "integrators/pixel_sample_integrator.h"

namespace veach {
namespace {

// Records each sample it is asked for, and returns 1 (NaN for odd sample indices if asked).
class RecordingIntegrator final : public PixelSampleIntegrator<RecordingIntegrator> {
public:
    RecordingIntegrator(const RenderSettings& settings, int width, bool odd_nan)
        : PixelSampleIntegrator(settings), m_width(width), m_odd_nan(odd_nan) {}

    struct TileState {
        int samples = 0;
    };
    TileState begin_tile(const RenderScene&, ThreadStats&) const { return {}; }
    Rgb evaluate_pixel_sample(TileState& state, const RenderScene&, const CameraModel&, float fx, float fy, float,
                              Sampler&, Film&, ThreadStats&) const {
        ++state.samples;
        const int x = static_cast<int>(std::floor(fx)), y = static_cast<int>(std::floor(fy));
        std::lock_guard<std::mutex> lock(m_mutex);
        const uint32_t index = static_cast<uint32_t>(m_next[static_cast<size_t>(y) * m_width + x]++);
        m_seen.emplace_back(y * m_width + x, index);
        if (m_odd_nan && index % 2 == 1) return Rgb(std::numeric_limits<float>::quiet_NaN());
        return Rgb(1.0f);
    }
    void begin_pass(const RenderScene&, uint32_t begin, uint32_t end, Film&) override {
        EXPECT_FALSE(m_in_pass);
        m_in_pass = true;
        m_passes.emplace_back(begin, end);
        m_seen_at_begin = m_seen.size();
    }
    void end_pass(const RenderScene&, uint32_t begin, uint32_t end, Film& film) override {
        EXPECT_TRUE(m_in_pass);
        m_in_pass = false;
        // Every sample of the pass was evaluated before its end.
        EXPECT_EQ(m_seen.size() - m_seen_at_begin, static_cast<size_t>(end - begin) * film.width() * film.height());
    }

    int m_width;
    bool m_odd_nan;
    mutable std::mutex m_mutex;
    mutable std::vector<int> m_next = std::vector<int>(64 * 64, 0);
    mutable std::vector<std::pair<int, uint32_t>> m_seen;
    std::vector<std::pair<uint32_t, uint32_t>> m_passes;
    size_t m_seen_at_begin = 0;
    bool m_in_pass = false;
};

const Scene& cornell() {
    static const Scene scene = import_scene(std::string(VEACH_EXAMPLES_DIR) + "/cornell/cornell.gltf");
    return scene;
}

TEST(IntegratorLoop, EverySampleOncePassesBracketedAndInOrder) {
    const int w = 40, h = 24, spp = 11;  // tiles of 16 cut short at both edges
    RenderSettings settings;
    settings.spp = spp;
    settings.threads = 2;
    RenderScene rs(cornell(), &cornell().cameras.at(0), w, h);
    Film film(w, h);
    RecordingIntegrator integrator(settings, w, false);
    RenderStats stats = render_image(rs, integrator, settings, film);
    EXPECT_EQ(stats.spp_done, spp);
    EXPECT_EQ(stats.nonfinite_samples, 0u);
    EXPECT_FALSE(integrator.m_in_pass);
    // Passes double (1, 2, 4, ...) and tile [0, spp) in order.
    ASSERT_FALSE(integrator.m_passes.empty());
    EXPECT_EQ(integrator.m_passes.front().first, 0u);
    for (size_t i = 1; i < integrator.m_passes.size(); ++i)
        EXPECT_EQ(integrator.m_passes[i].first, integrator.m_passes[i - 1].second);
    EXPECT_EQ(integrator.m_passes.back().second, static_cast<uint32_t>(spp));
    // Each pixel got spp samples, each once; its film value is their mean.
    ASSERT_EQ(integrator.m_seen.size(), static_cast<size_t>(w) * h * spp);
    for (int p = 0; p < w * h; ++p) EXPECT_EQ(integrator.m_next[p], spp) << "pixel " << p;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) EXPECT_EQ(film.pixel_sums(x, y).sum[1], double(spp));
}

TEST(IntegratorLoop, NonFiniteEstimatesAreDroppedAndCounted) {
    const int w = 16, h = 8, spp = 6;
    RenderSettings settings;
    settings.spp = spp;
    settings.threads = 1;
    RenderScene rs(cornell(), &cornell().cameras.at(0), w, h);
    Film film(w, h);
    RecordingIntegrator integrator(settings, w, true);
    RenderStats stats = render_image(rs, integrator, settings, film);
    // Samples 1, 3 and 5 of each pixel are NaN: dropped, never written, counted.
    EXPECT_EQ(stats.nonfinite_samples, static_cast<uint64_t>(w) * h * 3);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            EXPECT_EQ(film.pixel_sums(x, y).sum[0], 3.0);
            EXPECT_EQ(film.pixel_sums(x, y).weight, 3.0);
        }
}

}  // namespace
}  // namespace veach
