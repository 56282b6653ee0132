// The parser's limits and checks on hostile input: sweeps counted before they are expanded
// (plug-in uniform lists, long lists and relief ranges, fields x views x backends), repeated
// settings, scales and layer counts with their FILE:LINE, and text and path that must be UTF-8.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "harness/core/error.h"
#include "harness/experiment/experiment.h"
#include "tests/cli_util.h"

namespace {

namespace fs = std::filesystem;

// ---- sweeps counted before they are expanded ----

std::string list(int from, int to, double scale = 1) {
    std::string s = "[";
    for (int i = from; i <= to; ++i) s += (i > from ? ", " : "") + pxh::format_number(i * scale);
    return s + "]";
}

// Lines 1-8: name, samples, timing_repeats, [views], theta_deg, one fbm field.
const std::string kHead = pxh::test::ExperimentToml("big").theta("[30, 60]").field("fbm", 16);

// The message of parsing `text` (at `path`), or "" when it parses.
std::string parse_error(const std::string& text, const std::string& path = "/x/big.toml",
                        const pxh::ParseLimits& lim = {}) {
    try {
        pxh::parse_experiment(text, path, lim);
    } catch (const pxh::InputError& e) {
        return e.what();
    }
    return "";
}

TEST(SweepLimits, PluginUniformListsAreCountedBeforeExpansion) {
    const fs::path d = fs::temp_directory_path() / ("pxh_sweep_" + std::to_string(getpid()));
    fs::create_directories(d);
    std::ofstream(d / "plug.glsl") << "vec2 pxh_method(vec2 P) { return P; }\n";
    // A 65 KB entry: two 3000-value uniform lists (9 million settings).
    const std::string text = std::string("backends = [\"glsl\"]\n") + kHead +
                             "[[methods]]\nname = \"plug\"\nshader = \"plug.glsl\"\n"
                             "max_fetches = 4\nuniforms = { p_a = " +
                             list(0, 2999, 0.001) + ", p_b = " + list(0, 2999, 0.5) + " }\n";
    EXPECT_GT(text.size(), 35000u);
    const std::string err = parse_error(text, (d / "big.toml").string());
    fs::remove_all(d);
    EXPECT_NE(err.find("big.toml:10: this [[methods]] entry would write 18000000 rows (3000 p_a "
                       "x 3000 p_b x 1 heightfield(s) x 2 theta x 1 phi x 1 backend variant(s)) "
                       "> --max-rows 1000000"),
              std::string::npos)
        << err;
}

TEST(SweepLimits, ThreeLongListsAndReliefRanges) {
    // Three 1000-value lists: 10^9 settings (std::bad_alloc when expanded).
    std::string err = parse_error(kHead + "[[methods]]\nname = \"march\"\ncount = \"fixed\"\n" +
                                  "layers = " + list(1, 1000) + "\nlayers_min = " + list(1, 1000) +
                                  "\nlayers_max = " + list(1, 1000) + "\n");
    EXPECT_NE(err.find("would write 2000000000 rows (1000 layers x 1000 layers_max x 1000 "
                       "layers_min x 1 heightfield(s) x 2 theta"),
              std::string::npos)
        << err;
    // relief with layers_min and layers_max each 1..4096.
    err = parse_error(kHead + "[[methods]]\nname = \"relief\"\nlayers_min = " + list(1, 4096) +
                      "\nlayers_max = " + list(1, 4096) + "\n");
    EXPECT_NE(err.find("big.toml:9: this [[methods]] entry would write 33554432 rows (4096 "
                       "layers_max x 4096 layers_min x 1 heightfield(s) x 2 theta x 1 phi x 1 "
                       "backend variant(s))"),
              std::string::npos)
        << err;
    // Raising --max-rows leaves the memory the rows need: 33554432 x 1 KiB > 8 GiB.
    pxh::ParseLimits lim;
    lim.max_rows = size_t(1) << 40;
    err = parse_error(kHead + "[[methods]]\nname = \"relief\"\nlayers_min = " + list(1, 4096) +
                          "\nlayers_max = " + list(1, 4096) + "\n",
                      "/x/big.toml", lim);
    EXPECT_NE(err.find("need more than --max-memory 8.0 GiB"), std::string::npos) << err;
}

TEST(SweepLimits, FieldsViewsBackendsAndTheRunningTotal) {
    // A generator swept x scales x biases x views x backend variants, before a method is read.
    const std::string fields = R"(
name = "f"
precision = ["float", "double"]
[views]
theta_deg = { from = 0, to = 89, step = 1 }
phi_deg = { from = 0, to = 359, step = 1 }
[[heightfields]]
generator = "fbm"
size = 16
seed = )" + list(1, 10) + "\nscale = [0.01, 0.02]\n[[methods]]\nname = \"pom\"\n";
    std::string err = parse_error(fields);
    EXPECT_NE(err.find("big.toml:7: this [[heightfields]] entry would write 1296000 rows"),
              std::string::npos)
        << err;
    EXPECT_NE(err.find("1296000 rows (10 seed x 2 scale x 1 bias x 90 theta x 360 phi x 2 "
                       "backend variant(s) x 1 method setting (at least))"),
              std::string::npos)
        << err;
    // --backend glsl (one texture format) instead of the file's two CPU precisions: half, and
    // under the limit; under a lower one, refused with its product.
    pxh::ParseLimits lim;
    lim.backends = {"glsl"};
    EXPECT_EQ(parse_error(fields, "/x/big.toml", lim), "");
    lim.max_rows = 600000;
    err = parse_error(fields, "/x/big.toml", lim);
    EXPECT_NE(err.find("648000 rows (10 seed x 2 scale x 1 bias x 90 theta x 360 phi x 1 "),
              std::string::npos)
        << err;
    // Entries each under the limit, together over it: the entry that crosses it is named.
    std::string many = kHead;
    for (int k = 0; k < 3; ++k)
        many += "[[methods]]\nname = \"pom\"\nlayers_min = " + list(1 + k * 10, 10 + k * 10) +
                "\nlayers_max = " + list(100, 119) + "\n";
    lim = {};
    lim.max_rows = 1000;
    err = parse_error(many, "/x/big.toml", lim);
    EXPECT_NE(err.find("big.toml:17: this [[methods]] entry would write 400 rows (20 layers_max "
                       "x 10 layers_min"),
              std::string::npos)
        << err;
    EXPECT_NE(err.find("(800 more from the entries before it) > --max-rows 1000"),
              std::string::npos)
        << err;
    // An overflowing product saturates (never wraps to a small number).
    std::string huge = kHead + "[[methods]]\nname = \"march\"\ncount = \"fixed\"\n";
    for (const char* k : {"layers", "layers_min", "layers_max", "iterations", "tolerance"})
        huge +=
            std::string(k) + " = " + list(1, 4096, std::string(k) == "tolerance" ? 1e-4 : 1) + "\n";
    huge += "max_steps = " + list(0, 4096) + "\n";
    err = parse_error(huge);
    EXPECT_NE(err.find("would write more than 2^64 rows"), std::string::npos) << err;
    // Just under the limit: parsed, every setting there.
    lim.max_rows = 2 * 40 * 50;
    const auto ex =
        pxh::parse_experiment(kHead + "[[methods]]\nname = \"pom\"\nlayers_min = " + list(1, 40) +
                                  "\nlayers_max = " + list(51, 100) + "\n",
                              "/x/big.toml", lim);
    EXPECT_EQ(ex.methods.size(), 2000u);
    lim.max_rows -= 1;
    EXPECT_NE(parse_error(kHead + "[[methods]]\nname = \"pom\"\nlayers_min = " + list(1, 40) +
                              "\nlayers_max = " + list(51, 100) + "\n",
                          "/x/big.toml", lim)
                  .find("4000 rows"),
              std::string::npos);
}

// ---- repeated settings, scales, layer counts, UTF-8 ----

TEST(ParseChecks, RepeatedSettingIsOneRowAndOneWarning) {
    const std::string text = R"(
[views]
theta_deg = [30]
[[heightfields]]
generator = "fbm"
size = 16
name = "a"
[[heightfields]]
generator = "fbm"
size = 32
name = "b"
[[methods]]
name = "pom"
layers_min = [8, 8, 9, 8]
[[methods]]
name = "pom"
layers_min = 9
layers_max = 32
heightfields = ["b"]
[[methods]]
name = "parallax"
heightfields = ["a"]
[[methods]]
name = "parallax"
heightfields = ["b"]
[[methods]]
name = "parallax"
heightfields = ["a"]
)";
    const auto ex = pxh::parse_experiment(text, "/x/rep.toml");
    ASSERT_EQ(ex.methods.size(), 3u);  // pom min 8, pom min 9, parallax
    EXPECT_EQ(ex.methods[0].params.canonical(), "layers=adaptive;layers_min=8;layers_max=32");
    EXPECT_EQ(ex.methods[1].params.canonical(), "layers=adaptive;layers_min=9;layers_max=32");
    EXPECT_TRUE(ex.methods[1].heightfields.empty());  // every field already
    EXPECT_EQ(ex.methods[2].heightfields, (std::vector<std::string>{"a", "b"}));
    std::vector<std::string> repeats;
    for (const auto& w : ex.warnings)
        if (w.find("repeat one given before") != std::string::npos) repeats.push_back(w);
    ASSERT_EQ(repeats.size(), 3u);  // one per entry whose rows repeat (not parallax on b)
    EXPECT_NE(repeats[0].find("/x/rep.toml:12: 2 setting(s) of method 'pom' repeat one given "
                              "before (first: [layers=adaptive;layers_min=8;layers_max=32], as "
                              "at /x/rep.toml:12)"),
              std::string::npos)
        << repeats[0];
    EXPECT_NE(repeats[1].find("/x/rep.toml:15: 1 setting(s)"), std::string::npos) << repeats[1];
    EXPECT_EQ(repeats[2].rfind("/x/rep.toml:26: 1 setting(s) of method 'parallax'", 0), 0u)
        << repeats[2];
    EXPECT_NE(repeats[2].find("as at /x/rep.toml:20"), std::string::npos) << repeats[2];
    // The rows: one per setting, field and view.
    EXPECT_EQ(pxh::estimate_run(ex, {}).rows, 2u + 2u + 2u);
}

TEST(ParseChecks, ScaleAndLayerCountsWithFileAndLine) {
    const std::string base = R"(
[views]
theta_deg = [0, 30]
[[heightfields]]
generator = "fbm"
size = 16
scale = SCALE
[[methods]]
name = "march"
count = "COUNT"
layers_min = MIN
)";
    auto with = [&](const std::string& scale, const std::string& count, const std::string& min) {
        std::string t = base;
        t.replace(t.find("SCALE"), 5, scale);
        t.replace(t.find("COUNT"), 5, count);
        t.replace(t.find("MIN"), 3, min);
        return parse_error(t, "/x/s.toml");
    };
    EXPECT_EQ(with("0.05", "mix_scaled", "1"), "");
    EXPECT_EQ(with("1e-6", "mix", "8"), "");
    for (const std::string s : {"1e-320", "5e-324", "9.9e-7"}) {
        const std::string err = with(s, "mix", "8");
        EXPECT_EQ(err.rfind("/x/s.toml:7: scale = ", 0), 0u) << err;
        EXPECT_NE(err.find("is below 1e-06"), std::string::npos) << err;
    }
    std::string err = with("0.05", "mix_scaled", "0");
    EXPECT_EQ(err.rfind("/x/s.toml:8: ", 0), 0u) << err;
    EXPECT_NE(err.find("count = \"mix_scaled\" needs layers_min >= 1 (got 0)"), std::string::npos)
        << err;
    err = with("0.05", "mix_scaled", "0.5");
    EXPECT_NE(err.find("needs layers_min >= 1 (got 0.5)"), std::string::npos) << err;
}

TEST(ParseChecks, TextAndPathMustBeUtf8) {
    const std::string ok =
        "[views]\ntheta_deg = [30]\n[[heightfields]]\ngenerator = \"fbm\"\n"
        "size = 16\n[[methods]]\nname = \"pom\"\n";
    EXPECT_EQ(parse_error("# caf\xc3\xa9 \xe2\x82\xac \xf0\x9d\x84\x9e\n" + ok, "/x/u.toml"), "");
    EXPECT_EQ(parse_error(ok + "# caf\xe9\n", "/x/u.toml"),
              "/x/u.toml:8: column 6: byte 0xE9 is not UTF-8 (experiment files are UTF-8 text: "
              "re-save it as UTF-8)");
    EXPECT_NE(parse_error(ok, "/x/\xe9.toml").find("the experiment file's name is not UTF-8"),
              std::string::npos);
}

}  // namespace
