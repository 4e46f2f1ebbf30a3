#include "integrators/integrator.h"

#include "core/available_cpus.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <vector>

#include "film/adaptive_sampling.h"
#include "integrators/bdpt/adaptive_bidirectional.h"
#include "integrators/bdpt/bidirectional_tracer.h"
#include "integrators/lt/light_tracer.h"
#include "integrators/pt/path_tracer.h"

namespace veach {

std::vector<std::string> integrator_names() { return {"auto", "bdpt", "pt", "lt"}; }

std::unique_ptr<Integrator> make_integrator(const RenderSettings& settings) {
    // One (s, t) strategy is a BDPT notion: with pt or lt it would be ignored, silently.
    if (settings.integrator != "bdpt" && (settings.bdpt_s >= 0 || settings.bdpt_t >= 0))
        throw std::invalid_argument("the strategy options bdpt_s/bdpt_t (--bdpt-strategy) apply only to the bdpt "
                                    "integrator, not " + settings.integrator);
    if (settings.integrator == "auto") return std::make_unique<AdaptiveBidirectional>(settings);
    if (settings.integrator == "pt") return std::make_unique<PathTracer>(settings);
    if (settings.integrator == "lt") return std::make_unique<LightTracer>(settings);
    if (settings.integrator == "bdpt") {
        BdptOptions options;
        if (settings.bdpt_s >= 0 || settings.bdpt_t >= 0) {
            if (settings.bdpt_s < 0 || settings.bdpt_t < 1)
                throw std::invalid_argument("a bdpt strategy needs s >= 0 and t >= 1 with --integrator bdpt");
            options.only_s = settings.bdpt_s;
            options.only_t = settings.bdpt_t;
        }
        return std::make_unique<BidirectionalTracer>(settings, options);
    }
    throw std::invalid_argument("unknown integrator '" + settings.integrator + "' (known: auto, bdpt, pt, lt)");
}

namespace {
constexpr int k_tile_size = 16;
constexpr int k_max_pass_spp = 16;
}  // namespace

namespace {

// Renders samples [begin, end) of a tile, each pixel capped by its adaptive budget: runs of
// pixels in a row that share a cap go to the integrator as one-row tiles (the integrators key
// randomness by pixel, so the split changes nothing but the call count). Returns the camera
// samples taken.
uint64_t render_planned_tile(const RenderScene& rs, const Integrator& integrator, const Tile& tile, uint32_t begin,
                             uint32_t end, Film& film, ThreadStats& ts) {
    const uint64_t area = static_cast<uint64_t>(tile.x1 - tile.x0) * (tile.y1 - tile.y0);
    bool all_full = true;
    for (int y = tile.y0; y < tile.y1 && all_full; ++y)
        for (int x = tile.x0; x < tile.x1 && all_full; ++x) all_full = film.planned_samples(x, y) >= end;
    if (all_full) {
        integrator.render_tile(rs, tile, begin, end, film, ts);
        return area * (end - begin);
    }
    uint64_t taken = 0;
    for (int y = tile.y0; y < tile.y1; ++y) {
        for (int x = tile.x0; x < tile.x1;) {
            const uint32_t e = std::min(end, film.planned_samples(x, y));
            int x1 = x + 1;
            while (x1 < tile.x1 && std::min(end, film.planned_samples(x1, y)) == e) ++x1;
            if (e > begin) {
                integrator.render_tile(rs, Tile{x, y, x1, y + 1}, begin, e, film, ts);
                taken += static_cast<uint64_t>(x1 - x) * (e - begin);
            }
            x = x1;
        }
    }
    return taken;
}

}  // namespace

RenderStats render_image(const RenderScene& rs, Integrator& integrator, const RenderSettings& settings,
                         Film& film, const RenderControl& control) {
    using clock = std::chrono::steady_clock;
    auto start = clock::now();
    auto elapsed = [&] { return std::chrono::duration<double>(clock::now() - start).count(); };

    if (!std::isfinite(settings.noise_target) || settings.noise_target < 0)
        throw std::invalid_argument("--noise must be a finite number, at least 0");
    if (settings.min_spp < 0) throw std::invalid_argument("the adaptive pilot (min spp) must not be negative");
    const bool adaptive = settings.noise_target > 0 && integrator.pixels_hold_estimates();
    if (film.has_sample_plan() && (!adaptive || film.plan_target() != settings.noise_target)) {
        char target[32];
        std::snprintf(target, sizeof(target), "%g", static_cast<double>(film.plan_target()));
        throw std::invalid_argument(std::string("the checkpoint was made with adaptive sampling at --noise ") + target +
                                    "; resume with the same --noise and integrator (or delete it)");
    }
    // The pilot: enough samples for a usable variance estimate (the largest need among eight
    // neighbours makes up for a noisy one), few enough to leave time to spend where the noise is.
    // Fixed rather than grown with spp: with a time limit spp is only a cap.
    const int pilot_spp = std::max(2, settings.min_spp > 0 ? settings.min_spp : 16);
    // The pixels to render: the whole film, or a part's rectangle (whose tiles start at its corner).
    Tile area = control.bounds;
    if (area.x1 <= area.x0 || area.y1 <= area.y0) area = Tile{0, 0, film.width(), film.height()};
    if (area.x0 < 0 || area.y0 < 0 || area.x1 > film.width() || area.y1 > film.height())
        throw std::invalid_argument("pixel bounds outside the film");
    if ((area.x0 != 0 || area.y0 != 0 || area.x1 != film.width() || area.y1 != film.height()) &&
        settings.noise_target > 0)
        throw std::invalid_argument("adaptive sampling renders the whole film");
    const uint64_t pixels = static_cast<uint64_t>(area.x1 - area.x0) * (area.y1 - area.y0);

    std::vector<Tile> tiles;
    for (int y = area.y0; y < area.y1; y += k_tile_size)
        for (int x = area.x0; x < area.x1; x += k_tile_size)
            tiles.push_back({x, y, std::min(x + k_tile_size, area.x1), std::min(y + k_tile_size, area.y1)});
    // Camera samples taken once every pixel reaches sample index s, counted from the origin.
    const int origin = std::clamp(control.sample_origin, 0, settings.spp);
    auto samples_at = [&](int s) -> uint64_t {
        if (film.has_sample_plan()) return film.planned_total(static_cast<uint64_t>(s));
        return static_cast<uint64_t>(std::max(0, s - origin)) * pixels;
    };

    // Not TBB's automatic count: that is the machine's (or the affinity mask's) cores, while a
    // farm task's share of a node is often a cgroup quota too.
    const int threads = settings.threads > 0 ? settings.threads : available_cpus();
    tbb::task_arena arena(threads);

    RenderStats stats;
    stats.threads = threads;
    std::atomic<uint64_t> rays{0}, nonfinite{0}, pass_samples{0};
    std::atomic<bool> stop_tiles{false};
    auto cancelled = [&] { return control.cancel && control.cancel->load(std::memory_order_relaxed); };

    int done = std::clamp(control.first_sample, 0, settings.spp);
    // The largest budget of the plan: past it no pixel takes samples, and the render is complete.
    uint32_t max_budget = UINT32_MAX;
    auto update_plan = [&] {
        if (adaptive && !film.has_sample_plan() && done >= pilot_spp && done < settings.spp)
            film.set_sample_plan(plan_adaptive_samples(film, settings.noise_target, done), settings.noise_target, done);
        if (!film.has_sample_plan()) return;
        max_budget = 0;
        for (int y = 0; y < film.height(); ++y)
            for (int x = 0; x < film.width(); ++x) max_budget = std::max(max_budget, film.planned_samples(x, y));
        if (static_cast<uint64_t>(done) >= max_budget) done = settings.spp;
    };
    update_plan();  // a resumed render: the plan in the checkpoint, or one made from its samples
    auto active_pixels = [&] {
        if (!film.has_sample_plan()) return pixels;
        uint64_t active = 0;
        for (int y = 0; y < film.height(); ++y)
            for (int x = 0; x < film.width(); ++x) active += film.planned_samples(x, y) > static_cast<uint32_t>(done);
        return active;
    };

    int pass = 1;
    // A resumed render continues the pass schedule where it stood (the sums do not depend on it:
    // each pixel adds its samples in index order whatever the passes, so resuming is exact).
    for (int s = 0; s < done; pass = std::min(pass * 2, k_max_pass_spp)) s += std::min(pass, k_max_pass_spp);
    double seconds_per_sample = 0;  // per camera sample (one pixel, one sample index)
    while (done < settings.spp && !cancelled()) {
        int n = std::min({pass, k_max_pass_spp, settings.spp - done});
        // The pilot ends on a pass boundary, where the plan is made.
        if (adaptive && !film.has_sample_plan() && done < pilot_spp) n = std::min(n, pilot_spp - done);
        if (settings.time_limit > 0) {
            double left = settings.time_limit - elapsed();
            if (left <= 0) break;
            if (seconds_per_sample > 0) {
                // In double: a long time limit over a fast pass does not fit in an int.
                double fits = left / (seconds_per_sample * static_cast<double>(std::max<uint64_t>(1, active_pixels())));
                if (fits < 1.0) break;
                if (fits < n) n = static_cast<int>(fits);
            }
        }
        double pass_start = elapsed();
        uint32_t begin = static_cast<uint32_t>(done), end = static_cast<uint32_t>(done + n);
        pass_samples = 0;
        // In the arena: a hook that works in parallel (the default integrator's probe) uses the
        // render's threads.
        arena.execute([&] { integrator.begin_pass(rs, begin, end, film); });
        arena.execute([&] {
            tbb::parallel_for(tbb::blocked_range<size_t>(0, tiles.size(), 1), [&](const tbb::blocked_range<size_t>& r) {
                for (size_t t = r.begin(); t != r.end(); ++t) {
                    if (cancelled()) {
                        stop_tiles = true;
                        return;
                    }
                    ThreadStats ts;
                    uint64_t taken = render_planned_tile(rs, integrator, tiles[t], begin, end, film, ts);
                    pass_samples.fetch_add(taken, std::memory_order_relaxed);
                    rays.fetch_add(ts.rays, std::memory_order_relaxed);
                    nonfinite.fetch_add(ts.nonfinite, std::memory_order_relaxed);
                }
            });
        });
        if (stop_tiles) break;
        integrator.end_pass(rs, begin, end, film);
        done += n;
        if (pass_samples > 0) seconds_per_sample = (elapsed() - pass_start) / static_cast<double>(pass_samples.load());
        pass = std::min(pass * 2, k_max_pass_spp);
        update_plan();
        if (control.pass_done) control.pass_done(done);
        if (control.progress) {
            const double total = static_cast<double>(samples_at(settings.spp));
            const double taken = static_cast<double>(samples_at(done));
            double fraction = total > 0 ? taken / total : 1.0;
            double eta = seconds_per_sample * (total - taken);
            if (settings.time_limit > 0) {
                fraction = std::max(fraction, std::min(1.0, elapsed() / settings.time_limit));
                eta = std::min(eta, std::max(0.0, settings.time_limit - elapsed()));
            }
            control.progress(fraction, eta);
        }
    }
    stats.spp_done = done;
    stats.strategies = integrator.strategies();
    stats.cancelled = cancelled();
    stats.rays = rays.load();
    stats.nonfinite_samples = nonfinite.load();
    stats.camera_samples = samples_at(done);
    stats.mean_spp = pixels > 0 ? static_cast<double>(stats.camera_samples) / static_cast<double>(pixels) : 0.0;
    stats.seconds = elapsed();
    return stats;
}

}  // namespace veach
