// The exact tracer's per-ray fast path (trace_ray, the path perspective views take): on
// perspective rays (several angles, eye distances and fields of view; random, procedural and
// measured fields) and on the rays that stress a DDA (starts on grid lines, axis-parallel and
// vertical directions, flat and spiky fields, odd sizes) every hit equals the per-cell DDA's
// (trace_naive) bit for bit, uv and z; the view's outside pixels too (they carry the look-at
// ray). The walk solves a subset of the DDA's cells (on smooth fields far fewer): a
// different path, the same answers.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "harness/scene/perspective_camera.h"
#include "harness/truth/exact_tracer.h"
#include "heightfields/heightfields.h"
#include "heightfields/scanned.h"
#include "tests/test_util.h"

namespace pxh {
namespace {

HeightField generated(const char* name, int size) {
    const GeneratorInfo* g = find_generator(name);
    return generate_heightfield(*g, size, size, resolve_params(g->params, {}, "test", name));
}

struct Tally {
    long long rays = 0, differ = 0, walk_cells = 0, naive_cells = 0;
};

// The walk itself (trace_walk, for every ray) and trace_ray (the DDA for short rays) against
// the DDA.
void compare_ray(const ExactTracer& t, Vec2d P, Vec3d V, Tally& tally) {
    const TruthHit a = t.trace_walk(P, V), b = t.trace_naive(P, V), c = t.trace_ray(P, V);
    const bool same = a.uv.x == b.uv.x && a.uv.y == b.uv.y && a.z == b.z && c.uv.x == b.uv.x &&
                      c.uv.y == b.uv.y && c.z == b.z;
    if (!same && tally.differ < 5)
        ADD_FAILURE() << "P = (" << P.x << ", " << P.y << "), V = (" << V.x << ", " << V.y << ", "
                      << V.z << "): walk (" << a.uv.x << ", " << a.uv.y << ", " << a.z
                      << "), naive (" << b.uv.x << ", " << b.uv.y << ", " << b.z << ")";
    tally.differ += !same;
    EXPECT_LE(a.cells, b.cells);  // a subset of the DDA's cells
    tally.walk_cells += a.cells;
    tally.naive_cells += b.cells;
    ++tally.rays;
}

PerspectiveParams params(double theta, double phi, double distance, double fov, int n) {
    return {theta, phi, distance, fov, n};
}

// Every pixel of perspective views through the walk, the DDA and the Tracer interface.
Tally perspective_views(const HeightField& hf, double s, double b, int n) {
    const ExactTracer t(hf, s, b);
    Tally tally;
    size_t outside = 0;
    for (double theta : {0.0, 30.0, 60.0, 75.0, 85.0, 89.0})
        for (double distance : {1.5, 4.0, 16.0})
            for (double fov : {45.0, 90.0}) {
                const PerspectiveParams p = params(theta, 20 + 37 * theta, distance, fov, n);
                if (!eye_slab_problem(p, s, b).empty()) continue;
                const PerspectiveCamera cam(p);
                const View view = cam.view();
                outside += cam.outside_count();
                Hits through;
                t.trace(view, through);  // the interface: a perspective view is traced per ray
                for (size_t k = 0; k < view.size(); ++k) {
                    compare_ray(t, view.P[k], view.V[k], tally);
                    const TruthHit ref = t.trace_naive(view.P[k], view.V[k]);
                    tally.differ += through.uv[k].x != ref.uv.x || through.uv[k].y != ref.uv.y ||
                                    through.z[k] != ref.z;
                }
            }
    EXPECT_GT(outside, 0u);  // grazing views have pixels past the horizon: traced alike
    return tally;
}

TEST(RayWalk, PerspectiveRaysHitWhatTheCellDdaHitsBitForBit) {
    struct Case {
        const char* what;
        HeightField hf;
        double s, b;
        int n;
        bool smooth;
    };
    const Case cases[] = {
        {"random 64", test::random_field(64, 64, 7), 0.05, 1.0, 24, false},
        {"random 37 x 129", test::random_field(37, 129, 8), 0.1, 0.5, 20, false},
        {"fbm 256", generated("fbm", 256), 0.05, 1.0, 24, true},
        {"luxembourg (measured)", load_scan("luxembourg", "test"), 0.05, 1.0, 24, true},
    };
    for (const Case& c : cases) {
        const Tally t = perspective_views(c.hf, c.s, c.b, c.n);
        EXPECT_EQ(t.differ, 0) << c.what << ": of " << t.rays << " rays";
        EXPECT_GT(t.rays, 1000) << c.what;
        // A different path, solving a subset of the DDA's cells: on smooth fields the block
        // maxima rule most of them out (on white noise every block holds a high corner).
        EXPECT_LE(t.walk_cells, t.naive_cells) << c.what;
        if (c.smooth) {
            EXPECT_LT(t.walk_cells, t.naive_cells / 2) << c.what;
        }
    }
}

TEST(RayWalk, RaysThatStressTheDdaHitWhatItHits) {
    struct Case {
        const char* what;
        HeightField hf;
        double s, b;
    };
    HeightField flat = test::random_field(32, 32, 1);
    for (float& v : flat.texels) v = 0.25f;
    HeightField bottom = flat;
    for (float& v : bottom.texels) v = 0.0f;
    HeightField spike = bottom;
    spike.texels[17 * 32 + 9] = 1.0f;
    const Case cases[] = {{"flat", flat, 0.05, 1.0},
                          {"at the slab bottom", bottom, 0.2, 0.5},
                          {"one spike", spike, 0.3, 1.0},
                          {"random 3 x 200", test::random_field(3, 200, 4), 0.5, 0.5},
                          {"random 128 x 96", test::random_field(128, 96, 5), 0.1, 0.7}};
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> unit(0, 1);
    for (const Case& c : cases) {
        const ExactTracer t(c.hf, c.s, c.b);
        const int W = c.hf.width, H = c.hf.height;
        Tally tally;
        for (double theta : {0.0, 10.0, 45.0, 70.0, 85.0, 89.5})
            for (double phi : {0.0, 45.0, 90.0, 135.0, 180.0, 200.0, 270.0, 333.0}) {
                const Vec3d V = view_vector(theta, phi);
                for (int k = 0; k < 60; ++k) {
                    Vec2d P{unit(rng) * 3 - 1, unit(rng) * 3 - 1};
                    // Starts on grid lines (the entry point's X0 or Y0 an integer, or both:
                    // at phi = 45 on a square field such a ray passes through cell corners).
                    const double zt = c.s * (1 - c.b);
                    if (k % 3 != 2) P.x = (std::floor(unit(rng) * W) + 0.5) / W - V.x / V.z * zt;
                    if (k % 3 != 1) P.y = (std::floor(unit(rng) * H) + 0.5) / H - V.y / V.z * zt;
                    compare_ray(t, P, V, tally);
                }
            }
        EXPECT_EQ(tally.differ, 0) << c.what << ": of " << tally.rays << " rays";
    }
}

}  // namespace
}  // namespace pxh
