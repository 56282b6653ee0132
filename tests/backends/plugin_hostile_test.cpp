// Hostile and broken plug-in shaders through the binary, and the GL child process:
//   PluginFiles   - `shader =` reads only a regular UTF-8 text file inside the experiment's
//                   folder (absolute paths, ../, /proc, directories, FIFOs, links out, > 1 MiB,
//                   a Latin-1 byte: one line, exit 2, nothing written);
//   PluginRefused - found before any row, exit 2 and nothing written: a compile error at the
//                   user's FILE:LINE:COL (several errors, several lines), a reserved name, the
//                   height texture or the fetch counter used around the interface, a uniform
//                   that the shader does not use, a plug-in in a CPU-only run, a float uniform
//                   that does not fit a float;
//   PluginRows    - a shader that discards does not get the previous method's numbers; a
//                   shader over its declared bound fails its rows; a shader whose frame takes
//                   minutes fails its own rows within --gl-time-limit and every other row is ok;
//                   --gl egl on a software renderer warns once;
//   GlWorker      - the child process's answer equals the in-process backend's, field by field.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>

#include "harness/backends/gl_worker.h"
#include "harness/backends/glsl_backend.h"
#include "harness/results/csv_table.h"
#include "harness/scene/view.h"
#include "heightfields/heightfields.h"
#include "tests/cli_util.h"
#include "tests/test_util.h"

namespace fs = std::filesystem;

namespace {

class PluginFixture : public pxh::test::CliTest {
  protected:
    void SetUp() override {
        CliTest::SetUp();
        fs::create_directories(dir / "exp");
    }
    int sh(const std::string& cmd) { return CliTest::sh(cmd).status; }
    int run(const std::string& extra = "") {
        return sh(std::string(PXH_BINARY) + " run " + (dir / "exp" / "exp.toml").string() +
                  " --quiet --out " + (dir / "r").string() + " " + extra);
    }
    std::string err() { return slurp(dir / "err.txt"); }
    void write(const std::string& name, const std::string& text) {
        std::ofstream(dir / "exp" / name, std::ios::binary) << text;
    }
    // The experiment: maxmip and pom (CPU and GLSL), then the plug-in entry given.
    void experiment(const std::string& plugin_entry,
                    const std::string& backends = "\"cpu\", \"glsl\"",
                    const std::string& thetas = "0, 60") {
        write("exp.toml", "samples = 32\nbackends = [" + backends +
                              "]\ntiming_repeats = 0\n[views]\ntheta_deg = [" + thetas +
                              "]\n[[heightfields]]\ngenerator = \"bricks\"\nsize = 64\n"
                              "scale = 0.06\nbias = 1.0\n[[methods]]\nname = \"maxmip\"\n"
                              "[[methods]]\nname = \"pom\"\nlayers = 16\n[[methods]]\n" +
                              plugin_entry);
    }
    void plugin(const std::string& shader_path, const std::string& extra = "") {
        experiment("name = \"mine\"\nshader = \"" + shader_path + "\"\nmax_fetches = 1\n" + extra);
    }
    // Exit 2, one line that contains `what`, no results folder.
    void expect_refused(const std::string& what, int lines = 1) {
        EXPECT_EQ(run(), 2) << err();
        const std::string e = err();
        EXPECT_NE(e.find(what), std::string::npos) << e;
        EXPECT_EQ(std::count(e.begin(), e.end(), '\n'), lines) << e;
        EXPECT_FALSE(fs::exists(dir / "r")) << "nothing is written on bad input";
    }
};

const char* kOk = "vec2 pxh_method(vec2 P) { return P; }\n";

using PluginFiles = PluginFixture;

TEST_F(PluginFiles, AbsolutePathIsRefused) {
    plugin("/etc/passwd");
    expect_refused("exp.toml:");
    EXPECT_NE(err().find("shader '/etc/passwd': an absolute path"), std::string::npos) << err();
    plugin("/proc/self/environ");
    expect_refused("shader '/proc/self/environ': an absolute path");
}

TEST_F(PluginFiles, PathOutOfTheFolderIsRefused) {
    // ../../../etc/passwd from the experiment's folder: it exists, and it is outside.
    std::string up;
    for (auto it = dir.begin(); it != dir.end(); ++it) up += "../";
    plugin(up + "etc/passwd");
    expect_refused("lies outside the experiment's folder once links are resolved (/etc/passwd)");
    std::ofstream(dir / "outside.frag.glsl") << kOk;  // a shader beside the folder, not in it
    plugin("../outside.frag.glsl");
    expect_refused("lies outside the experiment's folder");
}

TEST_F(PluginFiles, SymlinkOutIsRefusedAndInsideIsFollowed) {
    fs::create_symlink("/proc/self/environ", dir / "exp" / "env.frag.glsl");
    plugin("env.frag.glsl");
    expect_refused("lies outside the experiment's folder");
    std::ofstream(dir / "outside.frag.glsl") << kOk;
    fs::create_symlink(dir / "outside.frag.glsl", dir / "exp" / "out.frag.glsl");
    plugin("out.frag.glsl");
    expect_refused("lies outside the experiment's folder");
    // A link that stays inside the folder is fine.
    fs::create_directories(dir / "exp" / "shaders");
    write("shaders/real.frag.glsl", kOk);
    fs::create_symlink("shaders/real.frag.glsl", dir / "exp" / "in.frag.glsl");
    plugin("in.frag.glsl");
    EXPECT_EQ(run(), 0) << err();
    const std::string run_json = slurp(dir / "r" / "run.json");
    EXPECT_NE(run_json.find("return P; }"), std::string::npos);
}

TEST_F(PluginFiles, DirectoryFifoAndDanglingLinkAreRefused) {
    fs::create_directories(dir / "exp" / "adir");
    plugin("adir");
    expect_refused("shader 'adir': is a directory");
    ASSERT_EQ(mkfifo((dir / "exp" / "fifo.frag.glsl").c_str(), 0600), 0);
    plugin("fifo.frag.glsl");
    expect_refused("shader 'fifo.frag.glsl': not a regular file");  // and it did not block
    fs::create_symlink(dir / "exp" / "nothing", dir / "exp" / "dangling.frag.glsl");
    plugin("dangling.frag.glsl");
    expect_refused("shader 'dangling.frag.glsl': cannot be resolved");
}

TEST_F(PluginFiles, LargeFileIsRefused) {
    write("big.frag.glsl", std::string(kOk) + "//" + std::string((1 << 20), 'x') + "\n");
    plugin("big.frag.glsl");
    expect_refused("a plug-in shader is at most 1048576 bytes (1 MiB)");
}

TEST_F(PluginFiles, NonUtf8ByteIsRefusedWhereItIs) {
    // A Latin-1 comment on line 2: it used to discard the whole run at its end.
    write("latin1.frag.glsl", std::string(kOk) + "// caf\xe9\n");
    plugin("latin1.frag.glsl");
    expect_refused((dir / "exp" / "latin1.frag.glsl").lexically_normal().string() +
                   ":2:7: byte 0xE9 is not UTF-8");
}

using PluginRefused = PluginFixture;

TEST_F(PluginRefused, CompileErrorsAtTheUsersLines) {
    // Two errors: two lines, each at its FILE:LINE:COL in the user's file.
    write("bad.frag.glsl",
          "// my shader\nvec2 pxh_method(vec2 P) {\n    float a = oops;\n    return P + "
          "nope;\n}\n");
    plugin("bad.frag.glsl");
    const std::string file = (dir / "exp" / "bad.frag.glsl").lexically_normal().string();
    EXPECT_EQ(run(), 2);
    const std::string e = err();
    EXPECT_NE(e.find("pxh: error: " + file + ":3:"), std::string::npos) << e;
    EXPECT_NE(e.find("oops' undeclared"), std::string::npos) << e;
    EXPECT_NE(e.find("pxh: error: " + file + ":4:"), std::string::npos) << e;
    EXPECT_NE(e.find("nope' undeclared"), std::string::npos) << e;
    EXPECT_FALSE(fs::exists(dir / "r"));
}

TEST_F(PluginRefused, ReservedLayerUniform) {
    write("layers.frag.glsl",
          "uniform float p_layers;\nvec2 pxh_method(vec2 P) { return P * p_layers; }\n");
    plugin("layers.frag.glsl", "uniforms = { p_layers = 8.0 }\n");
    expect_refused("layers.frag.glsl:1:15: 'p_layers' is a reserved name");
    // The documented way: the layer search with its count, no reserved uniform.
    write("search.frag.glsl",
          "uniform float p_steps;\nvec2 pxh_method(vec2 P) {\n    PxhLayers r = "
          "pxh_layer_search_n(P, p_steps);\n    return pxh_uv_at(r, float(r.k));\n}\n");
    experiment(
        "name = \"mine\"\nshader = \"search.frag.glsl\"\nmax_fetches = 17\nuniforms = { p_steps "
        "= 16.0 }\n");
    EXPECT_EQ(run(), 0) << err();
}

TEST_F(PluginRefused, HeightTextureAndCounterAroundTheInterface) {
    const std::pair<std::string, std::string> cases[] = {
        {"vec2 pxh_method(vec2 P) { return P + textureLod(u_height, P, 0.0).r; }\n",
         ":1:49: 'u_height' is pxh's height texture"},
        {"vec2 pxh_method(vec2 P) {\n  return P + texture(u_height, P).r;\n}\n",
         ":2:22: 'u_height' is pxh's height texture"},
        {"vec2 pxh_method(vec2 P) { return P + texelFetch(u_height, ivec2(0), 0).r; }\n",
         "'u_height' is pxh's height texture"},
        {"vec2 pxh_method(vec2 P) { float h = pxh_height(P); pxh_fetches = 0; return P; }\n",
         "'pxh_fetches' is pxh's fetch counter"},
        {"vec2 pxh_method(vec2 P) { return P + textureLod(u_view_map, P, 0.0).r; }\n",
         "'u_view_map' is pxh's per-sample view map"},
        {"#define T(a, b) a##b\nvec2 pxh_method(vec2 P) { return P + textureLod(T(u_, height), "
         "P, 0.0).r; }\n",
         ":1:18: token pasting (##) is refused"},
    };
    for (const auto& [source, message] : cases) {
        write("cheat.frag.glsl", source);
        plugin("cheat.frag.glsl");
        expect_refused(message);
    }
}

// The check before the run compiles every program the rows compile: each setting's lod mode
// (and a perspective camera's point map) declares names the grid's program does not. Before, it
// compiled the grid's alone: a plug-in declaring pxh_lambda passed it and failed every level
// row (exit 1, a results folder written), and one assigning pxh_lambda was refused although its
// level rows declare it.
TEST_F(PluginRefused, EveryLodProgramOfTheRowsIsChecked) {
    write("decl.frag.glsl", "float pxh_lambda;\nvec2 pxh_method(vec2 P) { return P; }\n");
    plugin("decl.frag.glsl", "lod = \"level\"\n");
    const std::string decl = (dir / "exp" / "decl.frag.glsl").lexically_normal().string();
    expect_refused("pxh: error: " + decl + ":1:");
    EXPECT_NE(err().find("pxh_lambda"), std::string::npos) << err();
    plugin("decl.frag.glsl");  // lod = base only: nothing declares it twice
    EXPECT_EQ(run(), 0) << err();
    fs::remove_all(dir / "r");
    write("grad.frag.glsl", "vec4 pxh_footprint;\nvec2 pxh_method(vec2 P) { return P; }\n");
    plugin("grad.frag.glsl", "lod = \"grad\"\n");
    expect_refused("grad.frag.glsl:1:");
    // Assigning the level rows' own pxh_lambda: what those rows compile, so accepted there ...
    write("set.frag.glsl",
          "vec2 pxh_method(vec2 P) {\n  pxh_lambda = 0.0;\n  return P + 0.0 * pxh_height(P);\n}\n");
    plugin("set.frag.glsl", "lod = \"level\"\n");
    EXPECT_EQ(run(), 0) << err();
    fs::remove_all(dir / "r");
    // ... and refused where the rows' program has no such name (lod = base).
    plugin("set.frag.glsl");
    expect_refused("set.frag.glsl:2:2: error: `pxh_lambda' undeclared", 2);
    // A macro of common.glsl's defined otherwise: the level program's preamble defines it.
    write("def.frag.glsl", "#define PXH_LOD_LEVEL 1\nvec2 pxh_method(vec2 P) { return P; }\n");
    plugin("def.frag.glsl", "lod = \"level\"\n");
    expect_refused("def.frag.glsl:1:");
    // Settings in several modes: each mode's program is checked.
    plugin("decl.frag.glsl", "lod = [\"base\", \"level\"]\n");
    expect_refused("decl.frag.glsl:1:");
}

TEST_F(PluginRefused, UnusedUniformIsFoundBeforeAnyRow) {
    write("u.frag.glsl", kOk);
    plugin("u.frag.glsl", "uniforms = { p_steps = 3.0 }\n");
    expect_refused("the method declares float uniform 'p_steps' but the shader does not use it");
    EXPECT_NE(err().find("u.frag.glsl"), std::string::npos);
    // A uniform the shader reads and the entry does not give: at its declaration's line.
    write("v.frag.glsl", "// v\nuniform float p_k;\nvec2 pxh_method(vec2 P) { return P * p_k; }\n");
    plugin("v.frag.glsl");
    expect_refused("v.frag.glsl:2:15: the shader reads float uniform 'p_k' but nothing sets it");
}

TEST_F(PluginRefused, PluginInCpuOnlyRun) {
    write("ok.frag.glsl", kOk);
    experiment("name = \"mine\"\nshader = \"ok.frag.glsl\"\nmax_fetches = 1\n", "\"cpu\"");
    expect_refused("exp.toml:17: plug-in 'mine' is a GLSL shader (it has no CPU rows)");
    experiment("name = \"mine\"\nshader = \"ok.frag.glsl\"\nmax_fetches = 1\n");
    EXPECT_EQ(run("--backend cpu"), 2);
    EXPECT_NE(err().find("--backend: the plug-in shader(s) 'mine' run on the glsl backend only"),
              std::string::npos)
        << err();
    EXPECT_EQ(run("--only backend=cpu"), 2);
    EXPECT_NE(err().find("run on the glsl backend only"), std::string::npos) << err();
    EXPECT_FALSE(fs::exists(dir / "r"));
}

TEST_F(PluginRefused, FloatUniformThatDoesNotFitAFloat) {
    write("f.frag.glsl", "uniform float p_k;\nvec2 pxh_method(vec2 P) { return P * p_k; }\n");
    plugin("f.frag.glsl", "uniforms = { p_k = 1e300 }\n");
    expect_refused("exp.toml:16: method 'mine' parameter 'p_k' = 1e+300 is outside [-3.4");
    plugin("f.frag.glsl", "uniforms = { p_k = 3.0e38 }\n");  // fits
    EXPECT_EQ(run(), 0) << err();
}

TEST_F(PluginRefused, TimeLimitOutOfRange) {
    write("ok.frag.glsl", kOk);
    plugin("ok.frag.glsl");
    for (const char* bad : {"0", "-1", "1e9"}) {
        EXPECT_EQ(run(std::string("--gl-time-limit ") + bad), 2) << bad;
        EXPECT_NE(err().find("--gl-time-limit: "), std::string::npos) << err();
        EXPECT_NE(err().find("is outside (0, 86400]"), std::string::npos) << err();
    }
    const std::string text = slurp(dir / "exp" / "exp.toml");
    write("exp.toml", "gl_time_limit_s = 0\n" + text);
    expect_refused("exp.toml:1: gl_time_limit_s = 0 is outside (0, 86400]");
    EXPECT_FALSE(fs::exists(dir / "r"));
}

using PluginRows = PluginFixture;

// Discards the right half (P.x > 0.5: columns i >= N/2 of the N x N grid), run after maxmip:
// exactly N^2/2 samples discarded, none of them with maxmip's (or any) uv.
TEST_F(PluginRows, DiscardedSamplesAreCountedNotInherited) {
    write("d.frag.glsl", "vec2 pxh_method(vec2 P) { if (P.x > 0.5) discard; return P; }\n");
    plugin("d.frag.glsl");
    ASSERT_EQ(run(), 0) << err();
    const pxh::CsvTable t = pxh::read_csv((dir / "r" / "results.csv").string());
    int mine = 0;
    for (size_t r = 0; r < t.rows.size(); ++r) {
        if (t.get(r, "method") != "mine") {
            EXPECT_EQ(t.get(r, "samples_discarded"), "0") << t.get(r, "method");
            continue;
        }
        ++mine;
        EXPECT_EQ(t.get(r, "status"), "ok");
        EXPECT_EQ(t.get(r, "samples_discarded"), "512");  // 32 x 32 / 2
        // a discard is counted once, in samples_discarded, never in nonfinite (conventions 9)
        EXPECT_EQ(t.get(r, "nonfinite"), "0");
        EXPECT_NE(t.get(r, "error").find("512 of 1024 samples discarded"), std::string::npos);
        // uv = P: at theta 0 the truth itself (error 0); at 60 degrees P is off by the
        // parallax, nowhere near maxmip's exact answer (err_mean ~6e-7 there).
        if (t.get(r, "theta_deg") == "0") EXPECT_EQ(t.get(r, "err_max"), "0");
        else EXPECT_GT(std::stod(t.get(r, "err_mean")), 0.5);
    }
    EXPECT_EQ(mine, 2);
    // The gate can limit it: samples_discarded <= 0 fails for the plug-in, holds for maxmip.
    std::ofstream(dir / "t.toml") << "[[limit]]\nmethod = \"mine\"\ncolumn = "
                                     "\"samples_discarded\"\nmax = 0\n";
    EXPECT_EQ(sh(std::string(PXH_BINARY) + " check " + (dir / "r").string() + " --thresholds " +
                 (dir / "t.toml").string()),
              1)
        << slurp(dir / "out.txt") << err();
    std::ofstream(dir / "t.toml") << "[[limit]]\nmethod = \"maxmip\"\ncolumn = "
                                     "\"samples_discarded\"\nmax = 0\n";
    EXPECT_EQ(sh(std::string(PXH_BINARY) + " check " + (dir / "r").string() + " --thresholds " +
                 (dir / "t.toml").string()),
              0)
        << slurp(dir / "out.txt") << err();
}

// The finding as reported: `if (p_x > 0.0) discard; return P;` after maxmip reported maxmip's
// numbers (err_mean 5.7e-7, status ok). Every sample is discarded: no number at all.
TEST_F(PluginRows, DiscardEverythingAfterMaxmipHasNoNumbers) {
    write("d.frag.glsl",
          "uniform float p_x;\nvec2 pxh_method(vec2 P) { if (p_x > 0.0) discard; return P; }\n");
    plugin("d.frag.glsl", "uniforms = { p_x = 1.0 }\n");
    // Every sample discarded: no answer at all, so the row fails (a failure is never a
    // number), naming the discards; maxmip's rows, drawn before it, stay ok and keep theirs.
    ASSERT_EQ(run(), 1) << err();
    const pxh::CsvTable t = pxh::read_csv((dir / "r" / "results.csv").string());
    int mine = 0;
    for (size_t r = 0; r < t.rows.size(); ++r) {
        if (t.get(r, "method") != "mine") {
            EXPECT_EQ(t.get(r, "status"), "ok");
            EXPECT_NE(t.get(r, "err_mean"), "");
            continue;
        }
        ++mine;
        EXPECT_EQ(t.get(r, "status"), "failed");
        EXPECT_NE(t.get(r, "error").find("every sample (1024) was discarded or left unwritten"),
                  std::string::npos)
            << t.get(r, "error");
        EXPECT_EQ(t.get(r, "err_mean"), "") << "maxmip's numbers leaked into a discarding shader";
    }
    EXPECT_EQ(mine, 2);
}

// A uv far beyond the tile is a float without a fraction: it shows the texture at the tile's
// corner, exactly as uv = 0 does. Its error is that of uv = 0, not 0 (texel_error used to
// subtract before wrapping: 1e16 - uv_true rounded to 1e16, and every row read err 0, status
// ok), on both cameras.
TEST_F(PluginRows, HugeUvScoresAsTheTileCornerNotPerfect) {
    write("k.frag.glsl",
          "uniform float p_k;\nvec2 pxh_method(vec2 P) { return vec2(p_k) + P * 0.0; }\n");
    for (const std::string camera : {"", "camera = \"perspective\"\ndistance = 2\n"}) {
        write("exp.toml",
              "samples = 16\nbackends = [\"glsl\"]\ntiming_repeats = 0\n[views]\n"
              "theta_deg = [0, 60]\n" +
                  camera +
                  "[[heightfields]]\ngenerator = \"bricks\"\nsize = 64\nscale = 0.06\n"
                  "bias = 1.0\n[[methods]]\nname = \"huge\"\nshader = \"k.frag.glsl\"\n"
                  "max_fetches = 1\nuniforms = { p_k = 1e16 }\n[[methods]]\nname = "
                  "\"zero\"\nshader = \"k.frag.glsl\"\nmax_fetches = 1\nuniforms = "
                  "{ p_k = 0.0 }\n");
        fs::remove_all(dir / "r");
        ASSERT_EQ(run(), 0) << err();
        const pxh::CsvTable t = pxh::read_csv((dir / "r" / "results.csv").string());
        std::map<std::string, std::map<std::string, std::string>> rows;  // theta -> method -> mean
        for (size_t r = 0; r < t.rows.size(); ++r) {
            EXPECT_EQ(t.get(r, "status"), "ok");
            EXPECT_EQ(t.get(r, "nonfinite"), "0");
            rows[t.get(r, "theta_deg")][t.get(r, "method")] =
                t.get(r, "err_mean") + " " + t.get(r, "err_max");
        }
        ASSERT_EQ(rows.size(), 2u) << camera;
        for (auto& [theta, m] : rows) {
            ASSERT_EQ(m.size(), 2u);
            EXPECT_EQ(m["huge"], m["zero"]) << camera << " theta " << theta;
            // The samples lie all over the tile: a quarter of it away on average (64 texels).
            EXPECT_GT(std::stod(m["huge"]), 4.0) << camera << " theta " << theta;
        }
    }
}

// What holds on llvmpipe (docs/guide/plugin-shaders.md, "What holds on which driver"): every loop
// is cut after 65535 iterations per fragment, counted over all its entries; the shader goes on and
// its row is ok. One sample at theta 0 on a 16-texel field: the truth is P = (0.5, 0.5), and a
// shader returning (0.5 + n / 2^21, 0.5) has err_mean = 16 n / 2^21 texels, so each row reads back
// its count.
TEST_F(PluginRows, LlvmpipeCutsEveryLoopAt65535Iterations) {
    write("one.frag.glsl",
          "uniform int p_n;\nvec2 pxh_method(vec2 P) {\n  int i = 0;\n  while (i < p_n) i++;\n"
          "  return vec2(0.5 + float(i) / 2097152.0, 0.5) + P * 0.0;\n}\n");
    write("nest.frag.glsl",
          "uniform int p_n;\nvec2 pxh_method(vec2 P) {\n  int i = 0, t = 0;\n  while (i < p_n) {\n"
          "    int j = 0;\n    while (j < p_n) { j++; t++; }\n    i++;\n  }\n"
          "  return vec2(0.5 + float(t) / 2097152.0, 0.5) + P * 0.0;\n}\n");
    write("fetch.frag.glsl",
          "uniform int p_n;\nvec2 pxh_method(vec2 P) {\n  int i = 0;\n  float h = 0.0;\n"
          "  while (i < p_n) { h += pxh_height(P); i++; }\n  return P + 0.0 * h;\n}\n");
    write("exp.toml",
          "samples = 1\nbackends = [\"glsl\"]\ntiming_repeats = 0\n[views]\ntheta_deg = [0]\n"
          "[[heightfields]]\ngenerator = \"bricks\"\nsize = 16\n"
          "[[methods]]\nname = \"one\"\nshader = \"one.frag.glsl\"\nmax_fetches = 1\n"
          "uniforms = { p_n = [100, 65535, 1000000] }\n"
          "[[methods]]\nname = \"nest\"\nshader = \"nest.frag.glsl\"\nmax_fetches = 1\n"
          "uniforms = { p_n = 60000 }\n"
          "[[methods]]\nname = \"fetch\"\nshader = \"fetch.frag.glsl\"\nmax_fetches = 1000\n"
          "uniforms = { p_n = 1000000 }\n");
    EXPECT_EQ(run(), 1) << err();  // the fetching loop's row fails
    if (slurp(dir / "r" / "run.json").find("llvmpipe") == std::string::npos)
        GTEST_SKIP() << "not llvmpipe: these are llvmpipe's numbers";
    const pxh::CsvTable t = pxh::read_csv((dir / "r" / "results.csv").string());
    std::map<std::string, double> count;  // method params -> iterations read back
    for (size_t r = 0; r < t.rows.size(); ++r) {
        const std::string key = t.get(r, "method") + " " + t.get(r, "params");
        if (t.get(r, "method") == "fetch") {
            EXPECT_EQ(t.get(r, "status"), "failed");
            EXPECT_NE(t.get(r, "error")
                          .find("fetches_max = 65535 exceeds the declared bound "
                                "fetches_bound = 1000"),
                      std::string::npos)
                << t.get(r, "error");
            continue;
        }
        EXPECT_EQ(t.get(r, "status"), "ok") << key;  // cut, yet ok: what the guide says
        // err_mean has 10 digits: the count to within 1e-4, rounded.
        count[key] = std::round(std::stod(t.get(r, "err_mean")) * 2097152.0 / 16);
    }
    ASSERT_EQ(count.size(), 4u);
    EXPECT_EQ(count["one p_n=100"], 100);
    EXPECT_EQ(count["one p_n=65535"], 65535);
    EXPECT_EQ(count["one p_n=1000000"], 65535);  // not 1e6: cut
    // The inner loop over all its 60000 entries: about 65535 in all, not 3.6e9.
    EXPECT_GE(count["nest p_n=60000"], 65533);
    EXPECT_LE(count["nest p_n=60000"], 65535);
    // docs/guide/plugin-shaders.md says what holds here, not the promise that such a row fails.
    std::ifstream readme(std::string(PXH_SOURCE_DIR) + "/docs/guide/plugin-shaders.md");
    const std::string text((std::istreambuf_iterator<char>(readme)), {});
    EXPECT_NE(text.find("every loop of the compiled shader after 65535 iterations per fragment"),
              std::string::npos);
    EXPECT_NE(text.find("an endless loop does **not** fail its row"), std::string::npos);
}

TEST_F(PluginRows, OverItsBoundFails) {
    write("w.frag.glsl",
          "vec2 pxh_method(vec2 P) {\n  int k = 0;\n  while (pxh_height(P + float(k) * 1e-3) < "
          "2.0) k++;\n  return P;\n}\n");
    experiment("name = \"mine\"\nshader = \"w.frag.glsl\"\nmax_fetches = 40\n");
    EXPECT_EQ(run(), 1) << err();
    const pxh::CsvTable t = pxh::read_csv((dir / "r" / "results.csv").string());
    for (size_t r = 0; r < t.rows.size(); ++r) {
        if (t.get(r, "method") != "mine") {
            EXPECT_EQ(t.get(r, "status"), "ok");
            continue;
        }
        EXPECT_EQ(t.get(r, "status"), "failed");
        EXPECT_EQ(t.get(r, "fetches_max"), "") << "a failure is never a number";
        EXPECT_NE(t.get(r, "error").find("exceeds the declared bound fetches_bound = 40"),
                  std::string::npos)
            << t.get(r, "error");
        EXPECT_NE(t.get(r, "error").find("fetches_max = "), std::string::npos);
    }
}

// A frame that takes minutes on llvmpipe (its loop cap is 65536 iterations, so the body is long:
// 1024 sin/cos per iteration; measured: over 45 s per frame here, 6 frames a row). With a 2 s
// limit each of its rows fails with the reason, the run goes on in fresh GL contexts, every
// other row is ok, and the run ends in seconds (run under `timeout`: a hang fails the test).
TEST_F(PluginRows, SlowShaderFailsItsRowsWithinTheTimeLimit) {
    write("slow.frag.glsl", R"(#define S acc = sin(acc * 1.0001 + 0.3) * cos(acc + float(i));
#define S4 S S S S
#define S16 S4 S4 S4 S4
#define S64 S16 S16 S16 S16
#define S256 S64 S64 S64 S64
vec2 pxh_method(vec2 P) {
    float acc = P.x;
    for (int i = 0; i < 1000000; ++i) { S256 S256 S256 S256 }
    return P + acc * 1e-30;
}
)");
    plugin("slow.frag.glsl");
    const auto t0 = std::chrono::steady_clock::now();
    EXPECT_EQ(sh("timeout 120 " + std::string(PXH_BINARY) + " run " +
                 (dir / "exp" / "exp.toml").string() + " --quiet --out " + (dir / "r").string() +
                 " --gl-time-limit 2"),
              1)
        << err();
    const double secs =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    EXPECT_LT(secs, 100) << "not ended by the time limit";
    const pxh::CsvTable t = pxh::read_csv((dir / "r" / "results.csv").string());
    int slow = 0, ok = 0;
    for (size_t r = 0; r < t.rows.size(); ++r) {
        if (t.get(r, "method") == "mine") {
            ++slow;
            EXPECT_EQ(t.get(r, "status"), "failed");
            EXPECT_EQ(t.get(r, "err_mean"), "");
            EXPECT_NE(t.get(r, "error")
                          .find("GL time limit: the row's GL work did not finish "
                                "within 2 s"),
                      std::string::npos)
                << t.get(r, "error");
        } else {
            ok += t.get(r, "status") == "ok";
        }
    }
    EXPECT_EQ(slow, 2);
    EXPECT_EQ(ok, 8) << "maxmip and pom, cpu and glsl, 2 views: all ok, the GLSL ones after a kill";
}

TEST_F(PluginRows, EglOnSoftwareWarnsOnce) {
    write("ok.frag.glsl", kOk);
    plugin("ok.frag.glsl");
    ASSERT_EQ(run("--gl egl"), 0) << err();
    const std::string e = err();
    const std::string w = "pxh: warning: --gl egl gave a software renderer";
    // This machine has no GPU: EGL lands on llvmpipe (surfaceless or a software device).
    ASSERT_NE(e.find(w), std::string::npos) << e;
    EXPECT_EQ(e.find(w), e.rfind(w)) << "one line: " << e;
    EXPECT_NE(e.find("llvmpipe"), std::string::npos) << e;
    ASSERT_EQ(run("--force"), 0) << err();  // osmesa: asked for software, no warning
    EXPECT_EQ(err().find("warning"), std::string::npos) << err();
}

// The child's answer is the in-process backend's, every field: pom with a light and per-sample
// directions on one process and the other.
TEST(GlWorker, ChildAnswersAsTheInProcessBackend) {
    const pxh::MethodInfo* pom = pxh::find_method("pom");
    ASSERT_TRUE(pom);
    const pxh::ParamValues params = pxh::test::params_for(*pom);
    const pxh::GeneratorInfo* g = pxh::find_generator("bricks");
    const pxh::HeightField hf =
        pxh::generate_heightfield(*g, 64, 64, pxh::resolve_params(g->params, {}, "test", "bricks"));
    pxh::GlslDraw d;
    d.method = pxh::GlslMethod::of(*pom);
    d.uniforms = pxh::method_uniforms(*pom, params);
    d.scene = {0.06, 1.0, pxh::view_vector(50, 30), 64, 64};
    d.hf = &hf;
    d.samples = 16;
    const pxh::LightSpec light{40, 200, 8, 32};
    d.light = &light;
    std::vector<pxh::Vec3d> V;
    for (int k = 0; k < 16 * 16; ++k) V.push_back(pxh::view_vector(20 + k % 50, k % 360));
    d.V = &V;
    d.frames = 3;
    pxh::BackendSettings s;
    pxh::GlslChildBackend child(s);
    // A child process, even though this test process may have made a GL context before.
    ASSERT_FALSE(child.in_process());
    EXPECT_GT(child.child_pid(), 0);
    const pxh::MethodOutput a = child.draw(d);
    pxh::GlslBackend in_process(pxh::GlslOptions{"", 1});
    const pxh::MethodOutput b = in_process.draw(d);
    ASSERT_EQ(a.uv.size(), 256u);
    ASSERT_EQ(a.uv.size(), b.uv.size());
    for (size_t k = 0; k < a.uv.size(); ++k) {
        EXPECT_EQ(a.uv[k].x, b.uv[k].x);
        EXPECT_EQ(a.uv[k].y, b.uv[k].y);
    }
    EXPECT_EQ(a.fetches, b.fetches);
    EXPECT_EQ(a.shadow_hard, b.shadow_hard);
    EXPECT_EQ(a.shadow_soft, b.shadow_soft);
    EXPECT_EQ(a.shadow_hard.size(), 256u);
    EXPECT_EQ(a.shader, b.shader);
    EXPECT_EQ(a.shader_sha256, b.shader_sha256);
    EXPECT_EQ(a.samples_discarded, 0);
    // The timing and the counters come back whole: unit, every repeat, the spread.
    EXPECT_EQ(a.timing.unit, "ms/frame");
    EXPECT_EQ(a.timing.repeats.size(), 3u);
    EXPECT_EQ(b.timing.repeats.size(), 3u);
    EXPECT_TRUE(a.timing.stats.median > 0) << "timings come back";
    EXPECT_EQ(a.timing.stats.median, pxh::spread(a.timing.repeats).median);
    EXPECT_EQ(a.timing.stats.max, pxh::spread(a.timing.repeats).max);
    ASSERT_EQ(a.counters.size(), b.counters.size());
    for (size_t i = 0; i < a.counters.size(); ++i) {
        EXPECT_EQ(a.counters[i].name, b.counters[i].name);
        EXPECT_LE(a.counters[i].value.min, a.counters[i].value.median);
        EXPECT_LE(a.counters[i].value.median, a.counters[i].value.max);
    }
    EXPECT_EQ(child.sources(), in_process.compiled_sources());
    EXPECT_EQ(child.facts().at("gl_renderer"), in_process.renderer());
    EXPECT_EQ(child.restarts(), 0);
}

}  // namespace
