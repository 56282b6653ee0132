// The Mann-Whitney U test `pxh compare` decides timing noise with, against values computed by
// hand, scipy's documented example, and a brute-force enumeration of every split of the pooled
// sample (an implementation that shares nothing with the recurrence); and the repeats cells.
#include "harness/metrics/timing_stats.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

namespace {

using pxh::mann_whitney_u;

TEST(TimingStats, ExactPValuesByHand) {
    // Fully separated: U = 0, and only 2 of the C(n1+n2, n1) orderings are this extreme.
    auto t = mann_whitney_u({1, 2, 3}, {4, 5, 6});
    EXPECT_TRUE(t.exact);
    EXPECT_DOUBLE_EQ(t.u, 0);
    EXPECT_DOUBLE_EQ(t.p, 2.0 / 20);
    t = mann_whitney_u({6, 7, 8, 9, 10}, {1, 2, 3, 4, 5});
    EXPECT_DOUBLE_EQ(t.u, 25);
    EXPECT_DOUBLE_EQ(t.p, 2.0 / 252);
    // One pair out of order (U = 1): U <= 1 in 2 of the 70 orderings of 4 + 4, each tail.
    t = mann_whitney_u({1, 2, 3, 5}, {4, 6, 7, 8});
    EXPECT_DOUBLE_EQ(t.u, 1);
    EXPECT_DOUBLE_EQ(t.p, 4.0 / 70);
    // scipy.stats.mannwhitneyu's documented example (Conover): U1 = 17, p = 0.1111 (exact).
    t = mann_whitney_u({19, 22, 16, 29, 24}, {20, 11, 17, 12});
    EXPECT_DOUBLE_EQ(t.u, 17);
    EXPECT_NEAR(t.p, 1.0 / 9, 1e-12);
    // The same samples: nothing to tell apart.
    t = mann_whitney_u({1, 2, 3, 4}, {1, 2, 3, 4});
    EXPECT_DOUBLE_EQ(t.u, 8);
    EXPECT_DOUBLE_EQ(t.p, 1);
}

// Every split of the pooled values into n1 + n2: the share whose U is at least as far from
// n1 n2 / 2 as the observed one is the exact two-sided p-value.
double brute_force_p(const std::vector<double>& a, const std::vector<double>& b) {
    std::vector<double> pooled(a);
    pooled.insert(pooled.end(), b.begin(), b.end());
    const size_t n = pooled.size(), n1 = a.size();
    auto u_of = [&](const std::vector<bool>& in_a) {
        double u = 0;
        for (size_t i = 0; i < n; ++i)
            for (size_t j = 0; j < n; ++j)
                if (in_a[i] && !in_a[j])
                    u += pooled[i] > pooled[j] ? 1 : pooled[i] == pooled[j] ? 0.5 : 0;
        return u;
    };
    std::vector<bool> observed(n, false);
    std::fill(observed.begin(), observed.begin() + long(n1), true);
    const double mid = double(n1 * b.size()) / 2, dev = std::abs(u_of(observed) - mid);
    std::vector<bool> mask(n, false);
    std::fill(mask.end() - long(n1), mask.end(), true);
    double extreme = 0, total = 0;
    do {
        ++total;
        extreme += std::abs(u_of(mask) - mid) >= dev - 1e-9;
    } while (std::next_permutation(mask.begin(), mask.end()));
    return extreme / total;
}

TEST(TimingStats, ExactMatchesBruteForce) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> d(0, 1);
    for (size_t n1 : {1, 2, 3, 5, 6})
        for (size_t n2 : {1, 4, 5, 7}) {
            std::vector<double> a(n1), b(n2);
            for (auto& x : a) x = d(rng) + 0.3;  // shifted: a range of p-values
            for (auto& x : b) x = d(rng);
            const auto t = mann_whitney_u(a, b);
            EXPECT_TRUE(t.exact);
            EXPECT_NEAR(t.p, brute_force_p(a, b), 1e-12) << n1 << " vs " << n2;
        }
}

// Equal repeats (timer ticks) keep the p-value exact: the permutation distribution given the
// tie groups, against the brute-force enumeration (ties counted 1/2 there too).
TEST(TimingStats, ExactWithTiesMatchesBruteForce) {
    // a = {1, 1, 2}, b = {2, 3, 3}: U = 0.5 (the 2 = 2 pair counts half). Of the 20 splits,
    // |U - 4.5| >= 4 for U = 0.5 (the observed one: {1, 1, 2} with either 2) and U = 8.5
    // (mirror), 2 splits each: p = 4 / 20. (scipy's normal approximation says 0.110.)
    auto t = mann_whitney_u({1, 1, 2}, {2, 3, 3});
    EXPECT_TRUE(t.exact);
    EXPECT_DOUBLE_EQ(t.u, 0.5);
    EXPECT_DOUBLE_EQ(t.p, 4.0 / 20);
    EXPECT_NEAR(t.p, brute_force_p({1, 1, 2}, {2, 3, 3}), 1e-12);
    // 5 + 5 timer-tick repeats, ties inside each sample only, fully separated: as without ties,
    // 2 / 252 (what pxh compare prints for a shader slower in every frame).
    t = mann_whitney_u({9, 9, 9.5, 10, 10}, {0.04, 0.04, 0.05, 0.05, 0.05});
    EXPECT_DOUBLE_EQ(t.u, 25);
    EXPECT_DOUBLE_EQ(t.p, 2.0 / 252);
    // Random samples drawn from a few values (many ties, within and across the samples).
    std::mt19937 rng(11);
    std::uniform_int_distribution<int> d(0, 3);
    for (size_t n1 : {1, 2, 4, 5, 6})
        for (size_t n2 : {2, 3, 5, 7}) {
            std::vector<double> a(n1), b(n2);
            for (auto& x : a) x = d(rng) + (n1 % 2);  // shifted in some: a range of p-values
            for (auto& x : b) x = d(rng);
            const auto u = mann_whitney_u(a, b);
            EXPECT_NEAR(u.p, brute_force_p(a, b), 1e-12) << n1 << " vs " << n2;
        }
}

TEST(TimingStats, NormalApproximationForLargeSamples) {
    // Large samples (n = 50 > 40): no ties, sigma^2 = 625 / 12 * 51; a = 0..24,
    // b = 10.5..34.5: U = 105, p = erfc(((312.5 - 105) - 0.5) / sigma / sqrt 2).
    std::vector<double> a, b;
    for (int i = 0; i < 25; ++i) a.push_back(i), b.push_back(i + 10.5);
    auto t = mann_whitney_u(a, b);
    EXPECT_FALSE(t.exact);
    EXPECT_DOUBLE_EQ(t.u, 105);
    EXPECT_NEAR(t.p, 5.909644085596031e-05, 1e-15);
    // With ties (n = 50): a = 0..24, b = 15..39, so 15..24 are ten tie groups of two,
    // sum(t^3 - t) = 60.
    std::vector<double> bt;
    for (int i = 0; i < 25; ++i) bt.push_back(i + 15);
    t = mann_whitney_u(a, bt);
    EXPECT_FALSE(t.exact);
    // a > b pairs: a = 16..24 over b = 15..a-1: sum_{k=1}^{9} k = 45; ties a = b = 15..24: 10.
    EXPECT_DOUBLE_EQ(t.u, 45 + 0.5 * 10);
    // sigma^2 = 625 / 12 (51 - 60 / 2450); z = (312.5 - 50 - 0.5) / sigma.
    const double sigma = std::sqrt(625.0 / 12 * (51 - 60.0 / 2450));
    EXPECT_NEAR(t.p, std::erfc((312.5 - 50 - 0.5) / sigma / std::sqrt(2.0)), 1e-15);
    // All tied: no information at all.
    t = mann_whitney_u({2, 2, 2}, {2, 2});
    EXPECT_DOUBLE_EQ(t.p, 1);
    EXPECT_THROW(mann_whitney_u({}, {1}), std::invalid_argument);
}

TEST(TimingStats, TooFewRepeatsForAVerdict) {
    // 2 / C(n1 + n2, n1): 2 + 2 repeats can never reach p < 0.05, 4 + 4 can.
    EXPECT_DOUBLE_EQ(pxh::min_p_value(2, 2), 2.0 / 6);
    EXPECT_DOUBLE_EQ(pxh::min_p_value(3, 3), 2.0 / 20);
    EXPECT_DOUBLE_EQ(pxh::min_p_value(4, 4), 2.0 / 70);
    EXPECT_DOUBLE_EQ(pxh::min_p_value(1, 9), 2.0 / 10);
    EXPECT_DOUBLE_EQ(pxh::min_p_value(0, 5), 1);
    EXPECT_GE(pxh::min_p_value(3, 3), pxh::kTimingAlpha);
    EXPECT_LT(pxh::min_p_value(4, 4), pxh::kTimingAlpha);
    EXPECT_LT(pxh::min_p_value(5, 5), pxh::kTimingAlpha);  // the default timing_repeats
}

TEST(TimingStats, RepeatsCells) {
    const std::vector<double> v = {12.5, 0.1, 3e-7, 1234567.25};
    const std::string cell = pxh::format_repeats(v);
    EXPECT_EQ(cell, "12.5;0.1;3e-07;1234567.25");
    EXPECT_EQ(*pxh::parse_repeats(cell), v);
    EXPECT_TRUE(pxh::parse_repeats("")->empty());
    for (const char* bad : {"1;;2", "1;x", "1;", ";1", "1;-2", "1;inf", "nan", "1 ;2"})
        EXPECT_FALSE(pxh::parse_repeats(bad)) << bad;
}

}  // namespace
