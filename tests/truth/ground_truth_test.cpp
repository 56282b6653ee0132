// Exact tracer (docs/conventions.md section 4) against closed forms and an independent brute-force
// march.
#include "harness/truth/ground_truth.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>

#include "tests/test_util.h"

namespace pxh {
namespace {

TEST(ViewVector, Convention) {
    const Vec3d v = view_vector(60, 90);
    EXPECT_NEAR(v.x, 0, 1e-15);
    EXPECT_NEAR(v.y, std::sin(M_PI / 3), 1e-15);
    EXPECT_NEAR(v.z, 0.5, 1e-15);
}

TEST(SampleGrid, TexelCentresOfAnNxNGrid) {
    const auto p = sample_grid(4);
    ASSERT_EQ(p.size(), 16u);
    EXPECT_DOUBLE_EQ(p[0].x, 0.125);
    EXPECT_DOUBLE_EQ(p[1].x, 0.375);
    EXPECT_DOUBLE_EQ(p[4].y, 0.375);  // row-major: index 4 starts row j = 1
}

// On a flat field at height h the visible point is P + V.xy / V.z * s (h - b), exactly.
TEST(ExactTracer, FlatFieldClosedForm) {
    for (double b : {0.0, 0.5, 1.0})
        for (double theta : {0.0, 30.0, 60.0, 85.0, 89.0}) {
            const HeightField hf = test::flat_field(8, 8, 0.3f);
            const ExactTracer tr(hf, 0.05, b);
            const Vec3d V = view_vector(theta, 20);
            const Vec2d P{0.31, 0.77};
            const TruthHit h = tr.trace(P, V);
            const double z = 0.05 * (double(0.3f) - b);
            EXPECT_NEAR(h.uv.x, P.x + V.x / V.z * z, 1e-12) << theta << " " << b;
            EXPECT_NEAR(h.uv.y, P.y + V.y / V.z * z, 1e-12);
            EXPECT_NEAR(h.z, z, 1e-14);
        }
}

// Single cell, straight down: the hit is the bilinear height itself.
TEST(ExactTracer, StraightDownHitsBilinearHeight) {
    const HeightField hf = test::random_field(16, 16, 3);
    const ExactTracer tr(hf, 0.1, 0.5);
    HeightSampler<double> hs(hf, 0.1, 0.5);
    for (const Vec2d P : test::random_points(200, 4)) {
        const TruthHit h = tr.trace(P, {0, 0, 1});
        EXPECT_NEAR(h.z, hs.z(P), 1e-14);
        EXPECT_DOUBLE_EQ(h.uv.x, P.x);
    }
}

// Random fields, many angles (up to 89 degrees, rays crossing many tiles): the exact hit
// agrees with a fine brute-force march. Brute force may step over a clip thinner than its
// step, so a mismatch is allowed only where the exact hit is earlier along the ray.
TEST(ExactTracer, AgreesWithBruteForceMarch) {
    struct Case {
        int w, h;
        double s, b, theta, phi;
    };
    const Case cases[] = {{16, 16, 0.05, 1.0, 30, 0}, {16, 16, 0.05, 1.0, 60, 45},
                          {32, 8, 0.1, 0.5, 75, 200}, {16, 16, 0.2, 0.0, 85, 130},
                          {8, 8, 0.05, 1.0, 89, 10},  {5, 7, 0.5, 0.3, 80, 300},
                          {16, 16, 1.0, 1.0, 70, 91}};
    int total = 0, exact_match = 0;
    for (const Case& c : cases) {
        const HeightField hf = test::random_field(c.w, c.h, 11 + c.w);
        const ExactTracer tr(hf, c.s, c.b);
        const Vec3d V = view_vector(c.theta, c.phi);
        const double texel = 1.0 / std::max(c.w, c.h);
        const double step = texel / 400 * V.z;  // fine in both height and distance
        for (const Vec2d P : test::random_points(60, 5)) {
            const Vec2d e = tr.trace(P, V).uv;
            const Vec2d bf = test::brute_force_hit(hf, c.s, c.b, P, V, step);
            const double d = std::hypot((e.x - bf.x) * c.w, (e.y - bf.y) * c.h);
            ++total;
            if (d < 1e-6) {
                ++exact_match;
            } else {
                // Exact must be the earlier hit (closer to the eye): further along +V.xy.
                const double along_e = e.x * V.x + e.y * V.y, along_b = bf.x * V.x + bf.y * V.y;
                EXPECT_GT(along_e, along_b)
                    << "case theta=" << c.theta << " P=" << P.x << "," << P.y;
            }
        }
    }
    EXPECT_GE(exact_match, total * 99 / 100) << exact_match << " of " << total;
}

TEST(ExactTracer, TilingIsPeriodic) {
    const HeightField hf = test::random_field(12, 9, 21);
    const ExactTracer tr(hf, 0.3, 0.6);
    const Vec3d V = view_vector(84, 33);
    for (const Vec2d P : test::random_points(50, 8)) {
        const Vec2d a = tr.trace(P, V).uv, b = tr.trace({P.x + 3, P.y - 2}, V).uv;
        EXPECT_NEAR(b.x - 3, a.x, 1e-9);
        EXPECT_NEAR(b.y + 2, a.y, 1e-9);
    }
}

// The maximum-mipmap tracer against the per-cell DDA: within 1e-9 texel on every ray (random fields
// of awkward sizes, many scales and biases, angles up to 89.9 degrees).
TEST(ExactTracer, HierarchicalEqualsNaiveOnEveryRay) {
    struct Case {
        int w, h;
        double s, b;
    };
    const Case cases[] = {{64, 64, 0.05, 1.0}, {300, 7, 0.1, 0.5}, {37, 129, 0.3, 0.0},
                          {1, 1, 0.05, 1.0},   {2, 2, 1.0, 0.5},   {128, 96, 0.02, 0.7},
                          {256, 256, 1.0, 1.0}};
    long long rays = 0, differ = 0;
    double worst = 0;
    for (const Case& c : cases) {
        const HeightField hf = test::random_field(c.w, c.h, uint32_t(c.w * 31 + c.h));
        const ExactTracer tr(hf, c.s, c.b);
        for (double theta : {0.0, 10.0, 45.0, 60.0, 80.0, 85.0, 89.0, 89.9})
            for (double phi : {0.0, 17.0, 90.0, 135.0, 251.0}) {
                const Vec3d V = view_vector(theta, phi);
                for (const Vec2d P : test::random_points(40, uint32_t(theta * 7 + phi))) {
                    const TruthHit a = tr.trace(P, V), b = tr.trace_naive(P, V);
                    const double d = std::hypot((a.uv.x - b.uv.x) * c.w, (a.uv.y - b.uv.y) * c.h);
                    worst = std::max(worst, d);
                    differ += (a.uv.x != b.uv.x || a.uv.y != b.uv.y);
                    ++rays;
                }
            }
    }
    EXPECT_LE(worst, 1e-9) << "texel; " << differ << " of " << rays << " rays not bit-identical";
}

// The whole-view tracer (the grid's parallel rays in lateral bands) against the per-cell DDA,
// on every ray: random fields of awkward sizes, azimuths on the axes and diagonals (ties between
// grid lines), rays starting exactly on grid lines (n = w, b = 1), angles to 89.9 degrees.
TEST(ExactTracer, GridTracerEqualsNaiveOnEveryRay) {
    struct Case {
        int w, h;
        double s, b;
        int n;
    };
    // n = w: one sample per cell (bands one cell wide, bounds from the cells themselves); fewer
    // samples: wider bands, bounds from coarser mipmap levels (odd sizes: partial blocks).
    const Case cases[] = {
        {64, 64, 0.05, 1.0, 64},  {300, 7, 0.1, 0.5, 30}, {37, 129, 0.3, 0.0, 37},
        {1, 1, 0.05, 1.0, 5},     {2, 2, 1.0, 0.5, 8},    {128, 96, 0.02, 0.7, 50},
        {256, 256, 1.0, 1.0, 32}, {64, 64, 0.1, 1.0, 16}, {129, 67, 0.05, 0.5, 20},
        {129, 67, 0.3, 0.5, 10},  {3, 200, 0.5, 0.5, 2},  {200, 3, 0.5, 0.5, 2},
        {37, 129, 0.3, 0.0, 6},   {300, 7, 0.1, 0.5, 5}};
    long long rays = 0, differ = 0;
    double worst = 0;
    for (const Case& c : cases) {
        const HeightField hf = test::random_field(c.w, c.h, uint32_t(c.w * 31 + c.h));
        const ExactTracer tr(hf, c.s, c.b);
        const std::vector<Vec2d> P = sample_grid(c.n);
        for (double theta : {0.0, 10.0, 45.0, 60.0, 80.0, 85.0, 89.0, 89.9})
            for (double phi : {0.0, 17.0, 45.0, 90.0, 135.0, 180.0, 251.0, 270.0, 315.0}) {
                const Vec3d V = view_vector(theta, phi);
                std::vector<TruthHit> g;
                tr.trace_grid(c.n, V, g);
                ASSERT_EQ(g.size(), P.size());
                for (size_t k = 0; k < P.size(); ++k) {
                    const TruthHit b = tr.trace_naive(P[k], V);
                    const double d =
                        std::hypot((g[k].uv.x - b.uv.x) * c.w, (g[k].uv.y - b.uv.y) * c.h);
                    worst = std::max(worst, d);
                    differ += (g[k].uv.x != b.uv.x || g[k].uv.y != b.uv.y || g[k].z != b.z);
                    ++rays;
                }
            }
    }
    EXPECT_EQ(differ, 0) << "of " << rays << " rays; worst " << worst << " texel";
    EXPECT_LE(worst, 1e-9);
}

// Coarse bounds at a tile seam: with 129 columns, level-2 blocks end in a one-column block, so a
// run of 4 columns crossing the seam touches three block columns. A wall standing on exactly
// that column (and on the first row, for the other axis) must be seen by every ray.
TEST(ExactTracer, ViewTracerSeesWallsOnPartialBlocksAtTheSeam) {
    for (const bool along_x : {true, false}) {
        const int W = along_x ? 129 : 64, H = along_x ? 64 : 129;
        HeightField hf(W, H, "seam-wall");
        for (int j = 0; j < H; ++j)
            for (int i = 0; i < W; ++i)
                hf.texels[size_t(j) * W + i] =
                    (along_x ? i == W - 1 : j == H - 1) ? 1.0f : 0.05f * float((i * 7 + j * 3) % 5);
        const ExactTracer tr(hf, 0.2, 1.0);
        const int n = 12;  // sparse samples: wide bands, bounds from level 2
        const auto P = sample_grid(n);
        long long differ = 0;
        for (double theta : {60.0, 80.0, 85.0})
            for (double phi : {0.0, 17.0, 90.0, 163.0, 180.0, 197.0, 270.0, 343.0}) {
                const Vec3d V = view_vector(theta, phi);
                std::vector<TruthHit> g;
                tr.trace_grid(n, V, g);
                for (size_t k = 0; k < P.size(); ++k) {
                    const TruthHit b = tr.trace_naive(P[k], V);
                    differ += (g[k].uv.x != b.uv.x || g[k].uv.y != b.uv.y);
                }
            }
        EXPECT_EQ(differ, 0) << (along_x ? "wall on the last column" : "wall on the last row");
    }
}

TEST(GroundTruth, IndependentOfThreadCount) {
    // With 1, 2 and 3 threads (bands then land on different threads in different orders), and
    // with dense and sparse samples (narrow and wide bands): identical, bit for bit.
    const HeightField hf = test::random_field(96, 80, 2);
    for (int n : {96, 24})
        for (double theta : {70.0, 88.0}) {
            std::vector<GroundTruth> runs;
            for (int threads : {1, 2, 3}) {
                tbb::global_control limit(tbb::global_control::max_allowed_parallelism,
                                          size_t(threads));
                runs.push_back(trace_ground_truth(hf, 0.05, 1.0, view_vector(theta, 10), n));
            }
            for (const GroundTruth& g : runs) {
                ASSERT_EQ(g.uv.size(), runs[0].uv.size());
                EXPECT_EQ(g.cells_mean, runs[0].cells_mean);
                for (size_t i = 0; i < g.uv.size(); ++i) {
                    ASSERT_EQ(g.uv[i].x, runs[0].uv[i].x);
                    ASSERT_EQ(g.uv[i].y, runs[0].uv[i].y);
                    ASSERT_EQ(g.z[i], runs[0].z[i]);
                }
            }
        }
}

}  // namespace
}  // namespace pxh
