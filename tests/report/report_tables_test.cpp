// The report's tables for papers: identical backends merged into one row (and only those),
// one table per height field with that field's numbers, the compact LaTeX method labels and
// their legend (one-to-one), booktabs rules and no vertical rules in every .tex table.
#include <OpenImageIO/imagebuf.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "harness/report/report.h"
#include "harness/report/report_data.h"
#include "harness/results/csv_table.h"
#include "harness/results/error_maps.h"
#include "harness/results/results.h"
#include "tests/cli_util.h"
#include "tests/report/report_folder.h"

namespace {

namespace fs = std::filesystem;
using pxh::test::Cells;

const std::vector<std::string> kColumns = {
    "method",         "params",    "heightfield",  "scale",    "bias",      "backend", "precision",
    "texture_format", "theta_deg", "phi_deg",      "err_mean", "err_p50",   "err_p95", "err_p99",
    "frac_gt_1",      "nonfinite", "fetches_mean", "time",     "time_unit", "status"};

// An ok row of `method params` on `field` (s = 0.05, b = 1) at θ, CPU float or GLSL r32f.
Cells row(const std::string& method, const std::string& params, const std::string& field, bool glsl,
          double theta, double err_mean, double err_p95, double fetches = 8) {
    char th[32], em[32], ep[32], fe[32];
    std::snprintf(th, sizeof th, "%g", theta);
    std::snprintf(em, sizeof em, "%.17g", err_mean);
    std::snprintf(ep, sizeof ep, "%.17g", err_p95);
    std::snprintf(fe, sizeof fe, "%.17g", fetches);
    return {{"method", method},
            {"params", params},
            {"heightfield", field},
            {"scale", "0.05"},
            {"bias", "1"},
            {"backend", glsl ? "glsl" : "cpu"},
            {"precision", "float"},
            {"texture_format", glsl ? "r32f" : ""},
            {"theta_deg", th},
            {"phi_deg", "0"},
            {"err_mean", em},
            {"err_p50", em},
            {"err_p95", ep},
            {"err_p99", ep},
            {"frac_gt_1", "0"},
            {"nonfinite", "0"},
            {"fetches_mean", fe},
            {"time", glsl ? "0.5" : "10"},
            {"time_unit", glsl ? "ms/frame" : "ns/sample"},
            {"status", "ok"}};
}

std::string f3(double v) {
    char b[32];
    std::snprintf(b, sizeof b, "%.3f", v);
    return b;
}

class ReportTables : public pxh::test::CliTest {
  protected:
    fs::path results(const std::vector<Cells>& rows,
                     const std::vector<std::string>& columns = kColumns,
                     const std::string& name = "res") {
        return pxh::test::write_results_folder(dir, columns, rows, name);
    }
    static fs::path report(const fs::path& res) { return pxh::test::report_tables_of(res); }
    static std::vector<std::string> md_row(const std::string& md, const std::string& first) {
        return pxh::test::markdown_row(md, first);
    }
    static int count(const std::string& text, const std::string& what) {
        int n = 0;
        for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1))
            ++n;
        return n;
    }
};

// A CPU and a GLSL series whose shown numbers agree are one row naming both, with the numbers
// of either and each backend's time; a setting whose GLSL error differs in the shown digits
// keeps a row per backend, each with its own numbers.
TEST_F(ReportTables, IdenticalBackendsMergedDifferentOnesApart) {
    std::vector<Cells> rows;
    for (bool glsl : {false, true}) {
        // pom layers=8: the GLSL twin differs below the third decimal (0.1234 vs 0.1231)
        rows.push_back(row("pom", "layers=8", "bricks", glsl, 10, glsl ? 0.1231 : 0.1234, 0.5));
        rows.push_back(row("pom", "layers=8", "bricks", glsl, 20, 0.3, 0.7));
        // parallax: the GLSL twin differs in the shown digits (0.200 vs 0.210)
        rows.push_back(row("parallax", "", "bricks", glsl, 10, glsl ? 0.21 : 0.2, 0.9, 1));
        rows.push_back(row("parallax", "", "bricks", glsl, 20, 0.2, 0.9, 1));
    }
    const fs::path rep = report(results(rows));
    const std::string md = slurp(rep / "summary.md");
    // pom: one row, both groups, band mean = (0.1234 + 0.3) / 2 = 0.2117 (CPU), p95 0.6
    const auto pom = md_row(md, "pom layers=8 [cpu/float = glsl/r32f]");
    ASSERT_EQ(pom.size(), 4u) << md;
    EXPECT_EQ(pom[0], f3((0.1234 + 0.3) / 2) + " / " + f3(0.6)) << md;
    EXPECT_EQ(pom[1], "8.0");
    EXPECT_EQ(pom[2], "10.0");   // time (ns/sample), from the CPU series
    EXPECT_EQ(pom[3], "0.500");  // time (ms/frame), from the GLSL series
    EXPECT_EQ(count(md, "| pom layers=8 ["), 1) << md;
    // parallax: two rows, each its own band mean
    const auto cpu = md_row(md, "parallax [cpu/float]");
    const auto gl = md_row(md, "parallax [glsl/r32f]");
    ASSERT_EQ(cpu.size(), 4u) << md;
    ASSERT_EQ(gl.size(), 4u) << md;
    EXPECT_EQ(cpu[0], f3(0.2) + " / " + f3(0.9));
    EXPECT_EQ(gl[0], f3((0.21 + 0.2) / 2) + " / " + f3(0.9));
    EXPECT_EQ(cpu[2], "10.0");
    EXPECT_EQ(cpu[3], "-");  // the CPU series has no frame time
    EXPECT_EQ(gl[2], "-");
    EXPECT_EQ(gl[3], "0.500");
    EXPECT_EQ(count(md, "| parallax ["), 2) << md;
    // LaTeX: the same rows under the compact labels, groups shortened
    const std::string tex = slurp(rep / "summary.tex");
    EXPECT_NE(tex.find("\npom [cpu = glsl] & " + f3((0.1234 + 0.3) / 2)), std::string::npos) << tex;
    EXPECT_NE(tex.find("\nparallax [cpu] & 0.200"), std::string::npos) << tex;
    EXPECT_NE(tex.find("\nparallax [glsl] & 0.205"), std::string::npos) << tex;
    // summary.csv keeps one line per series and band (the data, unrounded)
    const pxh::CsvTable csv = pxh::read_csv((rep / "summary.csv").string());
    std::set<std::string> series;
    for (size_t r = 0; r < csv.rows.size(); ++r) series.insert(csv.get(r, "series"));
    EXPECT_EQ(series.size(), 4u);
    // A cost column per time unit of the rows, named by it, in order of appearance
    const auto header =
        md.substr(md.find("| method"), md.find('\n', md.find("| method")) - md.find("| method"));
    EXPECT_NE(header.find("| fetches | time (ns/sample) | time (ms/frame) |"), std::string::npos)
        << header;
    EXPECT_GE(csv.index("time[ns/sample]"), 0);
    EXPECT_GE(csv.index("time[ms/frame]"), 0);
    for (size_t r = 0; r < csv.rows.size(); ++r) {
        const bool is_gl = csv.get(r, "group") == "glsl/r32f";
        EXPECT_EQ(csv.get(r, "time[ns/sample]"), is_gl ? "" : "10") << r;
        EXPECT_EQ(csv.get(r, "time[ms/frame]"), is_gl ? "0.5" : "") << r;
    }
}

// A results.csv written before the backends named their own timing (ns_per_sample on CPU
// rows, ms_per_frame on GLSL rows) reports exactly as the same rows with time and time_unit:
// the same tables, the same figure data, a cost per unit.
TEST_F(ReportTables, OldTimingColumnsReportLikeNewOnes) {
    std::vector<Cells> rows;
    for (bool glsl : {false, true})
        for (double theta : {10, 40, 70}) {
            rows.push_back(row("pom", "layers=8", "bricks", glsl, theta, 0.1 + theta / 1000, 0.5));
            rows.push_back(row("parallax", "", "bricks", glsl, theta, 0.3, 0.9, 1));
            rows.back()["time"] = glsl ? "0.125" : "2.5";
        }
    std::vector<Cells> old = rows;
    for (Cells& c : old) {
        c[c["time_unit"] == "ns/sample" ? "ns_per_sample" : "ms_per_frame"] = c["time"];
        c.erase("time");
        c.erase("time_unit");
    }
    std::vector<std::string> old_columns;
    for (const auto& c : kColumns)
        if (c == "time") old_columns.push_back("ns_per_sample");
        else if (c == "time_unit") old_columns.push_back("ms_per_frame");
        else old_columns.push_back(c);
    const fs::path now = report(results(rows, kColumns, "now"));
    const fs::path before = report(results(old, old_columns, "before"));
    for (const char* f : {"summary.csv", "summary.md", "summary.tex", "budget.md",
                          "data/cost_vs_error.csv", "data/cost_vs_error_bands.csv"}) {
        std::string b = slurp(before / f);  // a .tex names its results.csv
        for (size_t at; (at = b.find("/before/")) != std::string::npos;) b.replace(at, 8, "/now/");
        EXPECT_EQ(b, slurp(now / f)) << f;
    }
    const pxh::CsvTable bands = pxh::read_csv((now / "data/cost_vs_error_bands.csv").string());
    for (const char* c : {"time[ns/sample]", "time[ms/frame]", "pareto_time[ns/sample]",
                          "pareto_time[ms/frame]", "time_min[ns/sample]", "time_max[ms/frame]"})
        EXPECT_GE(bands.index(c), 0) << c;
    size_t checked = 0;
    for (size_t r = 0; r < bands.rows.size(); ++r) {
        const bool gl = bands.get(r, "group") == "glsl/r32f";
        const bool pom = bands.get(r, "setting") == "pom layers=8";
        EXPECT_EQ(bands.get(r, gl ? "time[ns/sample]" : "time[ms/frame]"), "");
        EXPECT_EQ(bands.number(r, gl ? "time[ms/frame]" : "time[ns/sample]"),
                  gl ? (pom ? 0.5 : 0.125) : (pom ? 10 : 2.5));
        // parallax: cheaper in both costs but worse; each on its group's front of its unit
        EXPECT_EQ(bands.get(r, gl ? "pareto_time[ms/frame]" : "pareto_time[ns/sample]"), "1");
        EXPECT_EQ(bands.get(r, gl ? "pareto_time[ns/sample]" : "pareto_time[ms/frame]"), "");
        ++checked;
    }
    EXPECT_EQ(checked, 2u * 2u * 3u);  // settings x groups x bands
}

// One table per height field, holding that field's numbers only: the band means computed
// here from results.csv, field by field, and the merge decided per field (identical twins on
// one field, different ones on the other).
TEST_F(ReportTables, OneTablePerFieldWithItsOwnNumbers) {
    std::vector<Cells> rows;
    const std::vector<std::string> fields = {"bricks", "fbm", "scan:jacksboro"};
    const double thetas[] = {0, 20, 45, 65, 70};
    int k = 0;
    for (size_t f = 0; f < fields.size(); ++f)
        for (const char* m : {"pom", "relief"})
            for (double th : thetas)
                for (bool glsl : {false, true}) {
                    ++k;
                    // a value per (field, method, θ); on fbm the GLSL twin of relief is off
                    double e = 0.01 * (1 + f) * (1 + th / 10) + (m[0] == 'r' ? 0.5 : 0);
                    if (glsl && fields[f] == "fbm" && m[0] == 'r') e += 0.05;
                    rows.push_back(row(m, "layers=16", fields[f], glsl, th, e, 2 * e + 0.001 * k,
                                       16 + double(f)));
                    if (glsl) rows.back()["err_p95"] = rows[rows.size() - 2]["err_p95"];
                }
    const fs::path res = results(rows);
    const fs::path rep = report(res);
    const std::string md = slurp(rep / "fields.md");

    // The band means, independently: results.csv read back, grouped by field, series, band.
    const pxh::CsvTable t = pxh::read_csv((res / "results.csv").string());
    struct Sum {
        double mean = 0, p95 = 0, fetches = 0;
        int n = 0;
    };
    std::map<std::tuple<std::string, std::string, int>, Sum> band;  // field, series, band
    for (size_t r = 0; r < t.rows.size(); ++r) {
        const double th = t.number(r, "theta_deg");
        const int b = th < 30 ? 0 : th < 60 ? 1 : 2;
        const std::string series =
            t.get(r, "method") + " " + t.get(r, "params") + " [" + t.get(r, "backend") + "/" +
            (t.get(r, "texture_format").empty() ? t.get(r, "precision")
                                                : t.get(r, "texture_format")) +
            "]";
        Sum& s = band[{t.get(r, "heightfield"), series, b}];
        s.mean += t.number(r, "err_mean");
        s.p95 += t.number(r, "err_p95");
        s.fetches += t.number(r, "fetches_mean");
        ++s.n;
    }
    const auto cell = [&](const std::string& f, const std::string& series, int b) {
        const Sum& s = band.at({f, series, b});
        return f3(s.mean / s.n) + " / " + f3(s.p95 / s.n);
    };
    for (const auto& f : fields) {
        const std::string head = "\n## " + f + " s=0.05 b=1\n";
        const size_t at = md.find(head);
        ASSERT_NE(at, std::string::npos) << head << md;
        const size_t end = md.find("\n## ", at + head.size());
        const std::string section = md.substr(at, end == std::string::npos ? end : end - at);
        EXPECT_EQ(count(md, head), 1);
        // pom: identical twins on every field, one row
        const auto pom = md_row(section, "pom layers=16 [cpu/float = glsl/r32f]");
        ASSERT_EQ(pom.size(), 6u) << section;
        for (int b = 0; b < 3; ++b)
            EXPECT_EQ(pom[size_t(b)], cell(f, "pom layers=16 [cpu/float]", b)) << f << " " << b;
        const size_t fi = size_t(&f - &fields[0]);
        EXPECT_EQ(pom[3], std::to_string(16 + fi) + ".0");  // fetches, one decimal
        // relief: merged but on fbm
        if (f == "fbm") {
            EXPECT_TRUE(md_row(section, "relief layers=16 [cpu/float = glsl/r32f]").empty());
            const auto c = md_row(section, "relief layers=16 [cpu/float]");
            const auto g = md_row(section, "relief layers=16 [glsl/r32f]");
            ASSERT_EQ(c.size(), 6u) << section;
            ASSERT_EQ(g.size(), 6u) << section;
            for (int b = 0; b < 3; ++b) {
                EXPECT_EQ(c[size_t(b)], cell(f, "relief layers=16 [cpu/float]", b));
                EXPECT_EQ(g[size_t(b)], cell(f, "relief layers=16 [glsl/r32f]", b));
            }
        } else {
            const auto r = md_row(section, "relief layers=16 [cpu/float = glsl/r32f]");
            ASSERT_EQ(r.size(), 6u) << section;
            EXPECT_EQ(r[2], cell(f, "relief layers=16 [cpu/float]", 2));
        }
        // no other field's number: the table holds exactly its two or three rows
        EXPECT_EQ(count(section, "\n| pom ") + count(section, "\n| relief "), f == "fbm" ? 3 : 2)
            << section;
    }
    // The pooled summary is not any one field's: its pom cell is the mean over the fields.
    const auto pooled = md_row(slurp(rep / "summary.md"), "pom layers=16 [cpu/float = glsl/r32f]");
    ASSERT_FALSE(pooled.empty());
    EXPECT_NE(pooled[0], cell("bricks", "pom layers=16 [cpu/float]", 0));

    // fields.csv: the same means unrounded, one line per field, series and band
    const pxh::CsvTable fc = pxh::read_csv((rep / "fields.csv").string());
    int checked = 0;
    for (size_t r = 0; r < fc.rows.size(); ++r) {
        if (fc.get(r, "band") != "60 <= θ < 75") continue;
        const std::string f = fc.get(r, "heightfield");
        const std::string name = f.substr(0, f.find(" s="));
        const Sum& s = band.at({name, fc.get(r, "series"), 2});
        EXPECT_NEAR(fc.number(r, "err_mean"), s.mean / s.n, 1e-12) << f;
        EXPECT_NEAR(fc.number(r, "err_p95"), s.p95 / s.n, 1e-12) << f;
        ++checked;
    }
    EXPECT_EQ(checked, 3 * 4);  // 3 fields x 2 settings x 2 backends
    // one LaTeX table per field, with its numbers
    for (const auto& f : fields) {
        std::string name = f + "_s_0.05_b_1";
        for (char& c : name)
            if (c == ':') c = '_';
        const std::string tex = slurp(rep / "fields" / (name + ".tex"));
        ASSERT_FALSE(tex.empty()) << name;
        EXPECT_NE(tex.find("Height field: " + f + " s=0.05 b=1."), std::string::npos) << tex;
        EXPECT_NE(tex.find(cell(f, "pom layers=16 [cpu/float]", 2)), std::string::npos) << tex;
    }
}

// The compact labels: the method and the values of the fewest parameters that tell its
// settings apart; the method alone for a single setting; letters when the values are long.
TEST(CompactLabels, FewestTellingParametersOrLetters) {
    const std::vector<std::pair<std::string, std::string>> s = {
        {"pom", "layers=32;layers_min=off;layers_max=off"},
        {"pom", "layers=adaptive;layers_min=8;layers_max=32"},
        {"parallax", ""},
        {"cone", "steps=32;map=dummer;min_step=texel"},
        {"cone", "steps=32;map=dummer_min;min_step=cell"},
        {"cone", "steps=128;map=bilinear;min_step=none"},
        {"relief", "layers=16;binary_steps=3"},
        {"relief", "layers=16;binary_steps=8"},
        {"relief", "layers=64;binary_steps=8"},
        {"x", "name=a_very_long_value_indeed"},
        {"x", "name=another_very_long_value"}};
    const std::vector<std::string> want = {
        "pom (32)",          "pom (adaptive)",  "parallax",       "cone (dummer)",
        "cone (dummer_min)", "cone (bilinear)", "relief (16, 3)", "relief (16, 8)",
        "relief (64, 8)",    "x (a)",           "x (b)"};
    EXPECT_EQ(pxh::compact_labels(s), want);
    // the values "a_very_long_value_indeed" would not fit a column: letters instead; and a
    // setting whose values are too long makes its method's every label a letter
    const auto l =
        pxh::compact_labels({{"y", "name=short_one"}, {"y", "name=this_is_far_too_long"}});
    EXPECT_EQ(l, (std::vector<std::string>{"y (a)", "y (b)"}));
}

// legend.md / legend.tex map each LaTeX label to exactly one setting's full parameters, every
// label of the .tex tables is in it, and no two settings share a label.
TEST_F(ReportTables, LatexLabelsAndLegendOneToOne) {
    std::vector<Cells> rows;
    const std::vector<std::pair<std::string, std::string>> settings = {
        {"pom", "layers=32;layers_min=off;layers_max=off"},
        {"pom", "layers=adaptive;layers_min=8;layers_max=32"},
        {"relief", "layers=32;layers_min=off;layers_max=off;binary_steps=5"},
        {"parallax_clamped", "max_offset=scale"},
        {"none", ""}};
    double e = 0.1;
    for (const auto& [m, p] : settings)
        for (double th : {0.0, 60.0}) rows.push_back(row(m, p, "fbm", false, th, e += 0.1, 1));
    const fs::path rep = report(results(rows));
    const std::string legend = slurp(rep / "legend.md");
    std::map<std::string, std::string> label_of;  // parameters -> label
    std::set<std::string> labels;
    std::istringstream in(legend);
    for (std::string line; std::getline(in, line);) {
        if (line.rfind("| ", 0) != 0 || line.rfind("| label", 0) == 0) continue;
        const size_t mid = line.find(" | ");
        const std::string label = line.substr(2, mid - 2);
        const std::string params = line.substr(mid + 3, line.size() - mid - 5);
        EXPECT_TRUE(labels.insert(label).second) << "label twice: " << label;
        EXPECT_TRUE(label_of.emplace(params, label).second) << "parameters twice: " << params;
    }
    ASSERT_EQ(label_of.size(), settings.size()) << legend;
    EXPECT_EQ(label_of.at("layers=32, layers_min=off, layers_max=off"), "pom (32)");
    EXPECT_EQ(label_of.at("layers=adaptive, layers_min=8, layers_max=32"), "pom (adaptive)");
    EXPECT_EQ(label_of.at("layers=32, layers_min=off, layers_max=off, binary_steps=5"), "relief");
    EXPECT_EQ(label_of.at("max_offset=scale"), "parallax_clamped");
    EXPECT_EQ(label_of.at("-"), "none");
    // every row of summary.tex starts with a legend label (escaped for TeX), each label once
    const std::string tex = slurp(rep / "summary.tex");
    for (const auto& l : labels) {
        std::string esc;
        for (char c : l) esc += c == '_' ? std::string("\\_") : std::string(1, c);
        EXPECT_EQ(count(tex, "\n" + esc + " & "), 1) << esc << "\n" << tex;
    }
    EXPECT_EQ(tex.find("layers\\_min"), std::string::npos) << tex;  // parameters only in the legend
    EXPECT_NE(slurp(rep / "legend.tex").find("pom (adaptive) & layers=adaptive, layers\\_min=8"),
              std::string::npos);
}

// Every .tex table the report writes: booktabs rules (\toprule, \midrule, \bottomrule, in that
// order, once each per tabular), no vertical rules in the column spec, no \hline.
TEST_F(ReportTables, EveryTexTableHasBooktabsRulesAndNoVerticalRules) {
    std::vector<Cells> rows;
    for (const char* f : {"sine", "bricks"})
        for (bool glsl : {false, true})
            for (double th : {0.0, 40.0, 80.0}) {
                rows.push_back(row("pom", "layers=8", f, glsl, th, 0.1 + th / 100, 0.3));
                rows.push_back(row("steep", "layers=8", f, glsl, th, 0.2 + th / 100, 0.4));
            }
    const fs::path rep = report(results(rows));
    int tables = 0;
    std::set<std::string> files;
    for (const auto& e : fs::recursive_directory_iterator(rep)) {
        if (e.path().extension() != ".tex") continue;
        files.insert(fs::relative(e.path(), rep).string());
        const std::string tex = slurp(e.path());
        const std::regex begin(R"(\\begin\{tabular\}\{([^}]*(\{[^}]*\}[^}]*)*)\})");
        int n = 0;
        for (std::sregex_iterator it(tex.begin(), tex.end(), begin), end; it != end; ++it) {
            ++n;
            const std::string spec = (*it)[1];
            EXPECT_EQ(spec.find('|'), std::string::npos) << e.path() << ": " << spec;
            const size_t at = size_t(it->position());
            const size_t top = tex.find("\\toprule", at), mid = tex.find("\\midrule", at),
                         bottom = tex.find("\\bottomrule", at),
                         close = tex.find("\\end{tabular}", at);
            EXPECT_TRUE(top < mid && mid < bottom && bottom < close) << e.path();
        }
        EXPECT_EQ(n, count(tex, "\\end{tabular}")) << e.path();
        EXPECT_EQ(count(tex, "\\toprule"), n) << e.path();
        EXPECT_EQ(count(tex, "\\bottomrule"), n) << e.path();
        EXPECT_EQ(tex.find("\\hline"), std::string::npos) << e.path();
        EXPECT_EQ(tex.find("\\vline"), std::string::npos) << e.path();
        tables += n;
    }
    const std::set<std::string> want = {"summary.tex", "budget.tex", "legend.tex",
                                        "fields/sine_s_0.05_b_1.tex",
                                        "fields/bricks_s_0.05_b_1.tex"};
    EXPECT_EQ(files, want);
    EXPECT_EQ(tables, 5);
}

// The montage cuts each map out of pxh run's PNG at error_map_box: inside the box exactly the
// map's colours (here a left half of 1/16 texel, a right half of 16 texels, so both ends of
// the scale), and the rows just above and below it are none of the map's colours (title and
// colour bar left out).
TEST_F(ReportTables, ErrorMapBoxCutsOutExactlyTheMap) {
    for (int n : {16, 24, 100, 500}) {
        std::vector<pxh::Vec2d> errors(size_t(n) * n);
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i)
                errors[size_t(j) * n + i] = i < n / 2 ? pxh::Vec2d{1.0 / 16, 0} : pxh::Vec2d{0, 16};
        const std::string stem = "m" + std::to_string(n);
        pxh::write_error_map(errors, n, (dir / "maps").string(), stem, "a title");
        OIIO::ImageBuf png((dir / "maps" / (stem + ".png")).string());
        ASSERT_TRUE(png.read()) << png.geterror();
        const pxh::ErrorMapBox box = pxh::error_map_box(n);
        ASSERT_GE(box.side, n);
        EXPECT_EQ(box.side % n, 0) << n;  // each sample a whole number of pixels
        float lo[3], hi[3];
        pxh::error_colour(1.0 / 16, lo);
        pxh::error_colour(16, hi);
        const auto is = [](const float* px, const float* c) {
            for (int k = 0; k < 3; ++k)
                if (std::abs(px[k] - c[k]) > 1.0f / 255) return false;
            return true;
        };
        float px[4];
        for (int y = 0; y < box.side; ++y)
            for (int x = 0; x < box.side; ++x) {
                png.getpixel(box.x0 + x, box.y0 + y, px);
                ASSERT_TRUE(is(px, x < box.side / 2 ? lo : hi)) << n << " at " << x << "," << y;
            }
        for (int x = 0; x < box.side; ++x)
            for (int y : {box.y0 - 1, box.y0 + box.side}) {
                png.getpixel(box.x0 + x, y, px);
                ASSERT_FALSE(is(px, lo) || is(px, hi)) << n << ": row " << y << " is map";
            }
    }
}

}  // namespace
