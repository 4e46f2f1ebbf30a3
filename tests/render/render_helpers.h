// Rendering a scene in a test and summarising the image statistically.
#pragma once

#include <vector>

#include "api/render_job.h"

namespace veach::test {

inline Image render(const Scene& scene, int size, int spp, const std::string& integrator = "pt", int max_depth = 64,
                    int threads = 0, uint64_t seed = 1, RenderStats* stats = nullptr) {
    RenderJobOptions o;
    o.width = o.height = size;
    o.render.spp = spp;
    o.render.integrator = integrator;
    o.render.max_depth = max_depth;
    o.render.threads = threads;
    o.render.seed = seed;
    RenderResult r = render_scene(scene, o);
    if (stats) *stats = r.stats;
    return r.image;
}

// Mean of one channel over the image.
inline double channel_mean(const Image& img, int c) {
    double sum = 0;
    for (size_t i = 0; i < img.rgba.size(); i += 4) sum += img.rgba[i + c];
    return sum / (img.rgba.size() / 4);
}

// Means of `block` x `block` pixel blocks, channel-averaged.
inline std::vector<double> block_means(const Image& img, int block) {
    std::vector<double> out;
    for (int by = 0; by + block <= img.height; by += block)
        for (int bx = 0; bx + block <= img.width; bx += block) {
            double s = 0;
            for (int y = by; y < by + block; ++y)
                for (int x = bx; x < bx + block; ++x) {
                    const float* p = img.pixel(x, y);
                    s += (p[0] + p[1] + p[2]) / 3.0;
                }
            out.push_back(s / (block * block));
        }
    return out;
}

}  // namespace veach::test
