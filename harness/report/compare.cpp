// pxh compare (harness/report/compare.h): BASE read, NEW streamed past it, the rows of BASE
// missing from NEW, the verdict; the parts are in compare_parts.h.
#include "harness/report/compare.h"

#include <algorithm>

#include "harness/core/error.h"
#include "harness/report/compare_parts.h"

namespace pxh {
namespace {

using namespace compare_detail;

// BASE's rows that no row of NEW matched, in file order.
Capped missing_from_new(const Base& base) {
    Capped only_base;
    std::vector<std::pair<size_t, const std::string*>> missing;  // by line: file order
    for (const auto& [key, i] : base.by_key)
        if (!base.rows[i].matched) missing.push_back({base.rows[i].line, &key});
    std::sort(missing.begin(), missing.end());
    for (const auto& m : missing) only_base.add(name_of_key(*m.second));
    return only_base;
}

// A comparison of nothing is no verdict: exit 2, saying how the two runs differ.
[[noreturn]] void no_match(const std::string& base_dir, const std::string& new_dir,
                           const CompareOptions& opt, const Base& base, const KeyValues& new_values,
                           const Tally& tally) {
    const std::string diff = key_differences(base.values, new_values);
    const bool methods =
        diff.rfind("method ", 0) == 0 || diff.find("; method ") != std::string::npos;
    const std::string why =
        "no row of NEW matches a row of BASE (" + std::to_string(base.rows.size()) +
        " rows in BASE, " + std::to_string(tally.only_new) + " in NEW): " +
        (base.rows.empty() && tally.only_new == 0 ? std::string("both runs are empty")
                                                  : "their keys differ in " + diff) +
        "; nothing was compared, so there is no verdict" +
        (methods ? " (rows of two methods are matched with --pair NEW=BASE)" : "");
    Verdict v{"pxh compare", base_dir + " -> " + new_dir, 2, "NO VERDICT: " + why, {}};
    v.cases.push_back({"rows matched", "pxh.compare", false, why, {}, {{"matched", 0}}});
    write_verdict_files(opt, v);
    throw InputError(new_dir + "/results.csv", why);
}

// The verdict line: report only, or PASS / FAIL with the gate's tolerances.
std::string verdict_line(const CompareOptions& opt, const Tally& tally) {
    if (opt.fail_on.empty())
        return "REPORT ONLY (no --fail-on): " + std::to_string(tally.changed) +
               " matched row(s) with changed errors or status";
    std::string spec;
    for (const CompareTolerance& t : opt.fail_on)
        spec += (spec.empty() ? "" : ",") + t.column + "=" + allowance(t);
    return std::string(tally.regressions.total ? "FAIL" : "PASS") + ": " +
           std::to_string(tally.regressions.total) + " regression(s) beyond --fail-on " + spec;
}

}  // namespace

std::pair<std::string, std::string> parse_pair(const std::string& spec) {
    const size_t eq = spec.find('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 == spec.size() ||
        spec.find('=', eq + 1) != std::string::npos)
        throw InputError("--pair", "'" + spec +
                                       "': NEW=BASE, two method names (e.g. my_pom=pom: NEW's "
                                       "rows of my_pom matched with BASE's rows of pom)");
    return {spec.substr(0, eq), spec.substr(eq + 1)};
}

int run_compare(const std::string& base_dir, const std::string& new_dir, const CompareOptions& opt,
                std::ostream& out) {
    // BASE: kept as compact records, by key; NEW: streamed past it.
    Base base;
    read_base(base_dir, opt, base);
    Bands bands(opt.band_edges);
    Tally tally;
    tally.band_context = varying_context(base.values);
    // The timing tests' family first (NEW read once more): each row's verdict is Holm's.
    timing_family(new_dir, opt, base, tally);
    tally.base_left_out = base.left_out;
    const KeyValues new_values = stream_new(new_dir, opt, base, bands, tally);
    const Capped only_base = missing_from_new(base);
    const bool gate_missing = !opt.fail_on.empty() && !opt.common;
    if (gate_missing) {
        for (const std::string& r : only_base.items)
            tally.regressions.add(INFINITY, r + ": missing from NEW");
        tally.regressions.total += only_base.total - only_base.items.size();
    }
    // A gated column one run lacks: nothing to compare it with, so the gate fails, saying so
    // (a NaN base would otherwise let any value through).
    const auto unjudged = [&](const std::string& column, const std::string& csv) {
        const std::string why = "--fail-on " + column + ": " + csv + " has no column " + column +
                                ", so the gate cannot compare it (it fails rather than pass "
                                "unseen)";
        tally.unjudged.push_back(why);
        tally.regressions.add(INFINITY, why);
    };
    for (const std::string& c : base.lacks) unjudged(c, base.csv);
    for (const std::string& c : tally.new_lacks)
        if (std::find(base.lacks.begin(), base.lacks.end(), c) == base.lacks.end())
            unjudged(c, new_dir + "/results.csv");
    tally.regressions.trim();
    if (tally.matched == 0) no_match(base_dir, new_dir, opt, base, new_values, tally);

    const std::string verdict = verdict_line(opt, tally);
    write_report(base_dir, new_dir, opt, verdict, tally, bands, only_base, out);
    const int rc = !opt.fail_on.empty() && tally.regressions.total ? 1 : 0;
    write_verdict_files(opt,
                        verdict_of(base_dir, new_dir, rc, verdict, tally, only_base, gate_missing));
    if (opt.fail_on.empty()) return 0;
    out << verdict << "\n";
    return rc;
}

}  // namespace pxh
