// `pxh compare BASE NEW`: two runs' results.csv, rows matched by their keys, the change of the
// error metrics, fetches and timings per row and per method setting and theta band, rows found
// in one run only, and an optional gate (--fail-on) for CI. The verdict comes first; timings
// change only when a two-sided Mann-Whitney U test over the rows' timed repeats says so
// (harness/metrics/timing_stats.h) over time_repeats, Holm-corrected over every tested row of
// the comparison (the false-alarm rate is the comparison's, 5%, not each row's). BASE is kept as
// compact records by key and NEW streamed past it: memory grows with BASE's keys, not with what the
// rows hold.
#pragma once
#include <ostream>
#include <string>
#include <vector>

namespace pxh {

// One --fail-on entry: column=+5% (relative to the base value) or column=+0.01 (absolute).
// A row regresses when new - base > the allowance (so +0 allows no increase at all).
struct CompareTolerance {
    std::string column;
    double amount = 0;
    bool relative = false;
};

// "err_p95=+5%,err_mean=+0.01,fetches_mean=+0": each column must be a measured numeric
// column of results.csv; InputError("--fail-on", ...) otherwise.
std::vector<CompareTolerance> parse_fail_on(const std::string& spec);

struct CompareOptions {
    bool markdown = false;
    std::vector<std::string> notes;  // lines printed under the verdict (the folders' checks)
    bool common = false;  // only the rows both runs have (the others counted, not a regression)
    std::vector<CompareTolerance> fail_on;  // empty: report only, exit 0
    std::vector<double> band_edges;         // theta bands (empty: the report's default)
    std::string junit, json;  // --junit FILE, --json FILE: the verdict for CI (report/verdict.h)
    // --only KEY=V,...: only the rows of both runs that match (pxh run --only's keys and
    // syntax, harness/experiment/only_rows.h); the others are left out of everything, counted.
    std::string only;
    // --pair NEW=BASE: NEW's rows of method NEW are matched with BASE's rows of method BASE (a
    // plug-in with the preset it reproduces), their params left out of the match (each side
    // then has one row per remaining key); both are named "NEW=BASE" in the report.
    std::vector<std::pair<std::string, std::string>> pairs;
};

// "NEW=BASE" as a pair of method names; InputError("--pair", ...) otherwise.
std::pair<std::string, std::string> parse_pair(const std::string& spec);

// Writes the comparison to `out`; returns the exit status: 0, or 1 when --fail-on is given and
// a matched row regresses beyond it (time: only when its repeats show it slower, or
// when there are too few repeats to say), a row that was ok failed, or (without `common`) a base
// row is missing from NEW. Times are compared between rows of the same time_unit only. Bad
// input (no results.csv, a malformed one, two rows with the same keys, a matched row on another
// field size, ground truth or time_unit) is an InputError naming the file and line. So is a
// comparison in which no row matched (with or without --common, gate or not): it names the keys
// whose values differ between the runs ("samples 64 vs 32"); a gate over nothing never passes.
// The regressions are listed largest change first (relative to the base value).
int run_compare(const std::string& base_dir, const std::string& new_dir, const CompareOptions& opt,
                std::ostream& out);

}  // namespace pxh
