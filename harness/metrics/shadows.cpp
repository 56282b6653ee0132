// shadow_err (fraction of samples whose hard shadow state is wrong) and shadow_soft_mae
// (mean |soft factor - true hard factor|), when a light was given.
#include <cmath>

#include "harness/metrics/metric.h"

namespace pxh {

namespace {

void add_shadow_errors(const MetricInput& in, ResultRow& row) {
    const MethodOutput& o = in.out;
    const size_t n = o.uv.size();
    if (in.gt.lit.empty() || o.shadow_hard.size() != n || n == 0) return;
    double wrong = 0, mae = 0, inside = 0;
    for (size_t k = 0; k < n; ++k) {
        if (!in.inside(k)) continue;
        ++inside;
        const double truth = in.gt.lit[k] ? 1.0 : 0.0;
        wrong += (o.shadow_hard[k] != truth);
        mae += std::abs(double(o.shadow_soft[k]) - truth);
    }
    row.set("shadow_err", inside ? wrong / inside : NAN);
    row.set("shadow_soft_mae", inside ? mae / inside : NAN);
}

}  // namespace

const Metric& shadows_metric() {
    static const Metric m{"shadows",
                          add_shadow_errors,
                          {ColumnSpec{"shadow_err", ColumnType::number, ColumnRole::measured,
                                      "fraction of samples whose hard shadow state is wrong"}
                               .in("shadow", "fraction")
                               .lead(),
                           ColumnSpec{"shadow_soft_mae", ColumnType::number, ColumnRole::measured,
                                      "mean |soft factor - true hard factor|"}
                               .in("shadow", "")
                               .lead()}};
    return m;
}

}  // namespace pxh
