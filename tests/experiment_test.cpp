// Experiment files: what parses, and every bad input named with file and line.
#include "harness/experiment.h"

#include <gtest/gtest.h>

#include "harness/error.h"

namespace pxh {
namespace {

const char* kGood = R"(
name = "t"
samples = 16
[views]
theta_deg = { from = 0, to = 80, step = 20 }
phi_deg = [0, 90]
[[heightfields]]
generator = "bricks"
size = 32
rows = [2, 4]
scale = [0.02, 0.05]
bias = 1.0
[[methods]]
name = "pom"
layers = [8, 16, 32]
[[methods]]
name = "relief"
layers_min = 8
layers_max = 32
)";

TEST(Experiment, ParsesAndExpandsSweeps) {
    const Experiment ex = parse_experiment(kGood, "good.toml");
    EXPECT_EQ(ex.name, "t");
    EXPECT_EQ(ex.samples, 16);
    EXPECT_EQ(ex.theta_deg, (std::vector<double>{0, 20, 40, 60, 80}));
    EXPECT_EQ(ex.phi_deg, (std::vector<double>{0, 90}));
    ASSERT_EQ(ex.heightfields.size(), 4u);  // rows x scale
    EXPECT_EQ(ex.heightfields[0].name, "bricks[rows=2;cols=2;mortar=0.1;bevel=0.01;seed=1]");
    EXPECT_DOUBLE_EQ(ex.heightfields[1].scale, 0.05);
    ASSERT_EQ(ex.methods.size(), 4u);  // 3 pom + 1 relief
    EXPECT_EQ(ex.methods[2].params.canonical(), "layers=32");
    EXPECT_EQ(ex.methods[3].params.canonical(), "layers_min=8;layers_max=32;binary_steps=5");
}

std::string error_of(const std::string& text) {
    try {
        parse_experiment(text, "bad.toml");
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

std::string replace(std::string s, const std::string& from, const std::string& to) {
    const auto pos = s.find(from);
    EXPECT_NE(pos, std::string::npos) << from;
    return s.replace(pos, from.size(), to);
}

TEST(Experiment, BadInputsNameFileLineAndProblem) {
    struct Case { std::string from, to, expect; };
    const Case cases[] = {
        {"samples = 16", "samples = 0", "bad.toml:3: 'samples' = 0 is outside [1, 8192]"},
        {"samples = 16", "sample = 16", "bad.toml:3: unknown key 'sample' in the experiment"},
        {"name = \"pom\"", "name = \"pomm\"", "bad.toml:14: unknown method 'pomm'"},
        {"layers = [8, 16, 32]", "layer = 8", "bad.toml:15: unknown parameter 'layer' for method 'pom'"},
        {"layers = [8, 16, 32]", "layers = 0", "parameter 'layers' = 0 is outside [1, 4096]"},
        {"generator = \"bricks\"", "generator = \"brick\"", "bad.toml:8: unknown generator 'brick'"},
        {"rows = [2, 4]", "rowz = 2", "unknown key 'rowz' in [[heightfields]]"},
        {"to = 80, step = 20", "to = 90, step = 30", "theta_deg = 90 is impossible"},
        {"theta_deg = { from = 0, to = 80, step = 20 }", "theta_deg = [-5]", "theta_deg = -5 is impossible"},
        {"scale = [0.02, 0.05]", "scale = 0", "bad.toml:11: scale must be > 0"},
        {"bias = 1.0", "bias = 1.5", "bad.toml:12: bias must lie in [0, 1]"},
        {"layers_max = 32", "layers_max = 32\nlayers = 4", "give either 'layers'"},
        {"samples = 16", "samples = [", "TOML syntax error"},
        {"samples = 16", "samples = 16\nground_truth = \"embre\"", "unknown ground_truth 'embre'"},
        {"samples = 16", "samples = 16\nbackends = [\"gpu\"]", "unknown backend 'gpu'"},
        {"samples = 16", "samples = 16\ntexture_format = \"r4\"", "unknown texture_format 'r4'"},
    };
    for (const auto& c : cases) {
        const std::string err = error_of(replace(kGood, c.from, c.to));
        EXPECT_NE(err.find(c.expect), std::string::npos) << "got: " << err << "\nwanted: " << c.expect;
    }
    EXPECT_NE(error_of("[views]\ntheta_deg=[0]\n").find("no [[heightfields]]"), std::string::npos);
    EXPECT_NE(error_of("samples = 4\n").find("missing [views]"), std::string::npos);
}

TEST(Experiment, MissingFileIsNamed) {
    try {
        load_experiment("/nonexistent/x.toml");
        FAIL();
    } catch (const InputError& e) {
        EXPECT_STREQ(e.what(), "/nonexistent/x.toml: no such file");
    }
}

}  // namespace
}  // namespace pxh
