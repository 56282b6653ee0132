// The tracer interface: the exact tracer's two paths (band tracer on an orthographic grid
// view, per ray otherwise) give the same hits bit for bit; Embree through the interface, also
// with a direction per ray, agrees with the exact tracer; the registry; the agreement
// statistics between two references.
#include "harness/truth/tracer.h"

#include <gtest/gtest.h>

#include <cmath>

#include "harness/core/error.h"
#include "harness/metrics/agreement.h"
#include "harness/truth/embree_truth.h"
#include "harness/truth/ground_truth.h"
#include "heightfields/heightfields.h"
#include "tests/test_util.h"

namespace pxh {
namespace {

HeightField generated(const char* name, int size) { return test::generated_field(name, size); }

// The same rays as an explicit per-sample view: one direction per ray, not marked parallel,
// not marked as the sample grid.
View per_sample(const View& v) {
    View out;
    out.P = v.P;
    out.V.assign(v.size(), v.V[0]);
    return out;
}

TEST(Tracer, ExactGridAndPerRayPathsAgreeBitForBit) {
    struct Case {
        int w, h;
        double s, b;
        int n;
    };
    const Case cases[] = {{64, 64, 0.05, 1.0, 64},
                          {37, 129, 0.3, 0.0, 20},
                          {128, 96, 0.1, 0.7, 50},
                          {3, 200, 0.5, 0.5, 9}};
    long long rays = 0, differ = 0, beyond = 0, band_cells = 0, naive_cells = 0;
    for (const Case& c : cases) {
        const HeightField hf = test::random_field(c.w, c.h, uint32_t(c.w * 17 + c.h));
        const auto exact = make_tracer("exact", hf, c.s, c.b);
        ExactTracer reference(hf, c.s, c.b);
        reference.set_path(ExactTracer::RayPath::scalar);  // the band tracer's scalar walk
        for (double theta : {0.0, 30.0, 70.0, 85.0, 89.5})
            for (double phi : {0.0, 45.0, 163.0, 270.0}) {
                const View grid = OrthographicCamera(theta, phi, c.n).view();
                ASSERT_TRUE(grid.orthographic_grid());
                const View each = per_sample(grid);
                ASSERT_FALSE(each.orthographic_grid());
                Hits a, b;
                exact->trace(grid, a);
                exact->trace(each, b);
                ASSERT_EQ(a.uv.size(), grid.size());
                ASSERT_EQ(b.uv.size(), grid.size());
                std::vector<TruthHit> band;
                reference.trace_grid(c.n, grid.V[0], band);
                for (size_t k = 0; k < grid.size(); ++k) {
                    differ += a.uv[k].x != b.uv[k].x || a.uv[k].y != b.uv[k].y || a.z[k] != b.z[k];
                    const int naive = reference.trace_naive(each.P[k], each.V[k]).cells;
                    beyond += a.cells[k] > naive || b.cells[k] > naive || band[k].cells > naive;
                    band_cells += band[k].cells;
                    naive_cells += naive;
                    ++rays;
                }
            }
    }
    EXPECT_EQ(differ, 0) << "of " << rays << " rays";
    // Every path counts the cells of trace_naive's DDA it solves, a subset of them; the band
    // tracer skips the cells its bounds rule out (so does the per-ray path,
    // tests/ray_walk_test.cpp): a different path from the per-cell DDA. Its scalar walk solves
    // the candidate runs' cells alone (on a vector path the DDA walks on past a run).
    EXPECT_EQ(beyond, 0) << "rays solving cells trace_naive does not reach";
    EXPECT_LT(band_cells, naive_cells / 2);
}

// Parallel rays off the grid (and a grid view whose rays are not parallel) take the per-ray
// path (trace_ray); still trace_naive's hits, solving a subset of its cells.
TEST(Tracer, ExactPerRayPathIsTraceNaive) {
    const HeightField hf = test::random_field(48, 40, 5);
    const ExactTracer exact(hf, 0.2, 0.5);
    View v;
    v.P = test::random_points(300, 9);
    v.V = {view_vector(75, 20)};
    v.parallel = true;
    Hits h;
    exact.trace(v, h);
    for (size_t k = 0; k < v.size(); ++k) {
        const TruthHit t = exact.trace_naive(v.P[k], v.V[0]);
        ASSERT_EQ(h.uv[k].x, t.uv.x);
        ASSERT_EQ(h.uv[k].y, t.uv.y);
        ASSERT_EQ(h.z[k], t.z);
        ASSERT_LE(h.cells[k], t.cells);
    }
}

// A fan of directions (each ray its own theta and phi): what a perspective camera gives.
View fan(int n) {
    View v = per_sample(orthographic_view(view_vector(0, 0), n));
    for (size_t k = 0; k < v.size(); ++k)
        v.V[k] = view_vector(80.0 * double(k % 97) / 96.0, 360.0 * double(k % 89) / 89.0);
    return v;
}

// h = f(u) + g(v): every bilinear patch is planar, so Embree's two triangles per cell are the
// exact surface (embree_test.cpp): both references agree to float precision, with one
// direction per ray too.
TEST(Tracer, EmbreeAgreesWithExactThroughTheInterface) {
    const HeightField hf = generated("sine", 64);
    for (double s : {0.05, 1.0}) {
        const auto exact = make_tracer("exact", hf, s, 0.5);
        const auto embree = make_tracer("embree", hf, s, 0.5);
        for (const View& v : {OrthographicCamera(85, 33, 48).view(), fan(48)}) {
            Hits a, b;
            exact->trace(v, a);
            embree->trace(v, b);
            EXPECT_TRUE(b.z.empty() && b.cells.empty());
            const ErrorStats st = reference_agreement(b.uv, a.uv, hf.width, hf.height);
            EXPECT_EQ(st.count, (long long)v.size());
            EXPECT_LT(st.max, 2e-3) << "s=" << s << (v.parallel ? " parallel" : " fan");
        }
    }
}

// Through the interface, a parallel view is exactly what the direct entry point traces.
TEST(Tracer, EmbreeParallelViewEqualsDirectEntry) {
    const HeightField hf = generated("fbm", 64);
    const EmbreeTracer embree(hf, 0.05, 1.0);
    const View v = OrthographicCamera(70, 10, 40).view();
    Hits h;
    embree.trace(v, h);
    const std::vector<Vec2d> direct = embree.trace(v.P, v.V[0]);
    Hits rays;  // the same direction given per ray: the same lanes, the same answers
    embree.trace(per_sample(v), rays);
    for (size_t k = 0; k < v.size(); ++k) {
        ASSERT_EQ(h.uv[k].x, direct[k].x);
        ASSERT_EQ(h.uv[k].y, direct[k].y);
        ASSERT_EQ(rays.uv[k].x, direct[k].x);
        ASSERT_EQ(rays.uv[k].y, direct[k].y);
    }
}

TEST(Tracer, RegistryListsExactAndEmbree) {
    EXPECT_EQ(tracer_names(), (std::vector<std::string>{"exact", "embree"}));
    const HeightField hf = test::random_field(8, 8, 1);
    for (const std::string& name : tracer_names())
        EXPECT_EQ(make_tracer(name, hf, 0.1, 1.0)->name(), name);
    try {
        (void)make_tracer("optix", hf, 0.1, 1.0);
        ADD_FAILURE() << "an unknown tracer was made";
    } catch (const InputError& e) {
        EXPECT_STREQ(e.what(), "tracer: unknown tracer 'optix' (known: exact, embree)");
    }
    EXPECT_THROW(check_tracer_name("Exact", "experiment.toml"), InputError);
    EXPECT_NO_THROW(check_tracer_name("embree", "experiment.toml"));
    EXPECT_THROW(make_tracer("exact", hf, 0.0, 1.0), std::invalid_argument);
}

TEST(Tracer, RefusesMalformedViewsAndRaysBeyondTheTravelLimit) {
    const HeightField hf = test::random_field(8, 8, 2);
    for (const std::string& name : tracer_names()) {
        const auto tr = make_tracer(name, hf, 1.0, 1.0);
        View v = per_sample(OrthographicCamera(30, 0, 4).view());
        Hits h;
        EXPECT_NO_THROW(tr->trace(v, h)) << name;
        v.V[7] = view_vector(89.999, 0);  // one ray of 16 travels 57296 tiles
        EXPECT_THROW(tr->trace(v, h), std::invalid_argument) << name;
        v.V.pop_back();
        EXPECT_THROW(tr->trace(v, h), std::invalid_argument) << name;
    }
}

// The truth stage through the interface equals the orthographic entry point, shadows and all;
// a tracer without a shadow query refuses a light.
TEST(Tracer, GroundTruthThroughTheInterface) {
    const HeightField hf = test::random_field(64, 48, 3);
    const ExactTracer exact(hf, 0.1, 1.0);
    const EmbreeTracer embree(hf, 0.1, 1.0);
    const Vec3d V = view_vector(60, 15), L = view_vector(70, 200);
    const GroundTruth a = trace_ground_truth(exact, V, 32, &L);
    const GroundTruth b = trace_ground_truth(static_cast<const Tracer&>(exact),
                                             per_sample(orthographic_view(V, 32)), &L);
    ASSERT_EQ(a.uv.size(), b.uv.size());
    size_t lit = 0;
    for (size_t k = 0; k < a.uv.size(); ++k) {
        ASSERT_EQ(a.uv[k].x, b.uv[k].x);
        ASSERT_EQ(a.uv[k].y, b.uv[k].y);
        ASSERT_EQ(a.z[k], b.z[k]);
        ASSERT_EQ(a.lit[k], b.lit[k]);
        lit += a.lit[k];
    }
    EXPECT_GT(lit, 0u);
    EXPECT_LT(lit, a.lit.size());  // some points in shadow: the query was asked
    EXPECT_TRUE(exact.has_shadow_query());
    EXPECT_FALSE(embree.has_shadow_query());
    EXPECT_THROW(embree.occluded({0.5, 0.5}, 0.0, L), std::logic_error);
    EXPECT_THROW(trace_ground_truth(embree, orthographic_view(V, 8), &L), std::logic_error);
    const GroundTruth e = trace_ground_truth(embree, orthographic_view(V, 8));
    EXPECT_EQ(e.uv.size(), 64u);
}

// Closed forms: offsets of a quarter texel and of 1, 2 texels (one across the tile seam).
TEST(Agreement, StatisticsOfKnownGaps) {
    const int W = 10, H = 20;
    std::vector<Vec2d> a, b;
    for (int k = 0; k < 8; ++k) {  // gap 0.25 texel
        a.push_back({0.3, 0.4});
        b.push_back({0.3 + 0.25 / W, 0.4});
    }
    a.push_back({0.99, 0.5});  // gap 1 texel: 0.99 -> 1.09, unwrapped past the seam
    b.push_back({1.09, 0.5});
    a.push_back({0.2, 3.0 - 1.0 / H});  // gap 2 texels in v, whole tiles apart
    b.push_back({-1.8, 1.0 + 1.0 / H});
    const ErrorStats st = reference_agreement(a, b, W, H);
    EXPECT_EQ(st.count, 10);
    EXPECT_NEAR(st.p50, 0.25, 1e-9);
    EXPECT_NEAR(st.max, 2.0, 1e-9);
    EXPECT_DOUBLE_EQ(st.frac_gt_0_5, 0.2);
    EXPECT_NEAR(st.p99, 1.0 + 0.91 * 1.0, 1e-9);  // position 8.91 of 0..9: 1 + 0.91 (2 - 1)
    EXPECT_THROW(reference_agreement(a, {}, W, H), std::logic_error);
}

}  // namespace
}  // namespace pxh
