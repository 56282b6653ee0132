#include "harness/metrics/reference.h"

namespace pxh {

void add_reference_columns(const ReferenceInfo& ref, ResultRow& row) {
    row.set_text("ground_truth", ref.ground_truth);
    row.set("gt_cells_mean", ref.cells_mean);
    row.set("gt_agree_p50", ref.agreement.p50);
    row.set("gt_agree_p99", ref.agreement.p99);
    row.set("gt_agree_max", ref.agreement.max);
    row.set("gt_agree_frac_gt_0_5", ref.agreement.frac_gt_0_5);
    row.set("gt_on_filled", ref.on_filled);
    row.set("gt_residual_max", ref.residual_max);
}

}  // namespace pxh
