// The parametric marcher (methods/march): set to pxh's own searches it is those methods bit for
// bit; every knob's GLSL twin agrees with the CPU reference; closed forms of the one-fetch forms
// and of the count rules; a preset that fixes the reference plane refuses another bias.
#include "methods/march/march.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "harness/backends/cpu_backend.h"
#include "harness/backends/glsl_backend.h"
#include "harness/core/error.h"
#include "harness/experiment/experiment.h"
#include "harness/metrics/metrics.h"
#include "methods/march/preset.h"
#include "tests/glsl_agreement.h"
#include "tests/test_util.h"

namespace pxh {

// A test-only preset whose engine fixes b = 0.5 (registered in pxh_tests only).
const MarchPresetRow kTestHalfBiasPreset{
    .name = "test_half_bias",
    .citation = "test only",
    .summary = "offset with b = 0.5",
    .knobs = {.search = MarchConfig::Offset, .offset_form = MarchConfig::OffSoft},
    .order = 900,
    .required_bias = 0.5,
    .bias_reason = "the test engine centres heights on 0.5",
};
PXH_REGISTER_PRESET(kTestHalfBiasPreset);

namespace {

using test::method;

template <typename T>
void expect_same(const char* pxh_name, const GivenParams& pxh_params, const GivenParams& knobs) {
    const HeightField hf = test::random_field(96, 96, 31, 0.0f, 1.0f);
    const auto P = test::random_points(3000, 7);
    for (double theta : {0.0, 30.0, 63.0, 84.0})
        for (double b : {1.0, 0.6}) {
            const auto sc = test::make_scene(hf, 0.07, b, theta, 37);
            const auto ref = test::run_method<T>(
                method(pxh_name), test::params_for(method(pxh_name), pxh_params), sc, hf, P);
            std::vector<int> f_ref, f_m;
            (void)test::run_method<T>(method(pxh_name),
                                      test::params_for(method(pxh_name), pxh_params), sc, hf, P,
                                      &f_ref);
            const auto got = test::run_method<T>(
                method("march"), test::params_for(method("march"), knobs), sc, hf, P, &f_m);
            for (size_t i = 0; i < P.size(); ++i) {
                ASSERT_EQ(ref[i].x, got[i].x) << pxh_name << " theta=" << theta << " i=" << i;
                ASSERT_EQ(ref[i].y, got[i].y) << pxh_name << " theta=" << theta << " i=" << i;
                ASSERT_EQ(f_ref[i], f_m[i]) << pxh_name << " fetches, i=" << i;
            }
        }
}

TEST(March, EqualsPxhSearchesBitForBit) {
    for (int prec = 0; prec < 2; ++prec) {
        auto check = [&](const char* n, const GivenParams& a, const GivenParams& b) {
            if (prec == 0) expect_same<float>(n, a, b);
            else expect_same<double>(n, a, b);
        };
        check("steep", {{"layers", 24}}, {{"count", "fixed"}, {"layers", 24}, {"refine", "none"}});
        check("steep", {{"layers_min", 4}, {"layers_max", 40}},
              {{"layers_min", 4}, {"layers_max", 40}, {"refine", "none"}});
        check("pom", {{"layers_min", 8}, {"layers_max", 32}}, {});
        check("pom", {{"layers", 13}}, {{"count", "fixed"}, {"layers", 13}});
        check("relief", {{"layers", 10}, {"binary_steps", 6}},
              {{"count", "fixed"}, {"layers", 10}, {"refine", "bisect"}, {"iterations", 6}});
    }
}

// One fetch: the four forms' closed forms on a flat field at height h.
TEST(March, OffsetFormsClosedForms) {
    HeightField hf(8, 8);
    const float h = 0.3f;
    std::fill(hf.texels.begin(), hf.texels.end(), h);
    const auto P = test::random_points(50, 3);
    const double s = 0.05, b = 0.6;
    for (double theta : {10.0, 50.0, 80.0}) {
        const auto sc = test::make_scene(hf, s, b, theta, 120);
        const double z = s * (double(h) - b);
        const Vec3d V = sc.V;
        const std::pair<const char*, double> forms[] = {
            {"tan", 1 / V.z}, {"sin", 1.0}, {"soft", 1 / (V.z + 0.3)}, {"sincos", V.z}};
        for (const auto& [form, f] : forms) {
            const auto uv =
                test::run_method<double>(method("march"),
                                         test::params_for(method("march"), {{"search", "offset"},
                                                                            {"offset_form", form},
                                                                            {"offset_soften", 0.3},
                                                                            {"mirror_v", true}}),
                                         sc, hf, P);
            for (size_t i = 0; i < P.size(); ++i) {
                EXPECT_NEAR(uv[i].x, P[i].x + V.x * z * f, 1e-12) << form;
                EXPECT_NEAR(uv[i].y, P[i].y - V.y * z * f, 1e-12) << form << " (v mirrored)";
            }
        }
    }
}

// The count rules at given V.z, against the engines' formulas written out.
TEST(March, LayerCountRules) {
    auto n_of = [](const char* rule, double lo, double hi, double theta, double s) {
        MarchConfig c;
        const char* names[] = {"fixed",       "mix",          "mix_trunc",
                               "mix_negated", "angle_scaled", "mix_scaled"};
        for (int i = 0; i < 6; ++i)
            if (std::string(names[i]) == rule) c.count = i;
        c.layers_min = lo;
        c.layers_max = hi;
        Scene<double> sc;
        sc.scale = s;
        sc.V = view_vector(theta, 0);
        return march_layer_count(c, sc);
    };
    const double vz = std::cos(60 * M_PI / 180);
    EXPECT_NEAR(n_of("mix", 8, 32, 60, 0.05), 32 - 24 * vz, 1e-12);
    EXPECT_EQ(n_of("mix_trunc", 8, 50, 70, 0.05), 35.0);  // int(50 - 42 cos 70) = int(35.6)
    EXPECT_NEAR(n_of("mix_negated", 4, 15, 60, 0.05), 15 + 11 * vz, 1e-12);  // Babylon
    EXPECT_NEAR(n_of("mix_scaled", 6, 1000, 60, 0.015), 6 * vz + 15 * (1 - vz), 1e-12);
    // HDRP: the angle of normalize(s V.xy, V.z) is atan(s tan(theta)); 5..15 samples.
    for (double theta : {0.0, 60.0, 85.0, 89.0}) {
        const double ang = std::atan(0.02 * std::tan(theta * M_PI / 180));
        const double expect = std::trunc(5 + 10 * std::min(1.0, ang / (M_PI / 2)));
        EXPECT_NEAR(n_of("angle_scaled", 5, 15, theta, 0.02), expect, 1.0) << theta;
    }
    EXPECT_EQ(n_of("angle_scaled", 5, 15, 60, 0.02), 5.0);
}

// A search that never hits: on_miss decides (last: uv_kmax; next: one layer further).
TEST(March, OnMissAndCaps) {
    HeightField hf(4, 4);
    std::fill(hf.texels.begin(), hf.texels.end(), 0.0f);  // h = 0: the slab's bottom
    const auto sc = test::make_scene(hf, 0.1, 1.0, 45, 0);
    const std::vector<Vec2d> P = {{0.3, 0.4}};
    const Vec2d dir = sc.V.xy() * (1 / sc.V.z);
    auto run = [&](const GivenParams& g) {
        return test::run_method<double>(method("march"), test::params_for(method("march"), g), sc,
                                        hf, P)[0];
    };
    // lt never hits at the bottom (g = 0 at k = n): 10 layers, last = uv_10 (full depth).
    const GivenParams base = {
        {"count", "fixed"}, {"layers", 10}, {"compare", "lt"}, {"refine", "none"}};
    GivenParams last = base, next = base, capped = base;
    next["on_miss"] = "next";
    capped["max_steps"] = 4;
    EXPECT_NEAR(run(last).x, P[0].x - dir.x * 0.1, 1e-12);
    EXPECT_NEAR(run(next).x, P[0].x - dir.x * 0.11, 1e-12);
    EXPECT_NEAR(run(capped).x, P[0].x - dir.x * 0.04, 1e-12);
}

// Every knob on the GLSL backend against the CPU float reference.
TEST(March, GlslTwinAgreesOnEveryKnob) {
    static GlslBackend gl(GlslOptions{"", 0});
    const MethodInfo& m = method("march");
    const GivenParams settings[] = {
        {{"search", "offset"}, {"offset_form", "soft"}},
        {{"search", "offset"}, {"offset_form", "sincos"}, {"mirror_v", true}},
        {{"count", "mix_trunc"},
         {"layers_min", 8},
         {"layers_max", 50},
         {"first", "top"},
         {"compare", "lt"},
         {"clamp_weight", false}},
        {{"count", "mix_negated"},
         {"layers_min", 4},
         {"layers_max", 15},
         {"max_steps", 14},
         {"on_miss", "next"},
         {"compare", "lt"},
         {"clamp_weight", false}},
        {{"count", "fixed"},
         {"layers", 32},
         {"step", "sin"},
         {"lag", true},
         {"compare", "lt"},
         {"refetch", true},
         {"clamp_weight", false},
         {"on_miss", "refine"}},
        {{"count", "mix_scaled"},
         {"layers_min", 6},
         {"layers_max", 1000},
         {"first", "bottom"},
         {"compare", "lt"},
         {"clamp_weight", false},
         {"on_miss", "refine"}},
        {{"count", "angle_scaled"},
         {"layers_min", 5},
         {"layers_max", 15},
         {"compare", "lt"},
         {"extra_layers", 1},
         {"on_miss", "refine"},
         {"refine", "secant"},
         {"iterations", 3}},
        {{"count", "fixed"},
         {"layers", 16},
         {"refine", "bisect"},
         {"iterations", 15},
         {"probe_last", true},
         {"tie", "stay"}},
        {{"layers_min", 1}, {"layers_max", 16}, {"refine", "bisect"}, {"refine_at_k0", true}},
        {{"count", "fixed"}, {"layers", 16}, {"refine", "contact"}},
    };
    const HeightField hf = test::random_field(64, 64, 5, 0.0f, 1.0f);
    const int N = 48;
    for (const auto& g : settings) {
        const MethodSpec spec{&m, test::params_for(m, g)};
        for (double theta : {20.0, 70.0}) {
            const Scene<double> sc{0.06, 1.0, view_vector(theta, 35), hf.width, hf.height};
            const test::GlslCpuDiff d = test::glsl_vs_cpu(gl, spec, sc, hf, N);
            EXPECT_LE(d.far, d.samples / 1000) << spec.params.canonical() << " theta=" << theta;
            EXPECT_LE(d.fetch_off, d.samples / 1000) << spec.params.canonical();
        }
    }
}

TEST(March, PresetRefusesAnotherBias) {
    const std::string head =
        "[views]\ntheta_deg = [0, 30]\n[[heightfields]]\ngenerator = "
        "\"flat\"\nsize = 8\nbias = ";
    const std::string tail = "\n[[methods]]\nname = \"test_half_bias\"\n";
    EXPECT_EQ(parse_experiment(head + "0.5" + tail, "e.toml").methods.size(), 1u);
    EXPECT_EQ(test::input_error([&] { parse_experiment(head + "1" + tail, "e.toml"); }),
              "e.toml:8: method 'test_half_bias' needs bias = 0.5 (the test engine centres "
              "heights on 0.5); heightfield 'flat' has bias = 1");
}

// `heightfields` in a [[methods]] entry: the preset runs only on the entries named there, so
// one experiment holds fields at several biases; the bias check and the row estimate follow.
TEST(March, MethodRestrictedToNamedFields) {
    const std::string text =
        "[views]\ntheta_deg = [0, 30, 60]\n"
        "[[heightfields]]\nname = \"half\"\ngenerator = \"flat\"\nsize = 8\nbias = 0.5\n"
        "[[heightfields]]\nname = \"top\"\ngenerator = \"flat\"\nsize = 8\nbias = 1\n"
        "[[methods]]\nname = \"test_half_bias\"\nheightfields = [\"half\"]\n"
        "[[methods]]\nname = \"pom\"\n";
    const Experiment ex = parse_experiment(text, "e.toml");
    ASSERT_EQ(ex.methods.size(), 2u);
    EXPECT_TRUE(ex.methods[0].runs_on("half"));
    EXPECT_FALSE(ex.methods[0].runs_on("top"));
    EXPECT_TRUE(ex.methods[1].runs_on("top"));
    // half: 2 methods x 3 views; top: 1 method x 3 views; one CPU float variant each.
    EXPECT_EQ(estimate_run(ex, {}).rows, 9u);
    std::string bad = text;
    bad.replace(bad.find("[\"half\"]"), 8, "[\"hlaf\"]");
    EXPECT_EQ(test::input_error([&] { parse_experiment(bad, "e.toml"); }),
              "e.toml:15: method 'test_half_bias': no heightfield named 'hlaf'");
}

}  // namespace
}  // namespace pxh

namespace pxh {
namespace {

// pxh run --only: a subset by any key, "any of" with |, and a key that matches nothing named.
TEST(RunOnly, KeepsTheMatchingEntriesAndViews) {
    const std::string text =
        "backends = [\"cpu\", \"glsl\"]\n[views]\ntheta_deg = [0, 30, 60]\nphi_deg = [0, 45]\n"
        "[[heightfields]]\nname = \"a\"\ngenerator = \"flat\"\nsize = 8\nscale = [0.02, 0.05]\n"
        "[[heightfields]]\nname = \"b\"\ngenerator = \"sine\"\nsize = 8\n"
        "[[methods]]\nname = \"pom\"\nlayers = [8, 16]\n[[methods]]\nname = \"steep\"\n";
    Experiment ex = parse_experiment(text, "e.toml");
    apply_only(ex, "method=pom,heightfield=a,scale=0.05,theta_deg=30|60,backend=glsl");
    ASSERT_EQ(ex.methods.size(), 2u);  // both layer settings of pom
    ASSERT_EQ(ex.heightfields.size(), 1u);
    EXPECT_EQ(ex.heightfields[0].scale, 0.05);
    EXPECT_EQ(ex.theta_deg, (std::vector<double>{30, 60}));
    EXPECT_EQ(ex.phi_deg, (std::vector<double>{0, 45}));
    EXPECT_EQ(ex.backends, (std::vector<std::string>{"glsl"}));
    Experiment ex2 = parse_experiment(text, "e.toml");
    EXPECT_EQ(test::input_error([&] { apply_only(ex2, "heightfield=c"); }),
              "--only: no heightfield matches (the experiment has: a (s=0.02 b=1), a "
              "(s=0.05 b=1), b (s=0.05 b=1))");
    EXPECT_THROW(apply_only(ex2, "color=red"), InputError);
    // The keys it lists are the ones it selects by: samples is an axis a run sets with
    // --samples, refused when given and not offered.
    const std::vector<std::string> keys = only_keys();
    EXPECT_EQ(std::count(keys.begin(), keys.end(), "samples"), 0);
    for (const char* k : {"method", "theta_deg", "distance", "lod"})
        EXPECT_EQ(std::count(keys.begin(), keys.end(), k), 1) << k;
    const std::string unknown = test::input_error([&] { apply_only(ex2, "color=red"); });
    EXPECT_EQ(unknown.find("samples"), std::string::npos) << unknown;
    EXPECT_NE(unknown.find("distance (and distance_min, distance_max)"), std::string::npos)
        << unknown;
    EXPECT_NE(test::input_error([&] { apply_only(ex2, "samples=8"); }).find("not one to select by"),
              std::string::npos);
}

}  // namespace
}  // namespace pxh
