// Plug-in shaders ([[methods]] shader = FILE) through the binary: a copy of the built-in pom
// shader gives the built-in pom's GLSL rows; a broken one is exit 2 before any row, at its
// FILE:LINE:COL; bad entries are one line and exit 2; and README's worked example
// (examples/shader_gate) passes its gate, while a deliberately worse shader fails both pxh check
// and pxh compare.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "harness/core/sha256.h"
#include "harness/results/csv_table.h"
#include "tests/cli_util.h"

namespace fs = std::filesystem;

namespace {

class Plugin : public pxh::test::CliTest {
  protected:
    int sh(const std::string& cmd) { return CliTest::sh(cmd).status; }
    int pxh(const std::string& args) { return CliTest::pxh(args).status; }
    std::string slurp(const std::string& name) { return CliTest::slurp(dir / name); }
    static std::string source(const std::string& rel) { return pxh::test::source_file(rel); }
};

// Two 64^2 fields at s = 0.06, b = 1, four views, pom on both backends; the tests add methods.
const std::string kHead = pxh::test::ExperimentToml()
                              .samples(48)
                              .backends("\"cpu\", \"glsl\"")
                              .theta("[0, 35, 70, 85]")
                              .field("bricks", 64, "scale = 0.06\nbias = 1.0")
                              .field("fbm", 64, "scale = 0.06\nbias = 1.0")
                              .method("pom", "layers = 24");

TEST_F(Plugin, CopyOfBuiltinPomGivesItsRows) {
    write("copy.frag.glsl", source("methods/pom/pom.frag.glsl"));
    write("exp.toml", kHead + R"([[methods]]
name = "pom_copy"
shader = "copy.frag.glsl"
max_fetches = 26
reference = "pom"
reference_params = { layers = 24 }
uniforms = { p_layers_adaptive = false, p_layers = 24.0, p_layers_min = 8.0, p_layers_max = 32.0 }
)");
    ASSERT_EQ(pxh("run " + (dir / "exp.toml").string() + " --quiet --out " + (dir / "r").string()),
              0)
        << slurp("err.txt");
    const pxh::CsvTable t = pxh::read_csv((dir / "r" / "results.csv").string());
    std::map<std::string, size_t> builtin, copy;  // glsl rows by field and view
    size_t cpu_rows_of_copy = 0;
    for (size_t r = 0; r < t.rows.size(); ++r) {
        const std::string k = t.get(r, "heightfield") + "/" + t.get(r, "theta_deg");
        if (t.get(r, "method") == "pom_copy") {
            if (t.get(r, "backend") == "cpu") ++cpu_rows_of_copy;
            else copy[k] = r;
        } else if (t.get(r, "backend") == "glsl") {
            builtin[k] = r;
        }
    }
    EXPECT_EQ(cpu_rows_of_copy, 0u) << "a plug-in has no CPU twin: no CPU rows";
    ASSERT_EQ(copy.size(), 8u);
    ASSERT_EQ(builtin.size(), 8u);
    for (const auto& [k, r] : copy) {
        for (const char* c : {"err_mean", "err_p95", "err_max", "frac_gt_1", "fetches_mean",
                              "fetches_max", "cpu_diff_max", "decision_mismatch", "status"})
            EXPECT_EQ(t.get(r, c), t.get(builtin[k], c)) << k << " " << c;
        EXPECT_EQ(t.get(r, "fetches_bound"), "26");
        EXPECT_EQ(t.get(r, "params"),
                  "p_layers=24;p_layers_adaptive=false;p_layers_max=32;p_layers_min=8");
        EXPECT_EQ(t.get(r, "shader"), (dir / "copy.frag.glsl").string());
    }
    // The rows carry the source's sha256 (the same text as the built-in pom's: the same hash),
    // and run.json the plug-in's source itself.
    for (const auto& [k, r] : copy) {
        EXPECT_EQ(t.get(r, "shader_sha256"), pxh::sha256_hex(source("methods/pom/pom.frag.glsl")));
        EXPECT_EQ(t.get(r, "shader_sha256"), t.get(builtin[k], "shader_sha256"));
    }
    const std::string run_json = slurp("r/run.json");
    EXPECT_NE(run_json.find("\"plugin_shaders\""), std::string::npos);
    EXPECT_NE(run_json.find("pxh_layer_search(P)"), std::string::npos) << "source not recorded";
}

// The run's summary names, per plug-in, the row farthest from its reference and that row's first
// differing samples (index, both uv, both fetch counts): here the POM of examples/shader_gate
// without its interpolation (layer decisions equal, so equal fetches; the uv a layer apart).
TEST_F(Plugin, SummaryPrintsTheFirstDifferingSamples) {
    std::string text = source("examples/shader_gate/my_pom.frag.glsl");
    text.replace(text.find("return uv - duv * w;"), 20, "return uv;");
    write("worse.frag.glsl", text);
    write("exp.toml", kHead + R"([[methods]]
name = "worse_pom"
shader = "worse.frag.glsl"
max_fetches = 34
uniforms = { p_steps = 32.0 }
reference = "pom"
reference_params = { layers = 32 }
)");
    ASSERT_EQ(pxh("run " + (dir / "exp.toml").string() + " --out " + (dir / "r").string()), 0)
        << slurp("err.txt");
    const std::string out = slurp("out.txt");
    const size_t at = out.find("the worst row per method:\n  worse_pom p_steps=32 [glsl/r32f] on ");
    ASSERT_NE(at, std::string::npos) << out;
    const std::string line = out.substr(at, out.find('\n', out.find("  worse_pom", at)) - at);
    EXPECT_NE(line.find(" texel): 0: "), std::string::npos) << line;
    EXPECT_NE(line.find(" fetches "), std::string::npos) << line;
    EXPECT_NE(line.find("; ..."), std::string::npos) << "three samples shown, then '...': " << line;
}

// A shader that does not compile is found before any row runs: exit 2, the driver's message at
// the user's FILE:LINE:COL (not Mesa's "2:2(14)"), and no results folder (it used to write a
// folder of failed rows, exit 1).
TEST_F(Plugin, BrokenShaderIsExit2BeforeAnyRow) {
    write("broken.frag.glsl", "vec2 pxh_method(vec2 P) {\n  return P + oops;\n}\n");
    write("exp.toml", kHead + R"([[methods]]
name = "broken"
shader = "broken.frag.glsl"
max_fetches = 1
)");
    EXPECT_EQ(pxh("run " + (dir / "exp.toml").string() + " --quiet --out " + (dir / "r").string()),
              2);
    const std::string err = slurp("err.txt");
    EXPECT_NE(err.find("pxh: error: " + (dir / "broken.frag.glsl").string() + ":2:"),
              std::string::npos)
        << err;
    EXPECT_NE(err.find("oops"), std::string::npos) << err;
    EXPECT_EQ(err.find("2:2("), std::string::npos) << "Mesa's location left in: " << err;
    EXPECT_FALSE(fs::exists(dir / "r")) << "nothing is written";
    EXPECT_EQ(slurp("out.txt"), "");
}

TEST_F(Plugin, BadEntriesAreOneLineExit2) {
    write("ok.frag.glsl", "vec2 pxh_method(vec2 P) { return P; }\n");
    const std::pair<std::string, std::string> cases[] = {
        {"name = \"pom\"\nshader = \"ok.frag.glsl\"\nmax_fetches = 1\n",
         "'pom' is a built-in method; a plug-in shader needs a name of its own"},
        {"name = \"mine\"\nshader = \"nope.frag.glsl\"\nmax_fetches = 1\n",
         "shader 'nope.frag.glsl': no such file"},
        {"name = \"mine\"\nshader = \"ok.frag.glsl\"\n", "needs max_fetches"},
        {"name = \"mine\"\nshader = \"ok.frag.glsl\"\nmax_fetches = 1\nuniforms = { steps = 3 }\n",
         "uniform 'steps': plug-in uniforms are named p_NAME"},
        {"name = \"mine\"\nshader = \"ok.frag.glsl\"\nmax_fetches = 1\nlayers = 3\n",
         "unknown key 'layers' in a plug-in [[methods]] entry"},
        {"name = \"mine\"\nshader = \"ok.frag.glsl\"\nmax_fetches = 1\nreference = \"nope\"\n",
         "reference 'nope' is not a built-in method"},
    };
    for (const auto& [entry, message] : cases) {
        write("exp.toml", kHead + "[[methods]]\n" + entry);
        EXPECT_EQ(
            pxh("run " + (dir / "exp.toml").string() + " --quiet --out " + (dir / "r").string()), 2)
            << entry;
        const std::string err = slurp("err.txt");
        EXPECT_NE(err.find(message), std::string::npos) << err;
        EXPECT_NE(err.find("exp.toml:"), std::string::npos) << "no file:line: " << err;
        EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
        EXPECT_FALSE(fs::exists(dir / "r")) << "nothing is written on bad input";
    }
}

// README "Gate your engine's shader in CI", verbatim: examples/shader_gate/gate.sh passes on
// the committed shader and baseline; a worse shader (no interpolation) fails check and compare.
TEST_F(Plugin, WorkedExampleGate) {
    const fs::path ex = fs::path(PXH_SOURCE_DIR) / "examples" / "shader_gate";
    // README quotes the gate's commands verbatim: every command line of gate.sh is in README.
    {
        const std::string readme = source("README.md"),
                          gate = source("examples/shader_gate/gate.sh");
        std::stringstream lines(gate);
        int commands = 0;
        for (std::string line; std::getline(lines, line);)
            if (line.rfind("\"$PXH\"", 0) == 0) {
                ++commands;
                EXPECT_NE(readme.find(line + "\n"), std::string::npos) << "README lacks: " << line;
            }
        EXPECT_EQ(commands, 3);
    }
    EXPECT_EQ(sh((ex / "gate.sh").string() + " " + PXH_BINARY + " " + ex.string() + " " +
                 (dir / "run").string()),
              0)
        << slurp("out.txt") << slurp("err.txt");
    EXPECT_NE(slurp("out.txt").find("PASS: 0 regression(s)"), std::string::npos);
    fs::create_directories(dir / "worse");
    for (const char* f : {"experiment.toml", "thresholds.toml"})
        fs::copy_file(ex / f, dir / "worse" / f);
    std::string shader = source("examples/shader_gate/my_pom.frag.glsl");
    const std::string interp = "return uv - duv * w;";
    ASSERT_NE(shader.find(interp), std::string::npos);
    shader.replace(shader.find(interp), interp.size(), "return uv;");
    std::ofstream(dir / "worse" / "my_pom.frag.glsl") << shader;
    ASSERT_EQ(pxh("run " + (dir / "worse" / "experiment.toml").string() + " --quiet --out " +
                  (dir / "worse_run").string()),
              0);
    EXPECT_EQ(pxh("check " + (dir / "worse_run").string() + " --thresholds " +
                  (ex / "thresholds.toml").string()),
              1)
        << slurp("out.txt");
    EXPECT_EQ(pxh("compare " + (ex / "baseline").string() + " " + (dir / "worse_run").string() +
                  " --fail-on err_p95=+5%,err_mean=+0.001,fetches_mean=+0"),
              1)
        << slurp("out.txt");
    EXPECT_NE(slurp("out.txt").find("my_pom p_steps=32 [glsl/r32f] on bricks s=0.05 b=1 theta=85"),
              std::string::npos)
        << slurp("out.txt");
}

}  // namespace
