// err_*, frac_*, nonfinite (docs/conventions.md sections 5.1-5.2), excluded, samples_outside
// and the pixel error err_px_* (section 10: |J^-1 e_uv| with the sample's footprint J).
#include <cmath>

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

}  // namespace pxh
