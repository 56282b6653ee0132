// budget.md's perceptual ranking ([shading] runs: the flip_mean column): per camera view and
// band, the cheapest method setting whose image a viewer can hardly tell from the truth's,
// i.e. whose every series' mean flip_mean over its rows in the band is at most X, for each X of
// kFlipBudgets. Cheapest as the texel budgets rank (fewest fetches per sample); a setting with
// a failed row, a non-finite output or a row without flip_mean in the band meets no budget.
#pragma once
#include <string>
#include <vector>

#include "harness/report/report_data.h"

namespace pxh {

inline const std::vector<double> kFlipBudgets = {0.005, 0.01, 0.02, 0.05, 0.1};

// Whether some ok row has a flip_mean (the run had [shading]).
bool has_flip(const ReportData& d);

// The ranking's tables, one per view ("" view: the whole run), in Markdown and LaTeX, with
// their notes; empty strings when no row has a flip_mean.
struct PerceptualBudget {
    std::string markdown, latex;
};
PerceptualBudget perceptual_budget(const ReportData& d);

}  // namespace pxh
