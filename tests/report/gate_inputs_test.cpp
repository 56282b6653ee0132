// The gates' inputs taken at their word: pxh compare --only and pxh check's filters take every
// key (base and radius among them, an empty base being the plane), a gated column a run lacks
// fails the gate naming the column and the file, and bad input is exit 2: --junit and --json
// naming one file, a hexadecimal --fail-on allowance, an invalid PXH_TRACER_PATH.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "harness/results/csv_table.h"
#include "tests/cli_util.h"

namespace fs = std::filesystem;

namespace {

class GateInputs : public pxh::test::CliTest {
  protected:
    std::string d(const std::string& name) { return (dir / name).string(); }
    // A CPU run on the plane and on a cylinder at two radii: 2 theta x 3 fields x 1 method.
    void curved_run(const std::string& name) {
        const std::string e =
            write(name + ".toml",
                  "name = \"curved\"\nsamples = 8\ntiming_repeats = 0\n"
                  "[views]\ntheta_deg = [0, 30]\n"
                  "[[heightfields]]\nname = \"flat\"\ngenerator = \"sine\"\nsize = 16\n"
                  "[[heightfields]]\nname = \"round\"\ngenerator = \"sine\"\nsize = 16\n"
                  "base = \"cylinder\"\nradius = [2, 8]\n"
                  "[[methods]]\nname = \"parallax\"\n");
        const auto r = pxh("run " + e + " --quiet --out " + d(name));
        ASSERT_EQ(r.status, 0) << r.out << r.err;
    }
};

// pxh compare --only by base and radius (a range), the rows left out counted; today's main has
// no --only on compare at all.
TEST_F(GateInputs, CompareOnlyTakesBaseAndRadius) {
    curved_run("a");
    ASSERT_EQ(pxh::read_csv(d("a") + "/results.csv").rows.size(), 6u);
    const auto all = pxh("compare " + d("a") + " " + d("a"));
    EXPECT_EQ(all.status, 0) << all.out << all.err;
    EXPECT_NE(all.out.find("6 rows matched"), std::string::npos) << all.out;
    const auto cyl = pxh("compare " + d("a") + " " + d("a") + " --only base=cylinder");
    EXPECT_EQ(cyl.status, 0) << cyl.out << cyl.err;
    EXPECT_NE(cyl.out.find("4 rows matched"), std::string::npos) << cyl.out;
    EXPECT_NE(cyl.out.find("--only base=cylinder: 2 rows of BASE and 2 of NEW left out"),
              std::string::npos)
        << cyl.out;
    const auto plane = pxh("compare " + d("a") + " " + d("a") + " --only base=plane");
    EXPECT_NE(plane.out.find("2 rows matched"), std::string::npos) << plane.out;
    const auto r = pxh("compare " + d("a") + " " + d("a") + " --only radius=1..4,theta_deg=30");
    EXPECT_NE(r.out.find("1 rows matched"), std::string::npos) << r.out;
    const auto bad = pxh("compare " + d("a") + " " + d("a") + " --only radius=x..4");
    EXPECT_EQ(bad.status, 2) << bad.out << bad.err;
    EXPECT_NE(bad.err.find("--only: 'radius=x..4': a range is radius=LO..HI"), std::string::npos)
        << bad.err;
    // pxh run --only base=cylinder (refused on today's main: "camera ... has no key base").
    const std::string e = (dir / "a.toml").string();
    const auto run =
        pxh("run " + e + " --quiet --out " + d("cyl") + " --only base=cylinder,radius=8");
    ASSERT_EQ(run.status, 0) << run.out << run.err;
    const pxh::CsvTable t = pxh::read_csv(d("cyl") + "/results.csv");
    ASSERT_EQ(t.rows.size(), 2u);
    for (size_t i = 0; i < t.rows.size(); ++i) {
        EXPECT_EQ(t.get(i, "base"), "cylinder");
        EXPECT_EQ(t.get(i, "radius"), "8");
    }
}

// pxh check: a limit on base = "plane" selects the plane's rows (whose base cell is empty), and
// radius ranges select curved ones; a plane-only limit is not refused as matching no row.
TEST_F(GateInputs, CheckFiltersByBaseAndRadius) {
    curved_run("a");
    const std::string th = write("th.toml",
                                 "[[limit]]\nbase = \"plane\"\ncolumn = \"err_mean\"\nmax = 1e9\n"
                                 "[[limit]]\nbase = \"cylinder\"\nradius_min = 4\n"
                                 "column = \"err_mean\"\nmax = 1e9\n");
    const auto r = pxh("check " + d("a") + " --thresholds " + th + " --json " + d("c.json"));
    EXPECT_EQ(r.status, 0) << r.out << r.err;
    const std::string j = slurp(dir / "c.json");
    // Each limit saw its own rows: 2 on the plane, 2 on the cylinder at R = 8.
    EXPECT_NE(j.find("\"passed\": true"), std::string::npos) << j;
    EXPECT_EQ(r.out.find("matches no row"), std::string::npos) << r.out;
    size_t twos = 0;
    for (size_t at = j.find("\"rows\": 2"); at != std::string::npos;
         at = j.find("\"rows\": 2", at + 1))
        ++twos;
    EXPECT_EQ(twos, 2u) << j;
}

// A column the gate names that BASE lacks: FAIL (exit 1), naming the column and the file, in the
// printed verdict and the JSON; on today's main it passed silently.
TEST_F(GateInputs, GatedColumnTheBaselineLacksFails) {
    const fs::path base = fs::path(PXH_SOURCE_DIR) / "examples" / "shader_gate" / "baseline";
    ASSERT_EQ(pxh::read_csv((base / "results.csv").string()).index("depth_err_mean"), -1);
    const auto r = pxh("compare " + base.string() + " " + base.string() +
                       " --fail-on err_p95=+0,depth_err_mean=+0 --json " + d("v.json") +
                       " --junit " + d("v.xml"));
    EXPECT_EQ(r.status, 1) << r.out << r.err;
    EXPECT_NE(r.out.find("FAIL: 1 regression(s) beyond --fail-on err_p95=+0,depth_err_mean=+0"),
              std::string::npos)
        << r.out;
    const std::string why = "--fail-on depth_err_mean: " + (base / "results.csv").string() +
                            " has no column depth_err_mean";
    EXPECT_NE(r.out.find(why), std::string::npos) << r.out;
    const std::string j = slurp(dir / "v.json");
    EXPECT_NE(j.find("\"passed\": false"), std::string::npos) << j;
    EXPECT_NE(j.find("has no column depth_err_mean"), std::string::npos) << j;
    EXPECT_NE(slurp(dir / "v.xml").find("<failure message=\"--fail-on depth_err_mean: "),
              std::string::npos);
    // Gating only what both have still passes.
    const auto ok = pxh("compare " + base.string() + " " + base.string() + " --fail-on err_p95=+0");
    EXPECT_EQ(ok.status, 0) << ok.out << ok.err;
}

TEST_F(GateInputs, BadGateInputIsExit2) {
    const fs::path base = fs::path(PXH_SOURCE_DIR) / "examples" / "shader_gate" / "baseline";
    const std::string b = base.string();
    // A hexadecimal allowance is no decimal number (std::stod read +0x10 as 16).
    for (const char* bad :
         {"err_p95=+0x10", "err_p95=0x1p4", "err_p95=+ 1", "err_p95=+1e", "err_p95=inf"}) {
        const auto r = pxh("compare " + b + " " + b + " --fail-on '" + bad + "'");
        EXPECT_EQ(r.status, 2) << bad << "\n" << r.out << r.err;
        EXPECT_NE(r.err.find("the allowance must be a number >= 0"), std::string::npos) << r.err;
    }
    for (const char* good : {"err_p95=+0", "err_p95=5%", "err_p95=+1.5e-3", "err_p95=+.5"}) {
        const auto r = pxh("compare " + b + " " + b + " --fail-on '" + good + "'");
        EXPECT_EQ(r.status, 0) << good << "\n" << r.out << r.err;
    }
    // --junit and --json naming one file (as given, or the same file by another path): refused
    // before anything is written.
    fs::create_directories(dir / "sub");
    for (const std::string& json : {d("v"), d("sub/../v")}) {
        const auto r = pxh("compare " + b + " " + b + " --fail-on err_p95=+0 --junit " + d("v") +
                           " --json " + json);
        EXPECT_EQ(r.status, 2) << r.out << r.err;
        EXPECT_NE(r.err.find("is also the --junit file"), std::string::npos) << r.err;
        EXPECT_FALSE(fs::exists(dir / "v"));
        const std::string th = write("th.toml", "[[limit]]\ncolumn = \"err_mean\"\nmax = 1e9\n");
        const auto c =
            pxh("check " + b + " --thresholds " + th + " --junit " + d("v") + " --json " + json);
        EXPECT_EQ(c.status, 2) << c.out << c.err;
        EXPECT_NE(c.err.find("is also the --junit file"), std::string::npos) << c.err;
        EXPECT_FALSE(fs::exists(dir / "v"));
    }
    // An invalid PXH_TRACER_PATH: exit 2 and one line naming it (today: exit 1).
    const std::string e = write("e.toml",
                                "samples = 8\ntiming_repeats = 0\n[views]\ntheta_deg = [30]\n"
                                "[[heightfields]]\ngenerator = \"sine\"\nsize = 16\n"
                                "[[methods]]\nname = \"parallax\"\n");
    const auto t = sh("PXH_TRACER_PATH=avx3 " + std::string(PXH_BINARY) + " run " + e +
                      " --quiet --out " + d("t"));
    EXPECT_EQ(t.status, 2) << t.out << t.err;
    EXPECT_EQ(t.err,
              "pxh: error: PXH_TRACER_PATH='avx3': not a per-ray path (scalar, avx2 or avx512) "
              "(unset it for the CPU's best path)\n");
    EXPECT_FALSE(fs::exists(dir / "t"));
    const auto fine = sh("PXH_TRACER_PATH=scalar " + std::string(PXH_BINARY) + " run " + e +
                         " --quiet --out " + d("t2"));
    EXPECT_EQ(fine.status, 0) << fine.out << fine.err;
}

}  // namespace
