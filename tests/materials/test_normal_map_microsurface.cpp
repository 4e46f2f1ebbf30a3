// A normal map as a microsurface (materials/normal_map_microsurface.h) is a BSDF like any other:
// it conserves energy (a white material in a furnace reflects everything, never more), it is
// reciprocal (in expectation: its evaluation is a random walk), and what sample() draws is what
// eval() describes. Tested through SurfaceBsdf on a flat surface (ng = ns = +z) with a mapped
// normal tilted by theta toward +x.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "core/rng.h"
#include "materials/surface_bsdf.h"

namespace veach {
namespace {

const Vec3 k_up(0.0f, 0.0f, 1.0f);

Vec3 direction(float theta, float phi) {
    return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

ShadingInputs lambert(float albedo) {
    ShadingInputs in;
    in.base_color = Rgb(albedo);
    in.dielectric_f0 = Rgb(0.0f);
    in.dielectric_f90 = 0.0f;
    return in;
}

ShadingInputs rough_metal() {
    ShadingInputs in;
    in.base_color = Rgb(0.9f, 0.6f, 0.3f);
    in.metallic = 1.0f;
    in.alpha = 0.3f * 0.3f;
    return in;
}

SurfaceBsdf mapped(const ShadingInputs& in, float tilt_degrees, const Vec3& wo) {
    Vec3 n_map = direction(tilt_degrees * k_pi / 180.0f, 0.0f);
    return SurfaceBsdf(SurfaceBsdf::NormalMapped{}, k_up, k_up, n_map, wo, in);
}

struct Estimate {
    double mean = 0, std_error = 0;
};

// Directional albedo by sample(): the mean of the weights (green channel), with its standard error.
Estimate sampled_albedo(const SurfaceBsdf& bsdf, const Vec3& wo, int n, uint64_t seed) {
    Rng rng(seed, 3);
    double sum = 0, sum2 = 0;
    for (int i = 0; i < n; ++i) {
        BsdfSample bs;
        if (!bsdf.sample(wo, rng.next_float(), rng.next_float(), rng.next_float(), TransportMode::Radiance, &bs))
            continue;
        sum += bs.weight.g;
        sum2 += double(bs.weight.g) * bs.weight.g;
    }
    Estimate e;
    e.mean = sum / n;
    e.std_error = std::sqrt(std::max(0.0, sum2 / n - e.mean * e.mean) / n);
    return e;
}

// White furnace: a white Lambert on grooves of 30 to 80 degrees reflects everything from every
// direction (the wall only redirects light), within the walk's cap and the estimate's noise,
// and never more than everything. The shading-normal frame it replaces kept only the directions
// above the mapped normal: (1 + cos theta) / 2 of a cosine lobe, 0.75 at 60 degrees.
TEST(NormalMapMicrosurface, WhiteLambertReflectsEverythingInAFurnace) {
    for (float tilt : {30.0f, 60.0f, 80.0f})
        for (float theta : {0.0f, 0.6f, 1.2f, 1.5f})
            for (float phi : {0.0f, 1.6f, 3.14f}) {
                Vec3 wo = direction(theta, phi);
                Estimate e = sampled_albedo(mapped(lambert(1.0f), tilt, wo), wo, 20000, 7);
                // Every weight is 1 (a white Lambert's): the only loss is a walk that fails.
                EXPECT_LE(e.mean, 1.0) << tilt << " " << theta << " " << phi;
                EXPECT_GT(e.mean, 0.995) << tilt << " " << theta << " " << phi;
            }
}

// With albedo 0.8 the grooves are darker than flat by the light absorbed in their extra bounces:
// the same at every view for this symmetric groove (measured 0.667 at 60 degrees; flat: 0.8).
TEST(NormalMapMicrosurface, GrooveDarkensByItsInterreflections) {
    for (float theta : {0.0f, 0.8f, 1.3f}) {
        Vec3 wo = direction(theta, 0.5f);
        Estimate e = sampled_albedo(mapped(lambert(0.8f), 60.0f, wo), wo, 40000, 11);
        EXPECT_NEAR(e.mean, 0.667, 5 * e.std_error + 0.002) << theta;
        EXPECT_LT(e.mean, 0.8);
    }
}

// The albedo by eval() (uniform directions over the hemisphere, eval / pdf) equals the albedo by
// sample(), per cell of a 4 x 8 grid in (cos theta, phi): eval's random-walk estimate describes
// what sample() draws. z-tests, Bonferroni over the cells and cases.
TEST(NormalMapMicrosurface, EvalDescribesWhatSampleDraws) {
    const int n_mu = 4, n_phi = 8, cells = n_mu * n_phi;
    auto cell_of = [&](const Vec3& w) {
        int i = std::min(n_mu - 1, int(w.z * n_mu));
        float phi = std::atan2(w.y, w.x) + k_pi;
        int j = std::min(n_phi - 1, int(phi / (2 * k_pi) * n_phi));
        return i * n_phi + j;
    };
    struct Case {
        ShadingInputs in;
        float tilt, theta, phi;
    };
    for (const Case& c : {Case{lambert(0.8f), 60.0f, 0.3f, 0.4f}, Case{lambert(0.8f), 45.0f, 1.2f, 3.0f},
                          Case{rough_metal(), 40.0f, 0.5f, 0.2f}, Case{rough_metal(), 60.0f, 1.0f, 2.5f}}) {
        Vec3 wo = direction(c.theta, c.phi);
        SurfaceBsdf bsdf = mapped(c.in, c.tilt, wo);
        const int n = 200000;
        std::vector<double> s(cells, 0), s2(cells, 0), e(cells, 0), e2(cells, 0);
        Rng rng(5, 9);
        for (int k = 0; k < n; ++k) {
            BsdfSample bs;
            if (bsdf.sample(wo, rng.next_float(), rng.next_float(), rng.next_float(), TransportMode::Radiance, &bs) &&
                bs.wi.z > 0.0f) {
                int cell = cell_of(bs.wi);
                s[cell] += bs.weight.g;
                s2[cell] += double(bs.weight.g) * bs.weight.g;
            }
            // Uniform over the hemisphere: density 1 / (2 pi).
            float mu = rng.next_float(), phi = 2 * k_pi * rng.next_float();
            float r = std::sqrt(std::max(0.0f, 1 - mu * mu));
            Vec3 wi(r * std::cos(phi), r * std::sin(phi), mu);
            double v = bsdf.eval(wo, wi, TransportMode::Radiance).g * 2 * k_pi;
            int cell = cell_of(wi);
            e[cell] += v;
            e2[cell] += v * v;
        }
        for (int cell = 0; cell < cells; ++cell) {
            double ms = s[cell] / n, me = e[cell] / n;
            double var = (s2[cell] / n - ms * ms) / n + (e2[cell] / n - me * me) / n;
            double z = (ms - me) / std::sqrt(std::max(var, 1e-14));
            EXPECT_LT(std::fabs(z), 4.5) << "tilt " << c.tilt << " cell " << cell << ": sampled " << ms
                                         << " evaluated " << me;
        }
    }
}

// Reciprocity: f(wo, wi) = f(wi, wo), that is eval(wo, wi) / wi.z = eval(wi, wo) / wo.z, for
// pairs of directions on the grooves, Lambert and rough metal on the perturbed facet. Each side
// is averaged over many BSDFs (each keyed by its own wo: independent walks); z-test per pair.
TEST(NormalMapMicrosurface, ReciprocalInExpectation) {
    Rng rng(17, 4);
    for (const ShadingInputs& in : {lambert(0.8f), rough_metal()})
        for (int pair = 0; pair < 12; ++pair) {
            Vec3 a = direction(1.45f * rng.next_float(), 2 * k_pi * rng.next_float());
            Vec3 b = direction(1.45f * rng.next_float(), 2 * k_pi * rng.next_float());
            double sum[2] = {0, 0}, sum2[2] = {0, 0};
            const int n = 4000;
            for (int k = 0; k < n; ++k) {
                // Each SurfaceBsdf's walks are keyed by its wo's bits: nudge it by a few ulps.
                Vec3 a_k = a * (1.0f + float(k) * 1e-7f), b_k = b * (1.0f + float(k) * 1e-7f);
                double f_ab = mapped(in, 60.0f, a_k).eval(a_k, b, TransportMode::Radiance).g / b.z;
                double f_ba = mapped(in, 60.0f, b_k).eval(b_k, a, TransportMode::Radiance).g / a.z;
                sum[0] += f_ab;
                sum2[0] += f_ab * f_ab;
                sum[1] += f_ba;
                sum2[1] += f_ba * f_ba;
            }
            double m0 = sum[0] / n, m1 = sum[1] / n;
            double var = (sum2[0] / n - m0 * m0) / n + (sum2[1] / n - m1 * m1) / n;
            double z = (m0 - m1) / std::sqrt(std::max(var, 1e-16));
            EXPECT_LT(std::fabs(z), 4.0) << "pair " << pair << ": " << m0 << " vs " << m1;
            EXPECT_GT(m0 + m1, 0.0) << "pair " << pair;
        }
}

// Importance transport needs no adjoint factor on flat geometry: the same directions give the
// same value in both modes, bounded however grazing the particle (the shading-normal frame's
// adjoint |wo.ns| / |wo.ng| grew without bound there).
TEST(NormalMapMicrosurface, ImportanceEqualsRadianceOnFlatGeometry) {
    for (float theta : {0.2f, 1.0f, 1.55f, 1.5704f}) {
        Vec3 wo = direction(theta, 3.0f), wi = direction(0.4f, 0.5f);
        SurfaceBsdf bsdf = mapped(lambert(0.8f), 60.0f, wo);
        Rgb r = bsdf.eval(wo, wi, TransportMode::Radiance), i = bsdf.eval(wo, wi, TransportMode::Importance);
        EXPECT_EQ(r.g, i.g) << theta;
        BsdfSample bs;
        Rng rng(3, 3);
        for (int k = 0; k < 1000; ++k)
            if (bsdf.sample(wo, rng.next_float(), rng.next_float(), rng.next_float(), TransportMode::Importance, &bs))
                EXPECT_LE(bs.weight.g, 0.8f + 1e-6f);
    }
}

// A flat map (the macro normal) changes nothing: the plain BSDF, bit for bit.
TEST(NormalMapMicrosurface, UntiltedMapIsThePlainBsdf) {
    Vec3 wo = direction(0.7f, 0.3f), wi = direction(0.2f, 2.0f);
    SurfaceBsdf plain(k_up, k_up, wo, rough_metal());
    SurfaceBsdf flat(SurfaceBsdf::NormalMapped{}, k_up, k_up, k_up, wo, rough_metal());
    EXPECT_EQ(plain.eval(wo, wi, TransportMode::Radiance).g, flat.eval(wo, wi, TransportMode::Radiance).g);
    EXPECT_EQ(plain.pdf_w(wo, wi), flat.pdf_w(wo, wi));
}

}  // namespace
}  // namespace veach
