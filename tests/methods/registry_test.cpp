// Every registered method, automatically (a new method is covered without editing this file):
// finite output on degenerate inputs, fetch counts within the declared bound, exact on flat
// fields where the method claims it.
#include <gtest/gtest.h>

#include <cmath>

#include "harness/metrics/metrics.h"
#include "harness/truth/ground_truth.h"
#include "tests/test_util.h"

namespace pxh {
namespace {

class EveryMethod : public ::testing::TestWithParam<std::string> {
  protected:
    const MethodInfo& m() const { return test::method(GetParam()); }
};

TEST(Registry, HasTheSeedMethods) {
    for (const char* name : {"none", "parallax", "parallax_limited", "parallax_clamped",
                             "parallax_halved", "pixel_step", "steep", "pom", "relief"})
        EXPECT_NE(find_method(name), nullptr) << name;
}

template <typename T>
void check_finite_and_bounded(const MethodInfo& m, const HeightField& hf, double s, double b,
                              double theta, const std::string& what) {
    const auto sc = test::make_scene(hf, s, b, theta, 37);
    const auto P = test::random_points(64, 3);
    std::vector<int> fetches;
    const ParamValues p = test::params_for(m);
    const auto uv = test::run_method<T>(m, p, sc, hf, P, &fetches);
    const int bound = m.max_fetches(p, sc);
    for (size_t i = 0; i < P.size(); ++i) {
        // a method that may discard answers NaN there (a NaN in both components)
        if (m.may_discard && std::isnan(uv[i].x) && std::isnan(uv[i].y)) continue;
        ASSERT_TRUE(std::isfinite(uv[i].x) && std::isfinite(uv[i].y))
            << m.name << " " << what << " theta=" << theta << " s=" << s << " b=" << b;
        ASSERT_LE(fetches[i], bound) << m.name << " " << what << " theta=" << theta;
        ASSERT_GE(fetches[i], 0);
    }
}

TEST_P(EveryMethod, FiniteAndWithinFetchBoundOnHardInputs) {
    const HeightField fields[] = {test::flat_field(1, 1, 0.5f),   test::random_field(2, 2, 1),
                                  test::random_field(64, 64, 2),  test::flat_field(16, 16, 0.0f),
                                  test::flat_field(16, 16, 1.0f), test::random_field(7, 3, 3)};
    const char* names[] = {"1x1", "2x2", "64x64", "flat0", "flat1", "7x3"};
    for (int f = 0; f < 6; ++f)
        for (double s : {1e-6, 0.05, 1.0})
            for (double b : {0.0, 0.5, 1.0})
                for (double theta : {0.0, 30.0, 85.0, 89.9}) {
                    check_finite_and_bounded<float>(m(), fields[f], s, b, theta, names[f]);
                    check_finite_and_bounded<double>(m(), fields[f], s, b, theta, names[f]);
                }
}

// The exact_on_flat flag is checked both ways (parallax and pom, the flat-field closed
// forms, are covered here for every bias and angle): a claim that fails, or an exact method that
// does not claim it, is a defect.
TEST_P(EveryMethod, ExactOnFlatFieldExactlyWhenClaimed) {
    double worst = 0;
    // 0.99: just below the top, where a search that takes the previous height of layer 1 as 1
    // (the DirectX SDK sample) returns P instead of the surface.
    for (float level : {0.0f, 0.3f, 0.99f, 1.0f})
        for (double b : {0.0, 0.5, 1.0})
            for (double theta : {0.0, 45.0, 80.0, 89.0}) {
                const HeightField hf = test::flat_field(32, 32, level);
                const auto sc = test::make_scene(hf, 0.05, b, theta, 100);
                const auto P = test::random_points(32, 4);
                const auto uv = test::run_method<double>(m(), test::params_for(m()), sc, hf, P);
                const ExactTracer tr(hf, 0.05, b);
                for (size_t i = 0; i < P.size(); ++i) {
                    const Vec2d e = texel_error(uv[i], tr.trace(P[i], sc.V).uv, 32, 32);
                    worst = std::max(worst, std::hypot(e.x, e.y));
                }
            }
    if (m().exact_on_flat) EXPECT_LT(worst, 1e-9) << m().name << " claims exactness on flat fields";
    else EXPECT_GT(worst, 1e-6) << m().name << " is exact on flat fields but does not claim it";
}

// Float and double runs of the same method agree closely on a smooth field at a moderate
// angle (the precision column measures a real, small difference, not a different method).
TEST_P(EveryMethod, FloatAndDoubleAgreeOnSmoothField) {
    HeightField hf(64, 64);
    for (int j = 0; j < 64; ++j)
        for (int i = 0; i < 64; ++i)
            hf.at(i, j) = float(0.5 + 0.25 * std::sin(2 * M_PI * (i + 0.5) / 64) *
                                          std::cos(2 * M_PI * (j + 0.5) / 64));
    const auto sc = test::make_scene(hf, 0.05, 1.0, 45, 10);
    const auto P = test::random_points(500, 6);
    const auto f = test::run_method<float>(m(), test::params_for(m()), sc, hf, P);
    const auto d = test::run_method<double>(m(), test::params_for(m()), sc, hf, P);
    int off = 0;
    for (size_t i = 0; i < P.size(); ++i)
        off += std::hypot(f[i].x - d[i].x, f[i].y - d[i].y) * 64 > 1e-3;
    EXPECT_LE(off, 2) << m().name;  // a layer decision may flip at a near-tie
}

INSTANTIATE_TEST_SUITE_P(Registry, EveryMethod, ::testing::ValuesIn(test::method_names()),
                         test::MethodName());

}  // namespace
}  // namespace pxh
