// pxh compare's timing verdicts over a whole comparison: the rows' Mann-Whitney U tests are
// Holm-corrected, so unchanged code timed twice (noise alone) gives no time regression where
// per-row tests at p < 0.05 gave several, while a 1.5x slowdown is still caught; a row counts
// only when its median also grew beyond the --fail-on margin. Rows with too few repeats for a
// verdict of their own are judged together (a signed-rank test over their median ratios, in
// the same Holm family): unchanged code with a uniform 3% drift passes, 1.5x is caught.
// TimingUnderLoad times a CPU experiment beside a busy loop: its repeats 1.05x slower (within the
// margin) give no regression, 1.5x slower are caught.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "harness/metrics/timing_stats.h"
#include "harness/results/csv_table.h"
#include "tests/cli_util.h"

namespace fs = std::filesystem;

namespace {

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const size_t n = v.size();
    return n % 2 ? v[n / 2] : (v[n / 2 - 1] + v[n / 2]) / 2;
}

std::string joined(const std::vector<double>& v) {
    std::string s;
    char b[32];
    for (double x : v) {
        std::snprintf(b, sizeof b, "%.17g", x);
        s += (s.empty() ? "" : ";") + std::string(b);
    }
    return s;
}

class TimingFamily : public pxh::test::CliTest {
  protected:
    std::string d(const std::string& name) { return (dir / name).string(); }
    // A copy of results folder FROM whose rows' timings are `times[row]` (each row's repeats;
    // time the median, time_min and time_max their ends), run.json beside it.
    void timed_copy(const std::string& from, const std::string& to,
                    const std::vector<std::vector<double>>& times) {
        fs::create_directories(dir / to);
        const pxh::CsvTable t = pxh::read_csv(d(from) + "/results.csv");
        const int c_t = t.index("time"), c_min = t.index("time_min"), c_max = t.index("time_max"),
                  c_rep = t.index("time_repeats");
        ASSERT_TRUE(c_t >= 0 && c_min >= 0 && c_max >= 0 && c_rep >= 0);
        std::stringstream in(slurp(dir / from / "results.csv"));
        std::string out, line;
        for (size_t n = 0; std::getline(in, line); ++n) {
            if (n > 0) {
                std::vector<std::string> f;
                std::stringstream ls(line);
                for (std::string x; std::getline(ls, x, ',');) f.push_back(x);
                if (line.back() == ',') f.push_back("");
                ASSERT_EQ(f.size(), t.columns.size()) << "a quoted comma in: " << line;
                const std::vector<double>& r = times.at(n - 1);
                char b[32];
                std::snprintf(b, sizeof b, "%.17g", median(r));
                f[size_t(c_t)] = b;
                std::snprintf(b, sizeof b, "%.17g", *std::min_element(r.begin(), r.end()));
                f[size_t(c_min)] = b;
                std::snprintf(b, sizeof b, "%.17g", *std::max_element(r.begin(), r.end()));
                f[size_t(c_max)] = b;
                f[size_t(c_rep)] = joined(r);
                line.clear();
                for (size_t i = 0; i < f.size(); ++i) line += (i ? "," : "") + f[i];
            }
            out += line + "\n";
        }
        write(to + "/results.csv", out);
        fs::copy_file(dir / from / "run.json", dir / to / "run.json");
    }
};

// 90 CPU rows of 10 repeats each, timed twice with nothing changed: every repeat of both runs
// drawn from the same distribution (10% spread), so every "change" is noise. Per-row U tests at
// p < 0.05 call some rows slower by more than a 5% margin (counted here from the same test
// pxh uses: what the gate failed on before); Holm over the 90 rows calls none. NEW 1.5x slower:
// caught on most rows.
TEST_F(TimingFamily, UnchangedCodeIsNoRegressionAndASlowdownIsCaught) {
    std::string e =
        "name = \"t\"\nsamples = 8\ntiming_repeats = 10\n"
        "[views]\ntheta_deg = [0, 10, 20, 30, 40, 50, 60, 70, 80]\n"
        "phi_deg = [0, 45, 90, 135, 180]\n"
        "[[heightfields]]\ngenerator = \"sine\"\nsize = 16\n"
        "[[methods]]\nname = \"parallax\"\n[[methods]]\nname = \"pom\"\nlayers = 8\n";
    const auto run = pxh("run " + write("t.toml", e) + " --quiet --out " + d("a"));
    ASSERT_EQ(run.status, 0) << run.out << run.err;
    const size_t rows = pxh::read_csv(d("a") + "/results.csv").rows.size();
    ASSERT_EQ(rows, 90u);
    std::mt19937 rng(1);
    std::normal_distribution<double> noise(0.0, 0.1);
    const auto draw = [&](double scale) {
        std::vector<std::vector<double>> t(rows);
        for (size_t i = 0; i < rows; ++i)
            for (int k = 0; k < 10; ++k) t[i].push_back(scale * 100.0 * std::exp(noise(rng)));
        return t;
    };
    const auto base = draw(1.0), again = draw(1.0), slow = draw(1.5);
    timed_copy("a", "base", base);
    timed_copy("a", "again", again);
    timed_copy("a", "slow", slow);
    // What per-row tests at p < 0.05 say of the unchanged pair: some rows "slower" beyond the
    // margin (the gate failed on each of them before Holm).
    int per_row_alarms = 0;
    for (size_t i = 0; i < rows; ++i) {
        const pxh::UTest u = pxh::mann_whitney_u(again[i], base[i]);
        if (u.p < 0.05 && u.u > 50 && median(again[i]) > 1.05 * median(base[i])) ++per_row_alarms;
    }
    ASSERT_GE(per_row_alarms, 1) << "the draws must show what an uncorrected gate cried wolf on";

    const auto same = pxh("compare " + d("base") + " " + d("again") +
                          " --accept-edited --fail-on err_p95=+0,time=+5%");
    EXPECT_EQ(same.status, 0) << same.out << same.err;
    EXPECT_NE(same.out.find("PASS: 0 regression(s)"), std::string::npos) << same.out;
    EXPECT_NE(same.out.find("Holm over the 90 rows tested"), std::string::npos) << same.out;
    EXPECT_NE(same.out.find(": 0 slower, 0 faster, 90 no significant change"), std::string::npos)
        << same.out;

    const auto slower = pxh("compare " + d("base") + " " + d("slow") +
                            " --accept-edited --fail-on err_p95=+0,time=+10%");
    EXPECT_EQ(slower.status, 1) << slower.out << slower.err;
    const size_t at = slower.out.find(" slower, 0 faster, ");
    ASSERT_NE(at, std::string::npos) << slower.out;
    const size_t from = slower.out.rfind(' ', at - 1) + 1;
    const int caught = std::stoi(slower.out.substr(from, at - from));
    EXPECT_GE(caught, 80) << slower.out;
    EXPECT_NE(slower.out.find("FAIL: " + std::to_string(caught) + " regression(s)"),
              std::string::npos)
        << slower.out;
    // A significant change within the margin is no regression: 1.5x against +100%.
    const auto margin =
        pxh("compare " + d("base") + " " + d("slow") + " --accept-edited --fail-on time=+100%");
    EXPECT_EQ(margin.status, 0) << margin.out;
    // Too few repeats for Holm's first level over these rows (5 + 5 repeats give at best
    // p = 0.007937 > 0.05 / 91): said, and the rows are judged together by the pooled
    // signed-rank test (one more member of the Holm family): 1.5x slower is caught, with that
    // reason, on every row past the margin.
    std::vector<std::vector<double>> b5, s5, a5;
    for (size_t i = 0; i < rows; ++i) {
        b5.emplace_back(base[i].begin(), base[i].begin() + 5);
        s5.emplace_back(slow[i].begin(), slow[i].begin() + 5);
        // unchanged code on a machine 3% busier: every repeat 3% slower, then noise
        a5.emplace_back();
        for (int k = 5; k < 10; ++k) a5.back().push_back(1.03 * again[i][size_t(k)]);
    }
    timed_copy("a", "b5", b5);
    timed_copy("a", "s5", s5);
    timed_copy("a", "a5", a5);
    const auto few =
        pxh("compare " + d("b5") + " " + d("s5") + " --accept-edited --fail-on time=+10%");
    EXPECT_EQ(few.status, 1) << few.out;
    EXPECT_NE(few.out.find("90 row(s) have too few repeats for Holm's first level p <= 0.0005495"),
              std::string::npos)
        << few.out;
    EXPECT_NE(few.out.find("timing, pooled: the 90 rows with too few repeats"), std::string::npos)
        << few.out;
    EXPECT_NE(few.out.find("too few repeats for a verdict of its own, but the 90 such rows "
                           "together are slower"),
              std::string::npos)
        << few.out;
    // The same 5-repeat rows unchanged, 3% slower from load: each row's median moves by noise,
    // many beyond 10% (what failed unchanged code before), but together they are not slower
    // beyond the margin: no regression.
    int beyond = 0;
    for (size_t i = 0; i < rows; ++i) beyond += median(a5[i]) > 1.10 * median(b5[i]);
    ASSERT_GE(beyond, 3) << "the draws must show rows past the margin by noise alone";
    const auto drift =
        pxh("compare " + d("b5") + " " + d("a5") + " --accept-edited --fail-on time=+10%");
    EXPECT_EQ(drift.status, 0) << drift.out;
    EXPECT_NE(drift.out.find("PASS: 0 regression(s)"), std::string::npos) << drift.out;
    EXPECT_NE(drift.out.find(": not slower beyond the margin"), std::string::npos) << drift.out;
}

class TimingUnderLoad : public TimingFamily {
  protected:
    // A busy loop on one core for as long as it lives (killed by its process id).
    struct BusyLoop {
        explicit BusyLoop(const fs::path& pid_file) : pid_file_(pid_file) {
            const int rc = std::system(
                ("sh -c 'while :; do :; done' >/dev/null 2>&1 & echo $! > " + pid_file.string())
                    .c_str());
            EXPECT_EQ(rc, 0);
        }
        ~BusyLoop() {
            std::string pid = pxh::test::slurp(pid_file_);
            pid.erase(std::remove(pid.begin(), pid.end(), '\n'), pid.end());
            if (!pid.empty()) (void)std::system(("kill " + pid + " 2>/dev/null").c_str());
        }
        fs::path pid_file_;
    };
    // Every row's timed repeats, in file order.
    std::vector<std::vector<double>> repeats_of(const std::string& folder) {
        const pxh::CsvTable t = pxh::read_csv(d(folder) + "/results.csv");
        std::vector<std::vector<double>> r;
        for (size_t i = 0; i < t.rows.size(); ++i)
            r.push_back(pxh::parse_repeats(t.get(i, "time_repeats")).value());
        return r;
    }
};

// A CPU experiment (90 rows, 10 single-thread repeats each) timed while a busy loop loads the
// machine. The gate's verdicts are tested on its own repeats, not on a second timed run: two
// real runs differ by whatever the machine did meanwhile (a burst over one row's ten repeats
// moved a row 1.7x on the 2-core CI machine), so asserting that two runs agree would be a timed
// assertion, which the suite does not make (speed is measured by benchmarks). Every repeat
// 1.05x (slower, mostly significantly, but within the 20% margin): no regression. Every repeat
// 1.5x (a method made 1.5x slower): caught on most rows. GLSL frames are no use here:
// llvmpipe's frame times under the same loop moved by up to 2.4x between two runs
// (docs/guide/gates.md).
TEST_F(TimingUnderLoad, AShiftWithinTheMarginPassesAndASlowerMethodIsCaught) {
    const std::string e =
        write("t.toml",
              "name = \"t\"\nsamples = 16\ntiming_repeats = 10\n"
              "[views]\ntheta_deg = [0, 10, 20, 30, 40, 50, 60, 70, 80]\n"
              "phi_deg = [0, 45, 90, 135, 180]\n"
              "[[heightfields]]\ngenerator = \"sine\"\nsize = 16\n"
              "[[methods]]\nname = \"parallax\"\n[[methods]]\nname = \"pom\"\nlayers = 8\n");
    {
        BusyLoop busy(dir / "busy.pid");
        const auto r = pxh("run " + e + " --quiet --out " + d("one"));
        ASSERT_EQ(r.status, 0) << r.out << r.err;
    }
    const auto scaled = [&](double f) {
        std::vector<std::vector<double>> rows = repeats_of("one");
        for (auto& row : rows)
            for (double& t : row) t *= f;
        return rows;
    };
    timed_copy("one", "within", scaled(1.05));
    const auto same = pxh("compare " + d("one") + " " + d("within") +
                          " --accept-edited --fail-on err_p95=+0,time=+20%");
    EXPECT_EQ(same.status, 0) << same.out << same.err;
    EXPECT_NE(same.out.find("PASS: 0 regression(s)"), std::string::npos) << same.out;
    EXPECT_NE(same.out.find("Holm over the 90 rows tested"), std::string::npos) << same.out;
    timed_copy("one", "slow", scaled(1.5));
    const auto caught = pxh("compare " + d("one") + " " + d("slow") +
                            " --accept-edited --fail-on err_p95=+0,time=+20%");
    EXPECT_EQ(caught.status, 1) << caught.out << caught.err;
    const size_t at = caught.out.find(" slower, ");
    ASSERT_NE(at, std::string::npos) << caught.out;
    const size_t from = caught.out.rfind(' ', at - 1) + 1;
    EXPECT_GE(std::stoi(caught.out.substr(from, at - from)), 80) << caught.out;
    EXPECT_NE(caught.out.find("FAIL: "), std::string::npos) << caught.out;
}

}  // namespace
