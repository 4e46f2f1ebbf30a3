// Filters and checkpoints in real renders of the Cornell box example: a filter redistributes
// light between neighbouring pixels but cannot change the image's mean; the first-hit passes
// hold what Blender's passes hold; a render resumed from a checkpoint equals the uninterrupted
// one bit for bit (path tracing: randomness is keyed by pixel and sample index).
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>

#include "job/render_job.h"
#include "importers/importer.h"

namespace veach {
namespace {

namespace fs = std::filesystem;

const Scene& cornell() {
    static const Scene scene = import_scene(std::string(VEACH_EXAMPLES_DIR) + "/cornell/cornell.gltf");
    return scene;
}

RenderJobOptions options(int size, int spp, const std::string& integrator = "pt") {
    RenderJobOptions o;
    o.width = size;
    o.height = size;
    o.render.spp = spp;
    o.render.integrator = integrator;
    o.render.seed = 5;
    return o;
}

struct MeanWithError {
    double mean = 0, standard_error = 0;
};

// The image's mean over all channels and its standard error from the variance pass (pixels are
// independent, so the variances of their means add).
MeanWithError image_mean(const Image& img) {
    const size_t n = static_cast<size_t>(img.width) * img.height;
    double sum = 0, var = 0;
    for (size_t i = 0; i < n; ++i)
        for (int c = 0; c < 3; ++c) {
            sum += img.rgba[i * 4 + c];
            var += img.variance[i * 3 + c];
        }
    return {sum / (3.0 * n), std::sqrt(var) / (3.0 * n)};
}

// Filter importance sampling is unbiased for the filtered image, and a normalised filter
// conserves the image's total: box and Blackman-Harris (and Gaussian) agree within noise plus
// a small allowance for the light the border pixels' wider support sees beyond the frame.
TEST(FilteredRender, FiltersKeepTheImageMean) {
    RenderJobOptions box = options(32, 96);
    MeanWithError m_box = image_mean(render_scene(cornell(), box).image);
    for (FilterType type : {FilterType::blackman_harris, FilterType::gaussian}) {
        RenderJobOptions o = box;
        o.film.filter = {type, 1.5f};
        Image img = render_scene(cornell(), o).image;
        MeanWithError m = image_mean(img);
        const double sigma = std::hypot(m_box.standard_error, m.standard_error);
        EXPECT_NEAR(m.mean, m_box.mean, 4.0 * sigma + 0.01 * m_box.mean)
            << filter_name(type) << ": box " << m_box.mean << " +- " << m_box.standard_error << ", filtered " << m.mean
            << " +- " << m.standard_error;
        EXPECT_GT(m.mean, 0.0);
    }
}

// Light tracing splats through the same filter: its mean agrees with path tracing's.
TEST(FilteredRender, LightTracingSplatsUseTheSameFilter) {
    RenderJobOptions pt = options(24, 64);
    pt.film.filter = {FilterType::blackman_harris, 1.5f};
    RenderJobOptions lt = pt;
    lt.render.integrator = "lt";
    lt.render.spp = 64;
    const Image a = render_scene(cornell(), pt).image;
    const Image b = render_scene(cornell(), lt).image;
    // Compare the interior (light tracing cannot splat from beyond the frame onto border
    // pixels) block by block: 4x4 blocks of 4x4 pixels, channel-averaged.
    double sa = 0, sb = 0;
    for (int y = 4; y < 20; ++y)
        for (int x = 4; x < 20; ++x)
            for (int c = 0; c < 3; ++c) {
                sa += a.pixel(x, y)[c];
                sb += b.pixel(x, y)[c];
            }
    EXPECT_NEAR(sb / sa, 1.0, 0.05) << "pt " << sa << " lt " << sb;
}

TEST(FilteredRender, FirstHitPassesHoldDepthNormalAlbedo) {
    // One sample per pixel: each pass value is one first hit.
    RenderJobOptions o = options(16, 1);
    o.film.aovs = true;
    Image img = render_scene(cornell(), o).image;
    ASSERT_EQ(img.depth.size(), 16u * 16u);
    size_t hits = 0;
    for (size_t i = 0; i < img.depth.size(); ++i) {
        const float* n = &img.normal[i * 3];
        const float* a = &img.albedo[i * 3];
        if (img.depth[i] == k_no_hit_depth) {
            // Blender's background: Z 1e10, no normal, no albedo.
            ASSERT_EQ(n[0] * n[0] + n[1] * n[1] + n[2] * n[2], 0.0f);
            ASSERT_EQ(a[0] + a[1] + a[2], 0.0f);
            continue;
        }
        ++hits;
        // In front of the camera, within the box's few metres.
        ASSERT_GT(img.depth[i], 0.0f);
        ASSERT_LT(img.depth[i], 100.0f);
        ASSERT_NEAR(n[0] * n[0] + n[1] * n[1] + n[2] * n[2], 1.0f, 1e-4f);
        for (int c = 0; c < 3; ++c) {
            ASSERT_GE(a[c], 0.0f);
            ASSERT_LE(a[c], 1.0f);
        }
    }
    // The box fills most of the frame.
    EXPECT_GT(hits, img.depth.size() / 2);
}

bool same_pixels(const Image& a, const Image& b) {
    return a.rgba.size() == b.rgba.size() &&
           std::memcmp(a.rgba.data(), b.rgba.data(), a.rgba.size() * sizeof(float)) == 0 &&
           std::memcmp(a.variance.data(), b.variance.data(), a.variance.size() * sizeof(float)) == 0;
}

// A render stopped after its checkpoint and resumed to the full spp equals the one that never
// stopped: same seed, same sample indices, and each pixel adds its samples in index order
// whatever the passes.
TEST(FilteredRender, ResumedRenderIsBitIdentical) {
    const fs::path path = fs::path(testing::TempDir()) / ("veach_resume_" + std::to_string(::getpid()) + ".checkpoint");
    RenderJobOptions full = options(24, 40);
    full.film.filter = {FilterType::gaussian, 1.5f};
    full.render.threads = 2;
    const Image reference = render_scene(cornell(), full).image;

    // "Interrupted": a render of 7 spp (passes of 1, 2, 4) checkpointing every pass keeps the
    // state after 3 spp (the last pass needs no checkpoint: its image is written).
    RenderJobOptions first = full;
    first.render.spp = 7;
    first.render.threads = 1;
    first.checkpoint.path = path.string();
    first.checkpoint.write = true;
    render_scene(cornell(), first);
    ASSERT_TRUE(fs::exists(path));

    RenderJobOptions resumed = full;
    resumed.checkpoint.path = path.string();
    resumed.checkpoint.resume = true;
    RenderResult r = render_scene(cornell(), resumed);
    EXPECT_EQ(r.resumed_spp, 3);
    EXPECT_EQ(r.stats.spp_done, 40);
    EXPECT_TRUE(same_pixels(reference, r.image));

    // A different seed is another render: its checkpoint is refused.
    RenderJobOptions other = resumed;
    other.render.seed = 6;
    EXPECT_ANY_THROW(render_scene(cornell(), other));
    fs::remove(path);
}

}  // namespace
}  // namespace veach
