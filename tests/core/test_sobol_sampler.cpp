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
            s.next_2d();                // pair 0
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

TEST(SobolSampler, OwenScrambleIsABijectionOnPrefixes) {
    // Nested uniform scrambling permutes each dyadic interval's halves: distinct inputs stay
    // distinct, and the top k bits of the output depend only on the top k bits of the input.
    std::set<uint32_t> outs;
    for (uint32_t i = 0; i < 4096; ++i) outs.insert(owen_scramble(i << 20, 77) >> 20);
    EXPECT_EQ(outs.size(), 4096u);
}

}  // namespace
}  // namespace veach
