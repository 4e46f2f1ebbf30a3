#include "integrators/integrator.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <stdexcept>
#include <vector>

#include "integrators/bdpt/bidirectional_tracer.h"
#include "integrators/pt/path_tracer.h"

namespace veach {

std::vector<std::string> integrator_names() { return {"bdpt", "pt", "lt"}; }

std::unique_ptr<Integrator> make_integrator(const RenderSettings& settings) {
    if (settings.integrator == "pt") return std::make_unique<PathTracer>(settings);
    if (settings.integrator == "bdpt" || settings.integrator == "lt") {
        BdptOptions options;
        options.light_tracing_only = settings.integrator == "lt";
        if (settings.bdpt_s >= 0 || settings.bdpt_t >= 0) {
            if (settings.integrator != "bdpt" || settings.bdpt_s < 0 || settings.bdpt_t < 1)
                throw std::invalid_argument("a bdpt strategy needs s >= 0 and t >= 1 with --integrator bdpt");
            options.only_s = settings.bdpt_s;
            options.only_t = settings.bdpt_t;
        }
        return std::make_unique<BidirectionalTracer>(settings, options);
    }
    throw std::invalid_argument("unknown integrator '" + settings.integrator + "' (known: bdpt, pt, lt)");
}

namespace {
constexpr int k_tile_size = 16;
constexpr int k_max_pass_spp = 16;
}  // namespace

RenderStats render_image(const RenderScene& rs, const Integrator& integrator, const RenderSettings& settings,
                         Film& film, const RenderControl& control) {
    using clock = std::chrono::steady_clock;
    auto start = clock::now();
    auto elapsed = [&] { return std::chrono::duration<double>(clock::now() - start).count(); };

    std::vector<Tile> tiles;
    for (int y = 0; y < film.height(); y += k_tile_size)
        for (int x = 0; x < film.width(); x += k_tile_size)
            tiles.push_back({x, y, std::min(x + k_tile_size, film.width()), std::min(y + k_tile_size, film.height())});

    int threads = settings.threads > 0 ? settings.threads : tbb::task_arena::automatic;
    tbb::task_arena arena(threads);

    RenderStats stats;
    std::atomic<uint64_t> rays{0}, nonfinite{0};
    std::atomic<bool> stop_tiles{false};
    auto cancelled = [&] { return control.cancel && control.cancel->load(std::memory_order_relaxed); };

    int done = std::clamp(control.first_sample, 0, settings.spp);
    int pass = 1;
    // A resumed render continues the pass schedule where it stood (the sums do not depend on it:
    // each pixel adds its samples in index order whatever the passes, so resuming is exact).
    for (int s = 0; s < done; pass = std::min(pass * 2, k_max_pass_spp)) s += std::min(pass, k_max_pass_spp);
    double seconds_per_spp = 0;
    while (done < settings.spp && !cancelled()) {
        int n = std::min({pass, k_max_pass_spp, settings.spp - done});
        if (settings.time_limit > 0) {
            double left = settings.time_limit - elapsed();
            if (left <= 0) break;
            if (seconds_per_spp > 0) {
                // In double: a long time limit over a fast pass does not fit in an int.
                double fits = left / seconds_per_spp;
                if (fits < 1.0) break;
                if (fits < n) n = static_cast<int>(fits);
            }
        }
        double pass_start = elapsed();
        uint32_t begin = static_cast<uint32_t>(done), end = static_cast<uint32_t>(done + n);
        arena.execute([&] {
            tbb::parallel_for(tbb::blocked_range<size_t>(0, tiles.size(), 1), [&](const tbb::blocked_range<size_t>& r) {
                for (size_t t = r.begin(); t != r.end(); ++t) {
                    if (cancelled()) {
                        stop_tiles = true;
                        return;
                    }
                    ThreadStats ts;
                    integrator.render_tile(rs, tiles[t], begin, end, film, ts);
                    rays.fetch_add(ts.rays, std::memory_order_relaxed);
                    nonfinite.fetch_add(ts.nonfinite, std::memory_order_relaxed);
                }
            });
        });
        if (stop_tiles) break;
        done += n;
        seconds_per_spp = (elapsed() - pass_start) / n;
        pass = std::min(pass * 2, k_max_pass_spp);
        if (control.pass_done) control.pass_done(done);
        if (control.progress) {
            double fraction = static_cast<double>(done) / settings.spp;
            double eta = seconds_per_spp * (settings.spp - done);
            if (settings.time_limit > 0) {
                fraction = std::max(fraction, std::min(1.0, elapsed() / settings.time_limit));
                eta = std::min(eta, std::max(0.0, settings.time_limit - elapsed()));
            }
            control.progress(fraction, eta);
        }
    }
    stats.spp_done = done;
    stats.cancelled = cancelled();
    stats.rays = rays.load();
    stats.nonfinite_samples = nonfinite.load();
    stats.camera_samples = static_cast<uint64_t>(done) * film.width() * film.height();
    stats.seconds = elapsed();
    return stats;
}

}  // namespace veach
