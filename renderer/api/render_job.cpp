#include "api/render_job.h"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <stdexcept>

namespace veach {

const Camera* select_camera(const Scene& scene, const std::string& spec) {
    if (spec.empty()) return scene.cameras.empty() ? nullptr : &scene.cameras[0];
    for (const Camera& c : scene.cameras)
        if (c.name == spec) return &c;
    char* end = nullptr;
    long index = std::strtol(spec.c_str(), &end, 10);
    if (end && *end == '\0' && index >= 0 && static_cast<size_t>(index) < scene.cameras.size())
        return &scene.cameras[static_cast<size_t>(index)];
    std::string known;
    for (size_t i = 0; i < scene.cameras.size(); ++i)
        known += (i ? ", " : "") + std::to_string(i) + " '" + scene.cameras[i].name + "'";
    throw std::invalid_argument("no camera '" + spec + "' in the scene (cameras: " +
                                (known.empty() ? std::string("none") : known) + ")");
}

RenderResult render_scene(const Scene& scene, const RenderJobOptions& options, const RenderControl& control) {
    using clock = std::chrono::steady_clock;
    const Camera* camera = select_camera(scene, options.camera);
    int width = options.width > 0 ? options.width : 1920;
    int height = options.height > 0 ? options.height : CameraModel::default_height(camera, width);
    if (width > 65536 || height > 65536) throw std::invalid_argument("image size over 65536 pixels");
    if (options.render.spp < 1) throw std::invalid_argument("--spp must be at least 1");
    if (options.render.max_depth < 0) throw std::invalid_argument("--max-depth must not be negative");
    std::unique_ptr<Integrator> integrator = make_integrator(options.render);

    RenderResult result;
    result.camera_name = camera ? camera->name : "default";
    result.triangles = scene.triangle_count();
    auto t0 = clock::now();
    RenderScene rs(scene, camera, width, height);
    auto t1 = clock::now();
    Film film(width, height);
    result.stats = render_image(rs, *integrator, options.render, film, control);
    auto t2 = clock::now();
    // Each pixel sample traced one light path (bdpt, lt): splats average over spp.
    result.image = film.resolve(result.stats.spp_done);
    result.build_seconds = std::chrono::duration<double>(t1 - t0).count();
    result.render_seconds = std::chrono::duration<double>(t2 - t1).count();
    return result;
}

size_t peak_resident_bytes() {
    std::ifstream f("/proc/self/status");
    std::string line;
    while (std::getline(f, line)) {
        if (line.rfind("VmHWM:", 0) == 0) return static_cast<size_t>(std::strtoull(line.c_str() + 6, nullptr, 10)) * 1024;
    }
    return 0;
}

}  // namespace veach
