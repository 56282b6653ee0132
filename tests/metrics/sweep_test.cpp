// Sliding and shimmering (docs/conventions.md section 5.3) on synthetic methods that exist only
// here, then the real methods' ordering on a rough field; then the same along a perspective
// camera's distance sweep: synthetic methods seen through the camera, the runner's pairing
// against a hand computation with outside pixels, both pairings in one run, slices and threads.
#include "harness/metrics/sweep.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <random>

#include "harness/experiment/experiment.h"
#include "harness/metrics/metrics.h"
#include "harness/run/runner.h"
#include "harness/scene/view.h"
#include "harness/truth/ground_truth.h"
#include "harness/truth/tracer.h"
#include "heightfields/heightfields.h"
#include "tests/test_util.h"

namespace pxh {
namespace {

HeightField generated(const char* name, int size) {
    const GeneratorInfo* g = find_generator(name);
    return generate_heightfield(*g, size, size, resolve_params(g->params, {}, "test", name));
}

// Error vectors of a synthetic method uv = truth + offset(P, theta) at one view.
template <class Offset>
std::vector<Vec2d> synthetic_errors(const HeightField& hf, double theta, int n, Offset offset) {
    const GroundTruth gt = trace_ground_truth(hf, 0.05, 1.0, view_vector(theta, 30), n);
    std::vector<Vec2d> e(gt.uv.size());
    for (size_t k = 0; k < e.size(); ++k) {
        const Vec2d o = offset(k, theta);  // in texels
        const Vec2d uv{gt.uv[k].x + o.x / hf.width, gt.uv[k].y + o.y / hf.height};
        e[k] = texel_error(uv, gt.uv[k], hf.width, hf.height);
    }
    return e;
}

TEST(Sweep, ConstantOffsetNeitherSlidesNorShimmers) {
    const HeightField hf = generated("fbm", 64);
    auto c = [](size_t, double) { return Vec2d{0.3, -0.2}; };
    const auto m = sweep_metrics(synthetic_errors(hf, 60, 48, c), synthetic_errors(hf, 60.5, 48, c),
                                 0.5, 64, 64);
    EXPECT_NEAR(m.sliding, 0, 1e-9);
    EXPECT_NEAR(m.shimmering, 0, 1e-9);
}

// Offset a * theta: every sample drifts by a * dt, so sliding = a texels per degree (for any
// dt) and nothing shimmers.
TEST(Sweep, OffsetGrowingWithThetaSlidesAtItsDerivative) {
    const HeightField hf = generated("fbm", 64);
    const double a = 0.04;
    auto grow = [&](size_t, double theta) { return Vec2d{a * theta * 0.6, a * theta * 0.8}; };
    for (double dt : {0.25, 1.0, 5.0}) {
        const auto m = sweep_metrics(synthetic_errors(hf, 50, 48, grow),
                                     synthetic_errors(hf, 50 + dt, 48, grow), dt, 64, 64);
        EXPECT_NEAR(m.sliding, a, 1e-9) << dt;
        EXPECT_NEAR(m.shimmering, 0, 1e-9) << dt;
    }
}

// Offsets uniform in [-1, 1]^2 texels, independent per sample and per `seed` (one seed a view).
auto random_offsets(uint32_t seed) {
    return [seed](size_t k, double) {
        std::mt19937 rng(seed * 1000003u + uint32_t(k));
        std::uniform_real_distribution<double> u(-1, 1);
        return Vec2d{u(rng), u(rng)};
    };
}

// Independent random offsets per sample and view, uniform in [-1, 1]^2 texels: the change d
// is the difference of two such vectors (E|d| ~ 1.04 texel), with a mean near 0.
TEST(Sweep, RandomPerSampleOffsetsShimmerWithoutSliding) {
    const HeightField hf = generated("fbm", 64);
    const double dt = 0.5;
    const auto m = sweep_metrics(synthetic_errors(hf, 40, 96, random_offsets(1)),
                                 synthetic_errors(hf, 40 + dt, 96, random_offsets(2)), dt, 64, 64);
    // E|x - y| for x, y uniform on [-1,1]^2: Monte Carlo in the test itself.
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-1, 1);
    double expect = 0;
    for (int i = 0; i < 200000; ++i) expect += std::hypot(u(rng) - u(rng), u(rng) - u(rng));
    expect /= 200000;
    EXPECT_NEAR(m.shimmering * dt, expect, 0.05);
    EXPECT_LT(m.sliding * dt, 0.05);  // ~ 1/sqrt(N) of the shimmer
}

// The papers' claims that hold on a rough field (fbm, s = 0.05, b = 0.5) for both scales
// measured: single-step parallax shimmers more and more toward grazing views; the layered
// searches (pom, relief) shimmer far less; offset limiting and halving flatten the relief
// (larger error) and slide (coherent drift) where parallax does not. Whether limiting reduces
// shimmer depends on scale and angle (docs/findings/sliding.md), so it is not asserted.
TEST(Sweep, RealMethodsOrderAsThePapersSay) {
    Experiment ex;
    ex.samples = 96;
    ex.backend.timing_repeats = 0;
    ex.theta_deg = {60, 75, 80};
    ex.phi_deg = {30};
    ex.sweep_dt_deg = 0.25;
    HeightfieldSpec hs = test::generator_spec("fbm", 128);
    hs.bias = 0.5;
    for (double s : {0.02, 0.05}) {
        hs.scale = s;
        ex.heightfields.push_back(hs);
    }
    for (const char* name : {"parallax", "parallax_limited", "parallax_halved", "pom", "relief"}) {
        const MethodInfo* m = find_method(name);
        ex.methods.push_back({m, test::params_for(*m)});
    }
    const auto rows = run_experiment(ex, RunOptions{});
    auto at = [&](const char* method, double s, double theta) {
        for (const auto& r : rows)
            if (r.text("method") == method && r.num("scale") == s && r.num("theta_deg") == theta)
                return r;
        ADD_FAILURE() << method;
        return ResultRow{};
    };
    for (double s : {0.02, 0.05}) {
        EXPECT_GT(at("parallax", s, 80).num("shimmering"),
                  10 * at("parallax", s, 60).num("shimmering"))
            << s;
        EXPECT_GT(at("parallax", s, 75).num("shimmering"),
                  2 * at("parallax", s, 60).num("shimmering"))
            << s;
        for (double theta : {75.0, 80.0}) {
            const auto par = at("parallax", s, theta);
            EXPECT_GT(par.num("shimmering"), 2 * at("pom", s, theta).num("shimmering"))
                << s << " " << theta;
            EXPECT_GT(par.num("shimmering"), 2 * at("relief", s, theta).num("shimmering"))
                << s << " " << theta;
            EXPECT_LT(at("pom", s, theta).num("err_mean"), par.num("err_mean") / 3);
        }
        for (double theta : {60.0, 75.0})
            for (const char* flattening : {"parallax_limited", "parallax_halved"}) {
                const auto par = at("parallax", s, theta), f = at(flattening, s, theta);
                EXPECT_GT(f.num("err_mean"), 1.5 * par.num("err_mean"))
                    << flattening << " " << s << " " << theta;
                EXPECT_GT(f.num("sliding"), 3 * par.num("sliding") + 0.002)
                    << flattening << " " << s << " " << theta;
            }
    }
    EXPECT_EQ(at("parallax", 0.05, 60).num("sweep_dt_deg"), 0.25);
}

// Consecutive views of a sweep without sweep_dt_deg: the pair (theta_k, theta_k+1) lands on
// row k; the last view of the sweep has none.
TEST(Sweep, ConsecutiveViewsFillAllButTheLastRow) {
    Experiment ex;
    ex.samples = 32;
    ex.backend.timing_repeats = 0;
    ex.theta_deg = {20, 40, 60};
    HeightfieldSpec hs = test::generator_spec("sine", 64);
    ex.heightfields = {hs};
    ex.methods.push_back({find_method("parallax"), test::params_for(*find_method("parallax"))});
    const auto rows = run_experiment(ex, RunOptions{});
    ASSERT_EQ(rows.size(), 3u);
    EXPECT_TRUE(std::isfinite(rows[0].num("sliding")));
    EXPECT_EQ(rows[0].num("sweep_dt_deg"), 20);
    EXPECT_TRUE(std::isfinite(rows[1].num("shimmering")));
    EXPECT_TRUE(std::isnan(rows[2].num("sliding")));
}

// The perspective view of pixel grid n at (theta, phi = 30, distance, fov).
View perspective_view(double theta, double distance, double fov, int n) {
    return Camera::create("perspective", {{{"distance", distance}, {"fov_deg", fov}}},
                          {theta, 30, n})
        ->view();
}

// Error vectors of a synthetic method uv = truth + offset(k, distance) seen through the camera
// at one distance; outside pixels (V.z <= cos 89 degrees, from the view's own V) carry NaN, as
// the runner leaves them out.
template <class Offset>
std::vector<Vec2d> perspective_errors(const HeightField& hf, double theta, double distance, int n,
                                      Offset offset) {
    const View view = perspective_view(theta, distance, 60, n);
    const auto tracer = make_tracer("exact", hf, 0.05, 1.0);
    const GroundTruth gt = trace_ground_truth(*tracer, view);
    std::vector<Vec2d> e(gt.uv.size());
    for (size_t k = 0; k < e.size(); ++k) {
        if (!(view.dir(k).z > std::cos(89 * M_PI / 180))) {
            e[k] = {NAN, NAN};
            continue;
        }
        const Vec2d o = offset(k, distance);  // in texels
        const Vec2d uv{gt.uv[k].x + o.x / hf.width, gt.uv[k].y + o.y / hf.height};
        e[k] = texel_error(uv, gt.uv[k], hf.width, hf.height);
    }
    return e;
}

ResultRow sized_row(const HeightField& hf) {
    ResultRow row;
    row.set("width", hf.width);
    row.set("height", hf.height);
    return row;
}

TEST(DistanceSweep, ConstantOffsetNeitherSlidesNorShimmers) {
    const HeightField hf = generated("fbm", 64);
    auto c = [](size_t, double) { return Vec2d{0.3, -0.2}; };
    ResultRow row = sized_row(hf);
    add_distance_sweep(perspective_errors(hf, 80, 2, 48, c), perspective_errors(hf, 80, 3, 48, c),
                       1.0, row);
    EXPECT_NEAR(row.num("sliding_dist"), 0, 1e-9);
    EXPECT_NEAR(row.num("shimmering_dist"), 0, 1e-9);
    EXPECT_EQ(row.num("sweep_dd"), 1.0);
    EXPECT_TRUE(std::isnan(row.num("sliding")));  // the theta columns are not touched
}

// Offset a * distance: every pixel drifts by a * dd, so sliding_dist = a texels per tile for
// any step, and nothing shimmers.
TEST(DistanceSweep, OffsetGrowingWithDistanceSlidesAtItsDerivative) {
    const HeightField hf = generated("fbm", 64);
    const double a = 0.07;
    auto grow = [&](size_t, double d) { return Vec2d{-a * d * 0.8, a * d * 0.6}; };
    for (double dd : {0.5, 2.0, 6.0}) {
        ResultRow row = sized_row(hf);
        add_distance_sweep(perspective_errors(hf, 70, 1.5, 48, grow),
                           perspective_errors(hf, 70, 1.5 + dd, 48, grow), dd, row);
        EXPECT_NEAR(row.num("sliding_dist"), a, 1e-9) << dd;
        EXPECT_NEAR(row.num("shimmering_dist"), 0, 1e-9) << dd;
        EXPECT_EQ(row.num("sweep_dd"), dd);
    }
}

// Independent random offsets per pixel and distance, uniform in [-1, 1]^2 texels: the change is
// the difference of two such vectors (E|d| ~ 1.04 texel), its mean near 0.
TEST(DistanceSweep, RandomPerPixelOffsetsShimmerWithoutSliding) {
    const HeightField hf = generated("fbm", 64);
    const double dd = 4;
    ResultRow row = sized_row(hf);
    add_distance_sweep(perspective_errors(hf, 45, 4, 96, random_offsets(1)),
                       perspective_errors(hf, 45, 8, 96, random_offsets(2)), dd, row);
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-1, 1);
    double expect = 0;
    for (int i = 0; i < 200000; ++i) expect += std::hypot(u(rng) - u(rng), u(rng) - u(rng));
    expect /= 200000;
    EXPECT_NEAR(row.num("shimmering_dist") * dd, expect, 0.05);
    EXPECT_LT(row.num("sliding_dist") * dd, 0.05);
}

TEST(DistanceSweep, SuccessorsAreTheNextDistanceAtTheSameFieldOfView) {
    // distance outer, fov inner: (1,30) (1,45) (2,30) (2,45) (0.5,30) (0.5,45)
    std::vector<CameraSetting> s;
    for (double d : {1.0, 2.0, 0.5})
        for (double f : {30.0, 45.0}) s.push_back({{{"distance", d}, {"fov_deg", f}}});
    // The perspective camera's entry names the key its sweep pairs along.
    const std::string key = camera_entry("perspective", "test").pair_key();
    ASSERT_EQ(key, "distance");
    const auto st = distance_steps(s, key);
    ASSERT_EQ(st.size(), 6u);
    EXPECT_EQ(st[0].next, 2u);
    EXPECT_EQ(st[0].dd, 1.0);
    EXPECT_EQ(st[1].next, 3u);
    EXPECT_EQ(st[1].dd, 1.0);
    EXPECT_FALSE(st[2].pairs());  // 2 -> 0.5 goes nearer: no pair, as a falling theta
    EXPECT_FALSE(st[3].pairs());
    EXPECT_FALSE(st[4].pairs());  // the last distance
    EXPECT_FALSE(st[5].pairs());
    // The orthographic camera pairs along no key: no successors.
    EXPECT_EQ(camera_entry("orthographic", "test").pair_key(), "");
    EXPECT_FALSE(distance_steps({CameraSetting{}}, "")[0].pairs());
    EXPECT_FALSE(distance_steps(s, "")[0].pairs());
}

// A perspective run over theta {45, 80} and distance {1.5, 4} at fov 60 (the 80-degree views
// have pixels past the horizon) of `none` (uv = P) in double.
Experiment distance_run(const std::string& extra = "") {
    return parse_experiment(
        "samples = 32\ntiming_repeats = 0\nbackends = [\"cpu\"]\nprecision = \"double\"\n" + extra +
            "[views]\ntheta_deg = [45, 80]\nphi_deg = [30]\ncamera = \"perspective\"\n"
            "distance = [1.5, 4]\nfov_deg = 60\n[[heightfields]]\nname = \"f\"\n"
            "generator = \"fbm\"\nwidth = 64\nheight = 64\nscale = 0.05\nbias = 1\n"
            "[[methods]]\nname = \"none\"\n[[methods]]\nname = \"pom\"\nlayers = 16\n",
        "e.toml");
}

// The runner's pairing against a hand computation: the error of `none` is P - truth, with P and
// V from the camera and the truth from the exact tracer; pixels outside at either distance
// (V.z <= cos 89 degrees) are left out, the change wrapped per tile, divided by dd = 2.5.
TEST(DistanceSweep, RunnerPairsPixelByPixelAndLeavesOutsidePixelsOut) {
    const Experiment ex = distance_run();
    const auto rows = run_experiment(ex, {});
    // distance outer, theta inner, methods innermost
    ASSERT_EQ(rows.size(), 8u);
    const HeightField hf = generated("fbm", 64);
    const auto tracer = make_tracer("exact", hf, 0.05, 1.0);
    for (double theta : {45.0, 80.0}) {
        const View v0 = perspective_view(theta, 1.5, 60, 32),
                   v1 = perspective_view(theta, 4, 60, 32);
        const GroundTruth g0 = trace_ground_truth(*tracer, v0),
                          g1 = trace_ground_truth(*tracer, v1);
        double mx = 0, my = 0;
        std::vector<Vec2d> d;
        size_t outside = 0;
        for (size_t k = 0; k < v0.size(); ++k) {
            // Inside from the geometry alone (the view gives outside pixels a stand-in ray):
            // d = f + a x r + a y w has d.z = -cos t + a y sin t and |d|^2 = 1 + a^2 (x^2 + y^2),
            // the same at both distances.
            const double t = theta * M_PI / 180, a = std::tan(30 * M_PI / 180);
            const double x = 2 * (double(k % 32) + 0.5) / 32 - 1;
            const double y = 2 * (double(k / 32) + 0.5) / 32 - 1;
            const double Vz =
                (std::cos(t) - a * y * std::sin(t)) / std::sqrt(1 + a * a * (x * x + y * y));
            if (!(Vz > std::cos(89 * M_PI / 180))) {
                ++outside;
                continue;
            }
            auto err = [&](const Vec2d& p, const Vec2d& q, int i) {
                const double e = (i ? p.y - q.y : p.x - q.x);
                return (e - std::floor(e + 0.5)) * 64;
            };
            double dx = err(v1.P[k], g1.uv[k], 0) - err(v0.P[k], g0.uv[k], 0);
            double dy = err(v1.P[k], g1.uv[k], 1) - err(v0.P[k], g0.uv[k], 1);
            dx -= 64 * std::floor(dx / 64 + 0.5);
            dy -= 64 * std::floor(dy / 64 + 0.5);
            d.push_back({dx, dy});
            mx += dx;
            my += dy;
        }
        mx /= double(d.size());
        my /= double(d.size());
        double spread = 0;
        for (const Vec2d& q : d) spread += std::hypot(q.x - mx, q.y - my);
        const double sliding = std::hypot(mx, my) / 2.5,
                     shimmering = spread / double(d.size()) / 2.5;
        const ResultRow& r = rows[theta == 45 ? 0 : 2];  // distance 1.5, method none
        ASSERT_EQ(r.text("method"), "none");
        ASSERT_EQ(r.num("distance"), 1.5);
        ASSERT_EQ(r.num("theta_deg"), theta);
        EXPECT_EQ(r.num("samples_outside"), double(outside)) << theta;
        if (theta == 80) {
            EXPECT_GT(outside, 50u);  // the top rows lie past the horizon
        }
        EXPECT_NEAR(r.num("sliding_dist"), sliding, 1e-9 * (1 + sliding)) << theta;
        EXPECT_NEAR(r.num("shimmering_dist"), shimmering, 1e-9 * (1 + shimmering)) << theta;
        EXPECT_GT(shimmering, 0.01) << theta;  // a number that could be wrong
        EXPECT_EQ(r.num("sweep_dd"), 2.5);
    }
}

// Both pairings in one run: theta pairs consecutive theta at one distance (the 45-degree rows),
// distance pairs consecutive distances at one theta (the 1.5-tile rows); the (4 tiles, 80
// degrees) rows have neither.
TEST(DistanceSweep, ThetaAndDistancePairingsCoexist) {
    const auto rows = run_experiment(distance_run(), {});
    ASSERT_EQ(rows.size(), 8u);
    for (const ResultRow& r : rows) {
        ASSERT_TRUE(r.ok()) << r.text("error");
        const bool near = r.num("distance") == 1.5, low = r.num("theta_deg") == 45;
        EXPECT_EQ(std::isfinite(r.num("sliding_dist")), near) << r.num("distance");
        EXPECT_EQ(std::isfinite(r.num("shimmering_dist")), near);
        EXPECT_EQ(std::isfinite(r.num("sweep_dd")), near);
        EXPECT_EQ(std::isfinite(r.num("sliding")), low) << r.num("theta_deg");
        EXPECT_EQ(std::isfinite(r.num("shimmering")), low);
        if (low) {
            EXPECT_EQ(r.num("sweep_dt_deg"), 35);
        }
    }
    // The theta pairing of a perspective view is pixel by pixel too (a fixed screen pixel, not a
    // fixed P): pom slides and shimmers less than `none` there at 1.5 tiles.
    EXPECT_GT(rows[0].num("shimmering"), rows[1].num("shimmering"));
    // With sweep_dt_deg each view gets its theta companion; the distance pairs are unchanged.
    const auto dt = run_experiment(distance_run("sweep_dt_deg = 0.5\n"), {});
    ASSERT_EQ(dt.size(), 8u);
    for (size_t i = 0; i < rows.size(); ++i) {
        EXPECT_EQ(dt[i].num("sweep_dt_deg"), 0.5);
        if (rows[i].num("distance") == 1.5) {
            EXPECT_EQ(dt[i].num("sliding_dist"), rows[i].num("sliding_dist")) << i;
            EXPECT_EQ(dt[i].num("shimmering_dist"), rows[i].num("shimmering_dist")) << i;
        }
    }
}

// A slice that runs the near distance but not the far one traces the far view as a companion:
// the same numbers as the whole run, bit for bit; and so does a run on one thread.
TEST(DistanceSweep, SlicesAndThreadsGiveTheSameNumbers) {
    const Experiment ex = distance_run();
    const auto whole = run_experiment(ex, {});
    RunOptions near_only;
    near_only.include = [](const ViewAt& v) { return v.camera == 0; };
    const auto slice = run_experiment(ex, near_only);
    ASSERT_EQ(slice.size(), 4u);
    std::vector<ResultRow> one;
    {
        tbb::global_control threads(tbb::global_control::max_allowed_parallelism, 1);
        one = run_experiment(ex, {});
    }
    ASSERT_EQ(one.size(), whole.size());
    for (size_t i = 0; i < whole.size(); ++i)
        for (const char* c : {"sliding_dist", "shimmering_dist", "sliding", "shimmering"}) {
            const double w = whole[i].num(c), o = one[i].num(c);
            EXPECT_TRUE(w == o || (std::isnan(w) && std::isnan(o))) << c << " " << i;
            if (i < 4 && std::string(c).find("dist") != std::string::npos) {
                EXPECT_TRUE(std::isfinite(slice[i].num(c))) << c << " " << i;
                EXPECT_EQ(slice[i].num(c), w) << c << " " << i;
            }
        }
}

}  // namespace
}  // namespace pxh
