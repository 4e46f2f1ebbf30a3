#include "film/film_checkpoint.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>
#include <vector>

#include "output/atomic_file.h"

namespace veach {

namespace {

// Layout (native byte order, doubles as IEEE 754): magic, then the header fields, then
// Film::state_size() doubles, then the end marker that proves the write completed.
constexpr char k_magic[8] = {'V', 'E', 'A', 'C', 'H', 'C', 'K', '1'};
constexpr char k_end[8] = {'V', 'E', 'A', 'C', 'H', 'E', 'N', 'D'};

struct Header {
    char magic[8];
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

}  // namespace

uint64_t fnv1a_64(const void* data, size_t size, uint64_t hash) {
    const auto* bytes = static_cast<const unsigned char*>(data);
    for (size_t i = 0; i < size; ++i) {
        hash ^= bytes[i];
        hash *= 0x100000001b3ull;
    }
    return hash;
}

void write_film_checkpoint(const std::string& path, const Film& film, uint64_t settings_hash, int spp_done) {
    Header h{};
    std::memcpy(h.magic, k_magic, sizeof(k_magic));
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
    if (std::fread(&h, sizeof(h), 1, f.get()) != 1 || std::memcmp(h.magic, k_magic, sizeof(k_magic)) != 0)
        fail(path, "not a veach checkpoint (or truncated)");
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
    if (std::fread(state.data(), sizeof(double), state.size(), f.get()) != state.size() ||
        std::fread(end, sizeof(end), 1, f.get()) != 1 || std::memcmp(end, k_end, sizeof(k_end)) != 0 ||
        std::fgetc(f.get()) != EOF)
        fail(path, "truncated or corrupt checkpoint");
    film.load_state(state.data(), state.size());
    return h.spp_done;
}

}  // namespace veach
