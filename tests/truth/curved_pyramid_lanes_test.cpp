// The pyramid tracer's vector paths (issue 62, item 2: harness/truth/curved_pyramid_lanes.h on
// the lane types of harness/truth/lanes.h) against its scalar trace_one: every ray's hit, t,
// residual, step count and hit's (u, v) bit for bit, on every path this CPU has (AVX-512: 8 doubles
// to a vector, AVX2: 4), over random views of random fields (plateaus, spikes), both bases, R from
// 0.1 to 1e6, orthographic and perspective cameras, with breakages of the pyramid, which the
// lanes must follow as the scalar code does.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "harness/scene/base_surface.h"
#include "harness/scene/curved_view.h"
#include "harness/scene/perspective_camera.h"
#include "harness/truth/curved_pyramid.h"
#include "harness/truth/curved_tracer.h"
#include "tests/test_util.h"
#include "tests/truth/random_curved_view.h"

namespace pxh {
namespace {

using test::generated_field;

// The vector paths this CPU runs (PXH_TRACER_PATH may lower the widest, never raise it).
std::vector<CurvedPyramid::Path> vector_paths() {
    std::vector<CurvedPyramid::Path> p;
    if (__builtin_cpu_supports("avx2")) p.push_back(CurvedPyramid::Path::avx2);
    if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq"))
        p.push_back(CurvedPyramid::Path::avx512);
    return p;
}

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// The rays on `path` in batches of `batch` against trace_one (and trace_one's texture
// coordinates of a hit against the base's, BaseSurface::coords at o + t d); the first ray that
// differs.
std::string differs(const CurvedPyramid& pyr, const BaseSurface& base,
                    const std::vector<WorldRay>& rays, CurvedPyramid::Path path, size_t batch,
                    size_t& hits) {
    std::vector<CurvedPyramid::One> got(rays.size());
    for (size_t at = 0; at < rays.size(); at += batch)
        pyr.trace_many(&rays[at], std::min(batch, rays.size() - at), &got[at], 1LL << 40, path);
    for (size_t k = 0; k < rays.size(); ++k) {
        const CurvedPyramid::One want = pyr.trace_one(rays[k], (1LL << 40) + 4096);
        hits += want.hit;
        if (want.hit) {
            const Vec2d uv = base.coords(v3_add(rays[k].o, v3_scale(rays[k].d, want.t))).uv;
            if (!same_bits(uv.x, want.u) || !same_bits(uv.y, want.v))
                return "ray " + std::to_string(k) + ": trace_one's uv is not the base's at its t";
        }
        if (want.hit != got[k].hit || !same_bits(want.u, got[k].u) ||
            !same_bits(want.v, got[k].v) || !same_bits(want.t, got[k].t) ||
            !same_bits(want.residual, got[k].residual) || want.steps != got[k].steps)
            return "ray " + std::to_string(k) + ": trace_one hit " + std::to_string(want.hit) +
                   " t " + std::to_string(want.t) + " steps " + std::to_string(want.steps) + ", " +
                   CurvedPyramid::path_name(path) + " hit " + std::to_string(got[k].hit) + " t " +
                   std::to_string(got[k].t) + " steps " + std::to_string(got[k].steps);
    }
    return "";
}

TEST(CurvedPyramidLanes, RandomViewsBitForBitTraceOne) {
    const auto paths = vector_paths();
    if (paths.empty()) GTEST_SKIP() << "this CPU has no vector path (AVX2 or AVX-512)";
    std::mt19937 rng(11);
    size_t rays = 0, hits = 0;
    for (int view = 0; view < 240; ++view) {
        const auto v = test::random_curved_view(rng);
        if (!v) continue;
        const CurvedView& cv = v->cv;
        const CurvedPyramid pyr(v->hf, v->s, v->b, *v->base);
        // batches of 1 (one lane busy), 37 (lanes left idle at the end) and the whole view
        const size_t batch = view % 3 == 0 ? 1 : (view % 3 == 1 ? 37 : cv.rays.size());
        for (CurvedPyramid::Path path : paths) {
            const std::string d = differs(pyr, *v->base, cv.rays, path, batch, hits);
            EXPECT_EQ(d, "") << "view " << view << ": " << v->name << " R " << v->R << " theta "
                             << v->theta;
        }
        rays += cv.rays.size();
    }
    EXPECT_GT(rays, 50000u);
    EXPECT_GT(hits, 40000u * paths.size());
}

// Fields of the bench (fbm 128^2) at the bench's angles, grazing views, the bounds lowered by a
// float step and nodes skipped (break_for_test): the lanes take the broken pyramid's steps too.
TEST(CurvedPyramidLanes, FbmGrazingAndBrokenPyramids) {
    const auto paths = vector_paths();
    if (paths.empty()) GTEST_SKIP() << "this CPU has no vector path (AVX2 or AVX-512)";
    const HeightField hf = generated_field("fbm", 128);
    size_t hits = 0;
    for (const char* name : {"cylinder", "sphere"})
        for (double R : {0.3, 1.5, 4.0})
            for (double theta : {0.0, 60.0, 85.0, 89.0})
                for (int breakage = 0; breakage < 3; ++breakage) {
                    const auto base = make_base(name, R);
                    const OrthographicCamera cam(theta, 20, 24);
                    const CurvedView cv = curved_view(cam, *base, 0);
                    CurvedPyramid pyr(hf, 0.05, 1, *base);
                    if (breakage == 1) pyr.break_for_test({1, -1});
                    if (breakage == 2) pyr.break_for_test({0, 2});
                    for (CurvedPyramid::Path path : paths)
                        EXPECT_EQ(differs(pyr, *base, cv.rays, path, 256, hits), "")
                            << name << " R " << R << " theta " << theta << " breakage " << breakage;
                }
    EXPECT_GT(hits, 3000u * paths.size());
}

// The path in words, and PXH_TRACER_PATH's choice (the tests run with it unset, as CI does):
// the default path is the widest this CPU has (AVX-512F and DQ; AVX2 with FMA, as the exact
// tracer's), and this build (GCC on x86-64) has the lanes.
TEST(CurvedPyramidLanes, DefaultPathIsTheWidest) {
    const CurvedPyramid::Path widest =
        __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq")
            ? CurvedPyramid::Path::avx512
            : (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")
                   ? CurvedPyramid::Path::avx2
                   : CurvedPyramid::Path::scalar);
    EXPECT_EQ(CurvedPyramid::cpu_path(), widest);
    EXPECT_EQ(CurvedPyramid::path_name(CurvedPyramid::Path::avx512),
              "avx512: 8 rays to a vector, double");
    EXPECT_EQ(CurvedPyramid::path_name(CurvedPyramid::Path::scalar), "scalar double");
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
    EXPECT_EQ(PXH_PYRAMID_LANES, 1);  // the project's compiler builds the lanes
#endif
    const char* env = std::getenv("PXH_TRACER_PATH");
    if (env && *env) GTEST_SKIP() << "PXH_TRACER_PATH is set";
    EXPECT_EQ(CurvedPyramid::default_path(), widest);
}

// The budget: a caller's stop (another thread spent the view's budget) ends the rays under way
// as over budget and leaves the rest unstarted, on every path; through CurvedTracer, a view
// over its budget is refused with CurvedWalkTooLong, as the walk's.
TEST(CurvedPyramidLanes, StopAndBudget) {
    const HeightField hf = generated_field("fbm", 64);
    const auto base = make_base("cylinder", 1.5);
    const OrthographicCamera cam(60, 20, 32);
    const CurvedView cv = curved_view(cam, *base, 0);
    const CurvedPyramid pyr(hf, 0.05, 1, *base);
    const std::atomic<bool> stop{true};
    std::vector<CurvedPyramid::Path> paths = vector_paths();
    paths.push_back(CurvedPyramid::Path::scalar);
    for (CurvedPyramid::Path path : paths) {
        std::vector<CurvedPyramid::One> got(cv.rays.size());
        pyr.trace_many(cv.rays.data(), got.size(), got.data(), 1LL << 40, path, &stop);
        size_t hits = 0, started = 0;
        long long most = 0;
        for (const auto& o : got) {
            hits += o.hit;
            started += o.steps > 0;
            most = std::max(most, o.steps);
        }
        EXPECT_EQ(hits, 0u) << CurvedPyramid::path_name(path);
        EXPECT_LE(started, 32u) << CurvedPyramid::path_name(path);  // one round of the lanes
        EXPECT_LE(most, 2 + pyr.levels()) << CurvedPyramid::path_name(path);
    }
    // the whole view takes about 18 steps a ray: a budget of 1000 steps is refused
    const CurvedTracer truth(hf, 0.05, 1, *base, 0.25, CurvedMethod::pyramid);
    EXPECT_THROW(truth.trace(cv.rays, 1000), CurvedWalkTooLong);
    EXPECT_NO_THROW(truth.trace(cv.rays, 1e6));
}

}  // namespace
}  // namespace pxh
