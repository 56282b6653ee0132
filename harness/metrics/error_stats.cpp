// err_*, frac_*, nonfinite (docs/conventions.md sections 5.1-5.2) and excluded.
#include <cmath>

#include "harness/metrics/metric.h"
#include "harness/metrics/metrics.h"

namespace pxh {

void add_error_stats(const MetricInput& in, ResultRow& row) {
    std::vector<double> mag;
    const std::vector<Vec2d>& uv = in.out.uv;
    mag.reserve(uv.size());
    long long excluded = 0;
    for (size_t k = 0; k < uv.size(); ++k) {
        if (in.exclude && (*in.exclude)[k]) {
            ++excluded;
            continue;
        }
        const Vec2d e = texel_error(uv[k], in.gt.uv[k], in.width, in.height);
        mag.push_back(std::hypot(e.x, e.y));
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
}

}  // namespace pxh
