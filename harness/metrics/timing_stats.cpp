#include "harness/metrics/timing_stats.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "harness/core/params.h"
#include "harness/metrics/row.h"

namespace pxh {

std::string format_repeats(const std::vector<double>& v) {
    std::string out;
    for (size_t i = 0; i < v.size(); ++i) out += (i ? ";" : "") + format_cell_number(v[i]);
    return out;
}

std::optional<std::vector<double>> parse_repeats(const std::string& cell) {
    std::vector<double> out;
    if (cell.empty()) return out;
    size_t start = 0;
    while (true) {
        const size_t end = cell.find(';', start);
        const auto v =
            parse_number(cell.substr(start, end == std::string::npos ? end : end - start));
        if (!v || !std::isfinite(*v) || *v < 0) return std::nullopt;
        out.push_back(*v);
        if (end == std::string::npos) return out;
        start = end + 1;
    }
}

double min_p_value(size_t n1, size_t n2) {
    if (n1 == 0 || n2 == 0) return 1;
    // C(n1 + n2, n1) as a double (exact far beyond any repeat count that matters).
    double c = 1;
    const size_t k = std::min(n1, n2);
    for (size_t i = 1; i <= k; ++i) c = c * double(n1 + n2 - k + i) / double(i);
    return std::min(1.0, 2 / c);
}

namespace {

// The exact null distribution of U given the pooled sample's tie groups (the permutation
// distribution: every choice of which n1 of the n values form the first sample equally likely).
// A tie group of g values with midrank r contributes j r to the first sample's rank sum in
// C(g, j) of the choices; counts[k][s] accumulates, group by group, the number of choices of k
// values whose doubled rank sum is s (doubled: midranks are multiples of 1/2). Without ties this
// is Mann & Whitney's (1947) distribution; with ties it is the exact conditional one (as
// StatXact's), which a normal approximation only approaches for large samples.
// Returns, for each doubled U = 0 .. 2 n1 n2, the number of choices giving it.
std::vector<double> doubled_u_counts(const std::vector<size_t>& groups, size_t n1) {
    size_t n = 0;
    for (size_t g : groups) n += g;
    const size_t s_max = n * (n + 1);  // twice the largest rank sum
    std::vector<std::vector<double>> counts(n1 + 1, std::vector<double>(s_max + 1, 0.0));
    counts[0][0] = 1;
    size_t first = 1;  // rank of the group's first value
    for (size_t g : groups) {
        const size_t twice_mid = 2 * first + g - 1;  // 2 (first + (first + g - 1)) / 2
        std::vector<std::vector<double>> next(n1 + 1, std::vector<double>(s_max + 1, 0.0));
        double binom = 1;  // C(g, j)
        for (size_t j = 0; j <= std::min(g, n1); ++j) {
            for (size_t k = 0; k + j <= n1; ++k)
                for (size_t s = 0; s + j * twice_mid <= s_max; ++s)
                    if (counts[k][s] != 0) next[k + j][s + j * twice_mid] += counts[k][s] * binom;
            binom = binom * double(g - j) / double(j + 1);
        }
        counts = std::move(next);
        first += g;
    }
    // U = R1 - n1 (n1 + 1) / 2, so 2U = 2 R1 - n1 (n1 + 1).
    const size_t offset = n1 * (n1 + 1);
    std::vector<double> out(2 * n1 * (n - n1) + 1, 0.0);
    for (size_t s = offset; s <= s_max; ++s)
        if (counts[n1][s] != 0) out[s - offset] += counts[n1][s];
    return out;
}

}  // namespace

UTest mann_whitney_u(const std::vector<double>& a, const std::vector<double>& b) {
    if (a.empty() || b.empty())
        throw std::invalid_argument("mann_whitney_u: both samples need at least one value");
    const size_t n1 = a.size(), n2 = b.size(), n = n1 + n2;
    UTest t;
    for (double x : a)
        for (double y : b) t.u += x > y ? 1.0 : x == y ? 0.5 : 0.0;
    // The pooled sample's tie groups, in order; sum of (g^3 - g) for the normal approximation.
    std::vector<double> pooled(a);
    pooled.insert(pooled.end(), b.begin(), b.end());
    std::sort(pooled.begin(), pooled.end());
    std::vector<size_t> groups;
    double tie_term = 0;
    for (size_t i = 0; i < n;) {
        size_t j = i;
        while (j < n && pooled[j] == pooled[i]) ++j;
        const double g = double(j - i);
        groups.push_back(j - i);
        tie_term += g * g * g - g;
        i = j;
    }
    const double mn = double(n1) * double(n2);
    if (groups.size() == 1) {
        t.p = 1;  // every value tied: nothing tells the samples apart
        return t;
    }
    if (n <= kExactUMaxValues) {
        // Two-sided: the share of choices whose U is at least as far from mn / 2 as the
        // observed one (with ties the distribution need not be symmetric).
        const std::vector<double> counts = doubled_u_counts(groups, n1);
        const double dev = std::abs(2 * t.u - mn);
        double total = 0, extreme = 0;
        for (size_t u2 = 0; u2 < counts.size(); ++u2) {
            total += counts[u2];
            if (std::abs(double(u2) - mn) >= dev) extreme += counts[u2];
        }
        t.exact = true;
        t.p = std::min(1.0, extreme / total);
        return t;
    }
    // Normal approximation: mean mn/2, variance mn/12 ((n + 1) - sum(t^3 - t) / (n (n - 1))),
    // with the continuity correction of 1/2 (scipy's default).
    const double var = mn / 12 * (double(n + 1) - tie_term / (double(n) * double(n - 1)));
    const double z = std::max(0.0, std::abs(t.u - mn / 2) - 0.5) / std::sqrt(var);
    t.p = std::min(1.0, std::erfc(z / std::sqrt(2.0)));
    return t;
}

}  // namespace pxh
