// Each component's columns, declared in the file that fills them (name, type, role, meaning,
// family, unit, direction, headline): harness/metrics/columns.cpp only places them in
// results.csv's order. A per-output metric declares its columns in its Metric instead
// (harness/metrics/metric.h); these are the ones whose place in results.csv predates that.
#pragma once
#include <vector>

#include "harness/metrics/columns.h"

namespace pxh {

// The short names the declarations use (`using namespace column_decl;` in a column list).
namespace column_decl {
inline constexpr ColumnType kText = ColumnType::text, kInt = ColumnType::integer,
                            kNum = ColumnType::number;
inline constexpr ColumnRole kKey = ColumnRole::key, kMeasured = ColumnRole::measured;
inline constexpr ColumnAxis kQuiet = ColumnAxis::quiet;
}  // namespace column_decl

std::vector<ColumnSpec> error_stats_columns();  // error_stats.cpp: err_*, frac_*, err_px_*
std::vector<ColumnSpec> fetches_columns();      // fetches.cpp: fetches_*
std::vector<ColumnSpec> timing_columns();       // timing.cpp: time*
std::vector<ColumnSpec> agreement_columns();    // agreement.cpp: cpu_diff_*, double_diff_*
std::vector<ColumnSpec> sweep_columns();        // sweep.cpp: sliding*, shimmering*
std::vector<ColumnSpec> image_columns();        // image_metrics.cpp: img_*
std::vector<ColumnSpec> reference_columns();    // reference.cpp: gt_*, ground_truth, excluded

}  // namespace pxh
