// Godot 4, Bevy and O3DE parallax: the literal transcriptions of
// tests/engines/literal_godot_bevy_o3de.h against closed forms on flat fields, their documented
// defects pinned with numbers, and agreement of each preset (methods/march/presets/godot.cpp,
// bevy.cpp, o3de.cpp, CPU float) with its literal on random fields, points and views.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include "harness/backends/cpu_backend.h"
#include "harness/backends/glsl_backend.h"
#include "harness/core/error.h"
#include "harness/experiment/experiment.h"
#include "harness/metrics/metrics.h"
#include "methods/method.h"
#include "tests/engines/literal_godot_bevy_o3de.h"
#include "tests/glsl_agreement.h"
#include "tests/methods/engine_checks.h"
#include "tests/test_util.h"

namespace pxh {
namespace {

using literal::EngineResult;
using literal::O3deQuality;

using test::expect_offset;
using test::layer_index;
const auto view = &test::engine_view;

const Vec2<float>& kP = test::kEngineP;
const auto& kAngles = test::kEngineAngles;

// ---- Godot 4 (heightmap_scale 5 -> s = 0.05; depth = 1 - h; b = 1) ---------------------------

double godot_n(Vec3<float> V) { return double(32.0f * (1.0f - V.z) + 8.0f * V.z); }

TEST(Godot, ParallaxIsOffsetLimitingWithBiasOne) {
    const float s = 0.05f, h = 0.3f;
    const HeightField hf = test::flat_field(16, 16, h);
    for (const auto& a : kAngles) {
        const Vec3<float> V = view(a[0], a[1]);
        const EngineResult r = literal::godot_parallax(hf, s, V, kP);
        expect_offset(r, kP, s * (h - 1) * V.x, s * (h - 1) * V.y, 1e-7, "godot_parallax");
        EXPECT_EQ(r.fetches, 1);
        // heightmap_flip_binormal mirrors v, heightmap_flip_tangent mirrors u.
        expect_offset(literal::godot_parallax(hf, s, V, kP, false, true), kP, s * (h - 1) * V.x,
                      -s * (h - 1) * V.y, 1e-7, "flip_binormal");
        expect_offset(literal::godot_parallax(hf, s, V, kP, true, false), kP, -s * (h - 1) * V.x,
                      s * (h - 1) * V.y, 1e-7, "flip_tangent");
    }
}

TEST(Godot, DeepOnAFlatFieldLandsAtTheSinThetaDepthAndRefetchesThePreviousLayer) {
    // No division by view_dir.z: the "hit" on a flat field is P + s (h - 1) V.xy, the true hit
    // of a relief of depth s V.z (shallower than s at oblique views).
    const float s = 0.05f, h = 0.3f;
    const HeightField hf = test::flat_field(16, 16, h);
    const double angles[][2] = {{10, 0}, {33, 130}, {58, 250}, {80, 315}};  // 60: n = 20, a tie
    for (const auto& a : angles) {
        const Vec3<float> V = view(a[0], a[1]);
        const double n = godot_n(V), x = 0.7 * n;
        ASSERT_GT(std::abs(x - std::round(x)), 0.02) << "test angle too close to a layer tie";
        const EngineResult r = literal::godot_deep(hf, s, V, kP);
        expect_offset(r, kP, s * (h - 1) * V.x, s * (h - 1) * V.y, 2e-6, "godot_deep");
        const double exact_tan = s * (1 - h) * std::hypot(V.x, V.y) / V.z;
        if (a[0] >= 33) {  // the defect in uv units: the true hit lies 1/V.z times farther
            EXPECT_GT(exact_tan - std::hypot(r.uv.x - kP.x, r.uv.y - kP.y), 1e-3);
        }
        EXPECT_EQ(r.fetches, int(std::ceil(x)) + 2);  // k + 1 in the loop, 1 re-fetch
    }
}

TEST(Godot, DeepLayerCountIsMixOfMaxAndMinLayers) {
    // Head-on n = heightmap_min_layers = 8: a flat h = 0.3 field stops at k = ceil(5.6) = 6.
    const HeightField hf = test::flat_field(16, 16, 0.3f);
    EXPECT_EQ(literal::godot_deep(hf, 0.05f, view(0, 0), kP).fetches, 6 + 2);
    EXPECT_EQ(literal::godot_deep(hf, 0.05f, view(0, 0), kP, 20, 32).fetches, 14 + 2);
    // Grazing (theta 89): n = 32 (1 - V.z) + 8 V.z = 31.58, k = ceil(0.7 n) = 23.
    EXPECT_EQ(literal::godot_deep(hf, 0.05f, view(89, 0), kP).fetches, 23 + 2);
}

TEST(Godot, DeepRunsTheInterpolationAlsoWhenTheLoopDoesNot) {
    // h = 1 (depth 0): the loop stops at k = 0, the refinement still fetches prev_ofs = P + delta
    // and returns weight 0 -> P: 2 fetches, no NaN.
    const HeightField hf = test::flat_field(16, 16, 1.0f);
    for (const auto& a : kAngles) {
        const EngineResult r = literal::godot_deep(hf, 0.05f, view(a[0], a[1]), kP);
        expect_offset(r, kP, 0, 0, 0, "godot_deep k = 0");
        EXPECT_EQ(r.fetches, 2);
    }
}

// ---- Bevy (parallax_depth_scale = s; depth map D = 1 - h; b = 1) -----------------------------

double bevy_n(Vec3<float> V, float max_layers = 16) {
    return double(max_layers * (1.0f - V.z) + 1.0f * V.z);
}

TEST(Bevy, OcclusionOnAFlatFieldIsExactAndRefetchesThePreviousLayer) {
    const float s = 0.1f, h = 0.3f;
    const HeightField hf = test::flat_field(16, 16, h);
    for (const auto& a : kAngles) {
        const Vec3<float> V = view(a[0], a[1]);
        const double x = 0.7 * bevy_n(V);
        ASSERT_GT(std::abs(x - std::round(x)), 0.02);
        const EngineResult r = literal::bevy_occlusion(hf, s, V, kP);
        expect_offset(r, kP, s * (h - 1) * V.x / V.z, s * (h - 1) * V.y / V.z, 2e-6, "occlusion");
        EXPECT_EQ(r.fetches, int(std::ceil(x)) + 2);
    }
}

TEST(Bevy, MirrorVTrueMarchesWithVMirrored) {
    // mirror_v = true (the literal code on a mikktspace frame, B = +dP/dv): the step is
    // (s/n) (-V.x, +V.y) / V.z, so on a flat field the hit is P + s (h - 1) (V.x, -V.y) / V.z.
    const float s = 0.1f, h = 0.3f;
    const HeightField hf = test::flat_field(16, 16, h);
    for (const auto& a : kAngles) {
        const Vec3<float> V = view(a[0], a[1]);
        const EngineResult r = literal::bevy_occlusion(hf, s, V, kP, 16.0f, true);
        expect_offset(r, kP, s * (h - 1) * V.x / V.z, -s * (h - 1) * V.y / V.z, 2e-6, "mirror_v");
        // ... which is the unmirrored result for the view mirrored in v.
        const Vec3<float> Vm(V.x, -V.y, V.z);
        const HeightField rf = test::random_field(16, 16, 5);
        const EngineResult m = literal::bevy_occlusion(rf, s, V, kP, 16.0f, true);
        const EngineResult u = literal::bevy_occlusion(rf, s, Vm, kP, 16.0f, false);
        EXPECT_EQ(m.uv.x, u.uv.x);
        EXPECT_EQ(m.uv.y, u.uv.y);
        EXPECT_EQ(m.fetches, u.fetches);
    }
}

TEST(Bevy, OneLayerHeadOnSinceTheMinimumLayerCountIsOne) {
    // n = mix(16, 1, V.z): head-on one layer, so occlusion is a single secant between depth 0 at P
    // and the depth at P - s V.xy / V.z. At theta = 0 every sample is at P: h(P) = 0.3 ->
    // k = 1 (layer depth 1 >= 0.7), fetches 1 + 1 + 1 re-fetch.
    const HeightField rf = test::random_field(16, 16, 9, 0.05f, 0.95f);
    const EngineResult r = literal::bevy_occlusion(rf, 0.1f, view(0, 0), kP);
    EXPECT_EQ(r.fetches, 3);
    expect_offset(r, kP, 0, 0, 0, "head-on");
    // At theta = 5 (n = 1.06, ceil 2): the march takes at most 2 layers (+ cap slack) on any field.
    for (uint32_t seed = 1; seed < 20; ++seed) {
        const HeightField f = test::random_field(16, 16, seed);
        EXPECT_LE(literal::bevy_occlusion(f, 0.1f, view(5, 40), kP).fetches, 2 + 1 + 1);
    }
}

TEST(Bevy, ReliefOnAFlatFieldEndsWithinTwoToTheMinusSixLayer) {
    const float s = 0.1f, h = 0.3f;
    const HeightField hf = test::flat_field(16, 16, h);
    for (const auto& a : kAngles) {
        const Vec3<float> V = view(a[0], a[1]);
        const double n = bevy_n(V);
        const EngineResult r = literal::bevy_relief(hf, s, V, kP);
        // Midpoint start, then 5 probes: the result is a bracket centre at 1/64 spacing, within
        // 1/64 layer of the hit.
        test::expect_flat_relief(r, kP, -s / n * V.x / V.z, -s / n * V.y / V.z, 0.7 * n, 5, 1e-4,
                                 "bevy relief");
    }
}

TEST(Bevy, ReliefRunsAlsoAtLayerZeroAndEndsAboveThePolygon) {
    // h = 1 (depth 0): the loop stops at k = 0; relief still bisects [-1, 0] and ends at layer
    // -1/64: P + (s/n) V.xy / V.z / 64, off the surface toward the eye.
    const float s = 0.1f;
    const HeightField hf = test::flat_field(16, 16, 1.0f);
    for (const auto& a : kAngles) {
        const Vec3<float> V = view(a[0], a[1]);
        const double d = s / bevy_n(V) / V.z / 64;
        const EngineResult r = literal::bevy_relief(hf, s, V, kP);
        expect_offset(r, kP, d * V.x, d * V.y, 1e-7, "relief k = 0");
        EXPECT_EQ(r.fetches, 1 + 5);
        const EngineResult o = literal::bevy_occlusion(hf, s, V, kP);
        expect_offset(o, kP, 0, 0, 0, "occlusion k = 0");
        EXPECT_EQ(o.fetches, 2);
    }
}

// ---- O3DE (factor = s; offset 0 -> b = 1; quality Low = 16 layers) --------------------------

TEST(O3de, BasicIsOffsetLimitingWithBiasOne) {
    const float s = 0.05f, h = 0.3f;
    const HeightField hf = test::flat_field(16, 16, h);
    for (const auto& a : kAngles) {
        const Vec3<float> V = view(a[0], a[1]);
        const EngineResult r = literal::o3de_basic(hf, s, V, kP);
        expect_offset(r, kP, s * (h - 1) * V.x, s * (h - 1) * V.y, 1e-7, "o3de_basic");
        EXPECT_EQ(r.fetches, 1);
    }
}

TEST(O3de, FixedLayersOnAFlatField) {
    // h = 0.3: depth 0.7 = 11.2 / 16 -> k = 12 at Low. Per-layer step -(s/16) V.xy / V.z.
    const float s = 0.05f, h = 0.3f;
    const HeightField hf = test::flat_field(16, 16, h);
    for (const auto& a : kAngles) {
        const Vec3<float> V = view(a[0], a[1]);
        const double du = -s / 16 * V.x / V.z, dv = -s / 16 * V.y / V.z;
        const EngineResult st = literal::o3de_steep(hf, s, V, kP);
        expect_offset(st, kP, 12 * du, 12 * dv, 1e-6, "steep");
        EXPECT_EQ(st.fetches, 13);
        const EngineResult pom = literal::o3de_pom(hf, s, V, kP);  // exact, no extra fetch
        expect_offset(pom, kP, 11.2 * du, 11.2 * dv, 2e-6, "pom");
        EXPECT_EQ(pom.fetches, 13);
        const EngineResult rel = literal::o3de_relief(hf, s, V, kP);  // 16 bisections
        EXPECT_NEAR(layer_index(rel, kP, du, dv), 11.2, 1e-3) << "relief";
        EXPECT_EQ(rel.fetches, 13 + 16);
        // Contact: sub-layers of 1/16 from layer 11; first at or below 11.2 is 11 + 4/16.
        const EngineResult con = literal::o3de_contact(hf, s, V, kP);
        expect_offset(con, kP, 11.25 * du, 11.25 * dv, 2e-6, "contact");
        EXPECT_EQ(con.fetches, 13 + 4);
    }
    // Quality Ultra: 128 layers (k = ceil(89.6) = 90), relief runs 128 bisection fetches.
    const Vec3<float> V = view(45, 30);
    EXPECT_EQ(literal::o3de_steep(hf, s, V, kP, O3deQuality::Ultra).fetches, 91);
    EXPECT_EQ(literal::o3de_relief(hf, s, V, kP, O3deQuality::Ultra).fetches, 91 + 128);
    EXPECT_EQ(literal::o3de_steep(hf, s, V, kP, O3deQuality::Medium).fetches, 24);  // ceil(22.4)
    EXPECT_EQ(literal::o3de_steep(hf, s, V, kP, O3deQuality::High).fetches, 46);    // ceil(44.8)
}

TEST(O3de, ReliefSignZeroStaysOnAnExactTie) {
    // h = 0.5: the march stops exactly on layer 8 (D = 0.5 = 8/16); sign(0) = 0, so relief never
    // moves: uv_8 exactly (pxh relief, stepping back on a tie, would leave the layer), and it
    // still fetches 16 times.
    const float s = 0.05f;
    const HeightField hf = test::flat_field(16, 16, 0.5f);
    const Vec3<float> V = view(50, 70);
    const EngineResult st = literal::o3de_steep(hf, s, V, kP);
    const EngineResult rel = literal::o3de_relief(hf, s, V, kP);
    EXPECT_EQ(rel.uv.x, st.uv.x);
    EXPECT_EQ(rel.uv.y, st.uv.y);
    EXPECT_EQ(st.fetches, 9);
    EXPECT_EQ(rel.fetches, 9 + 16);
}

TEST(O3de, LayerZeroReturnsPWithoutRefinement) {
    const HeightField hf = test::flat_field(16, 16, 1.0f);
    for (const auto& a : kAngles) {
        const Vec3<float> V = view(a[0], a[1]);
        for (auto alg : {literal::O3deAlgorithm::Steep, literal::O3deAlgorithm::POM,
                         literal::O3deAlgorithm::Relief, literal::O3deAlgorithm::Contact}) {
            const EngineResult r = literal::o3de_advanced(hf, 0.05f, V, kP, alg);
            expect_offset(r, kP, 0, 0, 0, "k = 0");
            EXPECT_EQ(r.fetches, 1);
        }
    }
}

TEST(O3de, PositiveOffsetClipsTheReliefAtThePolygon) {
    // offset = s / 2 raises an h = 1 field to z = +s/2 (pxh b = 0.5). O3DE clamps depths to the
    // polygon (D' = max(1 - h, offset / s)), so the search hits z = 0 at layer 8: uv = P, not the
    // unclipped hit P + V.xy / V.z * s / 2 (pxh's truth for b = 0.5).
    const float s = 0.05f;
    const HeightField hf = test::flat_field(16, 16, 1.0f);
    const Vec3<float> V = view(40, 200);
    for (auto alg : {literal::O3deAlgorithm::Steep, literal::O3deAlgorithm::POM}) {
        const EngineResult r = literal::o3de_advanced(hf, s, V, kP, alg, O3deQuality::Low, s / 2);
        expect_offset(r, kP, 0, 0, 1e-7, "clipped");
        EXPECT_EQ(r.fetches, 9);
    }
}

// ---- The presets (named settings of the marcher) against the literal transcriptions ----------

// Each preset (CPU float, the registered method) against its literal on two random fields,
// random points and views (theta 0..85, five phi each) at one scale, with the preset's
// parameters `given`. Where the engine resolves steps below float noise (O3DE contact at Ultra:
// sub-steps of 1/128^2 of the slab), `substep` and `fetch_fraction` widen what agrees.
test::LiteralSweep gbo_sweep(float s, const GivenParams& given = {}, double substep = 0,
                             double fetch_fraction = 0.001) {
    test::LiteralSweep sw;
    sw.fields = {test::random_field(64, 64, 1), test::random_field(64, 64, 2)};
    sw.scales = {s};
    sw.thetas = {0, 10, 30, 50, 70, 85};
    sw.phis = {0, 75, 160, 250, 320};
    sw.points = 100;
    sw.point_seed = 11;
    sw.given = given;
    sw.substep = substep;
    sw.fetch_fraction = fetch_fraction;
    return sw;
}
using test::expect_preset_matches;
using test::method;

TEST(GodotPreset, ParallaxMatchesTheLiteral) {
    expect_preset_matches("godot_parallax", PXH_LITERAL(literal::godot_parallax), gbo_sweep(0.05f));
    expect_preset_matches(
        "godot_parallax",
        [](auto& hf, float s, auto V, auto P) {
            return literal::godot_parallax(hf, s, V, P, false, true);
        },
        gbo_sweep(0.05f, {{"heightmap_flip_binormal", true}}));
}

TEST(GodotPreset, DeepMatchesTheLiteral) {
    expect_preset_matches("godot_deep", PXH_LITERAL(literal::godot_deep), gbo_sweep(0.05f));
    expect_preset_matches(
        "godot_deep",
        [](auto& hf, float s, auto V, auto P) {
            return literal::godot_deep(hf, s, V, P, 3, 50, false, true);
        },
        gbo_sweep(0.1f, {{"heightmap_min_layers", 3.0},
                         {"heightmap_max_layers", 50.0},
                         {"heightmap_flip_binormal", true}}));
}

TEST(BevyPreset, OcclusionMatchesTheLiteral) {
    expect_preset_matches("bevy_occlusion", PXH_LITERAL(literal::bevy_occlusion), gbo_sweep(0.1f));
    expect_preset_matches(
        "bevy_occlusion",
        [](auto& hf, float s, auto V, auto P) {
            return literal::bevy_occlusion(hf, s, V, P, 40.5f, true);
        },
        gbo_sweep(0.05f, {{"mirror_v", true}, {"max_parallax_layer_count", 40.5}}));
}

TEST(BevyPreset, ReliefMatchesTheLiteral) {
    expect_preset_matches("bevy_relief", PXH_LITERAL(literal::bevy_relief), gbo_sweep(0.1f));
    expect_preset_matches(
        "bevy_relief",
        [](auto& hf, float s, auto V, auto P) {
            return literal::bevy_relief(hf, s, V, P, 16.0f, 9, true);
        },
        gbo_sweep(0.1f, {{"mirror_v", true}, {"max_steps", 9.0}}));
    expect_preset_matches(
        "bevy_relief",
        [](auto& hf, float s, auto V, auto P) {
            return literal::bevy_relief(hf, s, V, P, 16.0f, 0);
        },
        gbo_sweep(0.1f, {{"max_steps", 0.0}}));
}

TEST(O3dePreset, BasicMatchesTheLiteral) {
    expect_preset_matches("o3de_basic", PXH_LITERAL(literal::o3de_basic), gbo_sweep(0.05f));
}

struct O3deQualityCase {
    const char* name;
    O3deQuality q;
};
const O3deQualityCase kQualities[] = {{"Low", O3deQuality::Low},
                                      {"Medium", O3deQuality::Medium},
                                      {"High", O3deQuality::High},
                                      {"Ultra", O3deQuality::Ultra}};

struct Slack {
    double substep = 0, fetch_fraction = 0.001;
};

void compare_o3de(const char* preset, literal::O3deAlgorithm alg, Slack ultra = {}) {
    for (const auto& q : kQualities) {
        const Slack sl = q.q == O3deQuality::Ultra ? ultra : Slack{};
        expect_preset_matches(
            preset,
            [&](auto& hf, float s, auto V, auto P) {
                return literal::o3de_advanced(hf, s, V, P, alg, q.q);
            },
            gbo_sweep(0.05f, {{"quality", std::string(q.name)}}, sl.substep, sl.fetch_fraction));
    }
}

TEST(O3dePreset, SteepMatchesTheLiteral) {
    compare_o3de("o3de_steep", literal::O3deAlgorithm::Steep);
}
TEST(O3dePreset, PomMatchesTheLiteral) { compare_o3de("o3de_pom", literal::O3deAlgorithm::POM); }
TEST(O3dePreset, ReliefMatchesTheLiteral) {
    compare_o3de("o3de_relief", literal::O3deAlgorithm::Relief);
}
TEST(O3dePreset, ContactMatchesTheLiteral) {
    // At Ultra a contact sub-step is 1/16384 of the slab: the engine's accumulated uv offsets
    // and the marcher's uv0 + duv x differ by float noise of that order, so the sub-step chosen
    // flips on ~0.6% of samples (fetch counts one apart, uv one sub-step apart, up to 0.0023
    // texel at theta 85). Low / Medium / High meet the plain rule.
    compare_o3de("o3de_contact", literal::O3deAlgorithm::Contact, {1.0 / (128.0 * 128.0), 0.01});
}

// The presets' own closed forms and the engines' fixed reference plane.
TEST(GboPresets, NeedBiasOneCiteACommitAndKeepTheEnginesDefaults) {
    for (const char* name :
         {"godot_parallax", "godot_deep", "bevy_occlusion", "bevy_relief", "o3de_basic",
          "o3de_steep", "o3de_pom", "o3de_relief", "o3de_contact"}) {
        const MethodInfo& m = method(name);
        EXPECT_EQ(m.required_bias, 1.0) << name;
        EXPECT_NE(m.citation.find("@ "), std::string::npos) << name << " cites a commit";
        const std::string toml =
            "[views]\ntheta_deg = [0, 30]\n[[heightfields]]\ngenerator = "
            "\"flat\"\nsize = 8\nbias = 0.5\n[[methods]]\nname = \"" +
            std::string(name) + "\"\n";
        try {
            parse_experiment(toml, "e.toml");
            ADD_FAILURE() << name << " accepted bias 0.5";
        } catch (const InputError& e) {
            EXPECT_NE(std::string(e.what()).find("needs bias = 1 ("), std::string::npos)
                << e.what();
        }
    }
    // Bevy default max_parallax_layer_count 16 and n_min 1: at theta 0 one layer; O3DE Low = 16.
    const HeightField hf = test::flat_field(16, 16, 0.3f);
    std::vector<int> f;
    test::run_method<float>(method("bevy_occlusion"), test::params_for(method("bevy_occlusion")),
                            test::make_scene(hf, 0.1, 1.0, 0, 0), hf, {Vec2d(kP)}, &f);
    EXPECT_EQ(f[0], 1 + 1 + 1);
    test::run_method<float>(method("o3de_steep"), test::params_for(method("o3de_steep")),
                            test::make_scene(hf, 0.05, 1.0, 45, 0), hf, {Vec2d(kP)}, &f);
    EXPECT_EQ(f[0], 12 + 1);
    test::run_method<float>(method("godot_deep"), test::params_for(method("godot_deep")),
                            test::make_scene(hf, 0.05, 1.0, 0, 0), hf, {Vec2d(kP)}, &f);
    EXPECT_EQ(f[0], 6 + 2);
}

// The presets at non-default engine settings on the GLSL twin (the registry test runs the
// defaults): O3DE Ultra (relief's 127 bisection probes + 1, contact's 128 sub-layers), Godot
// with flipped binormal and 4..64 layers, Bevy mirrored with 9 relief steps.
TEST(GboPresets, GlslAgreesAtNonDefaultSettings) {
    static GlslBackend gl(GlslOptions{"", 0});
    const std::pair<const char*, GivenParams> settings[] = {
        {"o3de_relief", {{"quality", std::string("Ultra")}}},
        {"o3de_contact", {{"quality", std::string("Medium")}}},
        {"o3de_pom", {{"quality", std::string("High")}}},
        {"godot_deep",
         {{"heightmap_min_layers", 4.0},
          {"heightmap_max_layers", 64.0},
          {"heightmap_flip_binormal", true}}},
        {"godot_parallax", {{"heightmap_flip_binormal", true}}},
        {"bevy_relief", {{"mirror_v", true}, {"max_steps", 9.0}}},
        {"bevy_occlusion", {{"mirror_v", true}, {"max_parallax_layer_count", 40.5}}},
    };
    const HeightField hf = test::random_field(64, 64, 7);
    const int N = 48;
    for (const auto& [name, given] : settings) {
        const MethodSpec spec{&method(name), test::params_for(method(name), given)};
        for (double theta : {0.0, 40.0, 75.0}) {
            const Scene<double> sc{0.05, 1.0, view_vector(theta, 35), hf.width, hf.height};
            const test::GlslCpuDiff d = test::glsl_vs_cpu(gl, spec, sc, hf, N);
            EXPECT_LE(d.far, d.samples / 1000) << spec.params.canonical() << " theta=" << theta;
            EXPECT_LE(d.fetch_off, d.samples / 1000) << spec.params.canonical();
        }
    }
}

}  // namespace
}  // namespace pxh
