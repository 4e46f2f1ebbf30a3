// The output driver: writes a scene-linear Image to a file whose format comes from the
// extension. Scene-linear formats (EXR, HDR) are written as they are; display-referred ones
// (PNG, JPEG, TIFF) go through an OpenColorIO display transform first. Writes are atomic: a
// temporary file in the target folder, renamed when complete.
#pragma once

#include <map>
#include <stdexcept>
#include <string>

#include "film/film.h"

namespace veach {

class OutputError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

struct DisplaySettings {
    std::string display;  // empty: the config's default display
    std::string view;     // empty: the display's default view ("Standard" in the built-in config)
    std::string look;     // empty: none
    float exposure = 0;   // stops, applied in scene-linear before the view
    float gamma = 1;      // applied after the view transform
};

struct OutputSettings {
    DisplaySettings display;
    bool half = false;             // EXR: half floats
    int quality = 95;              // JPEG
    int bits = 8;                  // PNG/TIFF: 8 or 16
    std::map<std::string, std::string> metadata;  // written as string attributes
};

// True for formats written scene-linear (no display transform).
bool is_scene_linear_format(const std::string& path);

// Throws OutputError with a one-line message naming the file on failure; never leaves a partial
// file under `path`.
void write_image(const Image& image, const std::string& path, const OutputSettings& settings);

}  // namespace veach
