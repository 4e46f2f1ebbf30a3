// Alpha coverage (glTF alphaMode) for camera, shadow and light rays, against analytic answers.
#include <gtest/gtest.h>

#include <cmath>

#include "render_helpers.h"
#include "test_scenes.h"

namespace veach {
namespace {

Mesh quad(float half, float z, int material) {
    Mesh m;
    m.name = "quad";
    m.positions = {Vec3(-half, -half, z), Vec3(half, -half, z), Vec3(half, half, z), Vec3(-half, half, z)};
    m.uv0 = {{0, 1}, {1, 1}, {1, 0}, {0, 0}};
    m.indices = {0, 1, 2, 0, 2, 3};
    m.material = material;
    return m;
}

Image render_with(const Scene& scene, int size, int spp, const std::string& integrator) {
    RenderJobOptions o;
    o.width = o.height = size;
    o.render.integrator = integrator;
    o.render.spp = spp;
    o.render.seed = 5;
    return render_scene(scene, o).image;
}

double column_mean(const Image& img, int x0, int x1) {
    double s = 0;
    for (int y = 0; y < img.height; ++y)
        for (int x = x0; x < x1; ++x) s += img.pixel(x, y)[1];
    return s / (img.height * (x1 - x0));
}

// A black MASK quad whose texture alpha is 0 on its left half and 1 on its right, filling the
// view in front of a uniform environment L: camera rays pass where alpha < alphaCutoff and see
// L; elsewhere they stop on a surface that neither reflects nor emits.
TEST(AlphaMask, CameraRaysPassWhereAlphaIsBelowCutoff) {
    Scene s;
    s.meshes.push_back(quad(1.0f, 0.0f, 0));
    Material m = test::lambert(Rgb(0.0f));
    m.alpha_mode = AlphaMode::Mask;
    m.alpha_cutoff = 0.5f;
    m.base_color_texture.texture = 0;
    s.materials.push_back(m);
    Texture t;
    t.width = 2;
    t.height = 1;
    t.texels = {1, 1, 1, 0, 1, 1, 1, 1};  // RGBA: left texel alpha 0, right texel alpha 1
    t.nearest = true;
    t.wrap_s = t.wrap_t = WrapMode::ClampToEdge;
    s.textures.push_back(t);
    s.instances.push_back({0, Transform()});
    s.cameras.push_back(test::camera_at(Vec3(0, 0, 0.8f), 1.0f));
    s.environment.enabled = true;
    s.environment.color = Rgb(2.0f);
    s.features.environment = s.features.alpha = s.features.textures = true;
    for (const char* integrator : {"pt", "bdpt"}) {
        Image img = render_with(s, 16, 16, integrator);
        EXPECT_NEAR(column_mean(img, 0, 8), 2.0, 1e-4) << integrator;
        EXPECT_NEAR(column_mean(img, 8, 16), 0.0, 1e-4) << integrator;
    }
}

// An open receiver plane (albedo a) under a wide black occluder at height 0.5 that covers all
// but ~1e-4 of the receiver's projected solid angle, in a uniform environment L. The receiver's
// radiance is a L times the occluder's transmittance: 1 for MASK with alpha below the cutoff,
// 0 for MASK above it, 1 - alpha for BLEND (stochastic opacity). Shadow rays (next-event
// estimation), BSDF-sampled rays and light subpaths (bdpt) all have to see through it alike.
struct Cover {
    AlphaMode mode;
    float alpha;
    double transmittance;
};

class AlphaOccluder : public ::testing::TestWithParam<std::tuple<std::string, int>> {};

TEST_P(AlphaOccluder, ReceiverSeesTheEnvironmentThroughIt) {
    const auto [integrator, which] = GetParam();
    const Cover covers[] = {{AlphaMode::Mask, 0.3f, 1.0},
                            {AlphaMode::Mask, 0.8f, 0.0},
                            {AlphaMode::Blend, 0.5f, 0.5},
                            {AlphaMode::Blend, 0.5f, 0.5}};
    const Cover& c = covers[which];
    const float a = 0.6f, l = 1.5f;
    Scene s;
    s.meshes.push_back(quad(0.45f, 0.0f, 0));
    s.meshes.push_back(quad(50.0f, 0.5f, 1));
    s.materials.push_back(test::lambert(Rgb(a)));
    Material occ = test::lambert(Rgb(0.0f));
    occ.alpha_mode = c.mode;
    occ.base_alpha = c.alpha;
    s.materials.push_back(occ);
    s.instances.push_back({0, Transform()});
    s.instances.push_back({1, Transform()});
    // Case 3: the occluder placed twice (the second copy far below, out of the way), so Embree
    // instances it and the filter runs on the instanced geometry.
    if (which == 3) s.instances.push_back({1, translation(Vec3(0, 0, -10))});
    s.cameras.push_back(test::camera_at(Vec3(0, 0, 0.3f), 1.0f));
    s.environment.enabled = true;
    s.environment.color = Rgb(l);
    s.features.environment = s.features.alpha = true;
    Image img = render_with(s, 16, 64, integrator);
    double expected = a * l * c.transmittance;
    EXPECT_NEAR(test::channel_mean(img, 1), expected, 0.015 * a * l) << integrator << " case " << which;
}

INSTANTIATE_TEST_SUITE_P(Cases, AlphaOccluder,
                         ::testing::Combine(::testing::Values("pt", "bdpt"), ::testing::Values(0, 1, 2, 3)));

}  // namespace
}  // namespace veach
