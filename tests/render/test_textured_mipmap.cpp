// Mip-mapping driven by the camera's ray cone, on a checkerboard plane seen from just above it, so
// that the view sweeps from a magnified texture at the bottom of the image to thousands of texels
// a pixel at the horizon. Prefiltering may blur (a small bias where checks are near a pixel in
// size) but must keep the pixel means of a supersampled full-resolution render, and it must take
// the aliasing noise out of low sample counts.
#include <gtest/gtest.h>

#include <cmath>

#include "core/rng.h"
#include "integrators/surface_hit.h"
#include "materials/gltf_material.h"
#include "render_helpers.h"
#include "test_scenes.h"

namespace veach {
namespace {

constexpr int k_size = 48;

// The plane y = 0 (80 x 80 units in front of a camera 0.5 above it, looking along -Z) emitting
// an sRGB black and white checker: one texture repeat per 2 units, 8 x 8 checks of 8 texels.
// Emission only (black base), so a pixel's value is the filtered texture and nothing else.
Scene checker_plane(bool srgb = true) {
    Scene s;
    Mesh m;
    m.name = "plane";
    m.positions = {Vec3(-40, 0, 0), Vec3(40, 0, 0), Vec3(40, 0, -80), Vec3(-40, 0, -80)};
    for (const Vec3& p : m.positions) m.uv0.push_back({p.x / 2.0f, p.z / 2.0f});
    m.indices = {0, 1, 2, 0, 2, 3};
    m.material = 0;
    s.meshes.push_back(m);
    Material mat = test::lambert(Rgb(0.0f), Rgb(1.0f));
    mat.emissive_texture.texture = 0;
    s.materials.push_back(mat);
    Texture t;
    t.name = "checker";
    t.width = t.height = 64;
    t.srgb = srgb;
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x) {
            float v = ((x / 2 + y / 2) & 1) ? 1.0f : 0.0f;
            t.texels.insert(t.texels.end(), {v, v, v, 1.0f});
        }
    s.textures.push_back(t);
    s.instances.push_back({0, Transform()});
    s.cameras.push_back(test::camera_at(Vec3(0, 0.5f, 0), 1.0f));
    return s;
}

// Per-pixel mean and variance of single samples of the first hit's emission, film positions
// uniform in the pixel (a 1-pixel box filter, the render's default): the estimator the path
// tracer runs for this scene, with the ray cone switched on or off.
struct PixelStats {
    std::vector<double> mean, variance;
};

PixelStats first_hit_emission(const Scene& scene, int spp, bool cone, uint64_t seed) {
    RenderScene rs(scene, &scene.cameras[0], k_size, k_size);
    const CameraModel& camera = rs.camera();
    PixelStats out;
    out.mean.resize(k_size * k_size);
    out.variance.resize(k_size * k_size);
    for (int y = 0; y < k_size; ++y)
        for (int x = 0; x < k_size; ++x) {
            Rng rng(seed, static_cast<uint64_t>(y * k_size + x));
            double sum = 0, sum2 = 0;
            for (int s = 0; s < spp; ++s) {
                float fx = x + rng.next_float(), fy = y + rng.next_float();
                Vec3 o, d;
                camera.generate_ray(fx, fy, &o, &d);
                RayHit rh;
                double v = 0;
                if (rs.accel().intersect(o, d, k_infinity, &rh)) {
                    SurfaceHit hit = make_surface_hit(rs, rh, cone ? camera.footprint_width(rh.t, d) : 0.0f);
                    v = evaluate_emission(*hit.material, scene, hit.attr).r;
                }
                sum += v;
                sum2 += v * v;
            }
            size_t i = static_cast<size_t>(y) * k_size + x;
            out.mean[i] = sum / spp;
            out.variance[i] = std::max(0.0, sum2 / spp - out.mean[i] * out.mean[i]) * spp / (spp - 1);
        }
    return out;
}

// The plane fills the lower half of the image. Rows 25 to 27 see it 5.5 to 22 units away at
// grazing angles (cos 0.02 to 0.09), where a pixel's cone is over four texels wide: level 2 and
// coarser, where the 2-texel checks have averaged to a uniform 0.5.
constexpr int k_first_plane_row = k_size / 2;
constexpr int k_far_rows[2] = {25, 28};

double plane_average(const std::vector<double>& v, int row_begin = k_first_plane_row, int row_end = k_size) {
    double sum = 0;
    for (int y = row_begin; y < row_end; ++y)
        for (int x = 0; x < k_size; ++x) sum += v[static_cast<size_t>(y) * k_size + x];
    return sum / ((row_end - row_begin) * k_size);
}

// Trilinear prefiltering is a small bias where checks are near a pixel in size (it blurs them a
// little beyond the pixel's own box); far away it returns exactly the mean the supersampled
// render converges to. Allowed: the plane's mean within 5 standard errors of the two renders'
// noise (6e-4 each), and a per-pixel RMS bias, beyond the noise the two renders add, of 0.02 (4%
// of the mean 0.5). The cone widened by 1/sqrt(cos) or 1/cos (surface_hit.cpp) measures 0.04 and
// 0.10 on 8-texel checks and fails this bound; the minor-axis cone measures 0.008 here.
TEST(TexturedMipmap, PixelMeansAgreeWithASupersampledFullResolutionRender) {
    Scene scene = checker_plane(false);
    const int ref_spp = test::spp(1024), mip_spp = test::spp(256);
    PixelStats reference = first_hit_emission(scene, ref_spp, false, 1);
    PixelStats mip = first_hit_emission(scene, mip_spp, true, 2);
    EXPECT_NEAR(plane_average(mip.mean), plane_average(reference.mean), test::tol(0.003));
    std::vector<double> sq(mip.mean.size()), noise(mip.mean.size());
    for (size_t i = 0; i < sq.size(); ++i) {
        sq[i] = (mip.mean[i] - reference.mean[i]) * (mip.mean[i] - reference.mean[i]);
        noise[i] = reference.variance[i] / ref_spp + mip.variance[i] / mip_spp;
    }
    double bias2 = plane_average(sq) - plane_average(noise);
    EXPECT_LT(bias2, 0.02 * 0.02) << "rms difference " << std::sqrt(plane_average(sq)) << ", of which noise "
                                  << std::sqrt(plane_average(noise));
}

// The point of mip-mapping at low sample counts: a sample that reads a prefiltered texel carries
// less of the checkerboard's aliasing. Over the plane the variance of a single sample (and so of
// a 4-sample pixel) falls by more than 30% (measured 47%); where the cone covers whole checks it
// vanishes (full resolution: 0.11).
TEST(TexturedMipmap, AliasingNoiseFallsAtLowSampleCounts) {
    Scene scene = checker_plane(false);
    PixelStats full = first_hit_emission(scene, test::spp(64), false, 3);
    PixelStats mip = first_hit_emission(scene, test::spp(64), true, 3);
    EXPECT_LT(plane_average(mip.variance), 0.7 * plane_average(full.variance));
    EXPECT_LT(plane_average(mip.variance, k_far_rows[0], k_far_rows[1]), 1e-3);
    EXPECT_GT(plane_average(full.variance, k_far_rows[0], k_far_rows[1]), 0.05);
}

// sRGB textures are averaged as light: far away the checker reflects half of it, 0.5. (Level 0
// keeps Cycles' filtering of encoded values, which darkens every black-to-white edge, so a
// full-resolution supersampled render of an sRGB checker converges to less than 0.5: 0.453 with
// 8-texel checks; see README "Textures".)
TEST(TexturedMipmap, MinifiedSrgbTexturesShowTheirMeanRadiance) {
    Scene scene = checker_plane(true);
    PixelStats mip = first_hit_emission(scene, test::spp(16), true, 4);
    EXPECT_NEAR(plane_average(mip.mean, k_far_rows[0], k_far_rows[1]), 0.5, 1e-4);
}

// Both integrators give camera rays their cone: at 4 spp the far rows come out at the texture's
// mean, 0.5, within 0.01 (measured 0.005: samples low in row 27 still blend in level 1), where
// full-resolution lookups scatter a 4-sample pixel by about sqrt(0.11 / 4) = 0.17. BDPT is asked
// for its camera subpath's own strategy (s = 0, t = 2: the camera ray finds the emitter); light
// subpaths read full resolution, and light tracing's splats are noisy on an emitter this large.
TEST(TexturedMipmap, IntegratorsFilterWhatCameraRaysSee) {
    Scene scene = checker_plane(false);
    for (const char* integrator : {"pt", "bdpt"}) {
        bool bdpt = integrator[0] == 'b';
        for (uint64_t seed : {1, 2}) {
            Image img = test::render(scene, k_size, 4, integrator, 1, 0, seed, nullptr, bdpt ? 0 : -1, bdpt ? 2 : -1);
            double worst = 0;
            for (int y = k_far_rows[0]; y < k_far_rows[1]; ++y)
                for (int x = 0; x < k_size; ++x) worst = std::max(worst, std::fabs(img.pixel(x, y)[0] - 0.5));
            EXPECT_LT(worst, 0.01) << integrator << " seed " << seed;
        }
    }
}

// BDPT's light tracing of an emitter the camera sees (s = 1, t = 1) reads its emissive texture
// with the camera's footprint at the light point, as the camera ray does (s = 0, t = 2, and pt).
// An emissive square facing the camera across its view, with stripes 64 texels wide, about 27
// texels a pixel: the prefiltered level blurs them over a pixel, so lit columns come out dimmer
// and dark ones brighter than full-resolution lookups make them. Measured on 16 column means:
// (1, 1) alone, unweighted, reading full resolution differed from pt by up to 0.125; with the
// footprint they agree within 0.011 (allowed 0.02).
TEST(TexturedMipmap, LightTracingOfAnEmitterReadsTheCameraFootprint) {
    Scene s;
    Mesh quad = test::make_quad(0.6f, Vec3(0, 0, -1));
    quad.uv0 = {{0, 1}, {1, 1}, {1, 0}, {0, 0}};
    quad.material = 0;
    s.meshes.push_back(quad);
    Material mat = test::lambert(Rgb(0.0f), Rgb(1.0f));
    mat.double_sided = false;
    mat.emissive_texture.texture = 0;
    s.materials.push_back(mat);
    Texture stripes;
    stripes.name = "stripes";
    stripes.width = 512;
    stripes.height = 512;
    stripes.srgb = false;
    for (int y = 0; y < stripes.height; ++y)
        for (int x = 0; x < stripes.width; ++x) {
            float v = (x / 64) % 2 == 0 ? 1.0f : 0.0f;
            stripes.texels.insert(stripes.texels.end(), {v, v, v, 1.0f});
        }
    s.textures.push_back(stripes);
    s.instances.push_back({0, Transform()});
    s.cameras.push_back(test::camera_at(Vec3(0, 0, 0), 0.5f));
    const int size = 16;
    Image pt = test::render(s, size, test::spp(256), "pt", 1, 0, 91);
    Image lt = test::render(s, size, test::spp(2048), "bdpt", 1, 0, 92, nullptr, 1, 1);
    auto column_means = [&](const Image& img) {
        std::vector<double> c(size, 0.0);
        for (int y = 0; y < size; ++y)
            for (int x = 0; x < size; ++x) c[x] += img.pixel(x, y)[0] / size;
        return c;
    };
    std::vector<double> a = column_means(pt), b = column_means(lt);
    for (int x = 0; x < size; ++x) EXPECT_NEAR(b[x], a[x], test::tol(0.02)) << "column " << x;
}

}  // namespace
}  // namespace veach
