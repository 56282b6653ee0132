// What the engine presets do with the sample's level of detail (methods/march/march.h, march():
// lod_fade, and pad_fetches for Babylon's loop), checked as the engines write it: HDRP's fade of
// the offset past _PPDLodThreshold, the DirectX SDK sample's blend to bump mapping and cut-off
// past g_nLODThreshold, PlayCanvas' occlusion mode (step count and fade from the level) against
// its literal transcription, and Babylon's 15 fetches on every sample. Below its threshold each
// preset is the knob-less search bit for bit. The level of detail reaches the method as
// HeightSampler::lod() through the CPU backend's per-sample lambda (heights at level 0: the rule
// is what is tested, not the filtering).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "harness/backends/cpu_backend.h"
#include "harness/backends/glsl_backend.h"
#include "harness/metrics/metrics.h"
#include "harness/scene/perspective_camera.h"
#include "methods/method.h"
#include "tests/engines/literal_js.h"
#include "tests/test_util.h"

namespace pxh {
namespace {

using test::make_scene;
using test::method;
using test::params_for;

// One method setting over P, every sample at level of detail lambda, in float.
MethodOutput run_at(const std::string& name, const GivenParams& given, const Scene<double>& sc,
                    const HeightField& hf, const std::vector<Vec2d>& P, double lambda) {
    const MethodInfo& m = method(name);
    const MethodSpec spec{&m, params_for(m, given)};
    const std::vector<double> lam(P.size(), lambda);
    return run_cpu(spec, "float", sc, hf, P, 0, nullptr, nullptr, nullptr, &lam);
}

// The presets' searches as `march` settings without the level-of-detail rule.
const GivenParams kHdrpSearch = {
    {"count", "angle_scaled"}, {"layers_min", 5},   {"layers_max", 15},
    {"compare", "lt"},         {"extra_layers", 1}, {"on_miss", "refine"},
    {"refine", "secant"},      {"iterations", 3},   {"tolerance", 0.01}};
const GivenParams kDxsdkSearch = {
    {"count", "mix_trunc"}, {"layers_min", 8},   {"layers_max", 50}, {"first", "top"},
    {"compare", "lt"},      {"on_miss", "last"}, {"refine", "lerp"}, {"clamp_weight", false}};
const GivenParams kBabylonSearch = {
    {"count", "mix_negated"}, {"layers_min", 4},   {"layers_max", 15}, {"compare", "lt"},
    {"max_steps", 14},        {"on_miss", "next"}, {"refine", "lerp"}, {"clamp_weight", false}};

struct Case {
    HeightField hf;
    double s, b;
};
std::vector<Case> cases() {
    return {{test::random_field(128, 128, 91), 0.02, 1.0},
            {test::random_field(64, 64, 92, 0.2f, 0.9f), 0.06, 1.0}};
}
const double kThetas[] = {10, 35, 60, 80};
const double kPhis[] = {20, 140, 250};

// `check(c, scene, ref)` on every case at every view of kThetas x kPhis, `ref` the plain search
// `search` (the march with those knobs at lambda 0) on P.
template <class Check>
void each_view(const GivenParams& search, const std::vector<Vec2d>& P, const Check& check) {
    for (const Case& c : cases())
        for (double theta : kThetas)
            for (double phi : kPhis) {
                const auto sc = make_scene(c.hf, c.s, c.b, theta, phi);
                check(c, sc, run_at("march", search, sc, c.hf, P, 0.0));
            }
}

// Every sample of `got` equals `ref` bit for bit, uv and fetches.
void expect_identical(const MethodOutput& got, const MethodOutput& ref, const std::string& what) {
    ASSERT_EQ(got.uv.size(), ref.uv.size());
    for (size_t i = 0; i < got.uv.size(); ++i) {
        ASSERT_EQ(got.uv[i].x, ref.uv[i].x) << what << " i=" << i;
        ASSERT_EQ(got.uv[i].y, ref.uv[i].y) << what << " i=" << i;
        ASSERT_EQ(got.fetches[i], ref.fetches[i]) << what << " i=" << i;
    }
}

TEST(EngineLod, HdrpBelowItsThresholdIsTheSearchBitForBit) {
    const auto P = test::random_points(500, 3);
    each_view(kHdrpSearch, P, [&](const Case& c, const Scene<double>& sc, const MethodOutput& ref) {
        for (double lambda : {-3.0, 0.0, 1.0, 4.5, 5.0})
            expect_identical(run_at("hdrp_pom", {}, sc, c.hf, P, lambda), ref,
                             "lambda " + std::to_string(lambda));
        // A lower threshold moves the band: at 2 the offset is untouched at lambda 2.
        expect_identical(run_at("hdrp_pom", {{"_PPDLodThreshold", 2}}, sc, c.hf, P, 2.0), ref,
                         "threshold 2");
    });
}

TEST(EngineLod, HdrpFadesTheOffsetOverTheLevelPastItsThreshold) {
    // PerPixelDisplacement.hlsl: offset *= (1.0 - saturate(lod - lodThreshold)), the march run
    // (and fetched) at every level; uv = P + offset.
    const auto P = test::random_points(500, 4);
    for (const Case& c : cases())
        for (double theta : kThetas) {
            const auto sc = make_scene(c.hf, c.s, c.b, theta, 75);
            const MethodOutput ref = run_at("march", kHdrpSearch, sc, c.hf, P, 0.0);
            for (double threshold : {5.0, 2.0})
                for (double lambda : {threshold + 0.25, threshold + 0.5, threshold + 0.875,
                                      threshold + 1.0, threshold + 3.0}) {
                    const MethodOutput got =
                        run_at("hdrp_pom", {{"_PPDLodThreshold", threshold}}, sc, c.hf, P, lambda);
                    const float lod = float(lambda), lodThreshold = float(threshold);
                    const float fade = 1.0f - std::clamp(lod - lodThreshold, 0.0f, 1.0f);
                    for (size_t i = 0; i < P.size(); ++i) {
                        const Vec2<float> p(P[i]), offset = Vec2<float>(ref.uv[i]) - p;
                        const Vec2<float> want = p + offset * fade;
                        EXPECT_NEAR(got.uv[i].x, want.x, 1e-7) << lambda << " i=" << i;
                        EXPECT_NEAR(got.uv[i].y, want.y, 1e-7) << lambda << " i=" << i;
                        EXPECT_EQ(got.fetches[i], ref.fetches[i]) << "the march always runs";
                        if (lambda >= threshold + 1) {  // faded out: P exactly
                            EXPECT_EQ(got.uv[i].x, double(p.x));
                            EXPECT_EQ(got.uv[i].y, double(p.y));
                        }
                    }
                }
        }
}

TEST(EngineLod, DxsdkBlendsToBumpMappingAndStopsPastItsThreshold) {
    // RenderScenePS: fMipLevel <= g_nLODThreshold: POM, and in (threshold - 1, threshold]
    // texSample = lerp(texSampleBase, texCoord, frac(fMipLevel)); above: bump mapping (texCoord,
    // no march). fMipLevel = max(level, 0).
    const auto P = test::random_points(500, 5);
    each_view(kDxsdkSearch, P,
              [&](const Case& c, const Scene<double>& sc, const MethodOutput& ref) {
                  for (double lambda : {-2.0, 0.0, 1.5, 2.0, 3.0})  // 3: frac 0, the POM uv
                      expect_identical(run_at("dxsdk_pom", {}, sc, c.hf, P, lambda), ref,
                                       "lambda " + std::to_string(lambda));
                  expect_identical(run_at("dxsdk_pom", {{"g_nLODThreshold", 16}}, sc, c.hf, P, 10),
                                   ref, "threshold 16 at lambda 10");
                  for (double lambda : {2.25, 2.5, 2.875}) {
                      const MethodOutput got = run_at("dxsdk_pom", {}, sc, c.hf, P, lambda);
                      const float fMipLevel = float(lambda);
                      const float fMipLevelFrac = fMipLevel - std::floor(fMipLevel);  // modf
                      for (size_t i = 0; i < P.size(); ++i) {
                          const Vec2<float> texCoord(P[i]), texSampleBase(ref.uv[i]);
                          // HLSL lerp(x, y, s) = x + s (y - x)
                          const Vec2<float> want =
                              texSampleBase + (texCoord - texSampleBase) * fMipLevelFrac;
                          EXPECT_NEAR(got.uv[i].x, want.x, 1e-7) << lambda << " i=" << i;
                          EXPECT_NEAR(got.uv[i].y, want.y, 1e-7) << lambda << " i=" << i;
                          EXPECT_EQ(got.fetches[i], ref.fetches[i]);
                      }
                  }
                  for (double lambda : {3.001, 4.0, 9.0}) {
                      const MethodOutput got = run_at("dxsdk_pom", {}, sc, c.hf, P, lambda);
                      for (size_t i = 0; i < P.size(); ++i) {
                          EXPECT_EQ(got.uv[i].x, double(float(P[i].x))) << lambda;
                          EXPECT_EQ(got.uv[i].y, double(float(P[i].y))) << lambda;
                          EXPECT_EQ(got.fetches[i], 0) << "bump mapping: no march";
                      }
                  }
              });
}

TEST(EngineLod, BabylonFetchesFifteenTimesOnEverySample) {
    // parallaxOcclusion's loop has no break: texture2D on each of its 15 iterations.
    const auto P = test::random_points(800, 6);
    for (const Case& c : cases())
        for (double s : {c.s, 0.05})
            for (double theta : {0.0, 10.0, 35.0, 60.0, 80.0, 88.0})
                for (double phi : kPhis) {
                    const auto sc = make_scene(c.hf, s, 1.0, theta, phi);
                    const MethodOutput got = run_at("babylon_pom", {}, sc, c.hf, P, 0.0);
                    const MethodOutput search = run_at("march", kBabylonSearch, sc, c.hf, P, 0.0);
                    int fewer = 0;
                    for (size_t i = 0; i < P.size(); ++i) {
                        ASSERT_EQ(got.fetches[i], 15) << "theta " << theta << " i=" << i;
                        ASSERT_EQ(got.uv[i].x, search.uv[i].x);  // the uv is the search's
                        ASSERT_EQ(got.uv[i].y, search.uv[i].y);
                        fewer += search.fetches[i] < 15;
                    }
                    // The padding is doing something: the search alone stops early somewhere
                    // (not head-on, where every layer sits at P and no field is that high).
                    if (theta > 0 && s > 0.03) {
                        EXPECT_GT(fewer, 0) << "theta " << theta;
                    }
                }
}

TEST(EngineLod, PlayCanvasOcclusionIsItsLiteralLoopAtEveryLevel) {
    // The preset against literal::playcanvas_occlusion (the shader's own variable names and
    // float accumulation): within 1e-3 texel and with the same fetch count on all but 0.1% of
    // the samples, over levels that move the step count from the cap to one step and the fade.
    const auto P = test::random_points(300, 7);
    int total = 0, off = 0, fetch_off = 0, faded = 0, skipped = 0;
    double worst = 0;
    for (const Case& c : cases())
        for (double s : {0.02, 0.1})
            for (double b : {0.5, 1.0, 0.2})
                for (double theta : {0.0, 10.0, 35.0, 60.0, 80.0, 87.0})
                    for (double phi : kPhis) {
                        const auto sc = make_scene(c.hf, s, b, theta, phi);
                        const Vec3<float> V(sc.V);
                        for (double lambda : {-1.0, 0.0, 1.0, 2.5, 4.0, 6.0}) {
                            const MethodOutput got =
                                run_at("playcanvas_occlusion", {}, sc, c.hf, P, lambda);
                            const float lod = float(std::max(lambda, 0.0));
                            // marchTexels, in double: inside (1, 3) the fade is partial
                            const double tanv = std::hypot(sc.V.x, sc.V.y) / sc.V.z;
                            const double texels =
                                s * std::min(tanv, 5.0) * c.hf.width / std::exp2(double(lod));
                            const bool partial = texels > 1.05 && texels < 2.95;
                            for (size_t i = 0; i < P.size(); ++i) {
                                const auto e = literal::playcanvas_occlusion(
                                    c.hf, float(s), float(b), V, Vec2<float>(P[i]), lod);
                                const double d =
                                    std::hypot(got.uv[i].x - e.uv.x, got.uv[i].y - e.uv.y) *
                                    c.hf.width;
                                worst = std::max(worst, d);
                                off += !(d <= 1e-3);
                                fetch_off += got.fetches[i] != e.fetches;
                                skipped += e.fetches == 0;
                                faded += partial;
                                ++total;
                            }
                        }
                    }
    EXPECT_LE(off, total / 1000) << off << " of " << total << ", worst " << worst << " texel";
    EXPECT_LE(fetch_off, total / 1000) << fetch_off << " of " << total;
    EXPECT_GT(skipped, total / 20);  // the fade reaches 0 (head-on, far levels): P, no tap
    EXPECT_GT(faded, total / 50);    // the fade band, where the offset is scaled
}

TEST(EngineLod, PlayCanvasOcclusionClosedForms) {
    // Head-on the march spans nothing: fade 0, P and no tap at every level. On a flat field at
    // level 0 with the fade whole, the uv is the field's point within the bisection's 1/64 step
    // (never worse than one step), and the taps are 1 + ceil-steps-to-the-hit + 5.
    const HeightField flat = test::flat_field(64, 64, 0.3f);
    const auto P = test::random_points(200, 8);
    const auto head_on = make_scene(flat, 0.1, 0.5, 0, 0);
    const MethodOutput h = run_at("playcanvas_occlusion", {}, head_on, flat, P, 0.0);
    for (size_t i = 0; i < P.size(); ++i) {
        EXPECT_EQ(h.uv[i].x, double(float(P[i].x)));
        EXPECT_EQ(h.fetches[i], 0);
    }
    for (double theta : {30.0, 60.0}) {
        const double s = 0.1, b = 0.5;
        const auto sc = make_scene(flat, s, b, theta, 40);
        const Vec3d V = sc.V;
        const double tanv = std::hypot(V.x, V.y) / V.z;
        const double slope = std::min(tanv, 5.0);  // the march's length per unit depth
        const double texels = s * slope * 64;      // marchTexels at level 0
        ASSERT_GT(texels, 3.0);                    // fade 1
        const double steps = std::min(texels / 2, 16.0);
        // the true point: depth (1 - h) = 0.7 of the volume, relative to the plane at 1 - b
        const double depth = 0.7;
        const int k = int(std::ceil(depth * steps - 1e-9));
        const MethodOutput got = run_at("playcanvas_occlusion", {}, sc, flat, P, 0.0);
        for (size_t i = 0; i < P.size(); ++i) {
            const double dir_x = -V.x / std::hypot(V.x, V.y), dir_y = -V.y / std::hypot(V.x, V.y);
            const double along = s * slope * (depth - (1 - b));
            const double ex = P[i].x + dir_x * along, ey = P[i].y + dir_y * along;
            const double err = std::hypot(got.uv[i].x - ex, got.uv[i].y - ey);
            EXPECT_LE(err, s * slope / steps / 64 + 1e-6) << "theta " << theta;
            EXPECT_EQ(got.fetches[i], 1 + k + 5) << "theta " << theta;
        }
    }
}

// ---- CPU against GLSL on perspective views, where lambda varies per pixel ------------------

struct Regimes {
    size_t inside = 0, far = 0, fetch_off = 0, at_p = 0, moved = 0;
    double worst = 0;
};

// The preset's GLSL render against its CPU float twin on perspective views (a 256^2 field seen
// with 32^2 pixels: lambda from about 3 to past 8), both twins fed the view's per-sample lambda;
// outside pixels left out. `on_grid`: the camera's V and lambda per pixel, drawn at the N x N
// grid's points instead of the camera's (the per-sample view and lambda maps without the point
// map).
Regimes glsl_vs_cpu_perspective(const std::string& name, const GivenParams& given, double b,
                                bool on_grid) {
    static GlslBackend gl(GlslOptions{"", 0});
    CpuBackend cpu(BackendSettings{});
    const MethodInfo& m = method(name);
    const MethodSpec spec{&m, params_for(m, given)};
    const HeightField hf = test::random_field(256, 256, 93, 0.0f, 1.0f);
    const double s = 0.05;
    Regimes r;
    for (double theta : {30.0, 60.0, 80.0})
        for (double D : {1.5, 6.0, 24.0}) {
            const PerspectiveParams pp{theta, 35, D, 50, 32};
            check_eye_above_slab(pp, s, b, "test");
            const View camera = PerspectiveCamera(pp).view();
            const std::vector<double> lambda = sample_lods(camera.J, hf.width, hf.height);
            View rays = camera;
            if (on_grid) {
                rays.P = sample_grid(32);
                rays.grid = 32;
                rays.inside.clear();  // outside pixels carry the look-at ray: a valid V
            }
            const Scene<double> sc{s, b, view_vector(theta, 35), hf.width, hf.height};
            ViewInput in{sc, hf, rays, nullptr, false, nullptr};
            in.lambda = &lambda;
            const MethodOutput g = gl.run(spec, in, {"float", "r32f"});
            const MethodOutput c = cpu.run(spec, in, {"float", ""});
            for (size_t k = 0; k < rays.size(); ++k) {
                if (!rays.is_inside(k)) continue;
                ++r.inside;
                const Vec2d e = texel_error(g.uv[k], c.uv[k], hf.width, hf.height);
                const double d = std::hypot(e.x, e.y);
                r.far += !(d <= 1e-3);
                r.worst = std::max(r.worst, d);
                r.fetch_off += g.fetches[k] != c.fetches[k];
                const Vec2d P = rays.P[k];
                const bool at_p =
                    c.uv[k].x == double(float(P.x)) && c.uv[k].y == double(float(P.y));
                r.at_p += at_p;
                r.moved += !at_p;
            }
        }
    return r;
}

TEST(EngineLodGlsl, PresetsWithLevelRulesAgreeWithTheirCpuTwinOnPerspectiveViews) {
    struct Row {
        const char* name;
        GivenParams given;
        double b;
    };
    const Row rows[] = {
        {"hdrp_pom", {}, 1.0},
        {"hdrp_pom", {{"_PPDLodThreshold", 3}}, 1.0},  // the fade band inside these views
        {"dxsdk_pom", {}, 1.0},
        {"dxsdk_pom", {{"g_nLODThreshold", 5}}, 1.0},
        {"playcanvas_occlusion", {}, 0.5},
        {"playcanvas_occlusion", {{"parallaxSamples", 8}}, 1.0},
        {"babylon_pom", {}, 1.0},
    };
    for (const Row& row : rows)
        for (bool on_grid : {false, true}) {
            const Regimes r = glsl_vs_cpu_perspective(row.name, row.given, row.b, on_grid);
            const std::string what = std::string(row.name) + " " +
                                     std::to_string(row.given.size()) +
                                     (on_grid ? " on the grid" : " perspective");
            const bool babylon = std::string(row.name) == "babylon_pom";
            // Babylon's interpolation weight is unclamped (docs/guide/engines.md): float rounding
            // of near-degenerate brackets is amplified, so its bound is on the worst sample.
            if (babylon) {
                EXPECT_LT(r.worst, 0.01) << what << ": worst " << r.worst << " texel";
            } else {
                EXPECT_LE(r.far, r.inside / 1000) << what << ": " << r.far << " of " << r.inside
                                                  << " beyond 1e-3 texel, worst " << r.worst;
            }
            EXPECT_LE(r.fetch_off, r.inside / 1000) << what << ": fetch counts differ";
            // The views reach both sides of each rule: samples displaced, and (but for Babylon,
            // which has no level rule) samples returned at P past the threshold.
            EXPECT_GT(r.moved, r.inside / 50) << what;
            if (!babylon) {
                EXPECT_GT(r.at_p, r.inside / 20) << what;
            }
        }
}

}  // namespace
}  // namespace pxh
