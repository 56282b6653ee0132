// The report's tables: summary, failed rows, sweeps, precision, budgets.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <set>
#include <sstream>

#include "harness/core/error.h"
#include "harness/core/params.h"
#include "harness/metrics/columns.h"
#include "harness/report/perceptual_budget.h"
#include "harness/report/report_data.h"
#include "harness/results/error_maps.h"
#include "harness/scene/view.h"

namespace pxh {

namespace {

// One line of summary.csv / fields.csv: a series over a band (or "all"); `lead` holds the
// fields before it (fields.csv: the height field).
void summary_csv_line(std::ostream& csv, const ReportData& d, const std::string& lead,
                      const std::string& s, const Series& ser, const std::string& band, double lo,
                      double hi, size_t views, const Acc& a) {
    csv << lead << csv_quote(s) << "," << csv_quote(ser.setting) << "," << csv_quote(ser.method)
        << "," << csv_quote(ser.group) << "," << csv_quote(band) << "," << csv_num(lo) << ","
        << csv_num(hi) << "," << (views ? std::to_string(views) : "") << ","
        << csv_num(a.err_mean.get()) << "," << csv_num(a.err_p50.get()) << ","
        << csv_num(a.err_p95.get()) << "," << csv_num(a.worst_p95) << ","
        << csv_num(a.fetches.get());
    for (const std::string& u : d.time_units) csv << "," << csv_num(a.time_in(u));
    csv << "," << csv_num(a.sliding.get()) << "," << csv_num(a.shimmering.get());
    if (d.has_views())
        csv << "," << csv_num(a.px_mean.get()) << "," << csv_num(a.px_p95.get()) << ","
            << csv_num(a.sliding_dist.get()) << "," << csv_num(a.shimmering_dist.get());
    csv << "\n";
}

// A camera run's view as the leading CSV fields: a value per camera key column of the run.
std::vector<std::string> view_keys(const ReportData& d) {
    return d.has_views() ? d.context_keys : std::vector<std::string>{};
}
std::string view_key_list(const ReportData& d) {
    std::string out;
    for (const std::string& k : view_keys(d)) out += (out.empty() ? "" : ", ") + k;
    return out;
}
std::string view_fields(const ReportData& d, const std::string& view) {
    std::string out;
    for (const std::string& k : view_keys(d)) {
        std::string value;
        std::stringstream ss(view);
        for (std::string kv; ss >> kv;)
            if (kv.rfind(k + "=", 0) == 0) value = kv.substr(k.size() + 1);
        out += value + ",";
    }
    return out;
}

// The header of summary.csv / fields.csv: a time[UNIT] column per time_unit of the rows.
std::string summary_columns(const ReportData& d) {
    std::string h =
        "series,setting,method,group,band,theta_lo,theta_hi,band_views,err_mean,err_p50,err_p95,"
        "err_p95_worst,fetches_mean";
    for (const std::string& u : d.time_units) h += "," + csv_quote("time[" + u + "]");
    h += ",sliding,shimmering";
    if (d.has_views()) {
        std::string keys;
        for (const std::string& k : view_keys(d)) keys += k + ",";
        h = keys + h + ",err_px_mean,err_px_p95,sliding_dist,shimmering_dist";
    }
    return h + "\n";
}

// Every band row and the "all" row of a series.
void summary_csv(std::ostream& csv, const ReportData& d, const std::string& lead,
                 const std::string& s, const Series& ser) {
    for (size_t b : d.present_bands()) {
        auto it = ser.band.find(b);
        if (it == ser.band.end()) continue;
        summary_csv_line(csv, d, lead, s, ser, d.bands.label(b), d.bands.lo(b), d.bands.hi(b),
                         d.bands.views(b), it->second);
    }
    summary_csv_line(csv, d, lead, s, ser, "all", NAN, NAN, 0, ser.all);
}

// A line of a table: the series of one setting whose shown numbers agree, written once.
struct Line {
    std::string setting;
    std::vector<const Series*> members;
};

// The lines of the series in `sers`, setting by setting (in the report's order), a setting's
// series merged when `shown` gives them the same cells.
template <class Shown>
std::vector<Line> merge_lines(const ReportData& d, const std::map<std::string, Series>& sers,
                              const Shown& shown) {
    std::vector<Line> lines;
    for (const auto& set : d.setting_order) {
        const size_t first = lines.size();
        std::vector<std::vector<std::string>> cells;
        for (const auto& s : d.settings.at(set).series) {
            auto it = sers.find(s);
            if (it == sers.end()) continue;
            const auto c = shown(it->second);
            size_t i = 0;
            while (i < cells.size() && cells[i] != c) ++i;
            if (i == cells.size()) {
                lines.push_back({set, {}});
                cells.push_back(c);
            }
            lines[first + i].members.push_back(&it->second);
        }
    }
    return lines;
}

// A line's name: in Markdown the setting and every group it stands for
// ("pom layers=8 [cpu/float = glsl/r32f]"); in LaTeX the compact label, with the short groups
// when the report has more than one.
std::string md_name(const Line& l) {
    std::string g;
    for (const Series* s : l.members) g += (g.empty() ? "" : " = ") + s->group;
    return l.setting + " [" + g + "]";
}
std::string tex_name(const ReportData& d, const Line& l, bool with_groups = true) {
    const std::string& label = d.tex_label.at(l.setting);
    if (d.group_order.size() < 2 || !with_groups) return label;
    std::string g;
    for (const Series* s : l.members) g += (g.empty() ? "" : " = ") + d.short_group(s->group);
    return label + " [" + g + "]";
}

// A time to three significant digits in fixed notation, whatever its unit: "10.0", "0.500",
// "0.0271", "1234".
std::string time_text(double v) {
    const int magnitude = v > 0 ? int(std::floor(std::log10(v))) : 0;
    return fmt(v, std::clamp(2 - magnitude, 0, 6));
}

// Three significant digits in fixed notation ("0.250", "0.00123"), "-" when missing.
std::string sig3(double v) { return std::isfinite(v) ? time_text(v) : "-"; }

// A time cell of a line: the value of each member that has one (a series has a time in its
// backend's unit only), distinct values joined.
template <class Get>
std::string time_cell(const Line& l, const Get& get) {
    std::vector<std::string> vals;
    for (const Series* s : l.members) {
        const double v = get(*s);
        if (!std::isfinite(v)) continue;
        const std::string t = time_text(v);
        if (std::find(vals.begin(), vals.end(), t) == vals.end()) vals.push_back(t);
    }
    if (vals.empty()) return "-";
    std::string out;
    for (const auto& v : vals) out += (out.empty() ? "" : " / ") + v;
    return out;
}

const char* const kMergeNote =
    "A row stands for every backend / precision / texture format in its brackets: their "
    "numbers in it agree as shown (printed once); where they differ each has its own row.";

// The summary table of a set of series (all fields pooled, or one field): Markdown and LaTeX
// (narrower: "mean / p95" said once in a note, and the groups left out of the rows when every
// row stands for all of them).
std::pair<TextTable, TextTable> series_tables(const ReportData& d,
                                              const std::map<std::string, Series>& sers) {
    const auto bands = d.present_bands();
    TextTable md, tex;
    md.header.push_back("method");
    tex.header.push_back("method");
    // A camera run: pixel error beside texel error in every band.
    const bool px = d.pixel_error;
    for (size_t b : bands) {
        md.header.push_back(d.bands.label(b) + (px ? " texel mean / p95" : " mean / p95"));
        tex.header.push_back(d.bands.label(b) + (px ? " texel" : ""));
        if (!px) continue;
        md.header.push_back(d.bands.label(b) + " pixel mean / p95");
        tex.header.push_back(d.bands.label(b) + " pixel");
    }
    const size_t band_columns = bands.size() * (px ? 2 : 1);
    std::vector<std::string> costs{"fetches"};
    for (const std::string& u : d.time_units) costs.push_back("time (" + u + ")");
    for (const std::string& h : costs) {
        md.header.push_back(h);
        tex.header.push_back(h);
    }
    md.align = tex.align = "l" + std::string(band_columns + costs.size(), 'r');
    const auto shown = [&](const Series& ser) {
        std::vector<std::string> c;
        for (size_t b : bands) {
            auto it = ser.band.find(b);
            c.push_back(it == ser.band.end() ? "-"
                                             : fmt(it->second.err_mean.get()) + " / " +
                                                   fmt(it->second.err_p95.get()));
            if (px)  // three significant digits: far away pixel errors are 1e-3 and less
                c.push_back(it == ser.band.end() ? "-"
                                                 : sig3(it->second.px_mean.get()) + " / " +
                                                       sig3(it->second.px_p95.get()));
        }
        c.push_back(fmt(ser.all.fetches.get(), 1));
        return c;
    };
    const auto lines = merge_lines(d, sers, shown);
    std::vector<std::string> groups;  // the groups of these series
    for (const auto& [name, ser] : sers)
        if (std::find(groups.begin(), groups.end(), ser.group) == groups.end())
            groups.push_back(ser.group);
    const bool all_merged = std::all_of(lines.begin(), lines.end(), [&](const Line& l) {
        return l.members.size() == groups.size();
    });
    for (const Line& l : lines) {
        std::vector<std::string> row = shown(*l.members.front());
        for (const std::string& u : d.time_units)
            row.push_back(time_cell(l, [&u](const Series& s) { return s.all.time_in(u); }));
        row.insert(row.begin(), md_name(l));
        md.rows.push_back(row);
        row.front() = tex_name(d, l, !all_merged);
        tex.rows.push_back(row);
    }
    tex.notes.push_back(px ? "Band cells: mean / p95 texel error (texel), mean / p95 pixel "
                             "error (pixel)."
                           : "Band cells: mean / p95 texel error.");
    if (all_merged && groups.size() > 1 && !lines.empty()) {
        std::string g;
        for (const Series* s : lines.front().members)
            g += (g.empty() ? "" : " = ") + d.short_group(s->group);
        tex.notes.push_back("Every row stands for " + g +
                            ": their numbers agree as shown (printed once).");
    }
    return {md, tex};
}

std::vector<std::string> summary_notes(const ReportData& d, bool tex) {
    auto notes = d.notes();
    notes.push_back(
        "Texel error, mean over rows of the per-row mean / 95th percentile, per "
        "band of the view angle θ (degrees); fetches and times over all angles.");
    if (d.pixel_error)
        notes.push_back(
            "Pixel error: the same means of err_px_mean / err_px_p95, the texel error seen on "
            "the screen (|J⁻¹ e|, screen pixels): what a viewer of the camera's image sees.");
    if (d.has_views())
        notes.push_back(
            "One table per camera view (its keys: " + view_key_list(d) +
            "): a mean over distances would mix errors that differ by orders of magnitude.");
    notes.push_back(kMergeNote);
    if (tex) notes.push_back("Method labels and their parameters: legend.tex.");
    return notes;
}

// A height field's name as a file name: safe characters only.
std::string file_name_of(const std::string& field) {
    std::string out;
    for (char c : field) {
        const bool keep = std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '-';
        if (keep) out += c;
        else if (out.empty() || out.back() != '_') out += '_';
    }
    return out.empty() ? "field" : out;
}

}  // namespace

// summary.csv / .md / .tex: per series (merged in .md / .tex), mean / p95 per band, cost.
void write_summary(const ReportData& d) {
    std::ostringstream csv;
    csv << summary_columns(d);
    if (!d.has_views()) {
        for (const auto& s : d.series_order) summary_csv(csv, d, "", s, d.series.at(s));
        auto [md, tex] = series_tables(d, d.series);
        md.notes = summary_notes(d, false);
        const auto extra = tex.notes;
        tex.notes = summary_notes(d, true);
        tex.notes.insert(tex.notes.begin(), extra.begin(), extra.end());
        d.write("summary.csv", csv.str());
        d.write("summary.md", md.markdown());
        d.write("summary.tex", tex.latex(d.dir + "/results.csv"));
        return;
    }
    // A camera run: a table per view, the notes once at the end.
    std::ostringstream md, tex;
    md << "# Summary per camera view\n";
    for (const auto& v : d.view_order) {
        const auto& sers = d.views.at(v).series;
        for (const auto& s : d.series_order)
            if (sers.count(s)) summary_csv(csv, d, view_fields(d, v), s, sers.at(s));
        auto [m, t] = series_tables(d, sers);
        md << "\n## " << ReportData::view_title(v) << "\n\n" << m.markdown();
        t.notes.insert(t.notes.begin(), "Camera view: " + ReportData::view_title(v) + ".");
        tex << t.latex(d.dir + "/results.csv") << "\n";
    }
    md << "\n";
    for (const auto& n : summary_notes(d, false)) md << n << "\n\n";
    for (const auto& n : summary_notes(d, true)) tex << tex_text(n) << "\n\n";
    d.write("summary.csv", csv.str());
    d.write("summary.md", md.str());
    d.write("summary.tex", tex.str());
}

// fields.csv / fields.md / fields/FIELD.tex: the summary of each height field on its own.
void write_fields(const ReportData& d) {
    std::ostringstream csv, md;
    csv << "heightfield," << summary_columns(d);
    md << "# Per height field\n\nThe summary table (summary.md) of each height field on its own "
          "rows.\n";
    d.folder().folder("fields");
    std::set<std::string> names;
    for (const auto& field : d.field_order) {
        // a camera run: a table per view of the field (fields/FIELD_d4_f45_r256.tex)
        std::vector<std::pair<std::string, const std::map<std::string, Series>*>> parts;
        if (!d.has_views()) parts.emplace_back("", &d.field_series.at(field));
        else
            for (const auto& v : d.view_order)
                if (d.field_views.at(field).count(v))
                    parts.emplace_back(v, &d.field_views.at(field).at(v).series);
        if (d.has_views()) md << "\n## " << one_line(field) << "\n";
        for (const auto& [view, sers_p] : parts) {
            const auto& sers = *sers_p;
            for (const auto& s : d.series_order)
                if (sers.count(s))
                    summary_csv(csv, d, csv_quote(field) + "," + view_fields(d, view), s,
                                sers.at(s));
            auto [m, t] = series_tables(d, sers);
            if (d.has_views())
                md << "\n### " << ReportData::view_title(view) << "\n\n" << m.markdown();
            else md << "\n## " << one_line(field) << "\n\n" << m.markdown();
            const std::string stem =
                file_name_of(field) +
                (view.empty() ? "" : d.tag_of(d.row(sers.begin()->second.first_row)));
            std::string name = stem;
            for (int k = 2; names.count(name); ++k) name = stem + "_" + std::to_string(k);
            names.insert(name);
            const auto extra = t.notes;
            t.notes = summary_notes(d, true);
            t.notes.insert(t.notes.begin(), extra.begin(), extra.end());
            if (!view.empty())
                t.notes.insert(t.notes.begin(),
                               "Camera view: " + ReportData::view_title(view) + ".");
            t.notes.insert(t.notes.begin(), "Height field: " + field + ".");
            d.write("fields/" + name + ".tex", t.latex(d.dir + "/results.csv"));
        }
    }
    md << "\n";
    for (const auto& n : summary_notes(d, false)) md << n << "\n\n";
    d.write("fields.csv", csv.str());
    d.write("fields.md", md.str());
}

// legend.md / legend.tex: each LaTeX label and the full parameters of its setting.
void write_legend(const ReportData& d) {
    TextTable tt;
    tt.header = {"label", "parameters"};
    tt.align = "ll";
    tt.latex_columns = "lp{0.6\\linewidth}";
    for (const auto& set : d.setting_order) {
        const ResultRow& r = d.row(d.series.at(d.settings.at(set).series.front()).first_row);
        std::string params;
        std::stringstream ss(r.text("params"));
        for (std::string p; std::getline(ss, p, ';');)
            if (!p.empty()) params += (params.empty() ? "" : ", ") + p;
        tt.rows.push_back({d.tex_label.at(set), params.empty() ? "-" : params});
    }
    tt.notes.push_back(
        "The method labels of the LaTeX tables: the method and, in parentheses, the values of "
        "the fewest parameters that tell its settings apart (letters when those are long); "
        "here each label's full parameters as results.csv writes them.");
    d.write("legend.md", tt.markdown());
    d.write("legend.tex", tt.latex(d.dir + "/results.csv"));
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

// sweep.md: sliding / shimmering per series and band (when measured), and a camera run's
// sliding_dist / shimmering_dist (what crawls as the eye moves away), a table per view.
void write_sweep(const ReportData& d) {
    bool angle = false, dist = false;
    for (const auto& s : d.series_order) {
        angle |= d.series.at(s).all.shimmering.n > 0;
        dist |= d.series.at(s).all.shimmering_dist.n > 0;
    }
    if (!angle && !dist) return;
    const auto bands = d.present_bands();
    const auto table = [&](const std::map<std::string, Series>& sers) {
        TextTable tt;
        tt.header.push_back("method");
        for (size_t b : bands) {
            if (angle) tt.header.push_back(d.bands.label(b) + " sliding / shimmering");
            if (dist) tt.header.push_back(d.bands.label(b) + " sliding_dist / shimmering_dist");
        }
        tt.align = "l" + std::string(bands.size() * (size_t(angle) + size_t(dist)), 'r');
        const auto shown = [&](const Series& ser) {
            std::vector<std::string> c;
            for (size_t b : bands) {
                auto it = ser.band.find(b);
                const bool none = it == ser.band.end();
                if (angle)
                    c.push_back(none ? "-"
                                     : fmt(it->second.sliding.get()) + " / " +
                                           fmt(it->second.shimmering.get()));
                if (dist)
                    c.push_back(none ? "-"
                                     : sig3(it->second.sliding_dist.get()) + " / " +
                                           sig3(it->second.shimmering_dist.get()));
            }
            return c;
        };
        for (const Line& l : merge_lines(d, sers, shown)) {
            std::vector<std::string> row = shown(*l.members.front());
            row.insert(row.begin(), md_name(l));
            tt.rows.push_back(row);
        }
        return tt;
    };
    std::vector<std::string> notes = d.notes();
    if (angle)
        notes.push_back(
            "Texels per degree of view change (docs/conventions.md section 5.3): "
            "sliding = |mean change of the error vector| / dt, shimmering = mean "
            "|change - mean change| / dt.");
    if (dist)
        notes.push_back(
            "sliding_dist / shimmering_dist: the same between consecutive eye distances, in "
            "texels per tile of eye distance (README, sliding_dist); on the nearer view's row, "
            "so the farthest distance has none (-).");
    notes.push_back(kMergeNote);
    if (!d.has_views()) {
        TextTable tt = table(d.series);
        tt.notes = notes;
        d.write("sweep.md", tt.markdown());
        return;
    }
    std::ostringstream md;
    md << "# Sweeps per camera view\n";
    for (const auto& v : d.view_order)
        md << "\n## " << ReportData::view_title(v) << "\n\n"
           << table(d.views.at(v).series).markdown();
    md << "\n";
    for (const auto& n : notes) md << n << "\n\n";
    d.write("sweep.md", md.str());
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

// The error a budget table ranks by: a column's means in Acc (budget: --budget-metric's,
// px_budget: err_px_p95).
struct Ranking {
    const char* header;
    std::string meaning, column;
    std::vector<double> budgets;
    Mean Acc::*mean;
};

// Does a setting meet a budget in a band? Only if no row of it failed there, none had
// non-finite outputs, and every one of its series (backend, precision, texture format) with
// rows there is within the budget: the conservative reading.
bool meets(const Part& p, const Setting& set, size_t band, double budget, const Ranking& k) {
    if (set.failed_bands.count(band)) return false;
    bool any = false;
    for (const auto& s : set.series) {
        const auto& bands = p.series.at(s).band;
        auto it = bands.find(band);
        if (it == bands.end()) continue;
        if (it->second.nonfinite || !((it->second.*k.mean).get() <= budget)) return false;
        any = true;
    }
    return any;
}

// The cheapest setting meeting a budget in a band (fewest fetches, then the time in each
// time_unit of the report, in order), as a cell (the setting's LaTeX label with `tex`).
std::string cheapest(const ReportData& d, const Part& p, size_t b, double budget, bool tex,
                     const Ranking& k) {
    const std::string* best = nullptr;
    double best_f = INFINITY;  // missing counts as the dearest
    std::vector<double> best_t;
    for (const auto& name : d.setting_order) {
        auto sit = p.settings.find(name);
        if (sit == p.settings.end()) continue;
        const Setting& set = sit->second;
        if (!meets(p, set, b, budget, k)) continue;
        const Acc& a = set.band.at(b);
        const double f = std::isfinite(a.fetches.get()) ? a.fetches.get() : INFINITY;
        std::vector<double> t;
        for (const std::string& u : d.time_units)
            t.push_back(std::isfinite(a.time_in(u)) ? a.time_in(u) : INFINITY);
        if (!best || f < best_f || (f == best_f && t < best_t)) {
            best = &name;
            best_f = f;
            best_t = t;
        }
    }
    if (tex) return best ? d.tex_label.at(*best) + ", " + fmt(best_f, 1) : "--";
    return best ? *best + " (" + fmt(best_f, 1) + " fetches)" : "no setting meets this budget";
}

// The budget table of one part (every row, or one camera view) under one ranking.
std::pair<TextTable, TextTable> budget_tables(const ReportData& d, const Part& p,
                                              const Ranking& k) {
    const auto bands = d.present_bands();
    TextTable tt;
    tt.header.push_back(k.header);
    for (size_t b : bands) tt.header.push_back(d.bands.label(b));
    tt.align = "r" + std::string(bands.size(), 'l');
    TextTable tex = tt;
    for (double budget : k.budgets) {
        std::vector<std::string> row = {format_number(budget)}, tex_row = row;
        for (size_t b : bands) {
            row.push_back(cheapest(d, p, b, budget, false, k));
            tex_row.push_back(cheapest(d, p, b, budget, true, k));
        }
        tt.rows.push_back(row);
        tex.rows.push_back(tex_row);
    }
    return {tt, tex};
}

std::string budget_note(const Ranking& k) {
    return std::string(
               "Cheapest method setting (fewest fetches, height and map lookups, per "
               "sample, then time, unit by unit, over its rows in the band) whose "
               "mean ") +
           k.meaning + " (`" + k.column +
           "`) in the band is within the budget on every backend, precision and "
           "texture format it ran on, with no failed row and no non-finite "
           "output there.";
}

}  // namespace

// budget.md / budget.tex: per band and budget, the cheapest method setting meeting it. A
// camera run: per view, ranked first by pixel error (err_px_p95: what the camera's image
// shows), then by the --budget-metric's texel error.
void write_budget(const ReportData& d) {
    const Ranking texel{d.metric.header, d.metric.meaning, d.metric.column, d.metric.budgets,
                        &Acc::budget};
    const char* const kTexNote =
        "A cell: the setting, its fetches per sample; --: no setting meets this budget. Method "
        "labels and their parameters: legend.tex.";
    if (!d.has_views()) {
        Part all{d.series, d.settings};
        auto [tt, tex] = budget_tables(d, all, texel);
        tt.notes = d.notes();
        tt.notes.push_back(budget_note(texel));
        tex.notes = tt.notes;
        tex.notes.push_back(kTexNote);
        const PerceptualBudget flip = perceptual_budget(d);
        d.write("budget.md", tt.markdown() + flip.markdown);
        d.write("budget.tex", tex.latex(d.dir + "/results.csv") + flip.latex);
        return;
    }
    const Ranking pixel{"p95 budget (pixels)",
                        "95th-percentile pixel error",
                        "err_px_p95",
                        {0.1, 0.25, 0.5, 1, 2, 4},
                        &Acc::px_budget};
    std::vector<const Ranking*> rankings;
    if (d.pixel_error) rankings.push_back(&pixel);
    rankings.push_back(&texel);
    std::ostringstream md, tex;
    md << "# Budgets per camera view\n";
    for (const auto& v : d.view_order) {
        md << "\n## " << ReportData::view_title(v) << "\n";
        for (const Ranking* k : rankings) {
            auto [m, t] = budget_tables(d, d.views.at(v), *k);
            md << "\n" << m.markdown();
            t.notes = {"Camera view: " + ReportData::view_title(v) + "; " + k->meaning + "."};
            tex << t.latex(d.dir + "/results.csv") << "\n";
        }
    }
    std::vector<std::string> notes = d.notes();
    if (d.pixel_error)
        notes.push_back(
            "A camera run: ranked first by pixel error (err_px_p95, the error on the screen, "
            "which shrinks with distance as texels shrink), then by the texel error "
            "(--budget-metric).");
    for (const Ranking* k : rankings) notes.push_back(budget_note(*k));
    md << "\n";
    for (const auto& n : notes) md << n << "\n\n";
    for (const auto& n : notes) tex << tex_text(n) << "\n\n";
    tex << tex_text(kTexNote) << "\n";
    const PerceptualBudget flip = perceptual_budget(d);  // [shading] runs
    md << flip.markdown;
    tex << flip.latex;
    d.write("budget.md", md.str());
    d.write("budget.tex", tex.str());
}

}  // namespace pxh
