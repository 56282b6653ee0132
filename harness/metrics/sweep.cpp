#include "harness/metrics/sweep.h"

#include "harness/metrics/metrics.h"

namespace pxh {

void add_sweep(const std::vector<Vec2d>& lo, const std::vector<Vec2d>& hi, double dt_deg,
               ResultRow& row) {
    if (lo.empty() || hi.empty()) return;
    const SweepMetrics sm =
        sweep_metrics(lo, hi, dt_deg, int(row.num("width")), int(row.num("height")));
    row.set("sliding", sm.sliding);
    row.set("shimmering", sm.shimmering);
    row.set("sweep_dt_deg", dt_deg);
}

}  // namespace pxh
