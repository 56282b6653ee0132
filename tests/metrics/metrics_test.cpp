// Texel error and its statistics (docs/conventions.md section 5) against hand-computed values.
#include "harness/metrics/metrics.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

namespace pxh {
namespace {

TEST(TexelError, WrapsToHalfOpenRangeAndScales) {
    // 0.3 uv in x on a 10-texel map is 3 texels.
    Vec2d e = texel_error({0.5, 0.5}, {0.2, 0.5}, 10, 20);
    EXPECT_NEAR(e.x, 3.0, 1e-12);
    EXPECT_NEAR(e.y, 0.0, 1e-12);
    // One tile away is the same texel: zero error.
    e = texel_error({1.25, -0.75}, {0.25, 0.25}, 10, 20);
    EXPECT_NEAR(e.x, 0.0, 1e-12);
    EXPECT_NEAR(e.y, 0.0, 1e-12);
    // 0.7 wraps to -0.3; -0.5 stays -0.5 (range [-0.5, 0.5)); +0.5 wraps to -0.5.
    EXPECT_NEAR(texel_error({0.7, 0}, {0, 0}, 1, 1).x, -0.3, 1e-12);
    EXPECT_NEAR(texel_error({0.0, 0}, {0.5, 0}, 1, 1).x, -0.5, 1e-12);
    EXPECT_NEAR(texel_error({0.5, 0}, {0.0, 0}, 1, 1).x, -0.5, 1e-12);
    // Non-square maps scale per component.
    e = texel_error({0.1, 0.1}, {0, 0}, 100, 10);
    EXPECT_NEAR(std::hypot(e.x, e.y), std::hypot(10.0, 1.0), 1e-9);
    EXPECT_TRUE(std::isnan(texel_error({NAN, 0}, {0, 0}, 4, 4).x));
}

TEST(TexelError, HugeUvKeepsItsPlaceInTheTile) {
    // A uv far beyond the tile (a plug-in's vec2(1e16), or P + vec2(1e30, -3e38) in float) is an
    // integer in floating point: it shows the texture at the tile's corner, not at the truth.
    // Subtracting first, 1e16 - 0.25 rounds to 1e16 and the wrapped error read 0.
    Vec2d e = texel_error({1e16, 1e16}, {0.25, 0.5}, 64, 32);
    EXPECT_DOUBLE_EQ(e.x, -0.25 * 64);  // 0 - 0.25 of a tile
    EXPECT_DOUBLE_EQ(e.y, -0.5 * 32);   // 0 - 0.5 wraps to -0.5
    e = texel_error({double(1e30f), double(-3e38f)}, {0.375, 0.125}, 16, 16);
    EXPECT_DOUBLE_EQ(e.x, -0.375 * 16);
    EXPECT_DOUBLE_EQ(e.y, -0.125 * 16);
    // The truth far out and the method in the first tile: the same wrap, either way round.
    e = texel_error({0.75, 0.25}, {-1099511627776.0 + 0.5, 1099511627776.0 + 0.125}, 8, 8);
    EXPECT_DOUBLE_EQ(e.x, 0.25 * 8);
    EXPECT_DOUBLE_EQ(e.y, 0.125 * 8);
    // A non-finite truth is no error either.
    EXPECT_TRUE(std::isnan(texel_error({0, 0}, {INFINITY, 0}, 4, 4).x));
}

TEST(ErrorStats, HandExample) {
    // Magnitudes 0, 0.25, 0.5, 1, 2 (+ one NaN, one Inf counted as non-finite).
    const ErrorStats s = error_stats({1.0, 0.0, 2.0, NAN, 0.25, 0.5, INFINITY});
    EXPECT_EQ(s.count, 5);
    EXPECT_EQ(s.nonfinite, 2);
    EXPECT_DOUBLE_EQ(s.mean, 3.75 / 5);
    EXPECT_DOUBLE_EQ(s.rms, std::sqrt((0 + 0.0625 + 0.25 + 1 + 4) / 5));
    EXPECT_DOUBLE_EQ(s.p50, 0.5);
    // p95: position 0.95 * 4 = 3.8 between 1 and 2 -> 1.8; p99: 3.96 -> 1.96.
    EXPECT_DOUBLE_EQ(s.p95, 1.8);
    EXPECT_DOUBLE_EQ(s.p99, 1.96);
    EXPECT_DOUBLE_EQ(s.max, 2.0);
    EXPECT_DOUBLE_EQ(s.frac_gt_0_5, 2.0 / 5);  // strictly greater: 1 and 2
    EXPECT_DOUBLE_EQ(s.frac_gt_1, 1.0 / 5);
}

TEST(ErrorStats, AllNonFiniteGivesNaNStatsNotZero) {
    const ErrorStats s = error_stats({NAN, NAN});
    EXPECT_EQ(s.nonfinite, 2);
    EXPECT_TRUE(std::isnan(s.mean));
}

// The selection gives what a sort gives, to the bit: ties, infinities, every size up to 40 and
// the quantiles' edges (0, 1, a rank exactly, between two ranks).
TEST(Percentiles, SelectionEqualsTheSortedArray) {
    std::mt19937 rng(7);
    const std::vector<double> qs = {0.0, 0.25, 0.5, 0.5, 0.95, 0.99, 0.999, 1.0};
    for (size_t n = 1; n <= 40; ++n)
        for (int trial = 0; trial < 20; ++trial) {
            std::vector<double> v(n);
            for (double& x : v) {
                const unsigned r = rng() % 10;
                x = r == 0 ? INFINITY : r < 3 ? double(rng() % 4) : double(rng()) / 7.0;
            }
            std::vector<double> sorted = v;
            std::sort(sorted.begin(), sorted.end());
            const std::vector<double> got = percentiles_of(v, qs);
            ASSERT_EQ(got.size(), qs.size());
            for (size_t i = 0; i < qs.size(); ++i) {
                const double want = percentile_sorted(sorted, qs[i]);
                if (std::isnan(want)) {
                    EXPECT_TRUE(std::isnan(got[i])) << "n " << n << " q " << qs[i];
                } else {
                    EXPECT_EQ(got[i], want) << "n " << n << " q " << qs[i];
                }
            }
        }
}

}  // namespace
}  // namespace pxh
