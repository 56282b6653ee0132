// pxh compare's judgement of a matched pair: the change of its timing (Mann-Whitney U over the
// repeats), the --fail-on gate (parsed here, applied per pair), and what the pair adds to the
// tallies: per row group, per method setting and theta band, per changed row.
#include <algorithm>
#include <cmath>
#include <optional>
#include <sstream>

#include "harness/core/error.h"
#include "harness/core/params.h"
#include "harness/metrics/columns.h"
#include "harness/metrics/timing_stats.h"
#include "harness/report/compare_parts.h"
#include "harness/results/results.h"

namespace pxh::compare_detail {
namespace {

// The change of a matched row's time: the ratio of medians, and whether the repeats tell it
// from noise: a two-sided Mann-Whitney U test whose p is at or below Holm's cut over every
// tested row of the comparison (the family-wise false-alarm rate is kTimingAlpha, not each
// row's), or too few repeats to say (for any level below kTimingAlpha, or for Holm's first
// level kTimingAlpha / m).
Timing timing_change(const Rec& b, const Rec& n, const Holm& family) {
    Timing t;
    if (!(b.t_median > 0) || !std::isfinite(n.t_median)) return t;
    t.ratio = n.t_median / b.t_median;
    t.n_base = b.repeats.size();
    t.n_new = n.repeats.size();
    if (b.repeats.empty() || n.repeats.empty()) {
        t.kind = Timing::no_repeats;
        return t;
    }
    if (!timing_tested(b, n)) {
        t.kind = Timing::too_few;
        return t;
    }
    const UTest u = mann_whitney_u(n.repeats, b.repeats);
    t.p = u.p;
    if (u.p <= family.cut)
        t.kind = u.u > double(t.n_base * t.n_new) / 2 ? Timing::slower : Timing::faster;
    else if (min_p_value(t.n_base, t.n_new) > family.alpha_m()) {
        t.kind = Timing::too_few;
        t.for_family = true;
    } else t.kind = Timing::noise;
    return t;
}

// Why a row's repeats are too few: for Holm's first level, when that is the reason.
std::string too_few_why(const Timing& t, const Holm& family) {
    if (!t.for_family) return "";
    return " (at best p=" + sig(min_p_value(t.n_base, t.n_new)) + "; Holm over " +
           std::to_string(family.m) + " timed rows needs p <= " + sig(family.alpha_m()) + ")";
}

// How far a value may grow under a tolerance; NaN base: any finite value is fine.
bool regresses(const CompareTolerance& t, double base, double now) {
    if (std::isnan(base)) return false;
    if (!std::isfinite(now)) return true;  // a number that became empty or infinite
    const double allowed = t.relative ? t.amount * std::abs(base) : t.amount;
    return now - base > allowed + 1e-12 * std::max(1.0, std::abs(base));
}

std::string short_sha(const std::string& s) { return s.empty() ? "none" : s.substr(0, 12); }

void count_timing(const Timing& timing, Tally& tally) {
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
            tally.t_too_few_family += timing.for_family;
            break;
        case Timing::no_repeats:
            ++tally.t_no_repeats;
            break;
        case Timing::none:
            break;
    }
}

// The gate: the pair's regressions beyond --fail-on, each handed to `regression`.
template <class Regression>
void gate_pair(const Rec& b, const Rec& n, const std::string& name, const CompareOptions& opt,
               const Timing& timing, const Holm& opt_family, const Regression& regression) {
    if (b.ok && !n.ok) {
        regression(INFINITY, name + ": failed (" + one_line(n.error) + ")");
        return;
    }
    if (!n.ok) return;
    for (size_t k = 0; k < opt.fail_on.size(); ++k) {
        const CompareTolerance& t = opt.fail_on[k];
        if (!regresses(t, b.tol[k], n.tol[k])) continue;
        std::string why;
        if (t.column == "time") {
            // A time regresses only when its repeats show it is slower, not noise.
            if (timing.kind == Timing::noise || timing.kind == Timing::faster) continue;
            const bool pooled = opt_family.pooled_n >= kPooledMin;
            if (timing.kind == Timing::too_few && pooled && !opt_family.pooled_slower)
                continue;  // too few for its own verdict; the rows together are not slower
            if (timing.kind == Timing::slower) why = "; slower, p=" + sig(timing.p);
            else if (timing.kind == Timing::too_few && pooled)
                why = "; too few repeats for a verdict of its own, but the " +
                      std::to_string(opt_family.pooled_n) + " such rows together are slower: x" +
                      sig(opt_family.pooled_ratio) + ", signed-rank p=" + sig(opt_family.pooled_p) +
                      " (Holm)";
            else if (timing.kind == Timing::too_few)
                why = "; no verdict: too few repeats, " + std::to_string(timing.n_base) + " and " +
                      std::to_string(timing.n_new) + too_few_why(timing, opt_family);
            else if (timing.kind == Timing::no_repeats) why = "; no verdict: no repeats recorded";
        }
        // The size of the change, relative to the base (absolute from a base of 0).
        const double size = std::isfinite(n.tol[k])
                                ? (n.tol[k] - b.tol[k]) / (b.tol[k] != 0 ? std::abs(b.tol[k]) : 1.0)
                                : INFINITY;
        regression(size, name + ": " + t.column + " " + sig(b.tol[k]) + " -> " + sig(n.tol[k]) +
                             " (allowed " + allowance(t) + why + ")");
    }
}

// Per band: the pair's changes in its method setting's theta band.
void add_to_band(const Rec& b, const Rec& n, const ResultRow& now, const Timing& timing,
                 Bands& bands, Tally& tally) {
    const int band = bands.of(b.theta);
    if (band < 0) return;
    bands.add_view(band, b.theta);
    std::string series = series_of(now);  // and its context: rows of two bases never pooled
    for (const std::string& k : tally.band_context)
        if (const std::string v = key_cell(now, k); !v.empty()) series += " " + k + "=" + v;
    BandAcc& a = tally.bands[{series, band}];
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

}  // namespace

bool timing_tested(const Rec& b, const Rec& n) {
    return b.ok && n.ok && b.t_median > 0 && std::isfinite(n.t_median) && !b.repeats.empty() &&
           !n.repeats.empty() && min_p_value(b.repeats.size(), n.repeats.size()) < kTimingAlpha;
}

double timing_p(const Rec& b, const Rec& n) { return mann_whitney_u(n.repeats, b.repeats).p; }

double signed_rank_p_slower(const std::vector<double>& d) {
    std::vector<double> a;
    for (double v : d)
        if (v != 0 && std::isfinite(v)) a.push_back(v);
    const size_t n = a.size();
    if (n < kPooledMin) return NAN;
    std::vector<size_t> idx(n);
    for (size_t i = 0; i < n; ++i) idx[i] = i;
    std::sort(idx.begin(), idx.end(),
              [&](size_t x, size_t y) { return std::abs(a[x]) < std::abs(a[y]); });
    double w_plus = 0, ties = 0;
    for (size_t i = 0; i < n;) {  // average ranks over runs of equal |d|
        size_t j = i;
        while (j + 1 < n && std::abs(a[idx[j + 1]]) == std::abs(a[idx[i]])) ++j;
        const double rank = 0.5 * double(i + j) + 1, t = double(j - i + 1);
        ties += t * t * t - t;
        for (size_t k = i; k <= j; ++k)
            if (a[idx[k]] > 0) w_plus += rank;
        i = j + 1;
    }
    const double nn = double(n);
    const double mean = nn * (nn + 1) / 4;
    const double var = nn * (nn + 1) * (2 * nn + 1) / 24 - ties / 48;
    if (!(var > 0)) return 1.0;
    const double z = (w_plus - mean - 0.5) / std::sqrt(var);
    return std::min(1.0, 0.5 * std::erfc(z / std::sqrt(2.0)));
}

Holm holm(std::vector<double> p) {
    // Holm (1979): the i-th smallest of m p-values (from 0) is significant when it and every
    // smaller one is at most kTimingAlpha / (m - i). The rows rejected are those at or below
    // the last p that passed: the family-wise error rate is at most kTimingAlpha whatever the
    // dependence between the rows' tests.
    std::sort(p.begin(), p.end());
    Holm h;
    h.m = p.size();
    for (size_t i = 0; i < p.size() && p[i] <= kTimingAlpha / double(p.size() - i); ++i)
        h.cut = p[i];
    return h;
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
                   std::to_string(t.n_new) + (t.for_family ? " for Holm's first level" : "") + ")";
        case Timing::no_repeats:
            return r + " (no repeats recorded: no verdict)";
        case Timing::none:
            break;
    }
    return r;
}

std::string allowance(const CompareTolerance& t) {
    return "+" + (t.relative ? sig(100 * t.amount) + "%" : sig(t.amount));
}

void Ranked::trim() {
    std::stable_sort(items.begin(), items.end(),
                     [](const auto& a, const auto& b) { return a.first > b.first; });
    if (items.size() > kShown) items.resize(kShown);
}

void trim(std::vector<Changed>& rows) {
    std::stable_sort(rows.begin(), rows.end(),
                     [](const Changed& a, const Changed& b) { return a.order > b.order; });
    if (rows.size() > kShown) rows.resize(kShown);
}

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
    const Timing timing = b.ok && n.ok ? timing_change(b, n, tally.family) : Timing{};
    count_timing(timing, tally);
    if (!opt.fail_on.empty()) gate_pair(b, n, name, opt, timing, tally.family, regression);
    if (b.ok && n.ok) add_to_band(b, n, now, timing, bands, tally);
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

}  // namespace pxh::compare_detail

namespace pxh {

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
        // A decimal number, an optional '+' before it: no hexadecimal ("+0x10" is not 16),
        // no spaces, nothing after it (parse_number is std::from_chars' general format).
        const std::optional<double> amount =
            parse_number(!v.empty() && v[0] == '+' ? v.substr(1) : v);
        t.amount = amount ? *amount : NAN;
        if (!amount || !std::isfinite(t.amount) || t.amount < 0)
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

}  // namespace pxh
