// Camera-first results and gates that cannot pass on nothing: pxh compare of runs that share no
// row exits 2 naming the keys that differ; the perspective camera's resolution with samples
// picking pixels of that image (a quick run measures the same pixels at the same levels);
// every axis a filter of --only and pxh check (with ranges), in row names; the verdicts as
// JUnit and JSON; regressions largest first; skipped settings said; --version; progress with
// elapsed and remaining time.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "harness/metrics/row.h"
#include "harness/results/csv_table.h"
#include "harness/results/results.h"
#include "tests/cli_util.h"

namespace fs = std::filesystem;
using pxh::test::ExperimentToml;

namespace {

class CameraGates : public pxh::test::CliTest {
  protected:
    std::string d(const std::string& name) { return (dir / name).string(); }
    // A perspective CPU run: fbm 64, pom 8 and parallax at lod base and level, theta 30 and
    // 60, distances 1.5 and 4, an image of `resolution` pixels a side.
    std::string camera_exp(int samples, int resolution, const std::string& extra_views = "") {
        ExperimentToml e("cam");
        e.samples(samples)
            .theta("[30, 60]")
            .phi("[30]")
            .view("camera", "\"perspective\"")
            .view("distance", "[1.5, 4]")
            .view("resolution", std::to_string(resolution))
            .field("fbm", 64, "scale = 0.05\nbias = 1.0")
            .method("parallax", "lod = [\"base\", \"level\"]")
            .method("pom", "layers = 8\nlod = [\"base\", \"level\"]");
        std::string s = e.str();
        if (!extra_views.empty()) s.insert(s.find("[[heightfields]]"), extra_views + "\n");
        return s;
    }
    pxh::test::CliResult run_into(const std::string& name, const std::string& exp,
                                  const std::string& extra = "") {
        const std::string f = write(name + ".toml", exp);
        return pxh("run " + f + " --quiet --out " + d(name) + " " + extra);
    }
};

// The case: a baseline at 64 samples, a quick run at 32: no row matches, and compare
// says so (exit 2) instead of PASS, with or without --common and a gate; the verdict files say
// the same.
TEST_F(CameraGates, CompareOfNothingIsNoVerdict) {
    ASSERT_EQ(run_into("base", camera_exp(16, 32)).status, 0);
    ASSERT_EQ(run_into("quick", camera_exp(16, 32), "--samples 8").status, 0);
    for (const std::string extra :
         {"", " --common", " --fail-on err_p95=+5%", " --common --fail-on err_p95=+5%"}) {
        const auto r = pxh("compare " + d("base") + " " + d("quick") + extra + " --json " +
                           d("v.json") + " --junit " + d("v.xml"));
        EXPECT_EQ(r.status, 2) << extra << "\n" << r.out << r.err;
        EXPECT_EQ(r.out.find("PASS"), std::string::npos) << r.out;
        EXPECT_NE(r.err.find("no row of NEW matches a row of BASE (16 rows in BASE, 16 in NEW)"),
                  std::string::npos)
            << r.err;
        EXPECT_NE(r.err.find("their keys differ in samples 16 vs 8"), std::string::npos) << r.err;
        // Only samples differs: the resolution is the file's, the same in both.
        EXPECT_EQ(r.err.find("resolution"), std::string::npos) << r.err;
        const auto j = nlohmann::json::parse(slurp(dir / "v.json"));
        EXPECT_EQ(j["passed"], false);
        EXPECT_EQ(j["exit_code"], 2);
        EXPECT_EQ(j["failures"], 1);
        EXPECT_NE(slurp(dir / "v.xml").find("<failure message=\"no row of NEW matches"),
                  std::string::npos);
    }
    // Two empty results folders: nothing to compare either.
    fs::create_directories(dir / "e1");
    fs::create_directories(dir / "e2");
    const std::string header = slurp(dir / "base" / "results.csv")
                                   .substr(0, slurp(dir / "base" / "results.csv").find('\n') + 1);
    write("e1/results.csv", header);
    write("e2/results.csv", header);
    const auto e = pxh("compare " + d("e1") + " " + d("e2") + " --accept-edited");
    EXPECT_EQ(e.status, 2) << e.out << e.err;
    EXPECT_NE(e.err.find("both runs are empty"), std::string::npos) << e.err;
}

// resolution is the camera's, samples picks pixels of its image: the rows record both, and a
// quick run's level of detail is that of the full image's pixels (it was log2(R / N) higher when
// the image shrank with samples).
TEST_F(CameraGates, QuickRunMeasuresTheSameImagesPixels) {
    ASSERT_EQ(run_into("full", camera_exp(32, 32)).status, 0);
    ASSERT_EQ(run_into("quick", camera_exp(32, 32), "--samples 8").status, 0);
    ASSERT_EQ(run_into("small", camera_exp(8, 8)).status, 0);  // an image of 8 pixels a side
    const pxh::CsvTable full = pxh::read_csv(d("full") + "/results.csv"),
                        quick = pxh::read_csv(d("quick") + "/results.csv"),
                        small = pxh::read_csv(d("small") + "/results.csv");
    ASSERT_EQ(full.rows.size(), quick.rows.size());
    ASSERT_EQ(full.rows.size(), small.rows.size());
    for (size_t i = 0; i < full.rows.size(); ++i) {
        EXPECT_EQ(full.get(i, "resolution"), "32");
        EXPECT_EQ(quick.get(i, "resolution"), "32");
        EXPECT_EQ(quick.get(i, "samples"), "8");
        EXPECT_EQ(small.get(i, "resolution"), "8");
        const double lf = std::stod(full.get(i, "lod_mean")),
                     lq = std::stod(quick.get(i, "lod_mean")),
                     ls = std::stod(small.get(i, "lod_mean"));
        // The same image: the subset's mean level is the full one's within its sampling
        // spread; the 8-pixel image sits two levels up (footprints 4 times larger).
        EXPECT_NEAR(lq, lf, 0.35) << full.get(i, "distance") << " " << full.get(i, "theta_deg");
        EXPECT_GT(ls - lf, 1.2) << full.get(i, "distance") << " " << full.get(i, "theta_deg");
    }
    // More samples than the image has pixels: refused, naming the option, nothing written.
    const auto r = run_into("over", camera_exp(32, 32), "--samples 64");
    EXPECT_EQ(r.status, 2) << r.err;
    EXPECT_NE(r.err.find("--samples: samples = 64 exceeds the perspective image's resolution 32"),
              std::string::npos)
        << r.err;
    EXPECT_FALSE(fs::exists(dir / "over"));
    // In the file: at [views]'s line.
    const auto f = run_into("over2", camera_exp(64, 32));
    EXPECT_EQ(f.status, 2) << f.err;
    EXPECT_NE(f.err.find("over2.toml:"), std::string::npos) << f.err;
    EXPECT_NE(f.err.find("exceeds the perspective image's resolution 32"), std::string::npos)
        << f.err;
}

// --only selects by every axis: lod and the camera's keys among them, numeric ones as ranges;
// an unknown key lists the keys and suggests the nearest.
TEST_F(CameraGates, OnlyTakesEveryAxis) {
    const std::string exp = write("cam.toml", camera_exp(8, 8));
    const auto count = [&](const std::string& only, const std::string& out) {
        const auto r = pxh("run " + exp + " --quiet --out " + d(out) + " --only " + only);
        EXPECT_EQ(r.status, 0) << only << ": " << r.err;
        return pxh::read_csv(d(out) + "/results.csv").rows.size();
    };
    EXPECT_EQ(count("lod=level", "a"), 8u);
    EXPECT_EQ(count("distance=1.5", "b"), 8u);
    EXPECT_EQ(count("distance_min=2,lod=base", "c"), 4u);
    EXPECT_EQ(count("theta_max=40,method=pom", "d"), 4u);
    EXPECT_EQ(count("resolution=8,fov_deg=45", "e"), 16u);
    const pxh::CsvTable c = pxh::read_csv(d("c") + "/results.csv");
    for (size_t i = 0; i < c.rows.size(); ++i) {
        EXPECT_EQ(c.get(i, "distance"), "4");
        EXPECT_EQ(c.get(i, "lod"), "base");
    }
    const auto bad = pxh("run " + exp + " --quiet --out " + d("x") + " --only distanse=4");
    EXPECT_EQ(bad.status, 2);
    EXPECT_NE(bad.err.find("unknown key 'distanse' (did you mean 'distance'?)"), std::string::npos)
        << bad.err;
    EXPECT_NE(bad.err.find("resolution_max), lod, depth, cut (and cut_min, cut_max)\n"),
              std::string::npos)
        << bad.err;
    EXPECT_EQ(bad.err.find("samples"), std::string::npos) << bad.err;  // set by --samples
    const auto none = pxh("run " + exp + " --quiet --out " + d("y") + " --only distance=7");
    EXPECT_EQ(none.status, 2);
    EXPECT_NE(none.err.find("no distance matches (the experiment has: 1.5, 4)"), std::string::npos)
        << none.err;
    EXPECT_FALSE(fs::exists(dir / "x"));
}

// pxh check filters by every axis (distance, lod; distance_min/distance_max), names the worst
// row with its distance, and writes JUnit and JSON verdicts.
TEST_F(CameraGates, CheckFiltersByEveryAxisAndWritesVerdicts) {
    ASSERT_EQ(run_into("r", camera_exp(8, 8)).status, 0);
    const std::string th = write("th.toml",
                                 "[[limit]]\nmethod = \"pom\"\nlod = \"level\"\ndistance = 4\n"
                                 "column = \"err_px_p95\"\nmax = 1000\n"
                                 "[[limit]]\nmethod = \"parallax\"\ndistance_max = 2\n"
                                 "column = \"err_p95\"\nmax = 0\n");
    const auto r = pxh("check " + d("r") + " --thresholds " + th + " --junit " + d("c.xml") +
                       " --json " + d("c.json"));
    EXPECT_EQ(r.status, 1) << r.out << r.err;
    EXPECT_NE(r.out.find("method=pom distance=4 lod=level"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("method=parallax distance in [-inf, 2]"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("  worst: parallax"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find(" distance=1.5 fov_deg=45 resolution=8: "), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("1 passed, 1 failed"), std::string::npos) << r.out;
    const std::string xml = slurp(dir / "c.xml");
    EXPECT_NE(xml.find("tests=\"2\" failures=\"1\""), std::string::npos) << xml;
    EXPECT_NE(xml.find("<failure message=\"err_p95 worst "), std::string::npos) << xml;
    const auto j = nlohmann::json::parse(slurp(dir / "c.json"));
    EXPECT_EQ(j["tool"], "pxh check");
    EXPECT_EQ(j["passed"], false);
    ASSERT_EQ(j["cases"].size(), 2u);
    EXPECT_EQ(j["cases"][0]["passed"], true);
    EXPECT_EQ(j["cases"][0]["rows"], 2);  // pom lod=level at distance 4: theta 30 and 60
    EXPECT_EQ(j["cases"][1]["passed"], false);
    EXPECT_GT(j["cases"][1]["worst"].get<double>(), 0);
    // A verdict file pxh wrote is replaced; one it did not write is refused.
    write("mine.json", "{\"my\": \"notes\"}\n");
    const auto again = pxh("check " + d("r") + " --thresholds " + th + " --json " + d("c.json"));
    EXPECT_EQ(again.status, 1) << again.err;
    const auto theirs =
        pxh("check " + d("r") + " --thresholds " + th + " --json " + d("mine.json"));
    EXPECT_EQ(theirs.status, 2) << theirs.err;
    EXPECT_NE(theirs.err.find("is not a verdict pxh wrote: not replaced"), std::string::npos)
        << theirs.err;
    EXPECT_EQ(slurp(dir / "mine.json"), "{\"my\": \"notes\"}\n");
    // A distance range no row lies in checks nothing: refused.
    const std::string empty =
        write("e.toml", "[[limit]]\ndistance_min = 100\ncolumn = \"err_p95\"\nmax = 1\n");
    const auto e = pxh("check " + d("r") + " --thresholds " + empty);
    EXPECT_EQ(e.status, 2) << e.out << e.err;
    EXPECT_NE(e.err.find("matches no row"), std::string::npos) << e.err;
}

// compare's gate: regressions listed largest change first, a testcase per method setting and
// backend variant in the JUnit file, pixel error in the band table.
TEST_F(CameraGates, CompareSortsRegressionsAndWritesVerdicts) {
    ASSERT_EQ(run_into("a", camera_exp(8, 8)).status, 0);
    // A copy with two rows' err_p95 made worse: row 3 by +50%, row 6 by +400%.
    fs::create_directories(dir / "b");
    fs::copy_file(dir / "a" / "run.json", dir / "b" / "run.json");
    const pxh::CsvTable t = pxh::read_csv(d("a") + "/results.csv");
    const int c = t.index("err_p95");
    std::string out;
    for (size_t i = 0; i < t.columns.size(); ++i) out += (i ? "," : "") + t.columns[i];
    out += "\n";
    for (size_t r = 0; r < t.rows.size(); ++r) {
        for (size_t i = 0; i < t.columns.size(); ++i) {
            std::string cell = t.rows[r][i];
            if (int(i) == c && (r == 3 || r == 6))
                cell = pxh::format_cell_number(std::stod(cell) * (r == 3 ? 1.5 : 5.0));
            out += (i ? "," : "") + pxh::csv_quote(cell);
        }
        out += "\n";
    }
    write("b/results.csv", out);
    const auto r = pxh("compare " + d("a") + " " + d("b") +
                       " --accept-edited --fail-on err_p95=+5% --junit " + d("g.xml"));
    EXPECT_EQ(r.status, 1) << r.out << r.err;
    const size_t list = r.out.find("largest change first");
    ASSERT_NE(list, std::string::npos) << r.out;
    const size_t big = r.out.find(": err_p95 ", list);
    ASSERT_NE(big, std::string::npos) << r.out;
    // The first listed regression is the +400% row.
    const std::string first = r.out.substr(big, r.out.find('\n', big) - big);
    char b6[32];
    std::snprintf(b6, sizeof b6, ": err_p95 %.4g -> ", std::stod(t.get(6, "err_p95")));
    EXPECT_EQ(first.rfind(b6, 0), 0u) << first << " (expected " << b6 << ")";
    EXPECT_NE(r.out.find("d err_px_p95"), std::string::npos) << r.out;
    const std::string xml = slurp(dir / "g.xml");
    // 4 method settings and the rows of BASE found in NEW.
    EXPECT_NE(xml.find("tests=\"5\" failures=\"2\""), std::string::npos) << xml;
    EXPECT_NE(xml.find("classname=\"pxh.compare\" name=\"pom "
                       "layers=8;layers_min=off;layers_max=off [cpu/float]\""),
              std::string::npos)
        << xml;
}

// A setting a backend cannot run is said on stderr and in run.json, not silently missing.
TEST_F(CameraGates, SkippedSettingsAreSaid) {
    ExperimentToml e("skip");
    e.backends("\"cpu\", \"glsl\"")
        .theta("[30]")
        .field("fbm", 16)
        .method("pom", "layers = 8\nlod = [\"base\", \"grad\"]");
    const std::string f = write("skip.toml", e);
    const auto r = pxh("run " + f + " --quiet --backend cpu --out " + d("s"));
    ASSERT_EQ(r.status, 0) << r.err;
    const std::string want =
        "backend cpu makes no rows of 1 method setting(s) (pom "
        "layers=8;layers_min=off;layers_max=off "
        "lod=grad): lod 'grad' "
        "samples through the GPU's own level selection: glsl only";
    EXPECT_NE(r.err.find("pxh: warning: " + want), std::string::npos) << r.err;
    const auto j = nlohmann::json::parse(slurp(dir / "s" / "run.json"));
    bool found = false;
    for (const auto& w : j["warnings"]) found = found || w.get<std::string>() == want;
    EXPECT_TRUE(found) << j["warnings"].dump();
}

// An unknown method, parameter or key suggests the nearest name.
TEST_F(CameraGates, UnknownNamesSuggestTheNearest) {
    ExperimentToml e("n");
    e.theta("[0]").field("fbm", 16).method("pmo");
    auto r = pxh("run " + write("n.toml", e) + " --quiet --out " + d("n"));
    EXPECT_EQ(r.status, 2);
    EXPECT_NE(r.err.find("unknown method 'pmo' (did you mean 'pom'?) (known: "), std::string::npos)
        << r.err;
    ExperimentToml p("p");
    p.theta("[0]").field("fbm", 16).method("pom", "layres = 8");
    r = pxh("run " + write("p.toml", p) + " --quiet --out " + d("p"));
    EXPECT_EQ(r.status, 2);
    EXPECT_NE(r.err.find("unknown parameter 'layres' (did you mean 'layers'?) for "),
              std::string::npos)
        << r.err;
    ExperimentToml k("k");
    k.theta("[0]").field("fbm", 16).method("pom").set("sampels", "8");
    r = pxh("run " + write("k.toml", k) + " --quiet --out " + d("k"));
    EXPECT_EQ(r.status, 2);
    EXPECT_NE(r.err.find("unknown key 'sampels' (did you mean 'samples'?)"), std::string::npos)
        << r.err;
}

// pxh --version is the build's git describe, as run.json records it.
TEST_F(CameraGates, VersionIsWhatRunJsonRecords) {
    ExperimentToml e("v");
    e.theta("[0]").field("fbm", 16).method("parallax");
    const auto run = pxh("run " + write("v.toml", e) + " --quiet --out " + d("v"));
    ASSERT_EQ(run.status, 0) << run.err;
    const auto j = nlohmann::json::parse(slurp(dir / "v" / "run.json"));
    const auto r = pxh("--version");
    EXPECT_EQ(r.status, 0);
    EXPECT_EQ(r.out, "pxh " + j["pxh_version"].get<std::string>() + "\n");
}

// Progress (not a terminal: one line per view) shows the elapsed time and, from the second view
// on, an estimate of what is left.
TEST_F(CameraGates, ProgressShowsElapsedAndWhatIsLeft) {
    ExperimentToml e("p");
    e.theta("[0, 30, 60]").field("fbm", 16).method("parallax");
    const auto r = pxh("run " + write("p.toml", e) + " --out " + d("p"));
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.err.find("[1/3 0:00] fbm s="), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("[3/3 0:00, ~0:00 left] fbm"), std::string::npos) << r.err;
}

}  // namespace
