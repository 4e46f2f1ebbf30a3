// Content identity: one stable 64-bit hash for "is this the same render?", shared by checkpoints
// and part files. It hashes what shapes the image, never where it came from: the bytes of every
// input file (not their paths) and every setting, numbers by their exact bit patterns (a float
// printed with six decimals would make --noise 1e-7 and 0 the same render).
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>

namespace veach {

// FNV-1a, 64 bits (not cryptographic: it only has to tell another render's state from ours).
inline constexpr uint64_t k_fnv_offset = 0xcbf29ce484222325ull;
uint64_t fnv1a_64(const void* data, size_t size, uint64_t hash = k_fnv_offset);
inline uint64_t fnv1a_64(const std::string& s, uint64_t hash = k_fnv_offset) {
    return fnv1a_64(s.data(), s.size(), hash);
}

// Continues `hash` over the bytes of the file at `path`. Returns false (hash unchanged) when the
// file cannot be read.
bool hash_file_content(const std::string& path, uint64_t* hash);

// A hash built field by field: each field is its name, its type and its exact bytes, so that
// neither two fields' texts nor a rounded number can collide.
class HashKey {
public:
    explicit HashKey(const char* domain) { text(domain); }
    HashKey& field(const char* name, const std::string& value) {
        text(name);
        return text(value);
    }
    HashKey& field(const char* name, const char* value) { return field(name, std::string(value)); }
    HashKey& field(const char* name, int64_t value) {
        text(name);
        return bytes("i", &value, sizeof(value));
    }
    HashKey& field(const char* name, uint64_t value) {
        text(name);
        return bytes("u", &value, sizeof(value));
    }
    HashKey& field(const char* name, int value) { return field(name, static_cast<int64_t>(value)); }
    HashKey& field(const char* name, bool value) { return field(name, static_cast<int64_t>(value)); }
    HashKey& field(const char* name, double value) {
        text(name);
        if (value == 0.0) value = 0.0;  // -0 and +0 shape the same image
        return bytes("d", &value, sizeof(value));
    }
    HashKey& field(const char* name, float value) { return field(name, static_cast<double>(value)); }
    uint64_t value() const { return m_hash; }

private:
    HashKey& text(const std::string& s) {
        const uint64_t n = s.size();
        bytes("s", &n, sizeof(n));
        m_hash = fnv1a_64(s.data(), s.size(), m_hash);
        return *this;
    }
    HashKey& bytes(const char* tag, const void* data, size_t size) {
        m_hash = fnv1a_64(tag, 1, m_hash);
        m_hash = fnv1a_64(data, size, m_hash);
        return *this;
    }
    uint64_t m_hash = k_fnv_offset;
};

}  // namespace veach
