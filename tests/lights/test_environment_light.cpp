// The environment light: Blender's equirectangular convention, rotation about +Y, and its
// importance sampling against its own density (chi-square in the map's (u, v) parameterisation,
// where the density is piecewise constant and cell integrals are exact).
#include <gtest/gtest.h>

#include <cmath>

#include "../materials/chi_square.h"
#include "core/rng.h"
#include "lights/environment_light.h"

namespace veach {
namespace {

// A w x h map of `base` radiance with one texel of `bright`.
Environment map_with_texel(int w, int h, int bx, int by, float bright, float base = 0.0f) {
    Environment env;
    env.enabled = true;
    env.width = w;
    env.height = h;
    env.texels.assign(static_cast<size_t>(w) * h * 3, base);
    for (int c = 0; c < 3; ++c) env.texels[(static_cast<size_t>(by) * w + bx) * 3 + c] = bright;
    return env;
}

TEST(EnvironmentLight, UniformColourIsTheSameEverywhereAndSampledUniformly) {
    Environment env;
    env.enabled = true;
    env.color = Rgb(0.5f, 1.0f, 2.0f);
    env.strength = 2;
    EnvironmentLight light(env);
    Rgb l = light.radiance(normalize(Vec3(0.3f, -0.2f, 0.9f)));
    EXPECT_FLOAT_EQ(l.r, 1.0f);
    EXPECT_FLOAT_EQ(l.b, 4.0f);
    EXPECT_FLOAT_EQ(light.pdf_w(Vec3(0, 1, 0)), k_inv_four_pi);
    EXPECT_NEAR(light.radiance_integral(), 4.0 * k_pi * (7.0 / 3.0), 1e-4);
}

// Cycles' direction_to_equirectangular with Blender's Z up = glTF's Y up: the image centre looks
// along +X, the top row looks up. A Mapping node's Z rotation of 90 degrees moves what was at +X
// to +Z (glTF), i.e. Blender's -Y.
TEST(EnvironmentLight, FollowsBlendersEquirectangularMappingAndRotation) {
    // 64 x 32 map, bright texels around the image centre (u = 0.5, v = 0.5).
    Environment env = map_with_texel(64, 32, 31, 15, 1.0f);
    for (int y = 15; y <= 16; ++y)
        for (int x = 31; x <= 32; ++x)
            for (int c = 0; c < 3; ++c) env.texels[(static_cast<size_t>(y) * 64 + x) * 3 + c] = 1.0f;
    EnvironmentLight light(env);
    EXPECT_NEAR(light.radiance(Vec3(1, 0, 0)).g, 1.0f, 1e-5);
    EXPECT_EQ(light.radiance(Vec3(-1, 0, 0)).g, 0.0f);
    EXPECT_EQ(light.radiance(Vec3(0, 0, 1)).g, 0.0f);
    env.rotation = k_pi / 2;
    EnvironmentLight rotated(env);
    EXPECT_NEAR(rotated.radiance(Vec3(0, 0, 1)).g, 1.0f, 1e-5);
    EXPECT_EQ(rotated.radiance(Vec3(1, 0, 0)).g, 0.0f);

    // The top row is what one sees looking up.
    Environment sky = map_with_texel(8, 4, 0, 0, 0.0f, 0.0f);
    for (int x = 0; x < 8; ++x) sky.texels[x * 3 + 1] = 3.0f;
    EnvironmentLight up(sky);
    EXPECT_NEAR(up.radiance(Vec3(0, 1, 0)).g, 3.0f, 1e-5);
    EXPECT_EQ(up.radiance(Vec3(0, -1, 0)).g, 0.0f);
}

TEST(EnvironmentLight, DensityIntegratesToOneAndFollowsRadiance) {
    Environment env = map_with_texel(16, 8, 5, 2, 40.0f, 0.5f);
    env.rotation = 0.7f;
    EnvironmentLight light(env);
    // Integrate pdf_w over the sphere in (theta, phi), d omega = sin(theta) d theta d phi: the
    // density's 1 / sin(theta) near the poles stays bounded in this measure.
    const int nt = 400, nphi = 800;
    double integral = 0, radiance = 0;
    for (int i = 0; i < nt; ++i)
        for (int j = 0; j < nphi; ++j) {
            double theta = k_pi * (i + 0.5) / nt, phi = 2 * k_pi * (j + 0.5) / nphi;
            double st = std::sin(theta);
            Vec3 w(static_cast<float>(st * std::cos(phi)), static_cast<float>(std::cos(theta)),
                   static_cast<float>(st * std::sin(phi)));
            integral += light.pdf_w(w) * st;
            radiance += light.radiance(w).average() * st;
        }
    double d = k_pi / nt * 2 * k_pi / nphi;
    EXPECT_NEAR(integral * d, 1.0, 2e-3);
    // radiance_integral (for light selection) is the integral of average radiance.
    EXPECT_NEAR(light.radiance_integral(), radiance * d, 0.02 * radiance * d);
}

// Chi-square of sample() against pdf_w(), 10^6 samples binned on a 64 x 32 grid in the map's
// (u, v), which refines the 16 x 8 map so that pdf_w sin(theta) is constant in each bin.
TEST(EnvironmentLight, SamplingMatchesItsDensityChiSquare) {
    Environment env = map_with_texel(16, 8, 11, 6, 60.0f, 0.2f);
    for (int x = 0; x < 16; ++x)  // a horizon gradient and a dark texel
        for (int c = 0; c < 3; ++c) env.texels[(3 * 16 + x) * 3 + c] += 0.1f * x;
    for (int c = 0; c < 3; ++c) env.texels[(1 * 16 + 4) * 3 + c] = 0.0f;
    EnvironmentLight light(env);
    const int nu = 64, nv = 32, n = 1000000;
    std::vector<double> observed(nu * nv, 0.0), expected(nu * nv, 0.0);
    Rng rng(7, 11);
    int mismatched = 0;
    for (int i = 0; i < n; ++i) {
        float pdf;
        Vec3 w = light.sample(rng.next_float(), rng.next_float(), &pdf);
        ASSERT_GT(pdf, 0.0f);
        // The sampled cell's density; a direction on a cell boundary may round into the neighbour.
        if (std::fabs(pdf - light.pdf_w(w)) > 1e-3f * pdf) ++mismatched;
        float u = 0.5f + std::atan2(w.z, w.x) * k_inv_two_pi, v = std::acos(clamp(w.y, -1.0f, 1.0f)) * k_inv_pi;
        int bu = std::clamp(static_cast<int>(u * nu), 0, nu - 1), bv = std::clamp(static_cast<int>(v * nv), 0, nv - 1);
        observed[bv * nu + bu] += 1;
    }
    for (int bv = 0; bv < nv; ++bv)
        for (int bu = 0; bu < nu; ++bu) {
            // pdf_w = pdf_uv / (2 pi^2 sin theta), pdf_uv constant over the bin.
            float theta = k_pi * (bv + 0.5f) / nv, phi = 2 * k_pi * ((bu + 0.5f) / nu - 0.5f);
            Vec3 w(std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi));
            double pdf_uv = light.pdf_w(w) * 2.0 * k_pi * k_pi * std::sin(theta);
            expected[bv * nu + bu] = pdf_uv / (nu * nv) * n;
        }
    EXPECT_LT(mismatched, n / 1000);
    double stat = 0, pool_obs = 0, pool_exp = 0;
    int used = 0;
    for (int i = 0; i < nu * nv; ++i) {
        if (expected[i] < 5) {
            pool_obs += observed[i];
            pool_exp += expected[i];
            continue;
        }
        stat += (observed[i] - expected[i]) * (observed[i] - expected[i]) / expected[i];
        ++used;
    }
    if (pool_exp > 0) {
        stat += (pool_obs - pool_exp) * (pool_obs - pool_exp) / pool_exp;
        ++used;
    }
    double p = test::gamma_q(0.5 * (used - 1), 0.5 * stat);
    EXPECT_GT(p, 0.01) << "chi2 " << stat << " dof " << used - 1;
}

}  // namespace
}  // namespace veach
