// `pxh compare BASE NEW` through the binary: identical runs pass, a deliberately worse shader
// (from --shader-dir) regresses beyond --fail-on and is named, rows present in one run only are
// listed (and fail the gate when missing from NEW), bad tolerances are one line with exit 2.
#include "harness/report/compare.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <set>
#include <sstream>

#include "harness/core/error.h"
#include "tests/cli_util.h"

namespace fs = std::filesystem;

namespace {

class Compare : public pxh::test::SuiteCliTest<Compare> {
  public:
    static constexpr const char* kDirName = "compare";

  protected:
    static void SetUpTestSuite() {
        make_dir();
        fs::create_directories(dir / "worse");
        const std::string exp = pxh::test::ExperimentToml("cmp")
                                    .samples(32)
                                    .backends("\"cpu\", \"glsl\"")
                                    .timing_repeats(2)
                                    .theta("[0, 40, 70]")
                                    .field("fbm", 64, "scale = 0.05\nbias = 1.0")
                                    .method("parallax")
                                    .method("pom", "layers = 16");
        write("exp.toml", exp);
        // Only the method's list changes: one row set fewer in NEW.
        write("fewer.toml", exp.substr(0, exp.find("[[methods]]\nname = \"pom\"")));
        // The parallax shader with half the offset: worse at every oblique view.
        write("worse/parallax.frag.glsl",
              "vec2 pxh_method(vec2 P) { return P + pxh_V.xy * (0.5 * pxh_z(P) / pxh_V.z); }\n");
        // The parallax method as a plug-in (the same text), and its worse copy, for --pair.
        write("plugin.toml",
              pxh::test::ExperimentToml("cmp")
                      .samples(32)
                      .backends("\"glsl\"")
                      .timing_repeats(2)
                      .theta("[0, 40, 70]")
                      .field("fbm", 64, "scale = 0.05\nbias = 1.0")
                      .str() +
                  "[[methods]]\nname = \"my_parallax\"\nshader = \"my_parallax.frag.glsl\"\n"
                  "max_fetches = 1\n");
        write("my_parallax.frag.glsl",
              "vec2 pxh_method(vec2 P) { return P + pxh_V.xy * (pxh_z(P) / pxh_V.z); }\n");
        fs::create_directories(dir / "worse_plugin");
        write("worse_plugin/plugin.toml", slurp(dir / "plugin.toml"));
        write("worse_plugin/my_parallax.frag.glsl",
              "vec2 pxh_method(vec2 P) { return P + pxh_V.xy * (0.5 * pxh_z(P) / pxh_V.z); }\n");
        const std::string e = d("exp.toml");
        for (const std::string& args :
             {"run " + e + " --quiet --out " + d("base"),
              "run " + e + " --quiet --out " + d("same"),
              "run " + e + " --quiet --out " + d("worse_run") + " --shader-dir " + d("worse"),
              "run " + d("fewer.toml") + " --quiet --out " + d("fewer_run"),
              "run " + d("plugin.toml") + " --quiet --out " + d("plugin_run"),
              "run " + d("worse_plugin/plugin.toml") + " --quiet --out " + d("worse_plugin_run")})
            run_or_record(args);
    }
};

TEST_F(Compare, IdenticalRunsPassTheGate) {
    EXPECT_EQ(run("compare " + d("base") + " " + d("same") +
                  " --fail-on err_p95=+0,err_mean=+0,fetches_mean=+0"),
              0)
        << slurp(dir / "out.txt") << slurp(dir / "err.txt");
    const std::string out = slurp(dir / "out.txt");
    // 2 methods x 3 views x (cpu float + glsl r32f) = 12 rows, none changed.
    EXPECT_NE(out.find("12 rows matched (0 with changed errors or status), 0 only in BASE, 0 "
                       "only in NEW"),
              std::string::npos)
        << out;
    EXPECT_NE(out.find("PASS: 0 regression(s)"), std::string::npos) << out;
}

// --pair NEW=BASE: a plug-in's rows matched with the preset's they reproduce (its 3 GLSL rows;
// the preset's CPU rows and pom are BASE's only, left out by --common): the same text passes a
// zero-tolerance gate, half its offset fails, named by the pair; without --pair nothing matches.
TEST_F(Compare, PairMatchesAPlugInWithTheMethodItReproduces) {
    const std::string gate = " --common --fail-on err_p95=+0,err_mean=+0,fetches_mean=+0";
    EXPECT_EQ(
        run("compare " + d("base") + " " + d("plugin_run") + " --pair my_parallax=parallax" + gate),
        0)
        << slurp(dir / "out.txt") << slurp(dir / "err.txt");
    std::string out = slurp(dir / "out.txt");
    EXPECT_NE(out.find("3 rows matched (0 with changed errors or status), 9 only in BASE, 0 only "
                       "in NEW"),
              std::string::npos)
        << out;
    EXPECT_EQ(run("compare " + d("base") + " " + d("worse_plugin_run") +
                  " --pair my_parallax=parallax" + gate),
              1);
    out = slurp(dir / "out.txt");
    EXPECT_NE(out.find("my_parallax=parallax [glsl/r32f] on fbm s=0.05 b=1 theta=40 phi=0: "
                       "err_p95"),
              std::string::npos)
        << out;
    // err_p95 and err_mean at theta 40 and 70 (theta 0 has no offset).
    EXPECT_NE(out.find("FAIL: 4 regression(s)"), std::string::npos) << out;
    EXPECT_EQ(run("compare " + d("base") + " " + d("plugin_run") + gate), 2);
    EXPECT_NE(slurp(dir / "err.txt").find("their keys differ in method"), std::string::npos);
    EXPECT_NE(slurp(dir / "err.txt").find("(rows of two methods are matched with --pair NEW=BASE)"),
              std::string::npos);
    EXPECT_EQ(run("compare " + d("base") + " " + d("plugin_run") + " --pair my_parallax"), 2);
    EXPECT_NE(slurp(dir / "err.txt").find("--pair: 'my_parallax': NEW=BASE"), std::string::npos)
        << slurp(dir / "err.txt");
}

TEST_F(Compare, WorseShaderFailsAndIsNamed) {
    EXPECT_EQ(run("compare " + d("base") + " " + d("worse_run") + " --fail-on err_p95=+5%"), 1)
        << slurp(dir / "err.txt");
    const std::string out = slurp(dir / "out.txt");
    // Only the GLSL parallax rows changed, and only the oblique ones can regress (theta = 0
    // has no offset at all): 2 regressions, both named with their view.
    EXPECT_NE(out.find("12 rows matched (2 with changed errors or status)"), std::string::npos)
        << out;
    EXPECT_NE(out.find("parallax [glsl/r32f] on fbm s=0.05 b=1 theta=40 phi=0: err_p95"),
              std::string::npos)
        << out;
    EXPECT_NE(out.find("theta=70 phi=0: err_p95"), std::string::npos) << out;
    EXPECT_EQ(out.find("[cpu/float] on fbm s=0.05 b=1 theta=40 phi=0: err_p95"), std::string::npos)
        << "a CPU row reported as regressed: " << out;
    EXPECT_NE(out.find("FAIL: 2 regression(s)"), std::string::npos) << out;
    // The per-row table lists exactly the two changed rows, the larger change first.
    const size_t table = out.find("changed row");
    ASSERT_NE(table, std::string::npos) << out;
    const size_t r70 = out.find("theta=70 phi=0  ", table),
                 r40 = out.find("theta=40 phi=0  ", table);
    EXPECT_NE(r70, std::string::npos) << out;
    EXPECT_NE(r40, std::string::npos) << out;
    EXPECT_LT(r70, r40) << "largest change of err_p95 first";
    // Without --fail-on: the same report, exit 0.
    EXPECT_EQ(run("compare " + d("base") + " " + d("worse_run") + " --markdown"), 0);
    EXPECT_NE(slurp(dir / "out.txt").find("| parallax [glsl/r32f] |"), std::string::npos)
        << slurp(dir / "out.txt");
}

TEST_F(Compare, RowsInOneRunOnly) {
    EXPECT_EQ(run("compare " + d("base") + " " + d("fewer_run")), 0);
    EXPECT_NE(slurp(dir / "out.txt")
                  .find("6 rows matched (0 with changed errors or status), 6 only "
                        "in BASE, 0 only in NEW"),
              std::string::npos)
        << slurp(dir / "out.txt");
    // A gate does not pass when rows disappear.
    EXPECT_EQ(run("compare " + d("base") + " " + d("fewer_run") + " --fail-on err_mean=+1"), 1);
    EXPECT_NE(slurp(dir / "out.txt").find(": missing from NEW"), std::string::npos);
    // Rows new in NEW are listed, not a regression.
    EXPECT_EQ(run("compare " + d("fewer_run") + " " + d("base") + " --fail-on err_mean=+0"), 0);
    EXPECT_NE(slurp(dir / "out.txt").find("Rows only in NEW (6)"), std::string::npos);
}

// The band table keeps rows of two bases apart (and names the radius where a base has one):
// a mean of NEW - BASE over a plane row and a cylinder row would be no row's change.
TEST_F(Compare, BandTableNeverPoolsTwoBases) {
    const std::string exp = pxh::test::ExperimentToml("bases")
                                .samples(16)
                                .backends("\"cpu\"")
                                .theta("[0, 40]")
                                .field("fbm", 32,
                                       "scale = 0.05\nbias = 1.0\nbase = [\"plane\", "
                                       "\"cylinder\"]\nradius = 0.5")
                                .method("parallax");
    write("bases.toml", exp);
    ASSERT_EQ(run("run " + d("bases.toml") + " --quiet --out " + d("bases_a")), 0);
    ASSERT_EQ(run("run " + d("bases.toml") + " --quiet --out " + d("bases_b")), 0);
    const auto r = pxh("compare " + d("bases_a") + " " + d("bases_b"));
    ASSERT_EQ(r.status, 0) << r.err;
    // The band lines: series, band and row count, columns apart by two spaces or more.
    std::set<std::string> lines;
    std::istringstream in(r.out);
    for (std::string line; std::getline(in, line);) {
        if (line.rfind("parallax [cpu/float]", 0) != 0) continue;
        std::string cells;
        for (size_t k = 0, n = 0; k < line.size() && n < 3; ++k) {
            const bool gap = line.compare(k, 2, "  ") == 0;
            if (gap) {
                while (k + 1 < line.size() && line[k + 1] == ' ') ++k;
                if (++n < 3) cells += " | ";
            } else {
                cells += line[k];
            }
        }
        lines.insert(cells);
    }
    const std::set<std::string> want = {
        "parallax [cpu/float] base=cylinder radius=0.5 | 0 <= θ < 30 | 1",
        "parallax [cpu/float] base=cylinder radius=0.5 | 30 <= θ < 60 | 1",
        "parallax [cpu/float] base=plane | 0 <= θ < 30 | 1",
        "parallax [cpu/float] base=plane | 30 <= θ < 60 | 1"};
    EXPECT_EQ(lines, want) << r.out;
    EXPECT_EQ(r.out.find("base=plane radius="), std::string::npos) << r.out;
}

TEST_F(Compare, BadInputIsOneLineExit2) {
    EXPECT_EQ(run("compare " + d("base") + " " + d("same") + " --fail-on status=+1"), 2);
    const std::string err = slurp(dir / "err.txt");
    EXPECT_EQ(err.rfind("pxh: error: --fail-on: 'status' is not a measured numeric column "
                        "(known: err_mean,",
                        0),
              0u)
        << err;
    EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
    EXPECT_EQ(run("compare " + d("base") + " " + d("nowhere")), 2);
    EXPECT_NE(slurp(dir / "err.txt").find("nowhere: no such results folder"), std::string::npos)
        << slurp(dir / "err.txt");
    EXPECT_THROW(pxh::parse_fail_on("err_p95=+5x"), pxh::InputError);
    EXPECT_THROW(pxh::parse_fail_on("err_p95=-1"), pxh::InputError);
    const auto t = pxh::parse_fail_on("err_p95=+5%,fetches_mean=+0");
    ASSERT_EQ(t.size(), 2u);
    EXPECT_TRUE(t[0].relative);
    EXPECT_DOUBLE_EQ(t[0].amount, 0.05);
    EXPECT_FALSE(t[1].relative);
}

}  // namespace
