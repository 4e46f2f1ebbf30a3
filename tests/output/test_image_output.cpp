// The output driver: every format written and read back through OpenImageIO, with the
// precision each format promises, metadata, and the atomic-write guarantees.
#include "output/image_output.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <iterator>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "output/display_transform.h"

namespace veach {
namespace {

namespace fs = std::filesystem;

// Output tests use the built-in config whatever the user's environment says.
class ScopedNoOcio {
public:
    ScopedNoOcio() {
        if (const char* old = std::getenv("OCIO")) m_old = old;
        unsetenv("OCIO");
    }
    ~ScopedNoOcio() {
        if (m_old) setenv("OCIO", m_old->c_str(), 1);
    }
    ScopedNoOcio(const ScopedNoOcio&) = delete;
    ScopedNoOcio& operator=(const ScopedNoOcio&) = delete;

private:
    std::optional<std::string> m_old;
};

class ImageOutputTest : public testing::Test {
protected:
    void SetUp() override {
        const std::string test = testing::UnitTest::GetInstance()->current_test_info()->name();
        m_dir = fs::path(testing::TempDir()) / ("veach_io_" + test + "_" + std::to_string(::getpid()));
        fs::remove_all(m_dir);
        fs::create_directories(m_dir);
    }
    void TearDown() override {
        std::error_code ec;
        fs::remove_all(m_dir, ec);
    }
    std::string file(const std::string& name) const { return (m_dir / name).string(); }

    // Names in the folder: after a write only the target may be there, never a temp file.
    std::vector<std::string> listing() const {
        std::vector<std::string> names;
        for (const auto& entry : fs::directory_iterator(m_dir)) names.push_back(entry.path().filename().string());
        std::sort(names.begin(), names.end());
        return names;
    }

    ScopedNoOcio m_env;
    fs::path m_dir;
};

// A smooth image with values spanning display black to over-range highlights, plus a varying
// alpha in [0.5, 1] so alpha handling is visible.
Image smooth_image(int width = 48, int height = 32) {
    Image img;
    img.width = width;
    img.height = height;
    img.rgba.resize(static_cast<size_t>(width) * height * 4);
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            const float u = static_cast<float>(x) / (width - 1), v = static_cast<float>(y) / (height - 1);
            float* p = img.pixel(x, y);
            p[0] = 1.5f * u * u;
            p[1] = 0.9f * v;
            p[2] = 0.05f + 0.4f * u * v;
            p[3] = 0.5f + 0.5f * v;
        }
    }
    return img;
}

struct ReadBack {
    OIIO::ImageSpec spec;
    std::vector<float> pixels;
    float at(int x, int y, int c) const {
        return pixels[(static_cast<size_t>(y) * spec.width + x) * spec.nchannels + c];
    }
};

// Reads the values as stored: for PNG/TIFF that means straight alpha, without OIIO
// premultiplying on the way in.
ReadBack read_back(const std::string& path) {
    ReadBack r;
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);
    auto in = OIIO::ImageInput::open(path, &config);
    if (!in) {
        ADD_FAILURE() << "cannot read " << path << ": " << OIIO::geterror();
        return r;
    }
    r.spec = in->spec();
    r.pixels.resize(static_cast<size_t>(r.spec.width) * r.spec.height * r.spec.nchannels);
    EXPECT_TRUE(in->read_image(0, 0, 0, r.spec.nchannels, OIIO::TypeDesc::FLOAT, r.pixels.data())) << in->geterror();
    return r;
}

// What the display-referred formats must hold: the built-in display transform's output, of
// straight (un-premultiplied) colour when the format stores alpha.
Image display_referred(const Image& image, bool straight_alpha) {
    Image out = image;
    if (straight_alpha)
        for (size_t i = 0; i < out.rgba.size(); i += 4)
            for (int c = 0; c < 3; ++c) out.rgba[i + c] /= out.rgba[i + 3];
    DisplayTransform({}).apply(out);
    return out;
}

std::string bytes_of(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

TEST(ImageOutputFormats, SceneLinearFormatsAreExrAndHdr) {
    EXPECT_TRUE(is_scene_linear_format("a.exr"));
    EXPECT_TRUE(is_scene_linear_format("dir.v2/A.EXR"));
    EXPECT_TRUE(is_scene_linear_format("a.hdr"));
    EXPECT_FALSE(is_scene_linear_format("a.png"));
    EXPECT_FALSE(is_scene_linear_format("a.jpg"));
    EXPECT_FALSE(is_scene_linear_format("a.tiff"));
    EXPECT_FALSE(is_scene_linear_format("exr"));
}

TEST_F(ImageOutputTest, ExrFloatIsExactAndZipCompressed) {
    Image img = smooth_image();
    img.pixel(5, 7)[0] = 1234.5f;  // scene-linear: no clamping
    img.pixel(6, 7)[1] = -0.25f;
    write_image(img, file("out.exr"), {});
    ReadBack r = read_back(file("out.exr"));
    EXPECT_EQ(r.spec.format, OIIO::TypeDesc::FLOAT);
    EXPECT_EQ(r.spec.nchannels, 4);
    EXPECT_EQ(r.spec.alpha_channel, 3);
    EXPECT_EQ(r.spec.get_string_attribute("compression"), "zip");
    ASSERT_EQ(r.pixels.size(), img.rgba.size());
    EXPECT_EQ(r.pixels, img.rgba);  // row 0 at the top, RGBA, bit-exact
    EXPECT_EQ(listing(), std::vector<std::string>({"out.exr"}));
}

TEST_F(ImageOutputTest, ExrHalfIsWithinHalfPrecision) {
    Image img = smooth_image();
    OutputSettings settings;
    settings.half = true;
    write_image(img, file("half.exr"), settings);
    ReadBack r = read_back(file("half.exr"));
    EXPECT_EQ(r.spec.format, OIIO::TypeDesc::HALF);
    ASSERT_EQ(r.pixels.size(), img.rgba.size());
    for (size_t i = 0; i < img.rgba.size(); ++i) {
        // Half has an 11-bit significand: relative error at most 2^-11 after rounding; values
        // this small (>= 0.05 except exact 0) are all normal halves.
        EXPECT_NEAR(r.pixels[i], img.rgba[i], std::abs(img.rgba[i]) * 0x1p-11f + 1e-7f) << i;
    }
}

TEST_F(ImageOutputTest, HdrIsRgbWithinRgbePrecision) {
    Image img = smooth_image();
    img.pixel(0, 0)[0] = 40.0f;  // over-range survives: HDR is scene-linear
    write_image(img, file("out.hdr"), {});
    ReadBack r = read_back(file("out.hdr"));
    ASSERT_EQ(r.spec.nchannels, 3);
    ASSERT_EQ(r.spec.width, img.width);
    ASSERT_EQ(r.spec.height, img.height);
    for (int y = 0; y < img.height; ++y) {
        for (int x = 0; x < img.width; ++x) {
            const float* p = img.pixel(x, y);
            // RGBE: 8-bit mantissas sharing the exponent of the largest channel.
            const float largest = std::max({p[0], p[1], p[2]});
            for (int c = 0; c < 3; ++c) EXPECT_NEAR(r.at(x, y, c), p[c], largest / 128.0f) << x << "," << y;
        }
    }
}

// Every stored channel within `tolerance` codes of the display-referred value, rounded.
void expect_quantised(const ReadBack& r, const Image& display, int channels, double max_code, long tolerance) {
    ASSERT_EQ(r.spec.width, display.width);
    ASSERT_EQ(r.spec.height, display.height);
    ASSERT_EQ(r.spec.nchannels, channels);
    for (int y = 0; y < display.height; ++y) {
        for (int x = 0; x < display.width; ++x) {
            for (int c = 0; c < channels; ++c) {
                const long expected = std::lround(display.pixel(x, y)[c] * max_code);
                const long got = std::lround(r.at(x, y, c) * max_code);
                EXPECT_LE(std::abs(got - expected), tolerance)
                    << x << "," << y << " channel " << c << ": expected " << display.pixel(x, y)[c] * max_code
                    << ", read " << r.at(x, y, c) * max_code;
            }
        }
    }
}

TEST_F(ImageOutputTest, Png8IsDisplayReferredAndRounded) {
    const Image img = smooth_image();
    write_image(img, file("out.png"), {});
    ReadBack r = read_back(file("out.png"));
    EXPECT_EQ(r.spec.format, OIIO::TypeDesc::UINT8);
    // Exact: rounding the transformed value is the only quantisation step.
    expect_quantised(r, display_referred(img, true), 4, 255, 0);
    EXPECT_EQ(listing(), std::vector<std::string>({"out.png"}));
}

TEST_F(ImageOutputTest, PngMidGreyIsCode118) {
    Image img;
    img.width = 4;
    img.height = 1;
    img.rgba = {0.18f, 0.18f, 0.18f, 1, 0, 0, 0, 1, 1, 1, 1, 1, 2, 2, 2, 1};
    write_image(img, file("grey.png"), {});
    ReadBack r = read_back(file("grey.png"));
    const long expected[] = {118, 0, 255, 255};
    for (int x = 0; x < 4; ++x)
        for (int c = 0; c < 3; ++c) EXPECT_EQ(std::lround(r.at(x, 0, c) * 255), expected[x]) << x;
}

TEST_F(ImageOutputTest, PngStoresStraightAlpha) {
    // Premultiplied mid-grey at half coverage: PNG (straight alpha by its spec) must hold the
    // mid-grey code and alpha 128; JPEG, without alpha, shows it composited over black.
    Image img;
    img.width = 1;
    img.height = 1;
    img.rgba = {0.09f, 0.09f, 0.09f, 0.5f};
    write_image(img, file("half.png"), {});
    ReadBack png = read_back(file("half.png"));
    ASSERT_EQ(png.spec.nchannels, 4);
    EXPECT_EQ(std::lround(png.at(0, 0, 0) * 255), 118);
    EXPECT_EQ(std::lround(png.at(0, 0, 3) * 255), 128);

    // A reader that premultiplies (OIIO's default) gets display colour times alpha.
    auto in = OIIO::ImageInput::open(file("half.png"));
    ASSERT_TRUE(in);
    float px[4];
    ASSERT_TRUE(in->read_image(0, 0, 0, 4, OIIO::TypeDesc::FLOAT, px));
    EXPECT_NEAR(px[0], 118.0f / 255 * 128.0f / 255, 1e-3);
}

TEST_F(ImageOutputTest, Png16IsDisplayReferredAndRounded) {
    const Image img = smooth_image();
    OutputSettings settings;
    settings.bits = 16;
    write_image(img, file("out16.png"), settings);
    ReadBack r = read_back(file("out16.png"));
    EXPECT_EQ(r.spec.format, OIIO::TypeDesc::UINT16);
    expect_quantised(r, display_referred(img, true), 4, 65535, 0);
}

TEST_F(ImageOutputTest, JpegIsWithinCompressionError) {
    // Gentle gradients, no clipping and opaque: the case JPEG is designed for.
    Image img = smooth_image(64, 64);
    for (int y = 0; y < img.height; ++y) {
        for (int x = 0; x < img.width; ++x) {
            const float u = x / 63.0f, v = y / 63.0f;
            float* p = img.pixel(x, y);
            p[0] = 0.1f + 0.5f * u;
            p[1] = 0.1f + 0.4f * v;
            p[2] = 0.2f + 0.3f * u * v;
            p[3] = 1.0f;
        }
    }
    write_image(img, file("out.jpg"), {});
    ReadBack r = read_back(file("out.jpg"));
    // JPEG has no alpha; at quality 95 on a smooth image the error stays within a few codes.
    expect_quantised(r, display_referred(img, false), 3, 255, 3);

    OutputSettings low;
    low.quality = 10;
    write_image(img, file("low.JPEG"), low);
    EXPECT_LT(fs::file_size(file("low.JPEG")), fs::file_size(file("out.jpg"))) << "quality is honoured";
}

TEST_F(ImageOutputTest, Tiff8And16) {
    const Image img = smooth_image();
    const Image display = display_referred(img, true);
    write_image(img, file("out.tif"), {});
    ReadBack r8 = read_back(file("out.tif"));
    EXPECT_EQ(r8.spec.format, OIIO::TypeDesc::UINT8);
    expect_quantised(r8, display, 4, 255, 0);

    OutputSettings settings;
    settings.bits = 16;
    write_image(img, file("out16.TIFF"), settings);
    ReadBack r16 = read_back(file("out16.TIFF"));
    EXPECT_EQ(r16.spec.format, OIIO::TypeDesc::UINT16);
    expect_quantised(r16, display, 4, 65535, 0);
    EXPECT_EQ(listing(), std::vector<std::string>({"out.tif", "out16.TIFF"}));
}

TEST_F(ImageOutputTest, DisplaySettingsReachTheFile) {
    Image img;
    img.width = 2;
    img.height = 1;
    img.rgba = {0.5f, 0.5f, 0.5f, 1, 0.09f, 0.09f, 0.09f, 1};
    OutputSettings settings;
    settings.display.view = "Raw";
    write_image(img, file("raw.png"), settings);
    EXPECT_EQ(std::lround(read_back(file("raw.png")).at(0, 0, 0) * 255), 128);

    OutputSettings exposed;
    exposed.display.exposure = 1;
    write_image(img, file("exposed.png"), exposed);
    EXPECT_EQ(std::lround(read_back(file("exposed.png")).at(1, 0, 1) * 255), 118);

    OutputSettings bad;
    bad.display.view = "Nope";
    try {
        write_image(img, file("bad.png"), bad);
        FAIL() << "an unknown view must throw";
    } catch (const OutputError& e) {
        const std::string msg = e.what();
        EXPECT_EQ(msg.rfind(file("bad.png") + ": ", 0), 0u) << msg;
        EXPECT_NE(msg.find("'Nope'"), std::string::npos) << msg;
    }
    EXPECT_FALSE(fs::exists(file("bad.png")));
}

TEST_F(ImageOutputTest, MetadataIsWrittenWithNumbersAsNumbersInExr) {
    const Image img = smooth_image(8, 8);
    OutputSettings settings;
    settings.metadata = {{"Software", "Veach 0.1.0"}, {"veach:spp", "256"}, {"veach:integrator", "pt"},
                         {"veach:render_seconds", "1.25"}, {"shot", "007"}, {"range", "0:16"}};
    for (const char* name : {"meta.exr", "meta.png", "meta.tif"}) {
        write_image(img, file(name), settings);
        ReadBack r = read_back(file(name));
        EXPECT_EQ(r.spec.get_string_attribute("Software"), "Veach 0.1.0") << name;
        if (std::string(name) == "meta.exr") {
            // EXR headers hold typed attributes: a whole number an int, a decimal a float, and
            // text that only starts like a number ("007", "0:16") stays text.
            const OIIO::ParamValue* spp = r.spec.find_attribute("veach:spp");
            ASSERT_NE(spp, nullptr);
            EXPECT_EQ(spp->type(), OIIO::TypeInt);
            EXPECT_EQ(spp->get_int(), 256);
            const OIIO::ParamValue* seconds = r.spec.find_attribute("veach:render_seconds");
            ASSERT_NE(seconds, nullptr);
            EXPECT_EQ(seconds->type(), OIIO::TypeFloat);
            EXPECT_EQ(seconds->get_float(), 1.25f);
            EXPECT_EQ(r.spec.get_string_attribute("shot"), "007");
            EXPECT_EQ(r.spec.get_string_attribute("range"), "0:16");
            EXPECT_EQ(r.spec.get_string_attribute("veach:integrator"), "pt");
        } else if (std::string(name) == "meta.png") {
            // PNG text chunks hold text only.
            EXPECT_EQ(r.spec.get_string_attribute("veach:spp"), "256") << name;
            EXPECT_EQ(r.spec.get_string_attribute("veach:integrator"), "pt") << name;
        }
        // Read back through the writer's own reader, every value as its text (TIFF in its description).
        std::map<std::string, std::string> meta;
        std::string error;
        ASSERT_TRUE(read_image_metadata(file(name), meta, error)) << error;
        EXPECT_EQ(meta["veach:spp"], "256") << name;
        EXPECT_EQ(meta["veach:render_seconds"], "1.25") << name;
    }
}

// Multi-layer EXR: channels named as Blender names them, each pass's values exact in float,
// Depth kept in float under --half, and a pass the film did not record refused before writing.
TEST_F(ImageOutputTest, MultiLayerExrUsesBlenderPassNames) {
    Image img = smooth_image(6, 5);
    const size_t n = 30;
    img.depth.resize(n);
    img.normal.resize(n * 3);
    img.albedo.resize(n * 3);
    img.variance.resize(n * 3);
    for (size_t i = 0; i < n; ++i) {
        img.depth[i] = 1.0f + 1e-3f * i;  // needs float: half would round it
        for (int c = 0; c < 3; ++c) {
            img.normal[i * 3 + c] = c == 2 ? 1.0f : 0.0f;
            img.albedo[i * 3 + c] = 0.25f * c;
            img.variance[i * 3 + c] = 1e-3f * (i + c);
        }
    }
    OutputSettings settings;
    settings.half = true;
    settings.exr_codec = "zips";
    settings.passes = {"variance", "combined", "depth", "normal", "albedo"};
    write_image(img, file("layers.exr"), settings);
    ReadBack r = read_back(file("layers.exr"));
    std::vector<std::string> names(r.spec.channelnames.begin(), r.spec.channelnames.end());
    std::vector<std::string> want = {"ViewLayer.Combined.R", "ViewLayer.Combined.G", "ViewLayer.Combined.B",
                                     "ViewLayer.Combined.A", "ViewLayer.Depth.Z",    "ViewLayer.Normal.X",
                                     "ViewLayer.Normal.Y",   "ViewLayer.Normal.Z",   "ViewLayer.Albedo.R",
                                     "ViewLayer.Albedo.G",   "ViewLayer.Albedo.B",   "ViewLayer.Variance.R",
                                     "ViewLayer.Variance.G", "ViewLayer.Variance.B"};
    std::vector<std::string> sorted_names = names, sorted_want = want;
    std::sort(sorted_names.begin(), sorted_names.end());
    std::sort(sorted_want.begin(), sorted_want.end());
    ASSERT_EQ(sorted_names, sorted_want);
    EXPECT_EQ(r.spec.get_string_attribute("compression"), "zips");
    auto channel = [&](const std::string& name) {
        return static_cast<int>(std::find(names.begin(), names.end(), name) - names.begin());
    };
    const int nc = r.spec.nchannels;
    EXPECT_EQ(r.spec.channelformat(channel("ViewLayer.Depth.Z")), OIIO::TypeDesc::FLOAT);
    EXPECT_EQ(r.spec.channelformat(channel("ViewLayer.Combined.R")), OIIO::TypeDesc::HALF);
    for (size_t i = 0; i < n; ++i) {
        EXPECT_EQ(r.pixels[i * nc + channel("ViewLayer.Depth.Z")], img.depth[i]);
        EXPECT_EQ(r.pixels[i * nc + channel("ViewLayer.Normal.Z")], 1.0f);
        EXPECT_EQ(r.pixels[i * nc + channel("ViewLayer.Albedo.B")], 0.5f);
        EXPECT_NEAR(r.pixels[i * nc + channel("ViewLayer.Combined.G")], img.rgba[i * 4 + 1],
                    1e-3f * std::max(1.0f, img.rgba[i * 4 + 1]));
        EXPECT_NEAR(r.pixels[i * nc + channel("ViewLayer.Variance.R")], img.variance[i * 3],
                    1e-3f * img.variance[i * 3] + 1e-7f);
    }

    Image plain = smooth_image(6, 5);
    settings.passes = {"combined", "normal"};
    EXPECT_THROW(write_image(plain, file("no_normal.exr"), settings), OutputError);
    settings.passes = {};
    settings.exr_codec = "lzma";
    EXPECT_THROW(write_image(plain, file("bad_codec.exr"), settings), OutputError);
    EXPECT_EQ(listing(), std::vector<std::string>({"layers.exr"}));
    EXPECT_TRUE(is_exr_codec("dwaa:45") && is_exr_codec("zip:9") && is_exr_codec("none"));
    EXPECT_FALSE(is_exr_codec("zip:0") || is_exr_codec("piz:3") || is_exr_codec(""));
    // Every listed codec is accepted; levels only where OpenEXR takes one (zip 1-9, dwa 1-1000).
    ASSERT_EQ(exr_codec_names().size(), 10u);
    for (const std::string& c : exr_codec_names()) {
        EXPECT_TRUE(is_exr_codec(c)) << c;
        const bool levelled = c == "zip" || c == "zips" || c == "dwaa" || c == "dwab";
        EXPECT_EQ(is_exr_codec(c + ":9"), levelled) << c;
        EXPECT_FALSE(is_exr_codec(c + (c[0] == 'z' ? ":10" : ":1001"))) << c;
    }
}

TEST_F(ImageOutputTest, MissingFolderThrowsAndCreatesNothing) {
    const std::string path = file("no/such/folder/out.png");
    try {
        write_image(smooth_image(4, 4), path, {});
        FAIL() << "expected OutputError";
    } catch (const OutputError& e) {
        const std::string msg = e.what();
        EXPECT_EQ(msg.rfind(path + ": ", 0), 0u) << msg;
        EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
    }
    EXPECT_FALSE(fs::exists(file("no")));
    EXPECT_TRUE(listing().empty());
}

TEST_F(ImageOutputTest, UnknownExtensionThrows) {
    const std::string path = file("out.xyz");
    try {
        write_image(smooth_image(4, 4), path, {});
        FAIL() << "expected OutputError";
    } catch (const OutputError& e) {
        EXPECT_EQ(std::string(e.what()), path + ": unknown image format '.xyz'");
    }
    EXPECT_THROW(write_image(smooth_image(4, 4), file("noextension"), {}), OutputError);
    EXPECT_TRUE(listing().empty());
}

TEST_F(ImageOutputTest, InvalidBitDepthThrowsBeforeWriting) {
    OutputSettings settings;
    settings.bits = 12;
    EXPECT_THROW(write_image(smooth_image(4, 4), file("out.png"), settings), OutputError);
    EXPECT_TRUE(listing().empty());
}

TEST_F(ImageOutputTest, OverwriteReplacesTheWholeFile) {
    write_image(smooth_image(200, 150), file("frame.exr"), {});
    const auto big = fs::file_size(file("frame.exr"));

    Image small = smooth_image(8, 4);
    write_image(small, file("frame.exr"), {});
    ReadBack r = read_back(file("frame.exr"));
    EXPECT_EQ(r.spec.width, 8);
    EXPECT_EQ(r.spec.height, 4);
    EXPECT_EQ(r.pixels, small.rgba);
    EXPECT_LT(fs::file_size(file("frame.exr")), big) << "no tail of the old file may remain";
    EXPECT_EQ(listing(), std::vector<std::string>({"frame.exr"}));

    // A write that fails leaves the previous file as it was, byte for byte.
    const std::string before = bytes_of(file("frame.exr"));
    OutputSettings bad;
    bad.display.look = "missing";
    EXPECT_THROW(write_image(small, file("frame.png"), bad), OutputError);
    write_image(small, file("frame.png"), {});
    const std::string png_before = bytes_of(file("frame.png"));
    EXPECT_THROW(write_image(smooth_image(16, 16), file("frame.png"), bad), OutputError);
    EXPECT_EQ(bytes_of(file("frame.png")), png_before);
    EXPECT_EQ(bytes_of(file("frame.exr")), before);
    EXPECT_EQ(listing(), std::vector<std::string>({"frame.exr", "frame.png"}));
}

TEST_F(ImageOutputTest, ConcurrentWritersLeaveOneWholeImage) {
    // Eight threads race to write the same file, each a different constant image; whichever
    // rename lands last, the file must be entirely one writer's image.
    constexpr int writers = 8;
    std::vector<std::thread> threads;
    std::atomic<int> failures{0};
    for (int k = 0; k < writers; ++k) {
        threads.emplace_back([&, k] {
            Image img;
            img.width = 64;
            img.height = 64;
            img.rgba.assign(static_cast<size_t>(64) * 64 * 4, static_cast<float>(k + 1));
            try {
                write_image(img, file("race.exr"), {});
            } catch (const OutputError&) {
                ++failures;
            }
        });
    }
    for (std::thread& t : threads) t.join();
    EXPECT_EQ(failures.load(), 0);
    ReadBack r = read_back(file("race.exr"));
    ASSERT_FALSE(r.pixels.empty());
    const float winner = r.pixels[0];
    EXPECT_GE(winner, 1.0f);
    EXPECT_LE(winner, static_cast<float>(writers));
    for (float v : r.pixels) ASSERT_EQ(v, winner);
    EXPECT_EQ(listing(), std::vector<std::string>({"race.exr"}));
}

TEST_F(ImageOutputTest, UnwritableTargetThrowsAndLeavesNoTemp) {
    // A folder in the target's place is refused before anything is written.
    fs::create_directories(m_dir / "taken.png");
    EXPECT_THROW(write_image(smooth_image(4, 4), file("taken.png"), {}), OutputError);
    EXPECT_EQ(listing(), std::vector<std::string>({"taken.png"}));
    EXPECT_TRUE(fs::is_directory(m_dir / "taken.png"));
}

}  // namespace
}  // namespace veach
