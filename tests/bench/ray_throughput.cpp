// The ray-tracing limit of a scene: incoherent closest-hit rays per second that Embree alone
// traces through the renderer's own BVH (accel/Accel), with origins uniform on the surfaces and
// cosine-distributed directions, on the threads asked for. `make bench` divides the renderer's
// rays/s by this number.
//   veach_ray_bench SCENE [--threads N] [--seconds S]
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "accel/embree_accel.h"
#include "core/rng.h"
#include "core/sampling.h"
#include "importers/importer.h"

using namespace veach;

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: veach_ray_bench SCENE [--threads N] [--seconds S]\n");
        return 1;
    }
    int threads = 0;
    double seconds = 2.0;
    for (int i = 2; i + 1 < argc; i += 2) {
        std::string a = argv[i];
        if (a == "--threads")
            threads = std::atoi(argv[i + 1]);
        else if (a == "--seconds")
            seconds = std::atof(argv[i + 1]);
    }
    Scene scene;
    try {
        scene = import_scene(argv[1]);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "veach_ray_bench: %s\n", e.what());
        return 2;
    }
    Accel accel(scene);
    // Every instanced triangle, chosen by area.
    struct Tri {
        Vec3 p0, e1, e2, n;
    };
    std::vector<Tri> tris;
    std::vector<float> areas;
    for (uint32_t i = 0; i < scene.instances.size(); ++i) {
        const Mesh& m = scene.meshes[scene.instances[i].mesh];
        for (uint32_t t = 0; t < m.triangle_count(); ++t) {
            Vec3 a, b, c;
            accel.triangle_world(i, t, &a, &b, &c);
            Vec3 cr = cross(b - a, c - a);
            float len = length(cr);
            if (!(len > 0.0f)) continue;
            tris.push_back({a, b - a, c - a, cr / len});
            areas.push_back(0.5f * len);
        }
    }
    Distribution1D pick(areas);
    tbb::task_arena arena(threads > 0 ? threads : tbb::task_arena::automatic);
    std::atomic<uint64_t> total{0};
    auto start = std::chrono::steady_clock::now();
    auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
    const int chunks = 1 << 20;
    arena.execute([&] {
        tbb::parallel_for(0, chunks, [&](int chunk) {
            if (elapsed() > seconds) return;
            Rng rng(1, static_cast<uint64_t>(chunk));
            uint64_t n = 0;
            for (int r = 0; r < 4096; ++r) {
                float pmf;
                const Tri& t = tris[pick.sample(rng.next_float(), &pmf)];
                Vec2 b = sample_uniform_triangle(rng.next_float(), rng.next_float());
                Vec3 p = t.p0 + t.e1 * b.x + t.e2 * b.y;
                Vec3 n_side = rng.next_float() < 0.5f ? t.n : -t.n;
                Vec3 d = Frame(n_side).to_world(sample_cosine_hemisphere(rng.next_float(), rng.next_float()));
                RayHit hit;
                accel.intersect(p + n_side * (1e-4f * (1.0f + length(p))), d, k_infinity, &hit);
                ++n;
            }
            total += n;
        });
    });
    double s = elapsed();
    std::printf("{\"rays\": %llu, \"seconds\": %.4f, \"rays_per_second\": %.1f, \"threads\": %d}\n",
                static_cast<unsigned long long>(total.load()), s, total.load() / s, arena.max_concurrency());
    return 0;
}
