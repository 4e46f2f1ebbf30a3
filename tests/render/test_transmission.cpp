// Refraction and absorption through closed meshes, rendered (KHR_materials_transmission and
// KHR_materials_volume), against what the physics requires:
// - a smooth, clear, white dielectric sphere in a uniform environment ("white furnace") is
//   invisible: Fresnel reflection and refraction conserve energy, and the 1/eta^2 radiance
//   scaling on entering is undone by eta^2 on leaving;
// - an index-matched absorbing sphere (ior 1: no reflection, no bending) seen through its centre
//   transmits Beer-Lambert's exp(-sigma_a d), i.e. attenuationColor after attenuationDistance.
#include <gtest/gtest.h>

#include <cmath>

#include "render_helpers.h"
#include "test_scenes.h"

namespace veach {
namespace {

Scene glass_sphere_in_furnace(float ior, Rgb attenuation_color, float attenuation_distance, float yfov) {
    Scene s;
    s.meshes.push_back(test::make_sphere(1.0f, Vec3(0, 0, 0), 96, 48));
    Material glass;
    glass.name = "glass";
    glass.base_color = Rgb(1.0f);
    glass.metallic = 0;
    glass.roughness = 0;
    glass.transmission = 1;
    glass.ior = ior;
    glass.attenuation_color = attenuation_color;
    glass.attenuation_distance = attenuation_distance;
    glass.double_sided = true;
    s.materials.push_back(glass);
    s.meshes[0].material = 0;
    s.instances.push_back({0, Transform()});
    s.cameras.push_back(test::camera_at(Vec3(0, 0, 3.0f), yfov));  // looks down -Z at the sphere
    s.environment.enabled = true;
    s.environment.color = Rgb(1.0f);
    s.features.environment = true;
    s.features.transmission = true;
    s.features.volume = attenuation_distance > 0.0f;
    return s;
}

class Transmission : public ::testing::TestWithParam<std::string> {};

TEST_P(Transmission, ClearGlassSphereVanishesInWhiteFurnace) {
    Scene s = glass_sphere_in_furnace(1.5f, Rgb(1.0f), 0.0f, 0.8f);
    RenderStats stats;
    Image img = test::render(s, 24, 64, GetParam(), 64, 0, 3, &stats);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(test::channel_mean(img, c), 1.0, 0.01) << GetParam();
    for (double b : test::block_means(img, 8)) EXPECT_NEAR(b, 1.0, 0.03) << GetParam();
    EXPECT_EQ(stats.nonfinite_samples, 0u);
}

INSTANTIATE_TEST_SUITE_P(Integrators, Transmission, ::testing::Values("pt", "bdpt"));

// Beer-Lambert is applied along path segments by the path tracer.
TEST(Volume, IndexMatchedSphereTransmitsAttenuationColourOverItsDiameter) {
    // attenuationDistance 2 = the diameter: the centre ray comes out as attenuationColor. The
    // camera's narrow field (0.04 rad) keeps every ray within 0.06 of the centre, where the
    // chord is 2 to within 0.1%.
    const Rgb color(0.5f, 0.25f, 0.8f);
    Scene s = glass_sphere_in_furnace(1.0f, color, 2.0f, 0.04f);
    Image img = test::render(s, 8, 64, "pt");
    const float expected[3] = {color.r, color.g, color.b};
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(test::channel_mean(img, c), expected[c], 0.01 * expected[c]) << c;
}

}  // namespace
}  // namespace veach
