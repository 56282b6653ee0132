// The metric families' tables and figure data, driven by the column registry alone
// (harness/metrics/columns.h: family, unit, direction, headline): a family a component brings
// gets its table and figure without a line here.
#include "harness/report/families.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <sstream>

#include "harness/core/params.h"
#include "harness/metrics/columns.h"
#include "harness/report/report_data.h"
#include "harness/report/text_table.h"
#include "harness/results/results.h"

namespace pxh {

namespace {

// Significant digits, "-" when missing: the families' numbers span decades (1e-6 tiles of depth
// to 30 texels), so fixed decimals would print most of them as 0.000.
std::string sig(double v) {
    if (!std::isfinite(v)) return std::isnan(v) ? "-" : (v > 0 ? "inf" : "-inf");
    if (v == 0) return "0";
    std::ostringstream o;
    o.precision(3);
    o << v;
    return o.str();
}

const char* better_text(Better b) {
    return b == Better::smaller  ? "smaller is better"
           : b == Better::larger ? "larger is better"
                                 : "";
}

std::string unit_text(const ColumnSpec& c) {
    return c.unit == "time_unit" ? "the row's time_unit" : c.unit;
}

// The series keys a family's rows are told apart by: every key of the run that can change the
// family and varies between its rows (sweep and field keys aside), method first.
std::vector<const ColumnSpec*> split_keys(const ReportData& d, const std::vector<size_t>& rows,
                                          const std::string& family) {
    std::vector<const ColumnSpec*> keys;
    for (const ColumnSpec* c : row_axes()) {
        if (sweep_key(c->name) || field_key(c->name) || !c->can_change(family)) continue;
        std::set<std::string> values;
        for (size_t r : rows) values.insert(d.row(r).cell(c->name));
        if (c->name == "method" || values.size() > 1) keys.push_back(c);
    }
    return keys;
}

// The rows a family draws on: ok rows with a value in one of its headline columns; where a key
// that cannot change the family varies, its first value's rows (noted in `held`).
std::vector<size_t> family_rows(const ReportData& d, const std::string& family,
                                const std::vector<const ColumnSpec*>& cols,
                                std::vector<std::string>* held) {
    std::vector<size_t> rows;
    for (size_t r : d.all_ok)
        if (std::any_of(cols.begin(), cols.end(),
                        [&](const ColumnSpec* c) { return std::isfinite(d.row(r).num(c->name)); }))
            rows.push_back(r);
    std::vector<std::pair<std::string, std::string>> keys;
    rows = d.held_rows(std::move(rows), family, &keys);
    for (const auto& [name, value] : keys) {
        const ColumnSpec* c = find_column(name);
        held->push_back((c ? c->shown_as() : name) + " = " + (value.empty() ? "(none)" : value));
    }
    return rows;
}

struct Key {
    std::vector<std::string> values;  // the split keys' cells
    bool operator<(const Key& o) const { return values < o.values; }
};

struct FamilyData {
    std::string name;
    std::vector<const ColumnSpec*> cols;  // headline columns with a value
    std::vector<size_t> rows;
    std::vector<std::string> held;
    std::vector<const ColumnSpec*> keys;  // split keys
    std::vector<Key> order;               // series in order of appearance
    // series -> band (or SIZE_MAX: all) -> column -> mean
    std::map<Key, std::map<size_t, std::vector<Mean>>> means;
    std::map<Key, size_t> first;  // a row of each series
    std::set<std::string> units;  // time_unit values of a timing family's rows
};

Key key_of(const FamilyData& f, const ResultRow& r) {
    Key k;
    for (const ColumnSpec* c : f.keys) k.values.push_back(r.cell(c->name));
    return k;
}

FamilyData collect(const ReportData& d, const std::string& family,
                   const std::vector<const ColumnSpec*>& cols) {
    FamilyData f;
    f.name = family;
    f.cols = cols;
    f.rows = family_rows(d, family, cols, &f.held);
    f.keys = split_keys(d, f.rows, family);
    for (size_t r : f.rows) {
        const ResultRow& row = d.row(r);
        const Key k = key_of(f, row);
        if (!f.means.count(k)) {
            f.order.push_back(k);
            f.first[k] = r;
        }
        auto& per_band = f.means[k];
        const int b = d.bands.of(row.num("theta_deg"));
        for (size_t band : {size_t(-1), size_t(b)}) {
            if (band != size_t(-1) && b < 0) continue;
            auto& m = per_band[band];
            m.resize(cols.size());
            for (size_t i = 0; i < cols.size(); ++i) m[i].add(row.num(cols[i]->name));
        }
        if (!row.text("time_unit").empty()) f.units.insert(row.text("time_unit"));
    }
    return f;
}

std::string key_header(const ColumnSpec* c) { return c->shown_as(); }

// One headline column's table: a line per series (a setting's backends whose printed numbers
// agree are one line, "cpu/float = glsl/r32f"), a column per band and all.
TextTable family_table(const ReportData& d, const FamilyData& f, size_t ci,
                       const std::vector<size_t>& bands) {
    // The backend, precision and texture format as one "backend" cell; a setting's
    // backends whose printed numbers agree are one line ("cpu/float = glsl/r32f").
    const auto is_group = [](const ColumnSpec* k) {
        return k->name == "backend" || k->name == "precision" || k->name == "texture_format";
    };
    TextTable t;
    bool group_cell = false;
    for (const ColumnSpec* k : f.keys) {
        if (is_group(k)) {
            if (!group_cell) t.header.push_back("backend");
            if (!group_cell) t.align += 'l';
            group_cell = true;
            continue;
        }
        t.header.push_back(key_header(k));
        t.align += 'l';
    }
    for (size_t b : bands) {
        t.header.push_back(d.bands.label(b));
        t.align += 'r';
    }
    t.header.push_back("all");
    t.align += 'r';
    struct Line {
        std::vector<std::string> head, numbers;
        std::string groups;
    };
    std::vector<Line> lines;
    for (const Key& k : f.order) {
        const auto& per_band = f.means.at(k);
        Line l;
        for (size_t i = 0; i < f.keys.size(); ++i)
            if (!is_group(f.keys[i])) l.head.push_back(k.values[i].empty() ? "-" : k.values[i]);
        l.groups = group_of(d.row(f.first.at(k)));
        bool any = false;
        for (size_t b : bands) {
            auto it = per_band.find(b);
            const double v = it == per_band.end() ? NAN : it->second[ci].get();
            any = any || std::isfinite(v);
            l.numbers.push_back(sig(v));
        }
        const double all = per_band.at(size_t(-1))[ci].get();
        any = any || std::isfinite(all);
        l.numbers.push_back(sig(all));
        if (!any) continue;
        auto same = std::find_if(lines.begin(), lines.end(), [&](const Line& o) {
            return o.head == l.head && o.numbers == l.numbers;
        });
        if (group_cell && same != lines.end()) same->groups += " = " + l.groups;
        else lines.push_back(l);
    }
    for (const Line& l : lines) {
        std::vector<std::string> cells;
        size_t h = 0;
        bool grouped = false;
        for (const ColumnSpec* k : f.keys) {
            if (is_group(k)) {
                if (!grouped) cells.push_back(l.groups);
                grouped = true;
            } else {
                cells.push_back(l.head[h++]);
            }
        }
        cells.insert(cells.end(), l.numbers.begin(), l.numbers.end());
        t.rows.push_back(cells);
    }
    return t;
}

// FAMILY.md: one table per headline column, a line per series, a column per angle band and
// all; FAMILY.csv: the same numbers, one line per series and band.
void write_family(const ReportData& d, const FamilyData& f) {
    const std::vector<size_t> bands = d.present_bands();
    std::ostringstream md, csv;
    md << "# " << family_title(f.name) << "\n\n"
       << "Means over the rows of each θ band of the per-row statistics (every φ and height "
          "field of the run pooled; fields.md has the texel error per field). A line per value "
          "of the keys that vary in the run and can change these numbers ("
       <<
        [&] {
            std::string k;
            for (const ColumnSpec* c : f.keys) k += (k.empty() ? "" : ", ") + c->shown_as();
            return k;
        }()
       << ").\n\n";
    if (!f.held.empty()) {
        md << "Keys that cannot change these numbers are held at one value: ";
        for (size_t i = 0; i < f.held.size(); ++i) md << (i ? ", " : "") << f.held[i];
        md << ".\n\n";
    }
    csv << "family";
    for (const ColumnSpec* c : f.keys) csv << "," << csv_quote(c->name);
    csv << ",band,theta_lo,theta_hi,rows";
    for (const ColumnSpec* c : f.cols) csv << "," << csv_quote(c->name);
    csv << "\n";
    for (size_t ci = 0; ci < f.cols.size(); ++ci) {
        const ColumnSpec& c = *f.cols[ci];
        std::string unit = unit_text(c);
        if (c.unit == "time_unit") {
            unit.clear();
            for (const auto& u : f.units) unit += (unit.empty() ? "" : " or ") + u;
        }
        md << "## " << c.name << (unit.empty() ? "" : " (" + unit + ")") << "\n\n"
           << c.meaning << (c.better == Better::none ? "" : "; ") << better_text(c.better)
           << ".\n\n";
        const TextTable t = family_table(d, f, ci, bands);
        if (t.rows.empty()) continue;
        md << t.markdown() << "\n";
    }
    for (const Key& k : f.order) {
        const auto& per_band = f.means.at(k);
        const auto line = [&](const std::string& band, double lo, double hi,
                              const std::vector<Mean>& m) {
            csv << csv_quote(f.name);
            for (const std::string& v : k.values) csv << "," << csv_quote(v);
            csv << "," << csv_quote(band) << "," << csv_num(lo) << "," << csv_num(hi) << ","
                << (m.empty() ? 0 : m[0].n);
            for (const Mean& x : m) csv << "," << csv_num(x.get());
            csv << "\n";
        };
        for (size_t b : bands)
            if (per_band.count(b))
                line(d.bands.edges(b), d.bands.lo(b), d.bands.hi(b), per_band.at(b));
        line("all", NAN, NAN, per_band.at(size_t(-1)));
    }
    for (const std::string& n : d.notes()) md << n << "\n\n";
    d.write("families/" + f.name + ".md", md.str());
    d.write("families/" + f.name + ".csv", csv.str());
}

// data/families/FAMILY_vs_X.csv: the headline columns' means per series, panel and x, for the
// plotter (harness/report/plot_families.py). x is θ, or another numeric key of the run with at
// least three values (a radius, a distance, a cut, a scale: means over θ, said in the axis
// label). The lines are the series keys (setting and group) that vary, the panels every other
// varying key (the view: base, radius, distance, ...); every field of the run pooled.
struct Figure {
    std::string x;  // a column name
    std::string file;
};

// The families whose curves against θ the report's own figures draw already: error_vs_theta
// (texel p50 and p95; a camera view's pixel error beside it) and sweep_vs_theta (sliding,
// shimmering). Their FAMILY_vs_theta would draw the same numbers twice; their curves against
// the run's other keys (a radius, a cut) are drawn.
bool drawn_elsewhere(const std::string& family) {
    return family == "texel" || family == "pixel" || family == "sliding";
}

// Whether every line of every panel is flat in x (all its points equal): a figure of flat
// lines says nothing its table does not (a precompute time against θ).
template <class Acc>
bool all_flat(const Acc& acc) {
    std::map<std::pair<std::string, std::string>, std::vector<double>> first;
    for (const auto& [k, m] : acc) {
        std::vector<double> v;
        for (const Mean& x : m) v.push_back(x.get());
        auto [it, fresh] = first.emplace(std::make_pair(std::get<0>(k), std::get<1>(k)), v);
        if (fresh) continue;
        for (size_t i = 0; i < v.size(); ++i)
            if (!(v[i] == it->second[i]) && !(std::isnan(v[i]) && std::isnan(it->second[i])))
                return false;
    }
    return true;
}

std::vector<Figure> write_figure_data(const ReportData& d, const FamilyData& f,
                                      bool theta_drawn_elsewhere) {
    std::vector<std::string> xs;
    if (!theta_drawn_elsewhere) xs.push_back("theta_deg");
    for (const ColumnSpec* c : f.keys) {
        if (!c->numeric()) continue;
        std::set<double> v;  // the key's values (NaN, a plane's radius, is no value: in a
                             // std::set it would compare equal to every later one)
        for (size_t r : f.rows)
            if (std::isfinite(d.row(r).num(c->name))) v.insert(d.row(r).num(c->name));
        if (v.size() >= 3) xs.push_back(c->name);
    }
    std::vector<Figure> figures;
    for (const std::string& x : xs) {
        // line: series keys; panel: the other keys but x
        using PKey = std::tuple<std::string, std::string, double>;  // panel, line, x
        std::map<PKey, std::vector<Mean>> acc;
        std::map<PKey, std::set<double>> thetas;
        std::vector<PKey> order;
        for (size_t r : f.rows) {
            const ResultRow& row = d.row(r);
            if (!std::isfinite(row.num(x))) continue;  // no value of x (a plane's radius)
            // line: the setting (method, params) and its backend group; panel: every other
            // key that varies (lod, depth, cut too: a figure keeps one line per setting and
            // backend, so its legend stays readable)
            std::string line = row.text("method"), panel;
            if (!row.text("params").empty()) line += " " + row.text("params");
            line += " [" + group_of(row) + "]";
            for (const ColumnSpec* c : f.keys) {
                if (c->name == x || c->name == "method" || c->name == "params" ||
                    c->name == "backend" || c->name == "precision" || c->name == "texture_format")
                    continue;
                const std::string v = row.cell(c->name);
                if (v.empty()) continue;  // a key the row has no value of (a plane's radius)
                panel += (panel.empty() ? "" : ", ") + c->shown_as() + " = " + v;
            }
            const PKey k{panel, line, row.num(x)};
            if (!acc.count(k)) order.push_back(k);
            auto& m = acc[k];
            m.resize(f.cols.size());
            for (size_t i = 0; i < f.cols.size(); ++i) m[i].add(row.num(f.cols[i]->name));
            thetas[k].insert(row.num("theta_deg"));
        }
        if (all_flat(acc)) continue;
        std::ostringstream o;
        o << "panel,line,x,rows,thetas";
        for (const ColumnSpec* c : f.cols) o << "," << csv_quote(c->name);
        o << "\n";
        for (const PKey& k : order) {
            const auto& m = acc.at(k);
            o << csv_quote(std::get<0>(k)) << "," << csv_quote(std::get<1>(k)) << ","
              << csv_num(std::get<2>(k)) << "," << m[0].n << "," << thetas.at(k).size();
            for (const Mean& x2 : m) o << "," << csv_num(x2.get());
            o << "\n";
        }
        const std::string file = "data/families/" + f.name + "_vs_" + x + ".csv";
        d.write(file, o.str());
        figures.push_back({x, file});
    }
    return figures;
}

}  // namespace

std::vector<std::string> family_names(const ReportData& d) {
    std::vector<std::string> names;
    for (const ColumnSpec* c : result_column_specs()) {
        if (c->role != ColumnRole::measured || c->family.empty() || !c->headline) continue;
        if (std::find(names.begin(), names.end(), c->family) != names.end()) continue;
        if (std::any_of(d.all_ok.begin(), d.all_ok.end(),
                        [&](size_t r) { return std::isfinite(d.row(r).num(c->name)); }))
            names.push_back(c->family);
    }
    return names;
}

void write_families(const ReportData& d) {
    const std::vector<std::string> names = family_names(d);
    if (names.empty()) return;
    d.folder().folder("families");
    d.folder().folder("data/families");
    std::ostringstream index;
    index << "family,title,x,x_unit,file,columns,units,better\n";
    for (const std::string& name : names) {
        std::vector<const ColumnSpec*> cols;
        for (const ColumnSpec* c : result_column_specs())
            if (c->role == ColumnRole::measured && c->family == name && c->headline &&
                std::any_of(d.all_ok.begin(), d.all_ok.end(),
                            [&](size_t r) { return std::isfinite(d.row(r).num(c->name)); }))
                cols.push_back(c);
        const FamilyData f = collect(d, name, cols);
        write_family(d, f);
        std::string columns, units, better;
        for (const ColumnSpec* c : cols) {
            std::string unit = c->unit;
            if (unit == "time_unit") {
                unit.clear();
                for (const auto& u : f.units) unit += (unit.empty() ? "" : " or ") + u;
            }
            columns += (columns.empty() ? "" : ";") + c->name;
            units += (units.empty() ? "" : ";") + unit;
            better +=
                std::string(better.empty() ? "" : ";") + (c->better == Better::smaller  ? "smaller"
                                                          : c->better == Better::larger ? "larger"
                                                                                        : "none");
        }
        // Values in two units (ns/sample and ms/frame) are not one axis: no figure (the
        // table has them per backend line; cost_vs_error draws each unit apart).
        if (f.units.size() > 1 && std::any_of(cols.begin(), cols.end(), [](const ColumnSpec* c) {
                return c->unit == "time_unit";
            }))
            continue;
        for (const Figure& fig : write_figure_data(d, f, drawn_elsewhere(name)))
            index << csv_quote(name) << "," << csv_quote(family_title(name)) << ","
                  << csv_quote(fig.x) << ","
                  << csv_quote(find_column(fig.x) ? find_column(fig.x)->unit : "") << ","
                  << csv_quote(fig.file) << "," << csv_quote(columns) << "," << csv_quote(units)
                  << "," << csv_quote(better) << "\n";
    }
    d.write("data/families/index.csv", index.str());
}

}  // namespace pxh
