// `pxh check DIR --thresholds FILE`: every [[limit]] of the file against the typed rows of
// DIR/results.csv.
#include <toml++/toml.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <optional>

#include "harness/core/error.h"
#include "harness/core/params.h"
#include "harness/report/report.h"
#include "harness/results/csv_table.h"
#include "harness/results/results.h"

namespace pxh {

namespace {

// The key columns a limit may select rows by.
const std::vector<std::string> kFilters = {"method",    "params",         "heightfield", "backend",
                                           "precision", "texture_format", "ground_truth"};

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

// One [[limit]] as read: where it is, its column, bounds, θ range and row filters.
struct Limit {
    std::string where, column, what;
    std::optional<double> lo, hi;
    double tmin = -1, tmax = 1e9;
    std::vector<std::pair<std::string, std::string>> wanted;  // filter -> value
};

struct Outcome {
    std::string what, column, limit;
    double worst;
    size_t rows;
    bool pass;
    std::string note;
};

toml::table parse_thresholds(const std::string& file) {
    toml::table root;
    try {
        root = toml::parse(read_regular_file(file), file);
    } catch (const toml::parse_error& e) {
        throw InputError(file + ":" + std::to_string(e.source().begin.line),
                         "TOML syntax error: " + std::string(e.description()));
    }
    for (const auto& [k, v] : root)
        if (k.str() != "limit")
            throw InputError(file, "unknown key '" + std::string(k.str()) +
                                       "' (a thresholds "
                                       "file holds [[limit]] tables)");
    return root;
}

// The column a limit names: in the file, registered, numeric.
void check_column(const ResultsFile& f, const std::string& where, const std::string& column) {
    if (!f.has(column)) throw InputError(where, "results.csv has no column '" + column + "'");
    const ColumnSpec* spec = find_column(column);
    if (!spec) throw InputError(where, "column '" + column + "' is not a column this pxh writes");
    if (spec->type == ColumnType::text)
        throw InputError(where, "column '" + column +
                                    "' is not numeric (it holds text): a "
                                    "limit needs a numeric column");
}

Limit read_limit(const toml::node& node, const std::string& file, const ResultsFile& f) {
    const toml::table& lt = *node.as_table();
    Limit l;
    l.where = file + ":" + std::to_string(node.source().begin.line);
    for (const auto& [k, v] : lt) {
        const std::string key(k.str());
        const bool filter = std::find(kFilters.begin(), kFilters.end(), key) != kFilters.end();
        if (!filter && key != "column" && key != "min" && key != "max" && key != "theta_min" &&
            key != "theta_max" && key != "note")
            throw InputError(l.where, "unknown key '" + key + "' in [[limit]]");
    }
    auto str = [&](const std::string& key) -> std::optional<std::string> {
        if (auto n = lt.get(key)) {
            if (!n->is_string()) throw InputError(l.where, "'" + key + "' must be a string");
            return *n->value<std::string>();
        }
        return std::nullopt;
    };
    auto num = [&](const char* key) -> std::optional<double> {
        if (auto n = lt.get(key)) {
            if (!(n->is_integer() || n->is_floating_point()))
                throw InputError(l.where, std::string("'") + key + "' must be a number");
            const double v = *n->value<double>();
            // nan compares false with everything: such a limit would pass every row.
            if (std::isnan(v))
                throw InputError(l.where, std::string("'") + key + "' is nan, not a limit");
            return v;
        }
        return std::nullopt;
    };
    const auto column = str("column");
    if (!column) throw InputError(l.where, "[[limit]] needs 'column'");
    l.column = *column;
    check_column(f, l.where, l.column);
    l.lo = num("min");
    l.hi = num("max");
    if (!l.lo && !l.hi) throw InputError(l.where, "[[limit]] needs 'min' or 'max'");
    l.tmin = num("theta_min").value_or(-1);
    l.tmax = num("theta_max").value_or(1e9);
    for (const auto& filter : kFilters)
        if (auto v = str(filter)) {
            l.what += (l.what.empty() ? "" : " ") + filter + "=" + *v;
            l.wanted.emplace_back(filter, filter == "params" ? canonical_params(*v) : *v);
        }
    if (lt.contains("theta_min") || lt.contains("theta_max"))
        l.what += std::string(l.what.empty() ? "" : " ") + "theta in [" +
                  format_number(l.tmin < 0 ? 0 : l.tmin) + ", " +
                  (l.tmax > 1e8 ? std::string("90") : format_number(l.tmax)) + "]";
    return l;
}

std::vector<size_t> matching_rows(const Limit& l, const ResultsFile& f) {
    std::vector<size_t> match;
    for (size_t r = 0; r < f.rows.size(); ++r) {
        const ResultRow& row = f.rows[r];
        bool ok = true;
        for (const auto& [k, v] : l.wanted)
            ok = ok && (k == "params" ? canonical_params(row.text(k)) : row.text(k)) == v;
        const double th = row.num("theta_deg");
        ok = ok && th >= l.tmin && th <= l.tmax;
        if (ok) match.push_back(r);
    }
    if (match.empty())
        throw InputError(l.where, "limit on '" + l.column + "' (" + l.what +
                                      ") matches no row: a limit that checks nothing is an error");
    return match;
}

Outcome evaluate(const Limit& l, const ResultsFile& f) {
    const std::vector<size_t> match = matching_rows(l, f);
    Outcome o{l.what.empty() ? "all rows" : l.what, l.column, "", NAN, match.size(), true, ""};
    o.limit = (l.lo ? ">= " + format_number(*l.lo) : "") + (l.lo && l.hi ? ", " : "") +
              (l.hi ? "<= " + format_number(*l.hi) : "");
    double worst_hi = -INFINITY, worst_lo = INFINITY;
    size_t failed = 0, nonfinite = 0;
    std::string first_error;
    for (size_t r : match) {
        const ResultRow& row = f.rows[r];
        // A failed row fails every limit that matches it: it has no value to pass with.
        if (!row.ok()) {
            if (!failed++) first_error = one_line(row.text("error"));
            continue;
        }
        const double v = row.num(l.column);
        if (!std::isfinite(v)) {
            ++nonfinite;
            continue;
        }
        worst_hi = std::max(worst_hi, v);
        worst_lo = std::min(worst_lo, v);
    }
    if (failed) o.note = std::to_string(failed) + " matching rows failed: " + first_error;
    if (nonfinite)
        o.note += (o.note.empty() ? "" : "; ") + std::to_string(nonfinite) +
                  " matching rows have a non-finite or empty value";
    o.pass = !failed && !nonfinite && !(l.hi && worst_hi > *l.hi) && !(l.lo && worst_lo < *l.lo);
    o.worst = l.hi ? worst_hi : worst_lo;
    return o;
}

// The table of outcomes; returns how many failed.
int print_outcomes(const std::vector<Outcome>& outcomes) {
    int failed = 0;
    std::cout << std::left << std::setw(4) << "#" << std::setw(72) << "rows selected"
              << std::setw(22) << "column" << std::setw(12) << "limit" << std::setw(12) << "worst"
              << std::setw(6) << "rows"
              << "result\n";
    for (size_t i = 0; i < outcomes.size(); ++i) {
        const auto& o = outcomes[i];
        failed += !o.pass;
        char worst[32];
        std::snprintf(worst, sizeof worst, "%.4g", o.worst);
        std::cout << std::left << std::setw(4) << i + 1 << std::setw(72) << o.what << std::setw(22)
                  << o.column << std::setw(12) << o.limit << std::setw(12)
                  << (std::isfinite(o.worst) ? worst : "-") << std::setw(6) << o.rows
                  << (o.pass ? "pass" : "FAIL") << (o.note.empty() ? "" : "  (" + o.note + ")")
                  << "\n";
    }
    std::cout << outcomes.size() - failed << " passed, " << failed << " failed\n";
    return failed;
}

}  // namespace

int run_check(const std::string& dir, const std::string& file) {
    const ResultsFile f = read_results((std::filesystem::path(dir) / "results.csv").string());
    const toml::table root = parse_thresholds(file);
    const toml::array* limits = root["limit"].as_array();
    if (!limits || limits->empty() || !limits->is_array_of_tables())
        throw InputError(file, "no [[limit]] tables");
    std::vector<Outcome> outcomes;
    for (const auto& node : *limits) outcomes.push_back(evaluate(read_limit(node, file, f), f));
    return print_outcomes(outcomes) ? 1 : 0;
}

}  // namespace pxh
