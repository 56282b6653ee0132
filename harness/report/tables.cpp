// The report's tables: summary, failed rows, sweeps, precision, budgets.
#include <algorithm>
#include <cstdio>
#include <iostream>
#include <sstream>

#include "harness/core/error.h"
#include "harness/core/params.h"
#include "harness/report/report_data.h"

namespace pxh {

namespace {

// One line of summary.csv: a series over a band (or "all").
void summary_csv_line(std::ostream& csv, const std::string& s, const Series& ser,
                      const std::string& band, double lo, double hi, size_t views, const Acc& a) {
    csv << csv_quote(s) << "," << csv_quote(ser.setting) << "," << csv_quote(ser.method) << ","
        << csv_quote(ser.group) << "," << csv_quote(band) << "," << csv_num(lo) << ","
        << csv_num(hi) << "," << (views ? std::to_string(views) : "") << ","
        << csv_num(a.err_mean.get()) << "," << csv_num(a.err_p50.get()) << ","
        << csv_num(a.err_p95.get()) << "," << csv_num(a.worst_p95) << ","
        << csv_num(a.fetches.get()) << "," << csv_num(a.ns.get()) << "," << csv_num(a.ms.get())
        << "," << csv_num(a.sliding.get()) << "," << csv_num(a.shimmering.get()) << "\n";
}

}  // namespace

// summary.csv / .md / .tex: per series, mean / p95 per band, cost.
void write_summary(const ReportData& d) {
    const auto bands = d.present_bands();
    std::ostringstream csv;
    csv << "series,setting,method,group,band,theta_lo,theta_hi,band_views,err_mean,err_p50,"
           "err_p95,err_p95_worst,fetches_mean,ns_per_sample,ms_per_frame,sliding,shimmering\n";
    TextTable tt;
    tt.header.push_back("method");
    for (size_t b : bands) tt.header.push_back(d.bands.label(b) + " mean / p95");
    for (const char* h : {"fetches", "CPU ns/sample", "GLSL ms/frame"}) tt.header.push_back(h);
    tt.align = "l" + std::string(bands.size() + 3, 'r');
    for (const auto& s : d.series_order) {
        const Series& ser = d.series.at(s);
        std::vector<std::string> row = {s};
        for (size_t b : bands) {
            auto it = ser.band.find(b);
            if (it == ser.band.end()) {
                row.push_back("-");
                continue;
            }
            row.push_back(fmt(it->second.err_mean.get()) + " / " + fmt(it->second.err_p95.get()));
            summary_csv_line(csv, s, ser, d.bands.label(b), d.bands.lo(b), d.bands.hi(b),
                             d.bands.views(b), it->second);
        }
        summary_csv_line(csv, s, ser, "all", NAN, NAN, 0, ser.all);
        row.push_back(fmt(ser.all.fetches.get(), 1));
        row.push_back(fmt(ser.all.ns.get(), 1));
        row.push_back(fmt(ser.all.ms.get(), 2));
        tt.rows.push_back(row);
    }
    tt.notes = d.notes();
    tt.notes.push_back(
        "Texel error, mean over rows of the per-row mean / 95th percentile, per "
        "band of the view angle θ (degrees); fetches and times over all angles.");
    d.write("summary.csv", csv.str());
    d.write("summary.md", tt.markdown());
    d.write("summary.tex", tt.latex(d.dir + "/results.csv"));
}

// failed.md: every failed row, what it was and why (nothing else uses them).
void write_failed(const ReportData& d) {
    if (d.failed.empty()) return;
    TextTable tt;
    tt.header = {"method", "params", "height field", "θ", "φ", "backend/format", "error"};
    tt.align = "llllrrl";
    for (size_t i : d.failed) {
        const ResultRow& r = d.row(i);
        tt.rows.push_back({r.text("method"), r.text("params"), field_of(r), r.cell("theta_deg"),
                           r.cell("phi_deg"), group_of(r), r.text("error")});
    }
    tt.notes.push_back("Rows with status not ok (" + d.file.path +
                       "): their metrics are left "
                       "out of every table, budget and plot of this report.");
    d.write("failed.md", tt.markdown());
    const size_t shown = std::min<size_t>(d.failed.size(), 20);
    std::cout << d.failed.size() << " failed rows, left out of every figure (report/failed.md):\n";
    for (size_t i = 0; i < shown; ++i) {
        const ResultRow& r = d.row(d.failed[i]);
        std::cout << "  " << setting_of(r) << " | " << field_of(r) << " | theta "
                  << r.cell("theta_deg") << " phi " << r.cell("phi_deg") << " | " << group_of(r)
                  << ": " << one_line(r.text("error")) << "\n";
    }
    if (shown < d.failed.size()) std::cout << "  ... and " << d.failed.size() - shown << " more\n";
}

// sweep.md: sliding / shimmering per series and band (when measured).
void write_sweep(const ReportData& d) {
    bool any = false;
    for (const auto& s : d.series_order) any |= d.series.at(s).all.shimmering.n > 0;
    if (!any) return;
    const auto bands = d.present_bands();
    TextTable tt;
    tt.header.push_back("method");
    for (size_t b : bands) tt.header.push_back(d.bands.label(b) + " sliding / shimmering");
    tt.align = "l" + std::string(bands.size(), 'r');
    for (const auto& s : d.series_order) {
        std::vector<std::string> row = {s};
        const auto& band = d.series.at(s).band;
        for (size_t b : bands) {
            auto it = band.find(b);
            row.push_back(it == band.end() ? "-"
                                           : fmt(it->second.sliding.get()) + " / " +
                                                 fmt(it->second.shimmering.get()));
        }
        tt.rows.push_back(row);
    }
    tt.notes = d.notes();
    tt.notes.push_back(
        "Texels per degree of view change (docs/conventions.md section 5.3): "
        "sliding = |mean change of the error vector| / dt, shimmering = mean "
        "|change - mean change| / dt.");
    d.write("sweep.md", tt.markdown());
}

// precision.md: what float precision itself costs, per setting and view angle (worst over the
// ok rows of each angle of |uv_float - uv_double|, texels), when both precisions ran.
void write_precision(const ReportData& d) {
    std::vector<double> thetas;
    std::map<std::string, std::map<double, double>> worst;
    std::vector<std::string> order;
    for (size_t i : d.ok) {
        const ResultRow& r = d.row(i);
        const double diff = r.num("double_diff_max");
        if (!std::isfinite(diff)) continue;
        const double th = r.num("theta_deg");
        if (std::find(thetas.begin(), thetas.end(), th) == thetas.end()) thetas.push_back(th);
        const std::string m = setting_of(r);
        if (!worst.count(m)) order.push_back(m);
        auto [it, fresh] = worst[m].emplace(th, diff);
        if (!fresh) it->second = std::max(it->second, diff);
    }
    if (order.empty()) return;
    std::sort(thetas.begin(), thetas.end());
    TextTable tt;
    tt.header.push_back("method");
    for (double th : thetas) tt.header.push_back("θ = " + format_number(th));
    tt.align = "l" + std::string(thetas.size(), 'r');
    for (const auto& m : order) {
        std::vector<std::string> row = {m};
        for (double th : thetas) {
            auto it = worst[m].find(th);
            char buf[32];
            std::snprintf(buf, sizeof buf, "%.2g", it == worst[m].end() ? NAN : it->second);
            row.push_back(it == worst[m].end() ? "-" : buf);
        }
        tt.rows.push_back(row);
    }
    tt.notes = d.notes(/*with_bands=*/false);
    tt.notes.push_back(
        "Largest |uv_float - uv_double| over the samples, in texels (CPU "
        "reference in float vs double on the same samples).");
    d.write("precision.md", tt.markdown());
}

namespace {

// Does a setting meet a budget in a band? Only if no row of it failed there, none had
// non-finite outputs, and every one of its series (backend, precision, texture format) with
// rows there is within the budget: the conservative reading.
bool meets(const ReportData& d, const Setting& set, size_t band, double budget) {
    if (set.failed_bands.count(band)) return false;
    bool any = false;
    for (const auto& s : set.series) {
        const auto& bands = d.series.at(s).band;
        auto it = bands.find(band);
        if (it == bands.end()) continue;
        if (it->second.nonfinite || !(it->second.budget.get() <= budget)) return false;
        any = true;
    }
    return any;
}

// The cheapest setting meeting a budget in a band (fewest fetches, then CPU time), as a cell.
std::string cheapest(const ReportData& d, size_t b, double budget) {
    const std::string* best = nullptr;
    double best_f = INFINITY, best_ns = INFINITY;  // missing counts as the dearest
    for (const auto& name : d.setting_order) {
        const Setting& set = d.settings.at(name);
        if (!meets(d, set, b, budget)) continue;
        const Acc& a = set.band.at(b);
        const double f = std::isfinite(a.fetches.get()) ? a.fetches.get() : INFINITY;
        const double ns = std::isfinite(a.ns.get()) ? a.ns.get() : INFINITY;
        if (!best || f < best_f || (f == best_f && ns < best_ns)) {
            best = &name;
            best_f = f;
            best_ns = ns;
        }
    }
    return best ? *best + " (" + fmt(best_f, 1) + " fetches)" : "no setting meets this budget";
}

}  // namespace

// budget.md / budget.tex: per band and budget, the cheapest method setting meeting it.
void write_budget(const ReportData& d) {
    const auto bands = d.present_bands();
    TextTable tt;
    tt.header.push_back(d.metric.header);
    for (size_t b : bands) tt.header.push_back(d.bands.label(b));
    tt.align = "r" + std::string(bands.size(), 'l');
    for (double budget : d.metric.budgets) {
        std::vector<std::string> row = {format_number(budget)};
        for (size_t b : bands) row.push_back(cheapest(d, b, budget));
        tt.rows.push_back(row);
    }
    tt.notes = d.notes();
    tt.notes.push_back(
        std::string("Cheapest method setting (fewest fetches, height and map lookups, per "
                    "sample, then CPU time, over its rows in the band) whose "
                    "mean ") +
        d.metric.meaning + " (`" + d.metric.column +
        "`) in the band is within the budget on every backend, precision and "
        "texture format it ran on, with no failed row and no non-finite "
        "output there.");
    d.write("budget.md", tt.markdown());
    d.write("budget.tex", tt.latex(d.dir + "/results.csv"));
}

}  // namespace pxh
