// The film's passes and state: the variance pass is the variance of each pixel's mean, AOVs
// follow Blender's conventions (Z from one sample, averaged normal and albedo), and a checkpoint
// restores the film bit for bit and refuses a render it was not made for.
#include "film/film.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "job/render_job.h"
#include "core/rng.h"
#include "film/film_checkpoint.h"

namespace veach {
namespace {

namespace fs = std::filesystem;

fs::path temp_file(const std::string& name) {
    return fs::path(testing::TempDir()) / ("veach_film_" + name + "_" + std::to_string(::getpid()));
}

// Samples 0, 1, 0, 1, ...: the sample variance is n / (4 (n - 1)) and the variance of the mean
// that divided by n; a constant pixel has none.
TEST(Film, VariancePassIsTheVarianceOfThePixelMean) {
    Film film(2, 1);
    const int n = 10;
    for (int k = 0; k < n; ++k) {
        film.add_sample(0, 0, Rgb(static_cast<float>(k % 2), 0.0f, 3.0f));
        film.add_sample(1, 0, Rgb(0.5f));
    }
    Image img = film.resolve(0);
    ASSERT_EQ(img.variance.size(), 6u);
    const double s2 = n / (4.0 * (n - 1));
    EXPECT_NEAR(img.variance[0], s2 / n, 1e-7);
    EXPECT_NEAR(img.variance[2], 0.0, 1e-7);
    EXPECT_NEAR(img.variance[3], 0.0, 1e-7);
    EXPECT_FLOAT_EQ(img.pixel(0, 0)[0], 0.5f);
}

TEST(Film, AovsFollowBlenderConventions) {
    FilmSettings s;
    s.aovs = true;
    Film film(2, 1, s);
    PixelAovs a;
    a.hit = true;
    a.depth = 2.0f;
    a.normal = Vec3(0, 0, 1);
    a.albedo = Rgb(0.8f, 0.2f, 0.1f);
    PixelAovs b = a;
    b.depth = 7.0f;
    b.normal = Vec3(1, 0, 0);
    b.albedo = Rgb(0.0f);
    film.add_sample(0, 0, Rgb(1.0f), &a);
    film.add_sample(0, 0, Rgb(1.0f), &b);
    film.add_sample(1, 0, Rgb(1.0f), nullptr);
    PixelAovs miss;
    film.add_sample(1, 0, Rgb(1.0f), &miss);
    Image img = film.resolve(0);
    ASSERT_EQ(img.depth.size(), 2u);
    // Z: the first sample's depth, never a blend of foreground and background.
    EXPECT_EQ(img.depth[0], 2.0f);
    EXPECT_EQ(img.depth[1], k_no_hit_depth);
    EXPECT_FLOAT_EQ(img.normal[0], 0.5f);
    EXPECT_FLOAT_EQ(img.normal[2], 0.5f);
    EXPECT_FLOAT_EQ(img.albedo[0], 0.4f);
    EXPECT_FLOAT_EQ(img.albedo[3], 0.0f);
    // A film without AOVs has no such passes.
    EXPECT_TRUE(Film(2, 1).resolve(0).depth.empty());
}

// Alpha is the fraction of a pixel's camera samples that hit geometry (the AOVs' hit flag), the
// splats adding light but no coverage; without FilmSettings::alpha it is 1.
TEST(Film, AlphaIsTheCoveredFractionOfCameraSamples) {
    FilmSettings s;
    s.alpha = true;
    Film film(2, 1, s);
    PixelAovs hit, miss;
    hit.hit = true;
    for (int k = 0; k < 4; ++k) film.add_sample(0, 0, Rgb(1.0f), k == 0 ? &miss : &hit);
    film.add_sample(1, 0, Rgb(0.0f), &miss);
    film.add_splat(1.5f, 0.5f, Rgb(2.0f));
    Image img = film.resolve(1);
    EXPECT_FLOAT_EQ(img.pixel(0, 0)[3], 0.75f);
    EXPECT_FLOAT_EQ(img.pixel(1, 0)[3], 0.0f);
    EXPECT_GT(img.pixel(1, 0)[0], 0.0f);
    Film opaque(2, 1);
    opaque.add_sample(0, 0, Rgb(1.0f), &miss);
    EXPECT_EQ(opaque.resolve(0).pixel(0, 0)[3], 1.0f);
}

// A 5x4 film with samples, AOVs and splats.
void fill(Film& film, int seed) {
    Rng rng(seed, 1);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 5; ++x)
            for (int k = 0; k < 3; ++k) {
                PixelAovs a;
                a.hit = rng.next_float() < 0.7f;
                a.depth = rng.next_float() * 10;
                a.normal = Vec3(rng.next_float(), 1, 0);
                a.albedo = Rgb(rng.next_float());
                film.add_sample(x, y, Rgb(rng.next_float(), rng.next_float() * 3, 0.1f / (1 + k)), &a);
            }
    for (int k = 0; k < 50; ++k) film.add_splat(rng.next_float() * 5, rng.next_float() * 4, Rgb(rng.next_float()));
}

bool same_image(const Image& a, const Image& b) {
    auto same = [](const std::vector<float>& u, const std::vector<float>& v) {
        // Empty vectors may have null data(), which memcmp must not see.
        return u.size() == v.size() && (u.empty() || std::memcmp(u.data(), v.data(), u.size() * sizeof(float)) == 0);
    };
    return same(a.rgba, b.rgba) && same(a.variance, b.variance) && same(a.depth, b.depth) && same(a.normal, b.normal) &&
           same(a.albedo, b.albedo);
}

TEST(FilmCheckpoint, RoundTripIsBitExact) {
    for (int variant = 0; variant < 3; ++variant) {
        const bool aovs = variant == 1;
        FilmSettings s;
        s.aovs = aovs;
        s.alpha = variant == 2;  // coverage is part of the state
        s.filter = {FilterType::blackman_harris, 1.5f};
        Film film(5, 4, s);
        fill(film, 3);
        const fs::path path = temp_file("roundtrip");
        write_film_checkpoint(path.string(), film, 0x1234, 3);
        Film restored(5, 4, s);
        EXPECT_EQ(read_film_checkpoint(path.string(), restored, 0x1234), 3);
        EXPECT_TRUE(same_image(film.resolve(3), restored.resolve(3))) << "aovs " << aovs;
        EXPECT_TRUE(restored.has_splats());
        fs::remove(path);
    }
}

std::string error_of(const std::function<void()>& f) {
    try {
        f();
    } catch (const CheckpointError& e) {
        return e.what();
    }
    return "";
}

TEST(FilmCheckpoint, RefusesAnotherRenderAndDamagedFiles) {
    FilmSettings s;
    Film film(5, 4, s);
    fill(film, 4);
    const fs::path path = temp_file("refuse");
    write_film_checkpoint(path.string(), film, 42, 3);

    Film other_size(6, 4, s);
    EXPECT_NE(error_of([&] { read_film_checkpoint(path.string(), other_size, 42); }).find("5x4"), std::string::npos);
    Film same(5, 4, s);
    std::string e = error_of([&] { read_film_checkpoint(path.string(), same, 43); });
    EXPECT_NE(e.find(path.string()), std::string::npos) << e;
    EXPECT_NE(e.find("other settings"), std::string::npos) << e;
    FilmSettings with_aovs;
    with_aovs.aovs = true;
    Film aov_film(5, 4, with_aovs);
    EXPECT_FALSE(error_of([&] { read_film_checkpoint(path.string(), aov_film, 42); }).empty());

    // Truncated by one byte, or not a checkpoint at all: refused, the film untouched.
    fs::resize_file(path, fs::file_size(path) - 1);
    EXPECT_NE(error_of([&] { read_film_checkpoint(path.string(), same, 42); }).find("truncated"), std::string::npos);
    { std::ofstream(path) << "hello"; }
    EXPECT_NE(error_of([&] { read_film_checkpoint(path.string(), same, 42); }).find("not a veach checkpoint"),
              std::string::npos);
    EXPECT_FALSE(same.has_splats());
    fs::remove(path);
    EXPECT_FALSE(error_of([&] { read_film_checkpoint(path.string(), same, 42); }).empty());
    // An unwritable place is a write error (a different failure from a bad checkpoint).
    EXPECT_THROW(write_film_checkpoint("/nonexistent-folder/x.checkpoint", film, 1, 1), CheckpointWriteError);
}

// A checkpoint is only what was written: a flipped byte anywhere (the CRC), NaN sums, or
// counts beyond the spp it claims are refused, never rendered into an image tagged complete.
TEST(FilmCheckpoint, RefusesCorruptContent) {
    Film film(5, 4);
    fill(film, 5);
    const fs::path path = temp_file("corrupt");
    write_film_checkpoint(path.string(), film, 42, 3);
    std::string bytes;
    {
        std::ifstream in(path, std::ios::binary);
        bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    }
    auto refused = [&](const std::string& content) {
        { std::ofstream(path, std::ios::binary) << content; }
        Film back(5, 4);
        return error_of([&] { read_film_checkpoint(path.string(), back, 42); });
    };
    EXPECT_TRUE(refused(bytes).empty());
    std::string flipped = bytes;
    flipped[flipped.size() / 2] ^= 0x20;
    EXPECT_NE(refused(flipped).find("CRC"), std::string::npos);
    // The right length of NaN bytes: not a checkpoint at all.
    EXPECT_FALSE(refused(std::string(bytes.size(), '\xff')).empty());
    // Fewer samples claimed than the pixels hold: a consistent CRC does not make it valid.
    Film counted(5, 4);
    fill(counted, 5);
    write_film_checkpoint(path.string(), counted, 42, 2);
    Film back(5, 4);
    EXPECT_NE(error_of([&] { read_film_checkpoint(path.string(), back, 42); }).find("beyond its spp"),
              std::string::npos);
    fs::remove(path);
}

// Every image-shaping number is hashed by its exact bits: a tiny noise target or a filter width
// one ulp away is another render.
TEST(FilmCheckpoint, SettingsHashIsExactForNumbers) {
    RenderJobOptions a;
    const uint64_t base = render_settings_hash(a, "cam", 16, 16);
    RenderJobOptions b = a;
    b.render.noise_target = 1e-7f;
    EXPECT_NE(render_settings_hash(b, "cam", 16, 16), base);
    RenderJobOptions c = a;
    c.film.filter.width = std::nextafter(1.0f, 2.0f);
    EXPECT_NE(render_settings_hash(c, "cam", 16, 16), base);
    EXPECT_EQ(render_settings_hash(a, "cam", 16, 16), base);
}

}  // namespace
}  // namespace veach
