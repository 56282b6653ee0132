// The parts of pxh compare (harness/report/compare.h) shared by its files: a row's identity
// across runs (compare_rows.cpp), the two results files read as compact records
// (compare_stream.cpp), what each matched pair adds to the tallies and the gate
// (compare_gate.cpp), and the printed report and machine-readable verdict (compare_tables.cpp).
#pragma once
#include <cmath>
#include <map>
#include <ostream>
#include <set>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "harness/metrics/row.h"
#include "harness/metrics/timing_stats.h"
#include "harness/report/bands.h"
#include "harness/report/compare.h"
#include "harness/report/text_table.h"
#include "harness/report/verdict.h"

namespace pxh::compare_detail {

// --- Row identity (compare_rows.cpp) ---

// What identifies a row across runs: every axis of the registry (row_axes(): what ran, on
// what, from where, where; the cameras' own keys among them) but the ground truth, whose
// change compare refuses outright (it is not a row of another run, it is another measure).
const std::vector<std::string>& keys();
// A key's cell; results written before cameras, level modes and camera resolutions had
// columns are the orthographic camera's rows at lod base, a perspective image of `samples`
// pixels a side.
std::string key_cell(const ResultRow& r, const std::string& c);
std::string key_of(const ResultRow& r);
// --pair: a row of a paired method renamed "NEW=BASE", its params emptied (NEW's rows when
// is_new, else BASE's), before it is keyed.
void pair_row(ResultRow& row, const CompareOptions& opt, bool is_new);
// The row's name from its key (row_name of the row the key was made of).
std::string name_of_key(const std::string& key);

// Every key's values in one run, for saying how two runs differ when no row matches.
struct KeyValues {
    std::vector<std::set<std::string>> values = std::vector<std::set<std::string>>(keys().size());
    void add(const ResultRow& r) {
        for (size_t i = 0; i < keys().size(); ++i)
            if (values[i].size() < 64) values[i].insert(key_cell(r, keys()[i]));
    }
};
// "samples 64 vs 32; lod base vs level": the keys whose values differ between the runs.
std::string key_differences(const KeyValues& b, const KeyValues& n);
// The context keys (columns.h: base, radius, samples, the cameras' keys, a component's own)
// that take more than one value in these rows, in key order: the band table splits by them.
std::vector<std::string> varying_context(const KeyValues& v);

// Four significant digits, "-" when missing.
std::string sig(double v);
std::string signed_sig(double v);

// --- The two results files (compare_stream.cpp) ---

// The changes reported (differences; timings as ratios): texel errors, fetches, pixel errors.
extern const char* const kErrors[];
constexpr int kNumErrors = 6;
constexpr size_t kShown = 50;  // rows listed per list; the rest counted

// Texts shared by many rows (shader files, hashes, ground truths), kept once.
class Pool {
  public:
    const std::string* of(const std::string& s) { return &*texts_.insert(s).first; }

  private:
    std::set<std::string> texts_;
};

// What compare keeps of a row: the few values it compares (numbers, shared texts), not the
// row. BASE's rows are kept like this by key (NEW's are streamed past them), so memory is what
// the keys take plus a few numbers per row, not what the rows hold.
struct Rec {
    size_t line = 0;  // in its results.csv
    std::string error;
    const std::string *shader = nullptr, *shader_sha256 = nullptr, *ground_truth = nullptr;
    const std::string* time_unit = nullptr;  // "" when untimed
    double width = NAN, height = NAN, theta = NAN;
    bool ok = false, matched = false;
    double err[kNumErrors] = {NAN, NAN, NAN, NAN, NAN, NAN};
    std::vector<double> tol;  // the --fail-on columns' values
    double t_median = NAN;    // time, in time_unit
    std::vector<double> repeats;
};

// Two cells the same: equal numbers, or both empty.
inline bool same(double a, double b) { return a == b || (std::isnan(a) && std::isnan(b)); }

// BASE's rows as records, by key, with the values of its keys.
struct Base {
    Pool pool;
    std::vector<Rec> rows;
    std::unordered_map<std::string, size_t> by_key;
    std::string csv;  // its results.csv
    KeyValues values;
    std::vector<std::string> lacks;  // the --fail-on columns its results.csv has no column for
    size_t left_out = 0;             // rows --only left out
};
void read_base(const std::string& base_dir, const CompareOptions& opt, Base& base);

struct Tally;
// The timing tests' family, before any pair is judged: NEW's rows streamed past BASE's once,
// the U test's p of every matched pair with a timing test (both ok, repeats on both sides that
// can reach p < kTimingAlpha), and Holm's step-down over them (holm).
void timing_family(const std::string& new_dir, const CompareOptions& opt, const Base& base,
                   Tally& tally);
// Streams NEW's rows past BASE's: each matched pair goes to add_pair (rows that only look
// alike are refused), the others are counted as only in NEW. Returns the values of NEW's keys.
KeyValues stream_new(const std::string& new_dir, const CompareOptions& opt, Base& base,
                     Bands& bands, Tally& tally);

// --- The tallies and the gate (compare_gate.cpp) ---

struct Timing {
    enum Kind { none, no_repeats, too_few, noise, slower, faster };
    Kind kind = none;
    double ratio = NAN;  // new / base median
    double p = NAN;      // Mann-Whitney U, two-sided
    size_t n_base = 0, n_new = 0;
    // too_few because the smallest p these repeats allow is above Holm's first level
    // kTimingAlpha / m (not because it is above kTimingAlpha itself)
    bool for_family = false;
};
// Whether a matched pair's repeats get a U test (both ok, repeats on both sides that can reach
// p < kTimingAlpha), and its p (two-sided).
bool timing_tested(const Rec& b, const Rec& n);
double timing_p(const Rec& b, const Rec& n);
// Holm's step-down at kTimingAlpha over the family's p-values: the p at or below which a row's
// change is significant (-1: none), and m (the family's size).
struct Holm {
    size_t m = 0;
    double cut = -1;
    double alpha_m() const { return m ? kTimingAlpha / double(m) : kTimingAlpha; }
    // The rows whose repeats are too few for a verdict of their own (5 + 5 repeats reach
    // p = 0.008, above Holm's first level once m > 6), judged together: a one-sided Wilcoxon
    // signed-rank test over their log(median ratio)s (one pair a row), its p one more member of
    // the Holm family above, and their geometric-mean ratio. `pooled_slower`: that test is
    // significant and the geometric mean exceeds the time margin; only then does such a row past
    // the margin count as a regression (with fewer than kPooledMin such rows, each row past the
    // margin counts, as there is nothing to pool).
    size_t pooled_n = 0;
    double pooled_p = NAN, pooled_ratio = NAN;
    bool pooled_slower = false;
};
// The fewest too-few rows the pooled test judges (its normal approximation's floor).
constexpr size_t kPooledMin = 8;
Holm holm(std::vector<double> p);
// One-sided (slower: d > 0) Wilcoxon signed-rank p over d, normal approximation with ties and
// continuity; zeros dropped. NaN with fewer than kPooledMin non-zero values.
double signed_rank_p_slower(const std::vector<double>& d);
std::string ratio_fmt(const Timing& t);
std::string allowance(const CompareTolerance& t);

// A list of names: the first kShown kept, the rest counted.
struct Capped {
    std::vector<std::string> items;
    size_t total = 0;
    void add(std::string s) {
        if (items.size() < kShown) items.push_back(std::move(s));
        ++total;
    }
};

// Per method setting and theta band: mean changes, geometric-mean timing ratio and verdicts.
struct BandAcc {
    Mean d[kNumErrors];
    double log_ratio = 0;
    int n_ratio = 0, rows = 0, slower = 0, faster = 0, noise = 0, no_verdict = 0;
};

// One changed row of the per-row table.
struct Changed {
    double order;  // |d err_p95|, inf when not finite
    std::vector<std::string> cells;
};

// Regressions, largest change first: the first kShown kept, the rest counted.
struct Ranked {
    std::vector<std::pair<double, std::string>> items;  // (size of change, text)
    size_t total = 0;
    void add(double size, std::string s) {
        items.emplace_back(std::isnan(size) ? INFINITY : size, std::move(s));
        ++total;
        if (items.size() > 4 * kShown) trim();
    }
    void trim();
};

// One compared row group (a method setting on a backend variant): a JUnit testcase.
struct GroupAcc {
    size_t rows = 0, regressions = 0;
    std::vector<std::string> details;  // the first kShown regressions' texts
};

// Everything compare prints, gathered while NEW streams past BASE.
struct Tally {
    size_t matched = 0, changed = 0, only_new = 0;
    Capped only_new_names;
    Ranked regressions;
    std::map<std::string, GroupAcc> groups;
    // Per series, the context keys varying in BASE (base, radius, a camera's keys, ...; see
    // band_context) and theta band: the band table never averages across a context key.
    std::map<std::pair<std::string, int>, BandAcc> bands;
    std::vector<std::string> band_context;  // the context keys whose values vary in BASE
    std::vector<Changed> rows;              // kept to the kShown largest (trimmed as it grows)
    size_t rows_changed = 0;
    int t_slower = 0, t_faster = 0, t_noise = 0, t_too_few = 0, t_no_repeats = 0;
    Holm family;               // the timing tests' (timing_family)
    int t_too_few_family = 0;  // of t_too_few: its repeats cannot reach Holm's first level
    std::set<std::string> shader_changes;
    std::vector<std::string> new_lacks;          // the --fail-on columns NEW's results.csv lacks
    size_t new_left_out = 0, base_left_out = 0;  // the rows --only left out
    // "--fail-on COL: FILE has no column COL ...": gated columns a run lacks, each a failure
    std::vector<std::string> unjudged;
};

void trim(std::vector<Changed>& rows);

// The pair's contribution to every table, list and verdict.
void add_pair(const Rec& b, const Rec& n, const ResultRow& now, const std::string& name,
              const CompareOptions& opt, Bands& bands, Tally& tally);

// --- The report and the verdict (compare_tables.cpp) ---

// The printed comparison (verdict line, summary, regressions, details) from the tallies.
void write_report(const std::string& base_dir, const std::string& new_dir,
                  const CompareOptions& opt, const std::string& verdict, Tally& tally,
                  const Bands& bands, const Capped& only_base, std::ostream& out);
// The machine-readable verdict: a testcase per compared row group, one for BASE's missing rows.
Verdict verdict_of(const std::string& base_dir, const std::string& new_dir, int rc,
                   const std::string& verdict, const Tally& tally, const Capped& only_base,
                   bool gate_missing);
void write_verdict_files(const CompareOptions& opt, const Verdict& v);

}  // namespace pxh::compare_detail
