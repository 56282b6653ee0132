// `pxh report DIR` and `pxh check DIR --thresholds FILE`: consumers of results.csv only.
#pragma once
#include <string>

namespace pxh {

// Writes DIR/report/: summary.csv/.md/.tex (per method setting and angle band), budget.md/.tex
// (cheapest method under error budgets), data/*.csv (plot-ready numbers, Pareto fronts
// included), and the plots (PNG + SVG) drawn by harness/plot_report.py unless plots = false.
int run_report(const std::string& dir, bool plots);

// Checks every limit of a thresholds file against DIR/results.csv; prints a table.
// Returns 0 if all pass, 1 if any fails; throws InputError (exit 2) on a malformed file or a
// limit that matches no row.
int run_check(const std::string& dir, const std::string& thresholds_file);

}  // namespace pxh
