// Sanity tests of the literal engine transcriptions in tests/engines/literal_unity_jme_ogre_dx.h:
// closed forms on flat and random fields, and the engines' documented defects pinned
// with numbers. Closed forms are computed here in double, independently of the transcriptions.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <tuple>
#include <utility>
#include <vector>

#include "harness/backends/cpu_backend.h"
#include "harness/scene/view.h"
#include "methods/march/march.h"
#include "tests/engines/literal_unity_jme_ogre_dx.h"
#include "tests/methods/engine_checks.h"
#include "tests/test_util.h"

namespace pxh {
namespace {

using literal::EngineResult;

const auto Vf = &test::engine_view;

// The exact answer on a flat field h = c, any b: the ray meets z = s (c - b) at
// P + s (c - b) V.xy / V.z (docs/conventions.md section 4).
Vec2d flat_truth(double s, double c, double b, Vec3<float> V, Vec2<float> P) {
    const double k = s * (c - b) / double(V.z);
    return {double(P.x) + k * double(V.x), double(P.y) + k * double(V.y)};
}

void expect_uv(const EngineResult& r, Vec2d want, double tol, const char* what) {
    EXPECT_NEAR(r.uv.x, want.x, tol) << what;
    EXPECT_NEAR(r.uv.y, want.y, tol) << what;
}

const std::vector<double> kThetas = {10, 30, 45, 60, 75, 85};
const std::vector<double> kPhis = {0, 37, 140, 250};

// ---- unity_parallax_offset ----

// Any field: uv = P + s (h(P) - 0.5) V.xy / (V.z + 0.42), one fetch.
TEST(EngineUnity, ParallaxOffsetClosedFormOnRandomField) {
    const HeightField hf = test::random_field(64, 64, 101);
    const auto pts = test::random_points(100, 102);
    for (const float s : {0.02f, 0.005f, 0.08f})
        test::expect_one_fetch_offset(
            literal::unity_parallax_offset, hf, s, pts, kThetas, kPhis,
            [&](double h, Vec3<float> V) { return s * (h - 0.5) / (double(V.z) + 0.42); }, 5e-7,
            "unity");
}

// The +0.42 limits the offset: never beyond (s/2)/0.42 however grazing, 0 straight down.
TEST(EngineUnity, OffsetLimitAndZeroAtNormalIncidence) {
    const HeightField one = test::flat_field(8, 8, 1.0f);
    const float s = 0.02f;
    const Vec2<float> P{0.3f, 0.7f};
    const EngineResult grazing = literal::unity_parallax_offset(one, s, Vf(89.9, 0), P);
    EXPECT_NEAR(grazing.uv.x - P.x,
                0.5 * s * std::sin(89.9 * M_PI / 180) / (std::cos(89.9 * M_PI / 180) + 0.42), 1e-7);
    EXPECT_LT(grazing.uv.x - P.x, 0.5 * s / 0.42);
    EXPECT_GT(grazing.uv.x - P.x, 0.99 * 0.5 * s / 0.42);
    const EngineResult down = literal::unity_parallax_offset(one, s, Vf(0, 0), P);
    EXPECT_EQ(down.uv.x, P.x);
    EXPECT_EQ(down.uv.y, P.y);
}

// ---- hdrp_pom ----

// Flat fields: regula falsi on a flat field lands on the surface at once (ih = c), so the result
// is exact; fetches = 1 (layer 0) + k* (linear search up to the first layer above the ray) + 1.
TEST(EngineHdrp, FlatFieldIsExactWithFetchCount) {
    const float s = 0.02f;
    for (const double c : {1.0, 0.83, 0.5, 0.13})
        for (const double theta : {10.0, 45.0, 70.0})
            for (const double phi : kPhis) {
                const HeightField hf = test::flat_field(16, 16, float(c));
                const Vec3<float> V = Vf(theta, phi);
                const Vec2<float> P{0.37f, 0.61f};
                const EngineResult r = literal::hdrp_pom(hf, s, V, P);
                expect_uv(r, flat_truth(s, c, 1.0, V, P), 1e-6, "hdrp flat");
                // numSteps = 5 below 82 degrees at s = 0.02: first k with c > 1 - k/5.
                const int kstar = int(std::floor(5 * (1 - c))) + 1;
                EXPECT_EQ(r.fetches, 1 + kstar + 1) << c << " " << theta;
            }
}

// The depth HDRP writes where its LOD fade acts (docs/conventions.md section 8, `engine`):
// ParallaxOcclusionMapping sets outHeight = currHeight (the last probe, at the unfaded offset)
// before offset *= 1 - saturate(lod - lodThreshold), and ApplyPerPixelDisplacement's depth
// offset reads that height. pxh's hdrp_pom hands the same height back (MethodHit::engine_z) and
// its engine formula gives the transcription's depth; the height at the faded uv (what pxh read
// before) differs on most samples.
TEST(EngineHdrp, EngineDepthReadsTheUnfadedProbeWhereTheFadeActs) {
    const HeightField hf = test::random_field(64, 64, 17);
    const float s = 0.05f;
    const auto P = test::random_points(300, 6);
    const MethodInfo& m = test::method("hdrp_pom");
    MethodSpec spec{&m, test::params_for(m)};
    spec.depth = DepthMode::engine;  // the heights are handed back where a depth mode reads them
    MarchConfig c;
    c.depth_offset = MarchConfig::PdoHdrp;
    int moved = 0, checked = 0;
    for (const double theta : {35.0, 60.0, 80.0})
        for (const double phi : kPhis)
            for (const double lambda : {5.25, 5.5, 5.875}) {
                const auto sc = test::make_scene(hf, s, 1.0, theta, phi);
                const std::vector<double> lam(P.size(), lambda);
                const MethodOutput out =
                    run_cpu(spec, "float", sc, hf, P, 0, nullptr, nullptr, nullptr, &lam);
                const Vec3<float> V = Vf(theta, phi);
                const Vec3d Vd(V), f{-Vd.x, -Vd.y, -Vd.z};
                for (size_t i = 0; i < P.size(); ++i) {
                    float outHeight = NAN;
                    const EngineResult r = literal::hdrp_pom(hf, s, V, Vec2<float>(P[i]), 5, 15,
                                                             float(lambda), 5.0f, &outHeight);
                    // float, in another operation order: a few ulps of uv (|uv| < 2), which the
                    // field's slopes turn into up to 10^-5 of height at 80 degrees
                    EXPECT_NEAR(out.uv[i].x, r.uv.x, 4e-6) << i;
                    EXPECT_NEAR(out.uv[i].y, r.uv.y, 4e-6) << i;
                    EXPECT_NEAR(out.engine_z[i], s * (outHeight - 1.0), 1e-5) << theta << " " << i;
                    const EngineDepthInput in{
                        Vec2d(Vec2<float>(P[i])), Vd, f,  out.uv[i], out.hit_z[i],
                        out.engine_z[i],          s,  1.0};
                    EXPECT_NEAR(march_engine_depth(c, in),
                                literal::hdrp_depth_offset(s, outHeight, Vd, f), 1e-4)
                        << theta << " " << i;
                    HeightSampler<double> at_faded(hf, s, 1.0);
                    moved += std::abs(at_faded.z(out.uv[i]) - out.engine_z[i]) > 1e-4;
                    ++checked;
                }
            }
    EXPECT_GT(moved, checked / 4);  // the faded uv's height is another number
}

// The "angle-based" count uses the angle of (s V.xy, V.z), not theta: at s = 0.02 it stays at
// _PPDMinSamples = 5 up to ~82 degrees. On a flat h = 0.05 field the search crosses at the last
// layer n (0.05 > 1 - n/n), so it fetches layers 0 .. n, then one secant fetch lands: n + 2.
// (On h = 0 the count would depend on float rounding: rayHeight, decremented n times, ends a hair
// below or above 0 depending on n, and the search stops at layer n or reads layer n + 1.)
TEST(EngineHdrp, StepCountFollowsTheScaledAngle) {
    const HeightField low = test::flat_field(16, 16, 0.05f);
    const float s = 0.02f;
    const std::pair<double, int> table[] = {{0, 5},  {30, 5}, {60, 5}, {80, 5}, {82, 5},
                                            {84, 6}, {85, 6}, {87, 7}, {88, 8}, {89, 10}};
    for (const auto& [theta, steps] : table) {
        const Vec3<float> V = Vf(theta, 20);
        const Vec2<float> P{0.5f, 0.25f};
        const EngineResult r = literal::hdrp_pom(low, s, V, P);
        EXPECT_EQ(r.fetches, steps + 2) << theta;
        expect_uv(r, flat_truth(s, 0.05f, 1.0, V, P), 2e-6, "hdrp h = 0.05");
    }
    // A larger amplitude makes the count vary: s = 1 at 60 degrees, unitAngle ~ 0.67, 11 steps.
    const EngineResult big = literal::hdrp_pom(low, 1.0f, Vf(60, 0), {0.5f, 0.5f});
    EXPECT_EQ(big.fetches, 11 + 2);
}

// Random fields: the result lies inside the bracket found by the linear search (layers k*-1 and
// k*), the secant used 1..3 fetches, and it stops early only when |rayHeight - h| <= 0.01. When
// three iterations do not converge the function returns the last evaluated offset, so some
// results are off the surface by more than the tolerance: count them.
TEST(EngineHdrp, RegulaFalsiBracketToleranceAndLastOffset) {
    const HeightField hf = test::random_field(64, 64, 103);
    const auto pts = test::random_points(500, 104);
    int unconverged = 0, total = 0;
    for (const float s : {0.02f, 0.1f})
        for (const double theta : {30.0, 60.0, 80.0})
            for (const double phi : kPhis) {
                const Vec3<float> V = Vf(theta, phi);
                const Vec3d vuv = {s * double(V.x), s * double(V.y), double(V.z)};
                const double l = std::sqrt(vuv.x * vuv.x + vuv.y * vuv.y + vuv.z * vuv.z);
                const double acos_fast = [&] {
                    const double x = vuv.z / l;
                    return ((0.0468878 * x - 0.203471) * x + 1.570796) * std::sqrt(1 - x);
                }();
                const int n = int(5 + 10 * std::min(1.0, acos_fast * 2 / M_PI));
                const Vec2d maxoff = {-s * double(V.x) / V.z, -s * double(V.y) / V.z};
                for (const Vec2d& Pd : pts) {
                    const Vec2<float> P(Pd);
                    const EngineResult r = literal::hdrp_pom(hf, s, V, P);
                    HeightSampler<double> hs(hf, 1, 0);
                    int kstar = n + 1;  // first layer k >= 1 with h > 1 - k/n (tested up to n)
                    bool tie = false;   // a layer within float reach of its bound: skip
                    for (int k = 1; k <= n; ++k) {
                        const Vec2d q = {P.x + k * maxoff.x / n, P.y + k * maxoff.y / n};
                        const double g = hs.height(q) - (1.0 - double(k) / n);
                        tie = tie || std::abs(g) < 1e-5;
                        if (g > 0) {
                            kstar = k;
                            break;
                        }
                    }
                    if (tie || kstar > n) continue;  // kstar > n: no crossing, unbracketed
                    const int secant = r.fetches - 1 - kstar;
                    EXPECT_GE(secant, 1);
                    EXPECT_LE(secant, 3);
                    // t = fraction of maxOffset travelled, ih = 1 - t
                    const double t = std::abs(maxoff.x) > std::abs(maxoff.y)
                                         ? (r.uv.x - P.x) / maxoff.x
                                         : (r.uv.y - P.y) / maxoff.y;
                    EXPECT_GE(t, (kstar - 1.0) / n - 1e-4);
                    EXPECT_LE(t, double(kstar) / n + 1e-4);
                    const double delta = (1 - t) - hs.height(Vec2d(r.uv));
                    if (secant < 3) {
                        EXPECT_LE(std::abs(delta), 0.01 + 1e-4);
                    }
                    unconverged += std::abs(delta) > 0.0101;
                    ++total;
                }
            }
    EXPECT_GT(total, 10000);
    std::printf("hdrp: %d of %d off the surface by more than 0.01\n", unconverged, total);
    EXPECT_GT(unconverged, 0);  // the last evaluated offset is returned, not re-interpolated
}

// ---- jme_parallax ----

// Any field: uv = P + s (h(P) - 0.6) V.z V.xy: a multiply by V.z where the classic method
// divides; the offset is largest at 45 degrees and vanishes at grazing angles.
TEST(EngineJme, ClassicClosedFormMultipliesByVz) {
    const HeightField hf = test::random_field(64, 64, 105);
    const float s = 0.05f;
    test::expect_one_fetch_offset(
        literal::jme_parallax, hf, s, test::random_points(100, 106), kThetas, kPhis,
        [&](double h, Vec3<float> V) { return s * (h - 0.6) * V.z; }, 5e-7, "jme classic");
    const HeightField one = test::flat_field(8, 8, 1.0f);
    auto off = [&](double theta) {
        return literal::jme_parallax(one, s, Vf(theta, 0), {0.5f, 0.5f}).uv.x - 0.5;
    };
    EXPECT_NEAR(off(45), 0.4 * s * 0.5, 1e-7);  // s (1 - 0.6) sin cos
    EXPECT_LT(off(85), 0.2 * off(45));
    EXPECT_NEAR(off(30), off(60), 1e-7);
}

// ---- jme_steep ----

double jme_n(double s, Vec3<float> V) { return 6 + (1000 * s - 6) * (1 - double(V.z)); }

// Flat fields that the first layer does not reach: the line fit through two equal heights is
// exact; fetches = first k with c > 1 - k/n.
TEST(EngineJme, SteepFlatFieldExactBelowFirstLayer) {
    const float s = 0.015f;  // 0.3 * ParallaxHeight 0.05
    for (const double c : {0.8, 0.5, 0.27})
        for (const double theta : {10.0, 45.0, 70.0, 85.0})
            for (const double phi : kPhis) {
                const HeightField hf = test::flat_field(16, 16, float(c));
                const Vec3<float> V = Vf(theta, phi);
                const Vec2<float> P{0.42f, 0.18f};
                const double n = jme_n(s, V);
                ASSERT_LE(c, 1 - 1 / n);
                const EngineResult r = literal::jme_steep(hf, s, V, P);
                expect_uv(r, flat_truth(s, c, 1.0, V, P), 4e-6, "jme steep flat");
                EXPECT_EQ(r.fetches, int(std::floor(n * (1 - c))) + 1) << c << " " << theta;
            }
}

// Defect: the first step compares against a previous height of 0 (fPrevHeight takes fCurrHeight
// = 0.0 before the first sample; P itself is never sampled). On a flat h = 1 field the loop stops
// at layer 1 and the fit through (1, 0) and (1 - 1/n, 1) gives amount = n/(n+1): the result is
// P - s V.xy / V.z / (n + 1) instead of P. In general, when layer 1 hits, amount = h1/(h1 + 1/n).
TEST(EngineJme, SteepFirstStepComparesAgainstZero) {
    const float s = 0.015f;
    const HeightField one = test::flat_field(16, 16, 1.0f);
    for (const double theta : {10.0, 45.0, 70.0, 85.0}) {
        const Vec3<float> V = Vf(theta, 30);
        const Vec2<float> P{0.3f, 0.6f};
        const double n = jme_n(s, V);
        const EngineResult r = literal::jme_steep(one, s, V, P);
        const double k = -s / V.z / (n + 1);
        expect_uv(r, {P.x + k * V.x, P.y + k * V.y}, 1e-6, "jme h = 1");
        EXPECT_GT(std::hypot(r.uv.x - P.x, r.uv.y - P.y), 1e-4);  // visibly not P
        EXPECT_EQ(r.fetches, 1);
    }
    // Random high field: wherever the loop stopped at layer 1, h(P) plays no part.
    const HeightField hf = test::random_field(64, 64, 107, 0.9f, 1.0f);
    int hits = 0;
    for (const Vec2d& Pd : test::random_points(300, 108)) {
        const Vec3<float> V = Vf(60, 75);
        const Vec2<float> P(Pd);
        const EngineResult r = literal::jme_steep(hf, s, V, P);
        if (r.fetches != 1) continue;
        ++hits;
        const double n = jme_n(s, V);
        const Vec2d off = {s * double(V.x) / V.z, s * double(V.y) / V.z};
        HeightSampler<double> hs(hf, 1, 0);
        const double h1 = hs.height({P.x - off.x / n, P.y - off.y / n});
        const double amount = h1 / (h1 + 1 / n);
        expect_uv(r, {P.x - off.x * (1 - amount), P.y - off.y * (1 - amount)}, 1e-6, "jme rnd");
    }
    EXPECT_GT(hits, 100);
}

// n = mix(6, 1000 s, 1 - V.z) stays real and depends on the scale: at s = 0.015 it grows from 6
// to ~14.2 at 85 degrees; at s = 0.005 (1000 s < 6) it falls toward grazing angles. Pinned by the
// fetch count on a flat h = 0.05 field: first k > 0.95 n.
TEST(EngineJme, SteepSampleCountDependsOnScale) {
    const HeightField hf = test::flat_field(16, 16, 0.05f);
    const std::tuple<float, double, int> table[] = {
        {0.015f, 10, 6}, {0.015f, 60, 10}, {0.015f, 85, 14},  // n 6.01, 10.5, 14.2
        {0.005f, 10, 6}, {0.005f, 60, 6},  {0.005f, 85, 5},   // n 5.98, 5.5, 5.09
    };
    for (const auto& [s, theta, fetches] : table) {
        const EngineResult r = literal::jme_steep(hf, s, Vf(theta, 0), {0.5f, 0.5f});
        EXPECT_EQ(r.fetches, fetches) << s << " " << theta;
    }
}

// At theta = 0, normalize(vViewDir.xy) = normalize(vec2(0)): the engine's result is NaN.
TEST(EngineJme, SteepIsNaNStraightDown) {
    const HeightField hf = test::random_field(16, 16, 109);
    const EngineResult r = literal::jme_steep(hf, 0.015f, Vf(0, 0), {0.5f, 0.5f});
    EXPECT_TRUE(std::isnan(r.uv.x));
    EXPECT_TRUE(std::isnan(r.uv.y));
}

// ---- ogre_parallax ----

// Any field: pxh parallax with b = 1, uv = P + s (h(P) - 1) V.xy / V.z (the "Inverse y" undoes
// OGRE's binormal toward -v).
TEST(EngineOgre, ParallaxClosedForm) {
    const HeightField hf = test::random_field(64, 64, 110);
    const float s = 0.04f;
    test::expect_one_fetch_offset(
        literal::ogre_parallax, hf, s, test::random_points(100, 111), kThetas, kPhis,
        [&](double h, Vec3<float> V) { return s * (h - 1.0) / V.z; }, 1e-6, "ogre parallax");
}

// ---- ogre_pom ----

// Flat h = c: the sample at P - k delta (delta = s V.xy / 32, no division by V.z) is compared
// with layer depth (k - 1)/32 (one-step lag). For c > 1/32 the loop breaks at k = floor(32 (1 -
// c)) + 2 and the interpolation returns P - delta - s (1 - c) V.xy: exact POM of a relief s V.z
// thick (sin theta step), shifted by one step. For c <= 1/32 it never breaks and returns
// P - s (1 - c) V.xy. Fetches: 1 dead + k + 1 re-fetch.
TEST(EngineOgre, PomOneStepLagAndSinThetaStep) {
    const float s = 0.04f;
    for (const double c : {1.0, 0.75, 0.4, 0.1, 0.02, 0.0})
        for (const double theta : {10.0, 45.0, 70.0, 85.0})
            for (const double phi : kPhis) {
                const HeightField hf = test::flat_field(16, 16, float(c));
                const Vec3<float> V = Vf(theta, phi);
                const Vec2<float> P{0.55f, 0.45f};
                const EngineResult r = literal::ogre_pom(hf, s, V, P);
                const bool breaks = c > 1.0 / 32;
                const double k = breaks ? -(1.0 / 32 + (1 - c)) * s : -(1 - c) * s;
                expect_uv(r, {P.x + k * V.x, P.y + k * V.y}, 4e-6, "ogre pom");
                const int kb = breaks ? int(std::floor(32 * (1 - c))) + 2 : 32;
                EXPECT_EQ(r.fetches, 1 + kb + 1) << c << " " << theta;
            }
    // The lag on a flat h = 1 field: P - delta where the surface is at P.
    const HeightField one = test::flat_field(8, 8, 1.0f);
    const Vec3<float> V = Vf(60, 0);
    const EngineResult r = literal::ogre_pom(one, s, V, {0.5f, 0.5f});
    EXPECT_NEAR(r.uv.x, 0.5 - s * V.x / 32, 3e-7);
    EXPECT_NEAR(r.uv.x, 0.5 - 0.04 * std::sin(M_PI / 3) / 32, 3e-7);
}

// No break and after - before = 0: h(uv_32) = 0 and h(uv_31) = 1/32 give weight 0/0 = NaN. The
// field holds 1/32 on texels 16..63 and 0 on texels 0..15 (every height <= 1/32, so the loop
// never breaks); s = 2 at 60 degrees makes delta 3.5 texels so that uv_31 and uv_32 fall on the
// two plateaus (x = P - k delta: uv_31 at 0.274, uv_32 at 0.220 modulo 1).
TEST(EngineOgre, PomNaNWithoutBreak) {
    HeightField hf(64, 4, "steps");
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 64; ++i) hf.at(i, j) = i >= 16 ? 1.0f / 32 : 0.0f;
    const Vec3<float> V = Vf(60, 0);
    const float s = 2.0f;
    const Vec2<float> P{0.952f, 0.5f};
    const float delta = s * V.x / 32;
    const float x31 = P.x - 31 * delta + 1, x32 = P.x - 32 * delta + 1;
    ASSERT_GT(x31, 16.5f / 64);
    ASSERT_LT(x31, 63.5f / 64);
    ASSERT_GT(x32, 0.5f / 64);
    ASSERT_LT(x32, 15.5f / 64);
    const EngineResult r = literal::ogre_pom(hf, s, V, P);
    EXPECT_TRUE(std::isnan(r.uv.x));
    EXPECT_EQ(r.fetches, 1 + 32 + 1);
    // One texel further the weight is finite again.
    const EngineResult ok = literal::ogre_pom(hf, s, V, {P.x + 0.03f, P.y});
    EXPECT_TRUE(std::isfinite(ok.uv.x));
}

// ---- dxsdk_pom ----

int dx_n(Vec3<float> V) { return int(50 + (8 - 50) * double(V.z)); }

// Flat fields below the first layer: exact (the line fit of two equal heights); fetches = first
// k with c > 1 - k/n, n = int(lerp(50, 8, V.z)). h = 0: no crossing, the zero-denominator guard
// gives amount 0 and the bottom point P - s V.xy / V.z after n fetches.
TEST(EngineDxsdk, FlatFieldExactBelowFirstLayer) {
    const float s = 0.02f;
    for (const double c : {0.853, 0.537, 0.291, 0.113, 0.0})
        for (const double theta : {10.0, 45.0, 70.0, 85.0})
            for (const double phi : kPhis) {
                const HeightField hf = test::flat_field(16, 16, float(c));
                const Vec3<float> V = Vf(theta, phi);
                const Vec2<float> P{0.21f, 0.77f};
                const int n = dx_n(V);
                ASSERT_LE(c, 1 - 1.0 / n);
                const EngineResult r = literal::dxsdk_pom(hf, s, V, P);
                expect_uv(r, flat_truth(s, c, 1.0, V, P), 2e-6, "dxsdk flat");
                const int k = c == 0 ? n : int(std::floor(n * (1 - c))) + 1;
                EXPECT_EQ(r.fetches, k) << c << " " << theta;
            }
}

// The sample count n = int(lerp(g_nMaxSamples 50, g_nMinSamples 8, V.z)), truncated, pinned by
// the fetch count on a flat h = 0.3 field (first k > 0.7 n).
TEST(EngineDxsdk, SampleCountIsTruncatedLerp) {
    const HeightField hf = test::flat_field(16, 16, 0.3f);
    const std::pair<double, int> table[] = {{10, 6}, {60, 21}, {85, 33}};  // n = 8, 29, 46
    for (const auto& [theta, fetches] : table) {
        const EngineResult r = literal::dxsdk_pom(hf, 0.02f, Vf(theta, 0), {0.5f, 0.5f});
        EXPECT_EQ(r.fetches, fetches) << theta;
    }
}

// Defect: fPrevHeight starts at 1.0, so when layer 1 already hits, pt2 = (1, 1), fDelta2 = 0 and
// the amount is exactly 1: the result is P itself, whatever the height. On a flat h = 0.99 field
// at 60 degrees (n = 29, layer 1 at 0.9655) the surface is at P - 0.01 s V.xy / V.z.
TEST(EngineDxsdk, FirstStepPreviousHeightOneReturnsP) {
    for (const float c : {0.99f, 1.0f, 0.97f}) {
        const HeightField hf = test::flat_field(16, 16, c);
        const Vec3<float> V = Vf(60, 123);
        const Vec2<float> P{0.33f, 0.66f};
        const EngineResult r = literal::dxsdk_pom(hf, 0.02f, V, P);
        EXPECT_EQ(r.uv.x, P.x) << c;
        EXPECT_EQ(r.uv.y, P.y) << c;
        EXPECT_EQ(r.fetches, 1);
    }
    // Just below layer 1 the result is exact again: a jump of s (1 - 28/29) tan(theta).
    const HeightField below = test::flat_field(16, 16, 0.96f);
    const Vec3<float> V = Vf(60, 123);
    const EngineResult r = literal::dxsdk_pom(below, 0.02f, V, {0.33f, 0.66f});
    expect_uv(r, flat_truth(0.02, 0.96f, 1.0, V, {0.33f, 0.66f}), 1e-6, "dxsdk 0.96");
    EXPECT_EQ(r.fetches, 2);
}

// At theta = 0, normalize(vViewTS.xy) is NaN: so is the engine's uv.
TEST(EngineDxsdk, NaNStraightDown) {
    const HeightField hf = test::random_field(16, 16, 112);
    const EngineResult r = literal::dxsdk_pom(hf, 0.02f, Vf(0, 0), {0.5f, 0.5f});
    EXPECT_TRUE(std::isnan(r.uv.x));
    EXPECT_EQ(r.fetches, 8);  // n = int(lerp(50, 8, 1)) = 8, no layer crossed with NaN uv
}

// ---- Phase 2: each preset (the marcher, CPU float) against the engine's literal loop ----

using test::method;

using test::method;

// White noise, and the same noise with its lower half set to 0 (black regions: about 1/16 of
// the bilinear field is exactly 0, where the searches find no crossing and the engines' miss
// paths run).
HeightField noise_field() { return test::random_field(128, 128, 201); }
HeightField black_field() {
    HeightField hf = test::random_field(128, 128, 207);
    for (auto& h : hf.texels) h = std::max(0.0f, 2 * h - 1);
    hf.name = "half black";
    return hf;
}

// The height where the ray leaves the slab (b = 1): P - s V.xy / V.z.
double bottom_height(const HeightField& hf, const Scene<double>& sc, Vec2d P) {
    HeightSampler<double> hs(hf, 1, 0);
    return hs.height({P.x - sc.scale * sc.V.x / sc.V.z, P.y - sc.scale * sc.V.y / sc.V.z});
}

// Both fields, 1500 random points, theta 10..85 and several phi, at the engine's default scale
// and larger ones. `bottom_ties`: a fetch count one apart where the height at the slab bottom is
// 0 is a tie (see HdrpPomMatchesLiteral).
void compare_with_literal(const char* name, const test::Literal& lit, double b,
                          std::vector<float> scales, bool bottom_ties = false) {
    ASSERT_EQ(method(name).required_bias, b) << name;
    test::LiteralSweep sw;
    sw.fields = {noise_field(), black_field()};
    sw.scales = std::move(scales);
    sw.points = 1500;
    if (bottom_ties)
        sw.fetch_tie = [](const HeightField& hf, const Scene<double>& sc, Vec2d P) {
            return bottom_height(hf, sc, P) == 0;
        };
    test::expect_preset_matches(name, lit, sw);
}

TEST(EnginePresets, UnityParallaxOffsetMatchesLiteral) {
    compare_with_literal("unity_parallax_offset", literal::unity_parallax_offset, 0.5,
                         {0.02f, 0.005f, 0.08f});
}
// At the engine's s = 0.02 and 0.03. Beyond, at 85 degrees, the regula falsi amplifies float
// rounding: each probe moves by (ih error) x (ray length in texels) x (noise slope), and at s =
// 0.08 the ray crosses ~120 texels of white noise, so ~2% of those samples end 1e-3..0.2 texel
// apart with the same fetch count (the marcher computes a probe's uv from the layer index, the
// engine from (1 - ih) numSteps texOffsetPerStep). Where h = 0 exactly at layer numSteps (black
// regions), the engine's rayHeight, decremented numSteps times, ends a hair below 0 for some
// numSteps (6 at 85 degrees) and stops there; the marcher's ray is exactly at the bottom there, so
// it reads layer numSteps + 1 as well (one fetch more, the same uv), or the other way round: where
// the height at the slab bottom is 0, a fetch count one apart is counted apart (and printed).
TEST(EnginePresets, HdrpPomMatchesLiteral) {
    compare_with_literal("hdrp_pom", PXH_LITERAL(literal::hdrp_pom), 1.0, {0.02f, 0.03f}, true);
}
TEST(EnginePresets, JmeMatchesLiteral) {
    compare_with_literal("jme_parallax", literal::jme_parallax, 0.6, {0.05f, 0.1f});
    compare_with_literal("jme_steep", literal::jme_steep, 1.0, {0.015f, 0.005f, 0.03f});
}
TEST(EnginePresets, OgreMatchesLiteral) {
    compare_with_literal("ogre_parallax", literal::ogre_parallax, 1.0, {0.04f, 0.1f});
    compare_with_literal("ogre_pom", literal::ogre_pom, 1.0, {0.04f, 0.1f});
}
TEST(EnginePresets, DxsdkPomMatchesLiteral) {
    compare_with_literal("dxsdk_pom", PXH_LITERAL(literal::dxsdk_pom), 1.0, {0.02f, 0.1f});
}

// Straight down the two engines that normalise V.xy give NaN (pinned above); their presets
// return P there, as the limit theta -> 0 of the engines' results does.
TEST(EnginePresets, StraightDownPresetsReturnPWhereTheEnginesGiveNaN) {
    const HeightField hf = test::random_field(32, 32, 203);
    const auto P = test::random_points(50, 204);
    for (const char* name : {"jme_steep", "dxsdk_pom"}) {
        const auto sc = test::make_scene(hf, 0.02, 1.0, 0.0, 0.0);
        const auto uv =
            test::run_method<float>(method(name), test::params_for(method(name)), sc, hf, P);
        for (size_t i = 0; i < P.size(); ++i) {
            EXPECT_NEAR(uv[i].x, P[i].x, 1e-7) << name;
            EXPECT_NEAR(uv[i].y, P[i].y, 1e-7) << name;
        }
    }
}

// The engine parameters reach the marcher: DirectX's g_nMinSamples / g_nMaxSamples and HDRP's
// _PPDMinSamples / _PPDMaxSamples, against the literal loops with the same values.
TEST(EnginePresets, EngineParametersReachTheMarcher) {
    const HeightField hf = test::random_field(64, 64, 205);
    const auto P = test::random_points(400, 206);
    int total = 0, off = 0;
    for (const double theta : {20.0, 60.0, 80.0}) {
        const auto sc = test::make_scene(hf, 0.05, 1.0, theta, 30);
        const auto dx = test::run_method<float>(
            method("dxsdk_pom"),
            test::params_for(method("dxsdk_pom"), {{"g_nMinSamples", 12}, {"g_nMaxSamples", 100}}),
            sc, hf, P);
        const auto hd = test::run_method<float>(
            method("hdrp_pom"),
            test::params_for(method("hdrp_pom"), {{"_PPDMinSamples", 16}, {"_PPDMaxSamples", 64}}),
            sc, hf, P);
        for (size_t i = 0; i < P.size(); ++i) {
            const Vec3<float> V(sc.V);
            const EngineResult a = literal::dxsdk_pom(hf, 0.05f, V, Vec2<float>(P[i]), 12, 100);
            const EngineResult h = literal::hdrp_pom(hf, 0.05f, V, Vec2<float>(P[i]), 16, 64);
            off += !(std::hypot(dx[i].x - a.uv.x, dx[i].y - a.uv.y) * 64 <= 1e-3);
            off += !(std::hypot(hd[i].x - h.uv.x, hd[i].y - h.uv.y) * 64 <= 1e-3);
            total += 2;
        }
    }
    EXPECT_LE(off, total / 1000);
}

}  // namespace
}  // namespace pxh
