// `pxh report DIR` and `pxh check DIR --thresholds FILE`: consumers of results.csv only.
#pragma once
#include <string>
#include <vector>

namespace pxh {

struct ReportOptions {
    bool plots = true;                  // false: tables and data only (no matplotlib needed)
    std::vector<double> bands;          // angle band edges in degrees, ascending, in [0, 90],
                                        //   at least 2; empty = 0,30,60,75,85,90. Bands are
                                        //   [e_i, e_i+1), the last one closed [e_k-1, e_k].
    std::string budget_metric = "p95";  // the budget table's error: p95 | p99 (texels, mean
                                        //   over rows of err_p95 / err_p99) | frac_gt_1
                                        //   (mean fraction of samples more than 1 texel off)
    double figure_width = 7.0;          // inches: the figures' width (fonts stay 8 pt)
    std::string formats = "png,pdf";    // the figures' files: a comma list of png, pdf, svg
    bool accept_edited = false;         // for the caller's verify_results_folder (main.cpp
                                        //   verifies the folder before run_report; run_report
                                        //   itself does not read run.json)
};

// Writes DIR/report/: summary.csv/.md/.tex (per series and angle band; in .md/.tex a setting's
// series whose printed numbers agree are one row), fields.csv/.md and fields/FIELD.tex (the
// same per height field), legend.md/.tex (the LaTeX tables' compact labels), budget.md/.tex
// (cheapest method setting under error budgets), sweep.md and precision.md (when measured),
// failed.md (when rows failed: they are listed, and left out of every number), data/*.csv
// (plot-ready numbers, Pareto fronts included), and the plots (PNG + SVG) drawn by
// harness/plot_report.py unless plots = false. Prints every file it writes. Throws
// InputError (exit 2) on bad options or an unreadable results.csv.
int run_report(const std::string& dir, const ReportOptions& options);
int run_report(const std::string& dir, bool plots);  // default options but plots

// --formats: a comma list of png, pdf and svg, each at most once; anything else is an
// InputError naming --formats.
void parse_figure_formats(const std::string& text);

// --figure-width: "single" (3.5 in, one column of a two-column paper), "double" (7 in, the
// full text width) or a number of inches in [2, 20]; anything else is an InputError.
double parse_figure_width(const std::string& text);

// Checks every limit of a thresholds file against DIR/results.csv; prints a table, and under
// each failing limit the row that fails it. A failed row (status != ok) fails every limit that
// matches it. Returns 0 if all pass, 1 if any fails; throws InputError (exit 2, FILE:LINE of
// the offending key) on a malformed file, a filter value no row has, or a limit that matches
// no row.
// --junit FILE / --json FILE also write the verdict (harness/report/verdict.h): a testcase per
// limit, failures with the worst value and the rows.
struct CheckOptions {
    std::string junit, json;
};
int run_check(const std::string& dir, const std::string& thresholds_file,
              const CheckOptions& options = {});

}  // namespace pxh
