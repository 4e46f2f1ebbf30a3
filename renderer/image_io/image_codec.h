// The one interface between libveach and its image module, libveach_image_io.so, which holds
// every OpenImageIO call. Debian's OpenImageIO pulls in ~260 shared libraries (FFmpeg, OpenCV,
// GDAL, DCMTK, ...), and the dynamic loader's work on them was most of the start of a process
// that reads and writes no image (a farm part writing a .vpart, `veach --version`, a host that
// only queries the device). The module is opened on first use instead (image_module.h), so only
// a process that decodes or encodes an image pays for it.
//
// Both sides are built from this header in one build and the module refuses a libveach of
// another version or interface, so C++ types may cross: no OpenImageIO type does. Nothing here
// throws across the boundary: failures come back as false or null with a message (OpenImageIO's
// text, possibly several lines; the caller makes it one line and names the file).
#pragma once

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

namespace veach::image_io {

// Changed whenever anything in this header changes: a module built from another header refuses.
constexpr int k_interface_version = 2;

enum class SampleType { uint8, uint16, half, float32 };

// What a file's header says, read before any pixel is decoded.
struct Header {
    int width = 0, height = 0, channels = 0;
    int alpha_channel = -1;   // the file's own alpha channel, -1 when it names none
    bool eight_bit = false;   // the file stores 8-bit samples
    std::string color_space;  // the reader's colour space attribute ("sRGB", "Linear", ... or "")
    std::string description;  // ImageDescription, "" when absent
    // Every string, integer and float attribute, numbers as text (integers in decimal, floats as
    // the shortest text that reads back as the same float).
    std::vector<std::pair<std::string, std::string>> attributes;
};

// An opened image: its header, then its pixels on request, so a caller can charge the decoded
// size against a budget before anything of that size is allocated.
class Decoder {
public:
    virtual ~Decoder() = default;
    virtual const Header& header() const = 0;
    // Channels [begin, end) of the first subimage as floats; pixel i's first value is written at
    // `first` + i * pixel_stride bytes (row 0 at the top).
    virtual bool read_channels(int begin, int end, float* first, std::ptrdiff_t pixel_stride,
                               std::string& error) = 0;
};

// One attribute of an image to write, a string, an integer or a float, kept in the order given.
struct Attribute {
    enum class Kind { Text, Integer, Float };
    std::string name;
    std::string text;
    int integer = 0;
    float number = 0;
    Kind kind = Kind::Text;
};

// An image to encode into memory.
struct EncodeRequest {
    std::string writer;  // OpenImageIO's writer ("openexr", "png", "jpeg", "tiff", "hdr")
    std::string name;    // the file the bytes are for, passed to the writer; nothing is written there
    int width = 0, height = 0, channels = 0;
    SampleType file_type = SampleType::float32;  // the samples the file stores
    // Multi-layer files: every channel's name and stored type, and which are alpha and depth.
    // Empty names: the writer's default names (R, G, B, A) and file_type for every channel.
    std::vector<std::string> channel_names;
    std::vector<SampleType> channel_types;
    int alpha_channel = -1, z_channel = -1;  // used only with channel_names
    std::vector<Attribute> attributes;
    SampleType data_type = SampleType::float32;  // the samples at `data`: width * height * channels
    const void* data = nullptr;
};

class Codec {
public:
    // Null (and `error`) when the file or bytes cannot be opened as an image. `name` is for the
    // reader: its extension, when it has one, tells the format of bytes in memory; the bytes must
    // outlive the decoder.
    virtual std::unique_ptr<Decoder> open_file(const std::string& path, std::string& error) const = 0;
    virtual std::unique_ptr<Decoder> open_memory(const unsigned char* data, size_t size, const std::string& name,
                                                 std::string& error) const = 0;
    // The whole file's bytes, encoded in memory (the encoders never touch the disk).
    virtual bool encode(const EncodeRequest& request, std::vector<unsigned char>& bytes,
                        std::string& error) const = 0;

protected:
    ~Codec() = default;
};

}  // namespace veach::image_io

// The module's only exported symbol: its codec, or null when `interface_version` or
// `veach_version` (VEACH_VERSION_STRING) is not the one it was built with.
namespace veach::image_io {
using ModuleEntry = const Codec* (*)(int interface_version, const char* veach_version);
constexpr const char* k_module_entry = "veach_image_io_codec";
}  // namespace veach::image_io
