// Tangent-space normal maps: generated tangents follow the UVs as MikkTSpace's do, a flat map
// changes nothing, a constant tilted map tilts the shading normal by the angle it encodes, and no
// map turns the shading normal below the geometric surface. And light transport over them: the
// mapped normal is a microsurface facet (materials/normal_map_microsurface.h), so pt, bdpt and lt
// give the same image under every kind of light, and a white surface in a furnace stays white.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "integrators/surface_hit.h"
#include "render_helpers.h"
#include "scene/mesh_tangents.h"
#include "test_scenes.h"

namespace veach {
namespace {

// A quad in z = 0 facing +Z with glTF's image-like UVs: u grows along +X, v grows along -Y
// (v = 0 is the image's top row), so the normal map's +X is world +X and its +Y (green) world +Y.
Mesh uv_quad() {
    Mesh m;
    m.positions = {Vec3(-1, -1, 0), Vec3(1, -1, 0), Vec3(1, 1, 0), Vec3(-1, 1, 0)};
    m.normals = {Vec3(0, 0, 1), Vec3(0, 0, 1), Vec3(0, 0, 1), Vec3(0, 0, 1)};
    m.uv0 = {{0, 1}, {1, 1}, {1, 0}, {0, 0}};
    m.indices = {0, 1, 2, 0, 2, 3};
    m.material = 0;
    return m;
}

// The surface hit at the quad's centre, seen from above, with material `m` and its textures.
SurfaceHit quad_hit(const Material& m, const std::vector<Texture>& textures, float tangent_sign = 0.0f) {
    Scene s;
    s.meshes.push_back(uv_quad());
    if (tangent_sign != 0.0f) {  // as a file's TANGENT attribute
        s.meshes[0].tangents.assign(4, Vec3(1, 0, 0));
        s.meshes[0].tangent_signs.assign(4, tangent_sign);
    } else {
        generate_tangents(&s.meshes[0], 0);
    }
    s.materials.push_back(m);
    s.textures = textures;
    s.instances.push_back({0, Transform()});
    s.cameras.push_back(test::camera_at(Vec3(0, 0, 2)));
    RenderScene rs(s, &s.cameras[0], 8, 8);
    RayHit rh;
    EXPECT_TRUE(rs.accel().intersect(Vec3(0.1f, 0.2f, 2), Vec3(0, 0, -1), k_infinity, &rh));
    return make_surface_hit(rs, rh);
}

Texture texel(float r, float g, float b) {
    Texture t;
    t.width = t.height = 1;
    t.texels = {r, g, b, 1};
    return t;
}

// The shading normal at the quad's centre with a 1x1 normal texture of `texel`.
Vec3 shading_normal(float r, float g, float b, float scale = 1.0f, float tangent_sign = 0.0f) {
    Material m = test::lambert(Rgb(0.5f));
    m.normal_texture.texture = 0;
    m.normal_scale = scale;
    return quad_hit(m, {texel(r, g, b)}, tangent_sign).ns;
}

TEST(NormalMap, GeneratedTangentsFollowTheUvs) {
    Mesh m = uv_quad();
    generate_tangents(&m, 0);
    ASSERT_EQ(m.tangents.size(), 4u);
    for (size_t i = 0; i < 4; ++i) {
        EXPECT_NEAR(m.tangents[i].x, 1.0f, 1e-6f);
        EXPECT_NEAR(m.tangents[i].y, 0.0f, 1e-6f);
        EXPECT_EQ(m.tangent_signs[i], 1.0f);  // cross(n, t) = +Y = the direction of decreasing v
    }
    // Mirrored UVs (u grows along -X) flip the handedness, as MikkTSpace's sign does.
    for (Vec2& uv : m.uv0) uv.x = 1 - uv.x;
    generate_tangents(&m, 0);
    for (size_t i = 0; i < 4; ++i) {
        EXPECT_NEAR(m.tangents[i].x, -1.0f, 1e-6f);
        EXPECT_EQ(m.tangent_signs[i], -1.0f);
    }
}

TEST(NormalMap, FlatMapChangesNothing) {
    Vec3 n = shading_normal(0.5f, 0.5f, 1.0f);
    EXPECT_NEAR(n.x, 0.0f, 1e-6f);
    EXPECT_NEAR(n.y, 0.0f, 1e-6f);
    EXPECT_NEAR(n.z, 1.0f, 1e-6f);
}

// A texel encoding (sin a, 0, cos a) tilts the normal by a toward the tangent (+X); green tilts
// toward the bitangent (+Y); normalTexture.scale multiplies x and y, so tan a' = scale tan a.
TEST(NormalMap, ConstantTiltedMapTiltsByTheEncodedAngle) {
    const float a = 0.5f;
    Vec3 n = shading_normal((std::sin(a) + 1) / 2, 0.5f, (std::cos(a) + 1) / 2);
    EXPECT_NEAR(std::acos(n.z), a, 1e-4f);
    EXPECT_NEAR(n.x, std::sin(a), 1e-4f);
    EXPECT_NEAR(n.y, 0.0f, 1e-6f);
    Vec3 g = shading_normal(0.5f, (std::sin(a) + 1) / 2, (std::cos(a) + 1) / 2);
    EXPECT_NEAR(g.y, std::sin(a), 1e-4f);
    Vec3 scaled = shading_normal((std::sin(a) + 1) / 2, 0.5f, (std::cos(a) + 1) / 2, 2.0f);
    EXPECT_NEAR(std::atan2(scaled.x, scaled.z), std::atan(2 * std::tan(a)), 1e-4f);
    // A file's TANGENT with w = -1 turns green toward -Y.
    Vec3 flipped = shading_normal(0.5f, (std::sin(a) + 1) / 2, (std::cos(a) + 1) / 2, 1.0f, -1.0f);
    EXPECT_NEAR(flipped.y, -std::sin(a), 1e-4f);
}

TEST(NormalMap, NeverBelowTheGeometricSurface) {
    Vec3 n = shading_normal(1.0f, 0.5f, 0.0f);  // encodes (1, 0, -1): below the surface
    EXPECT_NEAR(length(n), 1.0f, 1e-5f);
    EXPECT_GE(n.z, 0.019f);
    EXPECT_GT(n.x, 0.99f);  // bent up, keeping its azimuth
}

// KHR_materials_clearcoat: clearcoatNormalTexture tilts the coat's normal (SurfaceHit::ns_coat)
// and leaves the base's; a base normal map does not apply to the coat, whose normal is then the
// vertex normal. Texture 0 encodes a tilt of a toward +X, texture 1 toward +Y.
TEST(NormalMap, ClearcoatHasItsOwnNormal) {
    const float a = 0.5f;
    const float t = (std::sin(a) + 1) / 2, z = (std::cos(a) + 1) / 2;
    auto hit_with = [&](bool base_map, bool coat_map) {
        Material m = test::lambert(Rgb(0.5f));
        m.clearcoat = 1.0f;
        if (base_map) m.normal_texture.texture = 0;
        if (coat_map) m.clearcoat_normal_texture.texture = 1;
        return quad_hit(m, {texel(t, 0.5f, z), texel(0.5f, t, z)});
    };
    SurfaceHit both = hit_with(true, true);
    EXPECT_NEAR(both.ns.x, std::sin(a), 1e-4f);
    EXPECT_NEAR(both.ns_coat.y, std::sin(a), 1e-4f);
    EXPECT_NEAR(both.ns_coat.x, 0.0f, 1e-5f);
    SurfaceHit coat_only = hit_with(false, true);
    EXPECT_NEAR(coat_only.ns.z, 1.0f, 1e-6f);
    EXPECT_NEAR(coat_only.ns_coat.y, std::sin(a), 1e-4f);
    SurfaceHit base_only = hit_with(true, false);
    EXPECT_NEAR(base_only.ns.x, std::sin(a), 1e-4f);
    EXPECT_NEAR(base_only.ns_coat.z, 1.0f, 1e-6f);  // the vertex normal, not the base's map
}

// A quad of side 0.6 at z = -1 facing the camera at the origin (0.5 rad field of view: 0.51
// across at the quad, so it fills the view and most particles from the lights land in view),
// Lambertian `albedo` (or `m`), with grooves tilted +-60 degrees about the v axis every four
// texels of a 64 x 4 map read NEAREST: the view holds about five grooves.
Scene grooved_quad(const Material& m) {
    Scene s;
    Mesh quad = test::make_quad(0.6f, Vec3(0, 0, -1));
    quad.uv0 = {{0, 1}, {0.6f, 1}, {0.6f, 0}, {0, 0}};
    quad.normals.assign(4, Vec3(0, 0, 1));
    quad.tangents.assign(4, Vec3(1, 0, 0));
    quad.tangent_signs.assign(4, 1.0f);
    quad.material = 0;
    s.meshes.push_back(quad);
    Material mat = m;
    mat.normal_texture.texture = static_cast<int>(s.textures.size());
    s.materials.push_back(mat);
    Texture grooves;
    grooves.name = "grooves";
    grooves.width = 64;
    grooves.height = 4;
    grooves.nearest = true;
    const float sn = std::sin(60.0f * k_pi / 180.0f), cn = std::cos(60.0f * k_pi / 180.0f);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 64; ++x) {
            float sx = (x / 4) % 2 == 0 ? sn : -sn;
            grooves.texels.insert(grooves.texels.end(), {(sx + 1) / 2, 0.5f, (cn + 1) / 2, 1.0f});
        }
    s.textures.push_back(grooves);
    s.instances.push_back({0, Transform()});
    s.cameras.push_back(test::camera_at(Vec3(0, 0, 0), 0.5f));
    s.features.normal_maps = true;
    return s;
}

void uniform_environment(Scene* s, float value) {
    s->environment.enabled = true;
    s->environment.color = Rgb(value);
    s->features.environment = true;
}

// A lat-long map brighter on one side (+x) and toward the horizon than above: the grooves'
// two facets see different light.
void environment_map(Scene* s) {
    Environment& env = s->environment;
    env.enabled = true;
    env.width = 16;
    env.height = 8;
    env.texels.clear();
    for (int y = 0; y < env.height; ++y)
        for (int x = 0; x < env.width; ++x) {
            float v = 0.05f + (x < env.width / 2 ? 0.6f : 0.1f) * (y == 3 || y == 4 ? 3.0f : 1.0f);
            env.texels.insert(env.texels.end(), {v, 0.9f * v, 0.7f * v});
        }
    s->features.environment = true;
}

// A sun 50 degrees from the zenith, across the grooves.
void sun(Scene* s) {
    PunctualLight l;
    l.name = "sun";
    l.type = LightType::Directional;
    l.intensity = Rgb(3.0f);
    const float a = 50.0f * k_pi / 180.0f;
    l.direction = Vec3(-std::sin(a), 0.0f, -std::cos(a));
    s->lights.push_back(l);
}

// An emissive square (double-sided) above and to the side of the quad, out of view.
void emissive_square(Scene* s) {
    Mesh lamp = test::make_quad(0.4f, Vec3(0.7f, 0.1f, -0.6f));
    lamp.material = static_cast<uint32_t>(s->materials.size());
    s->materials.push_back(test::lambert(Rgb(0.0f), Rgb(6.0f)));
    s->meshes.push_back(lamp);
    s->instances.push_back({static_cast<uint32_t>(s->meshes.size() - 1), Transform()});
}

// Block means (4 x 4 blocks of 16 x 16 pixels and the image mean) over `runs` renders with
// different seeds: their mean and standard error.
using BlockEstimate = test::RunEstimate;

BlockEstimate block_estimate(const Scene& s, const std::string& integrator, int spp, int runs, uint64_t seed) {
    std::vector<std::vector<double>> blocks;
    for (int r = 0; r < runs; ++r) {
        RenderStats stats;
        Image img = test::render(s, 16, spp, integrator, 16, 0, seed + r, &stats);
        EXPECT_EQ(stats.nonfinite_samples, 0u) << integrator;
        std::vector<double> b = test::block_means(img, 4);
        b.push_back((test::channel_mean(img, 0) + test::channel_mean(img, 1) + test::channel_mean(img, 2)) / 3);
        blocks.push_back(b);
    }
    return test::mean_and_standard_error(blocks);
}

// |z| of every block mean and the image mean of `b` against `a` below 4.5. The standard errors
// come from the runs themselves, so z follows Student's t (about 46 degrees of freedom for two
// sets of 24 runs), not a normal: 238 such tests in this file give a false alarm about once in 90
// runs of the suite. (Six runs and a bound of 4 failed about every other run: 5 degrees of
// freedom per side make |z| > 4 forty times likelier than a normal says.)
void expect_same_image(const BlockEstimate& a, const BlockEstimate& b, const std::string& what) {
    for (size_t k = 0; k < a.mean.size(); ++k) {
        const double z = (a.mean[k] - b.mean[k]) / std::sqrt(a.se[k] * a.se[k] + b.se[k] * b.se[k] + 1e-14);
        EXPECT_LT(std::fabs(z), 4.5) << what << (k + 1 == a.mean.size() ? " image" : " block ") << k << ": "
                                     << a.mean[k] << " vs " << b.mean[k];
    }
}

enum class Lighting { UniformEnvironment, EnvironmentMap, Sun, EmissiveSquare };

class NormalMapTransport : public ::testing::TestWithParam<Lighting> {};

// pt, bdpt and lt agree on the grooved Lambert quad under every kind of light: z-tests on block
// means over independent runs. With the mapped normal as a shading frame, light tracing needed
// Veach's adjoint factor |wo.ns| / |wo.ng|, unbounded for the grazing particles an environment
// sends: its variance was infinite and its mean 1-3% off at any affordable count.
TEST_P(NormalMapTransport, PtBdptAndLtAgree) {
    Scene s = grooved_quad(test::lambert(Rgb(0.8f, 0.6f, 0.4f)));
    switch (GetParam()) {
        case Lighting::UniformEnvironment: uniform_environment(&s, 0.2f); break;
        case Lighting::EnvironmentMap: environment_map(&s); break;
        case Lighting::Sun: sun(&s); break;
        case Lighting::EmissiveSquare: emissive_square(&s); break;
    }
    const int runs = 24;
    BlockEstimate pt = block_estimate(s, "pt", test::spp(32), runs, 100);
    BlockEstimate bdpt = block_estimate(s, "bdpt", test::spp(16), runs, 200);
    BlockEstimate lt = block_estimate(s, "lt", test::spp(128), runs, 300);
    EXPECT_GT(pt.mean.back(), 0.01);
    expect_same_image(pt, bdpt, "bdpt vs pt");
    expect_same_image(pt, lt, "lt vs pt");
    expect_same_image(bdpt, lt, "lt vs bdpt");
}

INSTANTIATE_TEST_SUITE_P(Lights, NormalMapTransport,
                         ::testing::Values(Lighting::UniformEnvironment, Lighting::EnvironmentMap, Lighting::Sun,
                                           Lighting::EmissiveSquare),
                         [](const ::testing::TestParamInfo<Lighting>& info) {
                             switch (info.param) {
                                 case Lighting::UniformEnvironment: return std::string("UniformEnvironment");
                                 case Lighting::EnvironmentMap: return std::string("EnvironmentMap");
                                 case Lighting::Sun: return std::string("Sun");
                                 case Lighting::EmissiveSquare: return std::string("EmissiveSquare");
                             }
                             return std::string("unknown");
                         });

// A white Lambert on 60-degree grooves in a uniform environment of 0.2 shows 0.2 in every
// integrator: the microsurface loses no light (the shading-normal frame showed 0.15, the
// directions above the mapped normal), and albedo 0.8 comes out darker than flat (0.16) by the
// light absorbed between the facets: 0.2 x 0.667 (the model's albedo at 60 degrees, measured in
// tests/materials/test_normal_map_microsurface.cpp).
TEST(NormalMapTransport, WhiteGroovesInAFurnace) {
    for (float albedo : {1.0f, 0.8f}) {
        Scene s = grooved_quad(test::lambert(Rgb(albedo)));
        uniform_environment(&s, 0.2f);
        const double expected = albedo == 1.0f ? 0.2 : 0.2 * 0.667;
        for (const char* integrator : {"pt", "bdpt", "lt"}) {
            RenderStats stats;
            Image img = test::render(s, 16, test::spp(std::string(integrator) == "lt" ? 2048 : 256), integrator, 16,
                                     0, 21, &stats);
            EXPECT_EQ(stats.nonfinite_samples, 0u);
            const double mean = test::channel_mean(img, 1);
            EXPECT_NEAR(mean, expected, test::tol(0.003)) << integrator << " albedo " << albedo;
            if (albedo == 1.0f) EXPECT_LE(mean, 0.2 + test::tol(0.0015)) << integrator;
        }
    }
    // Seen 50 degrees off the normal, across the grooves, half the facets face away from the view:
    // the shading-normal frame drew them black (lines along the grooves). Here every pixel of the
    // white furnace is the furnace's 0.2.
    Scene s = grooved_quad(test::lambert(Rgb(1.0f)));
    uniform_environment(&s, 0.2f);
    const float a = 50.0f * k_pi / 180.0f;
    s.cameras[0].camera_to_world = translation(Vec3(std::sin(a), 0, -1 + std::cos(a))) *
                                   rotation_quaternion(0, std::sin(a / 2), 0, std::cos(a / 2));
    // Columns run along the grooves: a black line would darken one; noise averages out over 32 rows.
    Image img = test::render(s, 32, test::spp(256), "pt", 16, 0, 23);
    for (int x = 0; x < img.width; ++x) {
        double column = 0;
        for (int y = 0; y < img.height; ++y) column += img.pixel(x, y)[1];
        EXPECT_NEAR(column / img.height, 0.2, test::tol(0.006)) << "column " << x;
    }
}

// A rough metal with the same grooves and a base-colour texture, under the environment map: the
// microsurface over a glossy lobe, textured, in the three integrators.
TEST(NormalMapTransport, TexturedRoughMetalUnderAnEnvironmentMap) {
    Material metal;
    metal.name = "metal";
    metal.base_color = Rgb(1.0f);
    metal.metallic = 1.0f;
    metal.roughness = 0.4f;
    Scene s = grooved_quad(metal);
    Texture base;
    base.name = "base";
    base.width = base.height = 8;
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x) {
            bool odd = ((x / 2 + y / 2) & 1) != 0;
            base.texels.insert(base.texels.end(), {odd ? 0.95f : 0.5f, odd ? 0.7f : 0.45f, odd ? 0.3f : 0.4f, 1.0f});
        }
    s.materials[0].base_color_texture.texture = static_cast<int>(s.textures.size());
    s.textures.push_back(base);
    environment_map(&s);
    const int runs = 24;
    BlockEstimate pt = block_estimate(s, "pt", test::spp(32), runs, 400);
    BlockEstimate bdpt = block_estimate(s, "bdpt", test::spp(16), runs, 500);
    BlockEstimate lt = block_estimate(s, "lt", test::spp(128), runs, 600);
    EXPECT_GT(pt.mean.back(), 0.01);
    expect_same_image(pt, bdpt, "bdpt vs pt");
    expect_same_image(pt, lt, "lt vs pt");
}

}  // namespace
}  // namespace veach
