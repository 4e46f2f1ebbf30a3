// Every light type against its own claims: the directions sample_direct draws follow the density
// pdf_direct_w reports (chi-square), that density integrates to one over the sphere (numerically),
// the radiance a ray finds where a sample landed is the sample's radiance, emission samples carry
// the densities pdf_emission reports, follow them (chi-square) and carry the light's power.
// These are the identities bidirectional MIS relies on.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "../materials/chi_square.h"
#include "core/rng.h"
#include "lights/light_set.h"

namespace veach {
namespace {

constexpr double k_significance = 1e-4;

LightContext context() {
    LightContext ctx;
    ctx.center = Vec3(0, 0, 0);
    ctx.radius = 5;
    return ctx;
}

// Where a ray from `o` along `d` meets the light (for lights with a position), for the density
// queries that take a point.
using FindPoint = std::function<bool(const Vec3& o, const Vec3& d, Vec3* p)>;

template <typename L>
FindPoint by_intersect(const L& light) {
    return [&light](const Vec3& o, const Vec3& d, Vec3* p) {
        LightHit h;
        if (!light.intersect(o, d, k_infinity, &h)) return false;
        *p = h.p;
        return true;
    };
}

FindPoint at_infinity() {
    return [](const Vec3& o, const Vec3& d, Vec3* p) {
        *p = o + d * 1e3f;
        return true;
    };
}

// Checks sample_direct from `receiver` against pdf_direct_w and radiance.
template <typename L>
void check_direct(const L& light, const Vec3& receiver, const FindPoint& find, const Vec3& axis) {
    LightContext ctx = context();
    Frame frame(axis);
    // 1. Each sample's density and radiance are what the queries say for its point.
    Rng rng(7, 11);
    int produced = 0;
    for (int i = 0; i < 2000; ++i) {
        LightSample ls;
        if (!light.sample_direct(ctx, receiver, rng.next_float(), rng.next_float(), 1.0f, &ls)) continue;
        ++produced;
        float pdf = light.pdf_direct_w(ctx, receiver, ls.wi, ls.point, 1.0f);
        ASSERT_NEAR(pdf, ls.pdf_w, 2e-3f * ls.pdf_w) << "sample " << i;
        Rgb le = light.radiance(ctx, ls.point, -ls.wi);
        ASSERT_NEAR(le.g, ls.radiance.g, 2e-3f * ls.radiance.g + 1e-6f) << "sample " << i;
    }
    EXPECT_GT(produced, 1000);
    // 2. The directions follow the density (chi-square), which integrates to one.
    auto sample = [&](Rng& r, Vec3* d) {
        LightSample ls;
        if (!light.sample_direct(ctx, receiver, r.next_float(), r.next_float(), 1.0f, &ls)) return false;
        *d = frame.to_local(ls.wi);
        return true;
    };
    auto pdf = [&](const Vec3& local) {
        Vec3 wi = frame.to_world(local);
        Vec3 p;
        // Where the light sends nothing (outside a spot's cone) the sampler returns no sample.
        if (!find(receiver, wi, &p) || light.radiance(ctx, p, -wi).is_black()) return 0.0;
        return double(light.pdf_direct_w(ctx, receiver, wi, p, 1.0f));
    };
    test::ChiSquareResult res = test::chi_square_directions(sample, pdf, 100000, 80, 40, 32);
    EXPECT_GT(res.p_value, k_significance) << "chi2 " << res.statistic << " dof " << res.dof;
    EXPECT_LT(res.missing_mass, 0.01);
}

// Checks sample_emission against pdf_emission, the directions' density around the point's normal
// (or absolutely, for lights at infinity) and the emitted power.
template <typename L>
void check_emission(const L& light, double power, bool relative_to_normal, bool chi_square = true) {
    LightContext ctx = context();
    Rng rng(3, 5);
    double flux = 0;
    int n = 200000;
    LightEmission first;
    bool have_first = false;
    for (int i = 0; i < n; ++i) {
        LightEmission e;
        float u[5] = {rng.next_float(), rng.next_float(), rng.next_float(), rng.next_float(), rng.next_float()};
        if (!light.sample_emission(ctx, u[0], u[1], u[2], u[3], u[4], &e)) continue;
        if (!have_first) {
            first = e;
            have_first = true;
        }
        float pos, dir;
        light.pdf_emission(ctx, e.point, e.dir, &pos, &dir);
        ASSERT_NEAR(pos, e.pdf_pos_a, 1e-4f * e.pdf_pos_a);
        ASSERT_NEAR(dir, e.pdf_dir_w, 2e-3f * e.pdf_dir_w);
        Rgb le = light.radiance(ctx, e.point, e.dir);
        ASSERT_NEAR(le.g, e.value.g, 2e-3f * e.value.g + 1e-6f);
        float cos = relative_to_normal ? dot(e.normal, e.dir) : 1.0f;
        flux += e.value.g * cos / (e.pdf_pos_a * e.pdf_dir_w);
    }
    ASSERT_TRUE(have_first);
    if (power > 0) {
        EXPECT_NEAR(flux / n, power, 0.01 * power);
    }
    if (!chi_square) return;
    Frame frame(relative_to_normal ? first.normal : first.dir);
    Vec3 p0 = first.point;
    auto sample = [&](Rng& r, Vec3* d) {
        LightEmission e;
        float u[5] = {r.next_float(), r.next_float(), r.next_float(), r.next_float(), r.next_float()};
        if (!light.sample_emission(ctx, u[0], u[1], u[2], u[3], u[4], &e)) return false;
        *d = relative_to_normal ? Frame(e.normal).to_local(e.dir) : frame.to_local(e.dir);
        return true;
    };
    auto pdf = [&](const Vec3& local) {
        float pos, dir;
        light.pdf_emission(ctx, p0, frame.to_world(local), &pos, &dir);
        return double(dir);
    };
    test::ChiSquareResult res = test::chi_square_directions(sample, pdf, 100000, 40, 40, 32);
    EXPECT_GT(res.p_value, k_significance) << "chi2 " << res.statistic << " dof " << res.dof;
}

TEST(LightTypes, TriangleDirectAndEmission) {
    TriangleLight tl;
    tl.p0 = Vec3(-1, -1, 2);
    tl.e1 = Vec3(2, 0, 0);
    tl.e2 = Vec3(0, 2, 0.5f);
    Vec3 c = cross(tl.e1, tl.e2);
    tl.area = 0.5f * length(c);
    tl.n = -normalize(c);  // facing the origin
    tl.radiance_value = Rgb(2.0f);
    FindPoint find = [&](const Vec3& o, const Vec3& d, Vec3* p) {
        // Moller-Trumbore, enough for the test.
        Vec3 pv = cross(d, tl.e2);
        float det = dot(tl.e1, pv);
        if (std::fabs(det) < 1e-12f) return false;
        Vec3 tv = o - tl.p0;
        float u = dot(tv, pv) / det;
        Vec3 qv = cross(tv, tl.e1);
        float v = dot(d, qv) / det;
        float t = dot(tl.e2, qv) / det;
        if (u < 0 || v < 0 || u + v > 1 || t <= 0) return false;
        *p = o + d * t;
        return true;
    };
    check_direct(tl, Vec3(0, 0, 0), find, Vec3(0, 0, 1));
    check_emission(tl, k_pi * tl.area * 2.0, true);
}

TEST(LightTypes, RectangleAndEllipseAreaLights) {
    for (AreaShape shape : {AreaShape::Rectangle, AreaShape::Ellipse}) {
        SCOPED_TRACE(shape == AreaShape::Rectangle ? "rectangle" : "ellipse");
        AreaLight a = AreaLight::make(Vec3(0.3f, 0, 1.5f), Vec3(1.0f, 0, 0), Vec3(0, 0.6f, 0.2f), Vec3(0, 0, -1), shape,
                                      Rgb(3.0f));
        float expected_area = (shape == AreaShape::Rectangle ? 4.0f : k_pi) * length(cross(a.axis_u, a.axis_v));
        EXPECT_NEAR(a.area, expected_area, 1e-5f);
        check_direct(a, Vec3(0, 0, 0), by_intersect(a), Vec3(0, 0, 1));
        check_emission(a, k_pi * a.area * 3.0, true);
        // One-sided: nothing behind it, and rays from behind pass.
        LightSample ls;
        EXPECT_FALSE(a.sample_direct(context(), Vec3(0, 0, 3), 0.5f, 0.5f, 1.0f, &ls));
        LightHit h;
        EXPECT_FALSE(a.intersect(Vec3(0.3f, 0, 3), Vec3(0, 0, -1), k_infinity, &h));
    }
}

TEST(LightTypes, SphereOfAPointLight) {
    PointLight pl{Vec3(0, 0, 2), Rgb(5.0f), 0.7f};
    check_direct(pl, Vec3(0, 0, 0), by_intersect(pl), Vec3(0, 0, 1));
    check_emission(pl, 4.0 * k_pi * 5.0, true);  // the same power as the point it stands for
    // Far away it lights like the point: irradiance I / d^2 (exact for a sphere).
    LightContext ctx = context();
    Rng rng(1, 2);
    double e = 0;
    int n = 20000;
    Vec3 receiver(0, 0, -8);
    for (int i = 0; i < n; ++i) {
        LightSample ls;
        if (!pl.sample_direct(ctx, receiver, rng.next_float(), rng.next_float(), 1.0f, &ls)) continue;
        e += ls.radiance.g * ls.wi.z / ls.pdf_w;
    }
    EXPECT_NEAR(e / n, 5.0 / 100.0, 0.002 * 5.0 / 100.0);
    // A receiver inside the sphere sees none of it.
    LightSample ls;
    EXPECT_FALSE(pl.sample_direct(ctx, Vec3(0, 0, 2.1f), 0.5f, 0.5f, 1.0f, &ls));
}

TEST(LightTypes, SphereOfASpotLight) {
    SpotLight sl;
    sl.position = Vec3(0, 0, 2);
    sl.axis = normalize(Vec3(0.2f, 0, -1));
    sl.intensity = Rgb(4.0f);
    sl.cos_outer = std::cos(1.0f);
    sl.smooth = (1.0f - sl.cos_outer) * 0.3f;
    sl.falloff = SpotFalloff::Blender;
    sl.radius = 0.5f;
    check_direct(sl, Vec3(0, 0, 0), by_intersect(sl), Vec3(0, 0, 1));
    // Directions outside the cone carry nothing and are not returned: no chi-square on them.
    check_emission(sl, 0.0, true, false);
}

TEST(LightTypes, SunDisc) {
    // Cycles' sun: a sample's weight (radiance / pdf) is the irradiance exactly.
    float angle = 0.6f;
    DirectionalLight sun{normalize(Vec3(0.3f, -0.2f, -1)), Rgb(2.0f), std::tan(0.5f * angle)};
    check_direct(sun, Vec3(0, 0, 0), at_infinity(), -sun.direction);
    LightSample ls;
    ASSERT_TRUE(sun.sample_direct(context(), Vec3(), 0.3f, 0.8f, 1.0f, &ls));
    EXPECT_NEAR(ls.radiance.g / ls.pdf_w, 2.0f, 1e-4f);
    EXPECT_LE(std::acos(dot(ls.wi, -sun.direction)), 0.5f * angle + 1e-4f);
    check_emission(sun, 0.0, false);
}

TEST(LightTypes, EnvironmentThroughTheCommonQueries) {
    Environment env;
    env.enabled = true;
    env.color = Rgb(0.5f);
    EnvironmentLight light(env);
    check_direct(light, Vec3(0, 0, 0), at_infinity(), Vec3(0, 0, 1));
}

}  // namespace
}  // namespace veach
