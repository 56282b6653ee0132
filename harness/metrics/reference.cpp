#include "harness/metrics/reference.h"

#include <cmath>

#include "harness/metrics/column_groups.h"

namespace pxh {

void add_reference_columns(const ReferenceInfo& ref, ResultRow& row) {
    row.set_text("ground_truth", ref.ground_truth);
    row.set("gt_cells_mean", ref.cells_mean);
    row.set("gt_agree_p50", ref.agreement.p50);
    row.set("gt_agree_p99", ref.agreement.p99);
    row.set("gt_agree_max", ref.agreement.max);
    row.set("gt_agree_frac_gt_0_5", ref.agreement.frac_gt_0_5);
    row.set("gt_agree_rays", ref.agreement.count > 0 ? double(ref.agreement.count) : std::nan(""));
    row.set("gt_on_filled", ref.on_filled);
    row.set("gt_residual_max", ref.residual_max);
}

// The view's references (excluded: counted by error_stats, from the truth's filled holes).
// Declared here, by the code that fills them; harness/metrics/columns.cpp places them in
// results.csv's order.
std::vector<ColumnSpec> reference_columns() {
    using namespace column_decl;
    return {
        ColumnSpec{"gt_on_filled", kNum, kMeasured,
                   "measured fields: fraction of true hits on a filled hole"}
            .in("truth", "fraction", Better::none),
        ColumnSpec{"excluded", kInt, kMeasured, "samples left out of err_* (exclude_filled = true)"}
            .in("truth", "samples", Better::none),
        ColumnSpec{"gt_cells_mean", kNum, kMeasured,
                   "exact tracer: cells per ray given to the solver"}
            .in("truth", "cells/ray", Better::none),
        {"ground_truth", kText, kKey, "exact | embree: the reference of the err_* columns", kQuiet},
        ColumnSpec{"gt_agree_p50", kNum, kMeasured,
                   "|hit_exact - hit_check| median (texels; the check: Embree on the plane, the "
                   "walk at half "
                   "the step on a curved base; over the rays gt_agree_rays counts)"}
            .in("truth", "texels"),
        ColumnSpec{"gt_agree_p99", kNum, kMeasured,
                   "|hit_exact - hit_check| 99th percentile (texels; over gt_agree_rays rays)"}
            .in("truth", "texels")
            .lead(),
        ColumnSpec{"gt_agree_max", kNum, kMeasured,
                   "|hit_exact - hit_check| max (texels; over gt_agree_rays rays)"}
            .in("truth", "texels"),
        ColumnSpec{"gt_agree_frac_gt_0_5", kNum, kMeasured,
                   "fraction of samples where they differ > 0.5 texel"}
            .in("truth", "fraction"),
        ColumnSpec{"gt_agree_rays", kInt, kMeasured,
                   "rays the gt_agree_* columns compare (both references hit; truth_check picks "
                   "the rays: every one on the plane, one in 16 on a curved base by default)"}
            .in("truth", "rays", Better::none),
        ColumnSpec{
            "gt_residual_max", kNum, kMeasured,
            "curved bases: max |height above the base - s (h - b)| at the true hits (tiles); the "
            "gt_agree_* columns there compare the pyramid tracer with the walk at half the step "
            "(truth_check)"}
            .in("truth", "tiles")
            .lead(),
    };
}

}  // namespace pxh
