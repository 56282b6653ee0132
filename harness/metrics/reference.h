// The ground-truth columns of a view, on each of its rows: which reference the errors are
// against, what it cost, how far the two references disagree, and how many true hits lie
// on filled holes of a measured field.
#pragma once
#include <cmath>
#include <string>

#include "harness/metrics/metrics.h"
#include "harness/metrics/row.h"

namespace pxh {

struct ReferenceInfo {
    std::string ground_truth;   // exact | embree
    double cells_mean = NAN;    // exact tracer: cells per ray
    ErrorStats agreement;       // |hit_exact - hit_embree| over the samples (texels; NaN
                                //   when Embree did not run)
    double on_filled = NAN;     // fraction of true hits on a filled hole
    double residual_max = NAN;  // curved bases: the walk's max |g| at its hits (tiles)
};

// ground_truth, gt_cells_mean, gt_agree_p50/p99/max/frac_gt_0_5, gt_on_filled.
void add_reference_columns(const ReferenceInfo& ref, ResultRow& row);

}  // namespace pxh
