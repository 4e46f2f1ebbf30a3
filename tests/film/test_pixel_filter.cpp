// Pixel filters: each is a normalised density with the profile Blender's Cycles uses, its
// sampler draws offsets with exactly that density (chi-square), and a film reconstructs a
// uniformly lit image unchanged, both from camera samples and from light-tracing splats.
#include "film/pixel_filter.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/rng.h"
#include "film/film.h"
#include "materials/chi_square.h"

namespace veach {
namespace {

struct FilterCase {
    FilterType type;
    float width;
};

const FilterCase k_cases[] = {
    {FilterType::box, 1.0f},
    {FilterType::box, 2.0f},
    {FilterType::gaussian, 1.5f},
    {FilterType::gaussian, 0.7f},
    {FilterType::blackman_harris, 1.5f},
    {FilterType::blackman_harris, 3.0f},
};

std::string label(const FilterCase& c) { return std::string(filter_name(c.type)) + " " + std::to_string(c.width); }

// Integral of pdf() over the support by a fine midpoint rule: a density integrates to 1.
TEST(PixelFilter, PdfIntegratesToOne) {
    for (const FilterCase& c : k_cases) {
        PixelFilter f({c.type, c.width});
        const int n = 200000;
        const double r = f.radius(), h = 2.0 * r / n;
        double sum = 0.0;
        for (int i = 0; i < n; ++i) sum += f.pdf(static_cast<float>(-r + (i + 0.5) * h)) * h;
        EXPECT_NEAR(sum, 1.0, 1e-4) << label(c);
        EXPECT_EQ(f.pdf(static_cast<float>(r * 1.01 + 1e-3)), 0.0f) << label(c) << ": support ends at the radius";
    }
}

// Blender's supports: the Gaussian spans 3 widths (6 sigma), Blackman-Harris 2, the box 1; the
// tabulated density follows the continuous profile it was built from within 0.5%.
TEST(PixelFilter, FollowsCyclesProfiles) {
    EXPECT_FLOAT_EQ(PixelFilter({FilterType::box, 1.0f}).radius(), 0.5f);
    EXPECT_FLOAT_EQ(PixelFilter({FilterType::gaussian, 1.5f}).radius(), 2.25f);
    EXPECT_FLOAT_EQ(PixelFilter({FilterType::blackman_harris, 1.5f}).radius(), 1.5f);
    // Blackman-Harris: 1 at the centre (sum of the coefficients with alternating cos = +-1),
    // 6e-5 at the ends (a0 - a1 + a2 - a3).
    EXPECT_NEAR(PixelFilter::profile(FilterType::blackman_harris, 1.5f, 0.0), 1.0, 1e-12);
    EXPECT_NEAR(PixelFilter::profile(FilterType::blackman_harris, 1.5f, 1.5), 0.00006, 1e-6);
    // Gaussian: sigma = width / 4, so exp(-1/2) one sigma out.
    EXPECT_NEAR(PixelFilter::profile(FilterType::gaussian, 2.0f, 0.5), std::exp(-0.5), 1e-12);
    for (const FilterCase& c : k_cases) {
        if (c.type == FilterType::box) continue;
        PixelFilter f({c.type, c.width});
        double norm = 0.0;
        const int n = 20000;
        const double r = f.radius(), h = 2.0 * r / n;
        for (int i = 0; i < n; ++i) norm += PixelFilter::profile(c.type, c.width, -r + (i + 0.5) * h) * h;
        for (double t : {-0.8, -0.4, 0.0, 0.25, 0.6}) {
            const double x = t * r;
            EXPECT_NEAR(f.pdf(static_cast<float>(x)), PixelFilter::profile(c.type, c.width, x) / norm,
                        5e-3 * PixelFilter::profile(c.type, c.width, 0.0) / norm)
                << label(c) << " at " << x;
        }
    }
}

// Chi-square goodness of fit of sample() against the continuous profile (not merely against its
// own table): 40 equal-width bins, expected counts from integrating the profile.
TEST(PixelFilter, SamplingMatchesTheDensityChiSquare) {
    const int n_samples = 200000, bins = 40;
    const double alpha = 0.01 / std::size(k_cases);  // Bonferroni over the cases
    for (const FilterCase& c : k_cases) {
        PixelFilter f({c.type, c.width});
        const double r = f.radius(), bw = 2.0 * r / bins;
        std::vector<double> observed(bins, 0.0), expected(bins, 0.0);
        Rng rng(7, 11);
        for (int i = 0; i < n_samples; ++i) {
            const float x = f.sample(rng.next_float());
            ASSERT_LE(std::fabs(x), r * (1 + 1e-6)) << label(c);
            int b = std::clamp(static_cast<int>((x + r) / bw), 0, bins - 1);
            observed[b] += 1;
        }
        double total = 0.0;
        for (int b = 0; b < bins; ++b) {
            const int sub = 200;
            for (int k = 0; k < sub; ++k)
                expected[b] += PixelFilter::profile(c.type, c.width, -r + (b + (k + 0.5) / sub) * bw);
            total += expected[b];
        }
        // Pool bins with few expected samples (the Gaussian's and Blackman-Harris' tails).
        double chi2 = 0.0, pooled_o = 0.0, pooled_e = 0.0;
        int dof = -1;
        for (int b = 0; b < bins; ++b) {
            const double e = expected[b] / total * n_samples;
            if (e < 20.0) {
                pooled_o += observed[b];
                pooled_e += e;
                continue;
            }
            chi2 += (observed[b] - e) * (observed[b] - e) / e;
            ++dof;
        }
        if (pooled_e > 0.0) {
            chi2 += (pooled_o - pooled_e) * (pooled_o - pooled_e) / std::max(pooled_e, 1.0);
            ++dof;
        }
        const double p = test::gamma_q(0.5 * dof, 0.5 * chi2);
        EXPECT_GT(p, alpha) << label(c) << ": chi2 " << chi2 << " with " << dof << " dof";
    }
}

// The default box: a sample for pixel (x, y) lands inside that pixel at x + u exactly, as the
// integrators placed samples before filters existed (so box renders are unchanged).
TEST(PixelFilter, UnitBoxPlacesSamplesInsideTheirPixel) {
    Film film(8, 8);
    Rng a(3, 5), b(3, 5);
    for (int i = 0; i < 1000; ++i) {
        const float u1 = b.next_float(), u2 = b.next_float();
        auto [fx, fy] = film.sample_position(5, 2, Vec2{a.next_float(), a.next_float()});
        ASSERT_EQ(fx, 5 + u1);
        ASSERT_EQ(fy, 2 + u2);
    }
}

// A uniformly lit scene stays uniform whatever the filter: every camera sample carries the
// same radiance L, so each pixel's mean is L exactly.
TEST(PixelFilter, UniformImageUnchangedByCameraSamples) {
    for (const FilterCase& c : k_cases) {
        FilmSettings s;
        s.filter = {c.type, c.width};
        Film film(12, 10, s);
        const Rgb l(0.25f, 0.5f, 2.0f);
        for (int y = 0; y < film.height(); ++y)
            for (int x = 0; x < film.width(); ++x)
                for (uint32_t k = 0; k < 4; ++k) {
                    Rng rng = Rng::for_sample(1, static_cast<uint64_t>(y) * 12 + x, k);
                    film.sample_position(x, y, Vec2{rng.next_float(), rng.next_float()});
                    film.add_sample(x, y, l);
                }
        Image img = film.resolve(0);
        for (int y = 0; y < img.height; ++y)
            for (int x = 0; x < img.width; ++x) {
                ASSERT_FLOAT_EQ(img.pixel(x, y)[0], 0.25f) << label(c);
                ASSERT_FLOAT_EQ(img.pixel(x, y)[2], 2.0f) << label(c);
                ASSERT_FLOAT_EQ(img.variance[(static_cast<size_t>(y) * 12 + x) * 3], 0.0f) << label(c);
            }
    }
}

// Light-tracing splats: radiance L arriving uniformly over the film (a fine grid of splats, each
// worth L times its cell's area) must give L in every pixel far enough from the border that its
// whole support lies on the film: the splat weights are the same normalised filter.
TEST(PixelFilter, UniformSplatsGiveTheSameImage) {
    for (const FilterCase& c : k_cases) {
        FilmSettings s;
        s.filter = {c.type, c.width};
        const int w = 16, h = 14, per_pixel = 24;
        Film film(w, h, s);
        const float cell = 1.0f / per_pixel;
        const float l = 0.75f;
        for (int j = 0; j < h * per_pixel; ++j)
            for (int i = 0; i < w * per_pixel; ++i)
                film.add_splat((i + 0.5f) * cell, (j + 0.5f) * cell, Rgb(l * cell * cell));
        EXPECT_TRUE(film.has_splats());
        Image img = film.resolve(1.0);
        const int margin = static_cast<int>(std::ceil(film.filter().radius()));
        for (int y = margin; y < h - margin; ++y)
            for (int x = margin; x < w - margin; ++x)
                ASSERT_NEAR(img.pixel(x, y)[1], l, 2e-3 * l) << label(c) << " pixel " << x << "," << y;
    }
}

TEST(PixelFilter, NamesAndBadWidths) {
    FilterType t;
    EXPECT_TRUE(parse_filter_name("blackman-harris", &t));
    EXPECT_EQ(t, FilterType::blackman_harris);
    EXPECT_TRUE(parse_filter_name("gaussian", &t));
    EXPECT_FALSE(parse_filter_name("mitchell", &t));
    // The listed names are the ones parsed, each naming its own filter.
    ASSERT_EQ(filter_names(), std::vector<std::string>({"box", "gaussian", "blackman-harris"}));
    for (const std::string& n : filter_names()) {
        ASSERT_TRUE(parse_filter_name(n, &t)) << n;
        EXPECT_EQ(filter_name(t), n);
    }
    EXPECT_THROW(PixelFilter({FilterType::gaussian, 0.0f}), std::invalid_argument);
    EXPECT_THROW(PixelFilter({FilterType::box, -1.0f}), std::invalid_argument);
}

}  // namespace
}  // namespace veach
