// Adaptive sampling (--noise): a pixel's budget comes from its neighbours' pilot samples only,
// so the image stays unbiased; smooth pixels stop early, noisy ones take the whole spp, and the
// pixels that stopped reach the target error; splats and checkpoints stay right.
#include "film/adaptive_sampling.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>

#include "../render/test_scenes.h"
#include "job/render_job.h"
#include "core/rng.h"
#include "film/film_checkpoint.h"

namespace veach {
namespace {

namespace fs = std::filesystem;

// Adds `n` samples to every pixel: constant `flat` in columns x < split, else uniform in
// [0, 2 noisy_mean) (per-sample standard deviation noisy_mean / sqrt(3), per channel alike).
void fill(Film& film, int n, int split, float flat, float noisy_mean, uint64_t seed) {
    for (int y = 0; y < film.height(); ++y)
        for (int x = 0; x < film.width(); ++x) {
            Rng rng = Rng::for_sample(seed, static_cast<uint64_t>(y) * film.width() + x, 0);
            for (int k = 0; k < n; ++k) {
                float v = x < split ? flat : 2.0f * noisy_mean * rng.next_float();
                film.add_sample(x, y, Rgb(v));
            }
        }
}

TEST(AdaptivePlan, SmoothPixelsGetThePilotAndNoisyOnesTheirNeed) {
    Film film(12, 6);
    const int pilot = 400;
    fill(film, pilot, 6, 2.0f, 2.0f, 3);
    const double target = 0.02;
    std::vector<uint32_t> plan = plan_adaptive_samples(film, target, pilot);
    // Uniform on [0, 4]: sigma = 4 / sqrt(12), mu = 2: n = (sigma / (target mu))^2 = 833.
    const double expected = std::pow(4.0 / std::sqrt(12.0) / (target * 2.0), 2);
    for (int y = 0; y < 6; ++y) {
        for (int x = 0; x < 12; ++x) {
            uint32_t b = plan[static_cast<size_t>(y) * 12 + x];
            if (x < 5) {
                EXPECT_EQ(b, static_cast<uint32_t>(pilot)) << x << "," << y;  // no noisy neighbour
            } else {
                // The largest neighbour need: at most ~15% above the true need with 400 samples.
                EXPECT_GT(b, 0.9 * expected) << x << "," << y;
                EXPECT_LT(b, 1.3 * expected) << x << "," << y;
            }
        }
    }
    // With a smaller pilot the budget is never below the pilot.
    Film small(4, 4);
    fill(small, 8, 4, 1.0f, 1.0f, 1);
    for (uint32_t b : plan_adaptive_samples(small, 0.5, 8)) EXPECT_GE(b, 8u);
}

// The heart of the unbiasedness argument: changing a pixel's own samples cannot change its
// budget (only its neighbours' budgets).
TEST(AdaptivePlan, APixelsBudgetIgnoresItsOwnSamples) {
    Film a(5, 5), b(5, 5);
    fill(a, 16, 0, 0.0f, 1.0f, 9);
    fill(b, 16, 0, 0.0f, 1.0f, 9);
    for (int k = 0; k < 16; ++k) b.add_sample(2, 2, Rgb(k % 2 ? 100.0f : 0.0f));  // wildly noisy centre
    std::vector<uint32_t> pa = plan_adaptive_samples(a, 0.1, 16), pb = plan_adaptive_samples(b, 0.1, 16);
    EXPECT_EQ(pa[12], pb[12]);
    EXPECT_GT(pb[11], pa[11]);  // its neighbour sees it
    // A 1x1 film has no neighbours to judge from: it never stops early.
    Film one(1, 1);
    fill(one, 4, 1, 1.0f, 1.0f, 1);
    EXPECT_EQ(plan_adaptive_samples(one, 0.1, 4)[0], UINT32_MAX);
}

// Relative error, absolute below a thousandth of white: a near-black pixel with a little noise
// gets a finite budget.
TEST(AdaptivePlan, ErrorIsRelativeDownToAThousandthOfWhite) {
    EXPECT_DOUBLE_EQ(adaptive_error_scale(4.0), 4.0);
    EXPECT_DOUBLE_EQ(adaptive_error_scale(0.25), 0.25);
    EXPECT_DOUBLE_EQ(adaptive_error_scale(0.0), 1e-3);
    Film film(3, 3);
    for (int y = 0; y < 3; ++y)
        for (int x = 0; x < 3; ++x)
            for (int k = 0; k < 16; ++k) film.add_sample(x, y, Rgb(k == 0 ? 1.6e-3f : 0.0f));
    // mu = 1e-4, sigma = 4e-4 (sample variance 2.4e-6 / 15): n = (4e-4 / (0.1 x 1e-3))^2 = 16.
    std::vector<uint32_t> plan = plan_adaptive_samples(film, 0.1, 4);
    EXPECT_GT(plan[4], 10u);
    EXPECT_LT(plan[4], 20u);
}

// Splats with a plan: the pilot's paths weigh pilot/spp, the later ones the rest, each group
// averaged over its own number of paths; with no pixel stopped that is the plain average.
TEST(AdaptivePlan, SplatsAreWeighedByPilotAndLaterPaths) {
    Film film(2, 1);
    film.add_splat(0.5f, 0.5f, Rgb(8.0f));  // pilot: 4 spp x 2 pixels of paths
    for (int x = 0; x < 2; ++x)
        for (int k = 0; k < 4; ++k) film.add_sample(x, 0, Rgb(0.0f));
    film.set_sample_plan({4, 12}, 0.1f, 4);  // pixel 0 stops at the pilot, pixel 1 goes to 12
    film.add_splat(0.5f, 0.5f, Rgb(2.0f));   // 8 later paths (pixel 1's samples 4..11)
    Image img = film.resolve(12);
    // alpha = 4/12: (1/3) 8/4 + (2/3) 2 x 2 pixels / 8 paths.
    EXPECT_NEAR(img.pixel(0, 0)[0], 8.0 / 12.0 + (2.0 / 3.0) * 0.5, 1e-6);
    EXPECT_EQ(film.planned_total(12), 16u);
    EXPECT_EQ(img.sample_count[0], 4.0f);
    // No pixel stopped: the same as one channel over all 12 x 2 paths.
    Film full(2, 1);
    full.add_splat(0.5f, 0.5f, Rgb(8.0f));
    full.set_sample_plan({20, 20}, 0.1f, 4);
    full.add_splat(0.5f, 0.5f, Rgb(2.0f));
    EXPECT_NEAR(full.resolve(12).pixel(0, 0)[0], 10.0 / 12.0, 1e-6);
}

TEST(AdaptivePlan, CheckpointKeepsThePlanAndThePilotSplats) {
    Film film(3, 2);
    fill(film, 6, 1, 0.5f, 1.0f, 2);
    film.add_splat(1.5f, 0.5f, Rgb(3.0f));
    film.set_sample_plan(plan_adaptive_samples(film, 0.2, 6), 0.2f, 6);
    film.add_splat(2.5f, 1.5f, Rgb(1.0f));
    fs::path path = fs::path(testing::TempDir()) / ("veach_adaptive_" + std::to_string(::getpid()));
    write_film_checkpoint(path.string(), film, 42, 10);
    Film back(3, 2);
    EXPECT_EQ(read_film_checkpoint(path.string(), back, 42), 10);
    fs::remove(path);
    ASSERT_TRUE(back.has_sample_plan());
    EXPECT_EQ(back.plan_target(), 0.2f);
    EXPECT_EQ(back.plan_pilot_spp(), 6);
    Image a = film.resolve(10), b = back.resolve(10);
    EXPECT_EQ(a.rgba, b.rgba);
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 3; ++x) EXPECT_EQ(film.planned_samples(x, y), back.planned_samples(x, y));
}

// Every surface radiates L = 1.25: inside a sphere of albedo 0.6 emitting 0.5 (L = Le / (1 - a))
// sit a black sphere emitting L (seen exactly: no noise) and one of albedo 0.3 emitting
// L (1 - 0.3) (a little noise). Any unbiased render has mean 1.25 in every pixel.
constexpr double k_radiance = 1.25;
Scene three_noise_levels() {
    Scene s;
    s.meshes.push_back(test::make_sphere(1.0f, Vec3(0, 0, 0), 48, 24));
    s.meshes.push_back(test::make_sphere(0.25f, Vec3(-0.3f, 0, -0.5f), 32, 16));
    s.meshes.push_back(test::make_sphere(0.25f, Vec3(0.3f, 0, -0.5f), 32, 16));
    s.materials.push_back(test::lambert(Rgb(0.6f), Rgb(0.5f)));
    s.materials.push_back(test::lambert(Rgb(0.0f), Rgb(static_cast<float>(k_radiance))));
    s.materials.push_back(test::lambert(Rgb(0.3f), Rgb(static_cast<float>(k_radiance * 0.7))));
    for (uint32_t i = 0; i < 3; ++i) {
        s.meshes[i].material = i;
        s.instances.push_back({i, Transform()});
    }
    s.cameras.push_back(test::camera_at(Vec3(0, 0, 0.3f)));
    return s;
}

RenderResult render_adaptive(const Scene& s, int size, int spp, float target, const std::string& integrator,
                             int min_spp = 8, uint64_t seed = 5) {
    RenderJobOptions o;
    o.width = o.height = size;
    o.render.spp = spp;
    o.render.integrator = integrator;
    o.render.seed = seed;
    o.render.noise_target = target;
    o.render.min_spp = min_spp;
    return render_scene(s, o);
}

// The image mean over N pixels and its standard error from the variance pass.
void mean_and_error(const Image& img, double* mean, double* error) {
    double sum = 0, var = 0;
    const size_t n = img.sample_count.size();
    for (size_t i = 0; i < n; ++i) {
        sum += (img.rgba[i * 4] + img.rgba[i * 4 + 1] + img.rgba[i * 4 + 2]) / 3.0;
        var += (img.variance[i * 3] + img.variance[i * 3 + 1] + img.variance[i * 3 + 2]) / 3.0;
    }
    *mean = sum / n;
    *error = std::sqrt(var) / n;
}

class AdaptiveRenderOf : public ::testing::TestWithParam<std::string> {};

TEST_P(AdaptiveRenderOf, IsUnbiasedAndSpendsSamplesWhereTheNoiseIs) {
    // Not divided under sanitizers (test::spp): the spp must stay well above the 16-sample pilot
    // for the budgets to mean anything, and these renders are small.
    const int size = 32, spp = 128;
    const float target = 0.03f;
    RenderResult r = render_adaptive(three_noise_levels(), size, spp, target, GetParam(), 16);
    const Image& img = r.image;
    double mean, error;
    mean_and_error(img, &mean, &error);
    // Unbiased: the exact radiance within 4 standard errors (camera-sample variance; bdpt's
    // splats add a little noise the variance pass does not count, hence the floor).
    EXPECT_NEAR(mean, k_radiance, 4.0 * error + 0.002 * k_radiance) << "standard error " << error;

    // Where the samples went: the black emitter is exact and stops at the pilot; the walls of the
    // albedo-0.6 furnace are the noisiest and take every sample.
    auto count_at = [&](double u, double v) {
        return img.sample_count[static_cast<size_t>(v * size) * size + static_cast<size_t>(u * size)];
    };
    EXPECT_EQ(count_at(0.17, 0.5), 16.0f);  // the black emitter's centre: the pilot
    double corner = 0;
    for (int y = 0; y < 6; ++y)
        for (int x = 0; x < 6; ++x) corner += img.sample_count[static_cast<size_t>(y) * size + x] / 36.0;
    EXPECT_GT(corner, 0.75 * spp);           // most wall pixels take every sample
    EXPECT_LT(r.stats.mean_spp, 0.9 * spp);  // the smooth pixels saved ~10% of the samples
    EXPECT_EQ(r.stats.spp_done, spp);
    EXPECT_EQ(r.stats.camera_samples, static_cast<uint64_t>(std::llround(r.stats.mean_spp * size * size)));
}

// Pixels that stopped short of spp with noise left (more than the pilot) reach the target:
// their RMS relative error against the exact value is at most the target (with 20% room for the
// pilot's variance estimate), over a few renders' worth of such pixels.
TEST(AdaptiveRender, StoppedPixelsReachTheTarget) {
    const float target = 0.04f;
    double sq = 0;
    size_t count = 0;
    for (uint64_t seed = 1; seed <= 2; ++seed) {
        RenderResult r = render_adaptive(three_noise_levels(), 32, 512, target, "pt", 16, seed);
        for (size_t i = 0; i < r.image.sample_count.size(); ++i) {
            float n = r.image.sample_count[i];
            if (n <= 16.0f || n >= 512.0f) continue;
            double v = (r.image.rgba[i * 4] + r.image.rgba[i * 4 + 1] + r.image.rgba[i * 4 + 2]) / 3.0;
            double rel = (v - k_radiance) / adaptive_error_scale(k_radiance);
            sq += rel * rel;
            ++count;
        }
    }
    ASSERT_GT(count, 100u) << "too few pixels stopped between the pilot and spp to judge";
    EXPECT_LT(std::sqrt(sq / count), 1.2 * target) << count << " pixels";
}

INSTANTIATE_TEST_SUITE_P(Integrators, AdaptiveRenderOf, ::testing::Values("pt", "bdpt"));

// A render checkpointed after the plan was made and resumed to a larger spp is the render never
// interrupted, bit for bit (pt); a checkpoint made at another --noise is refused.
TEST(AdaptiveRender, ResumesExactlyAndRefusesAnotherTarget) {
    Scene s = three_noise_levels();
    fs::path path = fs::path(testing::TempDir()) / ("veach_adaptive_resume_" + std::to_string(::getpid()));
    fs::remove(path);
    RenderJobOptions o;
    o.width = o.height = 16;
    o.render.integrator = "pt";
    o.render.noise_target = 0.1f;
    o.render.min_spp = 8;
    o.render.seed = 3;
    o.render.spp = 40;
    o.checkpoint.path = path.string();
    o.checkpoint.write = true;  // every pass: the last one written is at 24 spp, past the pilot
    render_scene(s, o);
    ASSERT_TRUE(fs::exists(path));
    o.checkpoint.write = false;
    o.checkpoint.resume = true;
    o.render.spp = 96;
    RenderResult resumed = render_scene(s, o);
    EXPECT_EQ(resumed.resumed_spp, 24);
    RenderJobOptions fresh = o;
    fresh.checkpoint = {};
    RenderResult whole = render_scene(s, fresh);
    EXPECT_EQ(resumed.image.rgba, whole.image.rgba);
    EXPECT_EQ(resumed.image.sample_count, whole.image.sample_count);
    // render_job's settings hash refuses it (CheckpointError); render_image itself refuses a
    // film whose plan was made for another target (std::invalid_argument) whatever the caller.
    o.render.noise_target = 0.2f;
    EXPECT_ANY_THROW(render_scene(s, o));
    RenderScene rs(s, &s.cameras[0], 16, 16);
    Film film(16, 16);
    ASSERT_EQ(read_film_checkpoint(path.string(), film, checkpoint_key(fresh, "test", 16, 16)), 24);
    ASSERT_TRUE(film.has_sample_plan());
    for (float target : {0.2f, 0.0f}) {
        RenderSettings settings = fresh.render;
        settings.noise_target = target;
        std::unique_ptr<Integrator> pt = make_integrator(settings);
        EXPECT_THROW(render_image(rs, *pt, settings, film), std::invalid_argument) << target;
    }
    fs::remove(path);
}

}  // namespace
}  // namespace veach
