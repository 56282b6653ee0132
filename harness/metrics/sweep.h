// Sliding and shimmering of a row from its error vectors and those of a view dt degrees away
// (docs/conventions.md section 5.3; the statistics are sweep_metrics in metrics.h).
#pragma once
#include <vector>

#include "harness/core/vec.h"
#include "harness/metrics/row.h"

namespace pxh {

// sliding, shimmering, sweep_dt_deg; nothing when either view has no error vectors (a failed
// row). `lo` is the view at the smaller θ.
void add_sweep(const std::vector<Vec2d>& lo, const std::vector<Vec2d>& hi, double dt_deg,
               ResultRow& row);

}  // namespace pxh
