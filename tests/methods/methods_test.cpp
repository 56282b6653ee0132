// Each seed method against closed forms and literal transcriptions of its source.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "harness/metrics/metrics.h"
#include "harness/truth/ground_truth.h"
#include "methods/layered.h"
#include "tests/test_util.h"

namespace pxh {
namespace {

using test::make_scene;
using test::params_for;
using test::run_method;

using test::method;

double offset_length(Vec2d uv, Vec2d P) { return std::hypot(uv.x - P.x, uv.y - P.y); }

TEST(Parallax, PlanarSlopeRelativeErrorIsGradientTimesTan) {
    const int W = 512;
    HeightField hf(W, 4);
    const double k = 0.8;  // dh/du over most of the tile (a cliff at the wrap)
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < W; ++i) hf.at(i, j) = float(0.1 + k * (i + 0.5) / W);
    const double s = 0.05;
    const double g = s * k;
    for (double theta : {30.0, 45.0, 60.0}) {
        const auto sc = make_scene(hf, s, 0.0, theta, 0);  // b = 0: relief above, offset +x
        const ExactTracer tr(hf, s, 0.0);
        for (double px : {0.3, 0.5, 0.6}) {
            const Vec2d P{px, 0.5};
            const Vec2d uv = run_method<double>(method("parallax"), {}, sc, hf, {P})[0];
            const Vec2d truth = tr.trace(P, sc.V).uv;
            const double rel =
                (offset_length(uv, P) - offset_length(truth, P)) / offset_length(truth, P);
            // Heights are stored as float: the slope itself is exact only to ~1e-7.
            EXPECT_NEAR(std::abs(rel), g * std::tan(theta * M_PI / 180), 1e-6) << theta;
        }
    }
}

TEST(ParallaxLimited, FlatFieldRelativeErrorIsOneMinusCos) {
    const HeightField hf = test::flat_field(16, 16, 0.2f);
    for (double theta : {10.0, 45.0, 70.0, 85.0}) {
        const auto sc = make_scene(hf, 0.05, 1.0, theta, 40);
        const ExactTracer tr(hf, 0.05, 1.0);
        const Vec2d P{0.4, 0.6};
        const Vec2d uv = run_method<double>(method("parallax_limited"), {}, sc, hf, {P})[0];
        const Vec2d truth = tr.trace(P, sc.V).uv;
        const double rel = 1 - offset_length(uv, P) / offset_length(truth, P);
        EXPECT_NEAR(rel, 1 - std::cos(theta * M_PI / 180), 1e-12);
    }
}

// Kaneko 2001: u' = u + tan(theta_u) depth(u, v), v' likewise, theta measured for the
// viewing direction e = -V in the (u, n) and (v, n) planes, depth below the polygon = -z.
TEST(Parallax, IdenticalToKanekosOriginal) {
    const HeightField hf = test::random_field(64, 64, 9);
    for (double theta : {15.0, 50.0, 80.0}) {
        const auto sc = make_scene(hf, 0.05, 1.0, theta, 123);
        const auto P = test::random_points(200, 2);
        const auto uv = run_method<double>(method("parallax"), {}, sc, hf, P);
        HeightSampler<double> hs(hf, 0.05, 1.0);
        const Vec3d e{-sc.V.x, -sc.V.y, -sc.V.z};
        const double tan_u = e.x / -e.z, tan_v = e.y / -e.z;
        for (size_t i = 0; i < P.size(); ++i) {
            const double depth = -hs.z(P[i]);
            EXPECT_NEAR(uv[i].x, P[i].x + tan_u * depth, 1e-15);
            EXPECT_NEAR(uv[i].y, P[i].y + tan_v * depth, 1e-15);
        }
    }
}

TEST(ParallaxClamped, HugeClampIsParallaxZeroClampIsNone) {
    const HeightField hf = test::random_field(32, 32, 4);
    const auto sc = make_scene(hf, 0.05, 0.5, 75, 10);
    const auto P = test::random_points(300, 3);
    const auto par = run_method<float>(method("parallax"), {}, sc, hf, P);
    const auto huge =
        run_method<float>(method("parallax_clamped"),
                          params_for(method("parallax_clamped"), {{"max_offset", 1e6}}), sc, hf, P);
    const auto zero =
        run_method<float>(method("parallax_clamped"),
                          params_for(method("parallax_clamped"), {{"max_offset", 0}}), sc, hf, P);
    for (size_t i = 0; i < P.size(); ++i) {
        EXPECT_EQ(huge[i].x, par[i].x);
        EXPECT_EQ(huge[i].y, par[i].y);
        EXPECT_EQ(zero[i].x, float(P[i].x));
        EXPECT_EQ(zero[i].y, float(P[i].y));
    }
    // Default m = s: every offset component within s.
    const auto def = run_method<double>(method("parallax_clamped"),
                                        params_for(method("parallax_clamped")), sc, hf, P);
    double largest = 0;
    for (size_t i = 0; i < P.size(); ++i)
        largest = std::max({largest, std::abs(def[i].x - P[i].x), std::abs(def[i].y - P[i].y)});
    EXPECT_LE(largest, 0.05 + 1e-15);
    EXPECT_GT(largest, 0.05 * 0.99);  // at 75 degrees the clamp is reached
}

TEST(ParallaxHalved, HalfTheClassicOffset) {
    const HeightField hf = test::random_field(32, 32, 5);
    const auto sc = make_scene(hf, 0.05, 1.0, 60, 30);
    const auto P = test::random_points(100, 4);
    const auto full = run_method<double>(method("parallax"), {}, sc, hf, P);
    const auto half = run_method<double>(method("parallax_halved"), {}, sc, hf, P);
    for (size_t i = 0; i < P.size(); ++i) {
        EXPECT_NEAR(half[i].x - P[i].x, 0.5 * (full[i].x - P[i].x), 1e-15);
        EXPECT_NEAR(half[i].y - P[i].y, 0.5 * (full[i].y - P[i].y), 1e-15);
    }
}

// The layer search stops at the first layer at or below the surface: check k against every
// layer's g computed independently.
TEST(Pom, LayerSearchStopsAtFirstLayerAtOrBelowSurface) {
    const HeightField hf = test::random_field(64, 64, 6);
    const auto sc = make_scene(hf, 0.05, 1.0, 70, 15);
    const LayerConfig cfg = layer_config(params_for(method("pom"), {{"layers", 16}}), "test");
    for (const Vec2d P : test::random_points(300, 7)) {
        HeightSampler<double> hs(hf, 0.05, 1.0);
        const LayerSearch<double> r = layer_search(cfg, sc, hs, P);
        int first = -1;
        for (int k = 0; k <= 16 && first < 0; ++k) {
            HeightSampler<double> probe(hf, 0.05, 1.0);
            // b = 1: z_top = 0, so uv_0 = P and layer k sits at z = -k s / n.
            const double dz = 0.05 / 16;
            const Vec2d uvk{P.x - k * dz * sc.V.x / sc.V.z, P.y - k * dz * sc.V.y / sc.V.z};
            if (-k * dz - probe.z(uvk) <= 0) first = k;
        }
        EXPECT_EQ(r.k, first);
        EXPECT_EQ(hs.fetches, r.k + 1);
    }
}

TEST(Steep, FlatFieldErrorIsDistanceToFirstLayerBelow) {
    const float level = 0.61f;
    const HeightField hf = test::flat_field(64, 64, level);
    const double s = 0.05, n = 10;
    for (double theta : {30.0, 60.0, 80.0}) {
        const auto sc = make_scene(hf, s, 1.0, theta, 0);
        const Vec2d P{0.5, 0.5};
        const Vec2d uv = run_method<double>(
            method("steep"), params_for(method("steep"), {{"layers", n}}), sc, hf, {P})[0];
        const double d = s * (1 - double(level)), dz = s / n;
        const double k = std::ceil(d / dz);
        const double expect_uv = (k * dz - d) * std::tan(theta * M_PI / 180);
        const Vec2d truth = ExactTracer(hf, s, 1.0).trace(P, sc.V).uv;
        EXPECT_NEAR(truth.x - uv.x, expect_uv, 1e-12) << theta;  // steep overshoots to -x
    }
}

// On flat fields the bracket [k-1, k] holds the truth at a fraction f of a layer; after m
// steps relief returns the midpoint of an interval of width 2^-m containing it. With f
// spread uniformly (many levels), the mean error is layer * 2^-m / 4: it halves per step.
TEST(Relief, FlatFieldErrorHalvesPerBinaryStep) {
    const double s = 0.1, theta = 75;
    const int n = 8;
    const double layer_texels = s / n * std::tan(theta * M_PI / 180) * 256;
    std::vector<double> mean_err;
    for (int steps = 0; steps <= 8; ++steps) {
        double sum = 0;
        const int levels = 400;
        for (int l = 0; l < levels; ++l) {
            const float level = 0.02f + 0.96f * (l + 0.5f) / levels;
            const HeightField hf = test::flat_field(256, 256, level);
            const auto sc = make_scene(hf, s, 1.0, theta, 0);
            const Vec2d P{0.3, 0.6};
            const Vec2d uv = run_method<double>(
                method("relief"),
                params_for(method("relief"), {{"layers", n}, {"binary_steps", steps}}), sc, hf,
                {P})[0];
            const Vec2d e = texel_error(uv, ExactTracer(hf, s, 1.0).trace(P, sc.V).uv, 256, 256);
            const double err = std::hypot(e.x, e.y);
            EXPECT_LE(err, layer_texels * std::pow(0.5, steps + 1) + 1e-9) << steps;
            sum += err;
        }
        mean_err.push_back(sum / levels);
        EXPECT_NEAR(mean_err.back(), layer_texels * std::pow(0.5, steps) / 4,
                    0.1 * layer_texels * std::pow(0.5, steps) / 4)
            << steps;
    }
    for (int m = 1; m <= 8; ++m) EXPECT_NEAR(mean_err[m - 1] / mean_err[m], 2.0, 0.3) << m;
}

TEST(Layered, AdaptiveLayerCountIsTutorialMix) {
    const LayerConfig c =
        layer_config(params_for(method("pom"), {{"layers_min", 8}, {"layers_max", 32}}), "t");
    for (double theta : {0.0, 30.0, 60.0, 89.0}) {
        Scene<double> sc;
        sc.V = view_vector(theta, 0);
        const double a = std::abs(sc.V.z);
        EXPECT_NEAR(layer_count(c, sc), 32 * (1 - a) + 8 * a, 1e-12);
        EXPECT_EQ(max_layer_index(c, sc), int(std::ceil(32 * (1 - a) + 8 * a - 1e-12)));
    }
    EXPECT_DOUBLE_EQ(layer_count(c, Scene<double>{}), 8.0);  // straight down: n_min
}

// Fetch counts match the table in docs/conventions.md section 8: pom/steep k + 1, relief k + 1 +
// n_binary (k >= 1).
TEST(Layered, FetchCountsMatchTable) {
    const HeightField hf = test::random_field(64, 64, 12, 0.0f, 0.9f);  // never k = 0
    const auto sc = make_scene(hf, 0.05, 1.0, 60, 0);
    const auto P = test::random_points(200, 13);
    const LayerConfig cfg = layer_config(params_for(method("pom")), "t");
    std::vector<int> f_steep, f_pom, f_relief;
    run_method<double>(method("steep"), params_for(method("steep")), sc, hf, P, &f_steep);
    run_method<double>(method("pom"), params_for(method("pom")), sc, hf, P, &f_pom);
    run_method<double>(method("relief"), params_for(method("relief")), sc, hf, P, &f_relief);
    for (size_t i = 0; i < P.size(); ++i) {
        HeightSampler<double> hs(hf, 0.05, 1.0);
        const int k = layer_search(cfg, sc, hs, P[i]).k;
        ASSERT_GE(k, 1);
        EXPECT_EQ(f_steep[i], k + 1);
        EXPECT_EQ(f_pom[i], k + 1);
        EXPECT_EQ(f_relief[i], k + 1 + 5);
    }
}

// ---- Literal transcriptions of the tutorial's GLSL (depth maps, b = 1), in float ----
struct TutorialOut {
    Vec2<float> steep, pom, relief;
};

TutorialOut tutorial_glsl(const HeightField& hf, float height_scale, Vec3<float> viewDir,
                          Vec2<float> texCoords) {
    HeightSampler<float> hs(hf, 1.0f, 0.0f);
    auto depthMap = [&](Vec2<float> uv) { return 1.0f - hs.height(uv); };
    const float minLayers = 8.0f, maxLayers = 32.0f;
    const float a = std::abs(viewDir.z);
    const float numLayers = maxLayers * (1 - a) + minLayers * a;  // mix(maxLayers, minLayers, a)
    const float layerDepth = 1.0f / numLayers;
    float currentLayerDepth = 0.0f;
    const Vec2<float> P = viewDir.xy() * (1.0f / viewDir.z * height_scale);
    const Vec2<float> deltaTexCoords = P * (1.0f / numLayers);
    Vec2<float> currentTexCoords = texCoords;
    float currentDepthMapValue = depthMap(currentTexCoords);
    while (currentLayerDepth < currentDepthMapValue) {
        currentTexCoords = currentTexCoords - deltaTexCoords;
        currentDepthMapValue = depthMap(currentTexCoords);
        currentLayerDepth += layerDepth;
    }
    TutorialOut out;
    out.steep = currentTexCoords;
    // Parallax Occlusion Mapping
    const Vec2<float> prevTexCoords = currentTexCoords + deltaTexCoords;
    const float afterDepth = currentDepthMapValue - currentLayerDepth;
    const float beforeDepth = depthMap(prevTexCoords) - currentLayerDepth + layerDepth;
    const float weight = afterDepth / (afterDepth - beforeDepth);
    out.pom = prevTexCoords * weight + currentTexCoords * (1.0f - weight);
    // Relief Parallax Mapping: halve, step back from T3, then 5 binary-search iterations.
    Vec2<float> deltaTex = deltaTexCoords * 0.5f;
    float deltaLayerDepth = layerDepth * 0.5f;
    Vec2<float> cur = currentTexCoords + deltaTex;
    float curLayerDepth = currentLayerDepth - deltaLayerDepth;
    for (int i = 0; i < 5; ++i) {
        const float d = depthMap(cur);
        deltaTex = deltaTex * 0.5f;
        deltaLayerDepth *= 0.5f;
        if (d > curLayerDepth) {
            cur = cur - deltaTex;
            curLayerDepth += deltaLayerDepth;
        } else {
            cur = cur + deltaTex;
            curLayerDepth -= deltaLayerDepth;
        }
    }
    out.relief = cur;
    return out;
}

TEST(Layered, MatchTutorialGlslTranscription) {
    // Depths > 0 everywhere so no sample stops at layer 0 (the tutorial's POM divides 0/0 there).
    const HeightField hf = test::random_field(128, 128, 14, 0.0f, 0.97f);
    const float s = 0.08f;
    int total = 0;
    double worst[3] = {0, 0, 0};
    int off[3] = {0, 0, 0};
    for (double theta : {20.0, 55.0, 80.0}) {
        const auto sc = make_scene(hf, s, 1.0, theta, 65);
        const auto P = test::random_points(2000, 15);
        auto adaptive = [&](const char* name) {
            return params_for(method(name), {{"layers_min", 8}, {"layers_max", 32}});
        };
        const auto steep = run_method<float>(method("steep"), adaptive("steep"), sc, hf, P);
        const auto pom = run_method<float>(method("pom"), adaptive("pom"), sc, hf, P);
        const auto relief = run_method<float>(method("relief"), adaptive("relief"), sc, hf, P);
        for (size_t i = 0; i < P.size(); ++i) {
            const TutorialOut t = tutorial_glsl(hf, s, Vec3<float>(sc.V), Vec2<float>(P[i]));
            const Vec2d ours[3] = {steep[i], pom[i], relief[i]};
            const Vec2d theirs[3] = {Vec2d(t.steep), Vec2d(t.pom), Vec2d(t.relief)};
            for (int m = 0; m < 3; ++m) {
                const double d = std::hypot(ours[m].x - theirs[m].x, ours[m].y - theirs[m].y) * 128;
                worst[m] = std::max(worst[m], d);
                off[m] += d > 1e-3;
            }
            ++total;
        }
    }
    // The tutorial accumulates uv and depth incrementally, docs/conventions.md section 6.3 computes
    // uv_0 + k duv: float rounding differs, and at near-ties a layer decision can flip. Allow 0.1%.
    for (int m = 0; m < 3; ++m)
        EXPECT_LE(off[m], total / 1000) << "method " << m << " worst " << worst[m];
}

// ---- The pixel-offset paper's loop, literally (b = 0): move texel by texel along the eye
// vector until i d / H_i >= |V.xy| / V.z, with d the texel size and H_i the height there.
Vec2<float> paper_pixel_offset(const HeightField& hf, float s, Vec3<float> V, Vec2<float> P) {
    HeightSampler<float> hs(hf, s, 0.0f);
    const float vxy = std::sqrt(V.x * V.x + V.y * V.y);
    const float d = 1.0f / float(hf.width);
    const Vec2<float> dir = V.xy() * (1.0f / vxy);
    for (int i = 0;; ++i) {
        const Vec2<float> T = P + dir * (float(i) * d);
        const float H = hs.z(T);
        if (float(i) * d / H >= vxy / V.z) return T;
    }
}

TEST(PixelStep, MatchesPaperLoopWithBiasZero) {
    const HeightField hf = test::random_field(128, 128, 16, 0.05f, 1.0f);  // H_i > 0
    int total = 0, off = 0;
    for (double theta : {10.0, 45.0, 70.0, 85.0}) {
        const auto sc = make_scene(hf, 0.05, 0.0, theta, 250);
        const auto P = test::random_points(1000, 17);
        const auto ours =
            run_method<float>(method("pixel_step"), params_for(method("pixel_step")), sc, hf, P);
        for (size_t i = 0; i < P.size(); ++i) {
            const Vec2<float> t =
                paper_pixel_offset(hf, 0.05f, Vec3<float>(sc.V), Vec2<float>(P[i]));
            off += std::hypot(ours[i].x - t.x, ours[i].y - t.y) * 128 > 1e-3;
            ++total;
        }
    }
    // Division vs multiplication in the stopping test can flip an exact tie: allow 0.1%.
    EXPECT_LE(off, total / 1000) << off << " of " << total;
}

}  // namespace
}  // namespace pxh
