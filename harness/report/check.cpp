// `pxh check DIR --thresholds FILE`: every [[limit]] of the file against the typed rows of
// DIR/results.csv.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <map>
#include <optional>

#include "harness/core/error.h"
#include "harness/core/param_dict.h"
#include "harness/core/params.h"
#include "harness/experiment/only_rows.h"
#include "harness/metrics/columns.h"
#include "harness/report/report.h"
#include "harness/report/verdict.h"
#include "harness/results/csv_table.h"
#include "harness/results/results.h"
#include "harness/scene/view.h"

namespace pxh {

namespace {

// The key columns a limit may select rows by: every axis of the registry (row_axes(): method,
// field, backend, angles, the cameras' keys, lod, and any added later), text ones compared as
// text (params whatever the spaces around its separators), numeric ones as numbers, any of them
// a list ("any of"); and for each numeric axis a range, KEY_min and KEY_max (inclusive; theta's
// are theta_min and theta_max).
std::vector<const ColumnSpec*> filter_columns() { return row_axes(); }
// What identifies a row's baseline for `ratio_to`: every axis but the method and its
// parameters (the same field, view, camera, lod, backend, variant and reference as the row).
std::vector<std::string> same_as_baseline() {
    std::vector<std::string> v;
    for (const ColumnSpec* c : row_axes())
        if (c->name != "method" && c->name != "params") v.push_back(c->name);
    return v;
}

bool contains(const std::vector<std::string>& v, const std::string& s) {
    return std::find(v.begin(), v.end(), s) != v.end();
}

std::string joined(const std::vector<std::string>& v) {
    std::string out;
    for (const auto& s : v) out += (out.empty() ? "" : ", ") + s;
    return out;
}

// params with the spaces around '=' and ';' (and at the ends) removed: "layers = 16" in a
// thresholds file is the canonical "layers=16" of results.csv.
std::string canonical_params(const std::string& s) {
    std::string out;
    for (size_t i = 0; i < s.size(); ++i) {
        if (!std::isspace(static_cast<unsigned char>(s[i]))) {
            out += s[i];
            continue;
        }
        size_t j = i;
        while (j < s.size() && std::isspace(static_cast<unsigned char>(s[j]))) ++j;
        const bool separated = out.empty() || j == s.size() || out.back() == '=' ||
                               out.back() == ';' || s[j] == '=' || s[j] == ';';
        if (!separated) out += s.substr(i, j - i);
        i = j - 1;
    }
    return out;
}

// Two numbers as equal as results.csv (%.10g) can tell: 0.05 in a thresholds file is the
// 0.05 of a row, however it was computed before it was written.
bool same_number(double a, double b) {
    return a == b || std::fabs(a - b) <= 1e-9 * std::max(std::fabs(a), std::fabs(b));
}

// One filter of a limit: its key (a results.csv column), the values any of which a row may
// have, and where it is in the thresholds file.
struct Filter {
    std::string key, where;
    bool numeric = false;
    std::vector<std::string> texts;  // params canonical
    std::vector<double> numbers;

    size_t size() const { return numeric ? numbers.size() : texts.size(); }
    std::string shown(size_t k) const { return numeric ? format_number(numbers[k]) : texts[k]; }
    bool matches(const ResultRow& row, size_t k) const {
        if (numeric) return same_number(row.num(key), numbers[k]);
        if (key == "params") return canonical_params(row.text(key)) == texts[k];
        const std::string& v = row.text(key);  // an empty base is the plane, and so on
        return (v.empty() ? empty_axis_means(key) : v) == texts[k];
    }
    bool matches(const ResultRow& row) const {
        for (size_t k = 0; k < size(); ++k)
            if (matches(row, k)) return true;
        return false;
    }
};

// `ratio_to = { method = "parallax", params = "..." }`: the limit is on the row's value divided
// by the value of its baseline row (the same field, view and backend; this method).
struct RatioTo {
    std::string where, method, params;  // params canonical; "" = any (then it must be unique)
    bool has_params = false;
    std::string shown() const { return method + (has_params ? " " + params : ""); }
};

// One [[limit]] as read: where it is, its column, bounds, θ range and row filters.
// A numeric axis' range filter: KEY_min <= the row's value <= KEY_max (either may be absent).
struct Range {
    std::string key;
    std::optional<double> lo, hi;
};

struct Limit {
    std::string where, column, what;
    std::optional<double> lo, hi;
    std::vector<Range> ranges;
    std::vector<Filter> filters;
    std::optional<RatioTo> ratio;
};

struct Outcome {
    std::string what, column, limit;
    double worst;
    size_t rows;
    bool pass;
    std::string note;
    std::vector<std::string> details;  // printed under a FAIL row: the rows that fail it
};

// The thresholds file's [[limit]] tables, read by the one reader (harness/core/param_dict.h):
// [[limit]] is its only key.
std::vector<ParamDict> read_thresholds(const std::string& file) {
    const ParamDict root = ParamDict::parse(read_regular_file(file), file, "thresholds");
    std::vector<ParamDict> limits;
    if (root.is_list("limit")) {
        try {
            limits = root.tables("limit", "[[limit]]");
        } catch (const InputError&) {
            throw InputError(root.where("limit"), "no [[limit]] tables");
        }
    } else if (root.has("limit")) {
        throw InputError(root.where("limit"), "no [[limit]] tables");
    }
    root.report_unused([](const std::string& key, const std::string&) {
        return "unknown key '" + key + "' (a thresholds file holds [[limit]] tables)";
    });
    if (limits.empty()) throw InputError(root.where("limit"), "no [[limit]] tables");
    return limits;
}

// The measured numeric columns of the file, in its order: what a limit may name.
std::string numeric_columns(const ResultsFile& f) {
    std::vector<std::string> names;
    for (const auto& c : f.header)
        if (const ColumnSpec* spec = find_column(c))
            if (spec->type != ColumnType::text && spec->role == ColumnRole::measured)
                names.push_back(c);
    return "(the measured numeric columns of results.csv: " +
           (names.empty() ? std::string("none") : joined(names)) + ")";
}

// The column a limit names: in the file, registered, numeric.
void check_column(const ResultsFile& f, const std::string& where, const std::string& column) {
    if (!f.has(column))
        throw InputError(where, "results.csv has no column '" + column + "' " + numeric_columns(f));
    const ColumnSpec* spec = find_column(column);
    if (!spec)
        throw InputError(
            where, "column '" + column + "' is not a column this pxh writes " + numeric_columns(f));
    if (spec->type == ColumnType::text)
        throw InputError(where, "column '" + column +
                                    "' is not numeric (it holds text): a limit needs a numeric "
                                    "column " +
                                    numeric_columns(f));
}

// A filter as read: a value or a non-empty list of values, of the column's type, each found
// in some row of results.csv (a value no row has is a typo, or a limit that checks nothing).
Filter read_filter(const std::string& key, const std::vector<ParamDict::Element>& values,
                   const std::string& where, const ResultsFile& f) {
    Filter flt;
    flt.key = key;
    flt.where = where;
    const ColumnSpec* spec = find_column(key);
    flt.numeric = spec && spec->numeric();
    const std::string expected =
        flt.numeric ? "a number or a list of numbers" : "a string or a list of strings";
    for (const auto& v : values) {
        if (flt.numeric) {
            if (!v.value || !v.value->is_number())
                throw InputError(where, "'" + key + "' must be " + expected);
            const double d = v.value->number();
            if (std::isnan(d)) throw InputError(where, "'" + key + "' is nan: no row has it");
            flt.numbers.push_back(d);
        } else {
            if (!v.value || !v.value->is_name())
                throw InputError(where, "'" + key + "' must be " + expected);
            const std::string& s = v.value->name();
            flt.texts.push_back(key == "params" ? canonical_params(s) : s);
        }
    }
    if (!f.has(key))
        throw InputError(where, "results.csv has no column '" + key + "' to filter on");
    for (size_t k = 0; k < flt.size(); ++k) {
        bool found = false;
        for (const auto& row : f.rows) found = found || flt.matches(row, k);
        if (found) continue;
        std::vector<std::string> there;
        for (const auto& row : f.rows) {
            const std::string v = flt.numeric ? row.cell(key) : row.text(key);
            if (!contains(there, v)) there.push_back(v);
        }
        std::string listed;
        for (size_t i = 0; i < there.size() && i < 12; ++i)
            listed += (i ? ", " : "") + (there[i].empty() ? std::string("\"\"") : there[i]);
        if (there.size() > 12) listed += ", ... (" + std::to_string(there.size()) + " in all)";
        throw InputError(where, key + " = " +
                                    (flt.numeric ? flt.shown(k) : "\"" + flt.shown(k) + "\"") +
                                    " matches no row of results.csv (its " + key + ": " +
                                    (listed.empty() ? std::string("no rows") : listed) + ")");
    }
    return flt;
}

// `ratio_to = { method = "...", params = "..." }` (`where`: its line).
RatioTo read_ratio_to(const ParamDict& t, const std::string& where, const ResultsFile& f) {
    RatioTo r;
    r.where = where;
    auto text = [&](const std::string& key) -> std::optional<std::string> {
        if (!t.has(key)) return std::nullopt;
        if (t.is_list(key)) throw InputError(where, "ratio_to." + key + " must be a string");
        const auto v = t.elements(key);
        if (v.size() != 1 || !v[0].value || !v[0].value->is_name())
            throw InputError(where, "ratio_to." + key + " must be a string");
        return v[0].value->name();
    };
    const auto method = text("method");
    const auto params = text("params");
    t.report_unused([&](const std::string& key, const std::string&) {
        return "unknown key '" + key + "' in ratio_to (keys: method, params)";
    });
    if (!method) throw InputError(where, "ratio_to needs 'method' (the baseline method)");
    r.method = *method;
    if (params) {
        r.has_params = true;
        r.params = canonical_params(*params);
    }
    for (const auto& row : f.rows)
        if (row.text("method") == r.method &&
            (!r.has_params || canonical_params(row.text("params")) == r.params))
            return r;
    throw InputError(where, "ratio_to: no row of results.csv is " + r.shown() +
                                ": there is no baseline to divide by");
}

Limit read_limit(const ParamDict& lt, const ResultsFile& f) {
    Limit l;
    l.where = lt.where();
    auto num = [&](const std::string& key) -> std::optional<double> {
        const auto v = lt.number(key);
        // nan compares false with everything: such a limit would pass every row.
        if (v && std::isnan(*v))
            throw InputError(lt.where(key), "'" + key + "' is nan, not a limit");
        return v;
    };
    // The keys in the order the message of an unknown one lists them.
    const auto column = lt.string("column");
    l.lo = num("min");
    l.hi = num("max");
    // Each numeric axis' range, in the registry's order.
    for (const ColumnSpec* c : filter_columns()) {
        if (!c->numeric()) continue;
        Range r{c->name, num(range_key(*c, false)), num(range_key(*c, true))};
        if (r.lo || r.hi) l.ranges.push_back(r);
    }
    lt.string("note");  // a comment for the reader of the file
    // ratio_to is read (its table taken) before the unread keys are reported, its keys after.
    const std::optional<ParamDict> ratio =
        lt.table("ratio_to", "ratio_to",
                 "'ratio_to' must be a table, e.g. ratio_to = { method = \"parallax\" }");
    std::vector<std::pair<std::string, std::vector<ParamDict::Element>>> given;
    for (const ColumnSpec* c : filter_columns()) {
        const std::string& key = c->name;
        if (!lt.has(key)) continue;
        try {
            given.emplace_back(key, lt.elements(key));
        } catch (const InputError&) {
            throw InputError(lt.where(key), "'" + key + "' is an empty list: it matches no row");
        }
    }
    lt.report_unused([](const std::string& key, const std::string& known) {
        return "unknown key '" + key + "' in [[limit]] (keys: " + known + ")";
    });
    if (!column) throw InputError(l.where, "[[limit]] needs 'column'");
    l.column = *column;
    check_column(f, lt.where("column"), l.column);
    if (!l.lo && !l.hi) throw InputError(l.where, "[[limit]] needs 'min' or 'max'");
    if (ratio) l.ratio = read_ratio_to(*ratio, lt.where("ratio_to"), f);
    for (const Range& r : l.ranges)
        if (!f.has(r.key))
            throw InputError(l.where,
                             "results.csv has no column '" + r.key + "' to take a range of");
    for (const auto& [key, elements] : given) {
        Filter flt = read_filter(key, elements, lt.where(key), f);
        std::string values;
        for (size_t k = 0; k < flt.size(); ++k) values += (k ? ", " : "") + flt.shown(k);
        l.what += (l.what.empty() ? "" : " ") + key + "=" +
                  (lt.is_list(key) ? "[" + values + "]" : values);
        l.filters.push_back(std::move(flt));
    }
    for (const Range& r : l.ranges) {
        const ColumnSpec& c = *find_column(r.key);
        const bool theta = r.key == "theta_deg";
        l.what += std::string(l.what.empty() ? "" : " ") + c.shown_as() + " in [" +
                  (r.lo    ? format_number(*r.lo)
                   : theta ? std::string("0")
                           : std::string("-inf")) +
                  ", " +
                  (r.hi    ? format_number(*r.hi)
                   : theta ? std::string("90")
                           : std::string("inf")) +
                  "]";
    }
    if (l.ratio) l.what += std::string(l.what.empty() ? "" : " ") + "(/ " + l.ratio->shown() + ")";
    return l;
}

std::vector<size_t> matching_rows(const Limit& l, const ResultsFile& f) {
    std::vector<size_t> match;
    for (size_t r = 0; r < f.rows.size(); ++r) {
        const ResultRow& row = f.rows[r];
        bool ok = true;
        for (const auto& flt : l.filters) ok = ok && flt.matches(row);
        for (const Range& rg : l.ranges) {
            const double v = row.num(rg.key);
            ok = ok && !std::isnan(v) && (!rg.lo || v >= *rg.lo) && (!rg.hi || v <= *rg.hi);
        }
        if (ok) match.push_back(r);
    }
    if (match.empty())
        throw InputError(l.where, "limit on '" + l.column + "' (" + l.what +
                                      ") matches no row: a limit that checks nothing is an error");
    return match;
}

// A row as a failing limit names it: "pom layers=32 [cpu/float] on bricks s=0.05 b=1 theta=85
// phi=0" (and its other axes: " distance=4 fov_deg=45 resolution=256").
std::string row_named(const ResultRow& row) { return row_name(row); }

std::string short_number(double v) {
    char s[32];
    std::snprintf(s, sizeof s, "%.4g", v);
    return s;
}

// The key a row shares with its ratio_to baseline (kSameAsBaseline).
std::string baseline_key(const ResultRow& row) {
    std::string k;
    static const std::vector<std::string> same = same_as_baseline();
    for (const auto& c : same) k += row.cell(c) + '\x1f';
    return k;
}

// A matched row's value for the limit: its column's value, or (ratio_to) that divided by its
// baseline row's. `why` is set when it has none: the row (or its baseline) failed.
double limit_value(const Limit& l, const ResultsFile& f, size_t r,
                   const std::map<std::string, std::vector<size_t>>& baselines, std::string& why) {
    const ResultRow& row = f.rows[r];
    // A failed row fails every limit that matches it: it has no value to pass with.
    if (!row.ok()) {
        why = one_line(row.text("error"));
        return NAN;
    }
    const double v = row.num(l.column);
    if (!l.ratio) return v;
    const auto it = baselines.find(baseline_key(row));
    if (it == baselines.end())
        throw InputError(l.ratio->where, "ratio_to: " + row_named(row) + " has no baseline row (" +
                                             l.ratio->shown() +
                                             " on the same field, view and backend)");
    if (it->second.size() > 1)
        throw InputError(l.ratio->where, "ratio_to: " + std::to_string(it->second.size()) +
                                             " rows of " + l.ratio->shown() +
                                             " share the field, view and backend of " +
                                             row_named(row) + " (name the baseline's params)");
    const ResultRow& base = f.rows[it->second[0]];
    if (!base.ok()) {
        why = "its baseline " + row_named(base) + " failed: " + one_line(base.text("error"));
        return NAN;
    }
    const double b = base.num(l.column);
    return b > 0 || b < 0 ? v / b : NAN;  // a zero or empty baseline: no ratio
}

Outcome evaluate(const Limit& l, const ResultsFile& f) {
    const std::vector<size_t> match = matching_rows(l, f);
    Outcome o{l.what.empty() ? "all rows" : l.what, l.column, "", NAN, match.size(), true, "", {}};
    const std::string times = l.ratio ? " x " + l.ratio->method : "";
    o.limit = (l.lo ? ">= " + format_number(*l.lo) + times : "") + (l.lo && l.hi ? ", " : "") +
              (l.hi ? "<= " + format_number(*l.hi) + times : "");
    std::map<std::string, std::vector<size_t>> baselines;
    if (l.ratio)
        for (size_t r = 0; r < f.rows.size(); ++r) {
            const ResultRow& row = f.rows[r];
            if (row.text("method") == l.ratio->method &&
                (!l.ratio->has_params || canonical_params(row.text("params")) == l.ratio->params))
                baselines[baseline_key(row)].push_back(r);
        }
    double worst_hi = -INFINITY, worst_lo = INFINITY;
    size_t row_hi = 0, row_lo = 0;
    std::vector<size_t> failed, nonfinite;
    std::string first_why, first_cell;
    for (size_t r : match) {
        std::string why;
        const double v = limit_value(l, f, r, baselines, why);
        if (!why.empty()) {
            if (failed.empty()) first_why = why;
            failed.push_back(r);
            continue;
        }
        if (!std::isfinite(v)) {
            if (nonfinite.empty()) first_cell = std::isnan(v) ? "" : format_number(v);
            nonfinite.push_back(r);
            continue;
        }
        if (v > worst_hi) worst_hi = v, row_hi = r;
        if (v < worst_lo) worst_lo = v, row_lo = r;
    }
    if (!failed.empty())
        o.note = std::to_string(failed.size()) + " matching rows failed: " + first_why;
    if (!nonfinite.empty())
        o.note += (o.note.empty() ? "" : "; ") + std::to_string(nonfinite.size()) +
                  " matching rows have a non-finite or empty value" +
                  (l.ratio ? " (or a zero or empty baseline)" : "");
    const bool over = l.hi && worst_hi > *l.hi, under = l.lo && worst_lo < *l.lo;
    o.pass = failed.empty() && nonfinite.empty() && !over && !under;
    // The worst value is the one beyond a bound when one is (the lower when only it is).
    const bool low_side = under && !over ? true : over ? false : !l.hi;
    o.worst = low_side ? worst_lo : worst_hi;
    if (over || under) {
        const size_t r = low_side ? row_lo : row_hi;
        o.details.push_back("worst: " + row_named(f.rows[r]) + ": " + short_number(o.worst) +
                            times);
    }
    auto more = [](size_t n) { return n > 1 ? " (and " + std::to_string(n - 1) + " more)" : ""; };
    if (!failed.empty())
        o.details.push_back("failed: " + row_named(f.rows[failed[0]]) + ": " + first_why +
                            more(failed.size()));
    if (!nonfinite.empty())
        o.details.push_back("non-finite: " + row_named(f.rows[nonfinite[0]]) + ": " +
                            (first_cell.empty() ? "empty" : first_cell) + more(nonfinite.size()));
    return o;
}

// The table of outcomes, each failing limit followed by the rows that fail it; returns how
// many failed.
int print_outcomes(const std::vector<Outcome>& outcomes) {
    int failed = 0;
    int lw = 12;  // the limit column: wider for a ratio_to limit ("<= 3 x parallax")
    for (const auto& o : outcomes) lw = std::max(lw, int(o.limit.size()) + 1);
    std::cout << std::left << std::setw(4) << "#" << std::setw(72) << "rows selected"
              << std::setw(22) << "column" << std::setw(lw) << "limit" << std::setw(12) << "worst"
              << std::setw(6) << "rows"
              << "result\n";
    for (size_t i = 0; i < outcomes.size(); ++i) {
        const auto& o = outcomes[i];
        failed += !o.pass;
        std::cout << std::left << std::setw(4) << i + 1 << std::setw(72) << o.what << std::setw(22)
                  << o.column << std::setw(lw) << o.limit << std::setw(12)
                  << (std::isfinite(o.worst) ? short_number(o.worst) : "-") << std::setw(6)
                  << o.rows << (o.pass ? "pass" : "FAIL")
                  << (o.note.empty() ? "" : "  (" + o.note + ")") << "\n";
        if (!o.pass)
            for (const auto& d : o.details) std::cout << "  " << d << "\n";
    }
    std::cout << outcomes.size() - failed << " passed, " << failed << " failed\n";
    return failed;
}

}  // namespace

int run_check(const std::string& dir, const std::string& file, const CheckOptions& opt) {
    const ResultsFile f = read_results((std::filesystem::path(dir) / "results.csv").string());
    const std::vector<ParamDict> limits = read_thresholds(file);
    std::vector<Outcome> outcomes;
    for (const auto& limit : limits) outcomes.push_back(evaluate(read_limit(limit, f), f));
    const int failed = print_outcomes(outcomes);
    const int rc = failed ? 1 : 0;
    // The machine-readable verdict: a testcase per limit.
    Verdict v{"pxh check",
              dir + " --thresholds " + file,
              rc,
              std::to_string(outcomes.size() - size_t(failed)) + " passed, " +
                  std::to_string(failed) + " failed",
              {}};
    for (size_t i = 0; i < outcomes.size(); ++i) {
        const Outcome& o = outcomes[i];
        VerdictCase c{
            "#" + std::to_string(i + 1) + " " + o.column + " " + o.limit + " on " + o.what,
            "pxh.check",
            o.pass,
            "",
            o.pass ? std::vector<std::string>{} : o.details,
            {{"worst", o.worst}, {"rows", double(o.rows)}}};
        if (!o.pass)
            c.message = o.column + " worst " +
                        (std::isfinite(o.worst) ? short_number(o.worst) : std::string("-")) +
                        ", limit " + o.limit + (o.note.empty() ? "" : " (" + o.note + ")");
        v.cases.push_back(std::move(c));
    }
    if (!opt.junit.empty()) write_verdict_file(opt.junit, junit_xml(v), "--junit");
    if (!opt.json.empty()) write_verdict_file(opt.json, verdict_json(v), "--json");
    return rc;
}

}  // namespace pxh
