// maxmip (methods/maxmip): the exact method. Its double CPU twin against the exact ground truth
// on every procedural generator up to theta = 89 (power-of-two and odd sizes, two scale/bias
// pairs), its GLSL twin against the truth and against the CPU float twin, its pyramid against a
// brute-force maximum, and what the iteration cap does.
#include "methods/maxmip/maxmip.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "harness/backends/glsl_backend.h"
#include "harness/metrics/metrics.h"
#include "harness/truth/exact_tracer.h"
#include "heightfields/heightfields.h"
#include "tests/test_util.h"

namespace pxh {
namespace {

const MethodInfo& maxmip() { return *find_method("maxmip"); }

HeightField generated(const GeneratorInfo& g, int w, int h) {
    return generate_heightfield(g, w, h, resolve_params(g.params, {}, "test", g.name));
}

double texel_dist(Vec2d a, Vec2d b, const HeightField& hf) {
    const Vec2d e = texel_error(a, b, hf.width, hf.height);
    return std::hypot(e.x, e.y);
}

// The largest |maxmip - truth| (texels) over an N x N grid view, double precision.
double worst_vs_truth(const HeightField& hf, double s, double b, double theta, double phi) {
    const int N = 24;
    const auto sc = test::make_scene(hf, s, b, theta, phi);
    const auto P = sample_grid(N);
    const auto uv = test::run_method<double>(maxmip(), test::params_for(maxmip()), sc, hf, P);
    std::vector<TruthHit> truth;
    ExactTracer(hf, s, b).trace_grid(N, sc.V, truth);
    double worst = 0;
    for (size_t k = 0; k < P.size(); ++k)
        worst = std::max(worst, texel_dist(uv[k], truth[k].uv, hf));
    return worst;
}

// maxmip (double, CPU) matches the exact ground truth within 1e-6 texel on every
// procedural generator at theta up to 89. Both compute the same cells with the same closed form;
// the traversal only skips blocks whose highest corner lies below the ray.
TEST(MaxMip, DoubleMatchesTheExactTruthOnEveryGenerator) {
    for (const GeneratorInfo& g : all_generators())
        for (const auto& [w, h] : {std::pair{64, 64}, std::pair{45, 23}}) {
            const HeightField hf = generated(g, w, h);
            for (const auto& [s, b] : {std::pair{0.05, 1.0}, std::pair{0.2, 0.3}})
                for (double theta : {0.0, 30.0, 60.0, 80.0, 85.0, 89.0})
                    for (double phi : {0.0, 33.0, 90.0, 217.0})
                        ASSERT_LE(worst_vs_truth(hf, s, b, theta, phi), 1e-6)
                            << g.name << " " << w << "x" << h << " s=" << s << " b=" << b
                            << " theta=" << theta << " phi=" << phi;
        }
}

// The GLSL twin (float) on every generator up to theta = 89: the same fetch count as the CPU
// float twin on every sample and the same uv to 1e-4 texel (the same operations in the same
// order; measured: identical), and within float precision of the exact truth: every sample
// within 1e-3 texel (measured: 1.2e-4 at most, bumps at theta = 89). Float carries ~7 digits:
// the grid coordinate of a ray that travels up to s tan(89) = 2.9 tiles of 64 texels reaches
// ~200, whose last bit is ~1e-5 texel, and the root of a nearly tangent crossing amplifies that.
TEST(MaxMip, GlslIsTheCpuFloatTwinAndWithinFloatPrecisionOfTheTruth) {
    static GlslBackend gl(GlslOptions{"", 0});
    const int N = 48;
    const auto P = sample_grid(N);
    const MethodSpec spec{&maxmip(), test::params_for(maxmip())};
    for (const GeneratorInfo& g : all_generators()) {
        const HeightField hf = generated(g, 64, 64);
        ResourceCache cache(hf);
        const MethodResources res = cache.get("maxmip", maxmip().resources, 0.05, 1.0);
        for (double theta : {0.0, 45.0, 80.0, 89.0}) {
            const Scene<double> sc = test::make_scene(hf, 0.05, 1.0, theta, 33);
            const MethodOutput gpu = gl.run(spec, sc, hf, N, "r32f", nullptr, 0, &res);
            std::vector<int> fetches;
            const auto cpu = test::run_method<float>(maxmip(), spec.params, sc, hf, P, &fetches);
            std::vector<TruthHit> truth;
            ExactTracer(hf, 0.05, 1.0).trace_grid(N, sc.V, truth);
            double worst = 0, worst_cpu = 0;
            for (size_t k = 0; k < P.size(); ++k) {
                EXPECT_EQ(gpu.fetches[k], fetches[k]) << g.name << " theta=" << theta;
                worst_cpu = std::max(worst_cpu, texel_dist(gpu.uv[k], cpu[k], hf));
                worst = std::max(worst, texel_dist(gpu.uv[k], truth[k].uv, hf));
            }
            EXPECT_LE(worst_cpu, 1e-4) << g.name << " theta=" << theta;
            EXPECT_LE(worst, 1e-3) << g.name << " theta=" << theta;
        }
    }
}

// The cap: with too few iterations the traversal stops where it stood, a point on the eye ray
// that it has proven clear, so never beyond the true hit; the fetch count is the cap. With the
// default cap the result is the truth.
TEST(MaxMip, TheCapStopsOnTheRayBeforeTheHit) {
    const HeightField hf = test::random_field(64, 64, 41);
    const auto sc = test::make_scene(hf, 0.1, 0.6, 80, 20);
    const ExactTracer tr(hf, 0.1, 0.6);
    const auto P = test::random_points(300, 42);
    int stopped_short = 0;
    for (int cap : {1, 3, 10}) {
        std::vector<int> fetches;
        const auto uv = test::run_method<double>(
            maxmip(), test::params_for(maxmip(), {{"max_iterations", cap}}), sc, hf, P, &fetches);
        for (size_t k = 0; k < P.size(); ++k) {
            const TruthHit t = tr.trace(P[k], sc.V);
            // On the ray: uv = E - tau V.xy, with tau in [0, tau_true].
            const double zt = 0.1 * (1 - 0.6);
            const Vec2d E{P[k].x + sc.V.x / sc.V.z * zt, P[k].y + sc.V.y / sc.V.z * zt};
            const double tau = (E.x - uv[k].x) / sc.V.x, tau_true = (E.x - t.uv.x) / sc.V.x;
            EXPECT_NEAR(E.y - tau * sc.V.y, uv[k].y, 1e-12);
            EXPECT_GE(tau, -1e-12);
            EXPECT_LE(tau, tau_true + 1e-12) << "cap " << cap;
            EXPECT_LE(fetches[k], cap);
            stopped_short += tau < tau_true - 1e-9;
        }
    }
    EXPECT_GT(stopped_short, 300);  // the small caps do bind
}

// r_maxmip: level 0 holds each cell's four corners (wrapped), level L at node (nx, ny) the max
// over the corners of every cell the traversal assigns to that node (maxmip::node_of: an odd
// size's extra cells join the last node), checked by brute force on odd and even sizes.
TEST(MaxMip, PyramidHoldsTheCornersAndTheMaxOfEveryNodesCells) {
    for (const auto& [W, H] : {std::pair{16, 8}, std::pair{13, 6}, std::pair{5, 11}}) {
        // The highest texel at (0, 0): the corner of the wrapping cells (W - 1, .), which an
        // odd size puts into the last node together with its neighbours.
        HeightField hf = test::random_field(W, H, uint32_t(W * 100 + H), 0.0f, 0.5f);
        hf.at(0, 0) = 1.0f;
        const BuiltResource r = build_resource(maxmip().resources[0], hf, 0.05, 1.0);
        const auto& levels = r.image->levels;
        ASSERT_EQ(int(levels.size()), maxmip::top_level(W, H) + 1);
        size_t floats = 0;
        for (int L = 0; L < int(levels.size()); ++L) {
            const ResourceLevel& lv = levels[size_t(L)];
            floats += lv.texels.size();
            ASSERT_EQ(lv.width, maxmip::nodes_at(W, L));
            ASSERT_EQ(lv.height, maxmip::nodes_at(H, L));
            std::vector<float> want(size_t(lv.width) * lv.height * 4, -1.0f);
            for (int j = 0; j < H; ++j)
                for (int i = 0; i < W; ++i) {
                    const float c[4] = {hf.wrapped(i, j), hf.wrapped(i + 1, j),
                                        hf.wrapped(i, j + 1), hf.wrapped(i + 1, j + 1)};
                    const size_t n = size_t(maxmip::node_of(j, L, H)) * lv.width +
                                     size_t(maxmip::node_of(i, L, W));
                    for (int ch = 0; ch < 4; ++ch)
                        want[4 * n + ch] =
                            L == 0 ? c[ch] : std::max({want[4 * n + ch], c[0], c[1], c[2], c[3]});
                }
            for (size_t k = 0; k < want.size(); ++k)
                ASSERT_EQ(lv.texels[k], want[k]) << W << "x" << H << " level " << L << " k=" << k;
        }
        EXPECT_EQ(r.bytes, floats * sizeof(float));
    }
}

}  // namespace
}  // namespace pxh
