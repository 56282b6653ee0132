// The pxh binary end to end: results on disk, exit codes, no half-written results,
// thread-count independence.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "harness/core/sha256.h"
#include "harness/results/csv_table.h"
#include "tests/cli_util.h"

namespace {

namespace fs = std::filesystem;

using Result = pxh::test::CliResult;
class Cli : public pxh::test::CliTest {};

const std::string kSmall = pxh::test::ExperimentToml("small")
                               .samples(24)
                               .timing_repeats(1)
                               .theta("[0, 60, 85]")
                               .phi("[0, 30]")
                               .field("fbm", 32)
                               .field("spikes", 16, "bias = 0.5")
                               .method("parallax")
                               .method("pom", "layers = [8, 32]");

TEST_F(Cli, RunWritesResultsAndProvenance) {
    const auto exp = write("small.toml", kSmall);
    const Result r = pxh("run " + exp + " --out " + (dir / "res").string() + " --quiet");
    ASSERT_EQ(r.status, 0) << r.err;
    const std::string csv = slurp(dir / "res" / "results.csv");
    std::istringstream lines(csv);
    std::string header;
    std::getline(lines, header);
    for (const char* col :
         {"method",    "params",    "heightfield",  "backend",     "scale",   "bias",
          "theta_deg", "phi_deg",   "samples",      "width",       "height",  "err_mean",
          "err_rms",   "err_p50",   "err_p95",      "err_p99",     "err_max", "frac_gt_0_5",
          "frac_gt_1", "nonfinite", "fetches_mean", "fetches_max", "time"})
        EXPECT_NE(header.find(col), std::string::npos) << col;
    int rows = 0;
    for (std::string line; std::getline(lines, line);) ++rows;
    EXPECT_EQ(rows, 3 * 2 * 2 * 3);  // methods x fields x phi x theta
    const std::string run = slurp(dir / "res" / "run.json");
    for (const char* key : {"git_commit", "compiler", "cpu_model", "threads", "date_utc", "embree",
                            "openimageio", "experiment"})
        EXPECT_NE(run.find(key), std::string::npos) << key;
    EXPECT_NE(run.find("generator = \\\"spikes\\\""), std::string::npos);  // the file itself
    // Every timing comes with the spread of its repeats: min <= median <= max.
    const pxh::CsvTable t = pxh::read_csv((dir / "res" / "results.csv").string());
    for (size_t i = 0; i < t.rows.size(); ++i) {
        EXPECT_EQ(t.get(i, "time_unit"), "ns/sample") << i;
        const double lo = t.number(i, "time_min"), mid = t.number(i, "time"),
                     hi = t.number(i, "time_max");
        ASSERT_TRUE(std::isfinite(lo) && std::isfinite(hi)) << i;
        EXPECT_LE(lo, mid);
        EXPECT_LE(mid, hi);
    }
}

// Each backend's timing in its own unit: a CPU row's time is the median of its time_repeats
// (four, so the median is the mean of the middle two), min and max their extremes; a GLSL
// row's unit is ms/frame with its five frames as repeats and its timer-query counter beside;
// run.json has each backend's block (unit, what a repeat measures, repeats, counters).
TEST_F(Cli, EachBackendTimesInItsOwnUnit) {
    const auto exp = write("t.toml", pxh::test::ExperimentToml("t")
                                         .samples(16)
                                         .timing_repeats(4)
                                         .backends("\"cpu\", \"glsl\"")
                                         .theta("[0, 60]")
                                         .field("fbm", 32)
                                         .method("pom", "layers = 8")
                                         .str());
    const Result r = pxh("run " + exp + " --quiet --out " + (dir / "o").string());
    ASSERT_EQ(r.status, 0) << r.err;
    const pxh::CsvTable t = pxh::read_csv((dir / "o" / "results.csv").string());
    size_t cpu = 0, glsl = 0;
    for (size_t i = 0; i < t.rows.size(); ++i) {
        ASSERT_EQ(t.get(i, "status"), "ok") << t.where(i);
        std::vector<double> reps;
        std::stringstream ss(t.get(i, "time_repeats"));
        for (std::string v; std::getline(ss, v, ';');) reps.push_back(std::stod(v));
        std::sort(reps.begin(), reps.end());
        const bool is_cpu = t.get(i, "backend") == "cpu";
        (is_cpu ? cpu : glsl)++;
        EXPECT_EQ(t.get(i, "time_unit"), is_cpu ? "ns/sample" : "ms/frame");
        ASSERT_EQ(reps.size(), is_cpu ? 4u : 5u) << t.get(i, "time_repeats");
        const double median = is_cpu ? 0.5 * (reps[1] + reps[2]) : reps[2];
        EXPECT_NEAR(t.number(i, "time"), median, 1e-9 * median) << t.where(i);
        EXPECT_EQ(t.number(i, "time_min"), reps.front());
        EXPECT_EQ(t.number(i, "time_max"), reps.back());
        if (is_cpu) {
            EXPECT_EQ(t.get(i, "gpu_ms_per_frame"), "");
        } else {  // llvmpipe has 64-bit timer queries
            const double lo = t.number(i, "gpu_ms_per_frame_min"),
                         mid = t.number(i, "gpu_ms_per_frame"),
                         hi = t.number(i, "gpu_ms_per_frame_max");
            EXPECT_GT(lo, 0.0);
            EXPECT_LE(lo, mid);
            EXPECT_LE(mid, hi);
        }
    }
    EXPECT_EQ(cpu, 2u);
    EXPECT_EQ(glsl, 2u);
    const auto run = nlohmann::json::parse(slurp(dir / "o" / "run.json"));
    const auto& b = run.at("backends");
    EXPECT_EQ(b.at("cpu").at("timing").at("unit"), "ns/sample");
    EXPECT_EQ(b.at("cpu").at("timing").at("repeats"), 4);
    EXPECT_TRUE(b.at("cpu").at("timing").at("counters").empty());
    EXPECT_EQ(b.at("glsl").at("timing").at("unit"), "ms/frame");
    EXPECT_EQ(b.at("glsl").at("timing").at("repeats"), 5);  // RunOptions::gl_frames
    EXPECT_EQ(b.at("glsl").at("timing").at("counters").at(0).at("name"), "gpu_ms_per_frame");
    // Each backend writes only its own block: the GL facts are the glsl block's, once.
    EXPECT_FALSE(b.at("glsl").at("facts").at("gl_renderer").get<std::string>().empty());
    EXPECT_EQ(b.at("glsl").at("gl").at("GL_RENDERER"), b.at("glsl").at("facts").at("gl_renderer"));
    EXPECT_FALSE(b.at("glsl").at("sources").empty());
    for (const char* k :
         {"gl", "gl_renderer", "gl_version", "shaders", "shader_dir", "LP_NUM_THREADS"})
        EXPECT_FALSE(run.contains(k)) << k;
    EXPECT_FALSE(b.at("cpu").contains("gl"));
    EXPECT_FALSE(b.at("glsl").at("timing").at("measures").get<std::string>().empty());
}

// Same experiment, same numbers, whatever the thread count (timing columns aside).
TEST_F(Cli, ThreadCountDoesNotChangeNumbers) {
    std::string text = kSmall;  // plus the GLSL backend, a light and a measured field
    text.replace(text.find("timing_repeats = 1"), 18,
                 "timing_repeats = 1\nbackends = [\"cpu\", \"glsl\"]\n[light]\ntheta_deg = 40");
    text += "[[heightfields]]\nscan = \"lidar_b9\"\n";
    const auto exp = write("small.toml", text);
    ASSERT_EQ(pxh("run " + exp + " --quiet --threads 1 --out " + (dir / "t1").string()).status, 0);
    ASSERT_EQ(pxh("run " + exp + " --quiet --threads 2 --out " + (dir / "t2").string()).status, 0);
    // Every column except the timings (time* but its unit, gpu_ms_per_frame*).
    auto strip_timing = [](const fs::path& csv) {
        const pxh::CsvTable t = pxh::read_csv(csv.string());
        std::string out;
        for (size_t r = 0; r < t.rows.size(); ++r) {
            for (size_t c = 0; c < t.columns.size(); ++c)
                if ((t.columns[c].rfind("time", 0) != 0 || t.columns[c] == "time_unit") &&
                    t.columns[c].rfind("gpu_ms", 0) != 0)
                    out += t.rows[r][c] + ",";
            out += "\n";
        }
        return out;
    };
    const std::string a = strip_timing(dir / "t1" / "results.csv");
    const std::string b = strip_timing(dir / "t2" / "results.csv");
    EXPECT_GT(a.size(), 100u);
    EXPECT_EQ(a, b);
}

// ground_truth = "embree" measures against Embree's hits: numbers move by about the
// references' disagreement, which both runs record identically.
TEST_F(Cli, EmbreeGroundTruthSelectsTheReference) {
    std::string text = kSmall;
    const auto exact = write("exact.toml", text);
    text.replace(text.find("samples = 24"), 12, "samples = 24\nground_truth = \"embree\"");
    const auto embree = write("embree.toml", text);
    ASSERT_EQ(pxh("run " + exact + " --quiet --out " + (dir / "a").string()).status, 0);
    ASSERT_EQ(pxh("run " + embree + " --quiet --out " + (dir / "b").string()).status, 0);
    auto column = [&](const fs::path& csv, const std::string& name) {
        std::istringstream in(slurp(csv));
        std::string header, line;
        std::getline(in, header);
        int idx = 0, col = -1;
        std::istringstream hs(header);
        for (std::string c; std::getline(hs, c, ','); ++idx)
            if (c == name) col = idx;
        std::vector<std::string> out;
        while (std::getline(in, line)) {
            std::istringstream ls(line);
            std::string c;
            for (int i = 0; i <= col; ++i) std::getline(ls, c, ',');
            out.push_back(c);
        }
        return out;
    };
    const auto ea = column(dir / "a" / "results.csv", "err_mean");
    const auto eb = column(dir / "b" / "results.csv", "err_mean");
    const auto ga = column(dir / "a" / "results.csv", "gt_agree_max");
    const auto gb = column(dir / "b" / "results.csv", "gt_agree_max");
    ASSERT_EQ(ea.size(), eb.size());
    int differ = 0;
    for (size_t i = 0; i < ea.size(); ++i) {
        differ += ea[i] != eb[i];
        // Per sample |e_a - e_b| <= |truth_a - truth_b|, so the means differ by at most the
        // references' largest disagreement.
        EXPECT_LE(std::abs(std::stod(ea[i]) - std::stod(eb[i])), std::stod(ga[i]) + 1e-9) << i;
        EXPECT_EQ(ga[i], gb[i]);
    }
    EXPECT_GT(differ, 0) << "the reference made no difference";
    EXPECT_EQ(column(dir / "b" / "results.csv", "ground_truth")[0], "embree");
}

TEST_F(Cli, BadInputsExitTwoWithOneLineAndNoResults) {
    const std::string good = kSmall;
    auto variant = [&](const std::string& from, const std::string& to) {
        std::string s = good;
        s.replace(s.find(from), from.size(), to);
        return s;
    };
    struct Case {
        std::string text, expect;
    };
    const Case cases[] = {
        {variant("name = \"pom\"", "name = \"nope\""), "unknown method 'nope'"},
        {variant("generator = \"fbm\"", "generator = \"nope\""), "unknown generator 'nope'"},
        {variant("theta_deg = [0, 60, 85]", "theta_deg = [0, 90]"), "is impossible"},
        {variant("theta_deg = [0, 60, 85]", "theta_deg = [-1]"), "is impossible"},
        {variant("size = 16\nbias = 0.5", "size = 16\nbias = 2"), "bias must lie in [0, 1]"},
        {variant("size = 16\nbias = 0.5", "size = 16\nscale = -1"), "scale must be > 0"},
        {variant("samples = 24", "samples = 0"), "'samples' = 0"},
        {variant("generator = \"fbm\"\nsize = 32", "file = \"missing.png\""),
         "missing.png' (paths are relative to the experiment file): no such file"},
        {variant("generator = \"fbm\"\nsize = 32", "file = \"notimage.png\""),
         "notimage.png' (paths are relative to the experiment file): not a readable image"},
    };
    write("notimage.png", "hello, not a png\n");
    int k = 0;
    for (const auto& c : cases) {
        const auto exp = write("bad" + std::to_string(k) + ".toml", c.text);
        const fs::path out = dir / ("res" + std::to_string(k++));
        const Result r = pxh("run " + exp + " --out " + out.string());
        EXPECT_EQ(r.status, 2) << c.expect;
        EXPECT_NE(r.err.find(c.expect), std::string::npos) << r.err;
        EXPECT_TRUE(r.err.find(".toml") != std::string::npos ||
                    r.err.find(".png") != std::string::npos)
            << "names no file: " << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
        EXPECT_FALSE(fs::exists(out)) << "a results folder was left for a failed run";
        for (const auto& e : fs::directory_iterator(dir))
            EXPECT_EQ(e.path().string().find(".partial-"), std::string::npos) << e.path();
    }
    const Result missing = pxh("run " + (dir / "nope.toml").string());
    EXPECT_EQ(missing.status, 2);
    EXPECT_NE(missing.err.find("nope.toml: no such file"), std::string::npos);
}

// GLSL rows beside CPU rows; a broken shader fails only its own rows, with the driver's log.
TEST_F(Cli, GlslBackendRowsAndBrokenShader) {
    std::string text = kSmall;
    text.replace(text.find("timing_repeats = 1"), 18,
                 "timing_repeats = 1\nbackends = [\"cpu\", \"glsl\"]");
    const auto exp = write("gl.toml", text);
    std::filesystem::create_directories(dir / "shaders");
    write("shaders/pom.frag.glsl", "vec2 pxh_method(vec2 P) { return undefined_thing; }\n");
    const Result r = pxh("run " + exp + " --quiet --shader-dir " + (dir / "shaders").string() +
                         " --out " + (dir / "res").string());
    // Complete results are written, but a run with failed rows is not a success.
    ASSERT_EQ(r.status, 1) << r.err;
    EXPECT_NE(r.err.find("pxh: failed row: pom"), std::string::npos) << r.err;
    const std::string csv = slurp(dir / "res" / "results.csv");
    std::istringstream lines(csv);
    std::string line;
    int glsl_ok = 0, glsl_failed = 0, cpu = 0;
    while (std::getline(lines, line)) {
        if (line.find(",glsl,") != std::string::npos) {
            if (line.find(",failed,") != std::string::npos) {
                ++glsl_failed;
                EXPECT_NE(line.find("method 'pom'"), std::string::npos) << line;
                EXPECT_NE(line.find("undefined_thing"), std::string::npos) << line;
                // The error names the file actually compiled, not the built-in path.
                EXPECT_NE(line.find((dir / "shaders" / "pom.frag.glsl").string()),
                          std::string::npos)
                    << line;

            } else {
                ++glsl_ok;
            }
        } else if (line.find(",cpu,") != std::string::npos) {
            ++cpu;
        }
    }
    EXPECT_EQ(cpu, 36);
    EXPECT_EQ(glsl_failed, 24);  // both pom settings x 2 fields x 2 phi x 3 theta
    EXPECT_EQ(glsl_ok, 12);      // parallax
    EXPECT_NE(slurp(dir / "res" / "run.json").find("llvmpipe"), std::string::npos);
    // Every measured cell of a failed row is empty (0 would read as a perfect method); the
    // shader column says which source each GLSL row ran.
    const pxh::CsvTable t = pxh::read_csv((dir / "res" / "results.csv").string());
    int checked = 0;
    for (size_t i = 0; i < t.rows.size(); ++i) {
        if (t.get(i, "backend") != "glsl") continue;
        const bool failed = t.get(i, "status") == "failed";
        EXPECT_EQ(t.get(i, "shader"),
                  failed ? (dir / "shaders" / "pom.frag.glsl").string() : "builtin");
        for (const char* c :
             {"err_mean", "err_p95", "err_max", "frac_gt_1", "nonfinite", "fetches_mean", "time",
              "time_unit", "cpu_diff_max", "excluded", "gt_agree_p50"})
            if (failed) {
                EXPECT_EQ(t.get(i, c), "") << c;
                ++checked;
            } else {
                EXPECT_NE(t.get(i, c), "") << c;
            }
    }
    EXPECT_EQ(checked, 24 * 11);
    // run.json: the sha256 of every shader source compiled (the override and the built-ins).
    // (the glsl backend's block: its sources; with the --shader-dir it read them from).
    const auto run = nlohmann::json::parse(slurp(dir / "res" / "run.json"));
    const auto& glsl = run["backends"]["glsl"];
    const std::string pom_file = (dir / "shaders" / "pom.frag.glsl").string();
    ASSERT_TRUE(glsl["sources"].contains(pom_file)) << glsl["sources"].dump();
    EXPECT_EQ(glsl["sources"][pom_file], pxh::sha256_file(pom_file));
    EXPECT_TRUE(glsl["sources"].contains("builtin:methods/parallax/parallax.frag.glsl"));
    EXPECT_TRUE(glsl["sources"].contains("builtin:methods/common.glsl"));
    EXPECT_EQ(glsl["shader_dir"], fs::absolute(dir / "shaders").string());
}

// A --shader-dir that does not exist is an error, not the built-in shaders' numbers.
TEST_F(Cli, MissingShaderDirIsAnError) {
    std::string text = kSmall;
    text.replace(text.find("timing_repeats = 1"), 18, "timing_repeats = 1\nbackends = [\"glsl\"]");
    const auto exp = write("gl.toml", text);
    const Result r = pxh("run " + exp + " --quiet --shader-dir " + (dir / "shaderz").string() +
                         " --out " + (dir / "res").string());
    EXPECT_EQ(r.status, 2) << r.err;
    EXPECT_NE(r.err.find("shaderz: no such folder"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir / "res"));
}

// The shipped hard-case experiment: every method on every case is ok, finite and within its
// declared fetch bound, on both backends and both precisions.
TEST_F(Cli, HardCasesAreStable) {
    const std::string exp = std::string(PXH_SOURCE_DIR) + "/results/experiments/hard_cases.toml";
    const Result r = pxh("run " + exp + " --quiet --out " + (dir / "hard").string());
    ASSERT_EQ(r.status, 0) << r.err;
    std::istringstream in(slurp(dir / "hard" / "results.csv"));
    std::string header, line;
    std::getline(in, header);
    std::vector<std::string> names;
    std::istringstream hs(header);
    for (std::string c; std::getline(hs, c, ',');) names.push_back(c);
    auto idx = [&](const std::string& n) {
        return size_t(std::find(names.begin(), names.end(), n) - names.begin());
    };
    const size_t status = idx("status"), nonfinite = idx("nonfinite"), fmax = idx("fetches_max"),
                 bound = idx("fetches_bound"), mean = idx("err_mean");
    int rows = 0;
    while (std::getline(in, line)) {
        std::vector<std::string> c;
        std::istringstream ls(line);
        for (std::string v; std::getline(ls, v, ',');) c.push_back(v);
        ASSERT_GT(c.size(), bound) << line;
        EXPECT_EQ(c[status], "ok") << line;
        EXPECT_EQ(c[nonfinite], "0") << line;
        EXPECT_LE(std::stod(c[fmax]), std::stod(c[bound])) << line;
        EXPECT_FALSE(c[mean].empty()) << line;
        ++rows;
    }
    EXPECT_EQ(rows, 7 * 6 * 4 * 2 * 9 * 3);  // fields x (s, b) x theta x phi x methods x rows
}

// --maps: an EXR and a PNG per row; the EXR's magnitude channel reproduces err_max.
TEST_F(Cli, ErrorMapsMatchTheRow) {
    const auto exp = write("small.toml", kSmall);
    const Result r = pxh("run " + exp + " --quiet --maps --out " + (dir / "m").string());
    ASSERT_EQ(r.status, 0) << r.err;
    std::istringstream in(slurp(dir / "m" / "results.csv"));
    std::string header, line;
    std::getline(in, header);
    int maps = 0;
    while (std::getline(in, line)) {
        const auto pos = line.find("maps/");
        ASSERT_NE(pos, std::string::npos) << line;
        const std::string png = line.substr(pos, line.find(',', pos) - pos);
        EXPECT_TRUE(fs::exists(dir / "m" / png)) << png;
        const std::string exr = png.substr(0, png.size() - 4) + ".exr";
        EXPECT_TRUE(fs::exists(dir / "m" / exr)) << exr;
        ++maps;
    }
    EXPECT_EQ(maps, 36);
}

TEST_F(Cli, ListShowsMethodsAndGenerators) {
    const Result m = pxh("list methods");
    ASSERT_EQ(m.status, 0);
    for (const char* name : {"parallax", "pom", "layers_min", "relief", "binary_steps"})
        EXPECT_NE(m.out.find(name), std::string::npos) << name;
    const Result h = pxh("list heightfields");
    for (const char* name :
         {"flat", "sine", "bumps", "bricks", "pyramids", "terraces", "fbm", "spikes"})
        EXPECT_NE(h.out.find(name), std::string::npos) << name;
    EXPECT_EQ(pxh("list nothing").status, 2);
}

}  // namespace

// ./run.sh --help prints its usage, and only that.
TEST_F(Cli, RunShHelpIsTheUsage) {
    const std::string cmd =
        std::string(PXH_SOURCE_DIR) + "/run.sh --help > " + (dir / "h.txt").string();
    ASSERT_EQ(std::system(cmd.c_str()), 0);
    const std::string help = slurp(dir / "h.txt");
    EXPECT_NE(help.find("./run.sh test"), std::string::npos) << help;
    EXPECT_EQ(help.find("set -e"), std::string::npos) << help;
}
