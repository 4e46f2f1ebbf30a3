// Numerical stress: the arithmetic must hold at every scale a scene can have and for every
// extreme a material, a light or a camera can take. Every render here must finish with zero
// non-finite samples; each test also states what the physics requires of the image.
//
// VEACH_TEST_SPP_DIVISOR=N (make test-sanitize sets it) divides the sample counts, for builds
// whose rays cost ten times more (sanitizers); tolerances widen by sqrt(N), as the noise does.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <string>

#include "../render/render_helpers.h"
#include "../render/test_scenes.h"
#include "importers/importer.h"
#include "scene/scene_repair.h"

namespace veach {
namespace {

int spp_divisor() {
    const char* e = std::getenv("VEACH_TEST_SPP_DIVISOR");
    int d = e ? std::atoi(e) : 1;
    return d > 1 ? d : 1;
}
int spp(int n) { return std::max(1, n / spp_divisor()); }
double tol(double t) { return t * std::sqrt(static_cast<double>(spp_divisor())); }

Scene cornell() { return import_scene(std::string(VEACH_EXAMPLES_DIR) + "/cornell/cornell.gltf"); }

// The whole scene, camera included, moved by `to_world` (a similarity): the image must not change.
void transform_scene(Scene& s, const Transform& to_world) {
    for (Instance& inst : s.instances) inst.object_to_world = to_world * inst.object_to_world;
    for (Camera& c : s.cameras) c.camera_to_world = to_world * c.camera_to_world;
    for (PunctualLight& l : s.lights) l.position = to_world.point(l.position);
}

struct Rendered {
    Image image;
    RenderStats stats;
};

Rendered render(const Scene& s, int size, int n_spp, int max_depth = 64, const std::string& integrator = "pt") {
    Rendered r;
    r.image = test::render(s, size, n_spp, integrator, max_depth, 0, 1, &r.stats);
    return r;
}

void expect_finite(const Rendered& r) {
    EXPECT_EQ(r.stats.nonfinite_samples, 0u);
    for (float v : r.image.rgba) ASSERT_TRUE(std::isfinite(v));
}

double image_mean(const Image& img) {
    return (test::channel_mean(img, 0) + test::channel_mean(img, 1) + test::channel_mean(img, 2)) / 3.0;
}

// --- Scale -----------------------------------------------------------------------------------

class CornellScale : public ::testing::TestWithParam<std::pair<float, float>> {};

// Ray offsets come from the hit point's floating-point error bound, relative to its coordinates,
// so no length in the renderer depends on the scene's size: scaled by s or moved by d, the
// cornell box renders the same image (16x16 block means within 3%).
TEST_P(CornellScale, RendersTheSameImage) {
    static const Rendered reference = render(cornell(), 64, spp(64));
    auto [scale, offset] = GetParam();
    Scene s = cornell();
    transform_scene(s, translation(Vec3(offset, offset, offset)) * scaling(Vec3(scale, scale, scale)));
    // As the `veach` command does before rendering: a scene far from the origin is moved to it.
    Vec3 moved = rebase_scene(s);
    EXPECT_EQ(moved.x != 0.0f, offset != 0.0f);
    Rendered r = render(s, 64, spp(64));
    expect_finite(r);
    test::ImageComparison c = test::compare_images(r.image, reference.image, 16);
    for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(c.mean_ratio[ch], 1.0, tol(0.01)) << "channel " << ch;
    EXPECT_LT(c.worst_block, tol(0.03));
}

std::string scale_case_name(const ::testing::TestParamInfo<std::pair<float, float>>& info) {
    static const char* names[] = {"Scale1em4", "Scale1em2", "Scale1e2", "Scale1e4", "Offset1e5"};
    return names[info.index];
}

INSTANTIATE_TEST_SUITE_P(Robustness, CornellScale,
                         ::testing::Values(std::pair{1e-4f, 0.0f}, std::pair{1e-2f, 0.0f}, std::pair{1e2f, 0.0f},
                                           std::pair{1e4f, 0.0f}, std::pair{1.0f, 1e5f}),
                         scale_case_name);

// --- Degenerate geometry ---------------------------------------------------------------------

// The cornell box with garbage added to every mesh: NaN/Inf corners, zero-area, collinear and
// repeated-corner triangles, coincident duplicate faces, broken normals and UVs. After repair
// the image must be the clean box's: nothing that was valid was lost, nothing invalid shows.
TEST(DegenerateGeometry, RepairedSceneRendersLikeTheCleanOne) {
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    Scene clean = cornell();
    Scene dirty = cornell();
    for (Mesh& m : dirty.meshes) {
        uint32_t base = static_cast<uint32_t>(m.positions.size());
        m.positions.insert(m.positions.end(),
                           {{nan, 0, 0}, {0, inf, 0}, {0.1f, 0.1f, 0.1f}, {0.2f, 0.2f, 0.2f}, {0.4f, 0.4f, 0.4f}});
        if (!m.normals.empty())
            m.normals.insert(m.normals.end(), {{nan, 0, 0}, {0, 0, 0}, {0, 0, 0}, {0, 3, 0}, {0, 1, 0}});
        if (!m.uv0.empty()) m.uv0.insert(m.uv0.end(), {{nan, 0}, {inf, 0}, {0, 0}, {0, 0}, {0, 0}});
        if (!m.colors.empty()) m.colors.insert(m.colors.end(), 5, Rgba{1, 1, 1, 1});
        uint32_t a = m.indices[0], b = m.indices[1], c = m.indices[2];
        m.indices.insert(m.indices.end(), {base, a, b,                    // NaN corner
                                           base + 1, b, c,                // infinite corner
                                           base + 2, base + 2, a,         // repeated corner
                                           base + 2, base + 3, base + 4,  // collinear
                                           c, b, a,                       // a coincident copy, flipped
                                           a, a, a});
    }
    RepairCounts counts = repair_scene(dirty);
    EXPECT_GE(counts.nonfinite_triangles, 2 * dirty.meshes.size());
    EXPECT_GE(counts.degenerate_triangles, 3 * dirty.meshes.size());
    EXPECT_EQ(counts.duplicate_triangles, dirty.meshes.size());
    ASSERT_EQ(dirty.warnings.size(), 1u);

    Rendered ref = render(clean, 32, spp(32));
    Rendered r = render(dirty, 32, spp(32));
    expect_finite(r);
    test::ImageComparison c = test::compare_images(r.image, ref.image, 16);
    EXPECT_LT(c.worst_block, tol(0.03));
}

// Without repair the renderer itself must still not produce a NaN from broken normals.
TEST(DegenerateGeometry, UnrepairedBrokenNormalsGiveNoNaN) {
    Scene s = cornell();
    for (Mesh& m : s.meshes)
        for (size_t i = 0; i < m.normals.size(); i += 2) m.normals[i] = i % 4 ? Vec3(0, 0, 0) : Vec3(NAN, 0, 0);
    expect_finite(render(s, 16, spp(8)));
}

// --- Extreme materials and lights ------------------------------------------------------------

Material& material_named(Scene& s, const std::string& name) {
    for (Material& m : s.materials)
        if (m.name == name) return m;
    throw std::runtime_error("no material " + name);
}

// The tall box takes material `m` (a new one, so the walls keep theirs).
Scene cornell_with_tall_box(const Material& m) {
    Scene s = cornell();
    s.materials.push_back(m);
    for (size_t i = 0; i < s.meshes.size(); ++i)
        if (s.meshes[i].name.find("tall") != std::string::npos || i == 6)
            s.meshes[i].material = int32_t(s.materials.size() - 1);
    return s;
}

struct MaterialCase {
    const char* name;
    float metallic, roughness, ior, transmission;
};

class ExtremeMaterials : public ::testing::TestWithParam<MaterialCase> {};

// Smooth and rough limits, index-matched and near-index-matched glass, a very dense dielectric:
// every one ends its paths, produces no non-finite sample, and, as no material creates energy in
// a scene lit only from inside it, the image is not brighter than with a white Lambertian box
// with a 5% allowance for noise.
TEST_P(ExtremeMaterials, RenderFiniteAndDoNotCreateEnergy) {
    MaterialCase mc = GetParam();
    Material m = test::lambert(Rgb(0.8f));
    m.metallic = mc.metallic;
    m.roughness = mc.roughness;
    m.ior = mc.ior;
    m.specular = 1;
    m.transmission = mc.transmission;
    Rendered r = render(cornell_with_tall_box(m), 32, spp(32));
    expect_finite(r);
    Material white = test::lambert(Rgb(1.0f));
    Rendered bound = render(cornell_with_tall_box(white), 32, spp(32));
    EXPECT_LT(image_mean(r.image), image_mean(bound.image) * (1.0 + tol(0.05)));
    EXPECT_GT(image_mean(r.image), 0.0);
}

INSTANTIATE_TEST_SUITE_P(Robustness, ExtremeMaterials,
                         ::testing::Values(MaterialCase{"MirrorRoughness0", 1, 0, 1.5f, 0},
                                           MaterialCase{"DielectricRoughness0", 0, 0, 1.5f, 0},
                                           MaterialCase{"Roughness1", 1, 1, 1.5f, 0},
                                           MaterialCase{"GlassIor1", 0, 0, 1.0f, 1},
                                           MaterialCase{"GlassIor1_0001", 0, 0, 1.0001f, 1},
                                           MaterialCase{"GlassIor3", 0, 0, 3.0f, 1},
                                           MaterialCase{"RoughGlassIor1_0001", 0, 0.5f, 1.0001f, 1},
                                           MaterialCase{"Ior1Opaque", 0, 0.3f, 1.0f, 0}),
                         [](const auto& info) { return std::string(info.param.name); });

// Radiance is linear in emission: scaling the only light by 1e6 or 1e-6 scales the image by
// the same factor, sample for sample (the same random numbers trace the same paths).
TEST(ExtremeLights, EmissionScalesTheImageLinearly) {
    Rendered base = render(cornell(), 32, spp(8));
    for (float k : {1e6f, 1e-6f}) {
        Scene s = cornell();
        Material& light = material_named(s, "light");
        light.emission = light.emission * k;
        Rendered r = render(s, 32, spp(8));
        expect_finite(r);
        for (int ch = 0; ch < 3; ++ch)
            EXPECT_NEAR(test::channel_mean(r.image, ch) / (k * test::channel_mean(base.image, ch)), 1.0, 1e-3)
                << "scale " << k << " channel " << ch;
    }
}

PunctualLight point_light(Vec3 p, float intensity) {
    PunctualLight l;
    l.type = LightType::Point;
    l.position = p;
    l.intensity = Rgb(intensity);
    return l;
}

// A point light exactly on the floor: the floor under it receives light at grazing incidence
// (cos = 0) and points next to it 1/r^2 -> infinity; neither may become a NaN or an infinity.
TEST(ExtremeLights, PointLightLyingOnASurface) {
    Scene s = cornell();
    s.lights.push_back(point_light(Vec3(0.0f, 0.0f, 0.0f), 5.0f));   // on the floor (y = 0)
    s.lights.push_back(point_light(Vec3(0.3f, 0.0f, -1.0f), 5.0f));  // in the back corner
    expect_finite(render(s, 32, spp(16)));
    expect_finite(render(s, 16, spp(4), 64, "bdpt"));
}

// A spot with a zero cone emits nothing: the image is the scene's without it.
TEST(ExtremeLights, SpotWithZeroConeAddsNothing) {
    Scene s = cornell();
    PunctualLight spot = point_light(Vec3(0, 1.5f, 0), 100.0f);
    spot.type = LightType::Spot;
    spot.direction = Vec3(0, -1, 0);
    spot.cos_outer = spot.cos_inner = 1.0f;
    s.lights.push_back(spot);
    Rendered r = render(s, 32, spp(32));
    expect_finite(r);
    Rendered ref = render(cornell(), 32, spp(32));
    EXPECT_LT(test::compare_images(r.image, ref.image, 16).worst_block, tol(0.05));
    expect_finite(render(s, 16, spp(4), 64, "bdpt"));
}

// A closed white furnace: every surface emits Le and reflects all of it (albedo exactly 1).
// Russian roulette never fires (throughput stays 1), so the depth limit ends every path, and
// the radiance is exactly the Neumann series cut after D bounces: L = (D + 1) Le.
TEST(ExtremeMaterials, ClosedAlbedoOneBoxEndsAtTheDepthLimitWithTheExactValue) {
    for (int depth : {4, 64}) {
        Scene s;
        s.meshes.push_back(test::make_sphere(1.0f, Vec3(0, 0, 0), 24, 12));
        s.materials.push_back(test::lambert(Rgb(1.0f), Rgb(0.25f)));
        s.meshes[0].material = 0;
        s.instances.push_back({0, Transform()});
        s.cameras.push_back(test::camera_at(Vec3(0.1f, -0.2f, 0.05f)));
        Rendered r = render(s, 16, spp(16), depth);
        expect_finite(r);
        double expected = 0.25 * (depth + 1);
        EXPECT_NEAR(image_mean(r.image), expected, tol(0.01) * expected) << "depth " << depth;
    }
}

// --- Cameras and rays ------------------------------------------------------------------------

// Inside the closed tall box no light reaches the camera: the image is exactly black. A ray
// offset that is too small (self-hits) or too large (leaking through the walls) shows here.
TEST(CamerasAndRays, CameraInsideClosedGeometrySeesBlack) {
    Scene s = cornell();
    s.cameras[0].camera_to_world = translation(Vec3(-0.35f, 0.6f, -0.3f));
    Rendered r = render(s, 16, spp(8));
    expect_finite(r);
    EXPECT_EQ(image_mean(r.image), 0.0);
}

// A camera in the plane of the floor, looking along it: primary rays graze the floor at every
// angle down to zero. The far wall is still seen and lit; nothing becomes a NaN.
TEST(CamerasAndRays, GrazingRaysAlongTheFloor) {
    Scene s = cornell();
    s.cameras[0].camera_to_world = translation(Vec3(0.0f, 0.0f, 0.9f));
    Rendered r = render(s, 32, spp(8));
    expect_finite(r);
    EXPECT_GT(image_mean(r.image), 0.0);
    expect_finite(render(s, 16, spp(2), 64, "bdpt"));
}

// An empty scene (no geometry, no light, no camera) renders black, for every integrator.
TEST(CamerasAndRays, EmptySceneRendersBlack) {
    Scene s;
    for (const char* integrator : {"pt", "bdpt", "lt"}) {
        Rendered r = render(s, 8, 2, 8, integrator);
        expect_finite(r);
        EXPECT_EQ(image_mean(r.image), 0.0) << integrator;
    }
}

// No light at all: lit by a uniform white world (radiance 1) as glTF viewers do; a camera ray
// that escapes sees exactly radiance 1.
TEST(CamerasAndRays, SceneWithoutLightsIsLitByAWhiteWorld) {
    Scene s;
    s.meshes.push_back(test::make_sphere(1.0f, Vec3(0, 0, -5), 24, 12));
    s.materials.push_back(test::lambert(Rgb(0.5f)));
    s.meshes[0].material = 0;
    s.instances.push_back({0, Transform()});
    s.cameras.push_back(test::camera_at(Vec3(0, 0, 0), 1.2f));
    ASSERT_TRUE(light_unlit_scene(s));
    Rendered r = render(s, 32, spp(64));
    expect_finite(r);
    const float* corner = r.image.pixel(0, 0);  // misses the sphere: the sky itself
    EXPECT_NEAR(corner[0], 1.0f, 1e-4f);
    // A convex Lambertian body under a white sky sees the sky over its whole hemisphere, so its
    // radiance is albedo x 1 everywhere (the furnace argument): the central 4x4 pixels' mean
    // (the sphere's image is 4.7 pixels in radius).
    double centre = 0;
    for (int y = 14; y < 18; ++y)
        for (int x = 14; x < 18; ++x)
            centre += (r.image.pixel(x, y)[0] + r.image.pixel(x, y)[1] + r.image.pixel(x, y)[2]) / 3.0;
    EXPECT_NEAR(centre / 16.0, 0.5, tol(0.02));
}

}  // namespace
}  // namespace veach
