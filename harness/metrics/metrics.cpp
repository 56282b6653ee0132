#include "harness/metrics/metrics.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace pxh {

static double wrap_half(double e) { return e - std::floor(e + 0.5); }

// u - floor(u): the position inside its tile, whatever the tile's index; exact for u >= 0 and
// u <= -1 (floor(u) is 0, or within a factor of two of u), within an ulp of 1 + u in (-1, 0).
static double in_tile(double u) { return u - std::floor(u); }

Vec2d texel_error(Vec2d uv_method, Vec2d uv_true, int width, int height) {
    if (!std::isfinite(uv_method.x) || !std::isfinite(uv_method.y) || !std::isfinite(uv_true.x) ||
        !std::isfinite(uv_true.y))
        return {NAN, NAN};
    // Each uv wrapped into its tile before the difference: uv_method - uv_true rounds away the
    // position inside the tile once the two lie many tiles apart (a uv of 1e16 minus 0.3 is
    // 1e16, whose wrapped error would read 0), and the tiled texture shows the same texel at
    // both anyway.
    const double ex = in_tile(uv_method.x) - in_tile(uv_true.x);
    const double ey = in_tile(uv_method.y) - in_tile(uv_true.y);
    return {wrap_half(ex) * width, wrap_half(ey) * height};
}

double percentile_sorted(const std::vector<double>& s, double q) {
    const double pos = q * double(s.size() - 1);
    const size_t i = size_t(std::floor(pos));
    if (i + 1 >= s.size()) return s.back();
    const double f = pos - double(i);
    return s[i] + (s[i + 1] - s[i]) * f;
}

std::vector<double> percentiles_of(std::vector<double>& v, const std::vector<double>& qs) {
    std::vector<double> out;
    out.reserve(qs.size());
    const size_t n = v.size();
    if (!std::is_sorted(qs.begin(), qs.end()))
        throw std::logic_error("percentiles_of: the quantiles must be ascending");
    // v is partitioned at `from`: everything in [0, from) is at most everything in [from, n),
    // and the order statistics taken so far (at from - 1, and from - 2 after a `hi`) are in
    // their sorted places; the next ones, at ranks >= from, are selected from [from, n)
    size_t from = 0;
    auto at = [&](size_t i) {  // the i-th smallest, put in its place
        if (i >= from) {
            std::nth_element(v.begin() + long(from), v.begin() + long(i), v.end());
            from = i + 1;
        }
        return v[i];
    };
    for (double q : qs) {
        const double pos = q * double(n - 1);
        const size_t i = size_t(std::floor(pos));
        if (i + 1 >= n) {
            out.push_back(at(n - 1));
            continue;
        }
        const double lo = at(i);
        // the next order statistic: the least of what lies above i (put at i + 1)
        if (i + 1 >= from) {
            std::iter_swap(v.begin() + long(i + 1),
                           std::min_element(v.begin() + long(i + 1), v.end()));
            from = i + 2;
        }
        const double hi = v[i + 1];
        const double f = pos - double(i);
        out.push_back(lo + (hi - lo) * f);
    }
    return out;
}

SweepMetrics sweep_metrics(const std::vector<Vec2d>& e0, const std::vector<Vec2d>& e1, double step,
                           int width, int height) {
    SweepMetrics m;
    const size_t n = std::min(e0.size(), e1.size());
    std::vector<Vec2d> d;
    d.reserve(n);
    for (size_t k = 0; k < n; ++k) {
        double dx = e1[k].x - e0[k].x, dy = e1[k].y - e0[k].y;
        if (!std::isfinite(dx) || !std::isfinite(dy)) continue;
        dx -= width * std::floor(dx / width + 0.5);  // an error crossing the wrap is one tile off
        dy -= height * std::floor(dy / height + 0.5);
        d.push_back({dx, dy});
    }
    if (d.empty() || !(step > 0)) return m;
    double mx = 0, my = 0;
    for (const Vec2d& v : d) {
        mx += v.x;
        my += v.y;
    }
    mx /= double(d.size());
    my /= double(d.size());
    double spread = 0;
    for (const Vec2d& v : d) spread += std::hypot(v.x - mx, v.y - my);
    m.sliding = std::hypot(mx, my) / step;
    m.shimmering = spread / double(d.size()) / step;
    return m;
}

ErrorStats error_stats(const std::vector<double>& magnitudes) {
    ErrorStats st;
    std::vector<double> v;
    v.reserve(magnitudes.size());
    for (double m : magnitudes) {
        if (std::isfinite(m)) v.push_back(m);
        else ++st.nonfinite;
    }
    st.count = (long long)v.size();
    if (v.empty()) {
        st.mean = st.rms = st.p50 = st.p95 = st.p99 = st.max = NAN;
        st.frac_gt_0_5 = st.frac_gt_1 = NAN;
        return st;
    }
    double sum = 0, sum2 = 0;
    long long gt05 = 0, gt1 = 0;
    for (double m : v) {  // fixed order: the sums do not depend on threads
        sum += m;
        sum2 += m * m;
        gt05 += m > 0.5;
        gt1 += m > 1.0;
    }
    const double n = double(v.size());
    st.mean = sum / n;
    st.rms = std::sqrt(sum2 / n);
    st.frac_gt_0_5 = double(gt05) / n;
    st.frac_gt_1 = double(gt1) / n;
    const std::vector<double> p = percentiles_of(v, {0.50, 0.95, 0.99, 1.0});
    st.p50 = p[0];
    st.p95 = p[1];
    st.p99 = p[2];
    st.max = p[3];
    return st;
}

}  // namespace pxh
