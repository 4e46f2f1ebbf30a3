// BDPT's reusable pieces, each against what its job requires: the density conversions against
// the analytic change of measure and the light sampler's own densities; the random walk's
// throughput and Russian roulette unbiased (a white furnace's bounce-by-bounce expectation, the
// light start's emitted power); and the MIS weights of every strategy that can make one path
// summing to one (where bidirectional MIS bugs hide).
#include <gtest/gtest.h>

#include <cmath>
#include <variant>
#include <vector>

#include "importers/importer.h"
#include "integrators/bdpt/mis_weight.h"
#include "integrators/bdpt/subpaths.h"
#include "integrators/bdpt/vertex_densities.h"
#include "render_helpers.h"
#include "test_scenes.h"

namespace veach {
namespace {

TEST(BdptPieces, AreaDensityIsSolidAngleDensityTimesCosOverDistanceSquared) {
    PathVertex from, to;
    from.p = Vec3(0, 0, 0);
    to.p = Vec3(0, 3, 4);  // distance 5
    EXPECT_FLOAT_EQ(to_area_density(2.0f, from, to), 2.0f / 25.0f);  // no surface: no cosine
    to.has_normal = true;
    to.ng = Vec3(0, -1, 0);  // cos = 3/5
    EXPECT_FLOAT_EQ(to_area_density(2.0f, from, to), 2.0f / 25.0f * 0.6f);
    to.infinite = true;  // directions are the measure at infinity
    EXPECT_FLOAT_EQ(to_area_density(2.0f, from, to), 2.0f);
    to.infinite = false;
    to.p = from.p;
    EXPECT_EQ(to_area_density(2.0f, from, to), 0.0f);
    EXPECT_EQ(remap0(0.0f), 1.0f);
    EXPECT_EQ(remap0(0.25f), 0.25f);
}

TEST(BdptPieces, LightVertexDensitiesAreTheEmissionSamplers) {
    const Scene scene = import_scene(std::string(VEACH_EXAMPLES_DIR) + "/cornell/cornell.gltf");
    RenderScene rs(scene, &scene.cameras.at(0), 16, 16);
    const LightSet& lights = rs.lights();
    Rng rng(3, 9);
    int checked = 0;
    for (int i = 0; i < 200; ++i) {
        LightEmission e;
        if (!lights.sample_emission(rng.next_float(), rng.next_float(), rng.next_float(), rng.next_float(),
                                    rng.next_float(), &e))
            continue;
        PathVertex l;
        l.reset_endpoint(PathVertex::Kind::Light);
        l.light = e.light;
        l.p = e.point;
        l.ng = e.normal;
        l.has_normal = true;
        const float pmf = lights.selection_pmf(e.light);
        EXPECT_NEAR(light_origin_pdf_a(lights, l, e.dir) / (pmf * e.pdf_pos_a), 1.0f, 1e-5f);
        // A receiver 2 units along the particle, facing back at 30 degrees.
        PathVertex r;
        r.p = e.point + e.dir * 2.0f;
        r.has_normal = true;
        Vec3 side = normalize(cross(e.dir, std::fabs(e.dir.x) < 0.9f ? Vec3(1, 0, 0) : Vec3(0, 1, 0)));
        r.ng = -e.dir * std::cos(k_pi / 6) + side * std::sin(k_pi / 6);
        const float expected = e.pdf_dir_w / 4.0f * std::cos(k_pi / 6);
        EXPECT_NEAR(light_emission_pdf_area(lights, l, r) / expected, 1.0f, 1e-4f);
        ++checked;
    }
    EXPECT_GT(checked, 100);
}

// A closed Lambertian sphere of albedo a seen from inside, with a small emissive square behind
// the camera facing +z, away from it: no ray escapes, and each bounce multiplies the expected
// throughput by a.
struct Furnace {
    static constexpr float albedo = 0.6f;
    Scene scene;
    Furnace() {
        scene.meshes.push_back(test::make_sphere(5.0f, Vec3(0, 0, 0), 48, 24));
        scene.meshes[0].material = 0;
        scene.materials.push_back(test::lambert(Rgb(albedo)));
        Material emitter = test::lambert(Rgb(0.0f), Rgb(2.0f));
        emitter.double_sided = false;
        scene.materials.push_back(emitter);
        Mesh q = test::make_quad(0.5f, Vec3(0, 0, 1));
        q.material = 1;
        scene.meshes.push_back(q);
        scene.instances.push_back({0, Transform()});
        scene.instances.push_back({1, Transform()});
        scene.cameras.push_back(test::camera_at(Vec3(0, 0, 0.5f), 1.0f));
    }
};

TEST(BdptPieces, RandomWalkThroughputIsUnbiasedBounceByBounce) {
    Furnace f;
    RenderScene rs(f.scene, &f.scene.cameras[0], 8, 8);
    ThreadStats stats;
    SubpathContext ctx{&rs, &rs.lights(), &rs.camera(), 0.0f, &stats};
    const int max_depth = 12, n = test::spp(40000);
    std::vector<PathVertex> path(max_depth + 2);
    std::vector<double> sum(max_depth + 2, 0.0), sum2(max_depth + 2, 0.0);
    for (int i = 0; i < n; ++i) {
        Sampler rng(SamplerKind::Random, 17, 0, static_cast<uint64_t>(i));
        const int count = trace_camera_subpath(ctx, path, 4.0f, 4.0f, max_depth, rng);
        for (int k = 1; k < count; ++k) {
            if (path[k].instance != 0) break;  // found the emitter square: the walk goes on past it
            sum[k] += path[k].beta.g;
            sum2[k] += static_cast<double>(path[k].beta.g) * path[k].beta.g;
        }
    }
    // Vertex k >= 1 carries a^(k-1) in expectation, roulette or not (paths meeting the small
    // square are a few percent, counted as zero: compared one-sided at that rate).
    for (int k = 1; k <= 8; ++k) {
        const double mean = sum[k] / n, var = sum2[k] / n - mean * mean;
        const double expected = std::pow(Furnace::albedo, k - 1);
        const double se = std::sqrt(std::max(var, 1e-12) / n);
        EXPECT_LT(mean, expected + 4.5 * se) << "vertex " << k;
        EXPECT_GT(mean, 0.9 * expected - 4.5 * se) << "vertex " << k;
    }
}

TEST(BdptPieces, LightSubpathStartsWithTheEmittedPower) {
    Furnace f;
    RenderScene rs(f.scene, &f.scene.cameras[0], 8, 8);
    ThreadStats stats;
    SubpathContext ctx{&rs, &rs.lights(), &rs.camera(), 0.0f, &stats};
    std::vector<PathVertex> path(4);
    const int n = test::spp(40000);
    double sum = 0, sum2 = 0;
    for (int i = 0; i < n; ++i) {
        Sampler rng(SamplerKind::Random, 23, 0, static_cast<uint64_t>(i));
        if (trace_light_subpath(ctx, path, 2, rng) < 2) continue;
        sum += path[1].beta.g;
        sum2 += static_cast<double>(path[1].beta.g) * path[1].beta.g;
    }
    // A one-sided Lambertian emitter of radiance L and area A sends out pi L A; every particle
    // meets the sphere.
    const double mean = sum / n, se = std::sqrt(std::max(0.0, sum2 / n - mean * mean) / n);
    const double power = k_pi * 2.0 * 0.25;
    EXPECT_LT(std::fabs(mean - power), 4.5 * se + 1e-5 * power) << mean << " vs " << power;
}

// The path a camera subpath found, ending on an emitter, seen as the light subpath of s vertices
// joined to the camera subpath of t = n - s: the light side's forward densities are what a light
// subpath would have sampled, its reverse densities the camera walk's forward ones.
std::vector<PathVertex> as_light_subpath(const LightSet& lights, const std::vector<PathVertex>& full, int n, int s) {
    std::vector<PathVertex> light(static_cast<size_t>(std::max(s, 1)));
    for (int i = 0; i < s; ++i) {
        const PathVertex& v = full[n - 1 - i];
        PathVertex& l = light[i];
        l = v;
        l.pdf_rev = v.pdf_fwd;
        if (i == 0) {
            l.reset_endpoint(PathVertex::Kind::Light);
            l.light = v.light;
            l.p = v.p;
            l.ng = v.ng;
            l.has_normal = true;
            l.pdf_rev = v.pdf_fwd;
            l.pdf_fwd = light_origin_pdf_a(lights, l, normalize(full[n - 2].p - v.p));
        } else if (i == 1) {
            l.pdf_fwd = light_emission_pdf_area(lights, light[0], l);
        } else {
            const PathVertex& prev = light[i - 1];
            const Vec3 wo = normalize(light[i - 2].p - prev.p), wi = normalize(l.p - prev.p);
            l.pdf_fwd = to_area_density(prev.bsdf.pdf_w(wo, wi), prev, l);
        }
    }
    return light;
}

TEST(BdptPieces, MisWeightsOfEveryStrategyOfAPathSumToOne) {
    const Scene scene = import_scene(std::string(VEACH_EXAMPLES_DIR) + "/cornell/cornell.gltf");
    RenderScene rs(scene, &scene.cameras.at(0), 32, 32);
    const LightSet& lights = rs.lights();
    ThreadStats stats;
    SubpathContext ctx{&rs, &lights, &rs.camera(), 0.0f, &stats};
    const int max_depth = 6;
    std::vector<PathVertex> full(max_depth + 2);
    int paths = 0;
    for (uint64_t i = 0; i < 20000 && paths < 300; ++i) {
        Sampler rng(SamplerKind::Random, 5, i % 1024, i);
        const float fx = 1.0f + static_cast<float>(i % 30), fy = 1.0f + static_cast<float>((i / 30) % 30);
        const int count = trace_camera_subpath(ctx, full, fx + 0.5f, fy + 0.5f, max_depth, rng);
        // The first emitter the walk found ends the path (n vertices, camera included).
        int n = 0;
        for (int k = 2; k < count; ++k)
            if (full[k].light >= 0) {
                n = k + 1;
                break;
            }
        if (n < 3) continue;  // the camera seeing the light directly has one strategy left (s = 0)
        bool any_delta = false;
        for (int k = 0; k < n; ++k) any_delta |= full[k].delta;
        if (any_delta) continue;
        double total = 0;
        for (int s = 0; s < n; ++s) {
            const int t = n - s;
            std::vector<PathVertex> light = as_light_subpath(lights, full, n, s);
            std::vector<PathVertex> camera(full.begin(), full.begin() + t);
            if (t == 1 && !(rs.camera().importance(normalize(light[s - 1].p - camera[0].p)) > 0.0f)) {
                ADD_FAILURE() << "a camera path's first vertex is in view";
                continue;
            }
            total += mis_weight(lights, rs.camera(), light, s, camera, t, nullptr);
        }
        EXPECT_NEAR(total, 1.0, 1e-4) << "path of " << n << " vertices";
        ++paths;
    }
    EXPECT_GE(paths, 100);
}

}  // namespace
}  // namespace veach
