#include "film/film_checkpoint.h"

#include <zlib.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <vector>

#include "output/atomic_file.h"

namespace veach {

namespace {

// Layout (native byte order, doubles as IEEE 754): magic, then the header fields, then
// Film::state_size() doubles, then a CRC-32 of everything before it (a flipped or overwritten
// byte is refused, not rendered into an image tagged complete), then the end marker that proves
// the write completed.
constexpr char k_magic[8] = {'V', 'E', 'A', 'C', 'H', 'C', 'K', '3'};
// The magic of checkpoints written before the version was recorded: refused, saying so.
constexpr char k_magic_unversioned[8] = {'V', 'E', 'A', 'C', 'H', 'C', 'K', '2'};
constexpr char k_end[8] = {'V', 'E', 'A', 'C', 'H', 'E', 'N', 'D'};

struct Header {
    char magic[8];
    char version[16];  // VEACH_VERSION_STRING of the writer, NUL-padded
    uint32_t width, height;
    uint32_t aovs;
    int32_t spp_done;
    uint64_t settings_hash;
    uint64_t state_doubles;
};

struct FileCloser {
    void operator()(std::FILE* f) const { std::fclose(f); }
};
using File = std::unique_ptr<std::FILE, FileCloser>;

[[noreturn]] void fail(const std::string& path, const std::string& reason) {
    throw CheckpointError(path + ": " + reason);
}

// A version read from a file, printable on one line whatever its bytes.
std::string printable(std::string s) {
    for (char& c : s)
        if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) > 0x7e) c = '?';
    return s;
}

bool whole_in(double v, double lo, double hi) { return v >= lo && v <= hi && v == std::floor(v); }

// What a checkpoint written at a pass boundary must hold, beyond a matching CRC (which a file
// made to look like one could still carry): finite sums, and per-pixel sample counts that are
// whole numbers no larger than the samples per pixel it claims.
void check_state(const std::string& path, const Film& film, const std::vector<double>& state, int spp_done) {
    const size_t n = static_cast<size_t>(film.width()) * film.height();
    for (double v : state)
        if (!std::isfinite(v)) fail(path, "corrupt checkpoint (non-finite values)");
    const double* p = state.data();
    for (size_t i = 0; i < n; ++i, p += 7)
        if (!whole_in(p[6], 0, spp_done)) fail(path, "corrupt checkpoint (sample counts beyond its spp)");
    if (film.wants_aovs())
        for (size_t i = 0; i < n; ++i, p += 8)
            if (!whole_in(p[7], 0, spp_done)) fail(path, "corrupt checkpoint (pass sample counts beyond its spp)");
    p += n * 3;  // splats: finite is all that can be said
    if (state.size() == film.state_size(true)) {
        // The sample plan: a target, a pilot that fits within spp_done, whole budgets.
        if (!(p[0] > 0) || !whole_in(p[1], 2, spp_done)) fail(path, "corrupt checkpoint (adaptive sample plan)");
        for (size_t i = 0; i < n; ++i)
            if (!whole_in(p[2 + i], 0, 4294967295.0)) fail(path, "corrupt checkpoint (adaptive sample plan)");
    }
}

}  // namespace

void write_film_checkpoint(const std::string& path, const Film& film, uint64_t settings_hash, int spp_done) {
    Header h{};
    std::memcpy(h.magic, k_magic, sizeof(k_magic));
    static_assert(sizeof(VEACH_VERSION_STRING) <= sizeof(h.version), "version string too long");
    std::memcpy(h.version, VEACH_VERSION_STRING, sizeof(VEACH_VERSION_STRING));
    h.width = static_cast<uint32_t>(film.width());
    h.height = static_cast<uint32_t>(film.height());
    h.aovs = film.wants_aovs() ? 1u : 0u;
    h.spp_done = spp_done;
    h.settings_hash = settings_hash;
    h.state_doubles = film.state_size();
    std::vector<double> state(film.state_size());
    film.save_state(state.data());

    try {
        AtomicFile file(path);
        file.write(&h, sizeof(h));
        file.write(state.data(), state.size() * sizeof(double));
        uLong crc = crc32_z(crc32_z(0L, Z_NULL, 0), reinterpret_cast<const Bytef*>(&h), sizeof(h));
        crc = crc32_z(crc, reinterpret_cast<const Bytef*>(state.data()), state.size() * sizeof(double));
        const uint32_t crc32 = static_cast<uint32_t>(crc);
        file.write(&crc32, sizeof(crc32));
        file.write(k_end, sizeof(k_end));
        file.commit();
    } catch (const OutputError& e) {
        throw CheckpointWriteError(e.what());  // "PATH: what failed (why)"
    }
}

int read_film_checkpoint(const std::string& path, Film& film, uint64_t settings_hash) {
    File f(std::fopen(path.c_str(), "rb"));
    if (!f) fail(path, std::string("cannot read checkpoint: ") + std::strerror(errno));
    Header h{};
    const std::string here = std::string("this is veach ") + VEACH_VERSION_STRING + " (delete it to start afresh)";
    const size_t got = std::fread(&h, 1, sizeof(h), f.get());
    if (got >= sizeof(h.magic) && std::memcmp(h.magic, k_magic_unversioned, sizeof(h.magic)) == 0)
        fail(path, "checkpoint was made by a veach that did not record its version, " + here);
    if (got != sizeof(h) || std::memcmp(h.magic, k_magic, sizeof(k_magic)) != 0)
        fail(path, "not a veach checkpoint (or truncated)");
    // Another version may sample differently: its samples would not continue this render's.
    const std::string version(h.version, strnlen(h.version, sizeof(h.version)));
    if (version != VEACH_VERSION_STRING) fail(path, "checkpoint was made by veach " + printable(version) + ", " + here);
    if (h.width != static_cast<uint32_t>(film.width()) || h.height != static_cast<uint32_t>(film.height()))
        fail(path, "checkpoint is " + std::to_string(h.width) + "x" + std::to_string(h.height) + ", the render " +
                       std::to_string(film.width()) + "x" + std::to_string(film.height()));
    // With adaptive sampling the film's state carries the sample plan once it has been made.
    if (h.settings_hash != settings_hash || h.aovs != (film.wants_aovs() ? 1u : 0u) ||
        (h.state_doubles != film.state_size(false) && h.state_doubles != film.state_size(true)))
        fail(path, "checkpoint was made with other settings or another scene (delete it to start afresh)");
    if (h.spp_done < 0) fail(path, "corrupt checkpoint (negative spp)");
    std::vector<double> state(h.state_doubles);
    char end[8] = {};
    uint32_t stored_crc = 0;
    if (std::fread(state.data(), sizeof(double), state.size(), f.get()) != state.size() ||
        std::fread(&stored_crc, sizeof(stored_crc), 1, f.get()) != 1 || std::fread(end, sizeof(end), 1, f.get()) != 1 ||
        std::memcmp(end, k_end, sizeof(k_end)) != 0 || std::fgetc(f.get()) != EOF)
        fail(path, "truncated or corrupt checkpoint");
    uLong crc = crc32_z(crc32_z(0L, Z_NULL, 0), reinterpret_cast<const Bytef*>(&h), sizeof(h));
    crc = crc32_z(crc, reinterpret_cast<const Bytef*>(state.data()), state.size() * sizeof(double));
    if (static_cast<uint32_t>(crc) != stored_crc) fail(path, "corrupt checkpoint (CRC mismatch)");
    check_state(path, film, state, h.spp_done);
    film.load_state(state.data(), state.size());
    return h.spp_done;
}

}  // namespace veach
