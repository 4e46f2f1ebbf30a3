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

ImageData read_opened(std::unique_ptr<OIIO::ImageInput> in, const std::string& path);

}  // namespace

ImageData read_image(const std::string& path) { return read_opened(OIIO::ImageInput::open(path), path); }

ImageData read_image_memory(const unsigned char* data, size_t size, const std::string& name) {
    // OpenImageIO reads through a proxy over our bytes; it neither copies nor frees them.
    OIIO::Filesystem::IOMemReader proxy(const_cast<unsigned char*>(data), size);
    return read_opened(OIIO::ImageInput::open(name, nullptr, &proxy), name);
}

namespace {

ImageData read_opened(std::unique_ptr<OIIO::ImageInput> in, const std::string& path) {
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
    std::vector<float> raw(static_cast<size_t>(w) * h * nc);
    if (!in->read_image(0, 0, 0, nc, OIIO::TypeDesc::FLOAT, raw.data())) {
        std::string err = in->geterror();
        err = err.substr(0, err.find('\n'));
        throw ImageReadError(path + ": cannot decode the image" + (err.empty() ? "" : " (" + err + ")"));
    }
    ImageData out;
    out.width = w;
    out.height = h;
    std::string cs = spec.get_string_attribute("oiio:ColorSpace");
    out.srgb_encoded = cs == "sRGB" || (cs.empty() && spec.format.basetype == OIIO::TypeDesc::UINT8);
    out.rgba.resize(static_cast<size_t>(w) * h * 4);
    int alpha = spec.alpha_channel;
    for (size_t i = 0, n = static_cast<size_t>(w) * h; i < n; ++i) {
        const float* p = &raw[i * nc];
        float* o = &out.rgba[i * 4];
        if (nc >= 3) {
            o[0] = p[0], o[1] = p[1], o[2] = p[2];
        } else {
            o[0] = o[1] = o[2] = p[0];  // grey, or grey + alpha
        }
        o[3] = alpha >= 0 && alpha < nc ? p[alpha] : (nc == 2 ? p[1] : (nc >= 4 ? p[3] : 1.0f));
    }
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
