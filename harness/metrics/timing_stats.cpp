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

// The exact null distribution of U for sizes m, n: how many of the C(m + n, m) orderings give
// each U = 0 .. m n (Mann & Whitney 1947: N(m, n, u) = N(m - 1, n, u - n) + N(m, n - 1, u)).
std::vector<double> u_counts(size_t m, size_t n) {
    // row[j] = the distribution for (i, j), for the current i.
    std::vector<std::vector<double>> row(n + 1);
    for (size_t j = 0; j <= n; ++j) row[j] = {1.0};  // i = 0: U = 0 only
    for (size_t i = 1; i <= m; ++i) {
        std::vector<std::vector<double>> next(n + 1);
        next[0] = {1.0};  // j = 0: U = 0 only
        for (size_t j = 1; j <= n; ++j) {
            std::vector<double> d(i * j + 1, 0.0);
            const auto& up = row[j];         // (i - 1, j): shifted by j
            const auto& left = next[j - 1];  // (i, j - 1)
            for (size_t u = 0; u < up.size(); ++u) d[u + j] += up[u];
            for (size_t u = 0; u < left.size(); ++u) d[u] += left[u];
            next[j] = std::move(d);
        }
        row = std::move(next);
    }
    return row[n];
}

}  // namespace

UTest mann_whitney_u(const std::vector<double>& a, const std::vector<double>& b) {
    if (a.empty() || b.empty())
        throw std::invalid_argument("mann_whitney_u: both samples need at least one value");
    const size_t n1 = a.size(), n2 = b.size(), n = n1 + n2;
    UTest t;
    bool ties = false;
    for (double x : a)
        for (double y : b) t.u += x > y ? 1.0 : x == y ? 0.5 : 0.0;
    // Ranks of the pooled sample, for the tie correction: sum of (t^3 - t) over tie groups.
    std::vector<double> pooled(a);
    pooled.insert(pooled.end(), b.begin(), b.end());
    std::sort(pooled.begin(), pooled.end());
    double tie_term = 0;
    for (size_t i = 0; i < n;) {
        size_t j = i;
        while (j < n && pooled[j] == pooled[i]) ++j;
        const double g = double(j - i);
        if (g > 1) ties = true;
        tie_term += g * g * g - g;
        i = j;
    }
    const double mn = double(n1) * double(n2);
    // The smaller tail of U's distribution: U and mn - U are equally likely under the null.
    const double u_low = std::min(t.u, mn - t.u);
    if (!ties && n <= 40) {
        const std::vector<double> counts = u_counts(n1, n2);
        double total = 0, below = 0;
        for (size_t u = 0; u < counts.size(); ++u) {
            total += counts[u];
            if (double(u) <= u_low) below += counts[u];
        }
        t.exact = true;
        t.p = std::min(1.0, 2 * below / total);
        return t;
    }
    // Normal approximation: mean mn/2, variance mn/12 ((n + 1) - sum(t^3 - t) / (n (n - 1))),
    // with the continuity correction of 1/2 (scipy's default).
    const double var = mn / 12 * (double(n + 1) - tie_term / (double(n) * double(n - 1)));
    if (!(var > 0)) {
        t.p = 1;  // every value tied: nothing tells the samples apart
        return t;
    }
    const double z = std::max(0.0, std::abs(t.u - mn / 2) - 0.5) / std::sqrt(var);
    t.p = std::min(1.0, std::erfc(z / std::sqrt(2.0)));
    return t;
}

}  // namespace pxh
