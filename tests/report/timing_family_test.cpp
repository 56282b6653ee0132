// pxh compare's timing verdicts over a whole comparison: the rows' Mann-Whitney U tests are
// Holm-corrected, so unchanged code timed twice (noise alone) gives no time regression where
// per-row tests at p < 0.05 gave several, while a 1.5x slowdown is still caught; a row counts
// only when its median also grew beyond the --fail-on margin. TimingUnderLoad runs the same
// GLSL experiment twice beside a busy loop, and once with a shader that does 1.5x the work.
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
// p < 0.05 call some rows slower by more than the 10% margin (counted here from the same test
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
    std::mt19937 rng(58);
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
        if (u.p < 0.05 && u.u > 50 && median(again[i]) > 1.1 * median(base[i])) ++per_row_alarms;
    }
    ASSERT_GE(per_row_alarms, 1) << "the draws must show what an uncorrected gate cried wolf on";

    const auto same = pxh("compare " + d("base") + " " + d("again") +
                          " --accept-edited --fail-on err_p95=+0,time=+10%");
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
    // A significant change within the margin is no regression: 1.5x against +60%.
    const auto margin =
        pxh("compare " + d("base") + " " + d("slow") + " --accept-edited --fail-on time=+60%");
    EXPECT_EQ(margin.status, 0) << margin.out;
    // Too few repeats for Holm's first level over these rows: said, and a growth beyond the
    // margin is then no pass (5 + 5 repeats give at best p = 0.007937 > 0.05 / 90).
    std::vector<std::vector<double>> b5, s5;
    for (size_t i = 0; i < rows; ++i) {
        b5.emplace_back(base[i].begin(), base[i].begin() + 5);
        s5.emplace_back(slow[i].begin(), slow[i].begin() + 5);
    }
    timed_copy("a", "b5", b5);
    timed_copy("a", "s5", s5);
    const auto few =
        pxh("compare " + d("b5") + " " + d("s5") + " --accept-edited --fail-on time=+10%");
    EXPECT_EQ(few.status, 1) << few.out;
    EXPECT_NE(few.out.find("90 row(s) have too few repeats for Holm's first level p <= 0.0005556"),
              std::string::npos)
        << few.out;
    EXPECT_NE(few.out.find("no verdict: too few repeats, 5 and 5 (at best p=0.007937; Holm over 90 "
                           "timed rows needs p <= 0.0005556)"),
              std::string::npos)
        << few.out;
}

// A plug-in shader whose frame time is a loop of STEPS iterations per pixel (kept: its result is
// added scaled to nothing), so 3000 steps are about 1.5x the work of 2000.
std::string loop_shader(int steps) {
    return "uniform float p_k;\n"
           "vec2 pxh_method(vec2 P) {\n"
           "    float acc = P.x;\n"
           "    for (int i = 0; i < " +
           std::to_string(steps) +
           "; ++i) acc = sin(acc + float(i) * 1e-3);\n"
           "    return P + pxh_V.xy * (p_k * pxh_z(P) / pxh_V.z) + vec2(acc * 1e-30);\n"
           "}\n";
}

class TimingUnderLoad : public TimingFamily {
  protected:
    // A busy loop on one core for as long as it lives (its process group killed after).
    struct BusyLoop {
        explicit BusyLoop(const fs::path& pid_file) : pid_file_(pid_file) {
            std::system(
                ("sh -c 'while :; do :; done' >/dev/null 2>&1 & echo $! > " + pid_file.string())
                    .c_str());
        }
        ~BusyLoop() {
            const std::string pid = pxh::test::slurp(pid_file_);
            if (!pid.empty()) std::system(("kill " + pid + " 2>/dev/null").c_str());
        }
        fs::path pid_file_;
    };
};

// Two GLSL rows (5 frames each, within Holm's first level for 2 rows), run twice unchanged
// beside a busy loop: no time regression at a 20% margin; the shader doing 1.5x the work: slower,
// a time regression on each row whose median grew beyond 20%.
TEST_F(TimingUnderLoad, UnchangedRunsPassAndASlowerShaderIsCaught) {
    for (const char* v : {"fast", "fast2", "slow"}) fs::create_directories(dir / v);
    write("fast/my.frag.glsl", loop_shader(2000));
    write("fast2/my.frag.glsl", loop_shader(2000));
    write("slow/my.frag.glsl", loop_shader(3000));
    const std::string exp =
        "name = \"load\"\nsamples = 64\nbackends = [\"glsl\"]\n"
        "[views]\ntheta_deg = [30, 60]\n[[heightfields]]\ngenerator = \"fbm\"\n"
        "size = 64\nscale = 0.05\nbias = 1.0\n[[methods]]\nname = \"my\"\n"
        "shader = \"my.frag.glsl\"\nmax_fetches = 1\nuniforms = { p_k = 1.0 }\n";
    {
        BusyLoop busy(dir / "busy.pid");
        for (const char* v : {"fast", "fast2", "slow"}) {
            const auto r = pxh("run " + write(std::string(v) + "/exp.toml", exp) +
                               " --quiet --out " + d(std::string(v) + "/out"));
            ASSERT_EQ(r.status, 0) << v << "\n" << r.out << r.err;
        }
    }
    const auto same =
        pxh("compare " + d("fast/out") + " " + d("fast2/out") + " --fail-on err_p95=+0,time=+20%");
    EXPECT_EQ(same.status, 0) << same.out << same.err;
    EXPECT_NE(same.out.find("PASS: 0 regression(s)"), std::string::npos) << same.out;
    const auto slow =
        pxh("compare " + d("fast/out") + " " + d("slow/out") + " --fail-on err_p95=+0,time=+20%");
    EXPECT_EQ(slow.status, 1) << slow.out << slow.err;
    EXPECT_NE(slow.out.find("FAIL: 2 regression(s)"), std::string::npos) << slow.out;
    EXPECT_NE(slow.out.find(": 2 slower, 0 faster, 0 no significant change"), std::string::npos)
        << slow.out;
}

}  // namespace
