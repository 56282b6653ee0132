// A perspective distance sweep end to end: `pxh run` writes the distance pairing's columns
// (docs/conventions.md section 5.3) on every distance but the last, and `pxh report` and
// `pxh check` take them as any column.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "harness/results/csv_table.h"
#include "tests/cli_util.h"

namespace {

class DistanceSweepCli : public pxh::test::CliTest {};

const char* kSweep =
    "name = \"dist\"\nsamples = 16\ntiming_repeats = 0\nbackends = [\"cpu\"]\n"
    "precision = \"float\"\n[views]\ntheta_deg = [60]\nphi_deg = [30]\n"
    "camera = \"perspective\"\ndistance = { from = 1, to = 3, step = 1 }\nfov_deg = 45\n"
    "[[heightfields]]\nname = \"f\"\ngenerator = \"fbm\"\nwidth = 32\nheight = 32\n"
    "scale = 0.05\nbias = 1\n[[methods]]\nname = \"parallax\"\n[[methods]]\nname = \"pom\"\n"
    "layers = 16\n";

TEST_F(DistanceSweepCli, LastDistanceIsEmptyAndReportAndCheckTakeTheColumns) {
    const auto exp = write("dist.toml", kSweep);
    const auto res = (dir / "res").string();
    const auto r = pxh("run " + exp + " --quiet --out " + res);
    ASSERT_EQ(r.status, 0) << r.err;
    const pxh::CsvTable t = pxh::read_csv((dir / "res" / "results.csv").string());
    ASSERT_EQ(t.rows.size(), 6u);  // 3 distances x 2 methods
    double worst = 0;
    for (size_t i = 0; i < t.rows.size(); ++i) {
        const double d = t.number(i, "distance");
        for (const char* c : {"sliding_dist", "shimmering_dist", "sweep_dd"}) {
            if (d == 3) {
                EXPECT_EQ(t.get(i, c), "") << c << " row " << i;
            } else {
                EXPECT_TRUE(std::isfinite(t.number(i, c))) << c << " row " << i;
            }
        }
        if (d != 3) {
            EXPECT_EQ(t.number(i, "sweep_dd"), 1.0) << i;
            EXPECT_GT(t.number(i, "shimmering_dist"), 0) << i;
            worst = std::max(worst, t.number(i, "shimmering_dist"));
        }
        EXPECT_EQ(t.get(i, "sliding"), "") << i;  // one theta: no theta pairing
    }
    ASSERT_EQ(pxh("report --no-plots " + res).status, 0) << slurp(dir / "err.txt");
    // A limit on the new column over the paired distances: above the worst row passes, below
    // it fails; over every row it fails on the last distance's empty cells, as any column's
    // limit does.
    const auto limit = [&](const std::string& name, const std::string& select, double max) {
        return write(name, "[[limit]]\n" + select +
                               "column = \"shimmering_dist\"\nmax = " + std::to_string(max) + "\n");
    };
    const std::string paired = "distance = [1, 2]\n";
    auto r2 = pxh("check " + res + " --thresholds " + limit("a.toml", paired, worst * 1.01 + 1e-6));
    EXPECT_EQ(r2.status, 0) << r2.out << r2.err;
    EXPECT_NE(r2.out.find("1 passed, 0 failed"), std::string::npos) << r2.out;
    r2 = pxh("check " + res + " --thresholds " + limit("b.toml", paired, worst * 0.5));
    EXPECT_EQ(r2.status, 1) << r2.out << r2.err;
    r2 = pxh("check " + res + " --thresholds " + limit("c.toml", "", 1e6));
    EXPECT_EQ(r2.status, 1) << r2.out << r2.err;
    EXPECT_NE(r2.out.find("non-finite or empty"), std::string::npos) << r2.out;
}

}  // namespace
