// The JavaScript engines' parallax (three.js, Babylon.js, PlayCanvas): the literal transcriptions
// of tests/engines/literal_js.h against closed forms on flat fields, their documented defects
// pinned with numbers, and agreement with the seed methods where the engine's loop is one.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>

#include "harness/core/error.h"
#include "methods/method.h"
#include "tests/engines/literal_js.h"
#include "tests/methods/engine_checks.h"
#include "tests/test_util.h"

namespace pxh {
namespace {

using literal::EngineResult;
using test::make_scene;
using test::params_for;
using test::run_method;

using test::method;

using test::expect_offset;
using test::layer_index;
const auto view = &test::engine_view;

const Vec2<float>& kP = test::kEngineP;
const auto& kAngles = test::kEngineAngles;

// ---- three.js (positive parallaxScale on the depth map t = 1 - h; pxh b = 1) ----------------

// n = mix(maxLayers, minLayers, V.z) as the shader computes it (float).
double three_n(Vec3<float> V, float mn = 20, float mx = 25) {
    return double(mx * (1.0f - V.z) + mn * V.z);
}

TEST(ThreeJs, BasicIsOffsetLimitingOnTheDepthMap) {
    const float s = 0.05f, h = 0.3f;
    const HeightField hf = test::flat_field(16, 16, h);
    for (const auto& a : kAngles) {
        const Vec3<float> V = view(a[0], a[1]);
        const EngineResult r = literal::threejs_basic(hf, s, V, kP);
        // P - parallaxScale * V.xy * t with t = 1 - h: P + s (h - 1) V.xy, no division by V.z.
        expect_offset(r, kP, s * (h - 1) * V.x, s * (h - 1) * V.y, 1e-7, "basic");
        EXPECT_EQ(r.fetches, 1);
    }
}

TEST(ThreeJs, SteepOnAFlatFieldStopsAtTheFirstLayerBelowTheDepth) {
    const float s = 0.05f, h = 0.3f;  // depth 0.7
    const HeightField hf = test::flat_field(16, 16, h);
    for (const auto& a : kAngles) {
        const Vec3<float> V = view(a[0], a[1]);
        const double n = three_n(V), x = 0.7 * n;
        ASSERT_GT(std::abs(x - std::round(x)), 0.02) << "test angle too close to a layer tie";
        const int k = int(std::ceil(x));
        const EngineResult r = literal::threejs_steep(hf, s, V, kP);
        const double step = s / (V.z * n);  // |dtex| per unit V.xy
        expect_offset(r, kP, -k * step * V.x, -k * step * V.y, 1e-6, "steep");
        EXPECT_EQ(r.fetches, k + 1);
    }
}

TEST(ThreeJs, OcclusionOnAFlatFieldIsExactAndRefetchesThePreviousLayer) {
    const float s = 0.05f, h = 0.3f;
    const HeightField hf = test::flat_field(16, 16, h);
    for (const auto& a : kAngles) {
        const Vec3<float> V = view(a[0], a[1]);
        const int k = int(std::ceil(0.7 * three_n(V)));
        const EngineResult r = literal::threejs_occlusion(hf, s, V, kP);
        // Exact hit: P + V.xy / V.z * s (h - b), b = 1.
        expect_offset(r, kP, s * (h - 1) * V.x / V.z, s * (h - 1) * V.y / V.z, 2e-6, "occlusion");
        EXPECT_EQ(r.fetches, k + 2);
    }
}

TEST(ThreeJs, ReliefOnAFlatFieldEndsWithin1Over64LayerAfterFiveFetches) {
    const float s = 0.05f, h = 0.3f;
    const HeightField hf = test::flat_field(16, 16, h);
    for (const auto& a : kAngles) {
        const Vec3<float> V = view(a[0], a[1]);
        const double n = three_n(V);
        const EngineResult r = literal::threejs_relief(hf, s, V, kP);
        // The hit is at layer 0.7 n, the per-layer step -(s / n) V.xy / V.z.
        test::expect_flat_relief(r, kP, -s / n * V.x / V.z, -s / n * V.y / V.z, 0.7 * n, 5, 1e-3,
                                 "three.js relief");
    }
}

TEST(ThreeJs, ReliefWithoutLayerZeroGuardBisectsAboveTheSlab) {
    // h = 1 everywhere (depth 0): the march stops at k = 0, and relief bisects on layers [-1, 0]:
    // every probe is "above", so it returns layer -1/64, i.e. P + dtex / 64, off the surface
    // toward the eye (pxh relief returns P there). steep and occlusion return P.
    const float s = 0.05f;
    const HeightField hf = test::flat_field(16, 16, 1.0f);
    for (const auto& a : kAngles) {
        const Vec3<float> V = view(a[0], a[1]);
        const double d = s / (V.z * three_n(V)) / 64;
        expect_offset(literal::threejs_relief(hf, s, V, kP), kP, d * V.x, d * V.y, 1e-7, "relief");
        expect_offset(literal::threejs_steep(hf, s, V, kP), kP, 0, 0, 0, "steep");
        expect_offset(literal::threejs_occlusion(hf, s, V, kP), kP, 0, 0, 0, "occlusion");
        const auto pxh_relief =
            run_method<float>(method("relief"), params_for(method("relief")),
                              make_scene(hf, s, 1.0, a[0], a[1]), hf, {Vec2d(kP)});
        EXPECT_EQ(pxh_relief[0].x, double(kP.x));
        EXPECT_EQ(pxh_relief[0].y, double(kP.y));
    }
    // At theta 60 and n = 22.5 the step is 0.05 / (0.5 * 22.5) = 4.44e-3 uv per unit V.xy:
    // relief lands 0.0616 texels of a 1024 field away from P.
    const Vec3<float> V = view(60, 0);
    const EngineResult r = literal::threejs_relief(hf, s, V, kP);
    EXPECT_NEAR((r.uv.x - kP.x) * 1024, 0.05 / (0.5 * 22.5) / 64 * V.x * 1024, 1e-4);
    EXPECT_NEAR((r.uv.x - kP.x) * 1024, 0.0616, 1e-3);
}

TEST(ThreeJs, ThirtyIterationCapStopsTheSearchAtDepth30OverN) {
    // maxLayers = minLayers = 40 (above the example's GUI limit of 30): on a flat h = 0 field
    // (depth 1) the loop runs out at layer 30, depth 0.75. steep returns uv_30; occlusion has no
    // guard and extrapolates from layers 29, 30 (weight -10), which on a flat field lands on the
    // exact hit uv_40.
    const float s = 0.05f;
    const HeightField hf = test::flat_field(16, 16, 0.0f);
    const Vec3<float> V = view(45, 30);
    const double dtex = s / (V.z * 40.0);
    const EngineResult st = literal::threejs_steep(hf, s, V, kP, 40, 40);
    expect_offset(st, kP, -30 * dtex * V.x, -30 * dtex * V.y, 1e-6, "steep capped");
    EXPECT_EQ(st.fetches, 31);
    const EngineResult oc = literal::threejs_occlusion(hf, s, V, kP, 40, 40);
    expect_offset(oc, kP, -40 * dtex * V.x, -40 * dtex * V.y, 1e-5, "occlusion extrapolated");
    EXPECT_EQ(oc.fetches, 32);
    // With the example's 20..25 layers the search reaches the floor: k = ceil(n) = 22 at 45 deg
    // (23 fetches).
    const double n = three_n(V);
    ASSERT_NEAR(n, 25 - 5 * std::cos(M_PI / 4), 1e-5);  // 21.46
    const EngineResult full = literal::threejs_steep(hf, s, V, kP);
    const double d = s / (V.z * n);
    expect_offset(full, kP, -22 * d * V.x, -22 * d * V.y, 1e-6, "steep 20..25");
    EXPECT_EQ(full.fetches, 23);
}

// ---- Babylon.js -----------------------------------------------------------------------------

// Babylon's `lit` on a flat field h at every view, in both handedness modes (PARALLAX_RHS
// false and true): uv = P + k(V) V.xy, `fetches` fetches.
template <class Lit, class K>
void expect_babylon_flat(const Lit& lit, float s, float h, const K& k, double tol, int fetches) {
    const HeightField hf = test::flat_field(16, 16, h);
    for (const auto& a : kAngles) {
        const Vec3<float> V = view(a[0], a[1]);
        for (bool rhs : {false, true}) {
            const EngineResult r = lit(hf, s, V, kP, rhs);
            expect_offset(r, kP, k(V) * V.x, k(V) * V.y, tol, rhs ? "RHS" : "LHS");
            EXPECT_EQ(r.fetches, fetches);
        }
    }
}

TEST(Babylon, ParallaxOffsetIsOffsetLimitingAboveThePolygon) {
    // b = 0: P + s h V.xy, the same in both handedness modes.
    const float s = 0.05f, h = 0.7f;
    expect_babylon_flat([](const auto&... a) { return literal::babylon_parallax(a...); }, s, h,
                        [&](Vec3<float>) { return s * h; }, 1e-7, 1);
}

double babylon_n(Vec3<float> V) { return 15.0 + 11.0 * V.z; }

TEST(Babylon, PomOnAFlatFieldWithinReachIsExactAndFetches15) {
    const float s = 0.05f, h = 0.8f;  // depth 0.2 < 14 / n at every angle
    expect_babylon_flat([](const auto&... a) { return literal::babylon_pom(a...); }, s, h,
                        [&](Vec3<float> V) { return s * (h - 1) / V.z; }, 2e-6, 15);
}

TEST(Babylon, PomStepCountFromNDotMinusVWithCap15TestsOnlyDepth14OverN) {
    // numSamples = 15 + dot(-V, N) (4 - 15) = 15 + 11 V.z >= 15 while the loop stops after 15
    // samples: only depth 14 / n is tested (54% head-on). On a flat h = 0.1 field (depth 0.9)
    // no layer hits and the untested uv_15 = P - 15/n s V.xy / V.z is returned.
    const float s = 0.05f, h = 0.1f;
    const HeightField hf = test::flat_field(16, 16, h);
    for (const auto& a : kAngles) {
        const Vec3<float> V = view(a[0], a[1]);
        const double n = babylon_n(V), reach = 15 / n;
        ASSERT_LT(14 / n, 0.9);  // the last tested layer is above the surface
        const EngineResult r = literal::babylon_pom(hf, s, V, kP);
        expect_offset(r, kP, -reach * s * V.x / V.z, -reach * s * V.y / V.z, 2e-6, "uv_15");
    }
    // theta 60: n = 20.5, depth reached 15 / 20.5 = 0.732; theta 10: n = 25.83, 0.581.
    EXPECT_NEAR(15 / babylon_n(view(60, 0)), 0.7317, 1e-4);
    EXPECT_NEAR(15 / babylon_n(view(10, 0)), 0.5807, 1e-4);
    // h = 0.45 at theta 60 is reached (0.55 < 14 / 20.5 = 0.683): exact again.
    const HeightField reached = test::flat_field(16, 16, 0.45f);
    const Vec3<float> V = view(60, 0);
    expect_offset(literal::babylon_pom(reached, s, V, kP), kP, -0.55 * s * V.x / V.z,
                  -0.55 * s * V.y / V.z, 2e-6, "reached");
}

TEST(Babylon, PomIsNaNAtNormalIncidence) {
    // normalize(vec2(0)) is 0 * inf: vMaxOffset and the result are NaN at theta = 0 exactly.
    const HeightField hf = test::random_field(16, 16, 3);
    const EngineResult r = literal::babylon_pom(hf, 0.05f, Vec3<float>(0, 0, 1), kP);
    EXPECT_TRUE(std::isnan(r.uv.x));
    EXPECT_TRUE(std::isnan(r.uv.y));
    const EngineResult near0 = literal::babylon_pom(hf, 0.05f, view(0.01, 0), kP);
    EXPECT_TRUE(std::isfinite(near0.uv.x) && std::isfinite(near0.uv.y));
    EXPECT_NEAR(near0.uv.x, kP.x, 1e-4);
}

// ---- PlayCanvas -----------------------------------------------------------------------------

TEST(PlayCanvas, Basic221IsTheSlopeCappedOffsetAboutHalfHeight) {
    const float s = 0.025f;  // heightMapFactor 1
    for (float h : {0.1f, 0.5f, 0.9f}) {
        const HeightField hf = test::flat_field(16, 16, h);
        for (const auto& a : kAngles) {
            const Vec3<float> V = view(a[0], a[1]);
            const EngineResult r = literal::playcanvas_basic_v2_21(hf, s, V, kP);
            const double k = s * (h - 0.5) / (V.z + 0.42);
            expect_offset(r, kP, k * V.x, k * V.y, 1e-7, "playcanvas");
            EXPECT_EQ(r.fetches, 1);
        }
    }
    // theta 85, h = 1: the offset is s/2 |V.xy| / (V.z + 0.42) = 0.0245 uv, where the exact
    // b = 0.5 offset s/2 tan(theta) is 0.143.
    const HeightField top = test::flat_field(16, 16, 1.0f);
    const EngineResult r = literal::playcanvas_basic_v2_21(top, s, view(85, 0), kP);
    EXPECT_NEAR(r.uv.x - kP.x, 0.0245, 1e-4);
}

// ---- Agreement with the seed methods where the engine's loop is one (random fields) ----------

struct Compare {
    int total = 0, off = 0;
    double worst = 0, worst_layers = 0;  // texels; layers of three.js' 20..25 search
    void add(Vec2d a, Vec2<float> b, int W, double layer_texels) {
        const double d = std::hypot(a.x - b.x, a.y - b.y) * W;
        worst = std::max(worst, d);
        worst_layers = std::max(worst_layers, d / layer_texels);
        off += !(d <= 1e-3);
        ++total;
    }
};

template <typename Literal>
Compare compare_with_seed(const char* seed, const GivenParams& given, double b, float s,
                          Literal lit) {
    // Heights in [0, 0.97]: depth > 0 everywhere, so no sample stops at layer 0 (where
    // three.js relief differs from pxh relief by design, pinned above).
    const HeightField hf = test::random_field(128, 128, 41, 0.0f, 0.97f);
    Compare c;
    for (double theta : {10.0, 35.0, 60.0, 85.0})
        for (double phi : {0.0, 100.0, 215.0}) {
            const auto sc = make_scene(hf, s, b, theta, phi);
            const Vec3<float> V(sc.V);
            const double layer_texels = s * std::hypot(V.x, V.y) / (V.z * three_n(V)) * hf.width;
            const auto P = test::random_points(1000, uint32_t(theta * 7 + phi));
            const auto ours =
                run_method<float>(method(seed), params_for(method(seed), given), sc, hf, P);
            for (size_t i = 0; i < P.size(); ++i)
                c.add(ours[i], lit(hf, s, V, Vec2<float>(P[i])).uv, hf.width, layer_texels);
        }
    return c;
}

TEST(EnginesJs, ThreeJsLoopsAreTheSeedLayeredSearchOnTheDepthMap) {
    const std::map<std::string, double> layers = {{"layers_min", 20}, {"layers_max", 25}};
    const std::map<std::string, double> relief = {
        {"layers_min", 20}, {"layers_max", 25}, {"binary_steps", 5}};
    const float s = 0.05f;
    const Compare cases[] = {
        compare_with_seed("parallax_limited", {}, 1.0, s, literal::threejs_basic),
        compare_with_seed("steep", layers, 1.0, s,
                          [](const auto&... a) { return literal::threejs_steep(a...); }),
        compare_with_seed("pom", layers, 1.0, s,
                          [](const auto&... a) { return literal::threejs_occlusion(a...); }),
        compare_with_seed("relief", relief, 1.0, s,
                          [](const auto&... a) { return literal::threejs_relief(a...); }),
    };
    const char* names[] = {"basic", "steep", "occlusion", "relief"};
    // Float accumulation order differs (the engine adds dtex and layerHeight per step, pxh
    // computes uv_0 + k duv): near-ties flip. Relief probes converge on the root, so its five
    // decisions are near-ties far more often (17 of 12000 samples here, at every angle); a flipped
    // probe moves the result by at most 1/32 layer, and no further.
    for (int m = 0; m < 4; ++m)
        EXPECT_LE(cases[m].off, cases[m].total / (m == 3 ? 400 : 1000))
            << names[m] << ": " << cases[m].off << " of " << cases[m].total << ", worst "
            << cases[m].worst << " texel";
    EXPECT_LE(cases[3].worst_layers, 1.0 / 32 + 1e-3);
}

TEST(EnginesJs, BabylonParallaxIsTheSeedOffsetLimitingWithBiasZero) {
    const Compare c = compare_with_seed("parallax_limited", {}, 0.0, 0.05f, [](const auto&... a) {
        return literal::babylon_parallax(a...);
    });
    EXPECT_LE(c.off, c.total / 1000) << "worst " << c.worst;
}

// ---- The presets (named settings of the parametric marcher) against the literal loops ------

// The preset (CPU, float) against its literal transcription on two random fields, random points,
// at the engine's default scale and larger ones, and several polar and azimuth angles.
test::LiteralSweep js_sweep(bool with_theta0 = true, const GivenParams& given = {}) {
    test::LiteralSweep sw;
    sw.fields = {test::random_field(128, 128, 71), test::random_field(64, 64, 72, 0.2f, 0.9f)};
    sw.scales = {0.005f, 0.025f, 0.05f};
    sw.thetas = {10, 30, 50, 70, 85};
    if (with_theta0) sw.thetas.insert(sw.thetas.begin(), 0.0);
    sw.phis = {0, 75, 160, 290};
    sw.given = given;
    return sw;
}

TEST(EnginePresetsJs, ThreeJs) {
    test::expect_preset_matches("threejs_basic", literal::threejs_basic, js_sweep());
    test::expect_preset_matches("threejs_steep", PXH_LITERAL(literal::threejs_steep), js_sweep());
    test::expect_preset_matches("threejs_occlusion", PXH_LITERAL(literal::threejs_occlusion),
                                js_sweep());
    test::expect_preset_matches("threejs_relief", PXH_LITERAL(literal::threejs_relief), js_sweep());
}
TEST(EnginePresetsJs, Babylon) {
    test::expect_preset_matches("babylon_parallax", PXH_LITERAL(literal::babylon_parallax),
                                js_sweep());
    // theta = 0 left out: the engine returns NaN there (pinned in
    // Babylon.PomIsNaNAtNormalIncidence; the marcher's V.xy is 0 and it returns P). Fetches: the
    // engine's loop fetches on all 15 iterations, also after the hit, and so does the preset
    // (pad_fetches).
    test::expect_preset_matches("babylon_pom", PXH_LITERAL(literal::babylon_pom), js_sweep(false));
}
TEST(EnginePresetsJs, ThreeJsSteepAndOcclusionWithTheThirtyStepCapBinding) {
    // 40 layers (above the example's GUI range): the search stops at layer 30; occlusion
    // interpolates (extrapolates) from layers 29 and 30 all the same.
    const GivenParams forty = {{"parallaxMinLayers", 40.0}, {"parallaxMaxLayers", 40.0}};
    test::expect_preset_matches(
        "threejs_steep",
        [](const HeightField& hf, float s, Vec3<float> V, Vec2<float> P) {
            return literal::threejs_steep(hf, s, V, P, 40, 40);
        },
        js_sweep(true, forty));
    test::expect_preset_matches(
        "threejs_occlusion",
        [](const HeightField& hf, float s, Vec3<float> V, Vec2<float> P) {
            return literal::threejs_occlusion(hf, s, V, P, 40, 40);
        },
        js_sweep(true, forty));
    // Relief with the cap binding is not a marcher setting (the shader steps half a layer back
    // from an uncrossed layer 30, the marcher forward): the preset refuses more than 30 layers.
    EXPECT_THROW(params_for(method("threejs_relief"), {{"parallaxMaxLayers", 40}}), InputError);
}

TEST(EnginePresetsJs, ReferencePlanes) {
    for (const char* n :
         {"threejs_basic", "threejs_steep", "threejs_occlusion", "threejs_relief", "babylon_pom"})
        EXPECT_EQ(method(n).required_bias, 1.0) << n;
    EXPECT_EQ(method("babylon_parallax").required_bias, 0.0);
    EXPECT_EQ(method("playcanvas_basic_v2_21").required_bias, 0.5);
    // From 2.22 both modes read the plane from heightMapBase: any b.
    EXPECT_TRUE(std::isnan(method("playcanvas_basic").required_bias));
    EXPECT_TRUE(std::isnan(method("playcanvas_occlusion").required_bias));
}

// Every engine preset says which release it follows; PlayCanvas's the current stable one.
TEST(EnginePresetsJs, EveryPresetSaysTheReleaseItFollows) {
    int presets = 0;
    for (const MethodInfo& m : all_methods()) {
        if (m.shader_path != "methods/march/march.frag.glsl" || m.name == "march" ||
            m.name.rfind("test_", 0) == 0)  // a test's own rows
            continue;
        ++presets;
        EXPECT_FALSE(m.engine_version.empty()) << m.name;
    }
    EXPECT_EQ(presets, 25);  // ten engines' files
    EXPECT_NE(method("playcanvas_basic").engine_version.find("2.22.0"), std::string::npos);
    EXPECT_NE(method("playcanvas_occlusion").engine_version.find("2.22.0"), std::string::npos);
    EXPECT_NE(method("playcanvas_basic_v2_21").engine_version.find("2.21.4"), std::string::npos);
    EXPECT_NE(method("threejs_basic").engine_version.find("r131"), std::string::npos);
}

TEST(EnginePresetsJs, PlayCanvasBasic221) {
    test::expect_preset_matches("playcanvas_basic_v2_21", literal::playcanvas_basic_v2_21,
                                js_sweep());
}

// The 2.22+ offset mode against its literal at three planes: every sample within 1e-5 texel,
// one fetch each; and not the 2.21 mode (37.5 texels apart at theta 85 on a 256-texel field,
// the finding, is the order of what it gives here on h = 1).
TEST(EnginePresetsJs, PlayCanvasBasicFollows222) {
    const MethodInfo& m = method("playcanvas_basic");
    const ParamValues p = params_for(m, {});
    const auto P = test::random_points(300, 7);
    for (const HeightField& hf : js_sweep().fields)
        for (const double b : {0.5, 0.0, 1.0})
            for (const double theta : {10.0, 50.0, 85.0})
                for (const double phi : {0.0, 200.0}) {
                    const Scene<double> sc = make_scene(hf, 0.1, b, theta, phi);
                    std::vector<int> fetches;
                    const auto uv = run_method<float>(m, p, sc, hf, P, &fetches);
                    for (size_t i = 0; i < P.size(); ++i) {
                        const EngineResult e = literal::playcanvas_offset(
                            hf, 0.1f, float(b), Vec3<float>(sc.V), Vec2<float>(P[i]));
                        EXPECT_LE(std::hypot(uv[i].x - e.uv.x, uv[i].y - e.uv.y) * hf.width, 1e-5)
                            << "b " << b << " theta " << theta;
                        EXPECT_EQ(fetches[i], 1);
                    }
                }
    // h = 1, b = 0.5, theta 85: s/2 |V.xy| = 0.0498 uv (2.21: s/2 |V.xy| / (V.z + 0.42)).
    const HeightField top = test::flat_field(16, 16, 1.0f);
    EXPECT_NEAR(literal::playcanvas_offset(top, 0.1f, 0.5f, view(85, 0), kP).uv.x - kP.x,
                0.05 * std::sin(85 * M_PI / 180), 1e-6);
}

}  // namespace
}  // namespace pxh
