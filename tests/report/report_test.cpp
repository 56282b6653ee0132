// pxh check and pxh report, through the binary, on a real small run.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "harness/results/csv_table.h"
#include "tests/cli_util.h"

namespace {

namespace fs = std::filesystem;

class ReportCheck : public pxh::test::SuiteCliTest<ReportCheck> {
  public:
    static constexpr const char* kDirName = "report_test";

  protected:
    static void SetUpTestSuite() {
        make_dir();
        write("exp.toml", pxh::test::ExperimentToml("small")
                              .samples(32)
                              .backends("\"cpu\", \"glsl\"")
                              .timing_repeats(1)
                              .set("maps", "true")
                              .set("sweep_dt_deg", "0.5")
                              .theta("[10, 45, 70, 80]")
                              .field("bricks", 64)
                              .field("sine", 64)
                              .method("parallax")
                              .method("steep", "layers = 8")
                              .method("pom", "layers = [8, 32]"));
        run_or_record("run " + d("exp.toml") + " --quiet --out " + d("res"));
    }
    // The params of pom's layers=32 setting as results.csv spells them (other parameters of
    // the method may be listed after layers).
    static std::string pom32_params() {
        const pxh::CsvTable t = pxh::read_csv((dir / "res" / "results.csv").string());
        for (size_t r = 0; r < t.rows.size(); ++r)
            if (t.get(r, "method") == "pom" && t.get(r, "params").rfind("layers=32", 0) == 0)
                return t.get(r, "params");
        return "(no pom layers=32 row)";
    }
    static std::string thresholds(const std::string& name, const std::string& text) {
        return write(name, text);
    }
};

TEST_F(ReportCheck, PassingLimitsExitZero) {
    const auto t = thresholds("ok.toml", R"(
[[limit]]
method = "pom"
params = ")" + pom32_params() + R"("
theta_max = 70
column = "err_p95"
max = 1.0
[[limit]]
column = "nonfinite"
max = 0
)");
    EXPECT_EQ(run("check " + (dir / "res").string() + " --thresholds " + t), 0)
        << slurp(dir / "err.txt");
    EXPECT_NE(slurp(dir / "out.txt").find("2 passed, 0 failed"), std::string::npos);
}

// A tightened limit (half the measured worst) must fail.
TEST_F(ReportCheck, TightenedLimitFails) {
    const pxh::CsvTable t = pxh::read_csv((dir / "res" / "results.csv").string());
    double worst = 0;
    for (size_t r = 0; r < t.rows.size(); ++r)
        if (t.get(r, "method") == "steep") worst = std::max(worst, t.number(r, "err_p95"));
    ASSERT_GT(worst, 0);
    const auto th =
        thresholds("tight.toml", "[[limit]]\nmethod = \"steep\"\ncolumn = \"err_p95\"\nmax = " +
                                     std::to_string(worst / 2) + "\n");
    EXPECT_EQ(run("check " + (dir / "res").string() + " --thresholds " + th), 1);
    EXPECT_NE(slurp(dir / "out.txt").find("FAIL"), std::string::npos);
}

// A perturbed method (a pom shader that shifts its answer by a tenth of a texel) fails the
// accuracy gate that the real shader passes.
TEST_F(ReportCheck, PerturbedMethodFailsTheGate) {
    fs::create_directories(dir / "shaders");
    std::ofstream(dir / "shaders" / "pom.frag.glsl") << R"(
vec2 pxh_method(vec2 P) {
    PxhLayers r = pxh_layer_search(P);
    vec2 uv_k = pxh_uv_at(r, float(r.k));
    if (r.k == 0 || !r.crossed) return uv_k;
    float w = clamp(r.g_k / (r.g_k - r.g_prev), 0.0, 1.0);
    return pxh_uv_at(r, float(r.k - 1)) * w + uv_k * (1.0 - w) + vec2(0.1 / float(u_size.x), 0.0);
}
)";
    const auto th = thresholds("gate.toml", R"(
[[limit]]
method = "pom"
backend = "glsl"
column = "cpu_diff_p999"
max = 0.001
)");
    EXPECT_EQ(run("check " + (dir / "res").string() + " --thresholds " + th), 0);
    ASSERT_EQ(run("run " + (dir / "exp.toml").string() + " --quiet --shader-dir " +
                  (dir / "shaders").string() + " --out " + (dir / "perturbed").string()),
              0);
    EXPECT_EQ(run("check " + (dir / "perturbed").string() + " --thresholds " + th), 1);
}

TEST_F(ReportCheck, MalformedOrEmptyLimitsExitTwo) {
    const std::string res = (dir / "res").string();
    struct Case {
        std::string text, expect;
    };
    const Case cases[] = {
        {"[[limit]]\nmethod = \"nope\"\ncolumn = \"err_p95\"\nmax = 1\n", "matches no row"},
        {"[[limit]]\ncolumn = \"err_p96\"\nmax = 1\n", "no column 'err_p96'"},
        {"[[limit]]\ncolumn = \"err_p95\"\n", "needs 'min' or 'max'"},
        {"[[limit]]\ncolumn = \"err_p95\"\nmax = 1\nmethd = \"pom\"\n", "unknown key 'methd'"},
        {"[[limit]]\ncolumn = \"err_p95\"\nmax = [\n", "TOML syntax error"},
        {"limits = 3\n", "unknown key 'limits'"},
    };
    int k = 0;
    for (const auto& c : cases) {
        const auto th = thresholds("bad" + std::to_string(k++) + ".toml", c.text);
        EXPECT_EQ(run("check " + res + " --thresholds " + th), 2) << c.text;
        const std::string err = slurp(dir / "err.txt");
        EXPECT_NE(err.find(c.expect), std::string::npos) << err;
        EXPECT_NE(err.find(th), std::string::npos) << "names no file: " << err;
    }
    EXPECT_EQ(run("check " + (dir / "nowhere").string() + " --thresholds " +
                  (dir / "bad0.toml").string()),
              2);
}

// The report's numbers are the harness's: recompute two of them from results.csv here.
TEST_F(ReportCheck, ReportTablesAndPlots) {
    ASSERT_EQ(run("report " + (dir / "res").string()), 0) << slurp(dir / "err.txt");
    const fs::path rep = dir / "res" / "report";
    for (const char* f : {"summary.csv", "summary.md", "summary.tex", "budget.md", "budget.tex",
                          "sweep.md", "error_vs_theta.png", "error_vs_theta.pdf",
                          "sweep_vs_theta.png", "cost_vs_error.png", "cost_vs_error.pdf"})
        EXPECT_TRUE(fs::exists(rep / f)) << f;
    // One vector copy of each figure by default: PDF, no SVG (--formats png,pdf,svg adds it)
    EXPECT_FALSE(fs::exists(rep / "error_vs_theta.svg"));
    EXPECT_EQ(run("report " + (dir / "res").string() + " --no-plots --formats png,jpg"), 2);
    EXPECT_NE(slurp(dir / "err.txt")
                  .find("--formats: 'png,jpg' is not a comma list of png, pdf, "
                        "svg"),
              std::string::npos)
        << slurp(dir / "err.txt");
    int montages = 0;  // error_maps_FIELD_pPHI.png: one per field and azimuth
    for (const auto& e : fs::directory_iterator(rep))
        montages += e.path().filename().string().rfind("error_maps_", 0) == 0 &&
                    e.path().extension() == ".png";
    EXPECT_GT(montages, 0);
    const pxh::CsvTable res = pxh::read_csv((dir / "res" / "results.csv").string());
    const pxh::CsvTable sum = pxh::read_csv((rep / "summary.csv").string());
    // pom layers=32 on the CPU, band 60 <= θ < 75 (only θ = 70: flagged †): mean of err_mean
    // over its rows.
    double s = 0;
    int n = 0;
    for (size_t r = 0; r < res.rows.size(); ++r)
        if (res.get(r, "method") == "pom" && res.get(r, "params") == pom32_params() &&
            res.get(r, "backend") == "cpu" && res.number(r, "theta_deg") == 70) {
            s += res.number(r, "err_mean");
            ++n;
        }
    ASSERT_EQ(n, 2);
    bool found = false;
    for (size_t r = 0; r < sum.rows.size(); ++r)
        if (sum.get(r, "series") == "pom " + pom32_params() + " [cpu/float]" &&
            sum.get(r, "band") == "60 <= θ < 75 †") {
            EXPECT_NEAR(sum.number(r, "err_mean"), s / n, 1e-6 * (1 + s / n));
            found = true;
        }
    EXPECT_TRUE(found);
    // Pareto flags: a point is flagged exactly when no other point of its group (the points
    // of its plot panel) dominates it.
    const pxh::CsvTable cost = pxh::read_csv((rep / "data" / "cost_vs_error.csv").string());
    for (size_t i = 0; i < cost.rows.size(); ++i) {
        bool dominated = false;
        for (size_t j = 0; j < cost.rows.size(); ++j) {
            if (cost.get(j, "group") != cost.get(i, "group")) continue;
            const double ci = cost.number(i, "fetches_mean"), ei = cost.number(i, "err_mean");
            const double cj = cost.number(j, "fetches_mean"), ej = cost.number(j, "err_mean");
            if (j != i && cj <= ci && ej <= ei && (cj < ci || ej < ei)) dominated = true;
        }
        EXPECT_EQ(cost.get(i, "pareto_fetches"), dominated ? "0" : "1") << cost.get(i, "series");
    }
    EXPECT_NE(slurp(rep / "summary.tex").find("\\toprule"), std::string::npos);
    // Per band: a point is on its panel's front exactly when no point of the same band and
    // group dominates it; the band's mean error is the mean over the series' rows in it.
    const pxh::CsvTable bands = pxh::read_csv((rep / "data" / "cost_vs_error_bands.csv").string());
    ASSERT_GT(bands.rows.size(), 0u);
    for (size_t i = 0; i < bands.rows.size(); ++i) {
        bool dominated = false;
        const double ci = bands.number(i, "fetches_mean"), ei = bands.number(i, "err_mean");
        for (size_t j = 0; j < bands.rows.size(); ++j) {
            if (j == i || bands.get(j, "group") != bands.get(i, "group") ||
                bands.get(j, "band") != bands.get(i, "band"))
                continue;
            const double cj = bands.number(j, "fetches_mean"), ej = bands.number(j, "err_mean");
            if (cj <= ci && ej <= ei && (cj < ci || ej < ei)) dominated = true;
        }
        EXPECT_EQ(bands.get(i, "pareto_fetches"), dominated ? "0" : "1") << bands.get(i, "series");
        if (bands.get(i, "series") != "pom " + pom32_params() + " [cpu/float]") continue;
        double band_sum = 0;
        int count = 0;
        for (size_t r = 0; r < res.rows.size(); ++r) {
            const double th = res.number(r, "theta_deg");
            if (res.get(r, "method") == "pom" && res.get(r, "params") == pom32_params() &&
                res.get(r, "backend") == "cpu" && th >= bands.number(i, "band_lo") &&
                (th < bands.number(i, "band_hi") || th == 90)) {
                band_sum += res.number(r, "err_mean");
                ++count;
            }
        }
        ASSERT_GT(count, 0);
        EXPECT_NEAR(bands.number(i, "err_mean"), band_sum / count, 1e-6 * (1 + band_sum / count));
    }
}

}  // namespace
