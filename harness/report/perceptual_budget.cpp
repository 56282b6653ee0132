#include "harness/report/perceptual_budget.h"

#include <cmath>
#include <map>
#include <set>
#include <sstream>

#include "harness/core/params.h"
#include "harness/results/results.h"

namespace pxh {

namespace {

// Per view, setting and band: each series' mean flip_mean, and whether some row of the
// setting there has none (or a non-finite output).
struct BandFlip {
    std::map<std::string, Mean> series;
    bool unmeasured = false;
};
using FlipMeans = std::map<std::string, std::map<std::string, std::map<size_t, BandFlip>>>;

FlipMeans flip_means(const ReportData& d) {
    FlipMeans m;
    for (size_t r : d.ok) {
        const ResultRow& row = d.row(r);
        const int b = d.bands.of(row.num("theta_deg"));
        if (b < 0) continue;
        BandFlip& bf = m[d.view_of(row)][setting_of(row)][size_t(b)];
        const double f = row.num("flip_mean");
        if (!std::isfinite(f) || row.num("nonfinite") > 0) bf.unmeasured = true;
        bf.series[series_of(row)].add(f);
    }
    return m;
}

bool meets(const BandFlip& bf, double budget) {
    if (bf.unmeasured || bf.series.empty()) return false;
    for (const auto& s : bf.series)
        if (!(s.second.get() <= budget)) return false;
    return true;
}

// The cheapest setting of the view meeting the budget in the band (fewest fetches per sample,
// then the order of the report's settings), as a cell.
std::string cheapest(const ReportData& d, const Part& p, const FlipMeans::mapped_type& view,
                     size_t band, double budget, bool tex) {
    const std::string* best = nullptr;
    double best_f = INFINITY;
    for (const std::string& name : d.setting_order) {
        auto sit = p.settings.find(name);
        auto fit = view.find(name);
        if (sit == p.settings.end() || fit == view.end()) continue;
        if (sit->second.failed_bands.count(band)) continue;
        auto bit = fit->second.find(band);
        if (bit == fit->second.end() || !meets(bit->second, budget)) continue;
        auto ait = sit->second.band.find(band);
        const double f = ait != sit->second.band.end() && std::isfinite(ait->second.fetches.get())
                             ? ait->second.fetches.get()
                             : INFINITY;
        if (!best || f < best_f) {
            best = &name;
            best_f = f;
        }
    }
    if (tex) return best ? d.tex_label.at(*best) + ", " + fmt(best_f, 1) : "--";
    return best ? *best + " (" + fmt(best_f, 1) + " fetches)" : "no setting meets this budget";
}

const char* const kNote =
    "Perceptual budget ([shading]): the cheapest method setting (fewest fetches per sample) "
    "whose mean flip_mean (LDR-FLIP of its shaded image against the truth's, "
    "docs/conventions.md section 13) over its rows in the band is at most the budget on every "
    "backend, precision and texture format it ran on, with no failed row, no non-finite output "
    "and no row without flip_mean there.";

}  // namespace

bool has_flip(const ReportData& d) {
    for (size_t r : d.ok)
        if (std::isfinite(d.row(r).num("flip_mean"))) return true;
    return false;
}

PerceptualBudget perceptual_budget(const ReportData& d) {
    if (!has_flip(d)) return {};
    const FlipMeans means = flip_means(d);
    const auto bands = d.present_bands();
    std::ostringstream md, tex;
    md << "\n# Perceptual budgets (flip_mean)\n";
    for (const std::string& v : d.view_order) {
        auto vit = means.find(v);
        if (vit == means.end()) continue;
        TextTable tt;
        tt.header.push_back("flip_mean budget");
        for (size_t b : bands) tt.header.push_back(d.bands.label(b));
        tt.align = "r" + std::string(bands.size(), 'l');
        TextTable tx = tt;
        for (double budget : kFlipBudgets) {
            std::vector<std::string> row = {format_number(budget)}, tex_row = row;
            for (size_t b : bands) {
                row.push_back(cheapest(d, d.views.at(v), vit->second, b, budget, false));
                tex_row.push_back(cheapest(d, d.views.at(v), vit->second, b, budget, true));
            }
            tt.rows.push_back(row);
            tx.rows.push_back(tex_row);
        }
        if (d.has_views()) md << "\n## " << ReportData::view_title(v) << "\n";
        md << "\n" << tt.markdown();
        tx.notes = {(d.has_views() ? "Camera view: " + ReportData::view_title(v) + "; " : "") +
                    std::string("mean flip_mean.")};
        tex << tx.latex(d.dir + "/results.csv") << "\n";
    }
    md << "\n" << kNote << "\n";
    tex << tex_text(kNote) << "\n";
    return {md.str(), tex.str()};
}

}  // namespace pxh
