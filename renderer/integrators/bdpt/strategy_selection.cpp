#include "integrators/bdpt/strategy_selection.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <variant>

#include "core/rng.h"
#include "integrators/bdpt/bidirectional_tracer.h"
#include "integrators/pt/path_tracer.h"

namespace veach {

namespace {

constexpr StrategyMask k_e = family_bit(StrategyFamily::Emission), k_n = family_bit(StrategyFamily::LightSample),
                       k_c = family_bit(StrategyFamily::Camera), k_j = family_bit(StrategyFamily::Connection);
constexpr StrategyMask k_path_tracer = k_e | k_n;

// About this many probe pixels, each with this many samples: enough for per-pixel variances and
// a decision between families whose efficiencies differ by tens of percent, and a few tens of
// milliseconds of a render.
constexpr int k_probe_pixels = 1024;
// Two groups of samples per pixel, each a scrambled Sobol set of its own (its own seed): how far
// the groups' means differ measures the variance the render's stratified samples have, which
// the spread of the samples themselves overstates by a factor that differs between the
// estimators (on the lights scene 2.3x for pt, 1.3x for bdpt).
constexpr int k_probe_groups = 2, k_group_samples = 4;
constexpr int k_probe_samples = k_probe_groups * k_group_samples;
// Blocks per side of the grid the local means (relMSE's denominators) are taken over.
constexpr int k_mean_blocks = 8;
// Cost per ray: BDPT's vertex storage, densities both ways and MIS weights make its rays dearer
// than the path tracer's (rays/s of pt against bdpt in docs/BENCHMARKS.md: 1.2x to 1.5x).
constexpr double k_pt_ray_cost = 1.0, k_bdpt_ray_cost = 1.3;
// A set that traces a light subpath is chosen over the path tracer only when its estimated
// efficiency is this many times pt's: the probe sees the variance of 4-sample stratified sets,
// and pt's light samples, drawn from the sampler's stratified dimensions at every bounce, gain
// more from the render's hundreds of Sobol samples than BDPT's (lights scene, relative variance
// per sample from 4 to 64 spp: pt 0.54 to 0.35, bdpt 0.22 to 0.17 at 64 against independent
// numbers; the probe put full bdpt 1.8x ahead of pt there, the bench measures pt 1.15-1.3x
// ahead). Where light subpaths pay, they pay by far more (spheres' caustics: 320x, the corridor
// 25x estimated).
constexpr double k_light_subpath_margin = 3.0;
// relMSE's regularisation of dark pixels (tests/tools/image_compare.py).
constexpr double k_dark = 0.01;

// Smoother than this and a lobe may be a Dirac delta (gltf_bsdf.h: alpha below k_delta_alpha).
constexpr float k_smooth_roughness = 0.02f;

bool may_be_smooth(const Material& m) {
    const bool specular_lobe = m.metallic > 0.0f || m.metallic_roughness_texture.valid() || m.specular > 0.0f ||
                               m.specular_texture.valid() || m.transmission > 0.0f || m.transmission_texture.valid();
    const bool smooth_base =
        specular_lobe && (m.roughness < k_smooth_roughness || m.metallic_roughness_texture.valid());
    const bool smooth_coat = (m.clearcoat > 0.0f || m.clearcoat_texture.valid()) &&
                             (m.clearcoat_roughness < k_smooth_roughness || m.clearcoat_roughness_texture.valid());
    return smooth_base || smooth_coat;
}

// A light no ray can hit: a delta position (a point or spot without size) or direction (a sun
// without an angle).
bool is_delta_light(const LightSet& lights, size_t i) {
    return std::visit(
        [](const auto& l) {
            if constexpr (requires { l.delta_direction(); }) return l.delta_position() || l.delta_direction();
            else return l.delta_position();
        },
        lights.light(i));
}

// A recorded contribution's MIS sums under the strategies of `mask`: a2 the squared density ratios
// (its weight is 1 / a2 when its own family is in the set), a3 the cubed ones of the set's
// strategies in `part` (its camera-side or its splatted strategies). The power heuristic's
// estimator over the set has, on a path x, the second moment density f^2 sum_k w_k^2 / p_k =
// f^2 sum_k p_k^3 / (sum_k p_k^2)^2; any strategy that sampled x with weight w and value c = f / p
// estimates its integral by w c^2 a3 / a2^2, so the probe measures the variance of a set from
// paths the set itself samples poorly (a caustic the path tracer meets once in a thousand
// samples, that BDPT's connections find every time).
struct Sums {
    double a2 = 0, a3 = 0;
};
Sums sums_in(const ProbeContribution& c, StrategyMask mask, StrategyMask part) {
    Sums out;
    const bool own = (mask >> c.family) & 1u;
    out.a2 = own ? 1.0 : 0.0;
    out.a3 = own && ((part >> c.family) & 1u) ? 1.0 : 0.0;
    for (int f = 0; f < k_strategy_families; ++f) {
        if (!((mask >> f) & 1u)) continue;
        out.a2 += c.ratio_squares[f];
        if ((part >> f) & 1u) out.a3 += c.ratio_cubes[f];
    }
    return out;
}
double weight_in(const ProbeContribution& c, StrategyMask mask) {
    if (!((mask >> c.family) & 1u)) return 0.0;
    return 1.0 / sums_in(c, mask, 0).a2;
}

double cost_of(const ProbeSample& ps, StrategyMask mask) {
    double rays = static_cast<double>(ps.camera_rays) + static_cast<double>(ps.shadow_rays[1]);
    if (mask == k_path_tracer) return k_pt_ray_cost * rays;
    if (needs_light_subpath(mask)) rays += static_cast<double>(ps.light_rays);
    if (mask & k_c) rays += static_cast<double>(ps.shadow_rays[2]);
    if (mask & k_j) rays += static_cast<double>(ps.shadow_rays[3]);
    return k_bdpt_ray_cost * rays;
}

double channel(const Rgb& c, int ch) { return ch == 0 ? c.r : ch == 1 ? c.g : c.b; }

struct Splat {
    int block;
    ProbeContribution c;
};

struct PixelResult {
    int block = 0;
    std::vector<Rgb> camera;  // candidate-major: camera[k * k_probe_samples + j]
    std::vector<Rgb> path_tracer;  // pt's own samples
    std::vector<double> cost;
    // Per candidate and channel, over the pixel's camera-side contributions: the second moment's
    // diagonal measured directly (each contribution weighted by the set) and through the full
    // estimator (sums_in); the splatted strategies' share through the full estimator.
    std::vector<double> direct, reweighted, reweighted_splats;
    std::vector<double> splat_camera_part, splat_splat_part;  // the same from this pixel's splats
    std::vector<uint8_t> uncovered;  // a contribution the candidate's strategies cannot make
    std::vector<Splat> splats;
};

}  // namespace

std::vector<StrategyMask> candidate_masks() { return {k_path_tracer, k_e | k_n | k_j, k_e | k_n | k_c, k_all_strategies}; }

StrategyMask required_strategies(const RenderScene& rs) {
    const LightSet& lights = rs.lights();
    bool delta_light = false;
    for (size_t i = 0; i < lights.size() && !delta_light; ++i) delta_light = is_delta_light(lights, i);
    if (delta_light)
        for (const Material& m : rs.scene().materials)
            if (may_be_smooth(m)) return k_all_strategies;
    return k_path_tracer;
}

std::string describe(const StrategyChoice& choice) {
    if (choice.path_tracer) return "pt";
    std::string s = "bdpt:";
    const char letters[k_strategy_families] = {'e', 'n', 'c', 'j'};
    for (int f = 0; f < k_strategy_families; ++f)
        if ((choice.mask >> f) & 1u) s += letters[f];
    return s;
}

StrategyChoice choose_strategies(const RenderScene& rs, const RenderSettings& settings, const Film& film) {
    StrategyChoice choice;
    const StrategyMask required = required_strategies(rs);
    if (required == k_all_strategies || rs.lights().empty()) return choice;  // nothing to leave out
    const std::vector<StrategyMask> masks = candidate_masks();
    const size_t n_masks = masks.size();

    // The probe pixels: a regular grid over the whole film, whatever part of it this render draws.
    const int width = film.width(), height = film.height();
    const double pixels = static_cast<double>(width) * height;
    const int step = std::max(1, static_cast<int>(std::ceil(std::sqrt(pixels / k_probe_pixels))));
    std::vector<std::pair<int, int>> probe;
    for (int y = step / 2; y < height; y += step)
        for (int x = step / 2; x < width; x += step) probe.emplace_back(x, y);
    auto block_of = [&](float fx, float fy) {
        const int bx = std::clamp(static_cast<int>(fx * k_mean_blocks / width), 0, k_mean_blocks - 1);
        const int by = std::clamp(static_cast<int>(fy * k_mean_blocks / height), 0, k_mean_blocks - 1);
        return by * k_mean_blocks + bx;
    };

    // Random numbers of its own: the probe's samples share no value with any sample of the render.
    const uint64_t probe_seed = mix64(settings.seed ^ 0x70726f6265ull);
    BdptOptions full;
    const BidirectionalTracer tracer(settings, full);
    std::vector<PixelResult> results(probe.size());
    for (size_t i = 0; i < probe.size(); ++i) {
        PixelResult& res = results[i];
        res.block = block_of(static_cast<float>(probe[i].first), static_cast<float>(probe[i].second));
        res.camera.assign(n_masks * k_probe_samples, Rgb(0.0f));
        res.path_tracer.assign(k_probe_samples, Rgb(0.0f));
        res.cost.assign(n_masks, 0.0);
        res.direct.assign(n_masks * 3, 0.0);
        res.reweighted.assign(n_masks * 3, 0.0);
        res.reweighted_splats.assign(n_masks * 3, 0.0);
        res.splat_camera_part.assign(n_masks * 3, 0.0);
        res.splat_splat_part.assign(n_masks * 3, 0.0);
        res.uncovered.assign(n_masks, 0);
    }
    auto visit = [&](size_t i, int j, const ProbeSample& ps) {  // j: the sample in both groups
        PixelResult& res = results[i];
        bool finite = true;
        for (const ProbeContribution& c : ps.contributions) finite &= c.value.is_finite();
        if (!finite) return;  // dropped by the render too
        for (size_t k = 0; k < n_masks; ++k) {
            Rgb a(0.0f);
            for (const ProbeContribution& c : ps.contributions) {
                if (c.value.is_black()) continue;
                const Sums in_set = sums_in(c, masks[k], static_cast<StrategyMask>(masks[k] & ~k_c));
                if (!(in_set.a2 > 0.0)) res.uncovered[k] = 1;
                if (c.splat) continue;
                const double w = weight_in(c, masks[k]);
                a += c.value * static_cast<float>(w);
                const double w_full = weight_in(c, k_all_strategies);
                const Sums splats = sums_in(c, masks[k], k_c);
                for (int ch = 0; ch < 3; ++ch) {
                    const double v = channel(c.value, ch);
                    res.direct[k * 3 + ch] += (w * v) * (w * v);
                    if (in_set.a2 > 0.0) {
                        res.reweighted[k * 3 + ch] += w_full * v * v * in_set.a3 / (in_set.a2 * in_set.a2);
                        res.reweighted_splats[k * 3 + ch] += w_full * v * v * splats.a3 / (in_set.a2 * in_set.a2);
                    }
                }
            }
            res.camera[k * k_probe_samples + j] = a;
            res.cost[k] += cost_of(ps, masks[k]);
        }
        for (const ProbeContribution& c : ps.contributions)
            if (c.splat) res.splats.push_back({block_of(c.px, c.py), c});
    };
    // Each pixel's results in its own slot, reduced below in pixel order: the same sums whatever
    // the threads.
    // The path tracer's own samples too: its estimator is the emission and light-sample strategies'
    // over the same paths, but its light samples draw the sampler's stratified first dimensions
    // at every bounce (BDPT's draw them after its subpaths), which the render's Sobol points
    // reward (relative variance per sample on the lights scene at 64 spp: 0.35 with them, 0.82
    // with independent numbers); and its rays are counted as they are traced.
    const PathTracer path_tracer(settings);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, probe.size(), 16), [&](const tbb::blocked_range<size_t>& r) {
        for (int g = 0; g < k_probe_groups; ++g)
            tracer.probe(rs, film, mix64(probe_seed + static_cast<uint64_t>(g)), probe, r.begin(), r.end(),
                         k_group_samples,
                         [&](size_t i, int j, const ProbeSample& ps) { visit(i, g * k_group_samples + j, ps); });
        CameraModel moving_camera = rs.camera();
        for (size_t i = r.begin(); i != r.end(); ++i) {
            const auto [x, y] = probe[i];
            const uint64_t pixel = static_cast<uint64_t>(y) * width + x;
            ThreadStats stats;
            for (int g = 0; g < k_probe_groups; ++g) {
                for (int j = 0; j < k_group_samples; ++j) {
                    Sampler rng(settings.sampler, mix64(probe_seed + static_cast<uint64_t>(g)), pixel,
                                static_cast<uint32_t>(j));
                    auto [fx, fy] = film.sample_position(x, y, rng.next_2d());
                    const float time = rs.shutter_time(rng);
                    const CameraModel& camera = rs.camera_at(time, moving_camera);
                    Vec3 o, d;
                    camera.generate_ray(fx, fy, &o, &d);
                    const Rgb l = path_tracer.trace(rs, camera, o, d, time, rng, stats);
                    results[i].path_tracer[g * k_group_samples + j] = l.is_finite() ? l : Rgb(0.0f);
                }
            }
            results[i].cost[0] = k_pt_ray_cost * static_cast<double>(stats.rays);
        }
    });

    // Local means of the full estimator, per block: the camera side over the block's probe pixels,
    // the splats scaled from the probe's light paths to the film's.
    const double samples = static_cast<double>(probe.size()) * k_probe_samples;
    const size_t full_k = n_masks - 1;
    std::vector<double> mean(k_mean_blocks * k_mean_blocks * 3, 0.0), count(k_mean_blocks * k_mean_blocks, 0.0);
    std::vector<double> block_pixels(k_mean_blocks * k_mean_blocks, 0.0);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) block_pixels[block_of(x + 0.5f, y + 0.5f)] += 1.0;
    for (const PixelResult& res : results) {
        for (int j = 0; j < k_probe_samples; ++j)
            for (int ch = 0; ch < 3; ++ch) mean[res.block * 3 + ch] += channel(res.camera[full_k * k_probe_samples + j], ch);
        count[res.block] += k_probe_samples;
    }
    for (size_t b = 0; b < count.size(); ++b)
        for (int ch = 0; ch < 3; ++ch) mean[b * 3 + ch] /= std::max(1.0, count[b]);
    for (const PixelResult& res : results)
        for (const Splat& s : res.splats) {
            const double w = weight_in(s.c, masks[full_k]) * pixels / (std::max(1.0, block_pixels[s.block]) * samples);
            for (int ch = 0; ch < 3; ++ch) mean[s.block * 3 + ch] += channel(s.c.value, ch) * w;
        }
    auto relative = [&](int block, int ch, double square) {
        const double m = mean[block * 3 + ch];
        return square / (m * m + k_dark) / 3.0;
    };

    // Per candidate: the camera side's per-pixel variance measured directly (cross terms
    // between a sample's strategies included), its diagonal part replaced by the full
    // estimator's measure of it (unbiased for the same quantity, far less heavy-tailed), plus the
    // splats' second moment, likewise.
    choice.variance.assign(n_masks, 0.0);
    choice.cost.assign(n_masks, 0.0);
    std::vector<uint8_t> uncovered(n_masks, 0);
    for (size_t k = 0; k < n_masks; ++k) {
        // Relative to the local means: the camera side's variance per sample from the spread of
        // all samples (cross terms included) and from the groups' means (stratified); its
        // diagonal swapped for the full estimator's measure; the splats' second moment.
        double spread = 0.0, stratified = 0.0, swap = 0.0, splatted = 0.0, cost = 0.0;
        const bool pt = masks[k] == k_path_tracer;
        double pt_spread = 0.0;  // pt: its own samples' spread
        for (const PixelResult& res : results) {
            uncovered[k] |= res.uncovered[k];
            for (int ch = 0; ch < 3; ++ch) {
                double s1 = 0.0, s2 = 0.0, group[k_probe_groups] = {}, p1 = 0.0, p2 = 0.0;
                for (int j = 0; j < k_probe_samples; ++j) {
                    const double v = channel(res.camera[k * k_probe_samples + j], ch);
                    s1 += v;
                    s2 += v * v;
                    const double p = channel(res.path_tracer[j], ch);
                    p1 += p;
                    p2 += p * p;
                    // The stratification's gain: of pt's own samples for pt.
                    group[j / k_group_samples] += (pt ? p : v) / k_group_samples;
                }
                const double var = (s2 - s1 * s1 / k_probe_samples) / (k_probe_samples - 1);
                const double pt_var = (p2 - p1 * p1 / k_probe_samples) / (k_probe_samples - 1);
                spread += relative(res.block, ch, var);
                pt_spread += relative(res.block, ch, pt_var);
                double gm = 0.0, gv = 0.0;
                for (double m : group) gm += m / k_probe_groups;
                for (double m : group) gv += (m - gm) * (m - gm) / (k_probe_groups - 1);
                stratified += relative(res.block, ch, gv * k_group_samples);
                swap += relative(res.block, ch, res.reweighted[k * 3 + ch] - res.direct[k * 3 + ch]);
                splatted += relative(res.block, ch, res.reweighted_splats[k * 3 + ch]);
            }
            cost += res.cost[k];
            for (const Splat& s : res.splats) {
                const Sums in_set = sums_in(s.c, masks[k], static_cast<StrategyMask>(masks[k] & ~k_c));
                if (!(in_set.a2 > 0.0)) continue;
                const double w_full = weight_in(s.c, k_all_strategies);
                const double a3_camera = in_set.a3, a3_splats = sums_in(s.c, masks[k], k_c).a3;
                for (int ch = 0; ch < 3; ++ch) {
                    const double v = channel(s.c.value, ch), m2 = w_full * v * v / (in_set.a2 * in_set.a2);
                    swap += relative(s.block, ch, m2 * a3_camera);
                    splatted += relative(s.block, ch, m2 * a3_splats);
                }
            }
        }
        const double pixels_probed = static_cast<double>(probe.size());
        spread /= pixels_probed;
        stratified /= pixels_probed;
        swap /= samples;
        splatted /= samples;
        // The stratification's gain, measured on the spread, applied to the camera side.
        pt_spread /= pixels_probed;
        // For pt, the larger of its own samples' spread and the same strategies' measured
        // through the full estimator (robust where pt's samples miss rare paths: the corridor's
        // light through a door gap).
        const double own = pt ? pt_spread : spread;
        const double gain = own > 0.0 ? std::clamp(stratified / own, 0.05, 2.0) : 1.0;
        const double base = pt ? std::max(pt_spread, spread + swap) : std::max(0.0, spread + swap);
        const double variance = gain * base + splatted;
        choice.variance[k] = variance;
        choice.cost[k] = cost / samples;
    }
    // The most efficient allowed candidate; ties (a black image) go to the first, the cheapest.
    size_t best = SIZE_MAX;
    auto inefficiency = [&](size_t k) {
        const double product = choice.variance[k] * choice.cost[k];
        return needs_light_subpath(masks[k]) ? product * k_light_subpath_margin : product;
    };
    for (size_t k = 0; k < n_masks; ++k) {
        if ((masks[k] & required) != required || uncovered[k]) continue;
        if (best == SIZE_MAX || inefficiency(k) < inefficiency(best)) best = k;
    }
    choice.mask = masks[best];
    choice.path_tracer = choice.mask == k_path_tracer;
    return choice;
}

}  // namespace veach
