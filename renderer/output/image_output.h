// The output driver: writes a scene-linear Image to a file whose format comes from the
// extension. Scene-linear formats (EXR, HDR) are written as they are; display-referred ones
// (PNG, JPEG, TIFF) go through an OpenColorIO display transform first. Files are encoded in
// memory and written through AtomicFile (output/atomic_file.h): never a partial file.
#pragma once

#include <map>
#include <string>
#include <utility>
#include <vector>

#include "film/film.h"
#include "output/atomic_file.h"

namespace veach {

struct DisplaySettings {
    std::string display;  // empty: the config's default display
    std::string view;     // empty: the display's default view ("Standard" in the built-in config)
    std::string look;     // empty: none
    float exposure = 0;   // stops, applied in scene-linear before the view
    float gamma = 1;      // applied after the view transform
};

struct OutputSettings {
    DisplaySettings display;
    bool half = false;              // EXR: half floats
    std::string exr_codec = "zip";  // EXR compression: see is_exr_codec()
    // EXR render passes, in Blender's names: "combined", "depth", "normal", "albedo",
    // "variance". Empty: a plain RGBA file. Otherwise a multi-layer EXR with channels
    // ViewLayer.Combined.R/G/B/A, ViewLayer.Depth.Z, ViewLayer.Normal.X/Y/Z,
    // ViewLayer.Albedo.R/G/B, ViewLayer.Variance.R/G/B; with denoising also "noisy",
    // "denoising_normal", "denoising_albedo", "denoising_depth" (ViewLayer.Noisy.R/G/B,
    // ViewLayer.Denoising Normal.X/Y/Z, ...). Other formats write Combined only.
    std::vector<std::string> passes;
    int quality = 95;                             // JPEG
    int bits = 8;                                 // PNG/TIFF: 8 or 16
    // Written as attributes: numbers (a whole number that fits an int, a decimal) as int and
    // float attributes, anything else as a string; JPEG/TIFF in their description, HDR as header lines.
    std::map<std::string, std::string> metadata;
    // The host's own attributes (the render option "attributes", the command's --attrib), added
    // to `metadata` when an image is written.
    std::vector<std::pair<std::string, std::string>> user_attributes;
};

// True for formats written scene-linear (no display transform).
bool is_scene_linear_format(const std::string& path);
// True for formats this driver writes (by extension).
bool is_known_image_format(const std::string& path);

// OpenEXR compressions: none, rle, zips, zip, piz, pxr24, b44, b44a, dwaa, dwab; zip, zips,
// dwaa and dwab may carry a level ("zip:9", "dwaa:45").
bool is_exr_codec(const std::string& codec);
// The compressions' names above, in that order: what the C API lists and its messages quote.
const std::vector<std::string>& exr_codec_names();
// The pass names write_image() knows, in file order.
const std::vector<std::string>& known_passes();
// True when a pass needs the film's first-hit AOVs (depth, normal, albedo).
bool pass_needs_aovs(const std::string& pass);
// True for the passes only a denoised render has (noisy, denoising_normal/albedo/depth).
bool pass_needs_denoise(const std::string& pass);

// Throws OutputError with a one-line message naming the file on failure; never leaves a partial
// file under `path`.
void write_image(const Image& image, const std::string& path, const OutputSettings& settings);

// The metadata write_image() put into a file of any format it writes, read back: the string
// attributes of EXR, PNG, the "key=value; ..." ImageDescription of JPEG and TIFF, and the
// "key=value" header lines of Radiance HDR. False (and `error`, one line) when the file cannot
// be read as an image.
bool read_image_metadata(const std::string& path, std::map<std::string, std::string>& metadata, std::string& error);

}  // namespace veach
