// pxh report and pxh check on small hand-made results folders (and a few tiny real runs): failed
// rows, angle bands, budgets per method setting, Pareto fronts per group, params matching,
// whole-cell numbers, NaN limits, text columns, non-regular files, folder names with quotes.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "harness/core/error.h"
#include "harness/report/report.h"
#include "harness/results/csv_table.h"
#include "harness/results/results.h"
#include "tests/cli_util.h"

namespace {

namespace fs = std::filesystem;
using Cells = std::map<std::string, std::string>;

// The results.csv columns the report and check read.
const std::vector<std::string> kColumns = {
    "method",    "params",          "heightfield", "scale",      "bias",         "backend",
    "precision", "texture_format",  "theta_deg",   "phi_deg",    "err_mean",     "err_p50",
    "err_p95",   "err_p99",         "frac_gt_1",   "nonfinite",  "fetches_mean", "time",
    "time_unit", "double_diff_max", "sliding",     "shimmering", "map",          "status",
    "error"};

// One row: an ok CPU float row of pom layers=8 at theta 0, overridden by `cells`.
Cells row(const Cells& cells) {
    Cells r = {{"method", "pom"},      {"params", "layers=8"}, {"heightfield", "bricks"},
               {"scale", "0.05"},      {"bias", "1"},          {"backend", "cpu"},
               {"precision", "float"}, {"theta_deg", "0"},     {"phi_deg", "0"},
               {"err_mean", "0.1"},    {"err_p50", "0.1"},     {"err_p95", "0.2"},
               {"err_p99", "0.3"},     {"frac_gt_1", "0"},     {"nonfinite", "0"},
               {"fetches_mean", "8"},  {"time", "10"},         {"time_unit", "ns/sample"},
               {"status", "ok"}};
    for (const auto& [k, v] : cells) r[k] = v;
    return r;
}

// A GLSL row in texture format `fmt` (a frame time, in ms/frame).
Cells glsl(const std::string& fmt, Cells cells) {
    cells.emplace("backend", "glsl");
    cells.emplace("texture_format", fmt);
    cells.emplace("time", "0.5");
    cells.emplace("time_unit", "ms/frame");
    return row(cells);
}

class ReportFolder : public pxh::test::CliTest {
  protected:
    // Writes DIR/res/results.csv from the rows (kColumns, then `extra` columns); returns
    // DIR/res.
    std::string results(const std::vector<Cells>& rows,
                        const std::vector<std::string>& extra = {}) {
        const fs::path res = dir / "res";
        fs::create_directories(res);
        std::vector<std::string> columns = kColumns;
        columns.insert(columns.end(), extra.begin(), extra.end());
        std::string text;
        for (size_t c = 0; c < columns.size(); ++c) text += (c ? "," : "") + columns[c];
        text += "\n";
        for (const auto& r : rows) {
            for (size_t c = 0; c < columns.size(); ++c) {
                auto it = r.find(columns[c]);
                text += (c ? "," : "") + pxh::csv_quote(it == r.end() ? "" : it->second);
            }
            text += "\n";
        }
        std::ofstream(res / "results.csv", std::ios::binary) << text;
        return res.string();
    }
    // What `f` prints on stdout (exceptions pass through).
    template <class F>
    static std::string captured(F f) {
        testing::internal::CaptureStdout();
        try {
            f();
        } catch (...) {
            testing::internal::GetCapturedStdout();
            throw;
        }
        return testing::internal::GetCapturedStdout();
    }
    // run_report on a folder, its stdout returned (plots off unless asked).
    std::string report(const std::string& res, pxh::ReportOptions o = no_plots()) {
        return captured([&] { pxh::run_report(res, o); });
    }
    static pxh::ReportOptions no_plots() {
        pxh::ReportOptions o;
        o.plots = false;
        return o;
    }
    // run_check with a thresholds text: {exit code, stdout}.
    std::pair<int, std::string> check(const std::string& res, const std::string& limits) {
        const std::string file = write("limits.toml", limits);
        int rc = -1;
        const std::string out = captured([&] { rc = pxh::run_check(res, file); });
        return {rc, out};
    }
    // The message of the InputError `f` throws ("" if it throws none).
    template <class F>
    static std::string input_error(F f) {
        try {
            f();
        } catch (const pxh::InputError& e) {
            return e.what();
        }
        return "";
    }
    // The cells of the Markdown table row whose first cell is `first`.
    static std::vector<std::string> md_row(const std::string& md, const std::string& first) {
        std::istringstream in(md);
        std::string line;
        while (std::getline(in, line)) {
            if (line.rfind("| " + first + " |", 0) != 0) continue;
            std::vector<std::string> cells;
            size_t at = 1;
            for (size_t bar; (bar = line.find(" |", at)) != std::string::npos; at = bar + 2)
                cells.push_back(line.substr(at + 1, bar - at - 1));
            return cells;
        }
        return {};
    }
    // The summary.csv value of `column` for a series and band.
    static double summary(const fs::path& rep, const std::string& series, const std::string& band,
                          const std::string& column) {
        const pxh::CsvTable t = pxh::read_csv((rep / "summary.csv").string());
        for (size_t r = 0; r < t.rows.size(); ++r)
            if (t.get(r, "series") == series && t.get(r, "band") == band)
                return t.number(r, column);
        ADD_FAILURE() << "no summary row " << series << " / " << band;
        return NAN;
    }
};

// Failed rows are listed (printed, failed.md, a line in summary.md) and kept out of every
// statistic: here they carry numbers (as an old or edited results.csv may) that would show.
TEST_F(ReportFolder, FailedRowsListedAndLeftOutOfEveryFigure) {
    const Cells poison = {
        {"err_mean", "1000"},        {"err_p50", "1000"},      {"err_p95", "1000"},
        {"err_p99", "1000"},         {"fetches_mean", "1000"}, {"time", "1000"},
        {"double_diff_max", "1000"}, {"sliding", "1000"},      {"shimmering", "1000"},
        {"map", "maps/failed.png"},  {"status", "failed"}};
    Cells failed_pom = poison, failed_relief = poison;
    failed_pom.insert({{"theta_deg", "60"}, {"phi_deg", "45"}, {"error", "timed out"}});
    failed_relief.insert({{"method", "relief"},
                          {"params", "layers=4"},
                          {"theta_deg", "60"},
                          {"error", "shader did not compile"}});
    const std::string res = results({
        row({{"theta_deg", "0"},
             {"double_diff_max", "2e-06"},
             {"sliding", "0.01"},
             {"shimmering", "0.02"},
             {"map", "maps/a.png"}}),
        row({{"theta_deg", "60"},
             {"err_mean", "0.4"},
             {"err_p50", "0.3"},
             {"err_p95", "0.45"},
             {"double_diff_max", "3e-06"},
             {"sliding", "0.01"},
             {"shimmering", "0.02"},
             {"map", "maps/b.png"}}),
        row(failed_pom),
        glsl("r32f", failed_relief),
    });
    const std::string out = report(res);
    const fs::path rep = fs::path(res) / "report";
    // Listed: printed, in failed.md, and summary.md says so.
    EXPECT_NE(out.find("2 failed rows"), std::string::npos) << out;
    EXPECT_NE(out.find("relief layers=4"), std::string::npos) << out;
    EXPECT_NE(out.find("shader did not compile"), std::string::npos) << out;
    const std::string failed = slurp(rep / "failed.md");
    EXPECT_NE(failed.find("| relief | layers=4 | bricks s=0.05 b=1 | 60 | 0 | glsl/r32f | shader "
                          "did not compile |"),
              std::string::npos)
        << failed;
    EXPECT_NE(
        failed.find("| pom | layers=8 | bricks s=0.05 b=1 | 60 | 45 | cpu/float | timed out |"),
        std::string::npos)
        << failed;
    EXPECT_NE(slurp(rep / "summary.md").find("2 failed rows"), std::string::npos);
    // Out of every figure: the band 60-75 is the ok row alone, and no "1000" or relief (whose
    // only row failed) anywhere else.
    EXPECT_DOUBLE_EQ(summary(rep, "pom layers=8 [cpu/float]", "60 <= θ < 75 †", "err_mean"), 0.4);
    EXPECT_DOUBLE_EQ(summary(rep, "pom layers=8 [cpu/float]", "all", "fetches_mean"), 8);
    for (const auto& e : fs::recursive_directory_iterator(rep)) {
        // error_scale.csv: the maps' colour scale, no row's number
        if (!e.is_regular_file() || e.path().filename() == "failed.md" ||
            e.path().filename() == "error_scale.csv")
            continue;
        const std::string text = slurp(e.path());
        EXPECT_EQ(text.find("1000"), std::string::npos) << e.path();
        EXPECT_EQ(text.find("1e+03"), std::string::npos) << e.path();
        EXPECT_EQ(text.find("failed.png"), std::string::npos) << e.path();
        EXPECT_EQ(text.find("relief"), std::string::npos) << e.path();
    }
    EXPECT_NE(slurp(rep / "precision.md").find("3e-06"), std::string::npos);
    EXPECT_NE(slurp(rep / "data" / "maps.csv").find("maps/b.png"), std::string::npos);
    // A setting with a failed row in a band is no budget candidate there (its ok row at 60
    // would meet 0.5 texel), but is where it did not fail.
    const std::string budget = slurp(rep / "budget.md");
    EXPECT_EQ(md_row(budget, "0.5"), (std::vector<std::string>{"0.5", "pom layers=8 (8.0 fetches)",
                                                               "no setting meets this budget"}))
        << budget;
}

// pxh check: a failed row fails every limit that matches it, whatever the column.
TEST_F(ReportFolder, CheckFailsEveryLimitMatchingAFailedRow) {
    const std::string res = results({
        row({}),
        row({{"method", "parallax"}, {"params", ""}}),
        glsl("r32f", {{"theta_deg", "30"},
                      {"status", "failed"},
                      {"error", "link error"},
                      {"err_p95", ""},
                      {"fetches_mean", ""},
                      {"nonfinite", ""}}),
    });
    const auto [rc, out] = check(res, R"(
[[limit]]
method = "pom"
column = "err_p95"
max = 1
[[limit]]
column = "nonfinite"
max = 0
[[limit]]
method = "pom"
backend = "cpu"
column = "fetches_mean"
max = 8
[[limit]]
method = "parallax"
column = "err_p95"
max = 1
)");
    EXPECT_EQ(rc, 1);
    EXPECT_NE(out.find("2 passed, 2 failed"), std::string::npos) << out;
    EXPECT_NE(out.find("1 matching rows failed: link error"), std::string::npos) << out;
}

// Bands: exact edges in every table, a θ on an edge in the band above it, the last band
// closed, a band holding one view flagged; settable edges, validated.
TEST_F(ReportFolder, BandsWrittenExactlyAndSingleViewsFlagged) {
    std::vector<Cells> rows;
    for (const char* th : {"0", "30", "60", "85", "89.5"}) rows.push_back(row({{"theta_deg", th}}));
    const std::string res = results(rows);
    report(res);
    const fs::path rep = fs::path(res) / "report";
    const std::string md = slurp(rep / "summary.md");
    for (const char* label : {"0 <= θ < 30 †", "30 <= θ < 60 †", "60 <= θ < 75 †"})
        EXPECT_NE(md.find(label), std::string::npos) << label << "\n" << md;
    EXPECT_NE(md.find("| 85 <= θ <= 90 mean / p95 |"), std::string::npos) << md;  // 2 views
    EXPECT_NE(md.find("0 <= θ < 30 holds only θ = 0"), std::string::npos) << md;
    EXPECT_NE(slurp(rep / "budget.md").find("| 30 <= θ < 60 † |"), std::string::npos);
    EXPECT_NE(slurp(rep / "summary.tex").find("0 $\\le$ $\\theta$ $<$ 30 $^\\dagger$"),
              std::string::npos);
    EXPECT_EQ(summary(rep, "pom layers=8 [cpu/float]", "85 <= θ <= 90", "band_views"), 2);
    EXPECT_EQ(summary(rep, "pom layers=8 [cpu/float]", "30 <= θ < 60 †", "theta_lo"), 30);

    pxh::ReportOptions o = no_plots();
    o.bands = {0, 45, 90};
    report(res, o);
    const std::string md2 = slurp(rep / "summary.md");
    EXPECT_NE(md2.find("| 0 <= θ < 45 mean / p95 | 45 <= θ <= 90 mean / p95 |"), std::string::npos)
        << md2;
    EXPECT_EQ(md2.find("†"), std::string::npos) << md2;
    // Views outside the bands count only in "all".
    o.bands = {0, 45};
    report(res, o);
    const pxh::CsvTable sum = pxh::read_csv((rep / "summary.csv").string());
    ASSERT_EQ(sum.rows.size(), 2u);
    EXPECT_EQ(sum.get(0, "band"), "0 <= θ <= 45");
    EXPECT_EQ(sum.get(1, "band"), "all");

    for (const auto& edges : std::vector<std::vector<double>>{
             {30, 0}, {0}, {0, 100}, {-5, 30}, {0, 30, 30}, {0, NAN}}) {
        o.bands = edges;
        EXPECT_NE(input_error([&] { report(res, o); }).find("--bands"), std::string::npos);
    }
    o.bands = {};
    o.budget_metric = "p50";
    EXPECT_NE(input_error([&] { report(res, o); }).find("--budget-metric"), std::string::npos);
}

// Budgets rank method settings, not series: a setting meets a budget only if every backend /
// format series of it does, has no non-finite output there, and the metric is selectable.
TEST_F(ReportFolder, BudgetPerSettingConservativeWithSelectableMetric) {
    const std::string res = results({
        // pom layers=8: cheap, within 0.5 on the CPU but not on GLSL.
        row({{"theta_deg", "70"}, {"err_p95", "0.3"}, {"err_p99", "0.4"}}),
        glsl("r32f", {{"theta_deg", "70"}, {"err_p95", "0.7"}, {"err_p99", "0.8"}}),
        // pom layers=16: within 0.25 everywhere; float noise in its GLSL fetches.
        row({{"params", "layers=16"},
             {"theta_deg", "70"},
             {"fetches_mean", "16"},
             {"err_p95", "0.2"},
             {"err_p99", "0.3"}}),
        glsl("r32f", {{"params", "layers=16"},
                      {"theta_deg", "70"},
                      {"fetches_mean", "16.0001"},
                      {"err_p95", "0.2"},
                      {"err_p99", "0.3"}}),
        glsl("r8", {{"params", "layers=16"},
                    {"theta_deg", "70"},
                    {"fetches_mean", "15.9999"},
                    {"err_p95", "0.2"},
                    {"err_p99", "0.3"}}),
        // relief layers=4: cheaper, fine at p95, a long tail (p99, frac_gt_1).
        row({{"method", "relief"},
             {"params", "layers=4"},
             {"theta_deg", "70"},
             {"fetches_mean", "12"},
             {"err_p95", "0.15"},
             {"err_p99", "40"},
             {"frac_gt_1", "0.02"}}),
        // steep layers=4: cheapest and accurate, but some outputs were NaN.
        row({{"method", "steep"},
             {"params", "layers=4"},
             {"theta_deg", "70"},
             {"fetches_mean", "4"},
             {"err_p95", "0.01"},
             {"err_p99", "0.01"},
             {"nonfinite", "3"}}),
    });
    const fs::path rep = fs::path(res) / "report";
    auto budget_row = [&](const std::string& metric, const std::string& budget) {
        pxh::ReportOptions o = no_plots();
        o.budget_metric = metric;
        report(res, o);
        const auto cells = md_row(slurp(rep / "budget.md"), budget);
        return cells.size() == 2 ? cells[1] : "(no row " + budget + ")";
    };
    EXPECT_EQ(budget_row("p95", "0.1"), "no setting meets this budget");
    EXPECT_EQ(budget_row("p95", "0.25"), "relief layers=4 (12.0 fetches)");
    EXPECT_EQ(budget_row("p95", "1"), "pom layers=8 (8.0 fetches)");
    EXPECT_EQ(budget_row("p99", "0.5"), "pom layers=16 (16.0 fetches)");
    EXPECT_EQ(budget_row("p99", "1"), "pom layers=8 (8.0 fetches)");
    EXPECT_EQ(budget_row("frac_gt_1", "0.001"), "pom layers=8 (8.0 fetches)");
    EXPECT_EQ(budget_row("frac_gt_1", "0.01"), "pom layers=8 (8.0 fetches)");
    const std::string md = slurp(rep / "budget.md");
    EXPECT_NE(md.find("| frac_gt_1 budget (fraction of samples) |"), std::string::npos) << md;
    EXPECT_EQ(md.find("steep"), std::string::npos) << md;
    EXPECT_EQ(md.find("| none"), std::string::npos) << md;
}

// The Pareto front of each panel comes from the points drawn in it: one group (backend /
// precision or format) and one cost. Globally, the GLSL point of pom layers=8 would dominate
// the CPU point of pom layers=16 and push it off the CPU front.
TEST_F(ReportFolder, ParetoFrontPerGroup) {
    const std::string res = results({
        row({{"params", "layers=8"}, {"fetches_mean", "8"}, {"err_mean", "0.30"}, {"time", "10"}}),
        row({{"params", "layers=16"},
             {"fetches_mean", "16"},
             {"err_mean", "0.25"},
             {"time", "20"}}),
        glsl("r32f", {{"params", "layers=8"}, {"fetches_mean", "8"}, {"err_mean", "0.20"}}),
        glsl("r32f", {{"params", "layers=16"}, {"fetches_mean", "16"}, {"err_mean", "0.40"}}),
    });
    report(res);
    const pxh::CsvTable t =
        pxh::read_csv((fs::path(res) / "report" / "data" / "cost_vs_error.csv").string());
    std::map<std::string, std::string> flags;
    for (size_t r = 0; r < t.rows.size(); ++r)
        flags[t.get(r, "series")] = t.get(r, "group") + " " + t.get(r, "pareto_fetches") +
                                    t.get(r, "pareto_time[ns/sample]") +
                                    t.get(r, "pareto_time[ms/frame]");
    EXPECT_EQ(flags["pom layers=8 [cpu/float]"], "cpu/float 11");
    EXPECT_EQ(flags["pom layers=16 [cpu/float]"], "cpu/float 11");
    EXPECT_EQ(flags["pom layers=8 [glsl/r32f]"], "glsl/r32f 11");
    EXPECT_EQ(flags["pom layers=16 [glsl/r32f]"], "glsl/r32f 00");
}

// check matches params whatever the spaces around '=' and ';'.
TEST_F(ReportFolder, CheckParamsIgnoresSpacesAroundSeparators) {
    const std::string res =
        results({row({{"params", "layers=16;binary_steps=5"}}), row({{"params", "layers=8"}})});
    for (const char* p : {"layers = 16; binary_steps = 5", " layers=16 ;binary_steps=5 ",
                          "layers=16;binary_steps=5"}) {
        const auto [rc, out] = check(
            res, std::string("[[limit]]\nparams = \"") + p + "\"\ncolumn = \"err_p95\"\nmax = 1\n");
        EXPECT_EQ(rc, 0) << p;
        EXPECT_NE(out.find("1 passed, 0 failed"), std::string::npos) << out;
    }
    EXPECT_NE(input_error([&] {
                  check(res, "[[limit]]\nparams = \"layers=1 6\"\ncolumn = \"err_p95\"\nmax = 1\n");
              }).find("matches no row"),
              std::string::npos);
}

// Four rows that differ in every filter key, for the tests of filters below.
std::vector<Cells> filter_rows() {
    return {
        row({{"samples", "16"}}),  // pom, 0.05, 1, phi 0: err_p95 0.2
        row({{"scale", "0.02"}, {"phi_deg", "45"}, {"samples", "16"}, {"err_p95", "0.4"}}),
        row({{"method", "relief"},
             {"params", "layers=4"},
             {"bias", "0"},
             {"samples", "32"},
             {"err_p95", "0.8"}}),
        row({{"method", "parallax"},
             {"params", ""},
             {"heightfield", "fbm"},
             {"scale", "0.1"},
             {"bias", "0.5"},
             {"theta_deg", "85"},
             {"phi_deg", "90"},
             {"samples", "16"},
             {"err_p95", "5"}}),
    };
}

// The rows count and worst value of the one limit of `out` ("" when absent).
std::pair<std::string, std::string> rows_and_worst(const std::string& out) {
    std::istringstream in(out);
    std::string line;
    std::getline(in, line);  // header
    std::getline(in, line);
    std::vector<std::string> words;
    std::istringstream w(line);
    for (std::string x; w >> x;) words.push_back(x);
    if (words.size() < 3) return {"", ""};
    return {words[words.size() - 2], words[words.size() - 3]};
}

// Filters on scale, bias, phi_deg and samples compare numbers; any filter may be a list (any
// of its values). Each case: the filters, the rows they select and the worst err_p95 there.
TEST_F(ReportFolder, CheckFiltersOnNumbersAndLists) {
    const std::string res = results(filter_rows(), {"samples"});
    struct Case {
        std::string filters, rows, worst;
    };
    const Case cases[] = {
        {"scale = 0.05", "2", "0.8"},
        {"scale = 5e-2", "2", "0.8"},
        {"scale = 0.050000000001", "2", "0.8"},  // within what %.10g keeps
        {"scale = [0.02, 0.05]", "3", "0.8"},
        {"scale = [0.1]", "1", "5"},
        {"bias = 1", "2", "0.4"},
        {"bias = 1.0", "2", "0.4"},
        {"bias = [0, 0.5]", "2", "5"},
        {"phi_deg = 45", "1", "0.4"},
        {"phi_deg = [0, 90]", "3", "5"},
        {"samples = 32", "1", "0.8"},
        {"samples = [16]", "3", "5"},
        {"method = [\"pom\", \"relief\"]", "3", "0.8"},
        {"method = [\"pom\"]", "2", "0.4"},
        {"params = [\"layers = 8\", \"layers=4\"]", "3", "0.8"},
        {"heightfield = [\"fbm\", \"bricks\"]", "4", "5"},
        {"backend = [\"cpu\"]\nprecision = [\"float\"]", "4", "5"},
        {"method = [\"pom\", \"relief\"]\nscale = [0.05]", "2", "0.8"},
        {"method = [\"pom\", \"parallax\"]\nsamples = 16\nphi_deg = [45, 90]", "2", "5"},
    };
    for (const auto& c : cases) {
        auto [rc, out] =
            check(res, "[[limit]]\n" + c.filters + "\ncolumn = \"err_p95\"\nmax = 10\n");
        EXPECT_EQ(rc, 0) << c.filters << "\n" << out;
        EXPECT_EQ(rows_and_worst(out), std::make_pair(c.rows, c.worst)) << c.filters << "\n" << out;
        // The same limit tightened below its worst fails.
        std::tie(rc, out) =
            check(res, "[[limit]]\n" + c.filters + "\ncolumn = \"err_p95\"\nmax = " +
                           std::to_string(std::stod(c.worst) / 2) + "\n");
        EXPECT_EQ(rc, 1) << c.filters << "\n" << out;
    }
    // A list reads as one in the table.
    const auto [rc, out] =
        check(res,
              "[[limit]]\nmethod = [\"pom\", \"relief\"]\nscale = 0.05\ncolumn = \"err_p95\"\n"
              "max = 1\n");
    EXPECT_NE(out.find("method=[pom, relief] scale=0.05 "), std::string::npos) << out;
}

// A filter value no row has, a list with nothing in it, a value of the wrong type, a filter
// on a column results.csv lacks: exit 2, at the line of that key.
TEST_F(ReportFolder, CheckFilterErrorsNameTheKeyLine) {
    const std::string res = results(filter_rows(), {"samples"});
    struct Case {
        std::string filter, expect;
    };
    const Case cases[] = {
        {"method = [\"pom\", \"reliefx\"]",
         "limits.toml:4: method = \"reliefx\" matches no row of results.csv (its method: pom, "
         "relief, parallax)"},
        {"scale = [0.05, 0.07]",
         "limits.toml:4: scale = 0.07 matches no row of results.csv (its scale: 0.05, 0.02, 0.1)"},
        {"samples = 64", "limits.toml:4: samples = 64 matches no row"},
        {"method = []", "limits.toml:4: 'method' is an empty list: it matches no row"},
        {"scale = \"0.05\"", "limits.toml:4: 'scale' must be a number or a list of numbers"},
        {"phi_deg = [0, \"45\"]", "limits.toml:4: 'phi_deg' must be a number or a list of numbers"},
        {"bias = nan", "limits.toml:4: 'bias' is nan"},
        {"method = [\"pom\", 3]", "limits.toml:4: 'method' must be a string or a list of strings"},
        {"heightfield = 1", "limits.toml:4: 'heightfield' must be a string or a list of strings"},
        {"phi = 0",
         "limits.toml:4: unknown key 'phi' in [[limit]] (keys: column, min, max, scale_min, "
         "scale_max, bias_min, bias_max, radius_min, radius_max, theta_min, theta_max, phi_min, "
         "phi_max, samples_min, samples_max, distance_min, distance_max, fov_deg_min, "
         "fov_deg_max, resolution_min, resolution_max, cut_min, cut_max, note, ratio_to, method, "
         "params, heightfield, backend, precision, texture_format, scale, bias, base, radius, "
         "theta_deg, phi_deg, samples, camera, distance, fov_deg, resolution, lod, depth, cut, "
         "ground_truth)"},
    };
    for (const auto& c : cases) {
        const std::string e = input_error([&] {
            check(res, "# limits\n[[limit]]\ncolumn = \"err_p95\"\n" + c.filter + "\nmax = 1\n");
        });
        EXPECT_NE(e.find(c.expect), std::string::npos) << c.filter << "\n" << e;
    }
    // Without a samples column, a samples filter is refused (it would match nothing).
    const std::string old = results(filter_rows());
    EXPECT_NE(input_error([&] {
                  check(old, "[[limit]]\ncolumn = \"err_p95\"\nmax = 1\nsamples = 16\n");
              }).find("limits.toml:4: results.csv has no column 'samples' to filter on"),
              std::string::npos);
}

// A failing limit names its worst row under its table row: the one beyond the bound (the
// lowest for a min), a failed row, a row without a value. Passing limits add no line.
TEST_F(ReportFolder, CheckFailingLimitNamesItsWorstRow) {
    std::vector<Cells> rows = filter_rows();
    rows.push_back(glsl("r16", {{"theta_deg", "70"},
                                {"phi_deg", "30"},
                                {"err_p95", "0.3"},
                                {"fetches_mean", "3"},
                                {"samples", "16"}}));
    rows.push_back(glsl("r8", {{"theta_deg", "80"},
                               {"status", "failed"},
                               {"error", "link error"},
                               {"err_p95", ""},
                               {"samples", "16"}}));
    rows.push_back(row({{"method", "relief"},
                        {"params", "layers=4"},
                        {"theta_deg", "60"},
                        {"err_p95", ""},
                        {"samples", "32"}}));
    const std::string res = results(rows, {"samples"});
    const auto t = write("t.toml", R"([[limit]]
method = "pom"
backend = "cpu"
column = "err_p95"
max = 0.3
[[limit]]
method = "pom"
column = "fetches_mean"
min = 4
max = 10
[[limit]]
method = "pom"
column = "err_p95"
max = 1
[[limit]]
method = "relief"
column = "err_p95"
max = 1
[[limit]]
heightfield = "fbm"
column = "err_p95"
max = 1
)");
    const auto r = pxh("check " + res + " --accept-edited --thresholds " + t);
    EXPECT_EQ(r.status, 1) << r.out << r.err;
    const std::vector<std::string> lines = [&] {
        std::vector<std::string> v;
        std::istringstream in(r.out);
        for (std::string line; std::getline(in, line);) v.push_back(line);
        return v;
    }();
    // The lines under each table row (up to the next row), by limit number.
    auto under = [&](const std::string& n) {
        std::string text;
        bool in = false;
        for (const auto& line : lines) {
            if (line.rfind(n + " ", 0) == 0) {
                in = true;
                continue;
            }
            if (in && line.rfind("  ", 0) != 0) break;
            if (in) text += line + "\n";
        }
        return text;
    };
    EXPECT_EQ(under("1"),
              "  worst: pom layers=8 [cpu/float] on bricks s=0.02 b=1 theta=0 phi=45: "
              "0.4\n")
        << r.out;
    // A min: the lowest value is the worst, in the table too.
    EXPECT_EQ(under("2"),
              "  worst: pom layers=8 [glsl/r16] on bricks s=0.05 b=1 theta=70 phi=30: "
              "3\n  failed: pom layers=8 [glsl/r8] on bricks s=0.05 b=1 theta=80 "
              "phi=0: link error\n")
        << r.out;
    EXPECT_NE(r.out.find("fetches_mean          >= 4, <= 10 3 "), std::string::npos) << r.out;
    EXPECT_EQ(under("3"),
              "  failed: pom layers=8 [glsl/r8] on bricks s=0.05 b=1 theta=80 phi=0: "
              "link error\n")
        << r.out;
    EXPECT_EQ(under("4"),
              "  non-finite: relief layers=4 [cpu/float] on bricks s=0.05 b=1 "
              "theta=60 phi=0: empty\n")
        << r.out;
    EXPECT_EQ(under("5"), "  worst: parallax [cpu/float] on fbm s=0.1 b=0.5 theta=85 phi=90: 5\n")
        << r.out;
    EXPECT_NE(r.out.find("0 passed, 5 failed"), std::string::npos) << r.out;
    // Passing, the same table has no such lines.
    const auto ok = pxh("check " + res + " --accept-edited --thresholds " +
                        write("ok.toml",
                              "[[limit]]\nmethod = \"pom\"\nbackend = \"cpu\"\ncolumn = "
                              "\"err_p95\"\nmax = 1\n"));
    EXPECT_EQ(ok.status, 0) << ok.out << ok.err;
    EXPECT_EQ(ok.out.find("worst:"), std::string::npos) << ok.out;
}

// A text column or an unknown one: one error line at the column key's line, listing the
// numeric columns a limit may name; exit 2.
TEST_F(ReportFolder, CheckColumnErrorsListNumericColumns) {
    const std::string res = results({row({})});
    const std::string numeric =
        "(the measured numeric columns of results.csv: err_mean, err_p50, err_p95, err_p99, "
        "frac_gt_1, nonfinite, fetches_mean, time, double_diff_max, "
        "sliding, shimmering)\n";
    struct Case {
        std::string column, expect;
    };
    const Case cases[] = {
        {"status",
         "column 'status' is not numeric (it holds text): a limit needs a numeric "
         "column "},
        {"method",
         "column 'method' is not numeric (it holds text): a limit needs a numeric "
         "column "},
        {"err_p96", "results.csv has no column 'err_p96' "},
        {"err_rms", "results.csv has no column 'err_rms' "},  // registered, not in this file
    };
    for (const auto& c : cases) {
        const std::string t = write("t.toml", "# gate\n\n[[limit]]\nmethod = \"pom\"\ncolumn = \"" +
                                                  c.column + "\"\nmax = 1\n");
        const auto r = pxh("check " + res + " --accept-edited --thresholds " + t);
        EXPECT_EQ(r.status, 2) << r.out << r.err;
        const std::string expect = "pxh: error: " + t + ":5: " + c.expect + numeric;
        // One line, the last of stderr (--accept-edited warns before it).
        EXPECT_TRUE(r.err.size() >= expect.size() &&
                    r.err.compare(r.err.size() - expect.size(), expect.size(), expect) == 0)
            << r.err << "\nexpected: " << expect;
    }
    // A column results.csv has but this pxh does not write.
    const fs::path csv = fs::path(res) / "results.csv";
    std::string text = slurp(csv);
    text.insert(text.find('\n'), ",my_metric");
    text.insert(text.rfind('\n'), ",1");
    std::ofstream(csv, std::ios::binary) << text;
    EXPECT_NE(input_error([&] { check(res, "[[limit]]\ncolumn = \"my_metric\"\nmax = 1\n"); })
                  .find("limits.toml:2: column 'my_metric' is not a column this pxh writes (the "
                        "measured numeric columns of results.csv: err_mean,"),
              std::string::npos);
}

// The report names every file it writes; missing values are empty CSV cells (never "nan");
// map paths stay relative to the results folder.
TEST_F(ReportFolder, ListsEveryFileEmptyCellsRelativeMaps) {
    const std::string res = results({
        row({{"double_diff_max", "2e-06"},
             {"sliding", "0.1"},
             {"shimmering", "0.2"},
             {"map", "maps/a.png"}}),
        glsl("r8", {{"map", "maps/b.png"}}),
        row({{"status", "failed"}, {"error", "x"}, {"theta_deg", "40"}, {"err_p95", ""}}),
    });
    const std::string out = report(res);
    const fs::path rep = fs::path(res) / "report";
    size_t files = 0;
    for (const auto& e : fs::recursive_directory_iterator(rep)) {
        if (!e.is_regular_file()) continue;
        ++files;
        EXPECT_NE(out.find("wrote " + e.path().string() + "\n"), std::string::npos)
            << e.path() << "\n"
            << out;
        if (e.path().extension() == ".csv") {
            EXPECT_EQ(slurp(e.path()).find("nan"), std::string::npos) << e.path();
        }
    }
    // summary x3, fields x3 (one field), legend x2, failed, sweep, precision, budget x2,
    // data x5 (maps: with the colour scale), manifest; the families present (texel, fetches,
    // timing, sliding): families/F.md and .csv each, and data/families/index.csv, but no
    // family figure's data: error_vs_theta and sweep_vs_theta draw texel and sliding against
    // θ, fetches are flat in θ here, and timing is in two units
    EXPECT_EQ(files, 19u + 4 * 2 + 1);
    for (const char* f : {"texel", "fetches", "timing", "sliding"})
        EXPECT_TRUE(fs::exists(rep / "families" / (std::string(f) + ".md"))) << f;
    EXPECT_TRUE(std::isnan(summary(rep, "pom layers=8 [glsl/r8]", "all", "time[ns/sample]")));
    EXPECT_EQ(summary(rep, "pom layers=8 [glsl/r8]", "all", "time[ms/frame]"), 0.5);
    const pxh::CsvTable maps = pxh::read_csv((rep / "data" / "maps.csv").string());
    ASSERT_EQ(maps.rows.size(), 2u);
    EXPECT_EQ(maps.get(0, "map"), "maps/a.png");
    EXPECT_EQ(maps.get(1, "map"), "maps/b.png");
}

// Numbers are whole cells: the parser, and the report naming results.csv:LINE and the column.
TEST(CsvNumbers, WholeCellsOnly) {
    for (const char* bad :
         {"0.5garbage", "0x0 broken", "0x0", " 1", "1 ", "+1", "--1", "1,5", "one"})
        EXPECT_FALSE(pxh::parse_number(bad).has_value()) << bad;
    EXPECT_FALSE(pxh::parse_number("").has_value());
    EXPECT_EQ(*pxh::parse_number("inf"), INFINITY);
    EXPECT_EQ(*pxh::parse_number("-inf"), -INFINITY);
    EXPECT_TRUE(std::isnan(*pxh::parse_number("nan")));
    EXPECT_EQ(*pxh::parse_number("2.5e-3"), 2.5e-3);
    EXPECT_EQ(*pxh::parse_number("-7"), -7);
}

TEST_F(ReportFolder, MalformedNumberNamesLineAndColumn) {
    // A quoted newline in row 1: row 2 starts on line 4.
    const std::string res =
        results({row({{"error", "two\nlines"}}), row({{"err_p95", "0.5garbage"}})});
    const pxh::CsvTable t = pxh::read_csv(res + "/results.csv");
    EXPECT_EQ(t.number(0, "err_p95"), 0.2);
    EXPECT_TRUE(std::isnan(t.number(0, "map")));
    EXPECT_TRUE(std::isnan(t.number(0, "no such column")));
    const std::string e = input_error([&] { report(res); });
    EXPECT_NE(e.find("results.csv:4: column 'err_p95': '0.5garbage' is not a number"),
              std::string::npos)
        << e;
    results({row({{"fetches_mean", "0x0 broken"}})});
    EXPECT_NE(input_error([&] { report(res); }).find("results.csv:2: column 'fetches_mean'"),
              std::string::npos);
}

// results.csv is read once into typed rows: a malformed number in any numeric column (used by
// the tables or not) stops `pxh report` and `pxh check` with one line naming file:line and
// column, exit 2.
TEST_F(ReportFolder, MalformedNumberIsOneLineExit2) {
    const std::string res = results({row({}), row({{"time", "1.5.2"}})});
    const std::string expect =
        "pxh: error: " + res + "/results.csv:3: column 'time': '1.5.2' is not a number\n";
    // (--accept-edited on a hand-made folder also warns that run.json is missing.)
    auto one_error_line = [&](const std::string& err) {
        return err.size() >= expect.size() &&
               err.compare(err.size() - expect.size(), expect.size(), expect) == 0 &&
               err.find("pxh: error:") == err.size() - expect.size();
    };
    auto r = pxh("report --no-plots --accept-edited " + res);
    EXPECT_EQ(r.status, 2) << r.out << r.err;
    EXPECT_TRUE(one_error_line(r.err)) << r.err;
    r = pxh("check " + res + " --accept-edited --thresholds " +
            write("t.toml", "[[limit]]\ncolumn = \"err_p95\"\nmax = 1\n"));
    EXPECT_EQ(r.status, 2) << r.out << r.err;
    EXPECT_TRUE(one_error_line(r.err)) << r.err;
}

// A limit of nan would pass every row; a text column cannot be limited (exit 2, not 1).
TEST_F(ReportFolder, NanLimitsAndTextColumnsRefused) {
    const std::string res = results({row({})});
    // The error names the line of the nan key (line 4, or 5 for theta_max), not the table's.
    for (const char* limit : {"max = nan", "min = nan", "max = 1\ntheta_max = nan", "min = -nan"}) {
        const std::string e = input_error(
            [&] { check(res, std::string("\n[[limit]]\ncolumn = \"err_p95\"\n") + limit + "\n"); });
        const bool theta = std::string(limit).find("theta") != std::string::npos;
        EXPECT_NE(e.find(theta ? "limits.toml:5: '" : "limits.toml:4: '"), std::string::npos) << e;
        EXPECT_NE(e.find("' is nan, not a limit"), std::string::npos) << e;
    }
    const std::string e =
        input_error([&] { check(res, "[[limit]]\ncolumn = \"method\"\nmax = 1\n"); });
    EXPECT_NE(e.find("column 'method' is not numeric"), std::string::npos) << e;
    const auto r = pxh("check " + res + " --accept-edited --thresholds " +
                       write("t.toml", "[[limit]]\ncolumn = \"method\"\nmax = 1\n"));
    EXPECT_EQ(r.status, 2) << r.err;
    EXPECT_NE(r.err.find("pxh: error: " + (dir / "t.toml").string() +
                         ":2: column 'method' is not numeric"),
              std::string::npos)
        << r.err;
}

// A FIFO (or anything not a regular file) as thresholds file or results.csv is refused at once
// instead of blocking on the read.
TEST_F(ReportFolder, NonRegularFilesRefused) {
    const std::string res = results({row({})});
    const std::string fifo = (dir / "limits.fifo").string();
    ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
    // The binary runs under `timeout 20`: a blocking read must not hang the test.
    auto run = [&](const std::string& args) { return pxh_timeout(args); };
    auto r = run("check " + res + " --accept-edited --thresholds " + fifo);
    EXPECT_EQ(r.status, 2) << r.out << r.err;
    EXPECT_NE(r.err.find("pxh: error: " + fifo + ": is not a regular file"), std::string::npos)
        << r.err;
    r = run("check " + res + " --accept-edited --thresholds " + dir.string());
    EXPECT_EQ(r.status, 2) << r.err;
    EXPECT_NE(r.err.find("is not a regular file"), std::string::npos) << r.err;
    fs::remove(fs::path(res) / "results.csv");
    ASSERT_EQ(mkfifo((fs::path(res) / "results.csv").c_str(), 0600), 0);
    r = run("report --no-plots --accept-edited " + res);
    EXPECT_EQ(r.status, 2) << r.out << r.err;
    EXPECT_NE(r.err.find("results.csv: is not a regular file"), std::string::npos) << r.err;
}

// Plots are drawn by /usr/bin/python3 from an argument vector: folder names with quotes and
// shell syntax are passed as they are (nothing injected, nothing broken).
TEST_F(ReportFolder, FolderNamesReachThePlotterAsTheyAre) {
    const std::string exp = write("exp.toml", pxh::test::ExperimentToml("tiny")
                                                  .backends("\"cpu\"")
                                                  .set("maps", "true")
                                                  .theta("[0, 60]")
                                                  .field("sine", 16)
                                                  .method("parallax"));
    const auto quote = pxh::test::shell_quote;  // for the shell that runs the binary
    for (const std::string name : {"x'; touch INJECTED; echo '", "it's here"}) {
        const fs::path res = dir / name;
        ASSERT_EQ(pxh("run " + exp + " --quiet --out " + quote(res.string())).status, 0) << name;
        const auto r =
            sh("cd " + quote(dir.string()) + " && " + PXH_BINARY + " report " + quote(name));
        EXPECT_EQ(r.status, 0) << name << ": " << r.err;
        EXPECT_FALSE(fs::exists(dir / "INJECTED")) << name;
        EXPECT_TRUE(fs::exists(res / "report" / "cost_vs_error.png")) << name;
        int montages = 0;  // error_maps_FIELD_pPHI.png
        for (const auto& e : fs::directory_iterator(res / "report"))
            montages += e.path().filename().string().rfind("error_maps_", 0) == 0 &&
                        e.path().extension() == ".png";
        EXPECT_EQ(montages, 1) << name;
        EXPECT_EQ(slurp(dir / "err.txt").find("not found"), std::string::npos)
            << slurp(dir / "err.txt");
    }
    // The report of a moved folder still finds its error maps (paths relative to the folder).
    fs::rename(dir / "it's here", dir / "moved");
    fs::create_directories(dir / "redrawn");
    const std::string cmd =
        "/usr/bin/python3 " + std::string(PXH_SOURCE_DIR) + "/harness/report/plot_report.py " +
        quote((dir / "moved" / "report").string()) + " --into " +
        quote((dir / "redrawn").string()) + " >/dev/null 2>" + quote((dir / "err.txt").string());
    EXPECT_EQ(std::system(cmd.c_str()), 0);
    EXPECT_EQ(slurp(dir / "err.txt").find("not found"), std::string::npos)
        << slurp(dir / "err.txt");
}

}  // namespace
