#include "harness/metrics/agreement.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "harness/metrics/column_groups.h"
#include "harness/metrics/metrics.h"

namespace pxh {

OutputDiff compare_uv(const std::vector<Vec2d>& uv_a, const std::vector<int>& fetches_a,
                      const std::vector<Vec2d>& uv_b, const std::vector<int>& fetches_b, int width,
                      int height, const std::vector<uint8_t>* inside) {
    OutputDiff r;
    const size_t n = std::min(uv_a.size(), uv_b.size());
    std::vector<double> d;
    d.reserve(n);
    size_t worst_at = 0;  // index in d of the worst sample
    const bool masked = inside && inside->size() == n;
    for (size_t k = 0; k < n; ++k) {
        if (masked && !(*inside)[k]) continue;
        const bool a_none = !std::isfinite(uv_a[k].x) || !std::isfinite(uv_a[k].y);
        const bool b_none = !std::isfinite(uv_b[k].x) || !std::isfinite(uv_b[k].y);
        if (a_none && b_none) {  // both discarded (or both non-finite): they agree; counted
            ++r.skipped;
            continue;
        }
        const Vec2d e = texel_error(uv_a[k], uv_b[k], width, height);
        d.push_back(std::isfinite(e.x) ? std::hypot(e.x, e.y) : INFINITY);
        r.decision_mismatch += fetches_a[k] != fetches_b[k];
        if (r.worst < 0 || d.back() > d[size_t(worst_at)]) {
            r.worst = (long long)k;
            worst_at = d.size() - 1;
        }
        if (r.first.size() < kFirstDiffs &&
            (!(d.back() <= kDiffShown) || fetches_a[k] != fetches_b[k]))
            r.first.push_back(k);
    }
    for (size_t k : r.first) {
        char buf[160];
        std::snprintf(buf, sizeof buf, "%zu: %.7g %.7g | %.7g %.7g fetches %d | %d", k, uv_a[k].x,
                      uv_a[k].y, uv_b[k].x, uv_b[k].y, fetches_a[k], fetches_b[k]);
        r.first_text += (r.first_text.empty() ? "" : "; ") + std::string(buf);
    }
    if (d.empty()) return r;
    double sum = 0;
    for (double x : d) sum += x;
    r.mean = sum / double(d.size());
    const std::vector<double> p = percentiles_of(d, {0.95, 0.999, 1.0});
    r.p95 = p[0];
    r.p999 = p[1];
    r.max = p[2];
    return r;
}

OutputDiff compare_outputs(const MethodOutput& a, const MethodOutput& b, int width, int height,
                           const std::vector<uint8_t>* inside) {
    return compare_uv(a.uv, a.fetches, b.uv, b.fetches, width, height, inside);
}

double depth_diff_p999(const std::vector<double>& a, const std::vector<double>& b,
                       const std::vector<uint8_t>* inside) {
    if (a.empty() || a.size() != b.size()) return NAN;
    const bool masked = inside && inside->size() == a.size();
    std::vector<double> d;
    d.reserve(a.size());
    for (size_t k = 0; k < a.size(); ++k) {
        if (masked && !(*inside)[k]) continue;
        if (!std::isfinite(a[k]) && !std::isfinite(b[k])) continue;  // no uv in either
        d.push_back(std::isfinite(a[k] - b[k]) ? std::abs(a[k] - b[k]) : INFINITY);
    }
    if (d.empty()) return NAN;
    return percentiles_of(d, {0.999})[0];
}

void add_agreement(ResultRow& row, const MethodOutput& glsl, const MethodOutput& cpu_float,
                   int width, int height, const std::vector<uint8_t>* inside) {
    add_backend_agreement(compare_outputs(glsl, cpu_float, width, height, inside), row);
    row.set("depth_cpu_diff_p999", depth_diff_p999(glsl.depth, cpu_float.depth, inside));
}

void add_backend_agreement(const OutputDiff& d, ResultRow& row) {
    row.set("cpu_diff_max", d.max);
    row.set("cpu_diff_p999", d.p999);
    row.set("cpu_diff_mean", d.mean);
    row.set("cpu_diff_p95", d.p95);
    row.set("cpu_diff_worst_sample", d.worst < 0 ? NAN : double(d.worst));
    row.set_text("cpu_diff_first", d.first_text);
    row.set("decision_mismatch", double(d.decision_mismatch));
    row.set("cpu_diff_skipped", double(d.skipped));
}

void add_precision_agreement(const OutputDiff& d, ResultRow& row) {
    row.set("double_diff_max", d.max);
    row.set("double_diff_p999", d.p999);
    row.set("double_diff_skipped", double(d.skipped));
}

ErrorStats reference_agreement(const std::vector<Vec2d>& a, const std::vector<Vec2d>& b, int width,
                               int height) {
    if (a.size() != b.size()) throw std::logic_error("reference_agreement: hit counts differ");
    std::vector<double> gap(a.size());
    for (size_t k = 0; k < a.size(); ++k) {
        const Vec2d e = texel_error(a[k], b[k], width, height);
        gap[k] = std::hypot(e.x, e.y);
    }
    return error_stats(gap);
}

// Agreement between backends and precisions.
// Declared here, by the code that fills them; harness/metrics/columns.cpp places them in
// results.csv's order.
std::vector<ColumnSpec> agreement_columns() {
    using namespace column_decl;
    return {
        ColumnSpec{"cpu_diff_max", kNum, kMeasured, "GLSL: max |uv_glsl - uv_cpu_float| (texels)"}
            .in("agreement", "texels"),
        ColumnSpec{"cpu_diff_p999", kNum, kMeasured,
                   "GLSL: p99.9 |uv_glsl - uv_cpu_float| (texels)"}
            .in("agreement", "texels")
            .lead(),
        ColumnSpec{"cpu_diff_mean", kNum, kMeasured, "GLSL: mean |uv_glsl - uv_cpu_float| (texels)"}
            .in("agreement", "texels"),
        ColumnSpec{"cpu_diff_p95", kNum, kMeasured, "GLSL: p95 |uv_glsl - uv_cpu_float| (texels)"}
            .in("agreement", "texels"),
        ColumnSpec{"cpu_diff_worst_sample", kInt, kMeasured,
                   "GLSL: the sample with the largest |uv_glsl - uv_cpu_float| (index j N + i, "
                   "the first of equal ones)"}
            .in("agreement", "sample index", Better::none),
        ColumnSpec{"cpu_diff_first", kText, kMeasured,
                   "GLSL: the first samples (at most 8, in sample order) more than 1e-3 texel "
                   "from the CPU float twin or with another fetch count: 'k: GLSL uv | CPU uv "
                   "fetches GLSL | CPU', '; ' between them"},
        ColumnSpec{"decision_mismatch", kInt, kMeasured,
                   "GLSL: samples whose fetch count differs from CPU"}
            .in("agreement", "samples"),
        ColumnSpec{
            "cpu_diff_skipped", kInt, kMeasured,
            "GLSL: samples neither twin answered (both discarded or non-finite): left out of "
            "cpu_diff_* and decision_mismatch"}
            .in("agreement", "samples", Better::none),
        ColumnSpec{
            "depth_cpu_diff_p999", kNum, kMeasured,
            "GLSL: p99.9 |depth written - the CPU float twin's| (tiles, read back from the depth "
            "target)"}
            .in("agreement", "tiles"),
        ColumnSpec{"double_diff_max", kNum, kMeasured,
                   "CPU float: max |uv_float - uv_double| (texels)"}
            .in("agreement", "texels"),
        ColumnSpec{"double_diff_p999", kNum, kMeasured,
                   "CPU float: p99.9 |uv_float - uv_double| (texels)"}
            .in("agreement", "texels")
            .lead(),
        ColumnSpec{"double_diff_skipped", kInt, kMeasured,
                   "CPU float: samples neither precision answered: left out of double_diff_*"}
            .in("agreement", "samples", Better::none),
    };
}

}  // namespace pxh
