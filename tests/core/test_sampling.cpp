// Warping functions produce their stated densities; discrete distributions their weights.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "../materials/chi_square.h"
#include "core/sampling.h"

namespace veach {
namespace {

TEST(Sampling, CosineHemisphereMatchesItsPdf) {
    auto res = test::chi_square_directions(
        [](Rng& rng, Vec3* d) {
            *d = sample_cosine_hemisphere(rng.next_float(), rng.next_float());
            return true;
        },
        [](const Vec3& d) { return static_cast<double>(cosine_hemisphere_pdf_w(d.z)); });
    EXPECT_GT(res.p_value, 0.01 / 3);
}

// The concentric map's polynomial cos/sin give the map of Shirley & Chiu 1997 (written here
// with std::cos / std::sin) to float precision, and points on the unit circle for u on the
// square's edge.
TEST(Sampling, ConcentricDiskIsShirleyChiusMap) {
    const int n = 512;
    double worst = 0;
    for (int i = 0; i <= n; ++i)
        for (int j = 0; j <= n; ++j) {
            float u1 = static_cast<float>(i) / n, u2 = static_cast<float>(j) / n;
            float a = 2 * u1 - 1, b = 2 * u2 - 1;
            double r, phi;
            if (a == 0 && b == 0)
                r = phi = 0;
            else if (std::fabs(a) > std::fabs(b))
                r = a, phi = (M_PI / 4) * (static_cast<double>(b) / a);
            else
                r = b, phi = M_PI / 2 - (M_PI / 4) * (static_cast<double>(a) / b);
            Vec2 d = sample_concentric_disk(u1, u2);
            worst = std::max({worst, std::fabs(d.x - r * std::cos(phi)), std::fabs(d.y - r * std::sin(phi))});
            if (i == 0 || j == 0 || i == n || j == n) {
                EXPECT_NEAR(d.x * d.x + d.y * d.y, 1.0f, 1e-6f);
            }
        }
    EXPECT_LT(worst, 4e-7);
}

TEST(Sampling, UniformSphereMatchesItsPdf) {
    auto res = test::chi_square_directions(
        [](Rng& rng, Vec3* d) {
            *d = sample_uniform_sphere(rng.next_float(), rng.next_float());
            return true;
        },
        [](const Vec3&) { return static_cast<double>(k_inv_four_pi); });
    EXPECT_GT(res.p_value, 0.01 / 3);
}

TEST(Sampling, UniformConeMatchesItsPdf) {
    const float cos_max = 0.8f;
    auto res = test::chi_square_directions(
        [&](Rng& rng, Vec3* d) {
            *d = sample_uniform_cone(rng.next_float(), rng.next_float(), cos_max);
            return true;
        },
        [&](const Vec3& d) { return d.z >= cos_max ? 1.0 / (2 * k_pi * (1 - cos_max)) : 0.0; });
    EXPECT_GT(res.p_value, 0.01 / 3);
}

TEST(Sampling, UniformTriangleHasUniformBarycentrics) {
    Rng rng(1, 2);
    double m1 = 0, m2 = 0;
    const int n = 200000;
    for (int i = 0; i < n; ++i) {
        Vec2 b = sample_uniform_triangle(rng.next_float(), rng.next_float());
        ASSERT_GE(b.x, 0.0f);
        ASSERT_GE(b.y, 0.0f);
        ASSERT_LE(b.x + b.y, 1.0f + 1e-6f);
        m1 += b.x;
        m2 += b.y;
    }
    // Uniform over the triangle: each barycentric has mean 1/3 (standard error ~0.0005).
    EXPECT_NEAR(m1 / n, 1.0 / 3.0, 0.003);
    EXPECT_NEAR(m2 / n, 1.0 / 3.0, 0.003);
}

TEST(Sampling, Distribution1DFollowsWeightsAndSkipsZeros) {
    Distribution1D d({1.0f, 0.0f, 3.0f, 0.0f});
    EXPECT_FLOAT_EQ(d.pmf(0), 0.25f);
    EXPECT_FLOAT_EQ(d.pmf(1), 0.0f);
    EXPECT_FLOAT_EQ(d.pmf(2), 0.75f);
    Rng rng(3, 4);
    int counts[4] = {0, 0, 0, 0};
    for (int i = 0; i < 100000; ++i) {
        float pmf;
        counts[d.sample(rng.next_float(), &pmf)]++;
    }
    EXPECT_EQ(counts[1], 0);
    EXPECT_EQ(counts[3], 0);
    EXPECT_NEAR(counts[2] / 100000.0, 0.75, 0.01);
}

}  // namespace
}  // namespace veach
