// Warping functions produce their stated densities; discrete distributions their weights.
#include <gtest/gtest.h>

#include "../materials/chi_square.h"
#include "core/sampling.h"

namespace veach {
namespace {

TEST(Sampling, CosineHemisphereMatchesItsPdf) {
    auto res = test::chi_square_directions(
        [](Rng& rng, Vec3* d) { *d = sample_cosine_hemisphere(rng.next_float(), rng.next_float()); return true; },
        [](const Vec3& d) { return static_cast<double>(cosine_hemisphere_pdf_w(d.z)); });
    EXPECT_GT(res.p_value, 0.01 / 3);
}

TEST(Sampling, UniformSphereMatchesItsPdf) {
    auto res = test::chi_square_directions(
        [](Rng& rng, Vec3* d) { *d = sample_uniform_sphere(rng.next_float(), rng.next_float()); return true; },
        [](const Vec3&) { return static_cast<double>(k_inv_four_pi); });
    EXPECT_GT(res.p_value, 0.01 / 3);
}

TEST(Sampling, UniformConeMatchesItsPdf) {
    const float cos_max = 0.8f;
    auto res = test::chi_square_directions(
        [&](Rng& rng, Vec3* d) { *d = sample_uniform_cone(rng.next_float(), rng.next_float(), cos_max); return true; },
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
