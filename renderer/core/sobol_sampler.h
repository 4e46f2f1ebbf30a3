// Sample values for one pixel sample, keyed by (seed, pixel, sample index) like Rng.
//
// The first dimensions come in pairs from the (0,2)-sequence (the first two Sobol dimensions),
// each pair with its own Owen scrambling and its own scrambled index shuffle (Burley 2020,
// "Practical Hash-based Owen Scrambling"): within a pixel, the first N samples of every pair are
// stratified in all elementary intervals, so the pixel jitter and the first bounces' light and
// BSDF samples converge faster than with independent numbers. Later dimensions, where
// stratification no longer pays, come from PCG32. Owen scrambling keeps every sample uniformly
// distributed, so estimates stay unbiased.
//
// Cost: a pair is one SplitMix per scramble seed, three hashes and three bit reversals. Bit
// reversals cancel where they meet: the sample index is reversed once per Sampler, dimension 0 is
// the reversal of the shuffled index, and dimension 1 is generated directly in reversed bit order
// by byte tables of its generator matrix (instead of one XOR per set bit of a 32-bit index), so
// no value is reversed twice. next_1d() computes only the first coordinate of its pair. The
// values are the same as the textbook composition (test_sobol_sampler.cpp checks it).
#pragma once

#include <cstdint>

#include "core/math.h"
#include "core/rng.h"

namespace veach {

inline uint32_t reverse_bits(uint32_t x) {
    x = ((x >> 1) & 0x55555555u) | ((x & 0x55555555u) << 1);
    x = ((x >> 2) & 0x33333333u) | ((x & 0x33333333u) << 2);
    x = ((x >> 4) & 0x0f0f0f0fu) | ((x & 0x0f0f0f0fu) << 4);
    return __builtin_bswap32(x);  // the byte order: one instruction for the last two steps
}

// A hash in which every bit depends only on itself and lower bits (x += seed, and x ^= x * even
// constants only carry upward): applied to bit-reversed values it is a nested uniform (Owen)
// scramble. Constants from Burley 2020.
inline uint32_t owen_hash_reversed(uint32_t x, uint32_t seed) {
    x += seed;
    x ^= x * 0x6c50b47cu;
    x ^= x * 0xb82f1e52u;
    x ^= x * 0xc7afe638u;
    x ^= x * 0x8d22f6e6u;
    return x;
}

inline uint32_t owen_scramble(uint32_t x, uint32_t seed) {
    return reverse_bits(owen_hash_reversed(reverse_bits(x), seed));
}

// Sobol dimension 0 (van der Corput) and 1 (direction numbers v_k = v_(k-1) ^ (v_(k-1) >> 1)).
inline uint32_t sobol_dimension0(uint32_t i) { return reverse_bits(i); }
struct SobolDimension1Matrix {
    uint32_t v[32];
    constexpr SobolDimension1Matrix() : v() {
        uint32_t d = 1u << 31;
        for (int k = 0; k < 32; ++k, d ^= d >> 1) v[k] = d;
    }
};
inline constexpr SobolDimension1Matrix k_sobol_dimension1;
inline uint32_t sobol_dimension1(uint32_t i) {
    uint32_t r = 0;
    for (; i; i &= i - 1) r ^= k_sobol_dimension1.v[__builtin_ctz(i)];  // one XOR per set bit
    return r;
}
// reverse_bits(sobol_dimension1(i)) by four byte lookups: the generator matrix is linear over
// GF(2), so the contributions of i's four bytes XOR together.
struct SobolDimension1ReversedTables {
    uint32_t t[4][256];
    constexpr SobolDimension1ReversedTables() : t() {
        for (int byte = 0; byte < 4; ++byte)
            for (int v = 0; v < 256; ++v) {
                uint32_t r = 0;
                for (int b = 0; b < 8; ++b)
                    if (v & (1 << b)) {
                        uint32_t d = k_sobol_dimension1.v[byte * 8 + b], rev = 0;
                        for (int k = 0; k < 32; ++k) rev |= ((d >> k) & 1u) << (31 - k);
                        r ^= rev;
                    }
                t[byte][v] = r;
            }
    }
};
inline constexpr SobolDimension1ReversedTables k_sobol_dimension1_reversed;
inline uint32_t sobol_dimension1_reversed(uint32_t i) {
    const auto& t = k_sobol_dimension1_reversed.t;
    return t[0][i & 0xffu] ^ t[1][(i >> 8) & 0xffu] ^ t[2][(i >> 16) & 0xffu] ^ t[3][i >> 24];
}

enum class SamplerKind : uint8_t { Sobol, Random };

class Sampler {
public:
    // Pairs of dimensions drawn from the scrambled (0,2)-sequence: the camera jitter and the
    // first two bounces' light and BSDF samples.
    static constexpr int k_sobol_pairs = 12;

    Sampler(SamplerKind kind, uint64_t seed, uint64_t pixel, uint32_t sample_index)
        : m_rng(Rng::for_sample(seed, pixel, sample_index)),
          m_key(mix64(seed * 0x9e3779b97f4a7c15ull ^ mix64(pixel + 0x2545f4914f6cdd1dull))),
          m_index_reversed(reverse_bits(sample_index)),
          m_pair(kind == SamplerKind::Sobol ? 0 : k_sobol_pairs),
          m_random(kind != SamplerKind::Sobol) {}

    // Two stratified values (one dimension pair):
    //   i = owen_scramble(index, s0)                   the pair's shuffled index
    //   x = owen_scramble(sobol_dimension0(i), s1)     = reverse(hash(i, s1))
    //   y = owen_scramble(sobol_dimension1(i), s2)     = reverse(hash(reverse(dim1(i)), s2))
    Vec2 next_2d() {
        if (m_pair >= k_sobol_pairs) return {m_rng.next_float(), m_rng.next_float()};
        uint64_t h = pair_hash();
        uint32_t i = shuffled_index(h);
        uint32_t x = reverse_bits(owen_hash_reversed(i, static_cast<uint32_t>(h >> 32)));
        uint32_t y =
            reverse_bits(owen_hash_reversed(sobol_dimension1_reversed(i), static_cast<uint32_t>(mix64(h) >> 32)));
        return {to_unit(x), to_unit(y)};
    }
    // One value; in the stratified range it uses a whole pair (its x) so later pairs stay aligned.
    float next_1d() {
        if (m_pair >= k_sobol_pairs) return m_rng.next_float();
        uint64_t h = pair_hash();
        return to_unit(reverse_bits(owen_hash_reversed(shuffled_index(h), static_cast<uint32_t>(h >> 32))));
    }
    float next_float() { return next_1d(); }

    // The camera sample's shutter time in [0, 1): a dimension of its own beside the sequence of
    // pairs, not drawn from it, so every other value of the sample is the same whether or not the
    // render has a shutter (an image without motion blur is unchanged). Sobol: the pixel's
    // samples stratify the shutter as they stratify every pair (Owen-scrambled van der Corput,
    // index shuffled by its own scramble); Random: an independent value.
    // The sample index this sampler was made for (the denoiser's halves split by it).
    uint32_t sample_index() const { return reverse_bits(m_index_reversed); }

    float shutter_time() const {
        const uint64_t h = mix64(m_key ^ 0x5851f42d4c957f2dull);
        if (m_random) return to_unit(static_cast<uint32_t>(mix64(h + m_index_reversed) >> 32));
        return to_unit(reverse_bits(owen_hash_reversed(shuffled_index(h), static_cast<uint32_t>(h >> 32))));
    }

private:
    static float to_unit(uint32_t v) { return static_cast<float>(v >> 8) * 0x1p-24f; }
    uint64_t pair_hash() { return mix64(m_key + static_cast<uint64_t>(m_pair++) * 0xd1b54a32d192ed03ull); }
    // owen_scramble(index, low half of h), with the index's reversal done once per Sampler.
    uint32_t shuffled_index(uint64_t h) const {
        return reverse_bits(owen_hash_reversed(m_index_reversed, static_cast<uint32_t>(h)));
    }

    Rng m_rng;
    uint64_t m_key;
    uint32_t m_index_reversed;
    int m_pair;
    bool m_random;
};

}  // namespace veach
