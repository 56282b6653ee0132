// The results pipeline is driven by its registries: a key and a metric registered only in
// this test reach results.csv, the report's tables and figure data, pxh check, its JSON
// verdict and pxh compare without a line of report code naming them; and a run over the
// plane, a cylinder and a sphere is never averaged across its bases.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "harness/metrics/columns.h"
#include "harness/metrics/metric.h"
#include "harness/report/compare.h"
#include "harness/report/report.h"
#include "harness/results/csv_table.h"
#include "harness/results/results.h"
#include "harness/run/runner.h"
#include "heightfields/heightfields.h"
#include "tests/cli_util.h"
#include "tests/test_util.h"

namespace pxh {
namespace {

namespace fs = std::filesystem;

class RegisteredFamily : public test::CliTest {};

double mean_of(const std::vector<double>& v) {
    double s = 0;
    for (double x : v) s += x;
    return v.empty() ? NAN : s / double(v.size());
}

// A key "test_knob" (1 where err_mean < 0.05, else 2: a context key, since it varies) and a metric
// "test_score" = 2 err_mean + knob, of a family "testfam" that no report code names.
TEST_F(RegisteredFamily, FlowsIntoEveryOutput) {
    Experiment ex;
    ex.samples = 16;
    ex.backend.timing_repeats = 0;
    ex.theta_deg = {0, 30, 50, 70};
    HeightfieldSpec hs = test::generator_spec("sine", 64);
    hs.scale = 0.05;
    hs.bias = 1;
    ex.heightfields = {hs};
    ex.methods.push_back({find_method("pom"), test::params_for(*find_method("pom"))});
    ex.methods.push_back({find_method("parallax"), test::params_for(*find_method("parallax"))});
    const ColumnRegistration knob(
        {"test_knob", ColumnType::number, ColumnRole::key, "test only: a knob", ColumnAxis::named});
    const MetricRegistration reg(
        {"test_score",
         [](const MetricInput& in, ResultRow& row) {
             // (the row's keys are filled after its metrics: the knob reads a measured column)
             const double k = row.num("err_mean") < 0.05 ? 1 : 2;
             row.set("test_knob", k);
             row.set("test_score", 2 * row.num("err_mean") + k);
             (void)in;
         }},
        {ColumnSpec{"test_score", ColumnType::number, ColumnRole::measured, "test only"}
             .in("testfam", "points")
             .lead()});
    const std::vector<ResultRow> rows = run_experiment(ex, RunOptions{});
    ASSERT_EQ(rows.size(), 8u);
    const fs::path res = dir / "res";
    fs::create_directories(res);
    std::ofstream(res / "results.csv") << results_csv(rows);
    const ResultsFile back = read_results((res / "results.csv").string());
    ASSERT_EQ(back.rows.size(), 8u);
    std::map<std::string, int> knobs;  // rows per knob value
    std::set<std::pair<std::string, std::string>> method_knobs;
    for (const auto& r : back.rows) {
        EXPECT_NEAR(r.num("test_score"), 2 * r.num("err_mean") + r.num("test_knob"), 1e-9);
        ++knobs[r.cell("test_knob")];
        method_knobs.emplace(r.text("method"), r.cell("test_knob"));
    }
    ASSERT_EQ(knobs.size(), 2u);  // both values occur: the knob varies

    ReportOptions o;
    o.plots = false;
    testing::internal::CaptureStdout();
    ASSERT_EQ(run_report(res.string(), o), 0);
    testing::internal::GetCapturedStdout();
    // summary.md: a table per knob value, never one mean over both.
    const std::string summary = slurp(res / "report" / "summary.md");
    EXPECT_NE(summary.find("test_knob = 1"), std::string::npos) << summary;
    EXPECT_NE(summary.find("test_knob = 2"), std::string::npos) << summary;
    // The family's table: per method and knob, the mean of test_score over its rows.
    const CsvTable fam = read_csv((res / "report" / "families" / "testfam.csv").string());
    size_t checked = 0;
    for (size_t i = 0; i < fam.rows.size(); ++i) {
        if (fam.get(i, "band") != "all") continue;
        std::vector<double> v;
        for (const auto& r : back.rows)
            if (r.text("method") == fam.get(i, "method") &&
                r.cell("test_knob") == fam.get(i, "test_knob"))
                v.push_back(r.num("test_score"));
        ASSERT_FALSE(v.empty()) << slurp(res / "report" / "families" / "testfam.csv");
        EXPECT_NEAR(std::stod(fam.get(i, "test_score")), mean_of(v), 1e-9 * mean_of(v));
        ++checked;
    }
    EXPECT_EQ(checked, method_knobs.size());  // a line per method and knob value
    // The figure data: a panel per knob value, x = θ.
    const CsvTable fig =
        read_csv((res / "report" / "data" / "families" / "testfam_vs_theta_deg.csv").string());
    std::map<std::string, int> panels;
    for (size_t i = 0; i < fig.rows.size(); ++i) ++panels[fig.get(i, "panel")];
    EXPECT_EQ(panels.size(), 2u);
    // a point per method, θ and knob value: every row its own (one φ, one field)
    EXPECT_EQ(panels["test_knob = 1"], knobs["1"]);
    EXPECT_EQ(panels["test_knob = 2"], knobs["2"]);
    const std::string index = slurp(res / "report" / "data" / "families" / "index.csv");
    EXPECT_NE(index.find("testfam,testfam,theta_deg"), std::string::npos) << index;

    // pxh check limits it, filtered by the registered key, and says so in its JSON verdict.
    double most2 = 0;
    for (const auto& r : back.rows)
        if (r.num("test_knob") == 2) most2 = std::max(most2, r.num("test_score"));
    const auto check = [&](double max) {
        const std::string t =
            write("t.toml", "[[limit]]\ncolumn = \"test_score\"\ntest_knob = 2\nmax = " +
                                std::to_string(max) + "\n");
        CheckOptions co;
        co.json = (dir / "verdict.json").string();
        testing::internal::CaptureStdout();
        const int rc = run_check(res.string(), t, co);
        testing::internal::GetCapturedStdout();
        return rc;
    };
    EXPECT_EQ(check(most2 + 1e-9), 0);
    EXPECT_EQ(check(most2 - 1e-3), 1);
    EXPECT_NE(slurp(dir / "verdict.json").find("test_score"), std::string::npos);

    // pxh compare: rows keyed by the knob too; --only by it; a change of the score fails.
    const fs::path res2 = dir / "res2";
    fs::create_directories(res2);
    std::vector<ResultRow> worse = rows;
    for (auto& r : worse)
        if (r.num("test_knob") == 2) r.set("test_score", r.num("test_score") + 1);
    std::ofstream(res2 / "results.csv") << results_csv(worse);
    CompareOptions co;
    co.fail_on = parse_fail_on("test_score=+0.5");
    std::ostringstream out;
    EXPECT_EQ(run_compare(res.string(), res2.string(), co, out), 1) << out.str();
    co.only = "test_knob=1";
    std::ostringstream out1;
    EXPECT_EQ(run_compare(res.string(), res2.string(), co, out1), 0) << out1.str();
}

class MixedBases : public test::CliTest {};

// Plane, cylinder and sphere rows in one run: summary.md has a table per base and radius, and
// the texel family's per-base means are the test's own means over results.csv.
TEST_F(MixedBases, PerBaseMeansAreNeverPooled) {
    const std::string toml = write("mixed.toml", R"(name = "mixed"
samples = 16
backends = ["cpu"]
precision = "float"
timing_repeats = 0
[views]
theta_deg = [0, 40, 70]
phi_deg = [30]
camera = "perspective"
distance = 2
fov_deg = 40
[[heightfields]]
generator = "bricks"
size = 64
scale = 0.05
bias = 1.0
base = ["plane", "cylinder", "sphere"]
radius = [0.5]
[[methods]]
name = "pom"
layers = 16
)");
    const std::string res = (dir / "res").string();
    const auto run = pxh("run " + toml + " --out " + res);
    ASSERT_EQ(run.status, 0) << run.err;
    const auto rep = pxh("report " + res + " --no-plots");
    ASSERT_EQ(rep.status, 0) << rep.err;
    const ResultsFile back = read_results((dir / "res" / "results.csv").string());
    std::map<std::string, std::vector<double>> by_base;
    for (const auto& r : back.rows) by_base[r.text("base")].push_back(r.num("err_mean"));
    ASSERT_EQ(by_base.size(), 3u);
    const CsvTable t = read_csv((dir / "res" / "report" / "families" / "texel.csv").string());
    size_t seen = 0;
    for (size_t i = 0; i < t.rows.size(); ++i) {
        if (t.get(i, "band") != "all") continue;
        const std::string base = t.get(i, "base");
        ASSERT_TRUE(by_base.count(base)) << base;
        EXPECT_NEAR(std::stod(t.get(i, "err_mean")), mean_of(by_base[base]),
                    1e-9 * mean_of(by_base[base]))
            << base;
        ++seen;
    }
    EXPECT_EQ(seen, 3u);
    // summary.md: one table per base, none pooling them (its headings name the base)
    const std::string summary = slurp(dir / "res" / "report" / "summary.md");
    EXPECT_NE(summary.find("base = cylinder"), std::string::npos) << summary;
    EXPECT_NE(summary.find("base = sphere"), std::string::npos) << summary;
    // The command line's summary: a line per base, aligned (every line the header's width or
    // less, the numbers right-aligned under their headers)
    EXPECT_NE(run.out.find("cylinder"), std::string::npos) << run.out;
    EXPECT_NE(run.out.find("sphere"), std::string::npos) << run.out;
}

}  // namespace
}  // namespace pxh
