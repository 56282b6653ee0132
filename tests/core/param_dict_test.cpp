// The one parameter reader (harness/core/param_dict.h): typed getters with defaults, every key
// at its FILE:LINE, a key nobody read an error there; the same reader, and the same rule for
// integers beyond 2^53, under the experiment (top level, [[methods]], [views], a backend's
// keys) and the thresholds file.
#include "harness/core/param_dict.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "harness/core/error.h"
#include "harness/experiment/experiment.h"
#include "harness/report/report.h"
#include "tests/cli_util.h"
#include "tests/test_util.h"

namespace pxh {
namespace {

using test::input_error;

TEST(ParamsReader, TypedGettersKeepDefaultsAndLines) {
    const ParamDict d = ParamDict::parse(
        "a = 1.5\nn = 7\ns = \"x\"\nb = true\nlist = [1, 2.5]\n[sub]\nk = 3\n", "f.toml", "top");
    EXPECT_EQ(d.number("a", 0), 1.5);
    EXPECT_EQ(d.number("n", 0), 7.0);  // an integer where a number is read
    EXPECT_EQ(d.number("missing", 4.25), 4.25);
    EXPECT_EQ(d.integer("n", 0, 1, 10), 7);
    EXPECT_EQ(d.string("s", ""), "x");
    EXPECT_TRUE(d.boolean("b", false));
    EXPECT_EQ(d.numbers("list", {}), (std::vector<double>{1, 2.5}));
    EXPECT_EQ(d.numbers("missing", {9}), (std::vector<double>{9}));
    EXPECT_EQ(d.where("list"), "f.toml:5");
    const auto sub = d.table("sub", "[sub]");
    ASSERT_TRUE(sub);
    EXPECT_EQ(sub->where(), "f.toml:6");
    EXPECT_EQ(sub->integer("k", 0, 0, 5), 3);
    EXPECT_EQ(sub->where("k"), "f.toml:7");
    EXPECT_EQ(input_error([&] { d.integer("n", 0, 1, 5); }), "f.toml:2: 'n' = 7 is outside [1, 5]");
    EXPECT_EQ(input_error([&] { d.integer("a", 0, 1, 5); }), "f.toml:1: 'a' must be an integer");
    EXPECT_EQ(input_error([&] { d.number("s", 0); }), "f.toml:3: 's' must be a number");
    EXPECT_EQ(input_error([&] { d.boolean("n", false); }), "f.toml:2: 'n' must be true or false");
    // Everything was read (sub's own keys by sub): nothing to report.
    EXPECT_EQ(input_error([&] { d.report_unused(); }), "");
    EXPECT_EQ(input_error([&] { sub->report_unused(); }), "");
}

TEST(ParamsReader, UnreadKeyNamesItsLineAndWhatWasAsked) {
    const ParamDict d = ParamDict::parse("alpha = 1\n\nbeta = 2\ngamma = 3\n", "g.toml", "[t]");
    d.number("alpha", 0);
    d.has("delta");  // asked for, absent: still a key this consumer knows
    d.number("gamma", 0);
    EXPECT_EQ(input_error([&] { d.report_unused(); }),
              "g.toml:3: unknown key 'beta' in [t] (known: alpha, delta, gamma)");
    // has() asks but does not read.
    d.has("beta");
    EXPECT_NE(input_error([&] { d.report_unused(); }).find("unknown key 'beta'"),
              std::string::npos);
    EXPECT_EQ(input_error([&] {
                  d.report_unused([](const std::string& k, const std::string& known) {
                      return k + " | " + known;
                  });
              }),
              "g.toml:3: beta | alpha, delta, gamma, beta");
    // A syntax error names the line.
    EXPECT_NE(input_error([] {
                  ParamDict::parse("a = 1\nb = [\n", "h.toml", "x");
              }).find("h.toml:2: TOML syntax error"),
              std::string::npos);
}

// One rule: an integer read as a number is the nearest double; 2^53 + 1 has none of its own
// and reads as 2^53 (as the float literal 9007199254740993.0 would).
TEST(ParamsReader, IntegersBeyond2To53ReadAsTheNearestDouble) {
    const ParamDict d =
        ParamDict::parse("big = 9007199254740993\nlist = [9007199254740993, 3]\n", "b.toml", "t");
    EXPECT_EQ(d.number("big", 0), 9007199254740992.0);
    EXPECT_EQ(d.numbers("list", {}), (std::vector<double>{9007199254740992.0, 3}));
    const auto e = d.elements("big");
    ASSERT_EQ(e.size(), 1u);
    EXPECT_TRUE(e[0].integer);
    EXPECT_EQ(e[0].value->number(), 9007199254740992.0);
    EXPECT_EQ(input_error([&] { d.integer("big", 0, 0, 2147483647); }),
              "b.toml:1: 'big' = 9007199254740993 is outside [0, 2147483647]");
}

// Lines: 1 name, 2 samples, 3 timing_repeats, 4 [views], 5 theta_deg, 6-8 the field, 9-11 the
// method.
const std::string kExperiment =
    test::ExperimentToml("t").theta("[0, 30]").field("bricks", 16).method("pom", "layers = 8");

std::string experiment_error(const std::string& text) {
    return input_error([&] { parse_experiment(text, "e.toml"); });
}

std::string with_line(std::string text, const std::string& after, const std::string& line) {
    const size_t at = text.find(after);
    EXPECT_NE(at, std::string::npos) << after;
    return text.insert(at + after.size(), line + "\n");
}

TEST(ParamsUnread, ExperimentTopLevelKeyAtItsLine) {
    EXPECT_EQ(experiment_error(with_line(kExperiment, "samples = 8\n", "sampels = 8")),
              "e.toml:3: unknown key 'sampels' (did you mean 'samples'?) in the experiment (known: "
              "name, description, "
              "samples, backends, sweep_dt_deg, maps, exclude_filled, ground_truth, truth_check, "
              "timing_repeats, precision, gl, gl_time_limit_s, texture_format, views, light, "
              "render, shading, heightfields, methods)");
}

TEST(ParamsUnread, MethodEntryKeyAtItsLine) {
    EXPECT_EQ(
        experiment_error(with_line(kExperiment, "layers = 8\n", "layerz = 4")),
        "e.toml:12: unknown parameter 'layerz' (did you mean 'layers'?) for method 'pom' (known: "
        "layers, "
        "layers_min, layers_max)");
}

TEST(ParamsUnread, ViewsKeyTheOrthographicCameraDoesNotRead) {
    EXPECT_EQ(experiment_error(with_line(kExperiment, "theta_deg = [0, 30]\n", "fov_deg = 60")),
              "e.toml:6: unknown key 'fov_deg' in [views] (known: theta_deg, phi_deg, camera, "
              "cut; camera 'orthographic' reads no keys of its own)");
    // Its own keys go through the same reader: the camera is made from [views].
    const Experiment ex = parse_experiment(with_line(kExperiment, "theta_deg = [0, 30]\n",
                                                     "camera = "
                                                     "\"orthographic\""),
                                           "e.toml");
    EXPECT_EQ(ex.camera_params.where("camera"), "e.toml:6");
}

TEST(ParamsUnread, MisspeltBackendKeyAtItsLine) {
    const std::string err =
        experiment_error(with_line(kExperiment, "samples = 8\n", "texture_formats = \"r16\""));
    EXPECT_EQ(err.rfind("e.toml:3: unknown key 'texture_formats' (did you mean 'texture_format'?) "
                        "in the experiment (known: ",
                        0),
              0u)
        << err;
    // The backends read their own keys: the right spelling is among those asked for.
    EXPECT_NE(err.find(", texture_format,"), std::string::npos) << err;
    // Spelt right, the GLSL backend reads it whichever backends run (pxh run --backend).
    const Experiment ex = parse_experiment(
        with_line(kExperiment, "samples = 8\n", "texture_format = [\"r16\", \"r8\"]"), "e.toml");
    EXPECT_EQ(ex.backend.texture_formats, (std::vector<std::string>{"r16", "r8"}));
    EXPECT_EQ(backend_settings(ex).texture_formats, ex.backend.texture_formats);
}

TEST(ParamsUnread, BigIntegerRuleInTheExperiment) {
    // Read as the number 2^53 (the same rule as the thresholds file), not refused as no number.
    EXPECT_EQ(experiment_error(
                  with_line(kExperiment, "samples = 8\n", "gl_time_limit_s = 9007199254740993")),
              "e.toml:3: gl_time_limit_s = 9.007199255e+15 is outside (0, 86400] (seconds per "
              "row)");
}

class ParamsThresholds : public test::CliTest {
  protected:
    std::string results() {
        const auto res = dir / "res";
        std::filesystem::create_directories(res);
        std::ofstream(res / "results.csv", std::ios::binary)
            << "method,params,heightfield,scale,bias,backend,precision,texture_format,"
               "theta_deg,phi_deg,err_p95,status,error\n"
               "pom,layers=8,bricks,0.05,1,cpu,float,,0,0,0.25,ok,\n";
        return res.string();
    }
    std::pair<int, std::string> check(const std::string& limits) {
        const std::string file = write("limits.toml", limits);
        const std::string res = results();
        int rc = -1;
        testing::internal::CaptureStdout();
        try {
            rc = run_check(res, file);
        } catch (...) {
            testing::internal::GetCapturedStdout();
            throw;
        }
        return {rc, testing::internal::GetCapturedStdout()};
    }
};

TEST_F(ParamsThresholds, UnreadKeyAtItsLine) {
    const std::string err = input_error([&] {
        check(
            "[[limit]]\ncolumn = \"err_p95\"\nmax = 1\n\n[[limit]]\ncolumn = \"err_p95\"\n"
            "mx = 1\n");
    });
    EXPECT_EQ(err.rfind((dir / "limits.toml").string() +
                            ":7: unknown key 'mx' (did you mean 'max'?) in [[limit]] (keys: "
                            "column, min, max, ",
                        0),
              0u)
        << err;
}

TEST_F(ParamsThresholds, UnreadTopLevelKeyAtItsLine) {
    EXPECT_EQ(
        input_error([&] { check("\nlimitz = 2\n[[limit]]\ncolumn = \"err_p95\"\nmax = 1\n"); }),
        (dir / "limits.toml").string() +
            ":2: unknown key 'limitz' (did you mean 'limit'?) (a thresholds file holds [[limit]] "
            "tables)");
}

TEST_F(ParamsThresholds, BigIntegerRuleInTheThresholds) {
    // 2^53 + 1 is the number 2^53, as in the experiment: a limit, not a type error.
    const auto [rc, out] = check("[[limit]]\ncolumn = \"err_p95\"\nmin = 9007199254740993\n");
    EXPECT_EQ(rc, 1);
    EXPECT_NE(out.find(">= 9.007199255e+15"), std::string::npos) << out;
}

}  // namespace
}  // namespace pxh
