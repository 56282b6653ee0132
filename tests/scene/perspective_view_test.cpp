// A perspective camera's View through the stages after it (docs/conventions.md section 10):
// both tracers take its per-pixel rays, the exact hits match a brute-force march (and Embree on
// planar patches), and with a vanishing relief the truth and the single-step and layered methods
// return the sample itself.
#include <gtest/gtest.h>

#include <cmath>

#include "harness/backends/cpu_backend.h"
#include "harness/metrics/metrics.h"
#include "harness/scene/perspective_camera.h"
#include "harness/truth/tracer.h"
#include "heightfields/heightfields.h"
#include "tests/test_util.h"

namespace pxh {
namespace {

PerspectiveParams params(double theta, double phi, double distance, double fov, int n) {
    return {theta, phi, distance, fov, n};
}

double texels(Vec2d a, Vec2d b, int w, int h) {
    return std::hypot((a.x - b.x) * w, (a.y - b.y) * h);
}

TEST(PerspectiveView, ExactHitsAreTheBruteForceMarch) {
    const int W = 64;
    const HeightField hf = test::random_field(W, W, 31);
    const double s = 0.05, b = 1.0;
    const PerspectiveParams p = params(75, 30, 1.5, 60, 40);
    check_eye_above_slab(p, s, b, "test");
    const PerspectiveCamera cam(p);
    const View view = cam.view();
    const std::vector<uint8_t> in = cam.inside();
    ASSERT_GT(cam.outside_count(), 0u);  // the top rows are past the horizon
    Hits exact;
    make_tracer("exact", hf, s, b)->trace(view, exact);
    ASSERT_EQ(exact.uv.size(), view.size());
    int total = 0, match = 0;
    for (size_t k = 0; k < view.size(); ++k) {
        if (!in[k]) continue;
        const Vec3d V = view.V[k];
        if (k % 7 != 0 || V.z < 0.3) continue;  // the march costs s W 400 / V.z^2 steps
        const Vec2d bf = test::brute_force_hit(hf, s, b, view.P[k], V, 1.0 / W / 400 * V.z);
        ++total;
        if (texels(exact.uv[k], bf, W, W) < 1e-6) {
            ++match;
        } else {  // the march stepped over a thin crossing: exact is the earlier hit
            EXPECT_GT(exact.uv[k].x * V.x + exact.uv[k].y * V.y, bf.x * V.x + bf.y * V.y) << k;
        }
    }
    EXPECT_GT(total, 50);
    EXPECT_GE(match, total * 95 / 100);
}

// h = f(u) + g(v) (the "sine" field) makes every bilinear patch planar, so Embree's two
// triangles per cell are the exact surface: on the perspective rays too the references agree to
// Embree's float precision (as tests/truth/embree_test.cpp on the grid).
TEST(PerspectiveView, EmbreeMatchesExactOnPlanarPatches) {
    const HeightField hf = test::generated_field("sine", 64);
    for (const double theta : {40.0, 80.0}) {
        const PerspectiveCamera cam(params(theta, 123, 1.2, 75, 40));
        check_eye_above_slab(cam.params(), 0.05, 0.5, "test");
        const View view = cam.view();
        const std::vector<uint8_t> in = cam.inside();
        Hits exact, embree;
        make_tracer("exact", hf, 0.05, 0.5)->trace(view, exact);
        make_tracer("embree", hf, 0.05, 0.5)->trace(view, embree);
        double worst = 0;
        for (size_t k = 0; k < view.size(); ++k) {
            if (!in[k]) continue;
            const Vec2d e = texel_error(embree.uv[k], exact.uv[k], hf.width, hf.height);
            worst = std::max(worst, std::hypot(e.x, e.y));
        }
        EXPECT_LT(worst, 2e-3) << theta;
    }
}

// s -> 0: the relief vanishes, so the visible point is the sample P itself, and every method
// below returns P (to within s / V.z of offset), whatever each pixel's V.
TEST(PerspectiveView, VanishingReliefIsExactUnderThePerspectiveCamera) {
    const int W = 64;
    const HeightField hf = test::random_field(W, W, 41);
    const double s = 1e-9, b = 0.5;
    const PerspectiveCamera cam(params(70, 200, 2, 70, 32));
    const View view = cam.view();
    const std::vector<uint8_t> in = cam.inside();
    Hits truth;
    make_tracer("exact", hf, s, b)->trace(view, truth);
    const Scene<double> sc{s, b, view_vector(70, 200), W, W};
    for (const char* name : {"none", "parallax", "parallax_limited", "steep", "pom", "relief"}) {
        const MethodInfo& m = *find_method(name);
        const MethodSpec spec{&m, test::params_for(m)};
        for (const char* precision : {"double", "float"}) {
            const MethodOutput out = run_cpu(spec, precision, sc, hf, view.P, 0, nullptr, &view.V);
            // Float: P rounded to float, |P| up to tens of tiles here (1e-6 tile ~ 1e-4 texel).
            const double tol = std::string(precision) == "float" ? 1e-2 : 1e-4;
            for (size_t k = 0; k < view.size(); ++k) {
                if (!in[k]) continue;
                const Vec2d uv{out.uv[k].x, out.uv[k].y};
                ASSERT_LT(texels(uv, truth.uv[k], W, W), tol)
                    << name << " " << precision << " " << k;
                ASSERT_LT(texels(truth.uv[k], view.P[k], W, W), 1e-4) << k;
            }
        }
    }
}

}  // namespace
}  // namespace pxh
