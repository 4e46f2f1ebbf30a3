#include "output/image_output.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <system_error>
#include <vector>

#include "core/one_line.h"
#include "image_io/image_module.h"
#include "output/atomic_file.h"
#include "output/display_transform.h"

namespace veach {

namespace {

namespace fs = std::filesystem;

enum class Format { exr, hdr, png, jpeg, tiff };

// OpenEXR's compressions, in the order the API lists them; max_level 0: takes no level.
struct ExrCodec {
    const char* name;
    int max_level;
};
constexpr ExrCodec k_exr_codecs[] = {{"none", 0}, {"rle", 0},   {"zips", 9},  {"zip", 9},     {"piz", 0},
                                     {"pxr24", 0}, {"b44", 0}, {"b44a", 0}, {"dwaa", 1000}, {"dwab", 1000}};

struct FormatInfo {
    Format format;
    const char* oiio_name;  // the OIIO writer, named explicitly so the file name cannot mislead it
    const char* label;
};

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
    return s;
}

bool format_of(const std::string& path, FormatInfo& info) {
    const std::string ext = lower(fs::path(path).extension().string());
    if (ext == ".exr")
        info = {Format::exr, "openexr", "EXR"};
    else if (ext == ".hdr")
        info = {Format::hdr, "hdr", "HDR"};
    else if (ext == ".png")
        info = {Format::png, "png", "PNG"};
    else if (ext == ".jpg" || ext == ".jpeg")
        info = {Format::jpeg, "jpeg", "JPEG"};
    else if (ext == ".tif" || ext == ".tiff")
        info = {Format::tiff, "tiff", "TIFF"};
    else
        return false;
    return true;
}

[[noreturn]] void fail(const std::string& path, const std::string& reason) {
    throw OutputError(path + ": " + one_line(reason));
}

// Display-referred values in [0, 1] to integers, rounding to nearest so that mid-grey and
// other exact values land on the code value a colour-science formula predicts.
template <typename T>
std::vector<T> quantise(const std::vector<float>& values, int channels_in, int channels_out) {
    // In double: a float product can itself round across the .5 boundary at 16 bits.
    constexpr double scale = std::numeric_limits<T>::max();
    const size_t pixels = values.size() / channels_in;
    std::vector<T> out(pixels * channels_out);
    for (size_t i = 0; i < pixels; ++i) {
        for (int c = 0; c < channels_out; ++c) {
            float v = values[i * channels_in + c];
            v = v > 0.0f ? (v < 1.0f ? v : 1.0f) : 0.0f;
            out[i * channels_out + c] = static_cast<T>(std::lround(static_cast<double>(v) * scale));
        }
    }
    return out;
}

std::vector<float> drop_alpha(const std::vector<float>& rgba) {
    std::vector<float> rgb(rgba.size() / 4 * 3);
    for (size_t i = 0; i < rgba.size() / 4; ++i)
        for (int c = 0; c < 3; ++c) rgb[i * 3 + c] = rgba[i * 4 + c];
    return rgb;
}

// Pixels in the layout and type the file will hold, plus what the encoder is told of them
// (request.data is set when the bytes are encoded).
struct Encoded {
    image_io::EncodeRequest request;
    std::vector<float> f32;
    std::vector<uint8_t> u8;
    std::vector<uint16_t> u16;
    const void* data() const {
        if (!f32.empty()) return f32.data();
        if (!u8.empty()) return u8.data();
        return u16.data();
    }
};

void set_shape(Encoded& enc, int width, int height, int channels, image_io::SampleType file_type,
               image_io::SampleType data_type) {
    enc.request.width = width;
    enc.request.height = height;
    enc.request.channels = channels;
    enc.request.file_type = file_type;
    enc.request.data_type = data_type;
}

void add_attribute(Encoded& enc, const std::string& name, const std::string& text) {
    enc.request.attributes.push_back({name, text, 0, 0, image_io::Attribute::Kind::Text});
}

void add_attribute(Encoded& enc, const std::string& name, int value) {
    enc.request.attributes.push_back({name, std::string(), value, 0, image_io::Attribute::Kind::Integer});
}

// Metadata whose text is a number is written as one (an int attribute for a whole number that
// fits, else a float), so that a reader gets numbers: "64" an int, "1.25" a float, "0:16" text.
void add_metadata_attribute(Encoded& enc, const std::string& name, const std::string& text) {
    const char* begin = text.data();
    const char* end = begin + text.size();
    long long whole = 0;
    auto [p, ec] = std::from_chars(begin, end, whole);
    if (!text.empty() && ec == std::errc() && p == end && whole >= INT32_MIN && whole <= INT32_MAX &&
        (text.size() == 1 || text[0] != '0')) {
        add_attribute(enc, name, static_cast<int>(whole));
        return;
    }
    double number = 0;
    auto [q, ec2] = std::from_chars(begin, end, number);
    if (!text.empty() && ec2 == std::errc() && q == end && std::isfinite(number) &&
        text.find_first_of("eE.") != std::string::npos && text.find_first_not_of("0123456789.eE+-") == std::string::npos) {
        enc.request.attributes.push_back({name, std::string(), 0, static_cast<float>(number),
                                          image_io::Attribute::Kind::Float});
        return;
    }
    add_attribute(enc, name, text);
}

// One pass of a multi-layer EXR: Blender's layer name, its channel suffixes and where its values
// live in the Image.
struct PassLayout {
    const char* name;      // as --passes spells it
    const char* layer;     // Blender's pass name
    const char* suffixes;  // one letter per channel
    const std::vector<float> Image::*values;
    int stride;  // floats per pixel in `values`
};

const PassLayout k_pass_layouts[] = {
    {"combined", "Combined", "RGBA", &Image::rgba, 4},    {"depth", "Depth", "Z", &Image::depth, 1},
    {"normal", "Normal", "XYZ", &Image::normal, 3},       {"albedo", "Albedo", "RGB", &Image::albedo, 3},
    {"variance", "Variance", "RGB", &Image::variance, 3},
    // With --denoise: the image before denoising, and the denoiser's features (Cycles' names).
    {"noisy", "Noisy", "RGB", &Image::noisy, 3},
    {"denoising_normal", "Denoising Normal", "XYZ", &Image::denoising_normal, 3},
    {"denoising_albedo", "Denoising Albedo", "RGB", &Image::denoising_albedo, 3},
    {"denoising_depth", "Denoising Depth", "Z", &Image::denoising_depth, 1},
    {"samples", "Sample Count", "X", &Image::sample_count, 1},
};

// The view layer Blender names its passes under by default.
constexpr const char* k_view_layer = "ViewLayer";

// A multi-layer EXR laid out as Blender writes one: "ViewLayer.<Pass>.<channel>", channels of a
// pass together, passes in the order of k_pass_layouts whatever order they were asked in.
void encode_multilayer(Encoded& enc, const Image& image, const std::string& path, const OutputSettings& settings) {
    std::vector<const PassLayout*> chosen;
    for (const PassLayout& layout : k_pass_layouts)
        if (std::find(settings.passes.begin(), settings.passes.end(), layout.name) != settings.passes.end())
            chosen.push_back(&layout);
    for (const std::string& p : settings.passes)
        if (std::none_of(std::begin(k_pass_layouts), std::end(k_pass_layouts),
                         [&](const PassLayout& l) { return p == l.name; }))
            fail(path, "unknown render pass '" + p + "'");
    const size_t pixels = static_cast<size_t>(image.width) * image.height;
    std::vector<std::string> names;
    std::vector<image_io::SampleType> formats;
    const image_io::SampleType colour_type = settings.half ? image_io::SampleType::half : image_io::SampleType::float32;
    for (const PassLayout* l : chosen) {
        if ((image.*(l->values)).size() != pixels * l->stride)
            fail(path, std::string("the render has no ") + l->name + " pass (the film did not record it)");
        for (const char* c = l->suffixes; *c; ++c) {
            names.push_back(std::string(k_view_layer) + "." + l->layer + "." + *c);
            // Half floats keep 3 significant digits: fine for colour, not for depth, which
            // stays float as Blender writes it.
            const bool depth = l->stride == 1;  // Depth, Denoising Depth
            formats.push_back(depth ? image_io::SampleType::float32 : colour_type);
        }
    }
    const int channels = static_cast<int>(names.size());
    set_shape(enc, image.width, image.height, channels, image_io::SampleType::float32, image_io::SampleType::float32);
    enc.request.channel_names = names;
    enc.request.channel_types = formats;
    enc.request.alpha_channel = chosen.front() == &k_pass_layouts[0] ? 3 : -1;
    enc.request.z_channel = -1;
    enc.f32.resize(pixels * channels);
    for (size_t i = 0; i < pixels; ++i) {
        float* out = &enc.f32[i * channels];
        for (const PassLayout* l : chosen)
            for (int c = 0; c < l->stride; ++c) *out++ = (image.*(l->values))[i * l->stride + c];
    }
}

Encoded encode(const Image& image, const std::string& path, const FormatInfo& info, const OutputSettings& settings) {
    Encoded enc;
    const int w = image.width, h = image.height;
    switch (info.format) {
        case Format::exr:
            if (!is_exr_codec(settings.exr_codec)) {
                std::string known;
                for (const std::string& n : exr_codec_names()) known += (known.empty() ? "" : ", ") + n;
                fail(path, "unknown EXR codec '" + settings.exr_codec + "' (known: " + known + ")");
            }
            if (settings.passes.empty()) {
                set_shape(enc, w, h, 4, settings.half ? image_io::SampleType::half : image_io::SampleType::float32,
                          image_io::SampleType::float32);
                enc.f32 = image.rgba;
            } else {
                encode_multilayer(enc, image, path, settings);
            }
            add_attribute(enc, "compression", settings.exr_codec);
            return enc;
        case Format::hdr:
            // RGBE has no alpha channel.
            set_shape(enc, w, h, 3, image_io::SampleType::float32, image_io::SampleType::float32);
            enc.f32 = drop_alpha(image.rgba);
            return enc;
        case Format::png:
        case Format::tiff:
        case Format::jpeg: break;
    }

    // libjpeg's limit; past it libjpeg calls exit() from inside OpenImageIO.
    constexpr int k_max_jpeg_size = 65500;
    if (info.format == Format::jpeg && (w > k_max_jpeg_size || h > k_max_jpeg_size))
        fail(path, "JPEG images are at most " + std::to_string(k_max_jpeg_size) + " pixels wide and high, not " +
                       std::to_string(w) + "x" + std::to_string(h));
    int bits = 8;
    if (info.format != Format::jpeg) {
        if (settings.bits != 8 && settings.bits != 16)
            fail(path, std::string(info.label) + " bit depth must be 8 or 16, not " + std::to_string(settings.bits));
        bits = settings.bits;
    }
    // JPEG has no alpha; PNG and TIFF keep it.
    const int channels = info.format == Format::jpeg ? 3 : 4;
    Image display = image;
    if (channels == 4) {
        // The film is premultiplied (associated) like EXR; PNG stores straight alpha, and a
        // display transform is only meaningful on un-premultiplied colour. Alpha 0 keeps its
        // colour rather than dividing by zero.
        for (size_t i = 0; i < display.rgba.size(); i += 4) {
            const float a = display.rgba[i + 3];
            if (a > 0.0f && a != 1.0f)
                for (int c = 0; c < 3; ++c) display.rgba[i + c] /= a;
        }
    }
    try {
        DisplayTransform transform(settings.display);
        transform.apply(display);
    } catch (const std::exception& e) {
        fail(path, e.what());
    }
    const image_io::SampleType type = bits == 8 ? image_io::SampleType::uint8 : image_io::SampleType::uint16;
    if (bits == 8)
        enc.u8 = quantise<uint8_t>(display.rgba, 4, channels);
    else
        enc.u16 = quantise<uint16_t>(display.rgba, 4, channels);
    set_shape(enc, w, h, channels, type, type);
    if (channels == 4) {
        // Already un-premultiplied above: stop OIIO from dividing by alpha a second time.
        add_attribute(enc, "oiio:UnassociatedAlpha", 1);
    }
    if (info.format == Format::jpeg) {
        const int quality = std::clamp(settings.quality, 1, 100);
        add_attribute(enc, "Compression", "jpeg:" + std::to_string(quality));
        // Renders have sharp coloured edges (lights, saturated materials) that 4:2:0 chroma
        // subsampling visibly smears; full-resolution chroma costs little at these qualities.
        add_attribute(enc, "jpeg:subsampling", "4:4:4");
    }
    if (info.format == Format::tiff) add_attribute(enc, "compression", "zip");
    return enc;
}

// OpenImageIO's Radiance writer keeps no attributes, but a Radiance header is lines of
// "NAME=value" up to a blank line, and readers skip the names they do not know: the metadata
// goes there, after the "#?RADIANCE" line, before the bytes reach the disk.
bool add_radiance_header_lines(std::vector<unsigned char>& bytes, const std::map<std::string, std::string>& metadata) {
    const auto first_line = std::find(bytes.begin(), bytes.end(), '\n');
    if (bytes.size() < 2 || bytes[0] != '#' || bytes[1] != '?' || first_line == bytes.end()) return false;
    std::string lines;
    for (const auto& [key, value] : metadata) {
        std::string line = key + "=" + value;
        std::replace(line.begin(), line.end(), '\n', ' ');
        std::replace(line.begin(), line.end(), '\r', ' ');
        lines += line + "\n";
    }
    bytes.insert(first_line + 1, lines.begin(), lines.end());
    return true;
}

// Encodes the whole file into memory (the image module's encoders write through OpenImageIO's
// IOProxy): the encoders never touch the disk, so a full disk cannot make one of them fail
// half-way (libjpeg would exit() the process from inside OpenImageIO), and the bytes then go
// through AtomicFile, which checks every write.
std::vector<unsigned char> encode_file(Encoded& enc, const std::string& path, const FormatInfo& info) {
    const image_io::Codec* codec = nullptr;
    try {
        codec = &image_codec();
    } catch (const ImageModuleError& e) {
        fail(path, e.what());
    }
    enc.request.writer = info.oiio_name;
    enc.request.name = path;
    enc.request.data = enc.data();
    std::vector<unsigned char> bytes;
    std::string error;
    if (!codec->encode(enc.request, bytes, error)) fail(path, error);
    return bytes;
}

}  // namespace

bool is_known_image_format(const std::string& path) {
    FormatInfo info;
    return format_of(path, info);
}

bool is_exr_codec(const std::string& codec) {
    const size_t colon = codec.find(':');
    const std::string name = codec.substr(0, colon);
    for (const ExrCodec& c : k_exr_codecs) {
        if (name != c.name) continue;
        if (colon == std::string::npos) return true;
        if (c.max_level == 0) return false;
        const std::string level = codec.substr(colon + 1);
        if (level.empty() || level.size() > 4 || !std::all_of(level.begin(), level.end(), ::isdigit)) return false;
        const int v = std::stoi(level);
        return v >= 1 && v <= c.max_level;
    }
    return false;
}

const std::vector<std::string>& exr_codec_names() {
    static const std::vector<std::string> names = [] {
        std::vector<std::string> n;
        for (const ExrCodec& c : k_exr_codecs) n.push_back(c.name);
        return n;
    }();
    return names;
}

const std::vector<std::string>& known_passes() {
    static const std::vector<std::string> names = [] {
        std::vector<std::string> n;
        for (const PassLayout& l : k_pass_layouts) n.push_back(l.name);
        return n;
    }();
    return names;
}

bool pass_needs_aovs(const std::string& pass) { return pass == "depth" || pass == "normal" || pass == "albedo"; }

bool pass_needs_denoise(const std::string& pass) { return pass == "noisy" || pass.rfind("denoising_", 0) == 0; }

bool is_scene_linear_format(const std::string& path) {
    FormatInfo info;
    return format_of(path, info) && (info.format == Format::exr || info.format == Format::hdr);
}

void write_image(const Image& image, const std::string& path, const OutputSettings& settings) {
    FormatInfo info;
    if (!format_of(path, info)) {
        const std::string ext = fs::path(path).extension().string();
        fail(path, ext.empty() ? "unknown image format (no extension)" : "unknown image format '" + ext + "'");
    }
    if (image.width <= 0 || image.height <= 0 ||
        image.rgba.size() != static_cast<size_t>(image.width) * image.height * 4)
        fail(path, "invalid image (" + std::to_string(image.width) + "x" + std::to_string(image.height) + ")");

    const fs::path target(path);
    const fs::path folder = target.parent_path().empty() ? fs::path(".") : target.parent_path();
    std::error_code ec;
    if (!fs::is_directory(folder, ec)) fail(path, "folder '" + folder.string() + "' does not exist");
    if (fs::is_directory(target, ec)) fail(path, "is a folder");

    // Everything that can fail before touching the disk (display transform, settings) happens
    // here, so a bad setting never creates a temp file.
    Encoded enc = encode(image, path, info, settings);
    // EXR keeps typed attributes; PNG's text chunks (and the description of JPEG and TIFF) keep text.
    for (const auto& [key, value] : settings.metadata) {
        if (info.format == Format::exr)
            add_metadata_attribute(enc, key, value);
        else
            add_attribute(enc, key, value);
    }
    if ((info.format == Format::jpeg || info.format == Format::tiff) && !settings.metadata.empty() &&
        !settings.metadata.count("ImageDescription")) {
        // JPEG (EXIF) and TIFF only keep fixed tags, so our own keys would be dropped: they travel
        // together in the description, "key=value; key=value", which every viewer shows.
        std::string description;
        for (const auto& [key, value] : settings.metadata)
            description += (description.empty() ? "" : "; ") + key + "=" + value;
        add_attribute(enc, "ImageDescription", description);
    }

    std::vector<unsigned char> bytes = encode_file(enc, path, info);
    if (info.format == Format::hdr && !settings.metadata.empty() &&
        !add_radiance_header_lines(bytes, settings.metadata))
        fail(path, "cannot add the metadata to the Radiance header");
    write_file_atomically(path, bytes.data(), bytes.size());
}

namespace {

// "key=value; key=value" (JPEG and TIFF descriptions, as write_image() joins them).
void parse_description(const std::string& text, std::map<std::string, std::string>& metadata) {
    for (size_t start = 0; start < text.size();) {
        size_t end = text.find("; ", start);
        if (end == std::string::npos) end = text.size();
        const std::string item = text.substr(start, end - start);
        const size_t eq = item.find('=');
        if (eq != std::string::npos && eq > 0) metadata.emplace(item.substr(0, eq), item.substr(eq + 1));
        start = end + 2;
    }
}

}  // namespace

bool read_image_metadata(const std::string& path, std::map<std::string, std::string>& metadata, std::string& error) {
    FormatInfo info;
    if (!format_of(path, info)) {
        error = path + ": not an image format veach writes";
        return false;
    }
    if (info.format == Format::hdr) {
        // OpenImageIO keeps only the header lines it knows; ours sit between "#?RADIANCE" and
        // the blank line that ends the header.
        std::ifstream in(path, std::ios::binary);
        std::string line;
        if (!in || !std::getline(in, line) || line.rfind("#?", 0) != 0) {
            error = path + ": not a Radiance HDR file";
            return false;
        }
        for (int lines = 0; lines < 4096 && std::getline(in, line) && !line.empty(); ++lines) {
            const size_t eq = line.find('=');
            if (eq != std::string::npos && eq > 0) metadata.emplace(line.substr(0, eq), line.substr(eq + 1));
        }
        return true;
    }
    const image_io::Codec* codec = nullptr;
    try {
        codec = &image_codec();
    } catch (const ImageModuleError& e) {
        error = path + ": " + e.what();
        return false;
    }
    std::string open_error;
    auto input = codec->open_file(path, open_error);
    if (!input) {
        error = path + ": " + one_line(open_error);
        return false;
    }
    const image_io::Header& header = input->header();
    for (const auto& [key, value] : header.attributes) metadata.emplace(key, value);
    if (info.format == Format::jpeg || info.format == Format::tiff) parse_description(header.description, metadata);
    return true;
}

}  // namespace veach
