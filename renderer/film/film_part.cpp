#include "film/film_part.h"

#include <zlib.h>

#include <algorithm>
#include <cerrno>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>

#include "core/one_line.h"
#include "output/atomic_file.h"

namespace veach {

namespace {

constexpr char k_magic[8] = {'V', 'E', 'A', 'C', 'H', 'P', 'R', 'T'};
constexpr char k_end[8] = {'V', 'E', 'A', 'C', 'H', 'E', 'N', 'D'};
constexpr uint32_t k_max_header = 1 << 16;
// Doubles are byte-shuffled in blocks of this many (byte 0 of each, then byte 1, ...): the high
// bytes of neighbouring sums repeat, which zlib then finds.
constexpr size_t k_block_doubles = 1 << 16;

std::string number(double v) {
    char buf[40];
    std::snprintf(buf, sizeof(buf), "%.17g", v);
    return buf;
}

std::string header_text(const PartInfo& p, bool splats) {
    char identity[24];
    std::snprintf(identity, sizeof(identity), "%016" PRIx64, p.identity);
    std::ostringstream h;
    h << "veach-part 1\n"
      << "identity " << identity << "\n"
      << "version " << one_line(p.version) << "\n"
      << "width " << p.width << "\nheight " << p.height << "\n"
      << "aovs " << (p.aovs ? 1 : 0) << "\nsplats " << (splats ? 1 : 0) << "\n"
      << "samples " << p.sample_begin << " " << p.sample_end << "\nspp " << p.spp << "\n"
      << "bounds " << p.x0 << " " << p.x1 << " " << p.y0 << " " << p.y1 << "\n"
      << "frame " << number(p.frame) << "\nseed " << p.seed << "\n"
      << "filter " << filter_name(p.filter.type) << " " << number(p.filter.width) << "\n"
      << "render_seconds " << number(p.render_seconds) << "\n"
      << "camera " << one_line(p.camera) << "\nintegrator " << one_line(p.integrator) << "\n"
      << "scene " << one_line(p.scene) << "\n";
    return h.str();
}

[[noreturn]] void corrupt(const std::string& path, const std::string& why) { throw PartError(path + ": " + why); }

// Parses the header; checks that every field is there and in range.
PartInfo parse_header(const std::string& path, const std::string& text, bool* splats) {
    std::map<std::string, std::string> fields;
    std::istringstream in(text);
    std::string line;
    bool first = true;
    while (std::getline(in, line)) {
        if (first) {
            if (line != "veach-part 1") corrupt(path, "unsupported part file version");
            first = false;
            continue;
        }
        size_t space = line.find(' ');
        if (space == std::string::npos) corrupt(path, "corrupt part file header");
        fields[line.substr(0, space)] = line.substr(space + 1);
    }
    auto get = [&](const char* key) -> const std::string& {
        auto it = fields.find(key);
        if (it == fields.end()) corrupt(path, std::string("part file header lacks '") + key + "'");
        return it->second;
    };
    auto ints = [&](const char* key, int count) {
        std::istringstream s(get(key));
        std::vector<long long> v(count);
        for (long long& x : v)
            if (!(s >> x)) corrupt(path, std::string("corrupt part file field '") + key + "'");
        std::string rest;
        if (s >> rest) corrupt(path, std::string("corrupt part file field '") + key + "'");
        return v;
    };
    auto real = [&](const char* key) {
        char* end = nullptr;
        const std::string& v = get(key);
        double x = std::strtod(v.c_str(), &end);
        if (v.empty() || *end != '\0' || !std::isfinite(x))
            corrupt(path, std::string("corrupt part file field '") + key + "'");
        return x;
    };
    PartInfo p;
    {
        const std::string& id = get("identity");
        char* end = nullptr;
        p.identity = std::strtoull(id.c_str(), &end, 16);
        if (id.size() != 16 || *end != '\0') corrupt(path, "corrupt part file identity");
    }
    const auto size = ints("width", 1)[0], height = ints("height", 1)[0];
    const auto aovs = ints("aovs", 1)[0], has_splats = ints("splats", 1)[0];
    const std::vector<long long> samples = ints("samples", 2), bounds = ints("bounds", 4);
    const long long spp = ints("spp", 1)[0];
    if (size < 1 || size > 65536 || height < 1 || height > 65536) corrupt(path, "part file of an impossible size");
    if ((aovs != 0 && aovs != 1) || (has_splats != 0 && has_splats != 1)) corrupt(path, "corrupt part file flags");
    if (samples[0] < 0 || samples[0] >= samples[1] || samples[1] > spp || spp > INT32_MAX)
        corrupt(path, "corrupt part file sample range");
    if (bounds[0] < 0 || bounds[0] >= bounds[1] || bounds[1] > size || bounds[2] < 0 || bounds[2] >= bounds[3] ||
        bounds[3] > height)
        corrupt(path, "corrupt part file pixel bounds");
    p.width = static_cast<int>(size);
    p.height = static_cast<int>(height);
    p.aovs = aovs == 1;
    *splats = has_splats == 1;
    p.sample_begin = static_cast<int>(samples[0]);
    p.sample_end = static_cast<int>(samples[1]);
    p.spp = static_cast<int>(spp);
    p.x0 = static_cast<int>(bounds[0]);
    p.x1 = static_cast<int>(bounds[1]);
    p.y0 = static_cast<int>(bounds[2]);
    p.y1 = static_cast<int>(bounds[3]);
    p.frame = real("frame");
    {
        const std::string& seed = get("seed");
        char* end = nullptr;
        p.seed = std::strtoull(seed.c_str(), &end, 10);
        if (seed.empty() || *end != '\0') corrupt(path, "corrupt part file seed");
    }
    {
        std::istringstream f(get("filter"));
        std::string name, width;
        if (!(f >> name >> width) || !parse_filter_name(name, &p.filter.type))
            corrupt(path, "corrupt part file filter");
        char* end = nullptr;
        p.filter.width = std::strtof(width.c_str(), &end);
        if (*end != '\0' || !(p.filter.width > 0.0f && p.filter.width <= 64.0f))
            corrupt(path, "corrupt part file filter");
    }
    p.render_seconds = real("render_seconds");
    p.camera = get("camera");
    p.integrator = get("integrator");
    p.scene = get("scene");
    // Optional: parts written before the version was recorded have none.
    if (auto it = fields.find("version"); it != fields.end()) p.version = it->second;
    return p;
}

struct Sections {
    std::vector<double> pixels, aovs, splats;
    size_t total() const { return pixels.size() + aovs.size() + splats.size(); }
};

size_t expected_doubles(const PartInfo& p, bool splats) {
    const size_t area = p.area();
    return area * Film::k_part_pixel_doubles + (p.aovs ? area * Film::k_part_aov_doubles : 0) +
           (splats ? static_cast<size_t>(p.width) * p.height * 3 : 0);
}

// Visits the payload's doubles block by block, in file order, through the three sections.
template <class Fn>
void for_each_block(Sections& s, Fn&& fn) {
    std::vector<double>* parts[] = {&s.pixels, &s.aovs, &s.splats};
    std::vector<double> block;
    block.reserve(k_block_doubles);
    // A block may span sections: gather pointers to its doubles.
    std::vector<double*> where;
    where.reserve(k_block_doubles);
    for (std::vector<double>* v : parts) {
        for (double& d : *v) {
            where.push_back(&d);
            if (where.size() == k_block_doubles) {
                fn(where);
                where.clear();
            }
        }
    }
    if (!where.empty()) fn(where);
}

void shuffle(const std::vector<double*>& values, std::vector<unsigned char>* out) {
    const size_t n = values.size();
    out->resize(n * 8);
    for (size_t i = 0; i < n; ++i) {
        unsigned char b[8];
        std::memcpy(b, values[i], 8);
        for (int k = 0; k < 8; ++k) (*out)[k * n + i] = b[k];
    }
}

void unshuffle(const std::vector<unsigned char>& in, const std::vector<double*>& values) {
    const size_t n = values.size();
    for (size_t i = 0; i < n; ++i) {
        unsigned char b[8];
        for (int k = 0; k < 8; ++k) b[k] = in[k * n + i];
        std::memcpy(values[i], b, 8);
    }
}

// AtomicFile with a running CRC-32 of what went through it.
class CrcWriter {
public:
    explicit CrcWriter(AtomicFile& file) : m_file(file) {}
    void write(const void* data, size_t size) {
        m_crc = crc32_z(m_crc, static_cast<const Bytef*>(data), size);
        m_file.write(data, size);
    }
    uint32_t crc() const { return static_cast<uint32_t>(m_crc); }

private:
    AtomicFile& m_file;
    uLong m_crc = crc32_z(0L, Z_NULL, 0);
};

std::string read_whole_file(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    if (!f) corrupt(path, std::string("cannot read part file: ") + std::strerror(errno));
    std::string bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
    if (f.bad()) corrupt(path, "cannot read part file");
    return bytes;
}

// The header of a file's first bytes (magic, length, text).
std::string header_of(const std::string& path, const std::string& bytes, size_t* payload_offset) {
    if (bytes.size() < sizeof(k_magic) + 4 || std::memcmp(bytes.data(), k_magic, sizeof(k_magic)) != 0)
        corrupt(path, "not a veach part file");
    uint32_t length;
    std::memcpy(&length, bytes.data() + sizeof(k_magic), 4);
    if (length > k_max_header || bytes.size() < sizeof(k_magic) + 4 + length) corrupt(path, "truncated part file");
    *payload_offset = sizeof(k_magic) + 4 + length;
    return bytes.substr(sizeof(k_magic) + 4, length);
}

struct LoadedPart {
    PartInfo info;
    bool splats = false;
    Sections data;
};

LoadedPart load_part(const std::string& path) {
    const std::string bytes = read_whole_file(path);
    size_t offset = 0;
    LoadedPart part;
    const std::string header = header_of(path, bytes, &offset);
    const size_t trailer = 4 + sizeof(k_end);
    if (bytes.size() < offset + 8 + trailer || std::memcmp(bytes.data() + bytes.size() - sizeof(k_end), k_end, 8) != 0)
        corrupt(path, "truncated part file");
    uint32_t stored_crc;
    std::memcpy(&stored_crc, bytes.data() + bytes.size() - trailer, 4);
    const uLong crc =
        crc32_z(crc32_z(0L, Z_NULL, 0), reinterpret_cast<const Bytef*>(bytes.data()), bytes.size() - trailer);
    if (static_cast<uint32_t>(crc) != stored_crc) corrupt(path, "corrupt part file (CRC mismatch)");
    part.info = parse_header(path, header, &part.splats);
    uint64_t doubles;
    std::memcpy(&doubles, bytes.data() + offset, 8);
    offset += 8;
    if (doubles != expected_doubles(part.info, part.splats)) corrupt(path, "corrupt part file (payload size)");
    const size_t area = part.info.area();
    part.data.pixels.resize(area * Film::k_part_pixel_doubles);
    if (part.info.aovs) part.data.aovs.resize(area * Film::k_part_aov_doubles);
    if (part.splats) part.data.splats.resize(static_cast<size_t>(part.info.width) * part.info.height * 3);

    z_stream z{};
    if (inflateInit(&z) != Z_OK) corrupt(path, "cannot start zlib");
    z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(bytes.data() + offset));
    z.avail_in = static_cast<uInt>(bytes.size() - trailer - offset);
    std::vector<unsigned char> block;
    bool ok = true;
    for_each_block(part.data, [&](const std::vector<double*>& values) {
        if (!ok) return;
        block.resize(values.size() * 8);
        z.next_out = block.data();
        z.avail_out = static_cast<uInt>(block.size());
        while (z.avail_out > 0) {
            int rc = inflate(&z, Z_NO_FLUSH);
            if (rc == Z_STREAM_END && z.avail_out == 0) break;
            if (rc != Z_OK) {
                ok = false;
                return;
            }
        }
        unshuffle(block, values);
    });
    // The stream must end exactly with the payload.
    unsigned char extra;
    z.next_out = &extra;
    z.avail_out = 1;
    const int end = ok ? inflate(&z, Z_FINISH) : Z_DATA_ERROR;
    inflateEnd(&z);
    if (!ok || end != Z_STREAM_END || z.avail_out != 1 || z.avail_in != 0) corrupt(path, "corrupt part file (payload)");

    // Sums of finite samples are finite; counts are whole numbers within the range.
    const double max_count = part.info.sample_end - part.info.sample_begin;
    for (size_t i = 0; i < area; ++i) {
        const double* px = &part.data.pixels[i * Film::k_part_pixel_doubles];
        for (size_t k = 0; k < Film::k_part_pixel_doubles; ++k)
            if (!std::isfinite(px[k])) corrupt(path, "corrupt part file (non-finite sums)");
        const double w = px[6];
        if (w < 0 || w > max_count || w != std::floor(w)) corrupt(path, "corrupt part file (sample counts)");
        if (part.info.aovs) {
            const double* a = &part.data.aovs[i * Film::k_part_aov_doubles];
            for (size_t k = 0; k < Film::k_part_aov_doubles; ++k)
                if (!std::isfinite(a[k])) corrupt(path, "corrupt part file (non-finite passes)");
            if (a[7] < 0 || a[7] > max_count || a[7] != std::floor(a[7]))
                corrupt(path, "corrupt part file (pass sample counts)");
        }
    }
    for (double v : part.data.splats)
        if (!std::isfinite(v)) corrupt(path, "corrupt part file (non-finite splats)");
    return part;
}

std::string join_paths(const std::vector<std::string>& paths) {
    std::string out;
    for (const std::string& p : paths) out += (out.empty() ? "" : ", ") + p;
    return out;
}

bool overlap(int a0, int a1, int b0, int b1) { return a0 < b1 && b0 < a1; }

std::string made_by(const PartInfo& p) {
    return p.version.empty() ? "a veach that did not record its version" : "veach " + p.version;
}

}  // namespace

void write_film_part(const std::string& path, const Film& film, const PartInfo& info) {
    Sections s;
    film.save_pixels(info.x0, info.y0, info.x1, info.y1, &s.pixels, &s.aovs);
    const bool splats = film.has_splats();
    if (splats) film.save_splats(&s.splats);
    const std::string header = header_text(info, splats);

    AtomicFile file(path);
    CrcWriter out(file);
    out.write(k_magic, sizeof(k_magic));
    const uint32_t length = static_cast<uint32_t>(header.size());
    out.write(&length, 4);
    out.write(header.data(), header.size());
    const uint64_t doubles = s.total();
    out.write(&doubles, 8);

    z_stream z{};
    // Level 1: the shuffled sums compress nearly as well as at level 9, several times faster.
    if (deflateInit(&z, 1) != Z_OK) throw OutputError(path + ": cannot start zlib");
    std::vector<unsigned char> in, compressed(1 << 18);
    auto pump = [&](int flush) {
        do {
            z.next_out = compressed.data();
            z.avail_out = static_cast<uInt>(compressed.size());
            int rc = deflate(&z, flush);
            if (rc == Z_STREAM_ERROR) {
                deflateEnd(&z);
                throw OutputError(path + ": zlib failed");
            }
            out.write(compressed.data(), compressed.size() - z.avail_out);
        } while (z.avail_out == 0);
    };
    try {
        for_each_block(s, [&](const std::vector<double*>& values) {
            shuffle(values, &in);
            z.next_in = in.data();
            z.avail_in = static_cast<uInt>(in.size());
            pump(Z_NO_FLUSH);
        });
        z.next_in = nullptr;
        z.avail_in = 0;
        pump(Z_FINISH);
    } catch (...) {
        deflateEnd(&z);
        throw;
    }
    deflateEnd(&z);
    const uint32_t crc = out.crc();
    file.write(&crc, 4);
    file.write(k_end, sizeof(k_end));
    file.commit();
}

PartInfo read_film_part_info(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    if (!f) corrupt(path, std::string("cannot read part file: ") + std::strerror(errno));
    std::string head(sizeof(k_magic) + 4, '\0');
    if (!f.read(head.data(), static_cast<std::streamsize>(head.size()))) corrupt(path, "not a veach part file");
    if (std::memcmp(head.data(), k_magic, sizeof(k_magic)) != 0) corrupt(path, "not a veach part file");
    uint32_t length;
    std::memcpy(&length, head.data() + sizeof(k_magic), 4);
    if (length > k_max_header) corrupt(path, "corrupt part file header");
    std::string text(length, '\0');
    if (!f.read(text.data(), length)) corrupt(path, "truncated part file");
    bool splats;
    return parse_header(path, text, &splats);
}

MergedParts merge_film_parts(const std::vector<std::string>& paths, int expect_spp) {
    if (paths.empty()) throw PartError("no part files to merge");
    std::vector<PartInfo> infos;
    for (const std::string& p : paths) infos.push_back(read_film_part_info(p));
    const PartInfo& first = infos[0];
    for (size_t i = 1; i < infos.size(); ++i)
        if (infos[i].version != first.version)
            throw PartError(paths[0] + ", " + paths[i] + ": parts made by two versions of veach (" + made_by(first) +
                            ", " + made_by(infos[i]) + "): render every part of a frame with one version");
    for (size_t i = 1; i < infos.size(); ++i) {
        const PartInfo& p = infos[i];
        if (p.identity != first.identity || p.width != first.width || p.height != first.height ||
            p.aovs != first.aovs || p.frame != first.frame)
            throw PartError(paths[0] + ", " + paths[i] +
                            ": parts of different renders (settings, scene content, size, passes or frame differ)");
    }
    for (size_t i = 0; i < infos.size(); ++i) {
        for (size_t j = i + 1; j < infos.size(); ++j) {
            const PartInfo &a = infos[i], &b = infos[j];
            if (overlap(a.sample_begin, a.sample_end, b.sample_begin, b.sample_end) &&
                overlap(a.x0, a.x1, b.x0, b.x1) && overlap(a.y0, a.y1, b.y0, b.y1))
                throw PartError(paths[i] + ", " + paths[j] + ": overlapping parts (samples " +
                                std::to_string(std::max(a.sample_begin, b.sample_begin)) + ":" +
                                std::to_string(std::min(a.sample_end, b.sample_end)) + " of some pixels are in both)");
        }
    }
    const size_t w = static_cast<size_t>(first.width), h = static_cast<size_t>(first.height);
    // Samples per pixel over the frame: with no overlap, every pixel holding exactly expect_spp
    // samples from parts within [0, expect_spp) is an exact cover.
    std::vector<uint32_t> coverage(w * h, 0);
    uint64_t sample_pixels = 0;
    for (size_t i = 0; i < infos.size(); ++i) {
        const PartInfo& p = infos[i];
        if (expect_spp > 0 && p.sample_end > expect_spp)
            throw PartError(paths[i] + ": holds samples " + std::to_string(p.sample_begin) + ":" +
                            std::to_string(p.sample_end) + ", beyond --expect-spp " + std::to_string(expect_spp));
        for (int y = p.y0; y < p.y1; ++y)
            for (int x = p.x0; x < p.x1; ++x)
                coverage[y * w + x] += static_cast<uint32_t>(p.sample_end - p.sample_begin);
        sample_pixels += p.sample_pixels();
    }
    if (expect_spp > 0) {
        for (size_t i = 0; i < coverage.size(); ++i) {
            if (coverage[i] == static_cast<uint32_t>(expect_spp)) continue;
            const int x = static_cast<int>(i % w), y = static_cast<int>(i / w);
            // The first missing sample range of this pixel.
            std::vector<std::pair<int, int>> ranges;
            for (const PartInfo& p : infos)
                if (x >= p.x0 && x < p.x1 && y >= p.y0 && y < p.y1) ranges.emplace_back(p.sample_begin, p.sample_end);
            std::sort(ranges.begin(), ranges.end());
            int next = 0;
            for (const auto& r : ranges) {
                if (r.first > next) break;
                next = std::max(next, r.second);
            }
            int gap_end = expect_spp;
            for (const auto& r : ranges)
                if (r.first > next) {
                    gap_end = r.first;
                    break;
                }
            throw PartError(join_paths(paths) + ": gap with --expect-spp " + std::to_string(expect_spp) + ": samples " +
                            std::to_string(next) + ":" + std::to_string(gap_end) + " of pixel (" + std::to_string(x) +
                            ", " + std::to_string(y) + ") are in no part");
        }
    }

    // Added in sample order, so that each pixel's sums grow as one render's did.
    std::vector<size_t> order(infos.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(),
                     [&](size_t a, size_t b) { return infos[a].sample_begin < infos[b].sample_begin; });
    MergedParts merged;
    FilmSettings settings;
    settings.filter = first.filter;
    settings.aovs = first.aovs;
    merged.film = std::make_shared<Film>(first.width, first.height, settings);
    merged.info = first;
    merged.info.render_seconds = 0;
    int begin = INT32_MAX, end = 0, x0 = first.width, x1 = 0, y0 = first.height, y1 = 0;
    for (size_t k : order) {
        LoadedPart part = load_part(paths[k]);
        const PartInfo& p = part.info;
        if (p.identity != first.identity || p.version != first.version || p.width != first.width ||
            p.height != first.height || p.aovs != first.aovs)
            corrupt(paths[k], "changed while merging");
        merged.film->add_pixels(p.x0, p.y0, p.x1, p.y1, part.data.pixels.data(),
                                part.data.aovs.empty() ? nullptr : part.data.aovs.data());
        if (part.splats) merged.film->add_splats(part.data.splats.data());
        merged.info.render_seconds += p.render_seconds;
        merged.info.spp = std::max(merged.info.spp, p.spp);
        begin = std::min(begin, p.sample_begin);
        end = std::max(end, p.sample_end);
        x0 = std::min(x0, p.x0), x1 = std::max(x1, p.x1), y0 = std::min(y0, p.y0), y1 = std::max(y1, p.y1);
    }
    merged.info.sample_begin = begin;
    merged.info.sample_end = end;
    merged.info.x0 = x0, merged.info.x1 = x1, merged.info.y0 = y0, merged.info.y1 = y1;
    merged.single_piece = merged.info.sample_pixels() == sample_pixels;  // no overlap: an exact cover
    merged.splat_spp = static_cast<double>(sample_pixels) / static_cast<double>(w * h);
    merged.min_spp = static_cast<int>(*std::min_element(coverage.begin(), coverage.end()));
    merged.paths = paths;
    return merged;
}

}  // namespace veach
