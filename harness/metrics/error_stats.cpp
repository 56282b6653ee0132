// err_*, frac_*, nonfinite (docs/conventions.md sections 5.1-5.2), excluded, samples_outside
// and the pixel error err_px_* (section 10: |J^-1 e_uv| with the sample's footprint J).
#include <cmath>

#include "harness/metrics/column_groups.h"
#include "harness/metrics/metric.h"
#include "harness/metrics/metrics.h"
#include "harness/scene/footprint.h"

namespace pxh {

namespace {

void add_error_stats(const MetricInput& in, ResultRow& row) {
    std::vector<double> mag, px;
    const std::vector<Vec2d>& uv = in.out.uv;
    mag.reserve(uv.size());
    const bool footprints = in.view && !in.view->J.empty();
    if (footprints) px.reserve(uv.size());
    long long excluded = 0, outside = 0;
    for (size_t k = 0; k < uv.size(); ++k) {
        if (!in.inside(k)) {
            ++outside;
            continue;
        }
        if (!in.truth_shows(k)) continue;  // curved bases: cover_extra_frac counts it
        if (in.out.discarded.size() == uv.size() && in.out.discarded[k])
            continue;  // samples_discarded (and on curved bases cover_missing_frac) count it
        if (in.exclude && (*in.exclude)[k]) {
            ++excluded;
            continue;
        }
        const Vec2d e = texel_error(uv[k], in.gt.uv[k], in.width, in.height);
        mag.push_back(std::hypot(e.x, e.y));
        if (footprints)  // the uv error (texels / size), through the pixel's footprint
            px.push_back(pixel_error(in.view->footprint(k),
                                     {e.x / double(in.width), e.y / double(in.height)}));
    }
    const ErrorStats st = error_stats(mag);
    row.set("err_mean", st.mean);
    row.set("err_rms", st.rms);
    row.set("err_p50", st.p50);
    row.set("err_p95", st.p95);
    row.set("err_p99", st.p99);
    row.set("err_max", st.max);
    row.set("frac_gt_0_5", st.frac_gt_0_5);
    row.set("frac_gt_1", st.frac_gt_1);
    row.set("nonfinite", double(st.nonfinite));
    row.set("samples_discarded", double(in.out.samples_discarded));
    row.set("excluded", double(excluded));
    row.set("samples_outside", double(outside));
    if (footprints) {  // NaN (a non-finite output) is counted in nonfinite above
        const ErrorStats p = error_stats(px);
        row.set("err_px_mean", p.mean);
        row.set("err_px_p50", p.p50);
        row.set("err_px_p95", p.p95);
        row.set("err_px_max", p.max);
    }
}

}  // namespace

// Its columns are in the table of harness/metrics/columns.cpp.
const Metric& error_stats_metric() {
    static const Metric m{"error_stats", add_error_stats};
    return m;
}

// The error statistics (texel and pixel error) this file computes.
// Declared here, by the code that fills them; harness/metrics/columns.cpp places them in
// results.csv's order.
std::vector<ColumnSpec> error_stats_columns() {
    using namespace column_decl;
    return {
        ColumnSpec{"err_mean", kNum, kMeasured, "mean texel error |e| over the finite samples"}
            .in("texel", "texels")
            .lead(),
        ColumnSpec{"err_rms", kNum, kMeasured, "root mean square texel error"}.in("texel",
                                                                                  "texels"),
        ColumnSpec{"err_p50", kNum, kMeasured, "median texel error"}.in("texel", "texels"),
        ColumnSpec{"err_p95", kNum, kMeasured, "95th-percentile texel error"}
            .in("texel", "texels")
            .lead(),
        ColumnSpec{"err_p99", kNum, kMeasured, "99th-percentile texel error"}.in("texel", "texels"),
        ColumnSpec{"err_max", kNum, kMeasured, "largest texel error"}.in("texel", "texels"),
        ColumnSpec{"frac_gt_0_5", kNum, kMeasured,
                   "fraction of finite samples more than 0.5 texel off"}
            .in("texel", "fraction"),
        ColumnSpec{"frac_gt_1", kNum, kMeasured, "fraction of finite samples more than 1 texel off"}
            .in("texel", "fraction"),
        ColumnSpec{"nonfinite", kInt, kMeasured,
                   "samples whose output is NaN/Inf, discards not included (left out above)"}
            .in("texel", "samples"),
        ColumnSpec{
            "samples_discarded", kInt, kMeasured,
            "samples the method discarded (a silhouette method's miss: GLSL `discard`, the C++ "
            "twin's NaN answer; a GLSL fragment left unwritten too); not in nonfinite, fetches "
            "not counted"}
            .in("coverage", "samples", Better::none),
        {"samples_outside", kInt, kMeasured,
         "pixels outside the view (V.z <= cos 89 deg), left out of every statistic"},
        ColumnSpec{"lod_mean", kNum, kMeasured, "mean of max(lambda, 0) over the inside pixels"}.in(
            "pixel", "level", Better::none),
        ColumnSpec{"err_px_mean", kNum, kMeasured, "mean pixel error |J^-1 e_uv| (screen pixels)"}
            .in("pixel", "pixels")
            .lead(),
        ColumnSpec{"err_px_p50", kNum, kMeasured, "median pixel error"}.in("pixel", "pixels"),
        ColumnSpec{"err_px_p95", kNum, kMeasured, "95th-percentile pixel error"}
            .in("pixel", "pixels")
            .lead(),
        ColumnSpec{"err_px_max", kNum, kMeasured, "largest pixel error"}.in("pixel", "pixels"),
    };
}

}  // namespace pxh
