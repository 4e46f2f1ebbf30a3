// The film: scene-linear RGB per pixel, reconstructed with a pixel filter (film/pixel_filter.h).
// Camera samples are placed by filter importance sampling and accumulate in their own pixel
// (each pixel is owned by one tile at a time, so no locking); light-tracing splats are spread
// over the pixels whose filter covers them, in a separate channel of atomic doubles scaled by
// 1/spp when the image is read. Optional first-hit AOVs (depth, normal, albedo) ride along with
// camera samples for Blender-style render passes, and sums of squares give a variance pass.
// Adaptive sampling (film/adaptive_sampling.h) leaves a per-pixel sample budget here: each pixel
// is divided by its own sample count, and the splats are split at the moment the budget was set
// (see resolve()).
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <vector>

#include "core/math.h"
#include "core/rgb.h"
#include "film/pixel_filter.h"

namespace veach {

// A finished image: width x height RGBA float, row 0 at the top, scene-linear Rec.709. The
// render passes are filled when the film recorded them and empty otherwise.
struct Image {
    int width = 0, height = 0;
    std::vector<float> rgba;
    std::vector<float> depth;     // 1 per pixel: camera-space Z of the first hit (1e10 for none)
    std::vector<float> normal;    // 3 per pixel: world-space shading normal, sample average
    std::vector<float> albedo;    // 3 per pixel: base colour at the first hit, sample average
    std::vector<float> variance;  // 3 per pixel: estimated variance of the pixel's mean
    // 1 per pixel: the camera samples averaged into the pixel (fewer than spp where adaptive
    // sampling stopped it early, or where a non-finite sample was dropped).
    std::vector<float> sample_count;
    // With denoising: the colour as rendered (3 per pixel) and the denoiser's features (albedo
    // and normal 3 per pixel, depth 1; see DenoiseFeatures), Cycles' Denoising Data passes.
    std::vector<float> noisy;
    std::vector<float> denoising_albedo, denoising_normal, denoising_depth;
    float* pixel(int x, int y) { return &rgba[(static_cast<size_t>(y) * width + x) * 4]; }
    const float* pixel(int x, int y) const { return &rgba[(static_cast<size_t>(y) * width + x) * 4]; }
};

// What a camera sample's first hit tells the AOV passes.
struct PixelAovs {
    bool hit = false;  // false: the ray escaped (depth 1e10, normal and albedo 0, as in Blender)
    float depth = 0;   // distance along the camera's forward axis (Blender's Z pass)
    Vec3 normal;       // world-space unit shading normal
    Rgb albedo;        // base colour (the denoiser's albedo guide)
};

// What a camera sample tells the denoiser (denoise/denoise.h) about the surface it sees: the first
// hit, or where that is a mirror or smooth glass, the first surface seen through it
// (first_hit_aovs.h). Escaped rays leave everything 0.
struct DenoiseFeatures {
    bool hit = false;
    Vec3 position;  // world space
    Vec3 normal;    // world-space unit shading normal, facing the ray
    Rgb albedo;     // base colour, times the tint of the mirrors and glass on the way
    float depth = 0;  // the first hit's, along the camera's forward axis (as PixelAovs::depth)
};

// The halves a film keeps for the denoiser: the image from even and from odd sample indices (3
// floats per pixel each; independent estimates of the same image), and the features averaged
// over all samples (3 floats per pixel; depth 1, k_no_hit_depth where no sample hit).
struct FilmHalves {
    std::vector<float> even, odd;
    std::vector<float> albedo, normal, position, depth;
};

struct FilmSettings {
    FilterSettings filter;
    bool aovs = false;  // record depth, normal and albedo
    // Record coverage as the Combined pass's alpha: the fraction of a pixel's camera samples whose
    // ray hits scene geometry (alpha-tested surfaces let it through as they do in rendering),
    // from the same samples as the RGB. Without it alpha is 1.
    bool alpha = false;
    // Keep what the denoiser needs: the odd sample indices' sums beside the whole (the even ones
    // are the difference) and the denoising features (about 112 more bytes per pixel). Without
    // it the film allocates and does nothing more; the whole image is the same bit for bit
    // either way.
    bool halves = false;
};

// Blender's "no hit" depth.
inline constexpr float k_no_hit_depth = 1e10f;

class Film {
public:
    // Throws std::invalid_argument for a bad filter width.
    Film(int width, int height, const FilmSettings& settings = {});

    int width() const { return m_width; }
    int height() const { return m_height; }
    const PixelFilter& filter() const { return m_filter; }
    bool wants_aovs() const { return m_settings.aovs; }
    bool wants_alpha() const { return m_settings.alpha; }
    // Whether a camera sample needs its first hit traced (first_hit_aovs.h).
    bool wants_first_hit() const { return m_settings.aovs || m_settings.alpha; }
    bool wants_halves() const { return m_settings.halves; }

    struct Position {
        float fx, fy;
    };
    // The film position of a camera sample for pixel (x, y), drawn from the pixel filter with
    // the uniform 2D sample `u` (u.x for x). The 1-pixel box gives x + u.x, y + u.y exactly.
    Position sample_position(int x, int y, Vec2 u) const {
        if (m_filter.is_unit_box()) return {x + u.x, y + u.y};
        return {x + 0.5f + m_filter.sample(u.x), y + 0.5f + m_filter.sample(u.y)};
    }

    // A camera sample's radiance for pixel (x, y), placed by sample_position(): weight 1 in this
    // pixel only. Only the thread rendering the tile that owns the pixel calls this.
    // `sample_index` says which half the sample belongs to and `features` are the denoiser's
    // (both only used when the film keeps halves).
    void add_sample(int x, int y, const Rgb& radiance, const PixelAovs* aovs = nullptr, uint32_t sample_index = 0,
                    const DenoiseFeatures* features = nullptr) {
        const size_t i = static_cast<size_t>(y) * m_width + x;
        Pixel& p = m_pixels[i];
        p.sum[0] += radiance.r;
        p.sum[1] += radiance.g;
        p.sum[2] += radiance.b;
        p.sum_sq[0] += static_cast<double>(radiance.r) * radiance.r;
        p.sum_sq[1] += static_cast<double>(radiance.g) * radiance.g;
        p.sum_sq[2] += static_cast<double>(radiance.b) * radiance.b;
        p.weight += 1.0;
        if (aovs && m_settings.aovs) add_aovs(i, *aovs);
        if (aovs && m_settings.alpha && aovs->hit) m_alpha_hits[i] += 1.0;
        if (m_settings.halves) add_to_halves(i, radiance, sample_index, features);
    }
    // A light-tracing contribution landing on the film at continuous position (fx, fy), from the
    // light path traced for camera sample `sample_index` (its half); any thread may call this.
    void add_splat(float fx, float fy, const Rgb& value, uint32_t sample_index = 0);
    bool has_splats() const { return m_has_splats.load(std::memory_order_relaxed); }

    // Pixel values: camera samples averaged, plus splats divided by `splat_spp` (the sample
    // index every unstopped pixel reached: one light path per camera sample); the passes the film
    // recorded. With a sample plan, splats are weighted as explained in film.cpp.
    Image resolve(double splat_spp) const;
    // The two half images and the features (only when the film keeps halves; whole renders
    // only: every unstopped pixel reached sample index `splat_spp`). Each half is resolved as
    // resolve() does the whole, from its own samples and splats.
    FilmHalves resolve_halves(double splat_spp) const;

    // What a pixel has accumulated (camera samples only).
    struct PixelSums {
        double sum[3] = {0, 0, 0};
        double sum_sq[3] = {0, 0, 0};
        double weight = 0;  // finite samples added
    };
    const PixelSums& pixel_sums(int x, int y) const { return m_pixels[static_cast<size_t>(y) * m_width + x]; }

    // Adaptive sampling's per-pixel budget: pixel i takes samples [0, planned_samples(i)) and no
    // more. Set once, at a pass boundary where every pixel holds exactly `pilot_spp` samples; the
    // splats gathered so far are set aside as the pilot's (resolve() weighs them apart from the
    // later ones, whose number depends on the plan). `target` is kept to refuse resuming with
    // another one. Only while no thread renders.
    void set_sample_plan(std::vector<uint32_t> plan, float target, int pilot_spp);
    bool has_sample_plan() const { return !m_plan.empty(); }
    uint32_t planned_samples(int x, int y) const {
        return m_plan.empty() ? UINT32_MAX : m_plan[static_cast<size_t>(y) * m_width + x];
    }
    float plan_target() const { return m_plan_target; }
    int plan_pilot_spp() const { return m_plan_pilot_spp; }
    // Camera samples pixel i has taken (or will have taken) once every unstopped pixel reaches
    // sample index `spp`, summed over the image.
    uint64_t planned_total(uint64_t spp) const;

    // Checkpoints: the whole accumulated state as doubles in a fixed layout (per pixel: sums,
    // sums of squares, sample count, then the AOV sums when recorded, then the covered samples
    // when alpha is recorded, then the splats, then,
    // with a sample plan, its target, pilot spp, per-pixel budgets and the pilot's splats).
    // Only while no thread renders. load_state takes the number of doubles, which says whether
    // a plan is included: state_size(false) or state_size(true).
    size_t state_size() const { return state_size(has_sample_plan()); }
    size_t state_size(bool with_plan) const;
    void save_state(double* out) const;
    void load_state(const double* in, size_t count);

    // Part files (film/film_part.h): the camera-sample sums of the pixels in [x0, x1) x [y0, y1)
    // (per pixel: sums, sums of squares, sample count), their AOV sums when recorded (per pixel:
    // normal, albedo, depth, count), and every splat (3 per pixel of the whole film). The add_*
    // functions add another part's sums to these, exactly as a longer render would have
    // accumulated them: a pixel's depth stays its first sample's, so parts must be added in the
    // order of their sample ranges. Only while no thread renders.
    static constexpr size_t k_part_pixel_doubles = 7, k_part_aov_doubles = 8;
    void save_pixels(int x0, int y0, int x1, int y1, std::vector<double>* pixels, std::vector<double>* aovs) const;
    void add_pixels(int x0, int y0, int x1, int y1, const double* pixels, const double* aovs);
    void save_splats(std::vector<double>* splats) const;
    void add_splats(const double* splats);

private:
    using Pixel = PixelSums;
    struct AovSums {
        double normal[3] = {0, 0, 0};
        double albedo[3] = {0, 0, 0};
        double depth = 0;  // the first sample's: Blender's Z pass uses one sample, never a blend
        double count = 0;
    };
    void add_aovs(size_t i, const PixelAovs& aovs);
    struct HalfSums {
        double sum[3] = {0, 0, 0};
        double weight = 0;
    };
    // Summed over all samples; position in doubles (world coordinates far from the origin).
    struct FeatureSums {
        float albedo[3] = {0, 0, 0};
        float normal[3] = {0, 0, 0};
        float depth = 0;  // summed over the samples that hit
        float hits = 0;
        double position[3] = {0, 0, 0};
    };
    void add_to_halves(size_t i, const Rgb& radiance, uint32_t sample_index, const DenoiseFeatures* features);
    void splat_into(std::atomic<double>* channel, float fx, float fy, const Rgb& value);
    void save_halves(double* out, bool with_plan) const;
    void load_halves(const double* in, bool with_plan);

    int m_width, m_height;
    FilmSettings m_settings;
    PixelFilter m_filter;
    std::vector<Pixel> m_pixels;
    std::vector<AovSums> m_aovs;                      // empty unless settings.aovs
    std::vector<double> m_alpha_hits;                 // per pixel, empty unless settings.alpha
    std::unique_ptr<std::atomic<double>[]> m_splats;  // 3 per pixel
    // With halves: the odd sample indices' part of the sums and the splats, and the features.
    std::vector<HalfSums> m_odd;
    std::unique_ptr<std::atomic<double>[]> m_odd_splats;  // 3 per pixel
    std::vector<double> m_odd_pilot_splats;               // 3 per pixel, with a plan
    std::vector<FeatureSums> m_features;
    std::atomic<bool> m_has_splats{false};
    std::vector<uint32_t> m_plan;        // empty: no adaptive sampling
    std::vector<double> m_pilot_splats;  // 3 per pixel, with a plan
    float m_plan_target = 0;
    int m_plan_pilot_spp = 0;
};

}  // namespace veach
