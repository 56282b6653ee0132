#include "harness/results/results.h"

#include <algorithm>

#include "harness/core/error.h"
#include "harness/results/csv_table.h"
#include "harness/scene/base_surface.h"

namespace pxh {

std::string csv_quote(const std::string& s) {
    if (s.find_first_of(",\"\n") == std::string::npos) return s;
    std::string out = "\"";
    for (char c : s) out += c == '"' ? std::string("\"\"") : std::string(1, c);
    return out + "\"";
}

std::vector<std::string> result_columns() {
    std::vector<std::string> out;
    for (const ColumnSpec* c : result_column_specs()) out.push_back(c->name);
    return out;
}

std::string results_csv(const std::vector<ResultRow>& rows) {
    const auto specs = result_column_specs();
    std::vector<size_t> ids;
    std::string out;
    for (size_t c = 0; c < specs.size(); ++c) {
        out += (c ? "," : "") + specs[c]->name;
        ids.push_back(column_id(specs[c]->name));
    }
    out += "\n";
    for (const auto& r : rows) {
        const bool ok = r.ok();
        for (size_t c = 0; c < specs.size(); ++c) {
            if (c) out += ',';
            if (ok || specs[c]->role == ColumnRole::key) out += csv_quote(r.cell(ids[c]));
        }
        out += "\n";
    }
    return out;
}

std::string ResultsFile::where(size_t row) const {
    return path + ":" + std::to_string(row < lines.size() ? lines[row] : row + 2);
}

namespace {

// results.csv written before the backends named their own timing: CPU rows had ns_per_sample*,
// GLSL rows ms_per_frame*. Read as the columns they became, with the unit they were in (the
// one place that knows the old names; compare and report then see time and time_unit).
struct LegacyTiming {
    ColumnSpec old;    // the old column (its type as it was)
    const char* now;   // the column it is read as
    const char* unit;  // time_unit of a row with a value in it
};
const std::vector<LegacyTiming>& legacy_timing() {
    static const std::vector<LegacyTiming> cols = [] {
        std::vector<LegacyTiming> v;
        for (const auto& [prefix, unit] :
             {std::pair{"ns_per_sample", "ns/sample"}, std::pair{"ms_per_frame", "ms/frame"}}) {
            const std::string p = prefix;
            const auto old = [](std::string name, ColumnType type) {
                return ColumnSpec{std::move(name), type, ColumnRole::measured, "before time*"};
            };
            v.push_back({old(p, ColumnType::number), "time", unit});
            v.push_back({old(p + "_min", ColumnType::number), "time_min", unit});
            v.push_back({old(p + "_max", ColumnType::number), "time_max", unit});
            v.push_back({old(p + "_repeats", ColumnType::text), "time_repeats", unit});
        }
        return v;
    }();
    return cols;
}
const LegacyTiming* legacy_of(const ColumnSpec* spec) {
    for (const LegacyTiming& l : legacy_timing())
        if (spec == &l.old) return &l;
    return nullptr;
}

}  // namespace

bool ResultsFile::has(const std::string& column) const {
    const auto in_header = [&](const std::string& c) {
        return std::find(header.begin(), header.end(), c) != header.end();
    };
    if (in_header(column)) return true;
    for (const LegacyTiming& l : legacy_timing())
        if (column == l.now && in_header(l.old.name)) return true;
    return false;
}

std::vector<const ColumnSpec*> column_specs_of(const std::vector<std::string>& header) {
    std::vector<const ColumnSpec*> specs;
    for (const auto& name : header) {
        const ColumnSpec* spec = find_column(name);
        if (!spec)
            for (const LegacyTiming& l : legacy_timing())
                if (name == l.old.name) spec = &l.old;
        specs.push_back(spec);
    }
    return specs;
}

ResultRow parse_result_row(const std::vector<const ColumnSpec*>& specs,
                           const std::vector<std::string>& fields, const std::string& where) {
    ResultRow row;
    row.set_text("status", "");  // a file without a status column has no ok row
    for (size_t c = 0; c < specs.size() && c < fields.size(); ++c) {
        if (!specs[c]) continue;
        const std::string& cell = fields[c];
        const LegacyTiming* legacy = legacy_of(specs[c]);
        const std::string& name = legacy ? legacy->now : specs[c]->name;
        if (legacy && !cell.empty()) row.set_text("time_unit", legacy->unit);
        if (specs[c]->type == ColumnType::text) {
            if (!legacy || !cell.empty()) row.set_text(name, cell);
            continue;
        }
        if (cell.empty()) continue;
        const auto v = parse_number(cell);
        if (!v)
            throw InputError(where,
                             "column '" + specs[c]->name + "': '" + cell + "' is not a number");
        row.set(name, *v);
    }
    // results.csv written before every row stated its base left the plane's empty (or had no
    // base column): read as the base it was.
    if (row.text("base").empty()) row.set_text("base", default_base_name());
    return row;
}

ResultsFile read_results(const std::string& path) {
    const CsvTable t = read_csv(path);
    ResultsFile f;
    f.path = path;
    f.header = t.columns;
    f.lines = t.lines;
    const std::vector<const ColumnSpec*> specs = column_specs_of(t.columns);
    f.rows.reserve(t.rows.size());
    for (size_t r = 0; r < t.rows.size(); ++r)
        f.rows.push_back(parse_result_row(specs, t.rows[r], t.where(r)));
    return f;
}

std::string setting_of(const ResultRow& r) {
    const std::string& params = r.text("params");
    const std::string& lod = r.text("lod");
    const std::string& depth = r.text("depth");
    return r.text("method") + (params.empty() ? "" : " " + params) +
           (lod.empty() || lod == "base" ? "" : " lod=" + lod) +
           (depth.empty() || depth == "base" ? "" : " depth=" + depth) +
           (r.cell("cut").empty() ? "" : " cut=" + r.cell("cut"));
}

std::string group_of(const ResultRow& r) {
    const std::string& fmt = r.text("texture_format");
    return r.text("backend") + "/" + (fmt.empty() ? r.text("precision") : fmt);
}

std::string series_of(const ResultRow& r) { return setting_of(r) + " [" + group_of(r) + "]"; }

std::string field_of(const ResultRow& r) {
    return r.text("heightfield") + " s=" + r.cell("scale") + " b=" + r.cell("bias");
}

std::string row_name(const std::function<std::string(const std::string&)>& given) {
    // A key at its default is left out of the name, as lod and depth at base are: the base at
    // the default base (the plane), so a plane row is named as before every row stated it.
    const std::string plain = default_base_name();
    const auto cell = [&](const std::string& c) {
        std::string v = given(c);
        return c == "base" && v == plain ? std::string() : v;
    };
    const std::string params = cell("params"), lod = cell("lod"), fmt = cell("texture_format");
    const std::string depth = cell("depth");
    return cell("method") + (params.empty() ? "" : " " + params) +
           (lod.empty() || lod == "base" ? "" : " lod=" + lod) +
           (depth.empty() || depth == "base" ? "" : " depth=" + depth) +
           (cell("cut").empty() ? "" : " cut=" + cell("cut")) + " [" + cell("backend") + "/" +
           (fmt.empty() ? cell("precision") : fmt) + "] on " + cell("heightfield") +
           " s=" + cell("scale") + " b=" + cell("bias") + axes_name(cell);
}

std::string row_name(const ResultRow& r) {
    return row_name([&](const std::string& c) { return r.cell(c); });
}

}  // namespace pxh
