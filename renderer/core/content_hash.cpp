#include "core/content_hash.h"

#include <fstream>
#include <vector>

namespace veach {

uint64_t fnv1a_64(const void* data, size_t size, uint64_t hash) {
    const auto* bytes = static_cast<const unsigned char*>(data);
    for (size_t i = 0; i < size; ++i) {
        hash ^= bytes[i];
        hash *= 0x100000001b3ull;
    }
    return hash;
}

bool hash_file_content(const std::string& path, uint64_t* hash) {
    std::ifstream f(path, std::ios::binary);
    if (!f) return false;
    uint64_t h = *hash;
    std::vector<char> buffer(1 << 16);
    while (f) {
        f.read(buffer.data(), static_cast<std::streamsize>(buffer.size()));
        h = fnv1a_64(buffer.data(), static_cast<size_t>(f.gcount()), h);
    }
    if (f.bad()) return false;
    *hash = h;
    return true;
}

}  // namespace veach
