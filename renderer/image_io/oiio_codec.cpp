// libveach_image_io.so: the Codec of image_codec.h over OpenImageIO. The only file that includes
// OpenImageIO; libveach opens it on first use (image_module.cpp).
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <charconv>
#include <cstring>
#include <exception>

#include "image_io/image_codec.h"

namespace veach::image_io {

namespace {

OIIO::TypeDesc type_of(SampleType t) {
    switch (t) {
        case SampleType::uint8: return OIIO::TypeDesc::UINT8;
        case SampleType::uint16: return OIIO::TypeDesc::UINT16;
        case SampleType::half: return OIIO::TypeDesc::HALF;
        case SampleType::float32: break;
    }
    return OIIO::TypeDesc::FLOAT;
}

class OiioDecoder final : public Decoder {
public:
    // `proxy` (may be null) is the in-memory reader `input` reads through; kept alive with it.
    OiioDecoder(std::unique_ptr<OIIO::Filesystem::IOMemReader> proxy, std::unique_ptr<OIIO::ImageInput> input)
        : m_proxy(std::move(proxy)), m_input(std::move(input)) {
        const OIIO::ImageSpec& spec = m_input->spec();
        m_header.width = spec.width;
        m_header.height = spec.height;
        m_header.channels = spec.nchannels;
        m_header.alpha_channel = spec.alpha_channel;
        m_header.eight_bit = spec.format.basetype == OIIO::TypeDesc::UINT8;
        m_header.color_space = spec.get_string_attribute("oiio:ColorSpace");
        m_header.description = spec.get_string_attribute("ImageDescription");
        for (const OIIO::ParamValue& p : spec.extra_attribs) {
            if (p.nvalues() != 1) continue;
            if (p.type() == OIIO::TypeString)
                m_header.attributes.emplace_back(p.name().string(), p.get_string());
            else if (p.type() == OIIO::TypeInt)
                m_header.attributes.emplace_back(p.name().string(), std::to_string(p.get_int()));
            else if (p.type() == OIIO::TypeFloat) {
                char text[32];
                const float v = p.get_float();
                auto [end, ec] = std::to_chars(text, text + sizeof(text), v);
                m_header.attributes.emplace_back(p.name().string(), std::string(text, ec == std::errc() ? end : text));
            }
        }
    }
    ~OiioDecoder() override { m_input->close(); }

    const Header& header() const override { return m_header; }

    bool read_channels(int begin, int end, float* first, std::ptrdiff_t pixel_stride, std::string& error) override {
        try {
            if (m_input->read_image(0, 0, begin, end, OIIO::TypeDesc::FLOAT, first, pixel_stride)) return true;
            error = m_input->geterror();
        } catch (const std::exception& e) {
            error = e.what();
        }
        return false;
    }

private:
    std::unique_ptr<OIIO::Filesystem::IOMemReader> m_proxy;
    std::unique_ptr<OIIO::ImageInput> m_input;
    Header m_header;
};

std::unique_ptr<Decoder> opened(std::unique_ptr<OIIO::Filesystem::IOMemReader> proxy,
                                std::unique_ptr<OIIO::ImageInput> input, std::string& error) {
    if (!input) {
        error = OIIO::geterror();
        return nullptr;
    }
    return std::make_unique<OiioDecoder>(std::move(proxy), std::move(input));
}

class OiioCodec final : public Codec {
public:
    std::unique_ptr<Decoder> open_file(const std::string& path, std::string& error) const override {
        try {
            return opened(nullptr, OIIO::ImageInput::open(path), error);
        } catch (const std::exception& e) {
            error = e.what();
            return nullptr;
        }
    }

    std::unique_ptr<Decoder> open_memory(const unsigned char* data, size_t size, const std::string& name,
                                         std::string& error) const override {
        try {
            // OpenImageIO reads through a proxy over the caller's bytes; it neither copies nor frees them.
            auto proxy = std::make_unique<OIIO::Filesystem::IOMemReader>(const_cast<unsigned char*>(data), size);
            auto input = OIIO::ImageInput::open(name, nullptr, proxy.get());
            return opened(std::move(proxy), std::move(input), error);
        } catch (const std::exception& e) {
            error = e.what();
            return nullptr;
        }
    }

    bool encode(const EncodeRequest& request, std::vector<unsigned char>& bytes, std::string& error) const override {
        try {
            return encode_unguarded(request, bytes, error);
        } catch (const std::exception& e) {
            error = e.what();
            return false;
        }
    }

private:
    static bool encode_unguarded(const EncodeRequest& r, std::vector<unsigned char>& bytes, std::string& error) {
        OIIO::ImageSpec spec(r.width, r.height, r.channels, type_of(r.file_type));
        if (!r.channel_names.empty()) {
            spec.channelnames = r.channel_names;
            spec.channelformats.clear();
            for (SampleType t : r.channel_types) spec.channelformats.push_back(type_of(t));
            spec.alpha_channel = r.alpha_channel;
            spec.z_channel = r.z_channel;
        }
        for (const Attribute& a : r.attributes) {
            if (a.kind == Attribute::Kind::Integer)
                spec.attribute(a.name, a.integer);
            else if (a.kind == Attribute::Kind::Float)
                spec.attribute(a.name, a.number);
            else
                spec.attribute(a.name, a.text);
        }
        OIIO::Filesystem::IOVecOutput proxy(bytes);
        auto out = OIIO::ImageOutput::create(r.writer);
        if (!out) {
            error = "no OpenImageIO writer '" + r.writer + "': " + OIIO::geterror();
            return false;
        }
        if (!out->supports("ioproxy")) {
            error = "the OpenImageIO writer '" + r.writer + "' cannot encode to memory";
            return false;
        }
        out->set_ioproxy(&proxy);
        if (!out->open(r.name, spec)) {
            error = "cannot encode: " + out->geterror();
            return false;
        }
        bool ok = out->write_image(type_of(r.data_type), r.data);
        std::string err = ok ? std::string() : out->geterror();
        if (!out->close() && ok) {
            ok = false;
            err = out->geterror();
        }
        if (!ok) error = "cannot encode: " + (err.empty() ? std::string("unknown error") : err);
        return ok;
    }
};

}  // namespace

}  // namespace veach::image_io

extern "C" __attribute__((visibility("default"))) const veach::image_io::Codec* veach_image_io_codec(
    int interface_version, const char* veach_version) {
    static const veach::image_io::OiioCodec codec;
    if (interface_version != veach::image_io::k_interface_version || !veach_version ||
        std::strcmp(veach_version, VEACH_VERSION_STRING) != 0)
        return nullptr;
    return &codec;
}
