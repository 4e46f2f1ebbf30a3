// The film's halves for the denoiser (FilmSettings::halves): the even and odd sample indices are
// resolved apart, camera samples and light-tracing splats alike, each an estimate of the whole
// image; keeping them changes nothing of the image itself (bit for bit), and a denoised render
// carries the noisy image and the denoising passes.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "film/film.h"
#include "importers/importer.h"
#include "job/render_job.h"

namespace veach {
namespace {

const Scene& cornell() {
    static const Scene scene = import_scene(std::string(VEACH_EXAMPLES_DIR) + "/cornell/cornell.gltf");
    return scene;
}

RenderJobOptions options(int size, int spp, const std::string& integrator) {
    RenderJobOptions o;
    o.width = size;
    o.height = size;
    o.render.spp = spp;
    o.render.integrator = integrator;
    o.render.seed = 3;
    return o;
}

TEST(FilmHalves, EvenAndOddSamplesAreResolvedApart) {
    FilmSettings s;
    s.halves = true;
    Film film(2, 1, s);
    DenoiseFeatures f;
    f.hit = true;
    f.albedo = Rgb(0.5f, 0.25f, 1.0f);
    f.normal = Vec3(0.0f, 1.0f, 0.0f);
    f.position = Vec3(1.0f, 2.0f, 3.0f);
    f.depth = 4.0f;
    for (uint32_t k = 0; k < 5; ++k) {
        film.add_sample(0, 0, Rgb(static_cast<float>(k)), nullptr, k, &f);  // even 0, 2, 4; odd 1, 3
        film.add_sample(1, 0, Rgb(1.0f), nullptr, k, nullptr);             // no features: a miss
    }
    // One splat per half on pixel 1 (light paths of samples 0 and 1).
    film.add_splat(1.5f, 0.5f, Rgb(3.0f), 0);
    film.add_splat(1.5f, 0.5f, Rgb(5.0f), 1);
    const FilmHalves h = film.resolve_halves(5);
    ASSERT_EQ(h.even.size(), 6u);
    EXPECT_DOUBLE_EQ(h.even[0], 2.0);  // (0 + 2 + 4) / 3
    EXPECT_DOUBLE_EQ(h.odd[0], 2.0);   // (1 + 3) / 2
    // Splats over each half's paths per pixel: 3 even (0, 2, 4), 2 odd (1, 3).
    EXPECT_FLOAT_EQ(h.even[3], 1.0f + 3.0f / 3.0f);
    EXPECT_FLOAT_EQ(h.odd[3], 1.0f + 5.0f / 2.0f);
    EXPECT_FLOAT_EQ(h.albedo[0], 0.5f);
    EXPECT_FLOAT_EQ(h.albedo[2], 1.0f);
    EXPECT_FLOAT_EQ(h.normal[1], 1.0f);
    EXPECT_FLOAT_EQ(h.position[2], 3.0f);
    EXPECT_FLOAT_EQ(h.depth[0], 4.0f);
    EXPECT_FLOAT_EQ(h.albedo[3], 0.0f);
    EXPECT_FLOAT_EQ(h.depth[1], k_no_hit_depth);
    // The whole image is what it always was.
    const Image img = film.resolve(5);
    EXPECT_FLOAT_EQ(img.pixel(0, 0)[0], 2.0f);
    EXPECT_FLOAT_EQ(img.pixel(1, 0)[0], 1.0f + 8.0f / 5.0f);
}

// A checkpoint holds the halves: a film restored from it resolves the same halves bit for bit.
TEST(FilmHalves, TheStateCarriesTheHalves) {
    FilmSettings s;
    s.halves = true;
    Film film(3, 2, s), restored(3, 2, s);
    DenoiseFeatures f;
    f.hit = true;
    f.albedo = Rgb(0.3f);
    f.position = Vec3(1e3f, 2.0f, -5.0f);
    for (uint32_t k = 0; k < 7; ++k) {
        film.add_sample(k % 3, (k / 3) % 2, Rgb(0.1f * k, 0.2f, 0.3f), nullptr, k, &f);
        film.add_splat(0.5f + k % 3, 1.5f, Rgb(0.25f * k), k);
    }
    std::vector<double> state(film.state_size());
    film.save_state(state.data());
    restored.load_state(state.data(), state.size());
    const FilmHalves a = film.resolve_halves(7), b = restored.resolve_halves(7);
    EXPECT_EQ(a.even, b.even);
    EXPECT_EQ(a.odd, b.odd);
    EXPECT_EQ(a.albedo, b.albedo);
    EXPECT_EQ(a.position, b.position);
    EXPECT_EQ(a.depth, b.depth);
    // A film without halves has a smaller state: the sizes tell them apart.
    EXPECT_NE(Film(3, 2).state_size(), film.state_size());
}

TEST(FilmHalves, AFilmWithoutHalvesHasNone) {
    Film film(2, 2);
    film.add_sample(0, 0, Rgb(1.0f), nullptr, 1);
    EXPECT_TRUE(film.resolve_halves(1).even.empty());
}

// Keeping the halves must not touch the image: pt (camera samples) and bdpt (camera samples and
// splats), bit for bit; and the two halves average to the image within rounding.
TEST(FilmHalves, KeepingHalvesLeavesTheImageBitForBit) {
    for (const char* integrator : {"pt", "bdpt"}) {
        RenderJobOptions plain = options(24, 6, integrator), kept = plain;
        kept.film.halves = true;
        const RenderResult a = render_scene(cornell(), plain), b = render_scene(cornell(), kept);
        ASSERT_EQ(a.image.rgba.size(), b.image.rgba.size());
        EXPECT_EQ(0, std::memcmp(a.image.rgba.data(), b.image.rgba.data(), a.image.rgba.size() * sizeof(float)))
            << integrator;
        const FilmHalves h = b.film->resolve_halves(6);
        double worst = 0.0;
        for (size_t i = 0; i < h.even.size(); ++i) {
            const double whole = b.image.rgba[i / 3 * 4 + i % 3];
            worst = std::max(worst, std::fabs(0.5 * (h.even[i] + h.odd[i]) - whole) / (1e-3 + std::fabs(whole)));
        }
        EXPECT_LT(worst, 1e-4) << integrator;
    }
}

TEST(FilmHalves, ADenoisedRenderKeepsTheNoisyImageAndTheFeatures) {
    RenderJobOptions o = options(32, 8, "pt");
    const RenderResult plain = render_scene(cornell(), o);
    o.denoise = true;
    const RenderResult r = render_scene(cornell(), o);
    const size_t n = 32 * 32;
    ASSERT_EQ(r.image.noisy.size(), n * 3);
    ASSERT_EQ(r.image.denoising_albedo.size(), n * 3);
    ASSERT_EQ(r.image.denoising_normal.size(), n * 3);
    ASSERT_EQ(r.image.denoising_depth.size(), n);
    for (size_t i = 0; i < n; ++i)
        for (int c = 0; c < 3; ++c) ASSERT_EQ(r.image.noisy[i * 3 + c], plain.image.rgba[i * 4 + c]);
    bool changed = false;
    for (size_t i = 0; i < n; ++i) changed = changed || r.image.rgba[i * 4] != plain.image.rgba[i * 4];
    EXPECT_TRUE(changed);
    EXPECT_GT(r.denoise_seconds, 0.0);
}

// A denoised render is a pure function of the render: pt's images are the same bit for bit on 1
// and 2 threads, and so are their denoised images.
TEST(FilmHalves, ADenoisedRenderIsTheSameAtAnyThreadCount) {
    RenderJobOptions o = options(40, 6, "pt");
    o.denoise = true;
    o.render.threads = 1;
    const RenderResult one = render_scene(cornell(), o);
    o.render.threads = 2;
    const RenderResult two = render_scene(cornell(), o);
    ASSERT_EQ(one.image.rgba.size(), two.image.rgba.size());
    EXPECT_EQ(0, std::memcmp(one.image.rgba.data(), two.image.rgba.data(), one.image.rgba.size() * sizeof(float)));
    EXPECT_EQ(0, std::memcmp(one.image.noisy.data(), two.image.noisy.data(), one.image.noisy.size() * sizeof(float)));
}

TEST(FilmHalves, DenoisingRefusesParts) {
    RenderJobOptions o = options(16, 8, "pt");
    o.denoise = true;
    o.part.sample_begin = 0;
    o.part.sample_end = 4;
    EXPECT_THROW(render_scene(cornell(), o), std::invalid_argument);
}

}  // namespace
}  // namespace veach
