#include "harness/report/compare.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <sstream>

#include "harness/core/error.h"
#include "harness/core/params.h"
#include "harness/metrics/columns.h"
#include "harness/report/bands.h"
#include "harness/report/text_table.h"
#include "harness/results/results.h"

namespace pxh {
namespace {

// What identifies a row across runs (issue 16): what ran, on what, from where, where.
const char* const kKeys[] = {"method",  "params",    "heightfield",   "scale",
                             "bias",    "theta_deg", "phi_deg",       "samples",
                             "backend", "precision", "texture_format"};
// The changes reported (differences; timings as ratios).
const char* const kErrors[] = {"err_mean", "err_p95", "err_max", "fetches_mean"};

std::string key_of(const ResultRow& r) {
    std::string k;
    for (const char* c : kKeys) k += r.cell(c) + '\x1f';
    return k;
}

// "pom layers=32 [cpu/float] on bricks s=0.05 b=1 theta=30 phi=0"
std::string row_name(const ResultRow& r) {
    return series_of(r) + " on " + field_of(r) + " theta=" + r.cell("theta_deg") +
           " phi=" + r.cell("phi_deg");
}

struct Run {
    ResultsFile file;
    std::map<std::string, size_t> by_key;
};

Run load(const std::string& dir) {
    const auto path = std::filesystem::path(dir) / "results.csv";
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec))
        throw InputError(dir, "no results.csv here (a pxh run's results folder is needed)");
    Run run{read_results(path.string()), {}};
    for (size_t i = 0; i < run.file.rows.size(); ++i)
        if (!run.by_key.emplace(key_of(run.file.rows[i]), i).second)
            throw InputError(run.file.where(i),
                             "two rows with the same keys (" + row_name(run.file.rows[i]) + ")");
    return run;
}

// The timing column of a row's backend (CPU: ns per sample, GLSL: ms per frame).
const char* timing_column(const ResultRow& r) {
    return r.text("backend") == "cpu" ? "ns_per_sample" : "ms_per_frame";
}

struct Timing {
    double ratio = NAN;  // new / base median
    bool noise = false;  // the repeats' ranges overlap: the change is within their spread
};

Timing timing_change(const ResultRow& b, const ResultRow& n) {
    const std::string c = timing_column(b);
    Timing t;
    const double mb = b.num(c), mn = n.num(c);
    if (!(mb > 0) || !std::isfinite(mn)) return t;
    t.ratio = mn / mb;
    const double b_lo = b.num(c + "_min"), b_hi = b.num(c + "_max");
    const double n_lo = n.num(c + "_min"), n_hi = n.num(c + "_max");
    t.noise = n_lo <= b_hi && b_lo <= n_hi;
    return t;
}

// How far a value may grow under a tolerance; NaN base: any finite value is fine.
bool regresses(const CompareTolerance& t, double base, double now) {
    if (std::isnan(base)) return false;
    if (!std::isfinite(now)) return true;  // a number that became empty or infinite
    const double allowed = t.relative ? t.amount * std::abs(base) : t.amount;
    return now - base > allowed + 1e-12 * std::max(1.0, std::abs(base));
}

std::string signed_fmt(double v, int prec = 3) {
    if (!std::isfinite(v)) return "-";
    std::string s = fmt(v, prec);
    return v > 0 ? "+" + s : s;
}

std::string ratio_fmt(const Timing& t) {
    if (!std::isfinite(t.ratio)) return "-";
    return fmt(t.ratio, 2) + "x" + (t.noise ? " (noise)" : "");
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

struct Pair {
    const ResultRow* base;
    const ResultRow* now;
};

// Per method setting and theta band: mean changes, geometric-mean timing ratio.
TextTable band_table(const std::vector<Pair>& pairs, Bands& bands) {
    struct Acc {
        Mean d[4];
        double log_ratio = 0;
        int n_ratio = 0, rows = 0;
        bool all_noise = true;
    };
    std::map<std::pair<std::string, int>, Acc> acc;
    for (const Pair& p : pairs) {
        if (!p.base->ok() || !p.now->ok()) continue;
        const double theta = p.base->num("theta_deg");
        const int band = bands.of(theta);
        if (band < 0) continue;
        bands.add_view(band, theta);
        Acc& a = acc[{series_of(*p.base), band}];
        ++a.rows;
        for (int i = 0; i < 4; ++i) a.d[i].add(p.now->num(kErrors[i]) - p.base->num(kErrors[i]));
        const Timing t = timing_change(*p.base, *p.now);
        if (std::isfinite(t.ratio) && t.ratio > 0) {
            a.log_ratio += std::log(t.ratio);
            ++a.n_ratio;
            a.all_noise = a.all_noise && t.noise;
        }
    }
    TextTable t;
    t.header = {"method [backend]", "theta band", "rows",      "d err_mean",
                "d err_p95",        "d err_max",  "d fetches", "time ratio"};
    t.align = "llrrrrrr";
    for (const auto& [k, a] : acc) {
        Timing g;
        if (a.n_ratio) g = {std::exp(a.log_ratio / a.n_ratio), a.all_noise};
        t.rows.push_back({k.first, bands.edges(size_t(k.second)), std::to_string(a.rows),
                          signed_fmt(a.d[0].get()), signed_fmt(a.d[1].get()),
                          signed_fmt(a.d[2].get()), signed_fmt(a.d[3].get(), 2), ratio_fmt(g)});
    }
    t.notes.push_back(
        "d: mean over the band's rows of NEW - BASE (texels; fetches per sample); time ratio: "
        "geometric mean of NEW / BASE medians (CPU ns_per_sample, GLSL ms_per_frame), "
        "(noise) when every row's repeat ranges overlap.");
    return t;
}

// Per row: the rows whose errors, fetches or status changed, largest |d err_p95| first.
TextTable row_table(const std::vector<Pair>& pairs) {
    std::vector<std::pair<double, const Pair*>> changed;
    for (const Pair& p : pairs) {
        bool any = p.base->ok() != p.now->ok();
        for (const char* c : kErrors) any = any || p.base->cell(c) != p.now->cell(c);
        if (!any) continue;
        const double d = std::abs(p.now->num("err_p95") - p.base->num("err_p95"));
        changed.push_back({std::isfinite(d) ? d : INFINITY, &p});
    }
    std::stable_sort(changed.begin(), changed.end(),
                     [](const auto& a, const auto& b) { return a.first > b.first; });
    TextTable t;
    t.header = {"changed row", "err_mean", "err_p95", "err_max", "fetches", "time ratio"};
    t.align = "lrrrrr";
    auto change = [](const Pair& p, const char* c, int prec) {
        if (!p.now->ok()) return std::string("failed");
        return p.base->cell(c) + " -> " + p.now->cell(c) + " (" +
               signed_fmt(p.now->num(c) - p.base->num(c), prec) + ")";
    };
    const size_t shown = std::min<size_t>(changed.size(), 50);
    for (size_t i = 0; i < shown; ++i) {
        const Pair& p = *changed[i].second;
        t.rows.push_back({row_name(*p.now), change(p, "err_mean", 4), change(p, "err_p95", 4),
                          change(p, "err_max", 4), change(p, "fetches_mean", 2),
                          ratio_fmt(timing_change(*p.base, *p.now))});
    }
    if (changed.empty()) t.notes.push_back("No row's errors, fetches or status changed.");
    else if (shown < changed.size())
        t.notes.push_back("... and " + std::to_string(changed.size() - shown) +
                          " more changed rows (largest change of err_p95 first).");
    return t;
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
    if (out.empty()) throw InputError("--fail-on", "no tolerance given");
    return out;
}

int run_compare(const std::string& base_dir, const std::string& new_dir, const CompareOptions& opt,
                std::ostream& out) {
    const Run base = load(base_dir), now = load(new_dir);
    std::vector<Pair> pairs;
    std::vector<std::string> only_base, only_new, regressions;
    for (size_t i = 0; i < base.file.rows.size(); ++i) {
        const auto it = now.by_key.find(key_of(base.file.rows[i]));
        if (it == now.by_key.end()) only_base.push_back(row_name(base.file.rows[i]));
        else pairs.push_back({&base.file.rows[i], &now.file.rows[it->second]});
    }
    for (const ResultRow& r : now.file.rows)
        if (!base.by_key.count(key_of(r))) only_new.push_back(row_name(r));

    size_t changed = 0;
    for (const Pair& p : pairs) {
        bool any = p.base->ok() != p.now->ok();
        for (const char* c : kErrors) any = any || p.base->cell(c) != p.now->cell(c);
        changed += any;
        if (opt.fail_on.empty()) continue;
        if (p.base->ok() && !p.now->ok()) {
            regressions.push_back(row_name(*p.now) + ": failed (" + p.now->text("error") + ")");
            continue;
        }
        for (const CompareTolerance& t : opt.fail_on)
            if (p.now->ok() && regresses(t, p.base->num(t.column), p.now->num(t.column)))
                regressions.push_back(
                    row_name(*p.now) + ": " + t.column + " " + p.base->cell(t.column) + " -> " +
                    p.now->cell(t.column) + " (allowed +" +
                    (t.relative ? fmt(100 * t.amount, 2) + "%" : fmt(t.amount, 6)) + ")");
    }
    if (!opt.fail_on.empty())
        for (const std::string& r : only_base) regressions.push_back(r + ": missing from NEW");

    const std::string h = opt.markdown ? "### " : "";
    out << h << "pxh compare: " << base_dir << " (BASE) -> " << new_dir << " (NEW)\n\n";
    out << pairs.size() << " rows matched (" << changed << " with changed errors or status), "
        << only_base.size() << " only in BASE, " << only_new.size() << " only in NEW\n\n";
    Bands bands(opt.band_edges);
    write_table(band_table(pairs, bands), opt.markdown, out);
    auto list = [&](const std::string& title, const std::vector<std::string>& v) {
        if (v.empty()) return;
        out << h << title << " (" << v.size() << ")\n";
        const size_t shown = std::min<size_t>(v.size(), 50);
        for (size_t i = 0; i < shown; ++i) out << (opt.markdown ? "- " : "  ") << v[i] << "\n";
        if (shown < v.size()) out << "  ... and " << v.size() - shown << " more\n";
        out << "\n";
    };
    write_table(row_table(pairs), opt.markdown, out);
    list("Rows only in BASE", only_base);
    list("Rows only in NEW", only_new);
    if (opt.fail_on.empty()) return 0;
    list("Regressions beyond --fail-on", regressions);
    out << (regressions.empty() ? "PASS" : "FAIL") << ": " << regressions.size()
        << " regression(s) beyond --fail-on\n";
    return regressions.empty() ? 0 : 1;
}

}  // namespace pxh
