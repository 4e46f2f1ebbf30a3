// Refraction and absorption through closed meshes, rendered (KHR_materials_transmission and
// KHR_materials_volume), against what the physics requires:
// - a smooth, clear, white dielectric sphere in a uniform environment ("white furnace") is
//   invisible: Fresnel reflection and refraction conserve energy, and the 1/eta^2 radiance
//   scaling on entering is undone by eta^2 on leaving;
// - a thin glass wall (one plane: no interior to refract into) in the same furnace is invisible
//   too: what it does not reflect (F) it transmits (1 - F) with no 1/eta^2, since light leaves the
//   glass again at once; against a uniform emitter behind it in the dark it transmits exactly
//   1 - F, 0.96 at normal incidence for ior 1.5;
// - an index-matched absorbing sphere (ior 1: no reflection, no bending) seen through its centre
//   transmits Beer-Lambert's exp(-sigma_a d), i.e. attenuationColor after attenuationDistance.
#include <gtest/gtest.h>

#include <cmath>

#include "render_helpers.h"
#include "scene/mesh_topology.h"
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

// A glass plane between the camera (at z = 3, looking down -z) and, with `backlight`, a uniform
// emitter of radiance 1 behind it in a black world; without, a white furnace.
Scene glass_pane(float roughness, bool backlight) {
    Scene s;
    s.meshes.push_back(test::make_quad(8.0f, Vec3(0, 0, 0)));
    Material glass;
    glass.name = "pane";
    glass.base_color = Rgb(1.0f);
    glass.metallic = 0;
    glass.roughness = roughness;
    glass.transmission = 1;
    glass.ior = 1.5f;
    glass.double_sided = true;
    s.materials.push_back(glass);
    s.meshes[0].material = 0;
    s.instances.push_back({0, Transform()});
    if (backlight) {
        s.meshes.push_back(test::make_quad(400.0f, Vec3(0, 0, -1)));
        s.materials.push_back(test::lambert(Rgb(0.0f), Rgb(1.0f)));
        s.meshes[1].material = 1;
        s.instances.push_back({1, Transform()});
        s.features.emissive_meshes = true;
    } else {
        s.environment.enabled = true;
        s.environment.color = Rgb(1.0f);
        s.features.environment = true;
    }
    s.cameras.push_back(test::camera_at(Vec3(0, 0, 3.0f), 0.1f));
    s.features.transmission = true;
    return s;
}

// What tells a glass solid from a thin wall: a boundary. Exporters split vertices along seams, so
// closedness is by position.
TEST(MeshTopology, SolidsAreClosedSheetsAreNot) {
    EXPECT_TRUE(is_closed_mesh(test::make_sphere(1.0f, Vec3(0, 0, 0), 12, 6)));
    EXPECT_FALSE(is_closed_mesh(test::make_quad(1.0f, Vec3(0, 0, 0))));
    // A cube with four corners per face (24 vertices, as an exporter writes flat faces).
    Mesh cube;
    const int faces[6][4][3] = {{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}, {{0, 0, 1}, {0, 1, 1}, {1, 1, 1}, {1, 0, 1}},
                                {{0, 0, 0}, {0, 0, 1}, {1, 0, 1}, {1, 0, 0}}, {{0, 1, 0}, {1, 1, 0}, {1, 1, 1}, {0, 1, 1}},
                                {{0, 0, 0}, {0, 1, 0}, {0, 1, 1}, {0, 0, 1}}, {{1, 0, 0}, {1, 0, 1}, {1, 1, 1}, {1, 1, 0}}};
    for (int f = 0; f < 6; ++f) {
        uint32_t b = static_cast<uint32_t>(cube.positions.size());
        for (int k = 0; k < 4; ++k) cube.positions.push_back(Vec3(faces[f][k][0], faces[f][k][1], faces[f][k][2]));
        cube.indices.insert(cube.indices.end(), {b, b + 1, b + 2, b, b + 2, b + 3});
    }
    EXPECT_TRUE(is_closed_mesh(cube));
    Mesh open_box = cube;
    open_box.indices.resize(open_box.indices.size() - 6);  // without its last face
    EXPECT_FALSE(is_closed_mesh(open_box));
}

class Transmission : public ::testing::TestWithParam<std::string> {};

TEST_P(Transmission, ThinGlassPaneVanishesInWhiteFurnace) {
    RenderStats stats;
    Image img = test::render(glass_pane(0.0f, false), 16, 16, GetParam(), 64, 0, 3, &stats);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(test::channel_mean(img, c), 1.0, test::tol(0.01)) << GetParam();
    EXPECT_EQ(stats.nonfinite_samples, 0u);
}

TEST_P(Transmission, ThinGlassPaneTransmitsOneMinusFresnel) {
    // Smooth: exactly 1 - F(0) = 1 - 0.04 (the camera's 0.1 rad field keeps F within 1e-4 of it).
    Image img = test::render(glass_pane(0.0f, true), 8, 16, GetParam(), 64, 0, 3);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(test::channel_mean(img, c), 0.96, test::tol(0.005)) << GetParam();
    // Rough (0.4): the transmitted lobe is the reflection lobe mirrored, so it still returns all
    // but the Fresnel share and the single-scattering GGX loss of a few percent; a wall that
    // refracted into an interior would give about 0.43.
    Image rough = test::render(glass_pane(0.4f, true), 8, 32, GetParam(), 64, 0, 3);
    for (int c = 0; c < 3; ++c) {
        EXPECT_GT(test::channel_mean(rough, c), 0.85) << GetParam();
        EXPECT_LT(test::channel_mean(rough, c), 0.97) << GetParam();
    }
}


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
