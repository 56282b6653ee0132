// `pxh compare` as a gate people read and trust: timing noise decided by a Mann-Whitney U test
// over the rows' timed repeats (a run against itself: no change; against a shader that does
// clearly more work: a significant slowdown with its p-value; too few repeats: said), the
// verdict first, four significant digits, --common, Markdown with a <details> block, changed
// shader hashes and pxh versions, and the refusals: --fail-on "", rows on other field sizes or
// ground truths.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "harness/results/csv_table.h"
#include "harness/results/results.h"
#include "tests/cli_util.h"

namespace fs = std::filesystem;

namespace {

// A plug-in shader: parallax offset, one fetch. The busy one computes the same uv after a
// 4000-step loop whose result is kept (scaled to nothing), so only its time differs.
const char* kFast =
    "uniform float p_k;\n"
    "vec2 pxh_method(vec2 P) { return P + pxh_V.xy * (p_k * pxh_z(P) / pxh_V.z); }\n";
const char* kBusy =
    "uniform float p_k;\n"
    "vec2 pxh_method(vec2 P) {\n"
    "    float acc = P.x;\n"
    "    for (int i = 0; i < 4000; ++i) acc = sin(acc + float(i) * 1e-3);\n"
    "    return P + pxh_V.xy * (p_k * pxh_z(P) / pxh_V.z) + vec2(acc * 1e-30);\n"
    "}\n";

// THETA: the views' list. 5 + 5 repeats reach p = 0.007937 at best, which Holm's first level
// 0.05 / m allows for m <= 6 timed rows: the timing tests use one view (4 rows).
std::string experiment(const std::string& backends, int repeats,
                       const std::string& theta = "[0, 60]") {
    return "name = \"gate\"\nsamples = 32\nbackends = [" + backends +
           "]\ntiming_repeats = " + std::to_string(repeats) + "\n[views]\ntheta_deg = " + theta +
           "\n"
           "[[heightfields]]\ngenerator = \"fbm\"\nsize = 64\nscale = 0.05\nbias = 1.0\n"
           "[[methods]]\nname = \"parallax\"\n[[methods]]\nname = \"pom\"\nlayers = 8\n";
}

class CompareGate : public pxh::test::CliTest {
  protected:
    std::string d(const std::string& name) { return (dir / name).string(); }
    // A results folder of `exp` (written as NAME.toml, plus files beside it).
    void run_into(const std::string& name, const std::string& exp, const std::string& extra = "") {
        const std::string e = write(name + ".toml", exp);
        const auto r = pxh("run " + e + " --quiet --out " + d(name) + " " + extra);
        ASSERT_EQ(r.status, 0) << r.out << r.err;
    }
    // A copy of a results folder whose results.csv has one cell replaced (row 1 = first row).
    void edited_copy(const std::string& from, const std::string& to, const std::string& column,
                     const std::string& value, int row = 1) {
        fs::create_directories(dir / to);
        const pxh::CsvTable t = pxh::read_csv(d(from) + "/results.csv");
        const int c = t.index(column);
        ASSERT_GE(c, 0) << column;
        std::stringstream in(slurp(dir / from / "results.csv"));
        std::string out, line;
        for (int n = 0; std::getline(in, line); ++n) {
            if (n == row) {
                std::vector<std::string> f;
                std::stringstream ls(line);
                for (std::string x; std::getline(ls, x, ',');) f.push_back(x);
                if (line.back() == ',') f.push_back("");
                ASSERT_EQ(f.size(), t.columns.size()) << "a quoted comma in: " << line;
                f[size_t(c)] = value;
                line.clear();
                for (size_t i = 0; i < f.size(); ++i) line += (i ? "," : "") + f[i];
            }
            out += line + "\n";
        }
        write(to + "/results.csv", out);
    }
    // A copy of a results folder as pxh wrote it before the backends named their own timing:
    // time* as ns_per_sample* on CPU rows and ms_per_frame* on GLSL rows, no time_unit.
    void old_format_copy(const std::string& from, const std::string& to) {
        fs::create_directories(dir / to);
        fs::copy_file(dir / from / "run.json", dir / to / "run.json");
        const pxh::CsvTable t = pxh::read_csv(d(from) + "/results.csv");
        const char* const kTime[] = {"time", "time_min", "time_max", "time_repeats"};
        const char* const kSuffix[] = {"", "_min", "_max", "_repeats"};
        std::string out;
        std::vector<std::string> header;
        for (const auto& c : t.columns)
            if (c != "time_unit" &&
                std::find(std::begin(kTime), std::end(kTime), c) == std::end(kTime))
                header.push_back(c);
        for (const char* prefix : {"ns_per_sample", "ms_per_frame"})
            for (const char* suffix : kSuffix) header.push_back(std::string(prefix) + suffix);
        for (size_t i = 0; i < header.size(); ++i) out += (i ? "," : "") + header[i];
        out += "\n";
        for (size_t r = 0; r < t.rows.size(); ++r) {
            const std::string unit = t.get(r, "time_unit");
            ASSERT_TRUE(unit == "ns/sample" || unit == "ms/frame") << unit;
            for (size_t i = 0; i < header.size(); ++i) {
                std::string cell;
                const std::string& h = header[i];
                const bool ns = h.rfind("ns_per_sample", 0) == 0,
                           ms = h.rfind("ms_per_frame", 0) == 0;
                if (!ns && !ms) cell = t.get(r, h);
                else if (ns == (unit == "ns/sample"))
                    cell = t.get(r, "time" + h.substr(ns ? 13 : 12));
                out += (i ? "," : "") + pxh::csv_quote(cell);
            }
            out += "\n";
        }
        write(to + "/results.csv", out);
    }
    // compare's report from its "rows matched" line on, without the folders' own lines.
    std::string compared(const std::string& base, const std::string& now,
                         const std::string& extra = "") {
        const auto r = pxh("compare " + d(base) + " " + d(now) + " --accept-edited " + extra);
        EXPECT_NE(r.status, 2) << r.err;
        std::stringstream in(r.out);
        std::string out, line;
        bool on = false;
        for (int n = 0; std::getline(in, line); ++n) {
            if (n == 0) out += line + "\n";  // the verdict
            on = on || line.find(" rows matched (") != std::string::npos;
            if (on && line.find(d(base)) == std::string::npos &&
                line.find(d(now)) == std::string::npos)
                out += line + "\n";
        }
        return out + "exit " + std::to_string(r.status);
    }
};

TEST_F(CompareGate, RunAgainstItselfReportsNoChange) {
    run_into("a", experiment("\"cpu\", \"glsl\"", 5, "[60]"));
    const auto r = pxh("compare " + d("a") + " " + d("a") + " --fail-on err_p95=+0,time=+0");
    EXPECT_EQ(r.status, 0) << r.out << r.err;
    // The verdict is the first line; every row's timing: no significant change.
    EXPECT_EQ(r.out.rfind("pxh compare: PASS: 0 regression(s) beyond --fail-on err_p95=+0,"
                          "time=+0\n",
                          0),
              0u)
        << r.out;
    EXPECT_NE(r.out.find("Holm over the 4 rows tested"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("0 slower, 0 faster, 4 no significant change, 0 too few repeats for "
                         "a verdict, 0 without repeats"),
              std::string::npos)
        << r.out;
    EXPECT_NE(r.out.find("1x (noise)"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("shader changes: none"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("pxh version: "), std::string::npos) << r.out;
    EXPECT_NE(r.out.find(" (both)"), std::string::npos) << r.out;
    // Every timed row stored its repeats in its backend's unit: 5 CPU passes, 5 GLSL frames.
    const pxh::CsvTable t = pxh::read_csv(d("a") + "/results.csv");
    for (size_t i = 0; i < t.rows.size(); ++i) {
        const bool cpu = t.get(i, "backend") == "cpu";
        const std::string reps = t.get(i, "time_repeats");
        EXPECT_EQ(std::count(reps.begin(), reps.end(), ';'), 4) << reps;
        EXPECT_EQ(t.get(i, "time_unit"), cpu ? "ns/sample" : "ms/frame");
    }
}

// A results.csv written before the backends named their own timing compares against a new
// one as the new one does against itself: the same verdict, tallies and tables either way,
// with and without a gate on time; a copy with one time scaled shows the same change
// whichever format its base is in.
TEST_F(CompareGate, OldFormatBaselineComparesLikeANewOne) {
    run_into("a", experiment("\"cpu\", \"glsl\"", 5, "[60]"));
    old_format_copy("a", "old");
    EXPECT_EQ(pxh::read_csv(d("old") + "/results.csv").index("time"), -1);
    EXPECT_GE(pxh::read_csv(d("old") + "/results.csv").index("ns_per_sample_repeats"), 0);
    for (const std::string gate : {"", "--fail-on err_p95=+0,time=+0"}) {
        const std::string same = compared("a", "a", gate);
        EXPECT_NE(same.find("4 no significant change"), std::string::npos) << same;
        EXPECT_EQ(compared("old", "a", gate), same);
        EXPECT_EQ(compared("a", "old", gate), same);
    }
    // Every repeat of the first row (CPU) a thousand times slower: a significant slowdown,
    // seen alike from the old and the new baseline.
    const pxh::CsvTable t = pxh::read_csv(d("a") + "/results.csv");
    ASSERT_EQ(t.get(0, "backend"), "cpu");
    std::string slow;
    std::stringstream reps(t.get(0, "time_repeats"));
    for (std::string v; std::getline(reps, v, ';');)
        slow += (slow.empty() ? "" : ";") + std::to_string(std::stod(v) * 1000);
    edited_copy("a", "slow0", "time_repeats", slow);
    edited_copy("slow0", "slow", "time", std::to_string(t.number(0, "time") * 1000));
    fs::copy_file(dir / "a" / "run.json", dir / "slow" / "run.json");
    const std::string from_new = compared("a", "slow", "--fail-on time=+10%");
    EXPECT_NE(from_new.find("FAIL: 1 regression(s)"), std::string::npos) << from_new;
    EXPECT_NE(from_new.find("1 slower, 0 faster, 3 no significant change"), std::string::npos)
        << from_new;
    EXPECT_EQ(compared("old", "slow", "--fail-on time=+10%"), from_new);
}

TEST_F(CompareGate, BusierShaderIsASignificantSlowdown) {
    fs::create_directories(dir / "fast");
    fs::create_directories(dir / "busy");
    write("fast/my.frag.glsl", kFast);
    write("busy/my.frag.glsl", kBusy);
    const std::string exp =
        "name = \"busy\"\nsamples = 32\nbackends = [\"glsl\"]\n"
        "[views]\ntheta_deg = [60]\n[[heightfields]]\ngenerator = \"fbm\"\n"
        "size = 64\nscale = 0.05\nbias = 1.0\n[[methods]]\nname = \"my\"\n"
        "shader = \"my.frag.glsl\"\nmax_fetches = 1\n"
        "uniforms = { p_k = 1.0 }\n";
    run_into("fast/exp", exp);
    run_into("busy/exp", exp);
    const auto r =
        pxh("compare " + d("fast/exp") + " " + d("busy/exp") + " --fail-on err_p95=+0,time=+10%");
    EXPECT_EQ(r.status, 1) << r.out << r.err;
    // 5 frames each, every busy frame slower than every fast one: the exact p = 2 / 252.
    EXPECT_NE(r.out.find("1 slower, 0 faster, 0 no significant change"), std::string::npos)
        << r.out;
    EXPECT_NE(r.out.find("x slower (p=0.007937)"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("my p_k=1 [glsl/r32f] on fbm s=0.05 b=1 theta=60 phi=0: time "),
              std::string::npos)
        << r.out;
    EXPECT_NE(r.out.find("(allowed +10%; slower, p=0.007937)"), std::string::npos) << r.out;
    // The errors did not change: the only regression is the time.
    EXPECT_NE(r.out.find("FAIL: 1 regression(s)"), std::string::npos) << r.out;
    // The shader's hash changed, and is listed.
    EXPECT_NE(r.out.find("shader changes: 1\n  my p_k=1: "), std::string::npos) << r.out;
    // The other way round: significantly faster, no regression.
    const auto back =
        pxh("compare " + d("busy/exp") + " " + d("fast/exp") + " --fail-on time=+10%");
    EXPECT_EQ(back.status, 0) << back.out;
    EXPECT_NE(back.out.find("x faster (p=0.007937)"), std::string::npos) << back.out;
}

TEST_F(CompareGate, TooFewRepeatsIsSaidNotGuessed) {
    run_into("two", experiment("\"cpu\"", 2));
    const auto r = pxh("compare " + d("two") + " " + d("two"));
    EXPECT_EQ(r.status, 0) << r.out << r.err;
    EXPECT_NE(r.out.find("0 slower, 0 faster, 0 no significant change, 4 too few repeats for a "
                         "verdict"),
              std::string::npos)
        << r.out;
    EXPECT_NE(r.out.find("1x (no verdict: too few repeats)"), std::string::npos) << r.out;
    // A time allowed no growth at all, on a slower copy: no verdict is a failed gate, saying why.
    edited_copy("two", "two_slower", "time", "1e9");
    fs::copy_file(dir / "two" / "run.json", dir / "two_slower" / "run.json");
    const auto g =
        pxh("compare " + d("two") + " " + d("two_slower") + " --accept-edited --fail-on time=+0");
    EXPECT_EQ(g.status, 1) << g.out << g.err;
    EXPECT_NE(g.out.find("no verdict: too few repeats, 2 and 2)"), std::string::npos) << g.out;
}

TEST_F(CompareGate, FourDigitsVerdictFirstMarkdownDetails) {
    run_into("a", experiment("\"cpu\"", 0));
    const pxh::CsvTable t = pxh::read_csv(d("a") + "/results.csv");
    size_t k = 0;
    while (k < t.rows.size() && !(t.number(k, "err_p95") > 0)) ++k;
    ASSERT_LT(k, t.rows.size()) << "no row with an error";
    const double p95 = t.number(k, "err_p95");
    char twice[32], base[32], now[32];
    std::snprintf(twice, sizeof twice, "%.10g", 2 * p95);
    std::snprintf(base, sizeof base, "%.4g", p95);
    std::snprintf(now, sizeof now, "%.4g", 2 * p95);
    edited_copy("a", "b", "err_p95", twice, int(k) + 1);
    const auto r = pxh("compare " + d("a") + " " + d("b") +
                       " --accept-edited --fail-on err_p95=+5% --markdown");
    EXPECT_EQ(r.status, 1) << r.out << r.err;
    // The verdict first, then the summary, the regressions, and the tables folded away.
    EXPECT_EQ(
        r.out.rfind("### pxh compare: FAIL: 1 regression(s) beyond --fail-on err_p95=+5%\n", 0), 0u)
        << r.out;
    const size_t reg = r.out.find("err_p95 " + std::string(base) + " -> " + now + " (allowed +5%)"),
                 det = r.out.find("<details><summary>"), end = r.out.find("</details>"),
                 table = r.out.find("| method [backend] |");
    EXPECT_NE(reg, std::string::npos) << r.out;
    EXPECT_LT(reg, det) << r.out;
    EXPECT_LT(det, table) << r.out;
    EXPECT_LT(table, end) << r.out;
    EXPECT_NE(r.out.find("NOT VERIFIED (--accept-edited)"), std::string::npos) << r.out;
}

TEST_F(CompareGate, CommonLeavesOutRowsInOneRunOnly) {
    const std::string exp = experiment("\"cpu\"", 0);
    run_into("all", exp);
    run_into("parallax", exp, "--only method=parallax");
    auto r = pxh("compare " + d("all") + " " + d("parallax") + " --fail-on err_p95=+0");
    EXPECT_EQ(r.status, 1) << r.out;  // pom's rows are missing from NEW
    EXPECT_NE(r.out.find(": missing from NEW"), std::string::npos) << r.out;
    r = pxh("compare " + d("all") + " " + d("parallax") + " --common --fail-on err_p95=+0");
    EXPECT_EQ(r.status, 0) << r.out;
    EXPECT_NE(r.out.find("2 rows matched (0 with changed errors or status), 2 only in BASE, 0 "
                         "only in NEW\n--common: 2 rows only in BASE and 0 only in NEW left out"),
              std::string::npos)
        << r.out;
    EXPECT_NE(r.out.find("Rows only in BASE (left out: --common) (2)"), std::string::npos) << r.out;
}

TEST_F(CompareGate, RefusesWhatCannotBeCompared) {
    run_into("a", experiment("\"cpu\"", 0));
    // --fail-on "" is an error, not a gate switched off.
    auto r = pxh("compare " + d("a") + " " + d("a") + " --fail-on ''");
    EXPECT_EQ(r.status, 2) << r.out;
    EXPECT_EQ(r.err.rfind("pxh: error: --fail-on: '' gives no tolerance", 0), 0u) << r.err;
    EXPECT_EQ(r.out, "") << "nothing compared";
    // A row on another field size: refused with both places named.
    edited_copy("a", "wide", "width", "128");
    r = pxh("compare " + d("a") + " " + d("wide") + " --accept-edited");
    EXPECT_EQ(r.status, 2) << r.out;
    EXPECT_NE(r.err.find("wide/results.csv:2: parallax [cpu/float] on fbm s=0.05 b=1 theta=0 "
                         "phi=0 is on a 128x64 field here but 64x64 in BASE (" +
                         d("a") +
                         "/results.csv:2): compare refuses to match rows across "
                         "different field sizes"),
              std::string::npos)
        << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 2)
        << "a warning and the error: " << r.err;
    // Another ground truth.
    edited_copy("a", "embree", "ground_truth", "embree");
    r = pxh("compare " + d("a") + " " + d("embree") + " --accept-edited");
    EXPECT_EQ(r.status, 2) << r.out;
    EXPECT_NE(r.err.find("is measured against ground truth 'embree' here but 'exact' in BASE"),
              std::string::npos)
        << r.err;
    // Times in another unit: refused, not a ratio of numbers that do not compare.
    run_into("timed", experiment("\"cpu\"", 3));
    edited_copy("timed", "us", "time_unit", "us/sample");
    r = pxh("compare " + d("timed") + " " + d("us") + " --accept-edited");
    EXPECT_EQ(r.status, 2) << r.out;
    EXPECT_NE(r.err.find("us/results.csv:2: parallax [cpu/float] on fbm s=0.05 b=1 theta=0 "
                         "phi=0 is timed in us/sample here but in ns/sample in BASE (" +
                         d("timed") +
                         "/results.csv:2): compare refuses to compare times in different "
                         "units\n"),
              std::string::npos)
        << r.err;
    EXPECT_EQ(r.out, "") << "nothing compared";
}

}  // namespace
