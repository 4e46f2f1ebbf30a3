// Reading images through OpenImageIO, for what stb cannot read (EXR, HDR, TIFF, ...) and for
// environment maps. OpenImageIO lives in the image module (image_io/image_module.h), opened by
// the first read; a module that cannot be opened is an ImageReadError naming the file.
#pragma once

#include <cstdint>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

namespace veach {

class ImageReadError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;  // "FILE: what is wrong", one line
};

struct ImageData {
    int width = 0, height = 0;
    std::vector<float> rgba;    // width * height * 4, row 0 at the top
    bool srgb_encoded = false;  // the file stores sRGB-encoded values (8-bit PNG/JPEG, ...)
    bool eight_bit = false;     // the file stores 8-bit values: rgba holds k / 255 (to the last bit)
};

// Called with the header's size once it is known and before any pixel memory is allocated (the
// decoded image is width * height * 4 floats; nothing else of that order is allocated): a caller
// with a memory budget charges it here and throws to refuse the image.
using BeforeDecode = std::function<void(int width, int height)>;

// Reads the first subimage as float RGBA: grey becomes RGB, missing alpha is 1. Values are as
// stored (srgb_encoded tells whether they need decoding). Only the colour and alpha channels are
// read, straight into the RGBA buffer, so a file with many channels costs no more than RGBA.
// Throws ImageReadError.
ImageData read_image(const std::string& path, const BeforeDecode& before_decode = {});

// The same from encoded bytes in memory (an image inside a .glb or a data: URI); `name` is for
// messages, and its extension, when it has one, tells OpenImageIO the format.
ImageData read_image_memory(const unsigned char* data, size_t size, const std::string& name,
                            const BeforeDecode& before_decode = {});

// Reads an image as scene-linear RGBA: sRGB-encoded files are decoded. Throws ImageReadError.
ImageData read_image_linear(const std::string& path);

}  // namespace veach
