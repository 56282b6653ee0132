// The ground truths on hostile input: partial ray packets (1 to 8 samples), scales from 1e-300
// to the largest double, and views whose rays would travel too far sideways (the travel limit,
// kMaxRayTravelTiles): refused with a one-line reason, never a hang or unbounded memory.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <chrono>
#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>
#include <random>
#include <stdexcept>

#include "harness/bench/bench.h"
#include "harness/core/error.h"
#include "harness/experiment/experiment.h"
#include "harness/metrics/metrics.h"
#include "harness/run/runner.h"
#include "harness/scene/perspective_camera.h"
#include "harness/truth/embree_truth.h"
#include "harness/truth/ground_truth.h"
#include "heightfields/heightfields.h"
#include "tests/cli_util.h"
#include "tests/test_util.h"

namespace pxh {
namespace {

HeightField generated(const char* name, int size) { return test::generated_field(name, size); }

// The polar angle whose rays travel `tiles` sideways at scale s.
double theta_for_travel(double s, double tiles) { return std::atan(tiles / s) * 180 / M_PI; }

// ---- Partial packets -------------------------------------------------------------------------

// N = 1 .. 8 (1 to 64 rays: a lone partial packet of 16 for N <= 3, then partial last packets):
// Embree agrees with the exact tracer on planar patches (where its triangles are the exact
// surface), and the grid tracer stays bit-identical to the per-cell DDA.
TEST(TruthLimits, FewSamplesThroughBothTracers) {
    const HeightField hf = generated("sine", 32);
    for (double s : {0.05, 1.0}) {
        const ExactTracer exact(hf, s, 0.5);
        const EmbreeTracer embree(hf, s, 0.5);
        for (int n = 1; n <= 8; ++n)
            for (double theta : {0.0, 45.0, 85.0})
                for (double phi : {0.0, 33.0}) {
                    const Vec3d V = view_vector(theta, phi);
                    const auto P = sample_grid(n);
                    std::vector<TruthHit> grid;
                    exact.trace_grid(n, V, grid);
                    const auto em = embree.trace(P, V);
                    ASSERT_EQ(grid.size(), P.size());
                    ASSERT_EQ(em.size(), P.size());
                    for (size_t k = 0; k < P.size(); ++k) {
                        const TruthHit naive = exact.trace_naive(P[k], V);
                        ASSERT_EQ(grid[k].uv.x, naive.uv.x) << "n=" << n << " theta=" << theta;
                        ASSERT_EQ(grid[k].uv.y, naive.uv.y);
                        const Vec2d e = texel_error(em[k], naive.uv, hf.width, hf.height);
                        EXPECT_LT(std::hypot(e.x, e.y), 2e-3)
                            << "s=" << s << " n=" << n << " theta=" << theta << " phi=" << phi;
                    }
                }
    }
}

// Rays that finish at different segments leave lanes of a packet inactive from one call to
// the next: every ray still gets its own answer (17 rays: one full packet and one of 1).
TEST(TruthLimits, EmbreePacketsOfAnySizeAnswerEveryRay) {
    const HeightField hf = generated("sine", 16);
    const EmbreeTracer embree(hf, 1.0, 1.0);
    const ExactTracer exact(hf, 1.0, 1.0);
    const Vec3d V = view_vector(88, 20);  // ~29 tiles of travel: rays end after many segments
    for (size_t count : {1, 2, 3, 5, 15, 16, 17, 31}) {
        const auto P = test::random_points(int(count), 7);
        const auto em = embree.trace(P, V);
        for (size_t k = 0; k < count; ++k) {
            const Vec2d e = texel_error(em[k], exact.trace(P[k], V).uv, hf.width, hf.height);
            EXPECT_LT(std::hypot(e.x, e.y), 2e-3) << count << " rays, ray " << k;
        }
    }
}

// ---- Long skims over low ground --------------------------------------------------------------

// Low ground (heights up to 0.3) and one tall block, on a field larger than the grid tracer's
// coarse blocks (64 cells for one-cell bands) with partial blocks at its edges (520 x 200):
// grazing rays skim the ground for many tiles, so most chunks keep their coarse bound and are
// never built, and those that hold the block are. Every hit must still be the per-cell DDA's,
// bit for bit (every 7th ray checked), on both axes and in both directions.
TEST(TruthLimits, GridTracerSkimmingLowGroundEqualsNaive) {
    const int W = 520, H = 200, n = 256;
    HeightField hf = test::random_field(W, H, 5, 0.0f, 0.3f);
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i) hf.at(300 + i, 90 + j) = 0.95f;
    const ExactTracer tr(hf, 1.0, 1.0);
    const auto P = sample_grid(n);
    long long rays = 0, differ = 0;
    struct View {
        double theta, phi;
    };
    for (const View v : {View{87, 0}, View{87, 10}, View{87, 90}, View{87, 190}, View{87, 260},
                         View{87, 300}, View{88.5, 185}}) {
        const Vec3d V = view_vector(v.theta, v.phi);
        std::vector<TruthHit> g;
        tr.trace_grid(n, V, g);
        for (size_t k = 0; k < P.size(); k += 7) {
            const TruthHit b = tr.trace_naive(P[k], V);
            differ += (g[k].uv.x != b.uv.x || g[k].uv.y != b.uv.y || g[k].z != b.z);
            ++rays;
        }
    }
    EXPECT_EQ(differ, 0) << "of " << rays << " rays";
}

// ---- Scales ----------------------------------------------------------------------------------

// Any finite positive scale: on a flat field the hit is P + V.xy / V.z * s (h - b) exactly;
// both tracers find it for s from 1e-300 to 1e300, straight down and with rays travelling half
// a tile (so that they stay within the travel limit at any s).
TEST(TruthLimits, FlatFieldClosedFormFromTinyToHugeScales) {
    const HeightField hf = test::flat_field(8, 8, 0.3f);
    for (double s : {1e-300, 1e-6, 1.0, 1e20, 1e38, 1e300})
        for (double b : {0.0, 0.5, 1.0})
            for (double theta : {0.0, theta_for_travel(s, 0.5)}) {
                const ExactTracer exact(hf, s, b);
                const EmbreeTracer embree(hf, s, b);
                const Vec3d V = view_vector(theta, 30);
                const double z = s * (double(0.3f) - b);
                const auto P = sample_grid(4);
                std::vector<TruthHit> hits;
                exact.trace_grid(4, V, hits);
                const auto em = embree.trace(P, V);
                for (size_t k = 0; k < P.size(); ++k) {
                    const Vec2d want{P[k].x + V.x / V.z * z, P[k].y + V.y / V.z * z};
                    std::ostringstream where;
                    where << "s=" << s << " b=" << b << " theta=" << theta;
                    const std::string at = where.str();
                    EXPECT_NEAR(hits[k].uv.x, want.x, 1e-9) << at;
                    EXPECT_NEAR(hits[k].uv.y, want.y, 1e-9) << at;
                    EXPECT_NEAR(em[k].x, want.x, 1e-5) << "Embree " << at;
                    EXPECT_NEAR(em[k].y, want.y, 1e-5) << "Embree " << at;
                    const TruthHit one = exact.trace(P[k], V);
                    EXPECT_NEAR(one.uv.x, want.x, 1e-9) << at;
                }
            }
}

// The largest double as a scale: straight down both tracers answer P, and a slanted view
// ends in bounded time with finite coordinates (no hang, no overflowed index).
TEST(TruthLimits, LargestDoubleScaleTerminates) {
    const HeightField hf = generated("fbm", 8);
    const double s = std::numeric_limits<double>::max();
    for (double b : {0.0, 0.5, 1.0}) {
        const ExactTracer exact(hf, s, b);
        const EmbreeTracer embree(hf, s, b);
        for (double theta : {0.0, theta_for_travel(s, 100.0)}) {
            const Vec3d V = view_vector(theta, 40);
            const auto P = sample_grid(3);
            std::vector<TruthHit> hits;
            exact.trace_grid(3, V, hits);
            const auto em = embree.trace(P, V);
            for (size_t k = 0; k < P.size(); ++k) {
                EXPECT_TRUE(std::isfinite(hits[k].uv.x) && std::isfinite(hits[k].uv.y));
                EXPECT_TRUE(std::isfinite(em[k].x) && std::isfinite(em[k].y));
                if (theta == 0) {
                    EXPECT_EQ(hits[k].uv.x, P[k].x);
                    EXPECT_EQ(em[k].x, P[k].x);
                }
            }
        }
    }
}

TEST(TruthLimits, ScaleMustBeFinitePositive) {
    const HeightField hf = test::flat_field(4, 4, 0.5f);
    for (double s : {0.0, -1.0, std::numeric_limits<double>::infinity(), std::nan("")}) {
        EXPECT_THROW(ExactTracer(hf, s, 1.0), std::invalid_argument) << s;
        EXPECT_THROW(EmbreeTracer(hf, s, 1.0), std::invalid_argument) << s;
    }
}

// ---- The travel limit ------------------------------------------------------------------------

TEST(TruthLimits, RayTravelProblemNamesValueAndLimit) {
    // Accepted: the shipped grazing cases (hard_cases: s = 1 at 89.99 deg, 5730 tiles;
    // precision: s = 0.05 at 89.99) and the limit itself.
    EXPECT_EQ(ray_travel_problem(1.0, 89.99), "");
    EXPECT_EQ(ray_travel_problem(0.05, 89.99), "");
    EXPECT_EQ(ray_travel_problem(0.05, 89.999), "");  // pxh bench's steepest --theta
    EXPECT_EQ(ray_travel_problem(1e300, 0.0), "");
    EXPECT_EQ(ray_travel_problem(kMaxRayTravelTiles, 44.0), "");
    // Refused, with the travel and the limit in one line.
    const std::string why = ray_travel_problem(1.0, 89.999);
    EXPECT_NE(why.find("57295.8 tiles"), std::string::npos) << why;
    EXPECT_NE(why.find("limit of 6000 tiles"), std::string::npos) << why;
    EXPECT_NE(why.find("kMaxRayTravelTiles"), std::string::npos) << why;
    EXPECT_EQ(why.find('\n'), std::string::npos);
    EXPECT_NE(ray_travel_problem(0.05, 89.9999999), "");
    EXPECT_NE(ray_travel_problem(1e8, 45.0), "");
    EXPECT_NE(ray_travel_problem(1e300, 1.0), "");
    EXPECT_NE(ray_travel_problem(kMaxRayTravelTiles, 46.0), "");
    // Inputs that are no view at all.
    EXPECT_NE(ray_travel_problem(1.0, 90.0), "");
    EXPECT_NE(ray_travel_problem(1.0, -1.0), "");
    EXPECT_NE(ray_travel_problem(1.0, std::nan("")), "");
    EXPECT_NE(ray_travel_problem(0.0, 10.0), "");
    EXPECT_NE(ray_travel_problem(std::nan(""), 10.0), "");
    EXPECT_NE(ray_travel_problem(std::numeric_limits<double>::infinity(), 0.0), "");
    EXPECT_NE(ray_travel_problem(1.0, Vec3d{0.6, 0, -0.8}), "");  // below the horizon
}

// Whatever the parse-time check accepts, the tracers' own check accepts too (a view right at
// the limit must not fail in the middle of a run).
TEST(TruthLimits, TracersAcceptEveryViewTheParseAccepts) {
    for (double theta : {0.001, 1.0, 30.0, 60.0, 89.0, 89.99, 89.99999, 89.9999999})
        for (double phi : {0.0, 20.0, 45.0, 90.0, 200.0}) {
            const double s = kMaxRayTravelTiles / std::tan(theta * M_PI / 180.0);
            for (double f : {1.0, 1 - 1e-15, 1 + 1e-15}) {
                if (!ray_travel_problem(s * f, theta).empty()) continue;
                EXPECT_EQ(ray_travel_problem(s * f, view_vector(theta, phi)), "")
                    << "theta=" << theta << " phi=" << phi;
            }
        }
}

// Every entry point refuses a view beyond the limit before any work (previously: theta
// 89.999999 at s = 0.05 on 32^2 took 29 s and 1 GB; s = 1e300 never finished).
TEST(TruthLimits, TracersRefuseViewsBeyondTheLimit) {
    const HeightField hf = generated("fbm", 32);
    const auto P = sample_grid(4);
    struct Case {
        double s, theta;
    };
    for (const Case c :
         {Case{1.0, 89.999}, Case{0.05, 89.999999}, Case{1e8, 45.0}, Case{1e300, 60.0}}) {
        const ExactTracer exact(hf, c.s, 1.0);
        const EmbreeTracer embree(hf, c.s, 1.0);
        const Vec3d V = view_vector(c.theta, 20);
        const auto t0 = std::chrono::steady_clock::now();
        std::vector<TruthHit> hits;
        EXPECT_THROW(exact.trace_grid(16, V, hits), std::invalid_argument) << c.s << " " << c.theta;
        EXPECT_THROW(exact.trace(P[0], V), std::invalid_argument);
        EXPECT_THROW(exact.trace_naive(P[0], V), std::invalid_argument);
        EXPECT_THROW(embree.trace(P, V), std::invalid_argument);
        EXPECT_THROW(trace_ground_truth(exact, V, 16), std::invalid_argument);
        // A light beyond the limit (the shadow walk is as long), with a view that is fine.
        const Vec3d up = view_vector(0, 0);
        EXPECT_THROW(trace_ground_truth(exact, up, 4, &V), std::invalid_argument);
        EXPECT_THROW(exact.occluded({0.5, 0.5}, exact.z_bot(), V), std::invalid_argument);
        try {
            exact.trace_grid(16, V, hits);
        } catch (const std::invalid_argument& e) {
            EXPECT_NE(std::string(e.what()).find("kMaxRayTravelTiles"), std::string::npos)
                << e.what();
        }
        EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(),
                  5.0);
    }
}

// The shipped experiments stay within the limit (hard_cases.toml goes to s = 1 at 89.99 deg:
// 5730 tiles; precision.toml to s = 0.05 at 89.99 deg).
TEST(TruthLimits, ShippedExperimentsStayAccepted) {
    int files = 0;
    for (const auto& f : std::filesystem::directory_iterator(std::string(PXH_SOURCE_DIR) +
                                                             "/results/experiments")) {
        if (f.path().extension() != ".toml") continue;
        ++files;
        EXPECT_NO_THROW(load_experiment(f.path().string())) << f.path();
    }
    EXPECT_GE(files, 5);
}

// A light at the limit over a field whose highest point is the lit point's own height: every
// shadow ray is above all relief at once and ends there, instead of walking its 3000 tiles
// (1.5 million cells each: seconds for these 1024 rays before).
TEST(TruthLimits, ShadowRaysEndAboveTheHighestPoint) {
    const HeightField hf = test::flat_field(256, 256, 0.5f);
    const ExactTracer exact(hf, 1.0, 1.0);
    const Vec3d L = view_vector(theta_for_travel(1.0, kMaxRayTravelTiles) - 1e-9, 20);
    ASSERT_EQ(ray_travel_problem(1.0, L), "");
    const auto t0 = std::chrono::steady_clock::now();
    const GroundTruth gt = trace_ground_truth(exact, view_vector(30, 0), 32, &L);
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 1.0);
    for (uint8_t lit : gt.lit) ASSERT_EQ(lit, 1);
}

TEST(TruthLimits, BenchRefusesViewsBeyondTheLimit) {
    BenchOptions opt;
    opt.sizes = {16};
    opt.samples = 4;
    opt.repeats = 1;
    opt.scale = 1.0;
    opt.thetas = {30, 89.999};
    opt.out = (std::filesystem::temp_directory_path() /
               ("pxh_truth_limits_bench_" + std::to_string(::getpid()) + ".json"))
                  .string();
    std::filesystem::remove(opt.out);
    try {
        run_bench(opt);
        ADD_FAILURE() << "bench accepted s = 1 at 89.999 deg";
    } catch (const InputError& e) {
        EXPECT_EQ(std::string(e.what()).rfind("--theta: scale 1 at theta 89.999 deg", 0), 0u)
            << e.what();
    }
    EXPECT_FALSE(std::filesystem::exists(opt.out));  // refused before any work
}

// ---- Far eyes: the reach limit (kMaxSampleCells) ----------------------------------------------

std::string far_eye_experiment(double distance, int size, const std::string& extra = "") {
    return "samples = 16\ntiming_repeats = 0\nbackends = [\"cpu\"]\n" + extra +
           "[views]\ntheta_deg = [30]\ncamera = \"perspective\"\ndistance = " +
           format_number(distance) + "\n[[heightfields]]\nname = \"f\"\ngenerator = \"fbm\"\n" +
           "size = " + std::to_string(size) + "\nscale = 0.05\n[[methods]]\nname = \"pom\"\n" +
           "layers = 8\n";
}

std::string far_eye_error(double distance, int size) {
    try {
        (void)parse_experiment(far_eye_experiment(distance, size), "e.toml");
    } catch (const InputError& e) {
        return e.what();
    }
    return "(no error)";
}

// The bound the refusal uses holds: no inside pixel lies farther from the look-at point, and
// with every corner inside it is the farthest pixel itself.
TEST(TruthLimits, PerspectiveReachBoundsEveryInsidePixel) {
    for (double theta : {0.0, 30.0, 60.0, 85.0})
        for (double phi : {0.0, 37.0})
            for (double fov : {10.0, 45.0, 120.0})
                for (double D : {1.5, 100.0, 1e6}) {
                    const PerspectiveParams p{theta, phi, D, fov, 24};
                    const PerspectiveCamera cam(p);
                    const View v = cam.view();
                    double far = 0;
                    for (size_t k = 0; k < v.size(); ++k)
                        if (v.is_inside(k))
                            far = std::max(far, std::hypot(v.P[k].x - 0.5, v.P[k].y - 0.5));
                    const double bound = perspective_reach(p);
                    EXPECT_LE(far, bound * (1 + 1e-12)) << theta << " " << phi << " " << fov;
                    if (cam.outside_count() == 0) {
                        EXPECT_NEAR(far, bound, 1e-12 * bound) << theta << " " << fov << " " << D;
                    }
                }
    // A closed form: theta 0, the image's corner pixel (i = j = 0 of 24) at D tan(F/2) (23/24)
    // along both axes.
    const double a = std::tan(22.5 * M_PI / 180) * 23.0 / 24;
    EXPECT_NEAR(perspective_reach({0, 0, 10, 45, 24}), 10 * a * std::sqrt(2.0), 1e-12);
}

// fbm 32, pom 8, theta 30: D = 1e15 puts samples ~2^54 cells out, where the DDA's exit line
// x + 1 rounds back to x (the run hung, as did size 1024 at 1e14 and pxh bench at 1e15). Refused
// at the camera's key, naming the field, the setting and the limit; D = 1e9 stays accepted.
TEST(TruthLimits, FarEyesAreRefusedAtTheirKey) {
    EXPECT_EQ(far_eye_error(1e9, 32), "(no error)");
    const std::string e = far_eye_error(1e15, 32);
    EXPECT_EQ(e.rfind("e.toml:7: heightfield 'f': distance 1e+15, fov_deg 45, resolution 16 at "
                      "theta 30 puts inside pixels up to ",
                      0),
              0u)
        << e;
    EXPECT_NE(e.find(" cells of the 32 x 32 field: beyond the exact tracer's reach of 2^36 cells "
                     "(kMaxSampleCells), where its doubles no longer resolve a hit; bring the eye "
                     "closer"),
              std::string::npos)
        << e;
    EXPECT_NE(far_eye_error(1e14, 1024), "(no error)");
    // The limit scales with the field: 1e9 tiles of 32 texels pass, of 4096 they do not.
    EXPECT_NE(far_eye_error(1e9, 4096).find("4096 x 4096 field"), std::string::npos);
}

// The tracers refuse such samples themselves (a view that did not come through the parse), a
// line naming the limit, never an endless walk.
TEST(TruthLimits, TracersRefuseSamplesBeyondTheReach) {
    const HeightField hf = generated("fbm", 32);
    const ExactTracer exact(hf, 0.05, 1.0);
    const Vec3d V = view_vector(30, 0);
    const Vec2d far{1e15, 0.5};  // 3.2e16 cells: past 2^53
    EXPECT_THROW(exact.trace_naive(far, V), std::invalid_argument);
    EXPECT_THROW(exact.trace_ray(far, V), std::invalid_argument);
    EXPECT_THROW(exact.trace(far, V), std::invalid_argument);
    EXPECT_THROW(exact.trace_walk(far, V), std::invalid_argument);
    const PerspectiveCamera cam({30, 0, 1e15, 45, 8});
    Hits hits;
    try {
        exact.trace(cam.view(), hits);
        ADD_FAILURE() << "traced a view 1e15 tiles out";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("kMaxSampleCells"), std::string::npos) << e.what();
    }
    // Just inside the limit a ray is traced (to the same hit by every path).
    const Vec2d in{kMaxSampleCells / 32 - 1, 0.25};
    const TruthHit a = exact.trace_naive(in, V), b = exact.trace_ray(in, V);
    EXPECT_EQ(a.uv.x, b.uv.x);
    EXPECT_EQ(a.uv.y, b.uv.y);
    // b = 1: the ray enters at P (z_top = 0) and moves along -V, at most s tan 30 tiles.
    EXPECT_LE(a.uv.x, in.x);
    EXPECT_GE(a.uv.x, in.x - 0.05 * std::tan(M_PI / 6) - 1e-6);
    EXPECT_EQ(a.uv.y, in.y);
}

// Float rows lose accuracy with distance (pom float err_mean 0.0002 at D 2, 3.8 at 1e7, double
// rows 0.0002 throughout): the parse warns and the float rows say so; near eyes and double
// rows say nothing.
TEST(TruthLimits, FloatRowsSayWhereFloatStopsResolvingTexels) {
    const std::string both = "precision = [\"float\", \"double\"]\n";
    const Experiment near = parse_experiment(far_eye_experiment(2, 32, both), "e.toml");
    EXPECT_TRUE(near.warnings.empty());
    for (const ResultRow& r : run_experiment(near, {})) {
        ASSERT_TRUE(r.ok()) << r.text("error");
        EXPECT_EQ(r.text("error"), "") << r.text("precision");
    }
    const Experiment far = parse_experiment(far_eye_experiment(1e7, 32, both), "e.toml");
    ASSERT_EQ(far.warnings.size(), 1u);
    EXPECT_EQ(far.warnings[0].rfind("e.toml:8: heightfield 'f': distance 10000000, fov_deg 45, "
                                    "resolution 16 at theta 30 puts inside pixels up to ",
                                    0),
              0u)
        << far.warnings[0];
    EXPECT_NE(far.warnings[0].find("the float rows (CPU float, GLSL) lose accuracy with distance"),
              std::string::npos)
        << far.warnings[0];
    const auto rows = run_experiment(far, {});
    ASSERT_EQ(rows.size(), 2u);
    for (const ResultRow& r : rows) {
        ASSERT_TRUE(r.ok()) << r.text("error");
        if (r.text("precision") == "double") {
            EXPECT_EQ(r.text("error"), "");
            EXPECT_LT(r.num("err_mean"), 0.01);
            continue;
        }
        // The farthest inside sample of this view lies 5.78e6 tiles out: floats there are half
        // a tile = 16 texels apart (2^22 <= 5.78e6 < 2^23).
        EXPECT_EQ(r.text("error").rfind("note: float spaces uv 16 texels apart at inside "
                                        "samples (e.g. uv ",
                                        0),
                  0u)
            << r.text("error");
        EXPECT_GT(r.num("err_mean"), 1.0);  // the drift the note explains
    }
}

// A view with no inside pixel (theta 89.5, fov 1: every pixel looks past 89 degrees) measures
// nothing: its rows fail with the reason, never ok with empty cells.
TEST(TruthLimits, AllOutsideViewFailsWithItsReason) {
    std::string toml = far_eye_experiment(4, 32);
    toml.replace(toml.find("theta_deg = [30]"), 16, "theta_deg = [89.5]\nfov_deg = 1");
    const auto rows = run_experiment(parse_experiment(toml, "e.toml"), {});
    ASSERT_EQ(rows.size(), 1u);
    EXPECT_FALSE(rows[0].ok());
    EXPECT_EQ(rows[0].text("error").rfind("every sample (256) lies outside the view (V.z <= cos 89 "
                                          "degrees: at or beyond the horizon, samples_outside): "
                                          "nothing to measure",
                                          0),
              0u)
        << rows[0].text("error");
    EXPECT_TRUE(std::isnan(rows[0].num("err_mean")));
}

// A range of a camera's distances is values, not angles; the count is named.
TEST(TruthLimits, LongDistanceRangeNamesItsValues) {
    std::string toml = far_eye_experiment(4, 32);
    toml.replace(toml.find("distance = 4"), 12, "distance = { from = 1, to = 1e6, step = 1 }");
    EXPECT_THROW(
        {
            try {
                (void)parse_experiment(toml, "e.toml");
            } catch (const InputError& e) {
                EXPECT_STREQ(e.what(),
                             "e.toml:7: 'distance' range { from = 1, to = 1000000, step = 1 } "
                             "gives 1000000 values, more than 100000");
                throw;
            }
        },
        InputError);
}

// ---- Through the binary ----------------------------------------------------------------------

class TruthLimitsCli : public test::CliTest {
  protected:
    // A small experiment: one field, one view, the cheapest method, CPU only.
    std::string experiment(int samples, const std::string& field, double scale, double theta,
                           const std::string& extra = "") {
        std::ostringstream os;
        os.precision(17);
        os << "name = \"limits\"\nsamples = " << samples << "\ntiming_repeats = 0\n"
           << extra << "[views]\ntheta_deg = [" << theta << "]\nphi_deg = [0]\n\n"
           << "[[heightfields]]\ngenerator = \"" << field << "\"\nsize = 32\nscale = " << scale
           << "\nbias = 1.0\n\n[[methods]]\nname = \"pom\"\n";
        return write("e.toml", os.str());
    }
    // `timeout LIMIT pxh ARGS`, with the peak memory of the pxh process (kB).
    test::CliResult timed_pxh(const std::string& args, int limit_s, long& peak_kb) {
        const test::CliResult r =
            sh("timeout " + std::to_string(limit_s) + " /usr/bin/time -f %M -o " +
               (dir / "rss.txt").string() + " " + PXH_BINARY + " " + args);
        peak_kb = std::atol(slurp(dir / "rss.txt").c_str());
        return r;
    }
};

TEST_F(TruthLimitsCli, RunsWithOneToEightSamples) {
    for (int n = 1; n <= 8; ++n) {
        const std::string e = experiment(n, "fbm", 0.05, 60);
        const auto out = dir / ("out" + std::to_string(n));
        const test::CliResult r = pxh("run " + e + " --quiet --out " + out.string());
        EXPECT_EQ(r.status, 0) << "samples = " << n << ": " << r.err;
        EXPECT_TRUE(std::filesystem::exists(out / "results.csv")) << n;
    }
}

TEST_F(TruthLimitsCli, BenchWithOneSampleAndOnlyMeasuredColumns) {
    const std::string json = (dir / "b.json").string();
    test::CliResult r = pxh("bench --samples 1 --sizes 16 --repeats 1 --theta 30 --out " + json);
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(r.out.find("nan"), std::string::npos) << r.out;
    EXPECT_EQ(r.out.find("naive"), std::string::npos) << r.out;  // not measured: no column
    auto doc = nlohmann::json::parse(slurp(json));
    ASSERT_EQ(doc["results"].size(), 1u);
    const auto& row = doc["results"][0];
    EXPECT_FALSE(row.contains("naive_mrays_per_s"));
    EXPECT_FALSE(row.contains("per_ray_mipmap_mrays_per_s"));
    for (const auto& [key, value] : row.items()) EXPECT_FALSE(value.is_null()) << key;
    EXPECT_GT(row["exact_mrays_per_s"].get<double>(), 0);

    r = pxh("bench --samples 3 --sizes 16 --repeats 1 --theta 30 --naive --force --out " + json);
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(r.out.find("nan"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("naive Mr/s"), std::string::npos) << r.out;
    doc = nlohmann::json::parse(slurp(json));
    EXPECT_GT(doc["results"][0]["naive_mrays_per_s"].get<double>(), 0);
    EXPECT_GT(doc["results"][0]["per_ray_mipmap_mrays_per_s"].get<double>(), 0);
}

// The perspective mode: both tracers on the camera's rays, one row per theta and distance, the
// outside pixels counted as the camera's geometry says; its keys only with that camera.
TEST_F(TruthLimitsCli, BenchPerspectiveRowsPerThetaAndDistance) {
    const std::string json = (dir / "p.json").string();
    test::CliResult r =
        pxh("bench --camera perspective --distance 1.5 4 --fov 45 --samples 16 --sizes 32 "
            "--repeats 1 --theta 60 85 --naive --threads 1 --out " +
            json);
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(r.out.find("nan"), std::string::npos) << r.out;
    const auto doc = nlohmann::json::parse(slurp(json));
    EXPECT_EQ(doc["camera"], "perspective");
    ASSERT_EQ(doc["results"].size(), 4u);
    for (const auto& row : doc["results"]) {
        PerspectiveParams p;
        p.theta_deg = row["theta_deg"].get<double>();
        p.phi_deg = row["phi_deg"].get<double>();
        p.distance = row["distance"].get<double>();
        p.fov_deg = 45;
        p.samples = 16;
        EXPECT_EQ(row["samples_outside"].get<size_t>(), PerspectiveCamera(p).outside_count());
        EXPECT_GT(row["ratio_exact_over_embree"].get<double>(), 0);
        EXPECT_GT(row["trace_ray_mrays_per_s"].get<double>(), 0);
        EXPECT_LT(row["agree_p50_texel"].get<double>(), 0.05);  // triangles vs bilinear, 32^2
    }
    EXPECT_GT(doc["results"][2]["samples_outside"].get<size_t>(), 0u);  // 85 deg: the sky
    r = pxh("bench --distance 4 --samples 4 --sizes 16 --repeats 1 --out " +
            (dir / "q.json").string());
    EXPECT_EQ(r.status, 2) << r.err;
    EXPECT_NE(r.err.find("--distance"), std::string::npos) << r.err;
    EXPECT_FALSE(std::filesystem::exists(dir / "q.json"));
}

// Beyond the limit: exit 2, one line naming the experiment file and the height field's line,
// no results folder. Previously s = 1e300 never finished and 89.9999999 deg passed 6 GB.
TEST_F(TruthLimitsCli, RunRefusesViewsBeyondTheLimit) {
    struct Case {
        double scale, theta;
        std::string extra;
    };
    const Case cases[] = {{1.0, 89.999, ""},
                          {1e300, 45.0, ""},
                          {0.05, 89.9999999, ""},
                          {1.0, 30.0, "[light]\ntheta_deg = 89.999\n"},
                          {1.0, 89.99, "sweep_dt_deg = 0.009\n"}};  // the companion view: 89.999
    for (const Case& c : cases) {
        const std::string e = experiment(16, "fbm", c.scale, c.theta, c.extra);
        const auto out = dir / "refused";
        long peak = 0;
        const test::CliResult r =
            timed_pxh("run " + e + " --quiet --out " + out.string(), 60, peak);
        EXPECT_EQ(r.status, 2) << c.scale << " " << c.theta << ": " << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
        EXPECT_EQ(r.err.rfind("pxh: error: " + e + ":", 0), 0u) << r.err;
        EXPECT_NE(r.err.find("kMaxRayTravelTiles"), std::string::npos) << r.err;
        EXPECT_FALSE(std::filesystem::exists(out));
    }
}

// pxh run and pxh bench at a far eye: exit 2, one line, nothing written (both hung before).
TEST_F(TruthLimitsCli, FarEyesAreRefusedByRunAndBench) {
    const std::string e = write("far.toml", far_eye_experiment(1e15, 32));
    const auto out = dir / "far";
    test::CliResult r = pxh_timeout("run " + e + " --quiet --out " + out.string(), 60);
    EXPECT_EQ(r.status, 2) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_EQ(
        r.err.rfind("pxh: error: " + e + ":7: heightfield 'f': distance 1e+15, fov_deg 45", 0), 0u)
        << r.err;
    EXPECT_NE(r.err.find("kMaxSampleCells"), std::string::npos) << r.err;
    EXPECT_FALSE(std::filesystem::exists(out));
    const std::string json = (dir / "b.json").string();
    r = pxh_timeout(
        "bench --camera perspective --distance 1e15 --sizes 32 --samples 8 "
        "--repeats 1 --theta 30 --out " +
            json,
        60);
    EXPECT_EQ(r.status, 2) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_EQ(r.err.rfind("pxh: error: --distance: distance 1e+15 at theta 30 puts inside pixels "
                          "up to ",
                          0),
              0u)
        << r.err;
    EXPECT_FALSE(std::filesystem::exists(json));
}

// --base: the curved truth's tracers timed over the same rays, beside the exact tracer on the
// plane: the pyramid tracer, Embree on a displaced grid and the walk (issue 62, item 3), the
// pyramid's hits the walk's; a curved base without a radius, or a radius on the plane, is
// refused before any work.
TEST_F(TruthLimitsCli, BenchTimesTheCurvedWalk) {
    const std::string json = (dir / "c.json").string();
    test::CliResult r =
        pxh("bench --samples 16 --sizes 32 --repeats 2 --theta 30 70 --base cylinder "
            "--radius 0.5 --out " +
            json);
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.out.find("on cylinder R=0.5 ("), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("pyramid / Embree "), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("Embree grid ("), std::string::npos) << r.out;
    const auto doc = nlohmann::json::parse(slurp(json));
    ASSERT_EQ(doc["results"].size(), 2u);
    for (const auto& row : doc["results"]) {
        EXPECT_EQ(row["base"], "cylinder");
        EXPECT_EQ(row["radius"].get<double>(), 0.5);
        EXPECT_GT(row["curved_mrays_per_s"].get<double>(), 0);
        EXPECT_NEAR(
            row["ratio_curved_over_exact"].get<double>(),
            row["curved_mrays_per_s"].get<double>() / row["exact_mrays_per_s"].get<double>(), 1e-9);
        EXPECT_EQ(row["curved_seconds"].size(), 2u);
        EXPECT_GT(row["curved_rays_hit"].get<size_t>(), 0u);
        EXPECT_LT(row["curved_residual_max"].get<double>(), 1e-9);
        EXPECT_GT(row["curved_pyramid_mrays_per_s"].get<double>(), 0);
        EXPECT_EQ(row["curved_pyramid_seconds"].size(), 2u);
        EXPECT_EQ(row["curved_pyramid_vs_walk_hit_miss"].get<size_t>(), 0u);
        EXPECT_LT(row["curved_pyramid_vs_walk_uv_max"].get<double>(), 1e-9);
        EXPECT_LT(row["curved_pyramid_residual_max"].get<double>(), 1e-9);
        EXPECT_GT(row["curved_embree_mrays_per_s"].get<double>(), 0);
        EXPECT_GT(row["curved_embree_vertices"].get<size_t>(), 0u);
        EXPECT_NEAR(row["ratio_pyramid_over_embree"].get<double>(),
                    row["curved_pyramid_mrays_per_s"].get<double>() /
                        row["curved_embree_mrays_per_s"].get<double>(),
                    1e-9);
        // Embree's facets against the bilinear patches: within a texel at the median
        EXPECT_LT(row["curved_embree_err_p50"].get<double>(), 1.0);
    }
    for (const char* args : {"--base sphere", "--radius 2", "--base cylinder --radius 0.01"}) {
        r = pxh_timeout(std::string("bench --sizes 16 --samples 4 --repeats 1 ") + args +
                            " --out " + (dir / "d.json").string(),
                        60);
        EXPECT_EQ(r.status, 2) << args << ": " << r.err;
        EXPECT_NE(r.err.find("radius"), std::string::npos) << args << ": " << r.err;
        EXPECT_FALSE(std::filesystem::exists(dir / "d.json")) << args;
    }
}

// Issue 59, item 3: the grazing cylinder (4096^2, s 100, R 1000, theta 88.9, phi 90), which
// walked for minutes with 4 rays (hours with 256^2), ends at once with exit 2 and one line
// naming the estimate, the limit and the knobs: pxh run at the field's entry, pxh bench at
// --base, both before any work (no field is generated). The wall bound is generous: the old
// limit let the 4 rays through to a walk over 400 s. pxh bench keeps s = 0.05, so its case is
// the steepest view it takes, 89.999 degrees (a chord of 2865 tiles; 2 walks of 4 rays: 3.8e8
// steps). And pxh bench's walks stop at their budget during the run too.
TEST_F(TruthLimitsCli, GrazingCylinderIsRefusedByRunAndBench) {
    for (const char* samples : {"2", "256"}) {
        const std::string e = write(
            "g.toml", std::string("name = \"g\"\nsamples = ") + samples +
                          "\ntiming_repeats = 0\nbackends = [\"cpu\"]\n[views]\n"
                          "theta_deg = [88.9]\nphi_deg = [90]\n\n[[heightfields]]\n"
                          "generator = \"fbm\"\nsize = 4096\nscale = 100\nbias = 1.0\n"
                          "base = \"cylinder\"\nradius = 1000\n\n[[methods]]\nname = \"pom\"\n");
        const auto out = dir / "g";
        const test::CliResult r = pxh_timeout("run " + e + " --quiet --out " + out.string(), 300);
        EXPECT_EQ(r.status, 2) << samples << ": " << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
        EXPECT_EQ(r.err.rfind("pxh: error: " + e +
                                  ":9: heightfield 'fbm' (base cylinder radius "
                                  "1000, s = 100) at theta 88.9 phi 90: the "
                                  "curved truth's walk would take about ",
                              0),
                  0u)
            << r.err;
        EXPECT_NE(r.err.find("over the limit of 2^28 = 2.68e+08 steps a view "
                             "(kMaxCurvedWalkSteps"),
                  std::string::npos)
            << r.err;
        EXPECT_NE(r.err.find("lower theta, the scale, the field's size or samples"),
                  std::string::npos)
            << r.err;
        EXPECT_FALSE(std::filesystem::exists(out));
    }
    const std::string json = (dir / "g.json").string();
    const test::CliResult r = pxh_timeout(
        "bench --field fbm --sizes 4096 --theta 89.999 --phi 90 --samples 2 --repeats 1 "
        "--base cylinder --radius 1000 --out " +
            json,
        300);
    EXPECT_EQ(r.status, 2) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_EQ(r.err.rfind("pxh: error: --base: base cylinder radius 1000 on the 4096 x 4096 field "
                          "at theta 89.999: the curved truth's walk would take about ",
                          0),
              0u)
        << r.err;
    EXPECT_NE(r.err.find("steps for the 4 rays of this view"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("timed 2 times (a warm-up and --repeats 1)"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("(kMaxCurvedWalkSteps"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("lower --theta, --sizes, --samples or --repeats"), std::string::npos)
        << r.err;
    EXPECT_FALSE(std::filesystem::exists(json));
    // A view within the estimate whose walk steps shorter than it (a one-texel cliff over a
    // floor: about 6 times the estimate): each of the 1001 walks gets 2^28 / 1001 steps, and the
    // warm-up stops there, refused at --base with the count.
    const test::CliResult s = pxh_timeout(
        "bench --field step --sizes 1024 --theta 80 --phi 90 --samples 8 --repeats 1000 "
        "--base cylinder --radius 1000 --out " +
            json,
        300);
    EXPECT_EQ(s.status, 2) << s.err;
    EXPECT_EQ(std::count(s.err.begin(), s.err.end(), '\n'), 1) << s.err;
    EXPECT_EQ(s.err.rfind("pxh: error: --base: base cylinder radius 1000 on the 1024 x 1024 field "
                          "at theta 80: the curved truth's walk stopped after ",
                          0),
              0u)
        << s.err;
    EXPECT_NE(s.err.find("steps for the 64 rays of this view, over its budget of 2.68e+05 steps "
                         "(kMaxCurvedWalkSteps shared by the warm-up and --repeats"),
              std::string::npos)
        << s.err;
    EXPECT_FALSE(std::filesystem::exists(json));
}

// pxh bench's numbers, refused in pxh's words with exit 2: NaN (CLI11's ranges let it through,
// exit 1 later) and 0 (CLI11 printed the whole range of doubles, 309 digits).
TEST_F(TruthLimitsCli, BenchRefusesNanAndZeroInOneShortLine) {
    const std::string json = (dir / "b.json").string();
    const std::pair<std::string, std::string> cases[] = {
        {"--phi nan", "pxh: error: --phi: nan is not a finite angle\n"},
        {"--theta nan", "pxh: error: --theta: nan is not in [0, 89.999]\n"},
        {"--camera perspective --distance 0",
         "pxh: error: --distance: 0 is not a positive number of tiles\n"},
        {"--camera perspective --distance -2",
         "pxh: error: --distance: -2 is not a positive number of tiles\n"},
        {"--camera perspective --fov nan", "pxh: error: --fov: nan is not in [0.001, 179.999]\n"},
    };
    for (const auto& [args, line] : cases) {
        const test::CliResult r =
            pxh_timeout("bench --sizes 16 --samples 4 --repeats 1 " + args + " --out " + json, 60);
        EXPECT_EQ(r.status, 2) << args << ": " << r.err;
        EXPECT_EQ(r.err, line) << args;
        EXPECT_FALSE(std::filesystem::exists(json)) << args;
    }
}

// Just inside the limit, the worst kind of view (every ray skims a field whose rows it never
// leaves: phi = 0): the run finishes, within bounded time and memory.
TEST_F(TruthLimitsCli, LargestAcceptedTravelFinishesInBoundedMemory) {
    double theta = theta_for_travel(1.0, kMaxRayTravelTiles);
    while (!ray_travel_problem(1.0, theta).empty()) theta = std::nextafter(theta, 0.0);
    for (const char* field : {"fbm", "spikes"}) {
        const std::string e = experiment(32, field, 1.0, theta);
        long peak = 0;
        const auto t0 = std::chrono::steady_clock::now();
        const test::CliResult r =
            timed_pxh("run " + e + " --quiet --out " + (dir / field).string(), 120, peak);
        const double sec =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        EXPECT_EQ(r.status, 0) << field << ": " << r.err;
        EXPECT_LT(peak, 1024 * 1024) << field << ": peak " << peak << " kB";
        EXPECT_LT(sec, 60) << field;
    }
    // And straight down at an absurd scale (no travel at all): the truths finish; the method's
    // every sample is non-finite there, so its row fails (exit 1), never NaN called ok.
    const test::CliResult r =
        pxh("run " + experiment(16, "fbm", 1e300, 0) + " --quiet --out " + (dir / "huge").string());
    EXPECT_EQ(r.status, 1) << r.err;
    EXPECT_NE(r.err.find("gave a non-finite uv"), std::string::npos) << r.err;
    EXPECT_TRUE(std::filesystem::exists(dir / "huge" / "run.json"));
}

}  // namespace
}  // namespace pxh
