// The glTF BSDF obeys what the BRDF lecture demands of any BRDF: reciprocity and energy
// conservation (and, with multiple-scattering compensation, loses almost nothing to the GGX
// single-scattering approximation); its sampling routine draws directions with exactly the
// density it reports. Transmission follows Veach's rule for refraction: radiance scales by
// 1/eta^2 across the interface, flux (importance) does not.
#include <gtest/gtest.h>

#include <algorithm>

#include "chi_square.h"
#include "materials/ggx_energy.h"
#include "materials/gltf_bsdf.h"
#include "materials/microfacet_ggx.h"

namespace veach {
namespace {

ShadingInputs inputs(Rgb base, float metallic, float roughness, float specular = 1.0f, float ior = 1.5f,
                     float transmission = 0.0f) {
    ShadingInputs in;
    in.base_color = base;
    in.metallic = metallic;
    in.alpha = std::max(roughness * roughness, k_min_ggx_alpha);
    float r = (ior - 1) / (ior + 1);
    in.dielectric_f0 = Rgb(r * r * specular);
    in.dielectric_f90 = specular * std::min(1.0f, 50.0f * r * r);
    in.transmission = transmission;
    in.ior = ior;
    return in;
}

Vec3 direction(float theta, float phi) {
    return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

// Directional albedo: the integral of f |cos| over the sphere, by importance sampling, with its
// standard error.
Rgb albedo(const GltfBsdf& bsdf, const Vec3& wo, int n, TransportMode mode = TransportMode::Radiance,
           float* std_error = nullptr) {
    Rng rng(99, 1);
    Rgb sum(0.0f);
    double sum2 = 0;
    for (int i = 0; i < n; ++i) {
        BsdfSample bs;
        if (!bsdf.sample(wo, rng.next_float(), rng.next_float(), rng.next_float(), &bs, mode)) continue;
        sum += bs.weight;
        sum2 += static_cast<double>(bs.weight.max()) * bs.weight.max();
    }
    Rgb mean = sum / static_cast<float>(n);
    if (std_error) *std_error = static_cast<float>(std::sqrt(std::max(0.0, sum2 / n - mean.max() * mean.max()) / n));
    return mean;
}

TEST(GltfMaterial, NoSpecularLayerIsExactlyLambert) {
    // Blender's Specular 0 exports specularColorFactor 0: F0 = 0, and F90 follows it to 0.
    for (float roughness : {0.2f, 1.0f}) {
        GltfBsdf bsdf(inputs(Rgb(0.7f, 0.5f, 0.2f), 0, roughness, 0.0f));
        for (float t : {0.0f, 0.7f, 1.5f}) {
            Vec3 wo = direction(0.3f, 0.2f), wi = direction(t, 2.0f);
            Rgb f = bsdf.eval(wo, wi);
            EXPECT_EQ(f.r, 0.7f * k_inv_pi);
            EXPECT_EQ(f.g, 0.5f * k_inv_pi);
            EXPECT_EQ(f.b, 0.2f * k_inv_pi);
            EXPECT_NEAR(bsdf.pdf_w(wo, wi), wi.z * k_inv_pi, 1e-6f);
        }
    }
}

// E(mu) of the single-scattering lobe: 1 for a mirror, falling with roughness and at grazing.
TEST(GgxEnergy, TablesMatchKnownLimits) {
    EXPECT_NEAR(ggx_albedo(1.0f, k_min_ggx_alpha).e, 1.0f, 2e-3f);
    EXPECT_NEAR(ggx_average_albedo(k_min_ggx_alpha).e, 1.0f, 5e-3f);
    // A smooth mirror's Schlick weight is (1 - mu)^5 exactly.
    EXPECT_NEAR(ggx_albedo(0.5f, k_min_ggx_alpha).e_w, 1.0f / 32.0f, 2e-3f);
    float prev = 1.0f;
    for (float r : {0.2f, 0.5f, 0.8f, 1.0f}) {
        float e = ggx_average_albedo(r * r).e;
        EXPECT_LT(e, prev + 1e-4f) << "roughness " << r;
        prev = e;
    }
    // At roughness 1 single scattering loses a large fraction (Kulla & Conty 2017, fig. 2).
    EXPECT_LT(ggx_average_albedo(1.0f).e, 0.85f);
    EXPECT_GT(ggx_average_albedo(1.0f).e, 0.4f);
}

// A white metal is a perfect reflector: with multiple scattering it reflects >= 98% everywhere.
TEST(GltfMaterial, WhiteMetalFurnace) {
    for (float roughness : {0.0f, 0.1f, 0.3f, 0.5f, 0.7f, 0.85f, 1.0f})
        for (float theta : {0.0f, 0.6f, 1.1f, 1.4f, 1.53f}) {
            GltfBsdf bsdf(inputs(Rgb(1.0f), 1.0f, roughness));
            float se = 0;
            Rgb a = albedo(bsdf, direction(theta, 0.3f), 40000, TransportMode::Radiance, &se);
            EXPECT_GE(std::min({a.r, a.g, a.b}), 0.98f) << "roughness " << roughness << " theta " << theta;
            EXPECT_LE(a.max(), 1.0f + 4 * se + 0.005f) << "roughness " << roughness << " theta " << theta;
        }
}

// No material reflects more than it receives (white base, so the only limit is energy).
TEST(GltfMaterial, FurnaceGridNeverGainsEnergy) {
    int cases = 0;
    for (float roughness : {0.0f, 0.2f, 0.5f, 1.0f})
        for (float metallic : {0.0f, 0.5f, 1.0f})
            for (float ior : {1.1f, 1.5f, 2.5f})
                for (float specular : {0.0f, 0.5f, 1.0f})
                    for (float theta : {0.2f, 1.0f, 1.45f}) {
                        GltfBsdf bsdf(inputs(Rgb(1.0f), metallic, roughness, specular, ior));
                        float se = 0;
                        Rgb a = albedo(bsdf, direction(theta, 1.0f), 20000, TransportMode::Radiance, &se);
                        EXPECT_LE(a.max(), 1.0f + 4 * se + 0.005f) << "r " << roughness << " m " << metallic << " ior "
                                                                   << ior << " s " << specular << " theta " << theta;
                        // A white, non-absorbing layer stack keeps nearly all of it, too.
                        EXPECT_GE(std::min({a.r, a.g, a.b}), 0.97f) << "r " << roughness << " m " << metallic << " ior "
                                                                    << ior << " s " << specular << " theta " << theta;
                        ++cases;
                    }
    EXPECT_EQ(cases, 324);
}

ShadingInputs layered(ShadingInputs in, float clearcoat, float clearcoat_roughness, Rgb sheen, float sheen_roughness) {
    in.clearcoat = clearcoat;
    in.clearcoat_alpha = std::max(clearcoat_roughness * clearcoat_roughness, k_min_ggx_alpha);
    in.sheen_color = sheen;
    in.sheen_roughness = sheen_roughness;
    return in;
}

// The clearcoat and sheen layers (KHR_materials_clearcoat, KHR_materials_sheen) over any
// material never create energy; a white coat over a white metal loses little.
TEST(GltfMaterial, FurnaceGridWithClearcoatAndSheen) {
    for (float roughness : {0.0f, 0.5f, 1.0f})
        for (float metallic : {0.0f, 1.0f})
            for (float clearcoat : {0.0f, 0.5f, 1.0f})
                for (float cc_roughness : {0.0f, 0.3f, 1.0f})
                    for (float sheen : {0.0f, 1.0f})
                        for (float sheen_roughness : {0.3f, 1.0f})
                            for (float theta : {0.3f, 1.3f}) {
                                GltfBsdf bsdf(layered(inputs(Rgb(1.0f), metallic, roughness), clearcoat, cc_roughness,
                                                      Rgb(sheen), sheen_roughness));
                                float se = 0;
                                Rgb a = albedo(bsdf, direction(theta, 1.0f), 10000, TransportMode::Radiance, &se);
                                EXPECT_LE(a.max(), 1.0f + 4 * se + 0.005f)
                                    << "r " << roughness << " m " << metallic << " cc " << clearcoat << "/"
                                    << cc_roughness << " sheen " << sheen << "/" << sheen_roughness << " theta "
                                    << theta;
                                EXPECT_GT(a.max(), 0.6f);
                            }
}

TEST(GltfMaterial, Reciprocity) {
    Rng rng(5, 5);
    for (float metallic : {0.0f, 0.5f, 1.0f})
        for (float roughness : {0.05f, 0.3f, 0.7f, 1.0f})
            for (float specular : {0.3f, 1.0f})
                for (float transmission : {0.0f, 0.5f}) {
                    GltfBsdf bsdf(layered(
                        inputs(Rgb(0.8f, 0.4f, 0.3f), metallic, roughness, specular, 1.45f, transmission),
                        specular < 1.0f ? 0.7f : 0.0f, roughness, Rgb(0.9f, 0.5f, 0.2f) * transmission, roughness));
                    for (int i = 0; i < 100; ++i) {
                        Vec3 a = direction(rng.next_float() * 1.55f, rng.next_float() * 6.28f);
                        Vec3 b = direction(rng.next_float() * 1.55f, rng.next_float() * 6.28f);
                        Rgb fab = bsdf.eval(a, b), fba = bsdf.eval(b, a);
                        EXPECT_NEAR(fab.r, fba.r, 1e-5f * std::max(1.0f, fab.r));
                        EXPECT_NEAR(fab.g, fba.g, 1e-5f * std::max(1.0f, fab.g));
                        EXPECT_NEAR(fab.b, fba.b, 1e-5f * std::max(1.0f, fab.b));
                    }
                }
}

class GltfSamplingChiSquare : public ::testing::TestWithParam<std::tuple<float, float, float, float, float>> {};

// metallic, roughness, transmission, eta (relative index below), theta of wo (> pi/2: below).
// Metallic 2 and 3 stand for a dielectric with a clearcoat (roughness 0.3) or a sheen; 4 and 5
// for a dielectric and a rough glass under a clearcoat with its own, tilted normal; 6 for a thin
// glass wall (transmission the mirrored reflection lobe).
constexpr int k_chi_square_configurations = 12 + 12 + 2 + 4 + 4 + 4;

// A coat normal tilted by `angle` from the base's shading normal (local frame).
Vec3 tilted_coat_normal(float angle) { return direction(angle, 2.0f); }

TEST_P(GltfSamplingChiSquare, SampledDirectionsFollowPdf) {
    auto [metallic, roughness, transmission, eta, theta] = GetParam();
    ShadingInputs in = inputs(Rgb(0.6f, 0.5f, 0.4f), std::min(metallic, 1.0f), roughness, 1.0f, 1.5f, transmission);
    if (metallic == 2.0f) in = layered(inputs(Rgb(0.6f, 0.5f, 0.4f), 0.0f, roughness), 0.8f, 0.3f, Rgb(0.0f), 0.0f);
    if (metallic == 3.0f) in = layered(inputs(Rgb(0.6f, 0.5f, 0.4f), 0.0f, roughness), 0.0f, 0.0f, Rgb(0.8f), 0.5f);
    if (metallic == 4.0f) in = layered(inputs(Rgb(0.6f, 0.5f, 0.4f), 0.0f, roughness), 0.8f, 0.3f, Rgb(0.0f), 0.0f);
    if (metallic == 5.0f)
        in = layered(inputs(Rgb(0.6f, 0.5f, 0.4f), 0.0f, roughness, 1.0f, 1.5f, 1.0f), 0.8f, 0.4f, Rgb(0.0f), 0.0f);
    if (metallic == 6.0f) {
        in = inputs(Rgb(0.6f, 0.5f, 0.4f), 0.0f, roughness, 1.0f, 1.5f, 1.0f);
        in.thin_walled = true;
    }
    GltfBsdf bsdf(in, eta);
    if (metallic == 4.0f || metallic == 5.0f) bsdf.set_coat_normal(tilted_coat_normal(0.5f));
    Vec3 wo = direction(theta, 0.7f);
    auto res = test::chi_square_directions(
        [&](Rng& rng, Vec3* d) {
            BsdfSample bs;
            bool ok = bsdf.sample(wo, rng.next_float(), rng.next_float(), rng.next_float(), &bs);
            *d = bs.wi;
            return ok;
        },
        [&](const Vec3& d) { return static_cast<double>(bsdf.pdf_w(wo, d)); });
    EXPECT_GT(res.p_value, 0.01 / k_chi_square_configurations) << "chi2 " << res.statistic << " dof " << res.dof;
    EXPECT_LT(res.missing_mass, 0.01);
}

INSTANTIATE_TEST_SUITE_P(Reflection, GltfSamplingChiSquare,
                         ::testing::Combine(::testing::Values(0.0f, 1.0f), ::testing::Values(0.2f, 0.5f, 1.0f),
                                            ::testing::Values(0.0f), ::testing::Values(1.5f),
                                            ::testing::Values(0.3f, 1.2f)));
// Rough refraction entering (eta 1.5, wo above) and leaving (wo below the surface). Narrower
// lobes than roughness 0.3, or refracted lobes near the pole, fall inside single cells of the
// test's grid (its 6x6 midpoint rule cannot integrate them).
INSTANTIATE_TEST_SUITE_P(Transmission, GltfSamplingChiSquare,
                         ::testing::Combine(::testing::Values(0.0f), ::testing::Values(0.3f, 0.5f, 1.0f),
                                            ::testing::Values(1.0f), ::testing::Values(1.5f),
                                            ::testing::Values(0.7f, 1.2f, 2.0f, 2.8f)));
INSTANTIATE_TEST_SUITE_P(Layers, GltfSamplingChiSquare,
                         ::testing::Combine(::testing::Values(2.0f, 3.0f), ::testing::Values(0.6f),
                                            ::testing::Values(0.0f), ::testing::Values(1.5f),
                                            ::testing::Values(0.4f, 1.2f)));
INSTANTIATE_TEST_SUITE_P(TiltedCoat, GltfSamplingChiSquare,
                         ::testing::Combine(::testing::Values(4.0f), ::testing::Values(0.6f), ::testing::Values(0.0f),
                                            ::testing::Values(1.5f), ::testing::Values(0.4f, 1.2f)));
INSTANTIATE_TEST_SUITE_P(TiltedCoatGlass, GltfSamplingChiSquare,
                         ::testing::Combine(::testing::Values(5.0f), ::testing::Values(0.5f), ::testing::Values(1.0f),
                                            ::testing::Values(1.5f), ::testing::Values(0.7f, 2.5f)));
INSTANTIATE_TEST_SUITE_P(ThinWall, GltfSamplingChiSquare,
                         ::testing::Combine(::testing::Values(6.0f), ::testing::Values(0.3f, 0.6f), ::testing::Values(1.0f),
                                            ::testing::Values(1.5f), ::testing::Values(0.7f, 2.5f)));
INSTANTIATE_TEST_SUITE_P(Mixed, GltfSamplingChiSquare,
                         ::testing::Combine(::testing::Values(0.3f), ::testing::Values(0.4f), ::testing::Values(0.5f),
                                            ::testing::Values(1.33f), ::testing::Values(0.5f, 2.5f)));

// A thin wall has air on both sides: its transmission is reciprocal (f(wo, wi) = f(wi, wo) from
// either side), carries no 1/eta^2 in either transport mode, and sends a direction straight on
// (the smooth wall's transmitted sample is -wo).
TEST(GltfBsdfThinWall, ReciprocalWithoutEtaSquared) {
    ShadingInputs in = inputs(Rgb(0.9f, 0.8f, 0.7f), 0.0f, 0.5f, 1.0f, 1.5f, 1.0f);
    in.thin_walled = true;
    GltfBsdf bsdf(in, 1.5f);
    for (float a : {0.3f, 0.9f, 1.3f})
        for (float b : {1.9f, 2.4f, 2.9f, 0.6f}) {
            Vec3 wo = direction(a, 0.4f), wi = direction(b, 2.1f);
            Rgb f = bsdf.eval(wo, wi, TransportMode::Radiance), r = bsdf.eval(wi, wo, TransportMode::Radiance);
            Rgb g = bsdf.eval(wo, wi, TransportMode::Importance);
            EXPECT_GT(f.g, 0.0f) << a << " " << b;
            EXPECT_NEAR(f.g, r.g, 1e-4f * f.g) << a << " " << b;
            EXPECT_NEAR(f.g, g.g, 1e-6f * f.g) << a << " " << b;
        }
    ShadingInputs smooth = inputs(Rgb(1.0f), 0.0f, 0.0f, 1.0f, 1.5f, 1.0f);
    smooth.thin_walled = true;
    GltfBsdf pane(smooth, 1.5f);
    Vec3 wo = direction(0.5f, 1.0f);
    BsdfSample bs;
    ASSERT_TRUE(pane.sample(wo, 0.99f, 0.5f, 0.5f, &bs, TransportMode::Radiance));  // u_lobe past F: transmitted
    EXPECT_NEAR(bs.wi.x, -wo.x, 1e-6f);
    EXPECT_NEAR(bs.wi.y, -wo.y, 1e-6f);
    EXPECT_NEAR(bs.wi.z, -wo.z, 1e-6f);
    // weight = (1 - F) / P(transmit) = 1 for a white wall: nothing lost, nothing scaled.
    EXPECT_NEAR(bs.weight.g, 1.0f, 1e-5f);
}

// The Lambert fast path (F0 = F90 = 0, nothing else) is the general layered model's limit: a
// specular layer of F0 = F90 = 1e-6 takes the general path and must agree to that order, on
// both sides of the frame (the densities differ: the general path keeps sampling its specular
// lobe); the fast path samples exactly the density it reports (chi-square).
TEST(GltfMaterial, LambertFastPathMatchesTheGeneralModel) {
    Rng rng(8, 3);
    for (float roughness : {0.0f, 0.3f, 1.0f}) {
        ShadingInputs in = inputs(Rgb(0.7f, 0.5f, 0.2f), 0.0f, roughness, 0.0f);
        ShadingInputs near = in;
        near.dielectric_f0 = Rgb(1e-6f);
        near.dielectric_f90 = 1e-6f;
        GltfBsdf fast(in, 1.45f), general(near, 1.45f);
        ASSERT_TRUE(fast.is_lambert());
        ASSERT_FALSE(general.is_lambert());
        for (int i = 0; i < 200; ++i) {
            float side_o = i % 2 ? 1.0f : -1.0f, side_i = i % 3 ? side_o : -side_o;
            Vec3 wo = direction(rng.next_float() * 1.5f, rng.next_float() * 6.28f) * side_o;
            Vec3 wi = direction(rng.next_float() * 1.5f, rng.next_float() * 6.28f) * side_i;
            Rgb a = fast.eval(wo, wi), b = general.eval(wo, wi);
            EXPECT_NEAR(a.r, b.r, 1e-5f);
            EXPECT_NEAR(a.g, b.g, 1e-5f);
            EXPECT_NEAR(a.b, b.b, 1e-5f);
            BsdfSample sa, sb;
            float u0 = rng.next_float(), u1 = rng.next_float(), u2 = rng.next_float();
            ASSERT_TRUE(fast.sample(wo, u0, u1, u2, &sa));
            EXPECT_EQ(sa.wi.z > 0.0f, wo.z > 0.0f);
            EXPECT_NEAR(sa.pdf_w, fast.pdf_w(wo, sa.wi), 1e-5f);
            EXPECT_NEAR(sa.weight.r, 0.7f, 1e-6f);
        }
    }
    for (float theta : {0.4f, 2.5f}) {
        GltfBsdf bsdf(inputs(Rgb(0.6f), 0.0f, 0.5f, 0.0f));
        Vec3 wo = direction(theta, 0.7f);
        auto res = test::chi_square_directions(
            [&](Rng& r, Vec3* d) {
                BsdfSample bs;
                bool ok = bsdf.sample(wo, r.next_float(), r.next_float(), r.next_float(), &bs);
                *d = bs.wi;
                return ok;
            },
            [&](const Vec3& d) { return static_cast<double>(bsdf.pdf_w(wo, d)); });
        EXPECT_GT(res.p_value, 0.005) << "chi2 " << res.statistic << " dof " << res.dof;
        EXPECT_LT(res.missing_mass, 0.01);
    }
}

// set_outgoing() caches what depends on wo: for that wo every answer must be the uncached one
// bit for bit, and any other wo (a reverse density in BDPT) must not see the cache.
TEST(GltfMaterial, OutgoingCacheChangesNoAnswer) {
    Rng rng(4, 4);
    for (float metallic : {0.0f, 1.0f})
        for (float roughness : {0.0f, 0.4f, 1.0f})
            for (float transmission : {0.0f, 1.0f})
                for (float coat : {0.0f, 0.6f}) {
                    ShadingInputs in =
                        layered(inputs(Rgb(0.8f, 0.4f, 0.3f), metallic, roughness, 1.0f, 1.5f, transmission), coat,
                                roughness * 0.5f, Rgb(0.5f) * coat, 0.5f);
                    GltfBsdf plain(in, 1.5f), cached(in, 1.5f);
                    for (int i = 0; i < 100; ++i) {
                        float side = i % 2 ? 1.0f : -1.0f;
                        Vec3 wo = direction(rng.next_float() * 1.5f, rng.next_float() * 6.28f) * side;
                        Vec3 other = direction(rng.next_float() * 1.5f, rng.next_float() * 6.28f);
                        Vec3 wi = direction(rng.next_float() * 3.1f, rng.next_float() * 6.28f);
                        cached.set_outgoing(wo);
                        for (const Vec3& w : {wo, other}) {
                            Rgb a = plain.eval(w, wi), b = cached.eval(w, wi);
                            EXPECT_EQ(a.r, b.r);
                            EXPECT_EQ(a.g, b.g);
                            EXPECT_EQ(a.b, b.b);
                            EXPECT_EQ(plain.pdf_w(w, wi), cached.pdf_w(w, wi));
                            float u0 = rng.next_float(), u1 = rng.next_float(), u2 = rng.next_float();
                            BsdfSample sa, sb;
                            bool oka = plain.sample(w, u0, u1, u2, &sa), okb = cached.sample(w, u0, u1, u2, &sb);
                            ASSERT_EQ(oka, okb);
                            if (!oka) continue;
                            EXPECT_EQ(sa.wi.x, sb.wi.x);
                            EXPECT_EQ(sa.wi.z, sb.wi.z);
                            EXPECT_EQ(sa.pdf_w, sb.pdf_w);
                            EXPECT_EQ(sa.weight.g, sb.weight.g);
                            EXPECT_EQ(sa.delta, sb.delta);
                        }
                    }
                }
}

// Veach 1997 eq. 5.14: f(wi -> wo) / eta_o^2 = f(wo -> wi) / eta_i^2 in radiance mode, and the
// importance-mode BTDF is the transpose of the radiance-mode one (flux is not rescaled).
TEST(GltfMaterial, TransmissionEtaSquaredRule) {
    const float eta = 1.5f;
    GltfBsdf bsdf(inputs(Rgb(1.0f), 0.0f, 0.4f, 1.0f, eta, 1.0f), eta);
    Rng rng(7, 7);
    int checked = 0;
    for (int i = 0; i < 400; ++i) {
        Vec3 a = direction(rng.next_float() * 1.5f, rng.next_float() * 6.28f);         // outside, index 1
        Vec3 b = direction(k_pi - rng.next_float() * 1.5f, rng.next_float() * 6.28f);  // inside, index eta
        float f_ab = bsdf.eval(a, b, TransportMode::Radiance).r;  // light b -> a (leaving the medium)
        float f_ba = bsdf.eval(b, a, TransportMode::Radiance).r;  // light a -> b (entering)
        if (!(f_ab > 1e-4f)) continue;
        ++checked;
        EXPECT_NEAR(f_ab * eta * eta / f_ba, 1.0f, 1e-3f);  // f_ab / 1^2 = f_ba / eta^2
        EXPECT_NEAR(bsdf.eval(a, b, TransportMode::Importance).r, f_ba, 1e-4f * f_ba + 1e-6f);
    }
    EXPECT_GT(checked, 100);
}

// Energy in flux terms: R + T <= 1 for a white rough dielectric, exactly 1 when smooth; total
// internal reflection returns everything beyond the critical angle.
TEST(GltfMaterial, TransmissionConservesFluxAndReflectsTotallyInside) {
    for (float roughness : {0.0f, 0.1f, 0.5f, 1.0f})
        for (float theta : {0.2f, 1.0f, 1.4f, k_pi - 0.2f, k_pi - 1.0f}) {
            GltfBsdf bsdf(inputs(Rgb(1.0f), 0.0f, roughness, 1.0f, 1.5f, 1.0f), 1.5f);
            float se = 0;
            Rgb a = albedo(bsdf, direction(theta, 0.4f), 40000, TransportMode::Importance, &se);
            EXPECT_LE(a.max(), 1.0f + 4 * se + 0.005f) << "r " << roughness << " theta " << theta;
            if (roughness == 0.0f) EXPECT_NEAR(a.max(), 1.0f, 1e-4f) << "theta " << theta;
            // Single-scattering refraction loses energy with roughness (no compensation for the
            // transmissive lobe yet): bounded below only loosely.
            else
                EXPECT_GT(a.max(), roughness < 0.6f ? 0.75f : 0.35f) << "r " << roughness << " theta " << theta;
        }
    // Inside glass (wo below, eta 1/1.5 seen from there) at 60 degrees: past the critical angle
    // asin(1/1.5) = 41.8 degrees, every sample reflects, back inside.
    GltfBsdf smooth(inputs(Rgb(1.0f), 0.0f, 0.0f, 1.0f, 1.5f, 1.0f), 1.5f);
    EXPECT_TRUE(smooth.is_pure_delta());
    Vec3 wo = direction(k_pi - 1.05f, 0.0f);
    Rng rng(3, 3);
    for (int i = 0; i < 1000; ++i) {
        BsdfSample bs;
        ASSERT_TRUE(smooth.sample(wo, rng.next_float(), rng.next_float(), rng.next_float(), &bs));
        EXPECT_LT(bs.wi.z, 0.0f);
        EXPECT_TRUE(bs.delta);
        EXPECT_NEAR(bs.weight.r, 1.0f, 1e-5f);
    }
}

// Smooth refraction bends by Snell's law and carries (1 - F) / eta^2 of the radiance in.
TEST(GltfMaterial, SmoothRefractionFollowsSnell) {
    const float eta = 1.5f;
    GltfBsdf bsdf(inputs(Rgb(1.0f), 0.0f, 0.0f, 1.0f, eta, 1.0f), eta);
    Vec3 wo = direction(0.8f, 0.0f);
    Rng rng(4, 4);
    int refracted = 0;
    for (int i = 0; i < 2000; ++i) {
        BsdfSample bs;
        if (!bsdf.sample(wo, rng.next_float(), rng.next_float(), rng.next_float(), &bs)) continue;
        if (bs.wi.z > 0.0f) continue;
        ++refracted;
        float sin_t = std::sqrt(bs.wi.x * bs.wi.x + bs.wi.y * bs.wi.y);
        EXPECT_NEAR(sin_t * eta, std::sin(0.8f), 1e-5f);
        EXPECT_NEAR(bs.weight.r, 1.0f / (eta * eta), 1e-5f);  // (1 - F) / (1 - F) / eta^2
    }
    EXPECT_GT(refracted, 1700);
}

// KHR_materials_clearcoat's clearcoatNormalTexture: the coat is a GGX layer about its own normal
// cn. A smooth coat mirrors wo about cn (not about the base's normal); a tilted coat of any
// roughness over any base stays reciprocal and never reflects more than it receives; the per-hit
// cache changes no answer with a tilt (it then depends on wo, not only on |wo.z|).
TEST(GltfMaterial, TiltedClearcoatNormal) {
    {
        GltfBsdf smooth(layered(inputs(Rgb(0.5f), 0.0f, 0.6f), 1.0f, 0.0f, Rgb(0.0f), 0.0f));
        Vec3 cn = tilted_coat_normal(0.3f);
        smooth.set_coat_normal(cn);
        Vec3 wo = direction(0.5f, 0.4f);
        BsdfSample bs;
        ASSERT_TRUE(smooth.sample(wo, 0.0f, 0.5f, 0.5f, &bs));  // u_lobe 0: the coat's event
        EXPECT_TRUE(bs.delta);
        Vec3 expected = cn * (2.0f * dot(wo, cn)) - wo;
        EXPECT_NEAR(bs.wi.x, expected.x, 1e-5f);
        EXPECT_NEAR(bs.wi.y, expected.y, 1e-5f);
        EXPECT_NEAR(bs.wi.z, expected.z, 1e-5f);
        EXPECT_GT(std::fabs(bs.wi.x + wo.x) + std::fabs(bs.wi.y + wo.y), 0.1f);  // not the base's mirror
    }
    Rng rng(7, 7);
    for (float tilt : {0.3f, 0.8f})
        for (float cc_roughness : {0.0f, 0.3f, 1.0f})
            for (int base = 0; base < 3; ++base) {
                ShadingInputs in = base == 0   ? inputs(Rgb(1.0f), 0.0f, 0.5f)
                                   : base == 1 ? inputs(Rgb(1.0f), 1.0f, 0.3f)
                                               : inputs(Rgb(1.0f), 0.0f, 0.5f, 1.0f, 1.5f, 1.0f);
                in = layered(in, 1.0f, cc_roughness, Rgb(0.0f), 0.0f);
                GltfBsdf bsdf(in, 1.5f), cached(in, 1.5f);
                bsdf.set_coat_normal(tilted_coat_normal(tilt));
                cached.set_coat_normal(tilted_coat_normal(tilt));
                for (float theta : {0.2f, 0.9f, 1.4f, 2.0f}) {
                    if (theta > 1.6f && base != 2) continue;  // below: only glass is seen from there
                    float se = 0;
                    Rgb a = albedo(bsdf, direction(theta, 1.0f), 20000, TransportMode::Radiance, &se);
                    EXPECT_LE(a.max(), 1.0f + 4 * se + 0.005f)
                        << "tilt " << tilt << " cc " << cc_roughness << " base " << base << " theta " << theta;
                }
                for (int i = 0; i < 200; ++i) {
                    float side = i % 3 == 0 && base == 2 ? -1.0f : 1.0f;
                    Vec3 a = direction(rng.next_float() * 1.55f, rng.next_float() * 6.28f) * side;
                    Vec3 b = direction(rng.next_float() * 1.55f, rng.next_float() * 6.28f);
                    if (base != 2) {
                        Rgb fab = bsdf.eval(a, b), fba = bsdf.eval(b, a);
                        EXPECT_NEAR(fab.g, fba.g, 1e-5f * std::max(1.0f, fab.g)) << "tilt " << tilt << " base " << base;
                    }
                    cached.set_outgoing(a);
                    for (const Vec3& w : {a, b}) {
                        EXPECT_EQ(bsdf.eval(w, b).g, cached.eval(w, b).g);
                        EXPECT_EQ(bsdf.pdf_w(w, a), cached.pdf_w(w, a));
                        float u0 = rng.next_float(), u1 = rng.next_float(), u2 = rng.next_float();
                        BsdfSample sa, sb;
                        bool oka = bsdf.sample(w, u0, u1, u2, &sa), okb = cached.sample(w, u0, u1, u2, &sb);
                        ASSERT_EQ(oka, okb);
                        if (oka) {
                            EXPECT_EQ(sa.weight.g, sb.weight.g);
                        }
                    }
                }
            }
}

}  // namespace
}  // namespace veach
