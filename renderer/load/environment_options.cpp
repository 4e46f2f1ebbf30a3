#include "load/environment_options.h"

#include <cmath>
#include <filesystem>
#include <stdexcept>

#include "textures/image_reader.h"

namespace veach {

void apply_environment(const EnvironmentOptions& options, Scene* scene) {
    if (!options.requested()) return;
    if (!(std::isfinite(options.strength) && options.strength >= 0.0f))
        throw std::invalid_argument("the environment strength must be a finite number >= 0");
    Environment env;
    env.enabled = true;
    env.strength = options.strength;
    env.rotation = options.rotate_degrees * (k_pi / 180.0f);
    env.color = options.has_color ? options.color : Rgb(1.0f);
    if (!options.map_path.empty()) {
        // A FIFO would block the reader and /dev/zero never ends: only regular files are maps.
        std::error_code ec;
        const auto status = std::filesystem::status(options.map_path, ec);
        if (ec || !std::filesystem::exists(status)) throw std::invalid_argument(options.map_path + ": file not found");
        if (std::filesystem::is_directory(status)) throw std::invalid_argument(options.map_path + ": is a directory");
        if (!std::filesystem::is_regular_file(status))
            throw std::invalid_argument(options.map_path + ": not a regular file");
        ImageData img;
        try {
            img = read_image_linear(options.map_path);
        } catch (const ImageReadError& e) {
            throw std::invalid_argument(e.what());
        }
        env.width = img.width;
        env.height = img.height;
        env.source = options.map_path;
        env.texels.resize(static_cast<size_t>(img.width) * img.height * 3);
        for (size_t i = 0, n = static_cast<size_t>(img.width) * img.height; i < n; ++i)
            for (int c = 0; c < 3; ++c) env.texels[i * 3 + c] = img.rgba[i * 4 + c];
    }
    scene->environment = std::move(env);
    scene->features.environment = true;
}

}  // namespace veach
