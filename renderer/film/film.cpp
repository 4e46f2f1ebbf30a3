#include "film/film.h"

#include <cmath>

namespace veach {

Film::Film(int width, int height)
    : m_width(width), m_height(height),
      m_pixels(static_cast<size_t>(width) * height),
      m_splats(new std::atomic<double>[static_cast<size_t>(width) * height * 3]) {
    for (size_t i = 0; i < static_cast<size_t>(width) * height * 3; ++i) m_splats[i] = 0.0;
}

namespace {
void atomic_add(std::atomic<double>& a, double v) {
    double old = a.load(std::memory_order_relaxed);
    while (!a.compare_exchange_weak(old, old + v, std::memory_order_relaxed)) {
    }
}
}  // namespace

void Film::add_splat(float fx, float fy, const Rgb& value) {
    // Box filter of one pixel: the splat belongs to the pixel that contains it.
    int x = static_cast<int>(std::floor(fx));
    int y = static_cast<int>(std::floor(fy));
    if (x < 0 || y < 0 || x >= m_width || y >= m_height) return;
    size_t i = (static_cast<size_t>(y) * m_width + x) * 3;
    atomic_add(m_splats[i + 0], value.r);
    atomic_add(m_splats[i + 1], value.g);
    atomic_add(m_splats[i + 2], value.b);
    m_has_splats.store(true, std::memory_order_relaxed);
}

Image Film::resolve(double splat_spp) const {
    Image img;
    img.width = m_width;
    img.height = m_height;
    img.rgba.resize(static_cast<size_t>(m_width) * m_height * 4);
    double splat_scale = splat_spp > 0.0 ? 1.0 / splat_spp : 0.0;
    for (size_t i = 0; i < m_pixels.size(); ++i) {
        const Pixel& p = m_pixels[i];
        double inv = p.weight > 0.0 ? 1.0 / p.weight : 0.0;
        for (int c = 0; c < 3; ++c) {
            double v = p.sum[c] * inv + m_splats[i * 3 + c].load(std::memory_order_relaxed) * splat_scale;
            img.rgba[i * 4 + c] = static_cast<float>(v);
        }
        img.rgba[i * 4 + 3] = 1.0f;
    }
    return img;
}

}  // namespace veach
