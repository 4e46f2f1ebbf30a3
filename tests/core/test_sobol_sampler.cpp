// The scrambled (0,2)-sequence is stratified and uniform; both properties are what make it
// converge faster than independent numbers without bias.
#include <gtest/gtest.h>

#include <set>
#include <vector>

#include "core/sobol_sampler.h"

namespace veach {
namespace {

// The first 2^k points of a (0,2)-sequence put exactly one point in every elementary interval
// of area 2^-k (all shapes 2^-a x 2^-(k-a)); Owen scrambling preserves that.
TEST(SobolSampler, FirstPowerOfTwoPointsAreStratifiedInEveryElementaryInterval) {
    for (uint64_t pixel : {0ull, 7ull, 123456ull}) {
        const int k = 8, n = 1 << k;
        std::vector<Vec2> pts;
        for (int i = 0; i < n; ++i) {
            Sampler s(SamplerKind::Sobol, 3, pixel, static_cast<uint32_t>(i));
            s.next_2d();                 // pair 0
            pts.push_back(s.next_2d());  // pair 1: a different scramble and shuffle
        }
        for (int a = 0; a <= k; ++a) {
            int nx = 1 << a, ny = 1 << (k - a);
            std::set<int> cells;
            for (const Vec2& p : pts) cells.insert(static_cast<int>(p.x * nx) * ny + static_cast<int>(p.y * ny));
            EXPECT_EQ(static_cast<int>(cells.size()), n) << "interval shape " << nx << "x" << ny << " pixel " << pixel;
        }
    }
}

// Across pixels (independent scrambles) each value is uniform: mean 1/2, variance 1/12.
TEST(SobolSampler, ValuesAreUniformAcrossPixels) {
    double sum = 0, sum2 = 0, cross = 0;
    const int n = 100000;
    for (int p = 0; p < n; ++p) {
        Sampler s(SamplerKind::Sobol, 9, static_cast<uint64_t>(p), 5);
        Vec2 a = s.next_2d();
        float b = s.next_1d();
        sum += a.x;
        sum2 += a.x * a.x;
        cross += (a.y - 0.5) * (b - 0.5);
    }
    EXPECT_NEAR(sum / n, 0.5, 0.005);
    EXPECT_NEAR(sum2 / n - (sum / n) * (sum / n), 1.0 / 12.0, 0.002);
    EXPECT_NEAR(cross / n, 0.0, 0.003);  // different pairs are uncorrelated
}

// The fast paths (byte tables in reversed bit order, one reversal of the index per Sampler, x
// alone for next_1d) give the values of the textbook composition owen_scramble(sobol_d(i), s).
TEST(SobolSampler, FastPathsEqualTheTextbookComposition) {
    for (uint32_t k = 0; k < 100000; ++k) {
        uint32_t i = k * 2654435761u;
        uint32_t textbook = 0;
        for (int b = 0; b < 32; ++b) textbook |= ((sobol_dimension1(i) >> b) & 1u) << (31 - b);
        ASSERT_EQ(sobol_dimension1_reversed(i), textbook) << i;
        ASSERT_EQ(reverse_bits(reverse_bits(i)), i);
        ASSERT_EQ(reverse_bits(1u << (k % 32)), 1u << (31 - k % 32));
    }
    for (uint32_t index = 0; index < 64; ++index) {
        uint64_t key = mix64(3 * 0x9e3779b97f4a7c15ull ^ mix64(11 + 0x2545f4914f6cdd1dull));
        Sampler a(SamplerKind::Sobol, 3, 11, index), b(SamplerKind::Sobol, 3, 11, index);
        for (int pair = 0; pair < Sampler::k_sobol_pairs; ++pair) {
            uint64_t h = mix64(key + static_cast<uint64_t>(pair) * 0xd1b54a32d192ed03ull);
            uint32_t i = owen_scramble(index, static_cast<uint32_t>(h));
            uint32_t x = owen_scramble(sobol_dimension0(i), static_cast<uint32_t>(h >> 32));
            uint32_t y = owen_scramble(sobol_dimension1(i), static_cast<uint32_t>(mix64(h) >> 32));
            Vec2 v = a.next_2d();
            ASSERT_EQ(v.x, static_cast<float>(x >> 8) * 0x1p-24f) << index << " " << pair;
            ASSERT_EQ(v.y, static_cast<float>(y >> 8) * 0x1p-24f) << index << " " << pair;
            ASSERT_EQ(b.next_1d(), v.x);
        }
    }
}

TEST(SobolSampler, OwenScrambleIsABijectionOnPrefixes) {
    // Nested uniform scrambling permutes each dyadic interval's halves: distinct inputs stay
    // distinct, and the top k bits of the output depend only on the top k bits of the input.
    std::set<uint32_t> outs;
    for (uint32_t i = 0; i < 4096; ++i) outs.insert(owen_scramble(i << 20, 77) >> 20);
    EXPECT_EQ(outs.size(), 4096u);
}

}  // namespace
}  // namespace veach
