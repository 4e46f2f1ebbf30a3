#include "textures/image_reader.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <cmath>
#include <cstdint>
#include <limits>

#include "core/rgb.h"

namespace veach {

namespace {
// Images larger than this (in texels) are refused rather than risking an allocation failure
// from a corrupt or hostile header.
constexpr int64_t k_max_texels = int64_t(1) << 28;
}  // namespace

namespace {

ImageData read_opened(std::unique_ptr<OIIO::ImageInput> in, const std::string& path, const BeforeDecode& before);

}  // namespace

ImageData read_image(const std::string& path, const BeforeDecode& before_decode) {
    return read_opened(OIIO::ImageInput::open(path), path, before_decode);
}

ImageData read_image_memory(const unsigned char* data, size_t size, const std::string& name,
                            const BeforeDecode& before_decode) {
    // OpenImageIO reads through a proxy over our bytes; it neither copies nor frees them.
    OIIO::Filesystem::IOMemReader proxy(const_cast<unsigned char*>(data), size);
    return read_opened(OIIO::ImageInput::open(name, nullptr, &proxy), name, before_decode);
}

namespace {

ImageData read_opened(std::unique_ptr<OIIO::ImageInput> in, const std::string& path, const BeforeDecode& before) {
    if (!in) {
        std::string err = OIIO::geterror();
        if (err.empty()) err = "cannot open the image";
        // OIIO's messages may span lines; keep the first.
        err = err.substr(0, err.find('\n'));
        throw ImageReadError(path + ": " + err);
    }
    const OIIO::ImageSpec& spec = in->spec();
    int w = spec.width, h = spec.height, nc = spec.nchannels;
    if (w <= 0 || h <= 0 || nc <= 0 || static_cast<int64_t>(w) * h > k_max_texels)
        throw ImageReadError(path + ": unsupported image size " + std::to_string(w) + "x" + std::to_string(h));
    if (before) before(w, h);
    ImageData out;
    out.width = w;
    out.height = h;
    std::string cs = spec.get_string_attribute("oiio:ColorSpace");
    out.srgb_encoded = cs == "sRGB" || (cs.empty() && spec.format.basetype == OIIO::TypeDesc::UINT8);
    out.eight_bit = spec.format.basetype == OIIO::TypeDesc::UINT8;
    // The colour channels (the first three, or one grey channel) and the alpha channel are read
    // into their places of the RGBA buffer with a 4-float stride: the other channels of a
    // many-channel file (an EXR with AOVs) are never decoded into memory.
    const size_t texels = static_cast<size_t>(w) * h;
    out.rgba.assign(texels * 4, 1.0f);
    int alpha = spec.alpha_channel;
    if (alpha < 0 || alpha >= nc) alpha = nc == 2 ? 1 : (nc >= 4 ? 3 : -1);
    const int colour = nc >= 3 ? 3 : 1;
    const OIIO::stride_t stride = 4 * sizeof(float);
    auto read_channels = [&](int begin, int end, float* first) {
        if (!in->read_image(0, 0, begin, end, OIIO::TypeDesc::FLOAT, first, stride)) {
            std::string err = in->geterror();
            err = err.substr(0, err.find('\n'));
            throw ImageReadError(path + ": cannot decode the image" + (err.empty() ? "" : " (" + err + ")"));
        }
    };
    read_channels(0, colour, out.rgba.data());
    if (alpha >= 0) read_channels(alpha, alpha + 1, out.rgba.data() + 3);
    if (colour == 1)
        for (size_t i = 0; i < texels; ++i) out.rgba[i * 4 + 1] = out.rgba[i * 4 + 2] = out.rgba[i * 4];
    in->close();
    return out;
}

}  // namespace

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
