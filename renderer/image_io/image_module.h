// Opens libveach_image_io.so (image_codec.h: every OpenImageIO call) the first time an image is
// read or written, so that a process that reads and writes none never loads OpenImageIO.
#pragma once

#include <stdexcept>

#include "image_io/image_codec.h"

namespace veach {

class ImageModuleError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;  // one line, naming the module and why it failed
};

// The module's file name, installed beside libveach (the same folder as the library or program
// that holds this code), else found on the library path (RUNPATH, LD_LIBRARY_PATH, the system's).
constexpr const char* k_image_module_name = "libveach_image_io.so";

// The module's codec, opened on the first call (thread-safe) and kept for the process's life.
// Throws ImageModuleError, on every call, when it cannot be opened or is another version's.
const image_io::Codec& image_codec();

}  // namespace veach
