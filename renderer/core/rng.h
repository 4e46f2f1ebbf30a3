// Random numbers keyed by (seed, pixel, sample index), never by thread: every sample draws from
// its own stream, so images are identical for any thread count and sample ranges rendered on
// different machines sum to one long render.
#pragma once

#include <cstdint>

namespace veach {

// A 64-bit mixing function (SplitMix64's finaliser): good avalanche, cheap.
inline uint64_t mix64(uint64_t x) {
    x ^= x >> 30;
    x *= 0xbf58476d1ce4e5b9ull;
    x ^= x >> 27;
    x *= 0x94d049bb133111ebull;
    x ^= x >> 31;
    return x;
}

// PCG32 (O'Neill 2014): 64-bit state, 32-bit output, selectable stream.
class Rng {
public:
    Rng(uint64_t seed, uint64_t stream) {
        m_inc = (stream << 1u) | 1u;
        m_state = 0;
        next_u32();
        m_state += seed;
        next_u32();
    }
    // The stream for one sample of one pixel.
    static Rng for_sample(uint64_t seed, uint64_t pixel, uint64_t sample_index) {
        uint64_t key = mix64(seed * 0x9e3779b97f4a7c15ull + mix64(pixel + 0x632be59bd9b4e019ull));
        return Rng(mix64(key ^ sample_index * 0xd1b54a32d192ed03ull), key);
    }
    uint32_t next_u32() {
        uint64_t old = m_state;
        m_state = old * 6364136223846793005ull + m_inc;
        uint32_t xorshifted = static_cast<uint32_t>(((old >> 18u) ^ old) >> 27u);
        uint32_t rot = static_cast<uint32_t>(old >> 59u);
        return (xorshifted >> rot) | (xorshifted << ((32 - rot) & 31));
    }
    // Uniform in [0, 1): 24 random bits, so 1.0f is never returned.
    float next_float() { return static_cast<float>(next_u32() >> 8) * 0x1p-24f; }

private:
    uint64_t m_state, m_inc;
};

}  // namespace veach
