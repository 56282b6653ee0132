// Self-shadowing: the exact occlusion query against a closed form and brute force, and the
// tutorial's hard/soft march against the truth where the answer is unambiguous.
#include "methods/shadow.h"

#include <gtest/gtest.h>

#include <cmath>

#include "harness/truth/ground_truth.h"
#include "tests/test_util.h"

namespace pxh {
namespace {

// Plateau h = 1 on texels [0, W/2), low ground h = 0 on [W/2, W); the bilinear ramp runs from
// the centre of texel W/2 - 1 (top edge) to the centre of texel W/2.
HeightField cliff(int W) {
    HeightField hf(W, 4);
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < W; ++i) hf.at(i, j) = i < W / 2 ? 1.0f : 0.0f;
    return hf;
}

// Light from -u (phi = 180) at polar angle theta_L: a low-ground point at distance D past the
// top edge is in shadow iff the ray is still below the top there: D cot(theta_L) < s.
TEST(ShadowTruth, CliffClosedForm) {
    const int W = 256;
    const HeightField hf = cliff(W);
    const double s = 0.05;
    const ExactTracer tr(hf, s, 1.0);
    const double u_top = (W / 2 - 0.5) / W;
    int checked = 0;
    for (double theta_l : {30.0, 60.0, 80.0}) {
        const Vec3d L = view_vector(theta_l, 180);
        const double cot = 1 / std::tan(theta_l * M_PI / 180);
        for (double u = u_top + 1.5 / W; u < 0.999; u += 0.0037) {
            const double D = u - u_top;
            if (std::abs(D * cot - s) < 1e-6) continue;  // on the shadow boundary
            const bool expect = D * cot < s;
            EXPECT_EQ(tr.occluded({u, 0.5}, -s, L), expect) << "theta_l=" << theta_l << " u=" << u;
            ++checked;
        }
        // The plateau itself is lit (nothing above it), and so is any point straight up.
        EXPECT_FALSE(tr.occluded({0.25, 0.5}, 0.0, L));
        EXPECT_FALSE(tr.occluded({0.75, 0.5}, -s, {0, 0, 1}));
    }
    EXPECT_GT(checked, 300);
}

TEST(ShadowTruth, AgreesWithBruteForce) {
    int total = 0, agree = 0;
    for (int seed = 1; seed <= 4; ++seed) {
        const HeightField hf = test::random_field(24, 24, seed);
        const double s = 0.05 * seed, b = 0.25 * (seed - 1);
        const ExactTracer tr(hf, s, b);
        HeightSampler<double> hs(hf, s, b);
        for (double theta_l : {20.0, 55.0, 75.0, 86.0}) {
            const Vec3d L = view_vector(theta_l, 40.0 * seed);
            for (const Vec2d P : test::random_points(80, seed)) {
                const double z0 = hs.z(P);
                // March along L in tiny steps; occluded if the ray dips clearly below.
                const double tau_max = (s * (1 - b) - z0) / L.z;
                const double step = (1.0 / 24) / 500;
                double min_f = 1e300;
                for (double t = step; t < tau_max; t += step)
                    min_f = std::min(min_f, (z0 + t * L.z) - hs.z({P.x + t * L.x, P.y + t * L.y}));
                if (std::abs(min_f) < 1e-7 * s) continue;  // grazing: either answer is fine
                ++total;
                agree += tr.occluded(P, z0, L) == (min_f < 0);
            }
        }
    }
    EXPECT_GE(agree, total - total / 200) << agree << " of " << total;
    EXPECT_GT(total, 1000);
}

TEST(ShadowMarch, FlatFieldIsAlwaysLit) {
    const HeightField hf = test::flat_field(16, 16, 0.4f);
    const Scene<double> sc{0.05, 1.0, view_vector(0, 0), 16, 16};
    for (double theta_l : {0.0, 45.0, 85.0}) {
        HeightSampler<double> hs(hf, 0.05, 1.0);
        const auto f = shadow_factors(ShadowConfig{}, sc, view_vector(theta_l, 10), hs, {0.3, 0.3});
        EXPECT_EQ(f.hard, 1.0);
        EXPECT_EQ(f.soft, 1.0);
    }
}

// On the cliff, the tutorial's march gets the hard state right away from the boundary
// (within a layer step of it either answer is possible), and soft shadow is darker nearer
// the wall.
TEST(ShadowMarch, CliffHardStateMatchesTruthAwayFromBoundary) {
    const int W = 256;
    const HeightField hf = cliff(W);
    const double s = 0.05, theta_l = 60;
    const Scene<double> sc{s, 1.0, view_vector(0, 0), W, 4};
    const Vec3d L = view_vector(theta_l, 180);
    const ExactTracer tr(hf, s, 1.0);
    const double u_top = (W / 2 - 0.5) / W, cot = 1 / std::tan(theta_l * M_PI / 180);
    const double reach = s / cot;  // shadow length past the top edge
    double prev_soft = -1;
    int checked = 0;
    for (double D = 2.0 / W; D < 0.3; D += 0.002) {
        HeightSampler<double> hs(hf, s, 1.0);
        const Vec2d uv{u_top + D, 0.5};
        const auto f = shadow_factors(ShadowConfig{}, sc, L, hs, uv);
        const double layer = reach / 8;  // n >= 8 layers over the climb to z_top
        if (std::abs(D - reach) > layer + 2.0 / W) {
            EXPECT_EQ(f.hard == 1.0, !tr.occluded(uv, -s, L)) << "D=" << D;
            ++checked;
        }
        EXPECT_GE(f.soft, prev_soft - 1e-12) << "soft shadow must lighten away from the wall";
        prev_soft = f.soft;
        EXPECT_GE(f.soft, 0.0);
        EXPECT_LE(f.soft, 1.0);
    }
    EXPECT_GT(checked, 100);
}

}  // namespace
}  // namespace pxh
