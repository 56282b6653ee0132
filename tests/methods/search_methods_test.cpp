// The search refinements: secant, contact, binary, iterative. Closed forms on a
// planar slope (a field exactly linear in u), comparisons against the exact truth and against
// the seed methods at equivalent settings, a field built to break bisection, and GLSL = CPU at
// non-default settings (the registry-wide tests cover the defaults).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "harness/backends/cpu_backend.h"
#include "harness/backends/glsl_backend.h"
#include "harness/metrics/metrics.h"
#include "harness/truth/exact_tracer.h"
#include "heightfields/heightfields.h"
#include "tests/glsl_agreement.h"
#include "tests/test_util.h"

namespace pxh {
namespace {

using test::method;

HeightField generated(const char* name, int size) {
    const GeneratorInfo* g = find_generator(name);
    return generate_heightfield(*g, size, size, resolve_params(g->params, {}, "test", name));
}

// h(i, j) = i / 64 on 64 x 64 texels: every value exact in float, so between texel centres 0 and
// 63 the bilinear surface is exactly the plane h(u) = u - 0.5 / 64 (dh/du = 1).
HeightField ramp_field() {
    HeightField hf(64, 64, "ramp");
    for (int j = 0; j < 64; ++j)
        for (int i = 0; i < 64; ++i) hf.at(i, j) = float(i) / 64.0f;
    return hf;
}

// Points whose rays stay on the planar part of the ramp (away from the wrap at u = 0 / 1).
std::vector<Vec2d> ramp_points() {
    std::vector<Vec2d> P;
    for (const Vec2d& q : test::random_points(200, 41)) P.push_back({0.3 + 0.4 * q.x, q.y});
    return P;
}

double texel_dist(Vec2d a, Vec2d b, const HeightField& hf) {
    const Vec2d e = texel_error(a, b, hf.width, hf.height);
    return std::hypot(e.x, e.y);
}

// Texel errors against the exact truth on the N x N grid of one view, in double.
std::vector<double> errors(const MethodInfo& m, const GivenParams& given, const HeightField& hf,
                           double s, double b, double theta, double phi, int N = 32) {
    const auto sc = test::make_scene(hf, s, b, theta, phi);
    const auto P = sample_grid(N);
    const auto uv = test::run_method<double>(m, test::params_for(m, given), sc, hf, P);
    const ExactTracer tr(hf, s, b);
    std::vector<double> e(P.size());
    for (size_t i = 0; i < P.size(); ++i) e[i] = texel_dist(uv[i], tr.trace(P[i], sc.V).uv, hf);
    return e;
}

struct Stats {
    double mean = 0, p95 = 0;
};
Stats stats(std::vector<double> e) {
    std::sort(e.begin(), e.end());
    Stats s;
    for (double x : e) s.mean += x / double(e.size());
    s.p95 = percentile_sorted(e, 0.95);
    return s;
}

// Errors of one setting over a view set (theta x one phi) of one field, pooled.
std::vector<double> pooled(const MethodInfo& m, const GivenParams& given, const HeightField& hf,
                           const std::vector<double>& thetas) {
    std::vector<double> all;
    for (double theta : thetas) {
        const auto e = errors(m, given, hf, 0.05, 1.0, theta, 30);
        all.insert(all.end(), e.begin(), e.end());
    }
    return all;
}

// ---- secant ----------------------------------------------------------------------------------

// On a planar slope g is linear in the layer parameter, so the first secant point of the bracket
// is the exact hit: iterations = 1 (pom's interpolation) is already exact, and further probes
// keep it. Fetches: the layer search's plus one per probe (iterations - 1).
TEST(Secant, ExactOnAPlanarSlopeFromTheFirstSecantPoint) {
    const HeightField hf = ramp_field();
    const auto P = ramp_points();
    const MethodInfo& pom = method("pom");
    for (double b : {0.0, 0.5, 1.0})
        for (double theta : {10.0, 40.0, 70.0})
            for (double phi : {0.0, 120.0, 200.0}) {
                const auto sc = test::make_scene(hf, 0.05, b, theta, phi);
                const ExactTracer tr(hf, 0.05, b);
                std::vector<int> fp;
                const auto uv_pom =
                    test::run_method<double>(pom, test::params_for(pom), sc, hf, P, &fp);
                for (int it : {1, 2, 5}) {
                    std::vector<int> fs;
                    const auto uv = test::run_method<double>(
                        method("secant"), test::params_for(method("secant"), {{"iterations", it}}),
                        sc, hf, P, &fs);
                    for (size_t i = 0; i < P.size(); ++i) {
                        ASSERT_LT(texel_dist(uv[i], tr.trace(P[i], sc.V).uv, hf), 1e-9)
                            << "iterations " << it << " b " << b << " theta " << theta;
                        ASSERT_EQ(fs[i], fp[i] + it - 1) << "iterations " << it;
                        if (it == 1) {
                            ASSERT_LT(texel_dist(uv[i], uv_pom[i], hf), 1e-10);
                        }
                    }
                }
            }
}

// The paper's claim against bisection (relief): with the same layers, i secant points (i - 1
// probes) leave a smaller mean error than relief's i bisection steps, and more secant points
// never make the mean worse, on smooth and rough fields.
TEST(Secant, BeatsBisectionWithFewerProbesAndImprovesWithIterations) {
    for (const char* field : {"sine", "fbm"}) {
        const HeightField hf = generated(field, 128);
        const std::vector<double> thetas{30, 60, 75};
        double prev = INFINITY;
        for (int i : {1, 2, 3, 4, 6}) {
            const double sec =
                stats(pooled(method("secant"), {{"layers", 16}, {"iterations", i}}, hf, thetas))
                    .mean;
            const double rel =
                stats(pooled(method("relief"), {{"layers", 16}, {"binary_steps", i}}, hf, thetas))
                    .mean;
            EXPECT_LT(sec, rel) << field << " iterations " << i;
            EXPECT_LE(sec, prev * 1.001 + 1e-12) << field << " iterations " << i;
            prev = sec;
        }
    }
}

// ---- contact ---------------------------------------------------------------------------------

// The sub-layers of contact with n layers inside [k-1, k] are layers of pom with n^2 layers, and
// pom n^2 tests every one of them in order: where the coarse search brackets the first crossing
// pom n^2 finds, contact returns pom n^2's answer (the same bracket, the same interpolation);
// where the coarse search steps over a thin crossing, contact lands on a later one. So contact
// is never better than pom n^2, equal on almost every sample of smooth fields, and worse only on
// the few rays the coarse search misses (on sine and fbm at 128^2, theta up to 80: at most 15 of
// 4096 per setting; they dominate the mean, which is why the mean is not compared). Without the
// interpolation contact returns steep n^2's layer, far worse than pom n^2 (the comparison
// discriminates).
TEST(Contact, AtMostTheErrorOfPomWithNSquaredLayers) {
    const std::vector<double> thetas{20, 45, 70, 80};
    for (const char* field : {"sine", "fbm"}) {
        const HeightField hf = generated(field, 128);
        for (int n : {4, 6, 8}) {
            const auto c = pooled(method("contact"), {{"layers", n}}, hf, thetas);
            const auto p = pooled(method("pom"), {{"layers", n * n}}, hf, thetas);
            size_t worse = 0, better = 0;
            for (size_t i = 0; i < c.size(); ++i) {
                worse += c[i] > p[i] + 1e-9;
                better += c[i] < p[i] - 1e-9;
            }
            EXPECT_EQ(better, 0u) << field << " n " << n;
            EXPECT_LE(double(worse), 0.005 * double(c.size())) << field << " n " << n;
            const auto c0 = pooled(method("contact"), {{"layers", n}, {"lerp", false}}, hf, thetas);
            const auto st = pooled(method("steep"), {{"layers", n * n}}, hf, thetas);
            size_t same = 0;
            for (size_t i = 0; i < c0.size(); ++i) same += std::abs(c0[i] - st[i]) < 1e-9;
            EXPECT_GE(double(same), 0.995 * double(c0.size())) << field << " n " << n;
            EXPECT_GT(stats(c0).p95, 3 * stats(p).p95) << field << " n " << n;
        }
    }
}

// Fetches: the layer search's k + 1, then sub-layers up to the first at or below the surface, at
// most ceil(n) - 1 (layer k is known); the declared bound 2 ceil(n) is reached.
TEST(Contact, FetchCountsStayWithinTwiceTheLayers) {
    const HeightField hf = generated("fbm", 64);
    const auto P = sample_grid(32);
    for (double n : {5.0, 7.5, 16.0}) {
        const MethodInfo& m = method("contact");
        const ParamValues p = test::params_for(m, {{"layers", n}});
        const auto sc = test::make_scene(hf, 0.05, 1.0, 60, 10);
        std::vector<int> f;
        test::run_method<float>(m, p, sc, hf, P, &f);
        EXPECT_EQ(m.max_fetches(p, sc), 2 * int(std::ceil(n)));
        EXPECT_LE(*std::max_element(f.begin(), f.end()), 2 * int(std::ceil(n)));
        EXPECT_GT(*std::max_element(f.begin(), f.end()), int(std::ceil(n)) + 1);
    }
}

// ---- binary ----------------------------------------------------------------------------------

// One crossing (a planar slope): bisection keeps it bracketed, so the midpoint returned lies
// within half the last interval, 2^-(iterations + 1) of the slab's ray, of the exact hit.
TEST(Binary, ConvergesToTheOnlyCrossingOfAPlanarSlope) {
    const HeightField hf = ramp_field();
    const auto P = ramp_points();
    for (double theta : {20.0, 50.0, 70.0})
        for (int it : {3, 10, 20}) {
            const auto sc = test::make_scene(hf, 0.05, 0.5, theta, 160);
            const ExactTracer tr(hf, 0.05, 0.5);
            std::vector<int> f;
            const auto uv = test::run_method<double>(
                method("binary"), test::params_for(method("binary"), {{"iterations", it}}), sc, hf,
                P, &f);
            const double travel = 0.05 * std::hypot(sc.V.x, sc.V.y) / sc.V.z * hf.width;
            const double bound = travel * std::ldexp(1.0, -(it + 1));
            double worst = 0;
            for (size_t i = 0; i < P.size(); ++i) {
                worst = std::max(worst, texel_dist(uv[i], tr.trace(P[i], sc.V).uv, hf));
                ASSERT_EQ(f[i], it);
            }
            EXPECT_LE(worst, bound + 1e-9) << "theta " << theta << " iterations " << it;
            EXPECT_GT(worst, bound * 0.25) << "the bound is tight";
        }
}

// A thin wall on a low floor: a ray that meets the wall before the middle of the slab and is
// past it (above the floor) at the middle makes the first probe choose the far half, so
// bisection converges to the floor behind the wall (closed form: the floor z = s (0.1 - 1) is met
// at x = 0.9 of the ray) while the true hit is on the wall; pom with 256 layers finds the wall.
TEST(Binary, ConvergesBehindAThinWall) {
    HeightField hf(64, 8, "wall");
    for (int j = 0; j < 8; ++j)
        for (int i = 0; i < 64; ++i) hf.at(i, j) = (i == 30 || i == 31) ? 1.0f : 0.1f;
    const double s = 0.2, b = 1.0;
    const auto sc = test::make_scene(hf, s, b, 60, 0);
    std::vector<Vec2d> P;
    for (int i = 0; i < 256; ++i) P.push_back({(i + 0.5) / 256, 0.5});
    const auto uv =
        test::run_method<double>(method("binary"), test::params_for(method("binary")), sc, hf, P);
    const MethodInfo& pom = method("pom");
    const auto uv_pom =
        test::run_method<double>(pom, test::params_for(pom, {{"layers", 256}}), sc, hf, P);
    const ExactTracer tr(hf, s, b);
    const double reach = s * sc.V.x / sc.V.z;  // u travelled over the whole slab
    const double wall_lo = 29.5 / 64, wall_hi = 32.5 / 64;
    int checked = 0;
    for (size_t i = 0; i < P.size(); ++i) {
        const Vec2d truth = tr.trace(P[i], sc.V).uv;
        const bool on_wall = truth.x >= wall_lo && truth.x <= wall_hi;
        if (!on_wall || !(P[i].x - 0.5 * reach < wall_lo)) continue;
        ++checked;
        const Vec2d floor_hit{P[i].x - 0.9 * reach, P[i].y};
        EXPECT_LE(texel_dist(uv[i], floor_hit, hf), reach * 64 * std::ldexp(1.0, -11) + 1e-9)
            << P[i].x;
        EXPECT_GT(texel_dist(uv[i], truth, hf), 5.0) << P[i].x;
        EXPECT_LT(texel_dist(uv_pom[i], truth, hf), 0.1) << P[i].x;
    }
    EXPECT_GE(checked, 20);
}

// ---- iterative -------------------------------------------------------------------------------

// On a planar slope z(uv) = z(P) + g.(uv - P) with the gradient map exact, the point P + t V
// moves by t <- t + N_z (z(P) + t m), m = g.V.xy - V.z: t_k = t* (1 - r^k) with the fixed point
// t* = -z(P) / m (the exact hit) and r = 1 + N_z m (N_z = 1 / sqrt(1 + |g|^2); 1 without slope).
TEST(Iterative, LinearRecurrenceOnAPlanarSlope) {
    const HeightField hf = ramp_field();
    std::vector<Vec2d> P;
    for (const Vec2d& q : test::random_points(100, 43)) P.push_back({0.35 + 0.3 * q.x, q.y});
    const double s = 0.05, b = 0.5;
    const MethodInfo& m = method("iterative");
    for (bool slope : {true, false})
        for (double theta : {20.0, 50.0, 75.0})
            for (double phi : {0.0, 60.0, 180.0})
                for (int k : {1, 2, 3, 6}) {
                    const auto sc = test::make_scene(hf, s, b, theta, phi);
                    std::vector<int> f;
                    const auto uv = test::run_method<double>(
                        m, test::params_for(m, {{"iterations", k}, {"slope", slope}}), sc, hf, P,
                        &f);
                    const double gx = s * 1.0;  // s dh/du, dh/du = 64 / 64
                    const double nz = slope ? 1 / std::sqrt(1 + gx * gx) : 1.0;
                    const double mm = gx * sc.V.x - sc.V.z;
                    const double r = 1 + nz * mm;
                    for (size_t i = 0; i < P.size(); ++i) {
                        const double zP = s * ((P[i].x * 64 - 0.5) / 64 - b);
                        const double t = -zP / mm * (1 - std::pow(r, k));
                        const Vec2d want{P[i].x + sc.V.x * t, P[i].y + sc.V.y * t};
                        ASSERT_LT(texel_dist(uv[i], want, hf), 1e-9)
                            << "slope " << slope << " theta " << theta << " k " << k;
                        ASSERT_EQ(f[i], k * (slope ? 2 : 1));
                    }
                }
}

// r_grad holds the central differences in uv units, wrapped at the tile border:
// h = 0.5 + 0.2 sin(2 pi i / W) + 0.2 cos(2 pi j / H) gives
// dh/du = 0.2 cos(2 pi i / W) sin(2 pi / W) W and dh/dv = -0.2 sin(2 pi j / H) sin(2 pi / H) H.
TEST(Iterative, GradientMapIsTheWrappedCentralDifference) {
    const int W = 32, H = 16;
    HeightField hf(W, H, "sines");
    for (int j = 0; j < H; ++j)
        for (int i = 0; i < W; ++i)
            hf.at(i, j) =
                float(0.5 + 0.2 * std::sin(2 * M_PI * i / W) + 0.2 * std::cos(2 * M_PI * j / H));
    const MethodInfo& m = method("iterative");
    ASSERT_EQ(m.resources.size(), 1u);
    const BuiltResource r = build_resource(m.resources[0], hf, 0.05, 1.0);
    ASSERT_EQ(r.image->levels.size(), 1u);
    EXPECT_EQ(r.bytes, size_t(W) * H * 4 * 4);
    const auto& t = r.image->levels[0].texels;
    for (int j = 0; j < H; ++j)
        for (int i = 0; i < W; ++i) {
            const size_t k = (size_t(j) * W + size_t(i)) * 4;
            EXPECT_NEAR(t[k], 0.2 * std::cos(2 * M_PI * i / W) * std::sin(2 * M_PI / W) * W, 2e-5);
            EXPECT_NEAR(t[k + 1], -0.2 * std::sin(2 * M_PI * j / H) * std::sin(2 * M_PI / H) * H,
                        2e-5);
        }
}

// ---- GLSL twins at non-default settings -------------------------------------------------------

TEST(SearchMethodsGlsl, NonDefaultSettingsAgreeWithCpuFloat) {
    static GlslBackend gl(GlslOptions{"", 0});
    const HeightField hf = generated("fbm", 128);
    const int N = 64;
    struct Case {
        const char* name;
        GivenParams given;
    };
    const Case cases[] = {
        {"secant", {{"iterations", 1}}},
        {"secant", {{"layers_min", 4}, {"layers_max", 24}, {"iterations", 9}}},
        {"contact", {{"layers", 7.5}, {"lerp", false}}},
        {"contact", {{"layers_min", 3}, {"layers_max", 12}}},
        {"binary", {{"iterations", 3}}},
        {"binary", {{"iterations", 24}}},
        {"iterative", {{"iterations", 9}, {"slope", false}}},
        {"iterative", {{"iterations", 2}}},
    };
    for (const Case& c : cases) {
        const MethodInfo& m = method(c.name);
        const MethodSpec spec{&m, test::params_for(m, c.given)};
        ResourceCache cache(hf);
        const MethodResources res = cache.get(m.name, m.resources, 0.05, 0.5);
        for (double theta : {0.0, 45.0, 80.0}) {
            const Scene<double> sc{0.05, 0.5, view_vector(theta, 25), hf.width, hf.height};
            const test::GlslCpuDiff d = test::glsl_vs_cpu(gl, spec, sc, hf, N, &res);
            EXPECT_LE(d.far, d.samples / 1000) << c.name << " theta " << theta;
            EXPECT_LE(d.fetch_off, d.samples / 1000) << c.name << " theta " << theta;
        }
    }
}

}  // namespace
}  // namespace pxh
