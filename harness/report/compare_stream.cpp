// pxh compare's reading of the two runs: BASE's results.csv kept as compact records by key,
// NEW's streamed past them one row at a time, matched pairs checked (field size, ground truth,
// time unit) and handed to the tallies.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <unordered_set>

#include "harness/core/error.h"
#include "harness/experiment/only_rows.h"
#include "harness/metrics/columns.h"
#include "harness/metrics/timing_stats.h"
#include "harness/report/compare_parts.h"
#include "harness/results/csv_table.h"
#include "harness/results/results.h"

namespace pxh::compare_detail {

const char* const kErrors[] = {"err_mean",     "err_p95",     "err_max",
                               "fetches_mean", "err_px_mean", "err_px_p95"};

namespace {

Rec rec_of(const ResultRow& r, size_t line, const std::string& where, const CompareOptions& opt,
           Pool& pool) {
    Rec x;
    x.line = line;
    x.ok = r.ok();
    x.error = r.text("error");
    x.shader = pool.of(r.text("shader"));
    x.shader_sha256 = pool.of(r.text("shader_sha256"));
    x.ground_truth = pool.of(r.text("ground_truth"));
    x.width = r.num("width");
    x.height = r.num("height");
    x.theta = r.num("theta_deg");
    for (int i = 0; i < kNumErrors; ++i) x.err[i] = r.num(kErrors[i]);
    for (const CompareTolerance& t : opt.fail_on) x.tol.push_back(r.num(t.column));
    x.time_unit = pool.of(r.text("time_unit"));
    x.t_median = r.num("time");
    const auto reps = parse_repeats(r.text("time_repeats"));
    if (!reps)
        throw InputError(where, "column 'time_repeats': '" + r.text("time_repeats") +
                                    "' is not a ';'-separated list of times");
    x.repeats = *reps;
    return x;
}

std::string size_of(const Rec& r) { return sig(r.width) + "x" + sig(r.height); }

// results.csv of a results folder, one typed row at a time.
class RowStream {
  public:
    explicit RowStream(const std::string& dir)
        : in_(path_of(dir)), specs_(column_specs_of(in_.columns())) {}
    bool next(ResultRow& row) {
        if (!in_.next(fields_)) return false;
        row = parse_result_row(specs_, fields_, in_.where());
        return true;
    }
    // Whether the file has the column (under an older name too: results.cpp's renames).
    bool has(const std::string& column) const {
        ResultsFile header;
        header.header = in_.columns();
        return header.has(column);
    }
    std::string where() const { return in_.where(); }
    size_t line() const { return in_.line(); }
    const std::string& path() const { return in_.path(); }

  private:
    static std::string path_of(const std::string& dir) {
        const auto path = std::filesystem::path(dir) / "results.csv";
        std::error_code ec;
        if (!std::filesystem::is_regular_file(path, ec))
            throw InputError(dir, "no results.csv here (a pxh run's results folder is needed)");
        return path.string();
    }
    CsvReader in_;
    std::vector<const ColumnSpec*> specs_;
    std::vector<std::string> fields_;
};

// Rows that only look alike: refused, not compared.
void check_alike(const Rec& b, const Rec& n, const std::string& name, const std::string& where,
                 const std::string& there) {
    if (!same(b.width, n.width) || !same(b.height, n.height))
        throw InputError(where, name + " is on a " + size_of(n) + " field here but " + size_of(b) +
                                    " in BASE (" + there +
                                    "): compare refuses to match rows across "
                                    "different field sizes");
    if (*b.ground_truth != *n.ground_truth)
        throw InputError(where, name + " is measured against ground truth '" + *n.ground_truth +
                                    "' here but '" + *b.ground_truth + "' in BASE (" + there +
                                    "): compare refuses to match rows across "
                                    "different ground truths");
    if (!b.time_unit->empty() && !n.time_unit->empty() && *b.time_unit != *n.time_unit)
        throw InputError(where, name + " is timed in " + *n.time_unit + " here but in " +
                                    *b.time_unit + " in BASE (" + there +
                                    "): compare refuses to compare times in "
                                    "different units");
}

}  // namespace

void pair_row(ResultRow& row, const CompareOptions& opt, bool is_new) {
    if (opt.pairs.empty()) return;
    const std::string method = row.text("method");
    for (const auto& [now, base] : opt.pairs)
        if (method == (is_new ? now : base)) {
            row.set_text("method", now + "=" + base);
            row.set_text("params", "");
            return;
        }
}

void read_base(const std::string& base_dir, const CompareOptions& opt, Base& base) {
    RowStream in(base_dir);
    base.csv = in.path();
    for (const CompareTolerance& t : opt.fail_on)
        if (!in.has(t.column)) base.lacks.push_back(t.column);
    ResultRow row;
    const OnlyRows only(opt.only);
    while (in.next(row)) {
        if (!only.matches(row)) {
            ++base.left_out;
            continue;
        }
        pair_row(row, opt, false);
        base.values.add(row);
        if (!base.by_key.emplace(key_of(row), base.rows.size()).second)
            throw InputError(in.where(), "two rows with the same keys (" + row_name(row) + ")");
        base.rows.push_back(rec_of(row, in.line(), in.where(), opt, base.pool));
    }
}

void timing_family(const std::string& new_dir, const CompareOptions& opt, const Base& base,
                   Tally& tally) {
    // Only when something is timed: BASE has repeats (else nothing is tested, NEW not read).
    if (std::none_of(base.rows.begin(), base.rows.end(),
                     [](const Rec& r) { return !r.repeats.empty(); }))
        return;
    RowStream in(new_dir);
    Pool pool;
    std::vector<double> p;
    // Every timed pair: its smallest reachable p and log(median ratio), for the pooled test.
    std::vector<std::pair<double, double>> timed;
    ResultRow row;
    const OnlyRows only(opt.only);
    while (in.next(row)) {
        if (!only.matches(row)) continue;
        pair_row(row, opt, true);
        const auto it = base.by_key.find(key_of(row));
        if (it == base.by_key.end()) continue;
        const Rec n = rec_of(row, in.line(), in.where(), opt, pool);
        const Rec& b = base.rows[it->second];
        if (timing_tested(b, n)) p.push_back(timing_p(b, n));
        if (b.ok && n.ok && b.t_median > 0 && n.t_median > 0 && std::isfinite(n.t_median) &&
            !b.repeats.empty() && !n.repeats.empty())
            timed.emplace_back(min_p_value(b.repeats.size(), n.repeats.size()),
                               std::log(n.t_median / b.t_median));
    }
    // The rows too few to reach Holm's first level over the row tests plus the pooled one.
    const double alpha_first = kTimingAlpha / double(p.size() + 1);
    std::vector<double> d;
    for (const auto& [min_p, log_ratio] : timed)
        if (min_p > alpha_first) d.push_back(log_ratio);
    const double pooled_p = signed_rank_p_slower(d);
    if (std::isfinite(pooled_p)) p.push_back(pooled_p);
    tally.family = holm(p);
    Holm& h = tally.family;
    h.pooled_n = d.size();
    h.pooled_p = pooled_p;
    if (!d.empty()) {
        double sum = 0;
        for (double v : d) sum += v;
        h.pooled_ratio = std::exp(sum / double(d.size()));
    }
    // The margin the family must exceed: --fail-on time's relative allowance (0 without one).
    double margin = 0;
    for (const CompareTolerance& t : opt.fail_on)
        if (t.column == "time" && t.relative) margin = t.amount;
    h.pooled_slower = std::isfinite(pooled_p) && pooled_p <= h.cut && h.pooled_ratio > 1 + margin;
}

KeyValues stream_new(const std::string& new_dir, const CompareOptions& opt, Base& base,
                     Bands& bands, Tally& tally) {
    KeyValues new_values;
    RowStream in(new_dir);
    for (const CompareTolerance& t : opt.fail_on)
        if (!in.has(t.column)) tally.new_lacks.push_back(t.column);
    std::unordered_set<std::string> only_new;  // the keys of NEW's rows that BASE lacks
    ResultRow row;
    const OnlyRows only(opt.only);
    while (in.next(row)) {
        if (!only.matches(row)) {
            ++tally.new_left_out;
            continue;
        }
        pair_row(row, opt, true);
        new_values.add(row);
        const Rec n = rec_of(row, in.line(), in.where(), opt, base.pool);
        const std::string key = key_of(row), name = row_name(row);
        const auto it = base.by_key.find(key);
        Rec* b = it == base.by_key.end() ? nullptr : &base.rows[it->second];
        if (b ? b->matched : !only_new.insert(key).second)
            throw InputError(in.where(), "two rows with the same keys (" + name + ")");
        if (!b) {
            ++tally.only_new;
            tally.only_new_names.add(name);
            continue;
        }
        b->matched = true;
        check_alike(*b, n, name, in.where(), base.csv + ":" + std::to_string(b->line));
        add_pair(*b, n, row, name, opt, bands, tally);
    }
    return new_values;
}

}  // namespace pxh::compare_detail
