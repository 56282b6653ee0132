// Rows as keys plus named metric columns: the column registry, the results.csv writer and its
// typed reader, and a metric registered here (in the test binary only) that reaches
// results.csv, the typed reader and `pxh check` without any other change.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "harness/core/error.h"
#include "harness/metrics/metric.h"
#include "harness/metrics/timing_stats.h"
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

// The header pxh wrote before rows became named cells (identity with earlier results).
TEST(ResultRows, HeaderKeepsItsOrder) {
    const std::vector<std::string> expected = {"method",
                                               "params",
                                               "heightfield",
                                               "heightfield_id",
                                               "backend",
                                               "precision",
                                               "texture_format",
                                               "shader",
                                               "scale",
                                               "bias",
                                               "theta_deg",
                                               "phi_deg",
                                               "samples",
                                               "width",
                                               "height",
                                               "err_mean",
                                               "err_rms",
                                               "err_p50",
                                               "err_p95",
                                               "err_p99",
                                               "err_max",
                                               "frac_gt_0_5",
                                               "frac_gt_1",
                                               "nonfinite",
                                               "fetches_mean",
                                               "fetches_max",
                                               "fetches_bound",
                                               "time",
                                               "time_unit",
                                               "time_min",
                                               "time_max",
                                               "time_repeats",
                                               "gpu_ms_per_frame",
                                               "gpu_ms_per_frame_min",
                                               "gpu_ms_per_frame_max",
                                               "cpu_diff_max",
                                               "cpu_diff_p999",
                                               "decision_mismatch",
                                               "double_diff_max",
                                               "double_diff_p999",
                                               "sliding",
                                               "shimmering",
                                               "sweep_dt_deg",
                                               "map",
                                               "gt_on_filled",
                                               "excluded",
                                               "gt_cells_mean",
                                               "ground_truth",
                                               "gt_agree_p50",
                                               "gt_agree_p99",
                                               "gt_agree_max",
                                               "gt_agree_frac_gt_0_5",
                                               "shadow_err",
                                               "shadow_soft_mae",
                                               "status",
                                               "error"};
    std::vector<std::string> have = result_columns();
    // Columns added since (by other metrics) sit before status and error; the rest is fixed.
    have.erase(std::remove_if(have.begin(), have.end(),
                              [&](const std::string& c) {
                                  return std::find(expected.begin(), expected.end(), c) ==
                                         expected.end();
                              }),
               have.end());
    EXPECT_EQ(have, expected);
    EXPECT_EQ(result_columns().back(), "error");
    for (const ColumnSpec* c : result_column_specs()) EXPECT_FALSE(c->meaning.empty()) << c->name;
}

// The counter columns come from the backends' registry entries: each declared counter's NAME,
// NAME_min, NAME_max right after time_repeats, in registry order, their meaning naming the
// backend and the unit; the old per-backend timing columns are gone.
TEST(ResultRows, CounterColumnsAreTheBackendsDeclarations) {
    const std::vector<std::string> cols = result_columns();
    auto at = std::find(cols.begin(), cols.end(), "time_repeats");
    ASSERT_NE(at, cols.end());
    const std::vector<CounterSpec> counters = backend_counters();
    ASSERT_FALSE(counters.empty());  // glsl's timer-query time
    for (const CounterSpec& c : counters)
        for (const std::string& name : {c.name, c.name + "_min", c.name + "_max"}) {
            ASSERT_NE(++at, cols.end());
            EXPECT_EQ(*at, name);
            const ColumnSpec* spec = find_column(name);
            ASSERT_NE(spec, nullptr) << name;
            EXPECT_EQ(spec->type, ColumnType::number);
            EXPECT_EQ(spec->role, ColumnRole::measured);
            EXPECT_NE(spec->meaning.find("(" + c.unit + ")"), std::string::npos) << spec->meaning;
        }
    EXPECT_EQ(counters.front().name, "gpu_ms_per_frame");
    EXPECT_EQ(counters.front().unit, "ms/frame");
    EXPECT_EQ(backend_timing("cpu").unit, "ns/sample");
    EXPECT_EQ(backend_timing("glsl").unit, "ms/frame");
    for (const char* old : {"ns_per_sample", "ms_per_frame", "ns_per_sample_repeats"})
        EXPECT_EQ(find_column(old), nullptr) << old;
}

// A results.csv written before the backends named their own timing is read as the columns
// they became: a CPU row's ns_per_sample* as time* in ns/sample, a GLSL row's ms_per_frame* in
// ms/frame, an untimed row with no unit; has() answers for the new names.
TEST(ResultRows, OldTimingColumnsReadAsTime) {
    const fs::path p =
        fs::temp_directory_path() / ("pxh_old_timing_" + std::to_string(::getpid()) + ".csv");
    std::ofstream(p) << "method,backend,ns_per_sample,ns_per_sample_min,ns_per_sample_max,"
                        "ns_per_sample_repeats,ms_per_frame,ms_per_frame_min,ms_per_frame_max,"
                        "ms_per_frame_repeats,gpu_ms_per_frame,status\n"
                        "pom,cpu,12.5,12,14,12;12.5;14,,,,,,ok\n"
                        "pom,glsl,,,,,0.75,0.5,1.25,0.5;0.75;1.25,0.25,ok\n"
                        "pom,cpu,,,,,,,,,,ok\n";
    const ResultsFile f = read_results(p.string());
    fs::remove(p);
    ASSERT_EQ(f.rows.size(), 3u);
    EXPECT_TRUE(f.has("time"));
    EXPECT_TRUE(f.has("time_repeats"));
    EXPECT_FALSE(f.has("time_unit"));  // not in that file: each row's unit is implied
    const ResultRow& cpu = f.rows[0];
    EXPECT_EQ(cpu.num("time"), 12.5);
    EXPECT_EQ(cpu.num("time_min"), 12);
    EXPECT_EQ(cpu.num("time_max"), 14);
    EXPECT_EQ(cpu.text("time_repeats"), "12;12.5;14");
    EXPECT_EQ(cpu.text("time_unit"), "ns/sample");
    const ResultRow& gl = f.rows[1];
    EXPECT_EQ(gl.num("time"), 0.75);
    EXPECT_EQ(gl.num("time_min"), 0.5);
    EXPECT_EQ(gl.num("time_max"), 1.25);
    EXPECT_EQ(gl.text("time_repeats"), "0.5;0.75;1.25");
    EXPECT_EQ(gl.text("time_unit"), "ms/frame");
    EXPECT_EQ(gl.num("gpu_ms_per_frame"), 0.25);
    EXPECT_TRUE(std::isnan(f.rows[2].num("time")));
    EXPECT_EQ(f.rows[2].text("time_unit"), "");
    EXPECT_EQ(f.rows[2].text("time_repeats"), "");
}

// A row's timing columns are what its backend measured: time is the median of time_repeats
// (as written and read back), min and max their extremes, the unit the backend's; a counter
// sets its three columns.
TEST(ResultRows, TimingColumnsFromTheOutput) {
    MethodOutput out;
    out.timing = timing_of("ns/sample", {3.5, 1.25, 2.75, 9.0});
    out.counters.push_back({"gpu_ms_per_frame", spread({0.5, 0.25, 2})});
    const GroundTruth gt{};
    const Metric* timing = nullptr;
    for (const Metric* m : output_metrics())
        if (m->name == "timing") timing = m;
    ASSERT_NE(timing, nullptr);
    ResultRow row;
    timing->add(MetricInput{out, gt}, row);
    EXPECT_EQ(row.text("time_unit"), "ns/sample");
    EXPECT_EQ(row.cell("time_repeats"), "3.5;1.25;2.75;9");
    const auto reps = parse_repeats(row.text("time_repeats"));
    ASSERT_TRUE(reps);
    std::vector<double> sorted = *reps;
    std::sort(sorted.begin(), sorted.end());
    EXPECT_EQ(row.num("time"), 0.5 * (sorted[1] + sorted[2]));  // 3.125
    EXPECT_EQ(row.num("time"), 3.125);
    EXPECT_EQ(row.num("time_min"), 1.25);
    EXPECT_EQ(row.num("time_max"), 9.0);
    EXPECT_EQ(row.num("gpu_ms_per_frame"), 0.5);
    EXPECT_EQ(row.num("gpu_ms_per_frame_min"), 0.25);
    EXPECT_EQ(row.num("gpu_ms_per_frame_max"), 2.0);
    ResultRow untimed;
    const MethodOutput none;
    timing->add(MetricInput{none, gt}, untimed);
    EXPECT_EQ(untimed.cell("time"), "");
    EXPECT_EQ(untimed.cell("time_unit"), "");
    EXPECT_EQ(untimed.cell("time_repeats"), "");
    EXPECT_EQ(untimed.cell("gpu_ms_per_frame"), "");
}

// A failed row keeps its keys and has every measured cell empty; numbers and integers are
// written as results.csv always wrote them; a misspelt or mistyped column is a logic error.
TEST(ResultRows, FailedRowsAndFormats) {
    ResultRow ok, bad;
    for (ResultRow* r : {&ok, &bad}) {
        r->set_text("method", "pom");
        r->set("theta_deg", 60);
        r->set("samples", 16);
        r->set("fetches_bound", 33);
        r->set("err_mean", 0.125);
        r->set("nonfinite", 3);
        r->set("err_max", INFINITY);
    }
    bad.fail("shader, \"x\" failed");
    EXPECT_EQ(ok.cell("err_mean"), "0.125");
    EXPECT_EQ(ok.cell("nonfinite"), "3");
    EXPECT_EQ(ok.cell("err_max"), "inf");
    EXPECT_EQ(ok.cell("err_p95"), "");
    EXPECT_EQ(ok.cell("theta_deg"), "60");
    EXPECT_EQ(ok.cell("phi_deg"), "");
    EXPECT_EQ(format_cell_number(1.0 / 3.0), "0.3333333333");
    std::istringstream csv(results_csv({ok, bad}));
    std::string header, line_ok, line_bad;
    std::getline(csv, header);
    std::getline(csv, line_ok);
    std::getline(csv, line_bad);
    const auto cols = result_columns();
    auto cell = [&](const std::string& line, const std::string& col) {
        const pxh::CsvTable t = [&] {
            const fs::path p =
                fs::temp_directory_path() / ("pxh_rows_" + std::to_string(::getpid()) + ".csv");
            std::ofstream(p) << header << "\n" << line << "\n";
            auto r = read_csv(p.string());
            fs::remove(p);
            return r;
        }();
        return t.get(0, col);
    };
    EXPECT_EQ(cell(line_ok, "err_mean"), "0.125");
    EXPECT_EQ(cell(line_bad, "err_mean"), "");
    EXPECT_EQ(cell(line_bad, "nonfinite"), "");
    EXPECT_EQ(cell(line_bad, "err_max"), "");
    EXPECT_EQ(cell(line_bad, "fetches_bound"), "33");  // a key: kept
    EXPECT_EQ(cell(line_bad, "theta_deg"), "60");
    EXPECT_EQ(cell(line_bad, "status"), "failed");
    EXPECT_EQ(cell(line_bad, "error"), "shader, \"x\" failed");
    EXPECT_THROW(ok.set("err_maen", 1), std::logic_error);
    EXPECT_THROW(ok.set("method", 1), std::logic_error);
    EXPECT_THROW(ok.set_text("err_mean", "1"), std::logic_error);
    EXPECT_THROW((void)ok.num("method"), std::logic_error);
}

class RegisteredMetric : public test::CliTest {};

// A metric that exists only in this test binary: the total of the fetches over the samples,
// which must equal fetches_mean x N^2 (computed by the built-in fetches metric). Registering
// it is all it takes for the column to be in results.csv, read back as a number by the
// report's reader, limited by pxh check, and gone again when unregistered.
TEST_F(RegisteredMetric, ReachesResultsCsvAndIsReadBackTyped) {
    Experiment ex;
    ex.samples = 24;
    ex.backend.timing_repeats = 0;
    ex.theta_deg = {0, 45, 70};
    HeightfieldSpec hs = test::generator_spec("sine", 64);
    hs.scale = 0.05;
    hs.bias = 1;
    ex.heightfields = {hs};
    ex.methods.push_back({find_method("pom"), test::params_for(*find_method("pom"))});
    std::vector<ResultRow> rows;
    {
        const MetricRegistration reg(
            {"fetch_total",
             [](const MetricInput& in, ResultRow& row) {
                 long long total = 0;
                 for (int f : in.out.fetches) total += f;
                 row.set("test_fetch_total", double(total));
             }},
            {{"test_fetch_total", ColumnType::integer, ColumnRole::measured,
              "test only: height fetches summed over the samples"}});
        rows = run_experiment(ex, RunOptions{});
        ASSERT_EQ(rows.size(), 3u);
        const auto cols = result_columns();
        ASSERT_GE(cols.size(), 3u);
        EXPECT_EQ(cols[cols.size() - 3], "test_fetch_total");  // before status, error
        fs::create_directories(dir / "res");
        std::ofstream(dir / "res" / "results.csv") << results_csv(rows);
        const ResultsFile back = read_results((dir / "res" / "results.csv").string());
        ASSERT_EQ(back.rows.size(), 3u);
        for (size_t i = 0; i < 3; ++i) {
            const double total = back.rows[i].num("test_fetch_total");
            EXPECT_GT(total, 0);
            EXPECT_NEAR(total, back.rows[i].num("fetches_mean") * 24 * 24, 1e-6 * total) << i;
            EXPECT_EQ(total, rows[i].num("test_fetch_total"));
        }
        // pxh check limits it as it limits any numeric column.
        double most = 0;
        for (const auto& r : rows) most = std::max(most, r.num("test_fetch_total"));
        auto check = [&](double max) {
            const std::string t = write(
                "t.toml",
                "[[limit]]\ncolumn = \"test_fetch_total\"\nmax = " + std::to_string(max) + "\n");
            testing::internal::CaptureStdout();
            const int rc = run_check((dir / "res").string(), t);
            testing::internal::GetCapturedStdout();
            return rc;
        };
        EXPECT_EQ(check(most), 0);
        EXPECT_EQ(check(most - 1), 1);
        // A malformed cell of the new column is named like any other.
        std::string text = results_csv(rows);
        const size_t at = text.find("\n") + 1;
        const size_t col = size_t(cols.size() - 3);
        size_t p = at;
        for (size_t c = 0; c < col; ++c) p = text.find(',', p) + 1;
        text.insert(p, "x");
        std::ofstream(dir / "res" / "results.csv") << text;
        try {
            (void)read_results((dir / "res" / "results.csv").string());
            ADD_FAILURE() << "a malformed cell was read";
        } catch (const InputError& e) {
            EXPECT_NE(std::string(e.what()).find("results.csv:2: column 'test_fetch_total': 'x"),
                      std::string::npos)
                << e.what();
        }
    }
    const auto cols = result_columns();
    EXPECT_EQ(std::find(cols.begin(), cols.end(), "test_fetch_total"), cols.end());
    EXPECT_EQ(results_csv(rows).find("test_fetch_total"), std::string::npos);
}

}  // namespace
}  // namespace pxh
