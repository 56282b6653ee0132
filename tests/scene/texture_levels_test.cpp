// Texture levels (docs/conventions.md section 10): the area-weighted box levels against repeated
// 2 x 2 averaging and a brute-force rectangle overlap, the overlap weights, and the fetch at a
// level of detail against level-0 bilinear, each level's bilinear and the linear blend.
#include "harness/scene/texture_levels.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

#include "tests/test_util.h"

namespace pxh {
namespace {

using test::random_field;

template <typename T>
bool same_bits(T a, T b) {
    return std::memcmp(&a, &b, sizeof(T)) == 0;
}

TEST(TextureLevels, CountAndSizes) {
    EXPECT_EQ(last_level(1, 1), 0);
    EXPECT_EQ(last_level(2, 1), 1);
    EXPECT_EQ(last_level(3, 3), 1);
    EXPECT_EQ(last_level(16, 4), 4);
    EXPECT_EQ(last_level(1023, 5), 9);
    EXPECT_EQ(last_level(1024, 5), 10);
    const TextureLevels tl = build_texture_levels(random_field(16, 4, 1));
    ASSERT_EQ(tl.last(), 4);
    const int want[5][2] = {{16, 4}, {8, 2}, {4, 1}, {2, 1}, {1, 1}};
    for (int L = 0; L <= 4; ++L) {
        EXPECT_EQ(tl.levels[size_t(L)].width, want[L][0]) << L;
        EXPECT_EQ(tl.levels[size_t(L)].height, want[L][1]) << L;
    }
    const TextureLevels odd = build_texture_levels(random_field(5, 3, 2));
    ASSERT_EQ(odd.last(), 2);
    EXPECT_EQ(odd.levels[1].width, 2);
    EXPECT_EQ(odd.levels[1].height, 1);
    EXPECT_EQ(odd.levels[2].width, 1);
    EXPECT_EQ(odd.levels[2].height, 1);
    EXPECT_EQ(build_texture_levels(random_field(1, 1, 3)).last(), 0);
}

TEST(TextureLevels, ConstantFieldIsConstantOnEveryLevel) {
    for (const auto& [w, h] : {std::pair{7, 5}, {16, 16}, {13, 1}, {1, 9}, {100, 37}, {3, 3}}) {
        const TextureLevels tl = build_texture_levels(test::flat_field(w, h, 0.3f));
        for (const HeightField& level : tl.levels)
            for (float t : level.texels) ASSERT_EQ(t, 0.3f) << w << "x" << h;
        for (double lambda : {-1.0, 0.0, 0.3, 1.7, double(tl.last()), tl.last() + 5.0}) {
            EXPECT_EQ(level_fetch<float>(tl, {0.37f, -2.1f}, float(lambda)), 0.3f);
            EXPECT_EQ(level_fetch<double>(tl, {0.37, -2.1}, lambda), double(0.3f));
        }
    }
}

// Heights k / 256: every mean of 4^L of them is a multiple of 2^-(8 + 2L), exact in float for
// L <= 8, so the area levels and repeated 2 x 2 averaging (in double) must agree exactly. Once
// an axis is 1 texel wide the averaging is over the other axis only (2 x 1), as GL's sizes
// say.
HeightField average_2x2(const HeightField& f) {
    const int w = std::max(1, f.width / 2), h = std::max(1, f.height / 2);
    const int sx = f.width > 1 ? 2 : 1, sy = f.height > 1 ? 2 : 1;
    HeightField out(w, h);
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) {
            double sum = 0;
            for (int y = 0; y < sy; ++y)
                for (int x = 0; x < sx; ++x) sum += f.at(sx * i + x, sy * j + y);
            out.at(i, j) = float(sum / (sx * sy));
        }
    return out;
}

TEST(TextureLevels, PowerOfTwoLevelIsRepeated2x2Averaging) {
    std::mt19937 rng(7);
    std::uniform_int_distribution<int> k(0, 256);
    for (const auto& [w, h] : {std::pair{16, 16}, {32, 8}, {4, 64}, {2, 2}}) {
        HeightField f(w, h);
        for (float& t : f.texels) t = float(k(rng)) / 256.0f;
        const TextureLevels tl = build_texture_levels(f);
        HeightField avg = f;
        for (int L = 1; L <= tl.last(); ++L) {
            avg = average_2x2(avg);
            const HeightField& lv = tl.levels[size_t(L)];
            ASSERT_EQ(lv.width, avg.width);
            ASSERT_EQ(lv.height, avg.height);
            for (size_t t = 0; t < avg.texels.size(); ++t)
                ASSERT_EQ(lv.texels[t], avg.texels[t]) << w << "x" << h << " level " << L;
        }
    }
    // Any float heights: one rounding (area level) against one per level (averaging).
    const HeightField f = random_field(64, 64, 11);
    const TextureLevels tl = build_texture_levels(f);
    HeightField avg = f;
    for (int L = 1; L <= tl.last(); ++L) {
        avg = average_2x2(avg);
        for (size_t t = 0; t < avg.texels.size(); ++t)
            ASSERT_NEAR(tl.levels[size_t(L)].texels[t], avg.texels[t], 4e-7) << L;
    }
}

TEST(TextureLevels, OverlapWeightsOfEverySizeSumToOne) {
    // 5 -> 2: texel 0 covers [0, 2.5), texel 1 [2.5, 5): weights 0.4, 0.4, 0.2 and 0.2, 0.4, 0.4.
    const AxisCover a = level_axis_cover(5, 2, 0), b = level_axis_cover(5, 2, 1);
    EXPECT_EQ(a.first, 0);
    EXPECT_EQ(a.overlap, (std::vector<long long>{2, 2, 1}));
    EXPECT_EQ(b.first, 2);
    EXPECT_EQ(b.overlap, (std::vector<long long>{1, 2, 2}));
    // 7 -> 3: [0, 7/3), [7/3, 14/3), [14/3, 7) in units of 1/3: 3,3,1 | 2,3,2 | 1,3,3.
    EXPECT_EQ(level_axis_cover(7, 3, 1).first, 2);
    EXPECT_EQ(level_axis_cover(7, 3, 1).overlap, (std::vector<long long>{2, 3, 2}));
    for (int n0 = 1; n0 <= 70; ++n0)
        for (int L = 1; L <= last_level(n0, 1); ++L) {
            const int nl = level_size(n0, L);
            std::vector<long long> per_texel(size_t(n0), 0);
            for (int i = 0; i < nl; ++i) {
                const AxisCover c = level_axis_cover(n0, nl, i);
                long long total = 0;
                double weight = 0;
                for (size_t k = 0; k < c.overlap.size(); ++k) {
                    ASSERT_GT(c.overlap[k], 0);
                    total += c.overlap[k];
                    weight += double(c.overlap[k]) / n0;
                    per_texel[size_t(c.first) + k] += c.overlap[k];
                }
                ASSERT_EQ(total, n0) << n0 << " level " << L << " texel " << i;
                ASSERT_NEAR(weight, 1.0, 1e-14) << n0 << " level " << L << " texel " << i;
            }
            // Every level-0 texel is covered once in all: n_level units of 1 / n_level.
            for (int k = 0; k < n0; ++k) ASSERT_EQ(per_texel[size_t(k)], nl) << n0 << " " << k;
        }
}

TEST(TextureLevels, ThreeByThreeToOneIsThePlainMean) {
    const HeightField f = random_field(3, 3, 5);
    const TextureLevels tl = build_texture_levels(f);
    ASSERT_EQ(tl.last(), 1);
    double mean = 0;
    for (float t : f.texels) mean += t;
    mean /= 9;
    // Two divisions in double, one rounding to float: within half a float ulp of the mean.
    EXPECT_NEAR(tl.levels[1].texels[0], mean, 6e-8);
}

// Brute force: the area of the level texel's rectangle over each level-0 texel, in double.
TEST(TextureLevels, OddSizesAreTheAreaWeightedMean) {
    for (const auto& [w, h] : {std::pair{5, 3}, {7, 7}, {9, 4}, {13, 6}, {33, 17}, {1, 5}}) {
        const HeightField f = random_field(w, h, uint32_t(w * 100 + h));
        const TextureLevels tl = build_texture_levels(f);
        for (int L = 1; L <= tl.last(); ++L) {
            const HeightField& lv = tl.levels[size_t(L)];
            const double cw = double(w) / lv.width, ch = double(h) / lv.height;
            for (int j = 0; j < lv.height; ++j)
                for (int i = 0; i < lv.width; ++i) {
                    double sum = 0, area = 0;
                    for (int y = 0; y < h; ++y)
                        for (int x = 0; x < w; ++x) {
                            const double ox =
                                std::min((i + 1) * cw, x + 1.0) - std::max(i * cw, double(x));
                            const double oy =
                                std::min((j + 1) * ch, y + 1.0) - std::max(j * ch, double(y));
                            if (ox <= 0 || oy <= 0) continue;
                            sum += ox * oy * f.at(x, y);
                            area += ox * oy;
                        }
                    ASSERT_NEAR(area, cw * ch, 1e-12);
                    ASSERT_NEAR(lv.at(i, j), sum / area, 2e-7)
                        << w << "x" << h << " level " << L << " (" << i << ", " << j << ")";
                }
        }
    }
}

std::vector<Vec2d> probe_uvs() {
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> d(-3.0, 4.0);
    std::vector<Vec2d> uv = {{0, 0}, {1, 1}, {0.5, 0.5}, {-0.001, 2.999}};
    for (int k = 0; k < 300; ++k) uv.push_back({d(rng), d(rng)});
    return uv;
}

TEST(TextureLevels, FetchAtNonPositiveLodIsLevelZeroBitForBit) {
    const HeightField f = random_field(37, 23, 9);
    const TextureLevels tl = build_texture_levels(f);
    HeightSampler<float> hf(f, 1.0f, 0.0f);
    HeightSampler<double> hd(f, 1.0, 0.0);
    for (const Vec2d uv : probe_uvs())
        for (double lambda : {0.0, -0.25, -100.0, -HUGE_VAL, std::nan("")}) {
            const Vec2<float> uvf(uv);
            ASSERT_TRUE(same_bits(level_fetch<float>(tl, uvf, float(lambda)), hf.height(uvf)));
            ASSERT_TRUE(same_bits(level_fetch<double>(tl, uv, lambda), hd.height(uv)));
        }
}

TEST(TextureLevels, FetchAtIntegerLodIsThatLevelsBilinear) {
    const HeightField f = random_field(40, 24, 13);
    const TextureLevels tl = build_texture_levels(f);
    ASSERT_EQ(tl.last(), 5);
    for (const Vec2d uv : probe_uvs())
        for (int L = 0; L <= tl.last() + 2; ++L) {
            const int at = std::min(L, tl.last());
            const Vec2<float> uvf(uv);
            ASSERT_TRUE(same_bits(level_fetch<float>(tl, uvf, float(L)),
                                  level_bilinear<float>(tl, at, uvf)));
            ASSERT_TRUE(
                same_bits(level_fetch<double>(tl, uv, double(L)), level_bilinear(tl, at, uv)));
        }
    // A level's texel centres ((i + 0.5) / W_L, (j + 0.5) / H_L) give its texels (section 1 per
    // level): level 2 of 40 x 24 is 10 x 6.
    const HeightField& l2 = tl.levels[2];
    ASSERT_EQ(l2.width, 10);
    ASSERT_EQ(l2.height, 6);
    for (int j = 0; j < 6; ++j)
        for (int i = 0; i < 10; ++i)
            EXPECT_NEAR(level_fetch<double>(tl, {(i + 0.5) / 10, (j + 0.5) / 6}, 2.0), l2.at(i, j),
                        1e-12);
}

TEST(TextureLevels, BetweenLevelsIsTheLinearBlend) {
    // By hand: 4 x 1 heights 0, 1, 0.5, 0.25. Level 1 (2 x 1): 0.5, 0.375; level 2: 0.4375.
    HeightField f(4, 1);
    f.texels = {0.0f, 1.0f, 0.5f, 0.25f};
    const TextureLevels tl = build_texture_levels(f);
    ASSERT_EQ(tl.last(), 2);
    EXPECT_EQ(tl.levels[1].texels, (std::vector<float>{0.5f, 0.375f}));
    EXPECT_EQ(tl.levels[2].texels, (std::vector<float>{0.4375f}));
    // At u = 0.125 (texel 0's centre): level 0 gives 0; level 1 at x = 0.125 * 2 - 0.5 = -0.25
    // blends its texels 1 (0.375, wrapped) and 0 (0.5) with fx = 0.75: 0.46875; level 2: 0.4375.
    const Vec2d uv{0.125, 0.5};
    EXPECT_EQ(level_fetch<double>(tl, uv, 0.0), 0.0);
    EXPECT_EQ(level_fetch<double>(tl, uv, 1.0), 0.46875);
    EXPECT_EQ(level_fetch<double>(tl, uv, 0.25), 0.25 * 0.46875);
    EXPECT_EQ(level_fetch<double>(tl, uv, 1.5), 0.46875 + (0.4375 - 0.46875) * 0.5);
    EXPECT_EQ(level_fetch<double>(tl, uv, 2.0), 0.4375);
    EXPECT_EQ(level_fetch<double>(tl, uv, 9.0), 0.4375);
    // Any field: (1 - tau) b_L + tau b_{L+1}, the GL specification's form, within rounding.
    const TextureLevels rt = build_texture_levels(random_field(29, 50, 17));
    for (const Vec2d p : probe_uvs())
        for (double lambda : {0.1, 0.5, 1.999, 2.75, 4.3, 5.0 - 1e-9}) {
            const int d1 = int(std::floor(lambda));
            const double tau = lambda - d1;
            const double want =
                (1 - tau) * level_bilinear(rt, d1, p) + tau * level_bilinear(rt, d1 + 1, p);
            ASSERT_NEAR(level_fetch<double>(rt, p, lambda), want, 1e-15) << lambda;
            ASSERT_NEAR(level_fetch<float>(rt, Vec2<float>(p), float(lambda)), want, 1e-5)
                << lambda;
        }
}

TEST(TextureLevels, LevelSamplerCountsFetchesAndGivesTheSurface) {
    const HeightField f = random_field(16, 16, 21);
    const TextureLevels tl = build_texture_levels(f);
    // The `level` mode's sampler: HeightSampler given the levels and the sample's lambda.
    HeightSampler<double> ls(f, 0.05, 0.5, &tl, 1.25);
    const Vec2d uv{0.3, 0.7};
    EXPECT_EQ(ls.z(uv), 0.05 * (level_fetch(tl, uv, 1.25) - 0.5));
    EXPECT_EQ(ls.height(uv), level_fetch(tl, uv, 1.25));
    EXPECT_NE(ls.height(uv), HeightSampler<double>(f, 0.05, 0.5).height(uv));  // not level 0
    EXPECT_EQ(ls.fetches, 3);
    EXPECT_EQ(ls.lod(), 1.25);
    // Without levels it reads level 0 and still knows lambda (what pxh_lod() returns).
    HeightSampler<double> base(f, 0.05, 0.5, nullptr, 1.25);
    EXPECT_EQ(base.height(uv), HeightSampler<double>(f, 0.05, 0.5).height(uv));
    EXPECT_EQ(base.lod(), 1.25);
}

}  // namespace
}  // namespace pxh
