// The timed repeats of a row (results.csv's time_repeats, in the row's time_unit: every
// repeat, ';'-separated, in the order measured) and the significance test `pxh compare` decides
// timing noise with: the two-sided Mann-Whitney U test (as Google Benchmark's tools/compare.py,
// which calls scipy.stats.mannwhitneyu): exact for small samples (up to kExactUMaxValues values
// in all), ties included (the exact permutation distribution given the tie groups: timer ticks
// make equal repeats common, and the normal approximation scipy falls back to there misstates
// p for 5 + 5 repeats), else the normal approximation with tie and continuity corrections.
#pragma once
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace pxh {

// "12.5;12.75;13" (round-trip precision, as results.csv writes numbers); "" for none.
std::string format_repeats(const std::vector<double>& v);
// The values of such a cell; nullopt when a value is not a finite number >= 0 (the caller names
// the file and line). "" is no repeats.
std::optional<std::vector<double>> parse_repeats(const std::string& cell);

struct UTest {
    double u = 0;        // U of the first sample: pairs (a_i > b_j), ties counted 1/2
    double p = 1;        // two-sided p-value
    bool exact = false;  // from the exact (permutation) null distribution: small samples
};
// Samples of up to this many values in all get the exact p-value.
constexpr size_t kExactUMaxValues = 40;
// Needs both samples non-empty (std::invalid_argument otherwise).
UTest mann_whitney_u(const std::vector<double>& a, const std::vector<double>& b);

// The smallest two-sided p-value samples of these sizes can give, 2 / C(n1 + n2, n1) (1 when
// either is empty): when it is not below the significance level, no data can show a change and
// the test says "too few repeats" instead of a verdict.
double min_p_value(size_t n1, size_t n2);

// The significance level `pxh compare` uses (as compare.py's default alpha).
constexpr double kTimingAlpha = 0.05;

}  // namespace pxh
