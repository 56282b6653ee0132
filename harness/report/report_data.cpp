#include "harness/report/report_data.h"

#include <fstream>
#include <iostream>

#include "harness/core/error.h"

namespace pxh {

namespace fs = std::filesystem;

namespace {

const BudgetMetric kBudgetMetrics[] = {
    {"p95",
     "err_p95",
     "p95 budget (texels)",
     "95th-percentile texel error",
     {0.1, 0.25, 0.5, 1, 2, 4}},
    {"p99",
     "err_p99",
     "p99 budget (texels)",
     "99th-percentile texel error",
     {0.1, 0.25, 0.5, 1, 2, 4}},
    {"frac_gt_1",
     "frac_gt_1",
     "frac_gt_1 budget (fraction of samples)",
     "fraction of samples more than one texel off",
     {0.001, 0.003, 0.01, 0.03, 0.1}},
};

}  // namespace

const BudgetMetric& budget_metric(const std::string& name) {
    for (const auto& m : kBudgetMetrics)
        if (name == m.name) return m;
    throw InputError("--budget-metric", "'" + name + "' is not one of p95, p99, frac_gt_1");
}

void Acc::add(const ResultRow& r, const char* budget_column) {
    err_mean.add(r.num("err_mean"));
    err_p50.add(r.num("err_p50"));
    const double p95 = r.num("err_p95");
    err_p95.add(p95);
    if (std::isfinite(p95)) worst_p95 = std::isfinite(worst_p95) ? std::max(worst_p95, p95) : p95;
    fetches.add(r.num("fetches_mean"));
    ns.add(r.num("ns_per_sample"));
    ms.add(r.num("ms_per_frame"));
    sliding.add(r.num("sliding"));
    shimmering.add(r.num("shimmering"));
    budget.add(r.num(budget_column));
    nonfinite = nonfinite || r.num("nonfinite") > 0;
}

ReportData::ReportData(const std::string& d, const ReportOptions& o)
    : dir(d),
      out(fs::path(d) / "report"),
      bands(o.bands),
      metric(budget_metric(o.budget_metric)),
      file(read_results((fs::path(d) / "results.csv").string())) {
    for (const char* c : {"method", "theta_deg", "err_mean", "err_p95", "status"})
        if (!file.has(c))
            throw InputError(file.path,
                             std::string("no column '") + c + "' (not a pxh results file?)");
    for (size_t r = 0; r < file.rows.size(); ++r) (file.rows[r].ok() ? ok : failed).push_back(r);
    if (ok.empty()) throw InputError(file.path, "has no ok rows to report");
    assign_bands();
    collect();
}

void ReportData::assign_bands() {
    size_t outside = 0;
    for (size_t r : ok) {
        const double theta = row(r).num("theta_deg");
        const int b = bands.of(theta);
        if (b >= 0) bands.add_view(b, theta);
        outside += b < 0;
    }
    if (outside)
        std::cerr << "pxh: warning: " << outside << " rows have θ outside the bands ("
                  << bands.range() << "): they count only in the 'all' figures\n";
}

// Means per series and band over the ok rows only; failed rows only mark their setting's band
// (no budget is met where a row failed).
void ReportData::collect() {
    for (size_t r : ok) {
        const ResultRow& rr = row(r);
        const std::string s = series_of(rr), set = setting_of(rr);
        if (!series.count(s)) {
            series_order.push_back(s);
            series[s] = {set, rr.text("method"), group_of(rr), r, {}, {}};
            if (!settings.count(set)) setting_order.push_back(set);
            settings[set].series.push_back(s);
        }
        Series& ser = series[s];
        ser.all.add(rr, metric.column);
        const int b = bands.of(rr.num("theta_deg"));
        if (b < 0) continue;
        ser.band[size_t(b)].add(rr, metric.column);
        settings[set].band[size_t(b)].add(rr, metric.column);
    }
    for (size_t r : failed) {
        const int b = bands.of(row(r).num("theta_deg"));
        if (b >= 0) settings[setting_of(row(r))].failed_bands.insert(size_t(b));
    }
}

std::vector<size_t> ReportData::present_bands() const {
    std::vector<size_t> present;
    for (size_t i = 0; i < bands.size(); ++i)
        if (bands.present(i)) present.push_back(i);
    return present;
}

std::vector<std::string> ReportData::notes(bool with_bands) const {
    std::vector<std::string> n;
    if (!failed.empty())
        n.push_back(std::to_string(failed.size()) +
                    " failed rows (status not ok) are "
                    "left out of every figure here; they are listed in failed.md.");
    if (with_bands && !bands.note().empty()) n.push_back(bands.note());
    return n;
}

void ReportData::write(const std::string& rel, const std::string& text) const {
    const fs::path p = out / rel;
    std::ofstream f(p, std::ios::binary);
    f << text;
    if (!f) throw InputError(p.string(), "cannot write");
    std::cout << "wrote " << p.string() << "\n";
}

std::vector<bool> pareto(const std::vector<double>& cost, const std::vector<double>& err) {
    std::vector<bool> front(cost.size(), false);
    for (size_t i = 0; i < cost.size(); ++i) {
        if (!std::isfinite(cost[i]) || !std::isfinite(err[i])) continue;
        bool dominated = false;
        for (size_t j = 0; j < cost.size() && !dominated; ++j) {
            if (j == i || !std::isfinite(cost[j]) || !std::isfinite(err[j])) continue;
            dominated =
                cost[j] <= cost[i] && err[j] <= err[i] && (cost[j] < cost[i] || err[j] < err[i]);
        }
        front[i] = !dominated;
    }
    return front;
}

}  // namespace pxh
