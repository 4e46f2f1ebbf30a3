// The film: scene-linear RGB per pixel, reconstructed with a pixel filter (film/pixel_filter.h).
// Camera samples are placed by filter importance sampling and accumulate in their own pixel
// (each pixel is owned by one tile at a time, so no locking); light-tracing splats are spread
// over the pixels whose filter covers them, in a separate channel of atomic doubles scaled by
// 1/spp when the image is read. Optional first-hit AOVs (depth, normal, albedo) ride along with
// camera samples for Blender-style render passes, and sums of squares give a variance pass.
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

struct FilmSettings {
    FilterSettings filter;
    bool aovs = false;  // record depth, normal and albedo
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
    void add_sample(int x, int y, const Rgb& radiance, const PixelAovs* aovs = nullptr) {
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
    }
    // A light-tracing contribution landing on the film at continuous position (fx, fy); any
    // thread may call this.
    void add_splat(float fx, float fy, const Rgb& value);
    bool has_splats() const { return m_has_splats.load(std::memory_order_relaxed); }

    // Pixel values: camera samples averaged, plus splats divided by `splat_spp` (the number of
    // light paths per pixel traced); the passes the film recorded.
    Image resolve(double splat_spp) const;

    // Checkpoints: the whole accumulated state as doubles in a fixed layout (per pixel: sums,
    // sums of squares, sample count, then the AOV sums when recorded, then the splats). Only
    // while no thread renders.
    size_t state_size() const;
    void save_state(double* out) const;
    void load_state(const double* in);

private:
    struct Pixel {
        double sum[3] = {0, 0, 0};
        double sum_sq[3] = {0, 0, 0};
        double weight = 0;
    };
    struct AovSums {
        double normal[3] = {0, 0, 0};
        double albedo[3] = {0, 0, 0};
        double depth = 0;  // the first sample's: Blender's Z pass uses one sample, never a blend
        double count = 0;
    };
    void add_aovs(size_t i, const PixelAovs& aovs);

    int m_width, m_height;
    FilmSettings m_settings;
    PixelFilter m_filter;
    std::vector<Pixel> m_pixels;
    std::vector<AovSums> m_aovs;  // empty unless settings.aovs
    std::unique_ptr<std::atomic<double>[]> m_splats;  // 3 per pixel
    std::atomic<bool> m_has_splats{false};
};

}  // namespace veach
