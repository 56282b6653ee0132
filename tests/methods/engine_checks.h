// What the engine tests (tests/methods/engines_*_test.cpp) share: the view and offset helpers of
// their closed-form checks, and the comparison of a preset (the marcher, CPU float) with the
// literal transcription of its engine's loop (tests/engines/literal_*.h) over a sweep of fields,
// scales, views and points.
#pragma once
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include "harness/scene/view.h"
#include "methods/method.h"
#include "tests/engines/literal_common.h"
#include "tests/test_util.h"

namespace pxh::test {

using literal::EngineResult;
using Literal = std::function<EngineResult(const HeightField&, float, Vec3<float>, Vec2<float>)>;

// A literal function called with its defaults (a function with defaulted trailing parameters
// has no pointer of the four-argument type).
#define PXH_LITERAL(f) \
    [](const HeightField& hf, float s, Vec3<float> V, Vec2<float> P) { return f(hf, s, V, P); }

// pxh's V at (theta, phi) degrees, in float as the shaders get it.
inline Vec3<float> engine_view(double theta, double phi) {
    return Vec3<float>(view_vector(theta, phi));
}

// Expect uv == P + d (uv units) to within tol.
inline void expect_offset(const EngineResult& r, Vec2<float> P, double dx, double dy, double tol,
                          const char* what) {
    EXPECT_NEAR(r.uv.x, P.x + dx, tol) << what;
    EXPECT_NEAR(r.uv.y, P.y + dy, tol) << what;
}

// Layer index x of uv along the per-layer step duv (uv = P + duv x).
inline double layer_index(const EngineResult& r, Vec2<float> P, double dux, double duy) {
    return ((r.uv.x - P.x) * dux + (r.uv.y - P.y) * duy) / (dux * dux + duy * duy);
}

// The flat-field checks' sample point and views (theta, phi).
inline const Vec2<float> kEngineP{0.37f, 0.61f};
inline constexpr double kEngineAngles[][2] = {{10, 0}, {33, 130}, {60, 250}, {80, 315}};

// A relief search on a flat field whose hit lies at layer x = depth n (n layers of step
// duv per layer, along V): the loop stops at the first layer k = ceil(x) below it, then
// `bisections` halvings of the last layer leave the uv within 1 / 2^bisections layer of the
// hit, strictly inside (k - 1, k); fetches k + 1 + bisections.
inline void expect_flat_relief(const EngineResult& r, Vec2<float> P, double dux, double duy,
                               double x, int bisections, double slack, const char* what) {
    const int k = int(std::ceil(x));
    const double xi = layer_index(r, P, dux, duy);
    EXPECT_LE(std::abs(xi - x), std::ldexp(1.0, -bisections) + slack) << what;
    EXPECT_GT(xi, k - 1.0) << what;
    EXPECT_LT(xi, double(k)) << what;
    EXPECT_EQ(r.fetches, k + 1 + bisections) << what;
}

// A one-fetch offset on any field: at every point of `points` and every view (theta, phi) of
// `thetas` x `phis`, uv = P + k V.xy with k = offset(h, V) (h: the bilinear height at P, in
// double), and one fetch.
template <class Lit, class Offset>
void expect_one_fetch_offset(const Lit& lit, const HeightField& hf, float s,
                             const std::vector<Vec2d>& points, const std::vector<double>& thetas,
                             const std::vector<double>& phis, const Offset& offset, double tol,
                             const char* what) {
    HeightSampler<double> hs(hf, 1, 0);
    for (const double theta : thetas)
        for (const double phi : phis) {
            const Vec3<float> V = engine_view(theta, phi);
            for (const Vec2d& Pd : points) {
                const Vec2<float> P(Pd);
                const EngineResult r = lit(hf, s, V, P);
                const double k = offset(hs.height(Vec2d(P)), V);
                EXPECT_NEAR(r.uv.x, P.x + k * V.x, tol) << what << " at theta " << theta;
                EXPECT_NEAR(r.uv.y, P.y + k * V.y, tol) << what << " at theta " << theta;
                EXPECT_EQ(r.fetches, 1) << what;
            }
        }
}

// The sweep a preset is compared with its literal over.
struct LiteralSweep {
    std::vector<HeightField> fields;
    std::vector<float> scales;
    std::vector<double> thetas = {10, 30, 50, 70, 85};
    std::vector<double> phis = {0, 65, 200, 310};
    int points = 300;
    uint32_t point_seed = 202;  // the points: test::random_points(points, point_seed)
    GivenParams given;          // the preset's parameters (its defaults where not given)
    // Where the engine resolves steps below float noise (O3DE contact at Ultra), a sample also
    // agrees when it is within one such step (in slab fractions) of the literal's.
    double substep = 0;
    double fetch_fraction = 0.001;  // of the samples whose fetch counts may differ
    bool fetches = true;            // compare the fetch counts at all
    // A fetch count one apart counts as a tie, not a difference, where this says so.
    std::function<bool(const HeightField&, const Scene<double>&, Vec2d)> fetch_tie;
};

// The preset and the literal on every sample of the sweep (b: the preset's required bias): at
// most 0.1% of the samples more than 1e-3 texel apart (a NaN on either side counts apart), and
// at most `fetch_fraction` with other fetch counts; float accumulation order differs, so a
// near-tie can flip a layer decision. Prints what it found.
inline void expect_preset_matches(const char* preset, const Literal& lit, const LiteralSweep& sw) {
    const MethodInfo& m = method(preset);
    const ParamValues p = params_for(m, sw.given);
    const double b = m.required_bias;
    EXPECT_FALSE(std::isnan(b)) << preset << ": a literal comparison needs the engine's plane";
    const auto P = random_points(sw.points, sw.point_seed);
    int total = 0, off_uv = 0, off_fetches = 0, ties = 0;
    double worst = 0;
    for (const HeightField& hf : sw.fields)
        for (const float s : sw.scales)
            for (const double theta : sw.thetas)
                for (const double phi : sw.phis) {
                    const Scene<double> sc = make_scene(hf, s, b, theta, phi);
                    const Vec3<float> V(sc.V);
                    std::vector<int> fetches;
                    const auto uv = run_method<float>(m, p, sc, hf, P, &fetches);
                    const double step =
                        sw.substep * s * std::hypot(V.x, V.y) / V.z * hf.width * 1.01;
                    for (size_t i = 0; i < P.size(); ++i) {
                        const EngineResult e = lit(hf, s, V, Vec2<float>(P[i]));
                        const double d = std::hypot(uv[i].x - e.uv.x, uv[i].y - e.uv.y) * hf.width;
                        off_uv += !(d <= std::max(1e-3, step));
                        if (std::isfinite(d)) worst = std::max(worst, d);
                        if (sw.fetch_tie && std::abs(fetches[i] - e.fetches) == 1 &&
                            sw.fetch_tie(hf, sc, P[i]))
                            ++ties;
                        else off_fetches += fetches[i] != e.fetches;
                        ++total;
                    }
                }
    std::printf(
        "%s %s: %d samples, %d beyond the tolerance (worst %.3g texel), %d fetch counts differ, "
        "%d one apart at a tie\n",
        preset, p.canonical().c_str(), total, off_uv, worst, off_fetches, ties);
    EXPECT_GT(total, 0) << preset << ": the sweep has no samples";
    EXPECT_LE(off_uv, total / 1000) << preset << ": " << off_uv << " of " << total
                                    << " samples beyond 1e-3 texel (worst " << worst << ")";
    if (sw.fetches) {
        EXPECT_LE(off_fetches, int(total * sw.fetch_fraction))
            << preset << ": fetch counts differ on " << off_fetches << " of " << total;
    }
}

}  // namespace pxh::test
