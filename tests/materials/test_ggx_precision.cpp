// GGX in float, from the delta threshold (k_delta_alpha) up: the distribution and the density of
// its sampled directions are finite and exact to float precision at every roughness, and every
// lobe of the glTF BSDF built on it (metal, specular over diffuse, rough glass, clearcoat, sheen)
// evaluates, reports densities and samples finite values on a fine roughness grid. At roughness
// 0.010-0.0131 the textbook D = a2 / (pi (cos^2 (a2 - 1) + 1)^2) rounds a2 - 1 to -1 and divides
// by zero at the peak.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/rng.h"
#include "materials/fresnel.h"
#include "materials/gltf_bsdf.h"
#include "materials/microfacet_ggx.h"

namespace veach {
namespace {

double ggx_d_exact(double theta, double alpha) {
    double a2 = alpha * alpha, c = std::cos(theta), s = std::sin(theta);
    double t = s * s + a2 * c * c;
    return a2 / (3.14159265358979323846 * t * t);
}

// Roughness from just above the delta threshold (alpha = 1e-4) up to 1: fine where float
// trouble lives (below 0.05), coarser above.
std::vector<float> roughness_grid() {
    std::vector<float> r;
    float r0 = std::sqrt(k_delta_alpha);
    for (float x = r0; x < 0.05f; x += 0.0002f) r.push_back(x);
    for (float x = 0.05f; x <= 1.0f; x += 0.05f) r.push_back(x);
    return r;
}

bool finite(const Rgb& c) { return std::isfinite(c.r) && std::isfinite(c.g) && std::isfinite(c.b); }
bool finite_non_negative(const Rgb& c) { return finite(c) && c.r >= 0.0f && c.g >= 0.0f && c.b >= 0.0f; }

TEST(GgxPrecision, DistributionIsExactFromTheDeltaThresholdUp) {
    for (float roughness : roughness_grid()) {
        float alpha = std::max(roughness * roughness, k_delta_alpha);
        // Half vectors at the peak and at multiples of the lobe's width.
        for (float k : {0.0f, 0.1f, 0.5f, 1.0f, 2.0f, 5.0f, 20.0f}) {
            float theta = std::min(k * alpha, 1.5f);
            Vec3 h(std::sin(theta), 0.0f, std::cos(theta));
            double want = ggx_d_exact(theta, alpha);
            float d = ggx_d(h, alpha);
            ASSERT_TRUE(std::isfinite(d)) << "roughness " << roughness << " theta " << theta;
            EXPECT_NEAR(d / want, 1.0, 1e-4) << "roughness " << roughness << " theta " << theta;
            // The density of the reflected direction, G1(wo) D(h) / (4 wo.z), for wo on the normal.
            Vec3 wo(0.0f, 0.0f, 1.0f);
            float pdf = ggx_reflection_pdf_w(wo, h, alpha);
            ASSERT_TRUE(std::isfinite(pdf)) << "roughness " << roughness << " theta " << theta;
            EXPECT_NEAR(pdf / (want / 4.0), 1.0, 1e-4) << "roughness " << roughness << " theta " << theta;
        }
    }
}

struct Lobe {
    const char* name;
    ShadingInputs (*make)(float roughness);
};

ShadingInputs base_inputs() {
    ShadingInputs in;
    in.base_color = Rgb(0.8f, 0.6f, 0.4f);
    in.dielectric_f0 = Rgb(0.04f);
    in.dielectric_f90 = 1.0f;
    return in;
}

const Lobe k_lobes[] = {
    {"metal",
     [](float r) {
         ShadingInputs in = base_inputs();
         in.metallic = 1.0f;
         in.alpha = std::max(r * r, k_min_ggx_alpha);
         return in;
     }},
    {"dielectric",
     [](float r) {
         ShadingInputs in = base_inputs();
         in.alpha = std::max(r * r, k_min_ggx_alpha);
         return in;
     }},
    {"glass",
     [](float r) {
         ShadingInputs in = base_inputs();
         in.transmission = 1.0f;
         in.alpha = std::max(r * r, k_min_ggx_alpha);
         return in;
     }},
    {"clearcoat",
     [](float r) {
         ShadingInputs in = base_inputs();
         in.alpha = 0.25f;
         in.clearcoat = 1.0f;
         in.clearcoat_alpha = std::max(r * r, k_min_ggx_alpha);
         return in;
     }},
    {"sheen",
     [](float r) {
         ShadingInputs in = base_inputs();
         in.alpha = std::max(r * r, k_min_ggx_alpha);
         in.sheen_color = Rgb(1.0f);
         in.sheen_roughness = r;
         return in;
     }},
};

// eval, pdf_w and sample of every lobe, from above and below the frame (glass), at the mirror
// and refraction peaks and around them, and for sampled directions: finite, never negative.
TEST(GgxPrecision, EveryLobeIsFiniteOnAFineRoughnessGrid) {
    Rng rng(5, 3);
    for (const Lobe& lobe : k_lobes)
        for (float roughness : roughness_grid())
            for (float theta : {0.0f, 1e-3f, 0.3f, 1.0f, 1.45f, 1.56f})
                for (float side : {1.0f, -1.0f}) {
                    ShadingInputs in = lobe.make(roughness);
                    if (side < 0.0f && in.transmission <= 0.0f) continue;
                    GltfBsdf bsdf(in, 1.5f);
                    Vec3 wo(std::sin(theta) * 0.8f, std::sin(theta) * 0.6f, std::cos(theta) * side);
                    bsdf.set_outgoing(wo);
                    std::vector<Vec3> wis = {Vec3(-wo.x, -wo.y, wo.z)};
                    Vec3 t;
                    if (refract(Vec3(wo.x, wo.y, std::fabs(wo.z)), Vec3(0, 0, 1), side > 0 ? 1.5f : 1.0f / 1.5f, &t))
                        wis.push_back(Vec3(t.x, t.y, side > 0 ? t.z : -t.z));
                    size_t peaks = wis.size();
                    for (size_t i = 0; i < peaks; ++i)
                        for (float k : {0.5f, 1.0f, 3.0f}) {
                            float d = k * in.alpha;
                            wis.push_back(normalize(wis[i] + Vec3(d, 0.0f, 0.0f)));
                            wis.push_back(normalize(wis[i] + Vec3(0.0f, d, 0.0f)));
                        }
                    std::string what = std::string(lobe.name) + " roughness " + std::to_string(roughness) + " theta " +
                                       std::to_string(theta) + " side " + std::to_string(side);
                    for (const Vec3& wi : wis)
                        for (TransportMode mode : {TransportMode::Radiance, TransportMode::Importance}) {
                            ASSERT_TRUE(finite_non_negative(bsdf.eval(wo, wi, mode))) << what;
                            float pdf = bsdf.pdf_w(wo, wi);
                            ASSERT_TRUE(std::isfinite(pdf) && pdf >= 0.0f) << what;
                        }
                    for (int n = 0; n < 64; ++n) {
                        BsdfSample bs;
                        if (!bsdf.sample(wo, rng.next_float(), rng.next_float(), rng.next_float(), &bs)) continue;
                        ASSERT_TRUE(finite_non_negative(bs.weight)) << what;
                        ASSERT_TRUE(std::isfinite(bs.pdf_w) && bs.pdf_w > 0.0f) << what;
                        ASSERT_TRUE(std::isfinite(bs.wi.x) && std::isfinite(bs.wi.y) && std::isfinite(bs.wi.z)) << what;
                        if (bs.delta) continue;
                        ASSERT_TRUE(finite_non_negative(bsdf.eval(wo, bs.wi))) << what;
                        ASSERT_TRUE(std::isfinite(bsdf.pdf_w(wo, bs.wi))) << what;
                    }
                }
}

// A white metal just above the delta threshold is still a mirror that reflects everything: no
// sample is lost to a non-finite weight (38% were, and the metal rendered 12% dark).
TEST(GgxPrecision, NearMirrorMetalReflectsEverything) {
    for (float roughness : {0.0101f, 0.011f, 0.012f, 0.013f, 0.0135f}) {
        ShadingInputs in;
        in.base_color = Rgb(1.0f);
        in.metallic = 1.0f;
        in.alpha = roughness * roughness;
        GltfBsdf bsdf(in);
        ASSERT_FALSE(bsdf.is_pure_delta());
        for (float theta : {0.0f, 0.5f, 1.2f}) {
            Vec3 wo(std::sin(theta), 0.0f, std::cos(theta));
            Rng rng(17, 2);
            const int n = 4000;
            double sum = 0;
            for (int i = 0; i < n; ++i) {
                BsdfSample bs;
                if (!bsdf.sample(wo, rng.next_float(), rng.next_float(), rng.next_float(), &bs)) continue;
                if (finite(bs.weight)) sum += bs.weight.average();
            }
            EXPECT_NEAR(sum / n, 1.0, 0.01) << "roughness " << roughness << " theta " << theta;
        }
    }
}

}  // namespace
}  // namespace veach
