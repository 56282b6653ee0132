#include "harness/report/compare.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string_view>
#include <unordered_map>
#include <unordered_set>

#include "harness/core/error.h"
#include "harness/core/params.h"
#include "harness/metrics/columns.h"
#include "harness/metrics/timing_stats.h"
#include "harness/report/bands.h"
#include "harness/report/text_table.h"
#include "harness/report/verdict.h"
#include "harness/results/csv_table.h"
#include "harness/results/results.h"
#include "harness/scene/view.h"

namespace pxh {
namespace {

// What identifies a row across runs: every axis of the registry (row_axes(): what ran, on
// what, from where, where; the cameras' own keys among them) but the ground truth, whose
// change compare refuses outright (it is not a row of another run, it is another measure).
const std::vector<std::string>& keys() {
    static const std::vector<std::string> k = [] {
        std::vector<std::string> all;
        for (const ColumnSpec* c : row_axes())
            if (c->name != "ground_truth") all.push_back(c->name);
        return all;
    }();
    return k;
}
size_t key_index(const std::string& c) {
    return size_t(std::find(keys().begin(), keys().end(), c) - keys().begin());
}
// The changes reported (differences; timings as ratios): texel errors, fetches, pixel errors.
const char* const kErrors[] = {"err_mean",    "err_p95",    "err_max",
                               "fetches_mean", "err_px_mean", "err_px_p95"};
constexpr int kNumErrors = 6;
constexpr size_t kShown = 50;  // rows listed per list; the rest counted

// A key's cell; results written before cameras, level modes and camera resolutions had
// columns are the orthographic camera's rows at lod base, a perspective image of `samples`
// pixels a side.
std::string key_cell(const ResultRow& r, const std::string& c) {
    std::string v = r.cell(c);
    if (!v.empty()) return v;
    if (c == "camera") return "orthographic";
    if (c == "lod") return "base";
    for (const CameraEntry& e : camera_registry())
        for (const CameraKey& k : e.keys)
            if (k.name == c && !k.default_column.empty() && r.text("camera") == e.name)
                return r.cell(k.default_column);
    return v;
}

std::string key_of(const ResultRow& r) {
    std::string k;
    for (const std::string& c : keys()) k += key_cell(r, c) + '\x1f';
    return k;
}

// Four significant digits, "-" when missing.
std::string sig(double v) {
    if (std::isnan(v)) return "-";
    if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
    char b[32];
    std::snprintf(b, sizeof b, "%.4g", v);
    return b;
}
std::string signed_sig(double v) {
    if (!std::isfinite(v)) return "-";
    return (v > 0 ? "+" : "") + sig(v);
}

// The key's fields, in keys() order.
std::vector<std::string> fields_of_key(const std::string& key) {
    std::vector<std::string> f;
    size_t at = 0;
    for (size_t end; (end = key.find('\x1f', at)) != std::string::npos; at = end + 1)
        f.push_back(key.substr(at, end - at));
    return f;
}

// The row's name from its key (row_name of the row the key was made of).
std::string name_of_key(const std::string& key) {
    const std::vector<std::string> f = fields_of_key(key);
    if (f.size() != keys().size()) return key;
    return row_name([&](const std::string& c) {
        const size_t i = key_index(c);
        return i < f.size() ? f[i] : std::string();
    });
}

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

// Two cells the same: equal numbers, or both empty.
bool same(double a, double b) { return a == b || (std::isnan(a) && std::isnan(b)); }

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

struct Timing {
    enum Kind { none, no_repeats, too_few, noise, slower, faster };
    Kind kind = none;
    double ratio = NAN;  // new / base median
    double p = NAN;      // Mann-Whitney U, two-sided
    size_t n_base = 0, n_new = 0;
};

// The change of a matched row's time: the ratio of medians, and whether the repeats tell it
// from noise (a two-sided Mann-Whitney U test at kTimingAlpha), or too few repeats to say.
Timing timing_change(const Rec& b, const Rec& n) {
    Timing t;
    if (!(b.t_median > 0) || !std::isfinite(n.t_median)) return t;
    t.ratio = n.t_median / b.t_median;
    t.n_base = b.repeats.size();
    t.n_new = n.repeats.size();
    if (b.repeats.empty() || n.repeats.empty()) {
        t.kind = Timing::no_repeats;
        return t;
    }
    if (min_p_value(t.n_base, t.n_new) >= kTimingAlpha) {
        t.kind = Timing::too_few;
        return t;
    }
    const UTest u = mann_whitney_u(n.repeats, b.repeats);
    t.p = u.p;
    if (u.p >= kTimingAlpha) t.kind = Timing::noise;
    else t.kind = u.u > double(t.n_base * t.n_new) / 2 ? Timing::slower : Timing::faster;
    return t;
}

std::string ratio_fmt(const Timing& t) {
    if (!std::isfinite(t.ratio)) return "-";
    const std::string r = sig(t.ratio) + "x";
    switch (t.kind) {
        case Timing::slower:
            return r + " slower (p=" + sig(t.p) + ")";
        case Timing::faster:
            return r + " faster (p=" + sig(t.p) + ")";
        case Timing::noise:
            return r + " (noise, p=" + sig(t.p) + ")";
        case Timing::too_few:
            return r + " (too few repeats for a verdict: " + std::to_string(t.n_base) + " and " +
                   std::to_string(t.n_new) + ")";
        case Timing::no_repeats:
            return r + " (no repeats recorded: no verdict)";
        case Timing::none:
            break;
    }
    return r;
}

// How far a value may grow under a tolerance; NaN base: any finite value is fine.
bool regresses(const CompareTolerance& t, double base, double now) {
    if (std::isnan(base)) return false;
    if (!std::isfinite(now)) return true;  // a number that became empty or infinite
    const double allowed = t.relative ? t.amount * std::abs(base) : t.amount;
    return now - base > allowed + 1e-12 * std::max(1.0, std::abs(base));
}

std::string allowance(const CompareTolerance& t) {
    return "+" + (t.relative ? sig(100 * t.amount) + "%" : sig(t.amount));
}

void write_table(const TextTable& t, bool markdown, std::ostream& out) {
    if (markdown) {
        out << t.markdown() << "\n";
        return;
    }
    std::vector<size_t> w(t.header.size(), 0);
    auto widen = [&](const std::vector<std::string>& row) {
        for (size_t i = 0; i < row.size() && i < w.size(); ++i)
            w[i] = std::max(w[i], row[i].size());
    };
    widen(t.header);
    for (const auto& r : t.rows) widen(r);
    auto line = [&](const std::vector<std::string>& row) {
        std::string s;
        for (size_t i = 0; i < row.size(); ++i) {
            const std::string pad(w[i] - std::min(w[i], row[i].size()), ' ');
            s += (i ? "  " : "") + (t.align[i] == 'r' ? pad + row[i] : row[i] + pad);
        }
        while (!s.empty() && s.back() == ' ') s.pop_back();
        out << s << "\n";
    };
    line(t.header);
    for (const auto& r : t.rows) line(r);
    for (const auto& n : t.notes) out << n << "\n";
    out << "\n";
}

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
    void trim() {
        std::stable_sort(items.begin(), items.end(),
                         [](const auto& a, const auto& b) { return a.first > b.first; });
        if (items.size() > kShown) items.resize(kShown);
    }
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
    std::map<std::pair<std::string, int>, BandAcc> bands;
    std::vector<Changed> rows;  // kept to the kShown largest (trimmed as it grows)
    size_t rows_changed = 0;
    int t_slower = 0, t_faster = 0, t_noise = 0, t_too_few = 0, t_no_repeats = 0;
    std::set<std::string> shader_changes;
};

void trim(std::vector<Changed>& rows) {
    std::stable_sort(rows.begin(), rows.end(),
                     [](const Changed& a, const Changed& b) { return a.order > b.order; });
    if (rows.size() > kShown) rows.resize(kShown);
}

std::string short_sha(const std::string& s) { return s.empty() ? "none" : s.substr(0, 12); }

// The pair's contribution to every table, list and verdict.
void add_pair(const Rec& b, const Rec& n, const ResultRow& now, const std::string& name,
              const CompareOptions& opt, Bands& bands, Tally& tally) {
    ++tally.matched;
    GroupAcc& group = tally.groups[series_of(now)];
    ++group.rows;
    const auto regression = [&](double size, const std::string& text) {
        tally.regressions.add(size, text);
        ++group.regressions;
        if (group.details.size() < kShown) group.details.push_back(text);
    };
    bool any = b.ok != n.ok;
    for (int i = 0; i < kNumErrors; ++i) any = any || !same(b.err[i], n.err[i]);
    tally.changed += any;
    if (*b.shader_sha256 != *n.shader_sha256)
        tally.shader_changes.insert(setting_of(now) + ": " + short_sha(*b.shader_sha256) + " -> " +
                                    short_sha(*n.shader_sha256) +
                                    (n.shader->empty() ? "" : " (" + *n.shader + ")"));
    const Timing timing = b.ok && n.ok ? timing_change(b, n) : Timing{};
    switch (timing.kind) {
        case Timing::slower:
            ++tally.t_slower;
            break;
        case Timing::faster:
            ++tally.t_faster;
            break;
        case Timing::noise:
            ++tally.t_noise;
            break;
        case Timing::too_few:
            ++tally.t_too_few;
            break;
        case Timing::no_repeats:
            ++tally.t_no_repeats;
            break;
        case Timing::none:
            break;
    }
    // The gate.
    if (!opt.fail_on.empty()) {
        if (b.ok && !n.ok) {
            regression(INFINITY, name + ": failed (" + one_line(n.error) + ")");
        } else if (n.ok) {
            for (size_t k = 0; k < opt.fail_on.size(); ++k) {
                const CompareTolerance& t = opt.fail_on[k];
                if (!regresses(t, b.tol[k], n.tol[k])) continue;
                std::string why;
                if (t.column == "time") {
                    // A time regresses only when its repeats show it is slower, not noise.
                    if (timing.kind == Timing::noise || timing.kind == Timing::faster) continue;
                    if (timing.kind == Timing::slower) why = "; slower, p=" + sig(timing.p);
                    else if (timing.kind == Timing::too_few)
                        why = "; no verdict: too few repeats, " + std::to_string(timing.n_base) +
                              " and " + std::to_string(timing.n_new);
                    else if (timing.kind == Timing::no_repeats)
                        why = "; no verdict: no repeats recorded";
                }
                // The size of the change, relative to the base (absolute from a base of 0).
                const double size = std::isfinite(n.tol[k])
                                        ? (n.tol[k] - b.tol[k]) / (b.tol[k] != 0 ? std::abs(b.tol[k]) : 1.0)
                                        : INFINITY;
                regression(size, name + ": " + t.column + " " + sig(b.tol[k]) + " -> " +
                                     sig(n.tol[k]) + " (allowed " + allowance(t) + why + ")");
            }
        }
    }
    // Per band.
    if (b.ok && n.ok) {
        const int band = bands.of(b.theta);
        if (band >= 0) {
            bands.add_view(band, b.theta);
            BandAcc& a = tally.bands[{series_of(now), band}];
            ++a.rows;
            for (int i = 0; i < kNumErrors; ++i) a.d[i].add(n.err[i] - b.err[i]);
            if (std::isfinite(timing.ratio) && timing.ratio > 0) {
                a.log_ratio += std::log(timing.ratio);
                ++a.n_ratio;
                a.slower += timing.kind == Timing::slower;
                a.faster += timing.kind == Timing::faster;
                a.noise += timing.kind == Timing::noise;
                a.no_verdict += timing.kind == Timing::too_few || timing.kind == Timing::no_repeats;
            }
        }
    }
    // Per row: errors, fetches or status changed, or a time that significantly did.
    if (!any && timing.kind != Timing::slower && timing.kind != Timing::faster) return;
    ++tally.rows_changed;
    auto change = [&](int i) {
        if (!n.ok) return std::string("failed");
        return sig(b.err[i]) + " -> " + sig(n.err[i]) + " (" + signed_sig(n.err[i] - b.err[i]) +
               ")";
    };
    const double d = std::abs(n.err[1] - b.err[1]);
    tally.rows.push_back({std::isfinite(d) ? d : INFINITY,
                          {name, change(0), change(1), change(2), change(4), change(5), change(3),
                           ratio_fmt(timing)}});
    if (tally.rows.size() > 4 * kShown) trim(tally.rows);
}

TextTable band_table(const Tally& tally, const Bands& bands) {
    TextTable t;
    t.header = {"method [backend]", "theta band", "rows",          "d err_mean",
                "d err_p95",        "d err_max",  "d err_px_mean", "d err_px_p95",
                "d fetches",        "time ratio"};
    t.align = "llrrrrrrrr";
    for (const auto& [k, a] : tally.bands) {
        std::string ratio = "-";
        if (a.n_ratio) {
            ratio = sig(std::exp(a.log_ratio / a.n_ratio)) + "x";
            if (a.slower || a.faster)
                ratio += " (" + std::to_string(a.slower) + " slower, " + std::to_string(a.faster) +
                         " faster of " + std::to_string(a.n_ratio) + ")";
            else if (a.noise == a.n_ratio) ratio += " (noise)";
            else if (a.noise == 0) ratio += " (no verdict: too few repeats)";
            else ratio += " (noise; " + std::to_string(a.no_verdict) + " without a verdict)";
        }
        t.rows.push_back({k.first, bands.edges(size_t(k.second)), std::to_string(a.rows),
                          signed_sig(a.d[0].get()), signed_sig(a.d[1].get()),
                          signed_sig(a.d[2].get()), signed_sig(a.d[4].get()),
                          signed_sig(a.d[5].get()), signed_sig(a.d[3].get()), ratio});
    }
    t.notes.push_back(
        "d: mean over the band's rows of NEW - BASE (err: texels; err_px: screen pixels; "
        "fetches per sample); time ratio: "
        "geometric mean of NEW / BASE medians of time (each row in its backend's time_unit); a row "
        "is "
        "slower or faster when a two-sided Mann-Whitney U test over its timed repeats gives "
        "p < 0.05, noise otherwise.");
    return t;
}

TextTable row_table(Tally& tally) {
    trim(tally.rows);
    TextTable t;
    t.header = {"changed row", "err_mean",   "err_p95", "err_max",
                "err_px_mean", "err_px_p95", "fetches", "time ratio"};
    t.align = "lrrrrrrr";
    for (const Changed& c : tally.rows) t.rows.push_back(c.cells);
    if (tally.rows_changed == 0)
        t.notes.push_back("No row's errors, fetches, status or time (p < 0.05) changed.");
    else if (tally.rows.size() < tally.rows_changed)
        t.notes.push_back(
            "... and " + std::to_string(tally.rows_changed - tally.rows.size()) +
            " more changed rows (largest change of err_p95 first; then significant time changes).");
    return t;
}

// "0.1.0 (28c5cbf-dirty)" from a folder's run.json; "unknown" without one.
std::string pxh_version_of(const std::string& dir) {
    std::error_code ec;
    const auto p = std::filesystem::path(dir) / "run.json";
    if (!std::filesystem::is_regular_file(p, ec)) return "unknown (no run.json)";
    try {
        std::ifstream f(p, std::ios::binary);
        const auto j = nlohmann::json::parse(f);
        if (j.is_object() && j.contains("pxh_version") && j["pxh_version"].is_string())
            return one_line(j["pxh_version"].get<std::string>());
    } catch (const std::exception&) {
    }
    return "unknown";
}

void list(std::ostream& out, bool markdown, const std::string& title, const Capped& v) {
    if (v.total == 0) return;
    out << (markdown ? "#### " : "") << title << " (" << v.total << ")\n";
    for (const std::string& s : v.items) out << (markdown ? "- " : "  ") << s << "\n";
    if (v.items.size() < v.total) out << "  ... and " << v.total - v.items.size() << " more\n";
    out << "\n";
}

// Every key's values in one run, for saying how two runs differ when no row matches.
struct KeyValues {
    std::vector<std::set<std::string>> values = std::vector<std::set<std::string>>(keys().size());
    void add(const ResultRow& r) {
        for (size_t i = 0; i < keys().size(); ++i)
            if (values[i].size() < 64) values[i].insert(key_cell(r, keys()[i]));
    }
};

std::string listed(const std::set<std::string>& v) {
    std::string s;
    size_t n = 0;
    for (const std::string& x : v) {
        if (n++ == 4) return s + ", ...";
        s += (s.empty() ? "" : ", ") + (x.empty() ? std::string("(empty)") : x);
    }
    return s.empty() ? "(no rows)" : s;
}

// "samples 64 vs 32; lod base vs level": the keys whose values differ between the runs.
std::string key_differences(const KeyValues& b, const KeyValues& n) {
    std::string s;
    for (size_t i = 0; i < keys().size(); ++i) {
        if (b.values[i] == n.values[i]) continue;
        s += (s.empty() ? "" : "; ") + keys()[i] + " " + listed(b.values[i]) + " vs " +
             listed(n.values[i]);
    }
    return s.empty() ? "no key's values (each run's rows combine them differently)" : s;
}

void write_verdict_files(const CompareOptions& opt, const Verdict& v) {
    if (!opt.junit.empty()) write_verdict_file(opt.junit, junit_xml(v), "--junit");
    if (!opt.json.empty()) write_verdict_file(opt.json, verdict_json(v), "--json");
}

}  // namespace

std::vector<CompareTolerance> parse_fail_on(const std::string& spec) {
    std::vector<CompareTolerance> out;
    std::stringstream ss(spec);
    std::string item;
    while (std::getline(ss, item, ',')) {
        const auto eq = item.find('=');
        if (eq == std::string::npos)
            throw InputError("--fail-on", "'" + item + "' is not COLUMN=+AMOUNT or COLUMN=+PCT%");
        CompareTolerance t;
        t.column = item.substr(0, eq);
        std::string v = item.substr(eq + 1);
        const ColumnSpec* c = find_column(t.column);
        if (!c || c->role != ColumnRole::measured || c->type == ColumnType::text) {
            std::string names;
            for (const ColumnSpec* s : result_column_specs())
                if (s->role == ColumnRole::measured && s->type != ColumnType::text)
                    names += (names.empty() ? "" : ", ") + s->name;
            throw InputError(
                "--fail-on",
                "'" + t.column + "' is not a measured numeric column (known: " + names + ")");
        }
        if (!v.empty() && v.back() == '%') {
            t.relative = true;
            v.pop_back();
        }
        size_t used = 0;
        try {
            t.amount = std::stod(v, &used);
        } catch (const std::exception&) {
            used = 0;
        }
        if (v.empty() || used != v.size() || !std::isfinite(t.amount) || t.amount < 0)
            throw InputError("--fail-on", "'" + item +
                                              "': the allowance must be a number >= 0, e.g. "
                                              "err_p95=+5% or err_mean=+0.01");
        if (t.relative) t.amount /= 100;
        out.push_back(t);
    }
    if (out.empty())
        throw InputError("--fail-on", "'" + spec +
                                          "' gives no tolerance (leave --fail-on out for a report "
                                          "without a gate; an empty one does not switch it off)");
    return out;
}

int run_compare(const std::string& base_dir, const std::string& new_dir, const CompareOptions& opt,
                std::ostream& out) {
    // BASE: kept as compact records, by key.
    Pool pool;
    std::vector<Rec> base;
    std::unordered_map<std::string, size_t> by_key;
    std::string base_csv;
    KeyValues base_values, new_values;
    {
        RowStream in(base_dir);
        base_csv = in.path();
        ResultRow row;
        while (in.next(row)) {
            base_values.add(row);
            if (!by_key.emplace(key_of(row), base.size()).second)
                throw InputError(in.where(), "two rows with the same keys (" + row_name(row) + ")");
            base.push_back(rec_of(row, in.line(), in.where(), opt, pool));
        }
    }
    // NEW: streamed past it.
    Bands bands(opt.band_edges);
    Tally tally;
    {
        RowStream in(new_dir);
        std::unordered_set<std::string> only_new;  // the keys of NEW's rows that BASE lacks
        ResultRow row;
        while (in.next(row)) {
            new_values.add(row);
            const Rec n = rec_of(row, in.line(), in.where(), opt, pool);
            const std::string key = key_of(row), name = row_name(row);
            const auto it = by_key.find(key);
            Rec* b = it == by_key.end() ? nullptr : &base[it->second];
            if (b ? b->matched : !only_new.insert(key).second)
                throw InputError(in.where(), "two rows with the same keys (" + name + ")");
            if (!b) {
                ++tally.only_new;
                tally.only_new_names.add(name);
                continue;
            }
            b->matched = true;
            const std::string there = base_csv + ":" + std::to_string(b->line);
            // Rows that only look alike: refused, not compared.
            if (!same(b->width, n.width) || !same(b->height, n.height))
                throw InputError(in.where(), name + " is on a " + size_of(n) + " field here but " +
                                                 size_of(*b) + " in BASE (" + there +
                                                 "): compare refuses to match rows across "
                                                 "different field sizes");
            if (*b->ground_truth != *n.ground_truth)
                throw InputError(in.where(), name + " is measured against ground truth '" +
                                                 *n.ground_truth + "' here but '" +
                                                 *b->ground_truth + "' in BASE (" + there +
                                                 "): compare refuses to match rows across "
                                                 "different ground truths");
            if (!b->time_unit->empty() && !n.time_unit->empty() && *b->time_unit != *n.time_unit)
                throw InputError(in.where(), name + " is timed in " + *n.time_unit +
                                                 " here but in " + *b->time_unit + " in BASE (" +
                                                 there +
                                                 "): compare refuses to compare times in "
                                                 "different units");
            add_pair(*b, n, row, name, opt, bands, tally);
        }
    }
    Capped only_base;
    {
        std::vector<std::pair<size_t, const std::string*>> missing;  // by line: file order
        for (const auto& [key, i] : by_key)
            if (!base[i].matched) missing.push_back({base[i].line, &key});
        std::sort(missing.begin(), missing.end());
        for (const auto& m : missing) only_base.add(name_of_key(*m.second));
    }
    const bool gate_missing = !opt.fail_on.empty() && !opt.common;
    if (gate_missing) {
        for (const std::string& r : only_base.items)
            tally.regressions.add(INFINITY, r + ": missing from NEW");
        tally.regressions.total += only_base.total - only_base.items.size();
    }
    tally.regressions.trim();

    // A comparison of nothing is no verdict: exit 2, saying how the two runs differ.
    if (tally.matched == 0) {
        const std::string why =
            "no row of NEW matches a row of BASE (" + std::to_string(base.size()) +
            " rows in BASE, " + std::to_string(tally.only_new) + " in NEW): " +
            (base.empty() && tally.only_new == 0 ? std::string("both runs are empty")
                                                 : "their keys differ in " +
                                                       key_differences(base_values, new_values)) +
            "; nothing was compared, so there is no verdict";
        Verdict v{"pxh compare", base_dir + " -> " + new_dir, 2, "NO VERDICT: " + why, {}};
        v.cases.push_back({"rows matched", "pxh.compare", false, why, {}, {{"matched", 0}}});
        write_verdict_files(opt, v);
        throw InputError(new_dir + "/results.csv", why);
    }

    const bool md = opt.markdown;
    const std::string h = md ? "### " : "";
    // The verdict first.
    std::string verdict;
    if (opt.fail_on.empty())
        verdict = "REPORT ONLY (no --fail-on): " + std::to_string(tally.changed) +
                  " matched row(s) with changed errors or status";
    else {
        std::string spec;
        for (const CompareTolerance& t : opt.fail_on)
            spec += (spec.empty() ? "" : ",") + t.column + "=" + allowance(t);
        verdict = std::string(tally.regressions.total ? "FAIL" : "PASS") + ": " +
                  std::to_string(tally.regressions.total) + " regression(s) beyond --fail-on " +
                  spec;
    }
    out << h << "pxh compare: " << verdict << "\n\n";
    const std::string br = md ? "  \n" : "\n";  // a Markdown line break
    out << "BASE " << base_dir << " -> NEW " << new_dir << br;
    for (const std::string& n : opt.notes) out << n << br;
    out << tally.matched << " rows matched (" << tally.changed
        << " with changed errors or status), " << only_base.total << " only in BASE, "
        << tally.only_new << " only in NEW" << br;
    if (opt.common)
        out << "--common: " << only_base.total << " rows only in BASE and " << tally.only_new
            << " only in NEW left out" << br;
    out << "timing (two-sided Mann-Whitney U over the timed repeats, p < 0.05): " << tally.t_slower
        << " slower, " << tally.t_faster << " faster, " << tally.t_noise
        << " no significant change, " << tally.t_too_few << " too few repeats for a verdict, "
        << tally.t_no_repeats << " without repeats" << br;
    const std::string vb = pxh_version_of(base_dir), vn = pxh_version_of(new_dir);
    out << "pxh version: "
        << (vb == vn ? vb + " (both)" : "BASE " + vb + ", NEW " + vn + " (changed)") << br;
    out << "shader changes: "
        << (tally.shader_changes.empty() ? "none" : std::to_string(tally.shader_changes.size()))
        << "\n";
    for (const std::string& c : tally.shader_changes) out << (md ? "- " : "  ") << c << "\n";
    out << "\n";
    if (!opt.fail_on.empty() && tally.regressions.total) {
        Capped shown;
        for (const auto& r : tally.regressions.items) shown.add(r.second);
        shown.total = tally.regressions.total;
        list(out, md, "Regressions beyond --fail-on (largest change first)", shown);
    }
    // The details.
    if (md)
        out << "<details><summary>Details: per method and theta band, per changed "
               "row</summary>\n\n";
    write_table(band_table(tally, bands), md, out);
    write_table(row_table(tally), md, out);
    list(out, md, std::string("Rows only in BASE") + (opt.common ? " (left out: --common)" : ""),
         only_base);
    list(out, md, std::string("Rows only in NEW") + (opt.common ? " (left out: --common)" : ""),
         tally.only_new_names);
    if (md) out << "</details>\n\n";
    const int rc = !opt.fail_on.empty() && tally.regressions.total ? 1 : 0;
    // The machine-readable verdict: a testcase per compared row group.
    Verdict v{"pxh compare", base_dir + " -> " + new_dir, rc, verdict, {}};
    for (const auto& [series, g] : tally.groups) {
        VerdictCase c{series, "pxh.compare", g.regressions == 0, "", g.details,
                      {{"rows", double(g.rows)}, {"regressions", double(g.regressions)}}};
        if (g.regressions)
            c.message = std::to_string(g.regressions) + " of " + std::to_string(g.rows) +
                        " matched rows regress beyond --fail-on";
        v.cases.push_back(std::move(c));
    }
    if (gate_missing || only_base.total) {
        VerdictCase c{"rows of BASE found in NEW", "pxh.compare", !gate_missing || !only_base.total,
                      "", {}, {{"missing", double(only_base.total)}}};
        if (!c.passed) {
            c.message = std::to_string(only_base.total) + " rows of BASE are missing from NEW";
            c.details = only_base.items;
        }
        v.cases.push_back(std::move(c));
    }
    write_verdict_files(opt, v);
    if (opt.fail_on.empty()) return 0;
    out << verdict << "\n";
    return rc;
}

}  // namespace pxh
