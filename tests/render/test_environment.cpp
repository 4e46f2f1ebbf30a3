// Scenes lit by the environment, whose answer is known in closed form or by quadrature.
#include <gtest/gtest.h>

#include <cmath>

#include "lights/environment_light.h"
#include "render_helpers.h"
#include "test_scenes.h"

namespace veach {
namespace {

// An open plane z = 0 facing +Z (two triangles, 0.9 x 0.9), Lambert of albedo a, seen from
// straight above by a camera whose view it just fills (so most light particles land in view).
Scene open_plane(float albedo) {
    Scene s;
    Mesh m;
    m.name = "plane";
    m.positions = {Vec3(-0.45f, -0.45f, 0), Vec3(0.45f, -0.45f, 0), Vec3(0.45f, 0.45f, 0), Vec3(-0.45f, 0.45f, 0)};
    m.indices = {0, 1, 2, 0, 2, 3};
    m.material = 0;
    s.meshes.push_back(m);
    s.materials.push_back(test::lambert(Rgb(albedo)));
    s.instances.push_back({0, Transform()});
    s.cameras.push_back(test::camera_at(Vec3(0, 0, 0.8f), 1.0f));  // looks down -Z
    return s;
}

RenderSettings settings(const std::string& integrator, int s = -1, int t = -1) {
    RenderSettings r;
    r.integrator = integrator;
    r.bdpt_s = s;
    r.bdpt_t = t;
    return r;
}

Image render_with(const Scene& scene, int size, int spp, const RenderSettings& rs) {
    RenderJobOptions o;
    o.width = o.height = size;
    o.render = rs;
    o.render.spp = spp;
    o.render.seed = 3;
    return render_scene(scene, o).image;
}

// A uniform environment of radiance L gives irradiance pi L on an open plane, which reflects
// radiance a L whatever the depth limit (nothing above the plane reflects light back).
class UniformEnvironment : public ::testing::TestWithParam<std::string> {};

TEST_P(UniformEnvironment, OpenPlaneReflectsAlbedoTimesRadiance) {
    const float a = 0.5f;
    const Rgb l(0.8f, 1.0f, 1.25f);
    Scene s = open_plane(a);
    s.environment.enabled = true;
    s.environment.color = l;
    s.environment.strength = 2.0f;
    s.features.environment = true;
    const bool lt = GetParam() == "lt";
    Image img = render_with(s, 24, lt ? 1024 : 64, settings(GetParam()));
    const float expected[3] = {a * l.r * 2, a * l.g * 2, a * l.b * 2};
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(test::channel_mean(img, c), expected[c], 0.01 * expected[c]) << GetParam() << " channel " << c;
}

INSTANTIATE_TEST_SUITE_P(Integrators, UniformEnvironment, ::testing::Values("pt", "bdpt", "lt"));

TEST(UniformEnvironment, CameraSeesItWhereNothingIsInTheWay) {
    Scene s = open_plane(0.5f);
    s.cameras[0] = test::camera_at(Vec3(0, 0, 2.0f), 1.0f);  // the plane covers the image's centre only
    s.environment.enabled = true;
    s.environment.color = Rgb(1.5f);
    for (const char* integrator : {"pt", "bdpt"}) {
        Image img = render_with(s, 16, 64, settings(integrator));
        // Camera rays that escape see L exactly (no light sample can see the environment for them).
        EXPECT_NEAR(img.pixel(0, 0)[1], 1.5f, 1e-4f) << integrator;
        EXPECT_NEAR(img.pixel(15, 3)[1], 1.5f, 1e-4f) << integrator;
        double centre = (img.pixel(7, 7)[1] + img.pixel(8, 7)[1] + img.pixel(7, 8)[1] + img.pixel(8, 8)[1]) / 4;
        EXPECT_NEAR(centre, 0.75, 0.05) << integrator;
    }
}

// Cycles' Film > Transparent: where the camera sees the environment the pixel is (0, 0, 0, 0);
// the environment still lights what the camera sees (a L on the plane, as without the option);
// alpha is the covered fraction of each pixel, so its image mean is the plane's share of the
// view: (0.9 / (2 * 2 tan(yfov / 2)))^2 at distance 2. Every integrator, lt included (its
// camera samples carry the coverage, its splats the light).
TEST(UniformEnvironment, TransparentFilmHidesItFromTheCameraOnly) {
    Scene s = open_plane(0.5f);
    s.cameras[0] = test::camera_at(Vec3(0, 0, 2.0f), 1.0f);
    s.environment.enabled = true;
    s.environment.color = Rgb(1.5f);
    s.features.environment = true;
    const double covered = std::pow(0.9 / (4.0 * std::tan(0.5)), 2.0);
    for (const char* integrator : {"pt", "bdpt", "lt"}) {
        const bool lt = std::string(integrator) == "lt";
        RenderJobOptions o;
        o.width = o.height = 16;
        o.render = settings(integrator);
        o.render.spp = test::spp(lt ? 1024 : 128);
        o.render.seed = 3;
        o.render.transparent = true;
        o.film.alpha = true;
        Image img = render_scene(s, o).image;
        for (int c = 0; c < 4; ++c) {
            EXPECT_EQ(img.pixel(0, 0)[c], 0.0f) << integrator << " channel " << c;
            EXPECT_EQ(img.pixel(15, 3)[c], 0.0f) << integrator << " channel " << c;
        }
        double centre = (img.pixel(7, 7)[1] + img.pixel(8, 7)[1] + img.pixel(7, 8)[1] + img.pixel(8, 8)[1]) / 4;
        EXPECT_NEAR(centre, 0.75, test::tol(0.05)) << integrator;
        EXPECT_EQ(img.pixel(7, 7)[3], 1.0f) << integrator;
        EXPECT_NEAR(test::channel_mean(img, 3), covered, test::tol(0.01)) << integrator;
    }
    // Off, alpha is 1 everywhere and the environment is seen.
    Image opaque = render_with(s, 16, 16, settings("pt"));
    EXPECT_EQ(opaque.pixel(0, 0)[3], 1.0f);
    EXPECT_NEAR(opaque.pixel(0, 0)[1], 1.5f, 1e-4f);
}

// An environment map with one bright texel (and a dim rest), rotated: the plane's radiance is
// a/pi times the irradiance integral of the map's upper hemisphere, computed here by quadrature.
// Next-event estimation alone (bdpt strategy s = 1, t = 2), BSDF sampling alone (s = 0, t = 3),
// MIS path tracing and full bdpt must all find it.
TEST(EnvironmentMap, LightSamplingAndBsdfSamplingAgreeWithQuadrature) {
    const float a = 0.8f;
    Scene s = open_plane(a);
    Environment& env = s.environment;
    env.enabled = true;
    env.width = 16;
    env.height = 8;
    env.texels.assign(16 * 8 * 3, 0.05f);
    for (int c = 0; c < 3; ++c) env.texels[(2 * 16 + 9) * 3 + c] = 30.0f;  // above the horizon
    env.rotation = 0.6f;
    s.features.environment = true;

    EnvironmentLight light(env);
    double irradiance = 0;
    const int nz = 600, nphi = 1200;
    for (int i = 0; i < nz; ++i)
        for (int j = 0; j < nphi; ++j) {
            double z = (i + 0.5) / nz, phi = 2 * k_pi * (j + 0.5) / nphi;  // upper hemisphere of +Z
            double r = std::sqrt(1 - z * z);
            Vec3 w(static_cast<float>(r * std::cos(phi)), static_cast<float>(r * std::sin(phi)), static_cast<float>(z));
            irradiance += light.radiance(w).g * z;
        }
    irradiance *= 2 * k_pi / (nz * nphi);
    double expected = a / k_pi * irradiance;

    struct Case {
        const char* name;
        RenderSettings rs;
        int spp;
        double tol;
    } cases[] = {{"nee only", settings("bdpt", 1, 2), 64, 0.02},
                 {"bsdf only", settings("bdpt", 0, 3), 256, 0.03},
                 {"pt", settings("pt"), 64, 0.02},
                 {"bdpt", settings("bdpt"), 64, 0.02}};
    for (const Case& c : cases) {
        Image img = render_with(s, 16, c.spp, c.rs);
        EXPECT_NEAR(test::channel_mean(img, 1), expected, c.tol * expected) << c.name;
    }
}

}  // namespace
}  // namespace veach
