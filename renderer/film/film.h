// The film: scene-linear RGB per pixel. Camera samples accumulate per pixel (each pixel is
// owned by one tile at a time, so no locking); light-tracing splats go to a separate channel
// of atomic doubles, scaled by 1/spp when the image is read.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <vector>

#include "core/rgb.h"

namespace veach {

// A finished image: width x height RGBA float, row 0 at the top, scene-linear Rec.709.
struct Image {
    int width = 0, height = 0;
    std::vector<float> rgba;
    float* pixel(int x, int y) { return &rgba[(static_cast<size_t>(y) * width + x) * 4]; }
    const float* pixel(int x, int y) const { return &rgba[(static_cast<size_t>(y) * width + x) * 4]; }
};

class Film {
public:
    Film(int width, int height);

    int width() const { return m_width; }
    int height() const { return m_height; }

    // A camera sample's radiance for pixel (x, y). Only the thread rendering the tile that owns
    // the pixel calls this.
    void add_sample(int x, int y, const Rgb& radiance) {
        Pixel& p = m_pixels[static_cast<size_t>(y) * m_width + x];
        p.sum[0] += radiance.r;
        p.sum[1] += radiance.g;
        p.sum[2] += radiance.b;
        p.weight += 1.0;
    }
    // A light-tracing contribution landing on the film at continuous position (fx, fy); any
    // thread may call this.
    void add_splat(float fx, float fy, const Rgb& value);
    bool has_splats() const { return m_has_splats.load(std::memory_order_relaxed); }

    // Pixel values: camera samples averaged, plus splats divided by `splat_spp` (the number of
    // light paths per pixel traced).
    Image resolve(double splat_spp) const;

private:
    struct Pixel {
        double sum[3] = {0, 0, 0};
        double weight = 0;
    };
    int m_width, m_height;
    std::vector<Pixel> m_pixels;
    std::unique_ptr<std::atomic<double>[]> m_splats;  // 3 per pixel
    std::atomic<bool> m_has_splats{false};
};

}  // namespace veach
