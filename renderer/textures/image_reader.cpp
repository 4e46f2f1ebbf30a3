#include "textures/image_reader.h"

#include <cmath>
#include <cstdint>
#include <limits>

#include "core/rgb.h"
#include "image_io/image_module.h"

namespace veach {

namespace {
// Images larger than this (in texels) are refused rather than risking an allocation failure
// from a corrupt or hostile header.
constexpr int64_t k_max_texels = int64_t(1) << 28;

const image_io::Codec& codec_for(const std::string& path) {
    try {
        return image_codec();
    } catch (const ImageModuleError& e) {
        throw ImageReadError(path + ": " + e.what());
    }
}

ImageData read_opened(std::unique_ptr<image_io::Decoder> in, const std::string& open_error, const std::string& path,
                      const BeforeDecode& before) {
    if (!in) {
        std::string err = open_error.empty() ? std::string("cannot open the image") : open_error;
        // OIIO's messages may span lines; keep the first.
        err = err.substr(0, err.find('\n'));
        throw ImageReadError(path + ": " + err);
    }
    const image_io::Header& header = in->header();
    int w = header.width, h = header.height, nc = header.channels;
    if (w <= 0 || h <= 0 || nc <= 0 || static_cast<int64_t>(w) * h > k_max_texels)
        throw ImageReadError(path + ": unsupported image size " + std::to_string(w) + "x" + std::to_string(h));
    if (before) before(w, h);
    ImageData out;
    out.width = w;
    out.height = h;
    const std::string& cs = header.color_space;
    out.srgb_encoded = cs == "sRGB" || (cs.empty() && header.eight_bit);
    out.eight_bit = header.eight_bit;
    // The colour channels (the first three, or one grey channel) and the alpha channel are read
    // into their places of the RGBA buffer with a 4-float stride: the other channels of a
    // many-channel file (an EXR with AOVs) are never decoded into memory.
    const size_t texels = static_cast<size_t>(w) * h;
    out.rgba.assign(texels * 4, 1.0f);
    int alpha = header.alpha_channel;
    if (alpha < 0 || alpha >= nc) alpha = nc == 2 ? 1 : (nc >= 4 ? 3 : -1);
    const int colour = nc >= 3 ? 3 : 1;
    const std::ptrdiff_t stride = 4 * sizeof(float);
    auto read_channels = [&](int begin, int end, float* first) {
        std::string err;
        if (!in->read_channels(begin, end, first, stride, err)) {
            err = err.substr(0, err.find('\n'));
            throw ImageReadError(path + ": cannot decode the image" + (err.empty() ? "" : " (" + err + ")"));
        }
    };
    read_channels(0, colour, out.rgba.data());
    if (alpha >= 0) read_channels(alpha, alpha + 1, out.rgba.data() + 3);
    if (colour == 1)
        for (size_t i = 0; i < texels; ++i) out.rgba[i * 4 + 1] = out.rgba[i * 4 + 2] = out.rgba[i * 4];
    return out;
}

}  // namespace

ImageData read_image(const std::string& path, const BeforeDecode& before_decode) {
    std::string error;
    auto in = codec_for(path).open_file(path, error);
    return read_opened(std::move(in), error, path, before_decode);
}

ImageData read_image_memory(const unsigned char* data, size_t size, const std::string& name,
                            const BeforeDecode& before_decode) {
    std::string error;
    auto in = codec_for(name).open_memory(data, size, name, error);
    return read_opened(std::move(in), error, name, before_decode);
}

ImageData read_image_linear(const std::string& path) {
    ImageData img = read_image(path);
    if (img.srgb_encoded) {
        for (size_t i = 0; i < img.rgba.size(); i += 4)
            for (int c = 0; c < 3; ++c) img.rgba[i + c] = srgb_to_linear(img.rgba[i + c]);
        img.srgb_encoded = false;
    }
    return img;
}

}  // namespace veach
