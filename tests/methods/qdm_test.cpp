// qdm (methods/qdm): the traversal against a brute-force first hit of the ray with the surface
// the source's quadtree describes (each texel a flat-topped box, nearest filtering), the
// refinement's closed form on a ramp, the fetches per iteration, and the pyramid against a
// brute-force maximum.
#include "methods/qdm/qdm.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "harness/metrics/metrics.h"
#include "harness/truth/exact_tracer.h"
#include "tests/test_util.h"

namespace pxh {
namespace {

const MethodInfo& qdm() { return *find_method("qdm"); }

// The ray in the source's terms: uv(d) = p + v d at depth d in [0, 1] (depth = 1 - h).
struct DepthRay {
    Vec2d p, v;
};

DepthRay depth_ray(const Scene<double>& sc, Vec2d P) {
    const Vec2d dir{sc.V.x / sc.V.z, sc.V.y / sc.V.z};
    return {{P.x + dir.x * sc.z_top(), P.y + dir.y * sc.z_top()},
            {-dir.x * sc.scale, -dir.y * sc.scale}};
}

// Brute force: the first depth at which the ray is at or below the box surface (texel (i, j)
// a box of top depth 1 - h(i, j) over [i/W, (i+1)/W) x [j/H, (j+1)/H), tiled): walk the texels
// the ray crosses in order; in the texel entered at depth d_in and left at d_out, the hit is
// max(d_in, D) if D <= d_out.
double box_first_hit(const HeightField& hf, const DepthRay& r) {
    const int W = hf.width, H = hf.height;
    const double inf = std::numeric_limits<double>::infinity();
    long long i = (long long)std::floor(r.p.x * W), j = (long long)std::floor(r.p.y * H);
    const int si = r.v.x > 0 ? 1 : -1, sj = r.v.y > 0 ? 1 : -1;
    double d_in = 0;
    for (;;) {
        const double bx = r.v.x != 0 ? (double(i + (si > 0)) / W - r.p.x) / r.v.x : inf;
        const double by = r.v.y != 0 ? (double(j + (sj > 0)) / H - r.p.y) / r.v.y : inf;
        const double d_out = std::min({bx, by, 1.0});
        const double D = 1.0 - double(hf.wrapped(i, j));
        if (D <= d_out) return std::max(d_in, D);
        d_in = d_out;
        (bx <= by ? i : j) += bx <= by ? si : sj;
    }
}

// Per setting: samples off the straight-down view, those that stop within the nudge of the
// brute-force box hit, and those that stop later.
struct BoxAgreement {
    size_t n = 0, within = 0, late = 0;
};

BoxAgreement box_agreement(const HeightField& hf, double s, double theta, double phi) {
    const double nudge = s / (2.0 * hf.width);
    const auto sc = test::make_scene(hf, s, 0.5, theta, phi);
    const auto P = test::random_points(200, uint32_t(theta * 7 + phi));
    const auto uv = test::run_method<double>(
        qdm(), test::params_for(qdm(), {{"max_iterations", 100000}, {"refine", false}}), sc, hf, P);
    BoxAgreement a;
    for (size_t k = 0; k < P.size(); ++k) {
        const DepthRay r = depth_ray(sc, P[k]);
        const double want = box_first_hit(hf, r);
        const double vv = r.v.x * r.v.x + r.v.y * r.v.y;
        if (vv == 0) {  // straight down: the sample itself
            EXPECT_EQ(uv[k].x, P[k].x);
            EXPECT_EQ(uv[k].y, P[k].y);
            continue;
        }
        const double got = ((uv[k].x - r.p.x) * r.v.x + (uv[k].y - r.p.y) * r.v.y) / vv;
        // On the ray, and never before the first box hit.
        EXPECT_NEAR(r.p.x + r.v.x * got, uv[k].x, 1e-12);
        EXPECT_NEAR(r.p.y + r.v.y * got, uv[k].y, 1e-12);
        EXPECT_GE(got, want - 1e-9) << hf.width << "x" << hf.height << " theta=" << theta;
        ++a.n;
        const bool late = got > want + nudge * (1 + 1e-6) + 1e-12;
        a.within += !late;
        a.late += late;
    }
    return a;
}

// With a large cap and without the refinement, qdm stops at the first hit
// of the ray with the box surface its quadtree describes. It never stops before it (the pyramid
// is conservative, and a stop means the ray is inside a box), and it stops at most the source's
// nudge past a node border later (fDeltaNC = s / (2 W), in depth) where the ray enters the hit
// texel through a wall. The nudge can also carry the ray past a box it would only clip within
// that depth: a later stop. Horizontally the nudge is s^2 tan(theta) / 2 texels: 0.036 at
// s = 0.05, theta = 88 (measured: 0.1% of the samples at theta = 88 stop late), but 1.3 texels at s
// = 0.3 (measured: 45% of the samples at theta = 88 stop late, 3% at theta = 80).
TEST(Qdm, UnrefinedStopsAtTheFirstHitWithTheBoxSurface) {
    for (const auto& [W, H] : {std::pair{16, 16}, std::pair{12, 10}, std::pair{33, 7}})
        for (double s : {0.05, 0.3}) {
            const HeightField hf = test::random_field(W, H, uint32_t(W * H + int(s * 100)));
            BoxAgreement thin, all;
            for (double theta : {0.0, 30.0, 60.0, 80.0, 88.0})
                for (double phi : {10.0, 57.0, 180.0}) {
                    const BoxAgreement a = box_agreement(hf, s, theta, phi);
                    const bool small = s * s * std::tan(theta * M_PI / 180) / 2 <= 0.05;
                    (small ? thin : all).n += a.n;
                    (small ? thin : all).within += a.within;
                    all.late += a.late;
                }
            EXPECT_GE(double(thin.within), 0.99 * double(thin.n)) << W << "x" << H << " s=" << s;
            if (s > 0.1) {
                EXPECT_GT(all.late, 0u) << "the nudge skips nothing at s = 0.3?";
            }
        }
}

// The refinement's closed form: on a ramp h = a + c u (bilinear = linear there) the ray's depth
// and the map's depth are both linear along the ray, so interpolating the points one texel
// before and after the stop by their distances to the surface gives the exact crossing whenever
// those points straddle it within the ramp. Compared with the exact tracer.
TEST(Qdm, RefinementIsExactOnARamp) {
    const int W = 64;
    HeightField hf(W, 8);
    for (int j = 0; j < 8; ++j)
        for (int i = 0; i < W; ++i) hf.at(i, j) = float(0.1 + 0.8 * i / double(W - 1));
    const ExactTracer tr(hf, 0.05, 1.0);
    size_t n = 0, exact = 0;
    for (double theta : {30.0, 60.0, 75.0})
        for (double phi : {0.0, 180.0, 20.0}) {
            const auto sc = test::make_scene(hf, 0.05, 1.0, theta, phi);
            auto P = test::random_points(300, uint32_t(theta + phi));
            const auto uv = test::run_method<double>(qdm(), test::params_for(qdm()), sc, hf, P);
            const auto box = test::run_method<double>(
                qdm(), test::params_for(qdm(), {{"refine", false}}), sc, hf, P);
            for (size_t k = 0; k < P.size(); ++k) {
                const Vec2d t = tr.trace(P[k], sc.V).uv;
                const double u = t.x - std::floor(t.x);
                if (u < 0.2 || u > 0.8) continue;  // keep clear of the wrap's cliff
                ++n;
                const Vec2d e = texel_error(uv[k], t, W, 8), eb = texel_error(box[k], t, W, 8);
                exact += std::hypot(e.x, e.y) <= 1e-6;
                EXPECT_LE(std::hypot(e.x, e.y), std::hypot(eb.x, eb.y) + 1e-9);
            }
        }
    EXPECT_GT(n, 500u);
    EXPECT_GE(double(exact), 0.99 * double(n));
}

// One pyramid fetch per iteration and two height fetches for the refinement: with a cap of k
// the traversal makes exactly min(k, what it needs) iterations.
TEST(Qdm, FetchesAreOnePerIterationPlusTwo) {
    const HeightField hf = test::random_field(32, 32, 61);
    const auto sc = test::make_scene(hf, 0.05, 1.0, 70, 15);
    const auto P = test::random_points(100, 62);
    std::vector<int> total, split, free_total;
    test::run_method<float>(qdm(), test::params_for(qdm(), {{"max_iterations", 1000}}), sc, hf, P,
                            &free_total);
    for (int cap : {1, 4, 1000}) {
        test::run_method<float>(qdm(), test::params_for(qdm(), {{"max_iterations", cap}}), sc, hf,
                                P, &total, &split);
        for (size_t k = 0; k < P.size(); ++k) {
            const int iterations = std::min(cap, free_total[k] - 2);
            EXPECT_EQ(split[2 * k], 2);               // the refinement's heights
            EXPECT_EQ(split[2 * k + 1], iterations);  // r_qdm
            EXPECT_EQ(total[k], iterations + 2);
        }
    }
    // The traversal from the 1 x 1 top to level 0 needs at least top + 1 = 6 iterations.
    for (int f : free_total) EXPECT_GE(f, 6 + 2);
    std::vector<int> unrefined;
    test::run_method<float>(qdm(), test::params_for(qdm(), {{"refine", false}}), sc, hf, P,
                            &unrefined);
    for (size_t k = 0; k < P.size(); ++k) EXPECT_EQ(unrefined[k], std::min(64, free_total[k] - 2));
}

// r_qdm: level 0 the heights; level L at node k the max over every texel whose footprint
// [i/W, (i+1)/W) meets the node's [k/n, (k+1)/n) (n = max(1, W >> L)), in both directions;
// for power-of-two sizes that is the 2^L x 2^L block max. Brute force on odd and even sizes.
TEST(Qdm, PyramidIsTheMaxOverEachNodesFootprint) {
    for (const auto& [W, H] : {std::pair{16, 8}, std::pair{13, 6}, std::pair{5, 11}}) {
        const HeightField hf = test::random_field(W, H, uint32_t(W * 10 + H));
        const BuiltResource r = build_resource(qdm().resources[0], hf, 0.05, 1.0);
        const auto& levels = r.image->levels;
        ASSERT_EQ(int(levels.size()), qdm::top_level(W, H) + 1);
        for (int L = 0; L < int(levels.size()); ++L) {
            const ResourceLevel& lv = levels[size_t(L)];
            ASSERT_EQ(lv.width, qdm::nodes_at(W, L));
            ASSERT_EQ(lv.height, qdm::nodes_at(H, L));
            for (int ny = 0; ny < lv.height; ++ny)
                for (int nx = 0; nx < lv.width; ++nx) {
                    float want = -1;
                    for (int j = 0; j < H; ++j)
                        for (int i = 0; i < W; ++i) {
                            const bool in_x = double(i + 1) / W > double(nx) / lv.width &&
                                              double(i) / W < double(nx + 1) / lv.width;
                            const bool in_y = double(j + 1) / H > double(ny) / lv.height &&
                                              double(j) / H < double(ny + 1) / lv.height;
                            if (in_x && in_y) want = std::max(want, hf.at(i, j));
                        }
                    ASSERT_EQ(lv.texels[size_t(ny) * lv.width + nx], want)
                        << W << "x" << H << " level " << L << " node " << nx << "," << ny;
                }
        }
    }
}

}  // namespace
}  // namespace pxh
