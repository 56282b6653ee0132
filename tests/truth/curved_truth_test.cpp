// Curved base surfaces (docs/conventions.md section 12): the bases' frames against finite
// differences of B, their coordinates against B + h N, the curved truth against the exact tracer
// on the plane base and against a brute-force march with tiny steps on a cylinder and a sphere,
// and the run: base = "plane" given explicitly is today's rows, a radius of 10^4 converges to
// the plane's rows, a vanishing relief is exact on every base, and bad input is refused.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>

#include "harness/core/error.h"
#include "harness/experiment/experiment.h"
#include "harness/run/runner.h"
#include "harness/scene/base_surface.h"
#include "harness/scene/curved_view.h"
#include "harness/scene/perspective_camera.h"
#include "harness/truth/curved_tracer.h"
#include "harness/truth/ground_truth.h"
#include "tests/test_util.h"

namespace pxh {
namespace {

using test::generated_field;
using test::parse_error;
using test::random_field;
using test::run;

double dist(Vec3d a, Vec3d b) { return std::sqrt(v3_dot(v3_sub(a, b), v3_sub(a, b))); }

TEST(CurvedBase, FramesAreFiniteDifferencesOfB) {
    for (const char* name : {"cylinder", "sphere"})
        for (double R : {0.3, 1.0, 7.0}) {
            const auto base = make_base(name, R);
            std::mt19937 rng(7);
            std::uniform_real_distribution<double> U(0.5 - 0.7 * R, 0.5 + 0.7 * R);
            for (int i = 0; i < 50; ++i) {
                const Vec2d uv{U(rng), U(rng)};
                const BaseFrame f = base->frame(uv);
                const double h = 1e-6;
                const Vec3d du = v3_scale(
                    v3_sub(base->frame({uv.x + h, uv.y}).B, base->frame({uv.x - h, uv.y}).B),
                    0.5 / h);
                const Vec3d dv = v3_scale(
                    v3_sub(base->frame({uv.x, uv.y + h}).B, base->frame({uv.x, uv.y - h}).B),
                    0.5 / h);
                EXPECT_LT(dist(v3_unit(du), f.T), 1e-8) << name << " R " << R;
                EXPECT_LT(dist(v3_unit(dv), f.Bt), 1e-8) << name << " R " << R;
                EXPECT_NEAR(v3_dot(f.N, f.N), 1, 1e-12);
                EXPECT_NEAR(v3_dot(f.N, f.T), 0, 1e-12);
                EXPECT_NEAR(v3_dot(f.N, f.Bt), 0, 1e-12);
                EXPECT_NEAR(v3_dot(f.T, f.Bt), 0, 1e-12);  // orthonormal for these bases
                // the cylinder keeps arc length along u; the sphere along its equator only
                if (std::string(name) == "cylinder") {
                    EXPECT_NEAR(std::sqrt(v3_dot(du, du)), 1, 1e-8);
                }
                // coords inverts B + height N
                const BaseCoord c = base->coords(v3_add(f.B, v3_scale(f.N, 0.03)));
                EXPECT_NEAR(c.uv.x, uv.x, 1e-12);
                EXPECT_NEAR(c.uv.y, uv.y, 1e-12);
                EXPECT_NEAR(c.height, 0.03, 1e-12);
            }
            // through the look-at point with normal +z
            const BaseFrame c = base->frame({0.5, 0.5});
            EXPECT_LT(dist(c.B, {0.5, 0.5, 0}), 1e-15);
            EXPECT_LT(dist(c.N, {0, 0, 1}), 1e-15);
        }
}

// Brute force: march the world ray in steps of `step` from the outer shell, bisect the first
// step that ends at or below X. Its own g, from the base's coordinates and HeightSampler.
Vec2d brute_hit(const BaseSurface& base, const HeightField& hf, double s, double b, WorldRay r,
                double step) {
    HeightSampler<double> hs(hf, s, b);
    auto g = [&](double t) {
        const BaseCoord c = base.coords(v3_add(r.o, v3_scale(r.d, t)));
        return c.height - hs.z(c.uv);
    };
    const double t0 = base.hit(r.o, r.d, s * (1 - b), 0, false);
    if (!std::isfinite(t0)) return {NAN, NAN};
    double t_end = base.hit(r.o, r.d, s * (1 - b), t0, true);
    const double floor = base.hit(r.o, r.d, -s * b, t0, false);
    if (std::isfinite(floor)) t_end = std::isfinite(t_end) ? std::min(t_end, floor) : floor;
    for (double t = t0; t < t_end; t += step) {
        const double t2 = std::min(t + step, t_end);
        if (g(t2) <= 0) {
            double lo = t, hi = t2;
            for (int i = 0; i < 100; ++i) (g(0.5 * (lo + hi)) <= 0 ? hi : lo) = 0.5 * (lo + hi);
            return base.coords(v3_add(r.o, v3_scale(r.d, hi))).uv;
        }
    }
    return {NAN, NAN};
}

TEST(CurvedBase, TruthIsTheBruteForceMarch) {
    const HeightField hf = random_field(12, 12, 3);
    const double s = 0.06;
    for (const char* name : {"cylinder", "sphere"})
        for (double b : {1.0, 0.5}) {
            const auto base = make_base(name, 0.4);
            PerspectiveParams p;
            p.theta_deg = 55;
            p.phi_deg = 20;
            p.distance = 2;
            p.fov_deg = 35;
            p.samples = 24;
            const PerspectiveCamera cam(p);
            const CurvedView cv = curved_view(cam, *base, s * (1 - b));
            const CurvedHits h = CurvedTracer(hf, s, b, *base).trace(cv.rays);
            int hits = 0, misses = 0;
            for (size_t k = 0; k < cv.rays.size(); ++k) {
                const Vec2d bf = brute_hit(*base, hf, s, b, cv.rays[k], 2e-5);
                ASSERT_EQ(std::isfinite(bf.x), h.hit[k] != 0) << name << " b " << b << " k " << k;
                if (!h.hit[k]) {
                    ++misses;
                    continue;
                }
                ++hits;
                EXPECT_NEAR(h.uv[k].x, bf.x, 1e-7) << name << " b " << b << " k " << k;
                EXPECT_NEAR(h.uv[k].y, bf.y, 1e-7) << name << " b " << b << " k " << k;
            }
            EXPECT_GT(hits, 100);
            EXPECT_GT(misses, 20);  // the silhouette is in the image
            EXPECT_LT(h.residual_max, 1e-12);
        }
}

// On the plane base the walk finds section 4's exact hits (the exact tracer's), through the
// perspective camera, on a measured-like random field and bricks.
TEST(CurvedBase, OnThePlaneTheWalkIsTheExactTracer) {
    const HeightField fields[] = {random_field(32, 32, 11), generated_field("bricks", 64)};
    for (const HeightField& hf : fields) {
        const double s = 0.05, b = 1.0;
        PerspectiveParams p;
        p.theta_deg = 65;
        p.phi_deg = 30;
        p.distance = 1.5;
        p.fov_deg = 45;
        p.samples = 40;
        const PerspectiveCamera cam(p);
        const View view = cam.view();
        const GroundTruth gt = trace_ground_truth(*make_tracer("exact", hf, s, b), view);
        const auto plane = make_base("plane", NAN);
        const CurvedView cv = curved_view(cam, *plane, 0);
        const CurvedHits h = CurvedTracer(hf, s, b, *plane).trace(cv.rays);
        int compared = 0;
        for (size_t k = 0; k < view.size(); ++k) {
            if (!view.is_inside(k)) continue;
            ASSERT_TRUE(h.hit[k]);
            // the methods' view is the camera's own on the plane
            EXPECT_NEAR(cv.view.P[k].x, view.P[k].x, 1e-12);
            EXPECT_NEAR(cv.view.V[k].z, view.V[k].z, 1e-12);
            // the footprint by central differences of the base hit at 1/4 pixel is the camera's
            // closed form up to their O(h^2) truncation, which grows toward the horizon
            const Footprint &got = cv.view.J[k], &want = view.J[k];
            const double tol =
                (view.V[k].z >= 0.2 ? 2e-3 : 2e-2) *
                (std::hypot(want.dPdi.x, want.dPdi.y) + std::hypot(want.dPdj.x, want.dPdj.y));
            EXPECT_NEAR(got.dPdi.x, want.dPdi.x, tol) << k;
            EXPECT_NEAR(got.dPdi.y, want.dPdi.y, tol) << k;
            EXPECT_NEAR(got.dPdj.x, want.dPdj.x, tol) << k;
            EXPECT_NEAR(got.dPdj.y, want.dPdj.y, tol) << k;
            EXPECT_NEAR(h.uv[k].x * hf.width, gt.uv[k].x * hf.width, 1e-8) << k;
            EXPECT_NEAR(h.uv[k].y * hf.height, gt.uv[k].y * hf.height, 1e-8) << k;
            ++compared;
        }
        EXPECT_GT(compared, 1000);
    }
}

const std::string kHead =
    "samples = 32\ntiming_repeats = 0\nbackends = [\"cpu\"]\nprecision = \"double\"\n"
    "[views]\ntheta_deg = [0, 40, 70]\nphi_deg = [25]\ncamera = \"perspective\"\n"
    "distance = 2\nfov_deg = 40\n";
const std::string kMethods =
    "[[methods]]\nname = \"pom\"\nlayers = 16\n[[methods]]\nname = \"parallax\"\n"
    "[[methods]]\nname = \"maxmip\"\n";

std::string field(const std::string& extra, double scale = 0.05) {
    return "[[heightfields]]\nname = \"f\"\ngenerator = \"bricks\"\nsize = 64\nscale = " +
           std::to_string(scale) + "\nbias = 1.0\n" + extra;
}

TEST(CurvedBase, ExplicitPlaneIsTodaysRows) {
    const auto a = run(kHead + field("") + kMethods);
    const auto b = run(kHead + field("base = \"plane\"\n") + kMethods);
    ASSERT_EQ(a.size(), b.size());
    for (size_t i = 0; i < a.size(); ++i)
        for (const char* c : {"err_mean", "err_max", "err_px_mean", "fetches_mean",
                              "samples_outside", "gt_cells_mean", "gt_agree_max"})
            EXPECT_EQ(a[i].cell(c), b[i].cell(c)) << i << " " << c;
}

TEST(CurvedBase, LargeRadiusConvergesToThePlane) {
    // up to 40 degrees: at 70 the image's far pixels lie tens of tiles away, where even a
    // 10^4-tile radius sags by a good part of the relief
    std::string head = kHead;
    head.replace(head.find("[0, 40, 70]"), 11, "[0, 20, 40]");
    const auto plane = run(head + field("") + kMethods);
    for (const char* name : {"cylinder", "sphere"}) {
        const auto curved =
            run(head + field(std::string("base = \"") + name + "\"\nradius = 10000\n") + kMethods);
        ASSERT_EQ(plane.size(), curved.size());
        for (size_t i = 0; i < plane.size(); ++i) {
            const ResultRow &p = plane[i], &c = curved[i];
            ASSERT_TRUE(c.ok()) << c.text("error");
            EXPECT_EQ(c.text("base"), name);
            EXPECT_EQ(c.num("samples_outside"), p.num("samples_outside"));
            EXPECT_EQ(c.num("cover_extra_frac"), 0);
            EXPECT_EQ(c.num("cover_missing_frac"), 0);
            // a 10^4-tile radius sags 10^-4 tiles 1.4 tiles away: errors within a hundredth
            // of a texel of the plane's
            EXPECT_NEAR(c.num("err_mean"), p.num("err_mean"), 0.01)
                << name << " " << c.text("method") << " theta " << c.num("theta_deg");
            EXPECT_LT(c.num("gt_agree_max"), 1e-6);
        }
    }
}

// Issue 62: the curved truth is the pyramid tracer, and the walk at half the step that its
// gt_agree_* columns compare it with walks one ray in 16 by default (truth_check = "subset":
// the samples (i, j) with i % 4 == j % 4 == 2), every ray with "all", none with "none"; the
// rays compared are gt_agree_rays, and nothing else in a row moves. The plane's cross-check
// (Embree) takes every ray by default and the same subset when asked.
TEST(CurvedBase, TruthCheckPicksTheRaysOfTheAgreementColumns) {
    const std::string fields = field("base = \"cylinder\"\nradius = 0.5\n") +
                               "[[heightfields]]\nname = \"p\"\ngenerator = \"bricks\"\n"
                               "size = 64\nscale = 0.05\nbias = 1.0\n";
    const auto by_default = run(kHead + fields + kMethods);
    const auto all = run("truth_check = \"all\"\n" + kHead + fields + kMethods);
    const auto subset = run("truth_check = \"subset\"\n" + kHead + fields + kMethods);
    const auto none = run("truth_check = \"none\"\n" + kHead + fields + kMethods);
    ASSERT_EQ(all.size(), by_default.size());
    ASSERT_EQ(subset.size(), by_default.size());
    ASSERT_EQ(none.size(), by_default.size());
    int curved = 0, plane = 0;
    for (size_t i = 0; i < all.size(); ++i) {
        ASSERT_TRUE(all[i].ok()) << all[i].text("error");
        const bool is_curved = all[i].text("heightfield") == "f";
        // the default: a subset on the cylinder, every ray on the plane
        const auto& d = by_default[i];
        const auto& same = is_curved ? subset[i] : all[i];
        for (const char* c : {"gt_agree_rays", "gt_agree_p50", "gt_agree_max"})
            EXPECT_EQ(d.cell(c), same.cell(c)) << i << " " << c;
        for (const char* c : {"err_mean", "err_max", "err_px_mean", "cover_extra_frac",
                              "cover_missing_frac", "gt_residual_max", "depth_err_mean"})
            for (const auto* rows : {&all, &subset, &none})
                EXPECT_EQ((*rows)[i].cell(c), d.cell(c)) << i << " " << c;
        // 32 x 32 samples: the subset is 8 x 8 of them, less those no reference hits
        const double n_all = all[i].num("gt_agree_rays"), n_sub = subset[i].num("gt_agree_rays");
        EXPECT_GT(n_sub, 0) << i;
        EXPECT_LE(n_sub, 64) << i;
        EXPECT_GT(n_all, 8 * n_sub) << i;
        EXPECT_LE(n_all, 32 * 32) << i;
        if (!is_curved) {
            EXPECT_EQ(n_all, 32 * 32) << i;  // every ray hits the plane's relief
        }
        // the subset's statistics are of rays the whole check saw
        EXPECT_LE(subset[i].num("gt_agree_max"), all[i].num("gt_agree_max")) << i;
        if (is_curved) {  // the walk and the pyramid: rounding apart (Embree: its facets)
            EXPECT_LT(all[i].num("gt_agree_max"), 1e-6) << i;
        }
        EXPECT_TRUE(std::isnan(none[i].num("gt_agree_max"))) << i;
        EXPECT_TRUE(std::isnan(none[i].num("gt_agree_rays"))) << i;
        ++(is_curved ? curved : plane);
    }
    EXPECT_GT(curved, 0);
    EXPECT_GT(plane, 0);
    const std::string err = parse_error("truth_check = \"some\"\n" + kHead + fields + kMethods);
    EXPECT_EQ(err.rfind("e.toml:1", 0), 0u) << err;
    EXPECT_NE(err.find("unknown truth_check 'some' (known: all, subset, none"), std::string::npos)
        << err;
    // the estimate counts the truth and the check walk's share of the rays at twice a walk
    EXPECT_EQ(curved_walks("all", 1024), 3);
    EXPECT_EQ(curved_walks("subset", 1024), 1 + 2.0 / 16);
    EXPECT_EQ(curved_walks("", 1024), curved_walks("subset", 1024));
    EXPECT_EQ(curved_walks("subset", 4), 1 + 2.0 / 4);  // 2 x 2 samples: one ray checked
    EXPECT_EQ(curved_walks("none", 1024), 1);
    EXPECT_EQ(truth_check_rays(64, "subset"), (std::vector<size_t>{18, 22, 50, 54}));
}

TEST(CurvedBase, AVanishingReliefIsExactEverywhere) {
    for (const char* name : {"cylinder", "sphere"}) {
        const auto rows = run(
            kHead + field(std::string("base = \"") + name + "\"\nradius = 0.5\n", 1e-5) + kMethods);
        for (const ResultRow& r : rows) {
            ASSERT_TRUE(r.ok()) << r.text("error");
            EXPECT_LT(r.num("err_max"), 0.01) << name << " " << r.text("method");
            // a ray that meets the base with V_ts.z > cos 89 degrees sinks the relief's 10^-5
            // tiles before the 0.5-tile radius can lift it out (that needs V_ts.z below
            // sqrt(2 s / R) = 0.006): both fractions are exactly 0
            EXPECT_EQ(r.num("cover_extra_frac"), 0)
                << name << " " << r.text("method") << " theta " << r.num("theta_deg");
            EXPECT_EQ(r.num("cover_missing_frac"), 0)
                << name << " " << r.text("method") << " theta " << r.num("theta_deg");
        }
    }
}

// Relief below the base (b = 1): a ray that meets X has crossed the base first, so the truth
// never shows what the method cannot (cover_missing_frac = 0 exactly), while past the base's
// outline some rays cross the base and leave again above the relief (cover_extra_frac > 0).
// Relief around the base (b = 0.5): the relief standing out past the outline is missing.
TEST(CurvedBase, SilhouettesOnASmallSphere) {
    for (double b : {1.0, 0.5}) {
        const auto rows = run(kHead +
                              "[[heightfields]]\nname = \"f\"\ngenerator = \"bricks\"\nsize = 64\n"
                              "scale = 0.08\nbias = " +
                              std::to_string(b) + "\nbase = \"sphere\"\nradius = 0.3\n" + kMethods);
        for (const ResultRow& r : rows) {
            ASSERT_TRUE(r.ok()) << r.text("error");
            if (b == 1.0) {
                EXPECT_EQ(r.num("cover_missing_frac"), 0) << r.text("method");
                EXPECT_GT(r.num("cover_extra_frac"), 0.005) << r.text("method");
            } else {
                EXPECT_GT(r.num("cover_missing_frac"), 0.005) << r.text("method");
            }
            EXPECT_GT(r.num("err_mean"), 0.05) << r.text("method");  // flat methods on a curve
        }
    }
}

// The depth test on a curved base, in closed form: on a flat field h = c with b = 1 the true
// surface is the sphere of radius R - s (1 - c) under the base, so `base` (the base hit's depth)
// lies in front of the truth by the depth between the base hit and that sphere's hit, which the
// test computes with its own ray-sphere quadratic; a cut shell at c' (below the base for c' < 1)
// shows in truth exactly when c' > c and never for `base`, so every pixel flips when c' > c.
TEST(CurvedBase, DepthOnAFlatFieldIsTheShellsClosedForm) {
    const double s = 0.08, c = 0.25, R = 0.5;
    const std::string toml =
        "samples = 24\ntiming_repeats = 0\nbackends = [\"cpu\"]\nprecision = \"double\"\n"
        "[views]\ntheta_deg = [35]\nphi_deg = [20]\ncamera = \"perspective\"\ndistance = 2\n"
        "fov_deg = 40\ncut = [0.1, 0.6]\n[[heightfields]]\nname = \"flat\"\ngenerator = \"flat\"\n"
        "level = 0.25\nwidth = 16\nheight = 16\nscale = 0.08\nbias = 1.0\nbase = \"sphere\"\n"
        "radius = 0.5\n[[methods]]\nname = \"pom\"\nlayers = 16\ndepth = [\"base\", \"hit\"]\n";
    const auto rows = run(toml);
    ASSERT_EQ(rows.size(), 4u);
    // the expected bias of `base`: mean over the pixels both show of -(X_t - B_P) . f
    PerspectiveParams p;
    p.theta_deg = 35;
    p.phi_deg = 20;
    p.distance = 2;
    p.fov_deg = 40;
    p.samples = 24;
    const PerspectiveCamera cam(p);
    const Vec3d C{0.5, 0.5, -R}, f = cam.forward();
    auto first_root = [&](const WorldRay& r, double radius) {
        const Vec3d q = v3_sub(r.o, C);
        const double b = v3_dot(q, r.d), cc = v3_dot(q, q) - radius * radius;
        const double disc = b * b - cc;
        return disc < 0 ? NAN : -b - std::sqrt(disc);
    };
    double sum = 0;
    int count = 0;
    for (size_t k = 0; k < 24 * 24; ++k) {
        const WorldRay r = cam.world_ray(k, 0, 0, 0);
        const double tb = first_root(r, R), ts = first_root(r, R - s * (1 - c));
        if (!std::isfinite(tb) || !std::isfinite(ts)) continue;
        const Vec3d Bp = v3_add(r.o, v3_scale(r.d, tb));
        const double vz = -v3_dot(r.d, v3_unit(v3_sub(Bp, C)));
        if (!(vz > std::cos(89 * M_PI / 180))) continue;  // outside, as the view has it
        sum += -v3_dot(v3_scale(r.d, ts - tb), f);
        ++count;
    }
    ASSERT_GT(count, 100);
    double base_err = 0, hit_err = 0;
    for (const ResultRow& r : rows) {
        ASSERT_TRUE(r.ok()) << r.text("error");
        if (r.text("depth") == "base") {
            EXPECT_NEAR(r.num("depth_bias_mean"), sum / count, 1e-9);
            EXPECT_NEAR(r.num("cut_flip_frac"), r.num("cut") > c ? 1.0 : 0.0, 1e-12)
                << r.num("cut");
            base_err = r.num("depth_err_mean");
        } else {
            hit_err = r.num("depth_err_mean");
        }
    }
    // pom's own hit, reprojected in the tangent plane, is nearer the truth than the base's
    // depth on average (not exact: the plane is not the sphere)
    EXPECT_GT(base_err, 0.01);
    EXPECT_LT(hit_err, 0.5 * base_err);
}

TEST(CurvedBase, BadBasesAreRefused) {
    EXPECT_NE(
        parse_error(kHead + field("base = \"torus\"\nradius = 1\n") + kMethods).find("e.toml:"),
        std::string::npos);
    EXPECT_NE(parse_error(kHead + field("base = \"torus\"\nradius = 1\n") + kMethods)
                  .find("unknown base 'torus' (known: plane, cylinder, sphere)"),
              std::string::npos);
    EXPECT_NE(parse_error(kHead + field("base = \"cylinder\"\n") + kMethods).find("needs a radius"),
              std::string::npos);
    EXPECT_NE(
        parse_error(kHead + field("radius = 2\n") + kMethods).find("applies to a curved base"),
        std::string::npos);
    EXPECT_NE(parse_error(kHead + field("base = \"sphere\"\nradius = 0.04\n") + kMethods)
                  .find("must exceed scale * bias"),
              std::string::npos);
    EXPECT_NE(parse_error(kHead + field("base = \"sphere\"\nradius = -1\n") + kMethods)
                  .find("radius must be a finite number > 0"),
              std::string::npos);
    EXPECT_NE(parse_error(kHead + "[light]\ntheta_deg = 30\nphi_deg = 0\n" +
                          field("base = \"sphere\"\nradius = 1\n") + kMethods)
                  .find("[light] (true shadows) is not traced on a curved base"),
              std::string::npos);
}

// Issue 59, item 1: a radius over the precision bound R max(W, H) <= 2^30 cells is refused at
// the entry with the bound (it gave whole-texel errors with status ok at 1e15, and "lower theta
// or widen fov" at 1e300); just under the bound the rows are the plane's (the base is flat to
// 2^-31 texels there). The tracer refuses it too.
TEST(CurvedBase, RadiusOverThePrecisionBoundIsRefused) {
    for (const char* r : {"1e15", "1e300", "2e7"})
        for (const char* name : {"cylinder", "sphere"}) {
            const std::string err = parse_error(
                kHead + field(std::string("base = \"") + name + "\"\nradius = " + r + "\n") +
                kMethods);
            EXPECT_EQ(err.rfind("e.toml:11", 0), 0u) << err;  // the [[heightfields]] entry
            EXPECT_NE(err.find("precision bound R max(W, H) <= 2^30 cells"), std::string::npos)
                << err;
            EXPECT_NE(err.find("radius <= 1.68e+07 tiles here"), std::string::npos)
                << err;  // 2^30/64
        }
    const HeightField hf = generated_field("bricks", 64);
    const auto huge = make_base("sphere", 1e15);
    EXPECT_THROW(CurvedTracer(hf, 0.05, 1, *huge), std::invalid_argument);
    // a 32 x 32 field's bound is twice a 64 x 64 one's
    EXPECT_EQ(base_radius_problem("cylinder", 3.3e7, 32, 32), "");
    EXPECT_NE(base_radius_problem("cylinder", 3.4e7, 32, 32), "");
    EXPECT_EQ(base_radius_problem("plane", NAN, 1 << 14, 1 << 14), "");
    // just under the bound: the plane's rows (up to 40 degrees: at 70 the image's far pixels lie
    // tens of tiles away, where even this radius sags 10^-5 tiles)
    std::string head = kHead;
    head.replace(head.find("[0, 40, 70]"), 11, "[0, 20, 40]");
    const auto plane = run(head + field("") + kMethods);
    for (const char* name : {"cylinder", "sphere"}) {
        const auto curved =
            run(head + field(std::string("base = \"") + name + "\"\nradius = 1.6e7\n") + kMethods);
        ASSERT_EQ(plane.size(), curved.size());
        for (size_t i = 0; i < plane.size(); ++i) {
            ASSERT_TRUE(curved[i].ok()) << curved[i].text("error");
            EXPECT_NEAR(curved[i].num("err_mean"), plane[i].num("err_mean"),
                        1e-3 * plane[i].num("err_mean") + 1e-6)
                << name << " " << plane[i].text("method") << " theta " << plane[i].num("theta_deg");
            EXPECT_EQ(curved[i].num("samples_outside"), plane[i].num("samples_outside"));
        }
    }
}

// Issue 59, item 3: the curved walk's work is estimated before the run and bounded. A cylinder
// seen along its axis near grazing (4096^2, s 100, R 1000, theta 88.9, phi 90: hours a row) is
// refused at the entry with the estimate and the knobs; the estimate is the chord through the
// shell in quarter-texel steps (s / cos(theta) tiles on a nearly flat base), a lower bound of the
// walk's own steps; the walk stops at its budget.
TEST(CurvedBase, CurvedWalkIsEstimatedAndBounded) {
    const std::string err = parse_error(
        "samples = 256\ntiming_repeats = 0\nbackends = [\"cpu\"]\n[views]\ntheta_deg = [88.9]\n"
        "phi_deg = [90]\n[[heightfields]]\nname = \"f\"\ngenerator = \"fbm\"\nsize = 4096\n"
        "scale = 100\nbias = 1.0\nbase = \"cylinder\"\nradius = 1000\n" +
        kMethods);
    EXPECT_EQ(err.rfind("e.toml:7", 0), 0u) << err;
    EXPECT_NE(err.find("theta 88.9 phi 90: the curved truth's walk would take about 6.29e+12 steps "
                       "for the 65536 rays"),
              std::string::npos)
        << err;
    EXPECT_NE(err.find("kMaxCurvedWalkSteps"), std::string::npos) << err;
    EXPECT_NE(err.find("lower theta, the scale, the field's size or samples"), std::string::npos);

    // the estimate in closed form: 0.05 / cos 60 = 0.1 tiles in steps of 0.25 / 64 tiles
    const auto base = make_base("cylinder", 1e4);
    const OrthographicCamera cam(60, 0, 32);
    const CurvedWalkEstimate e = curved_walk_estimate(*base, 0.05, 1, 64, 64, cam, 32 * 32);
    EXPECT_NEAR(e.chord_max, 0.1, 1e-4);              // the cylinder bends 1e-5 over it
    EXPECT_NEAR(e.steps / (3.0 * 32 * 32), 26, 0.5);  // ceil(25.6) per ray, the check walk twice
    // the walk on a flat field takes at least as many steps (more as it nears the floor)
    const HeightField flat = generated_field("flat", 64);
    const CurvedView cv = curved_view(cam, *base, 0);
    const CurvedHits h = CurvedTracer(flat, 0.05, 1, *base).trace(cv.rays);
    EXPECT_GE(h.steps_mean, 25);
    EXPECT_LE(h.steps_mean, 26 + 64);
    // over its budget the walk stops and says so
    try {
        (void)CurvedTracer(flat, 0.05, 1, *base).trace(cv.rays, 5000);
        ADD_FAILURE() << "the walk did not stop at its budget";
    } catch (const CurvedWalkTooLong& x) {
        EXPECT_NE(std::string(x.what()).find("over its budget of 5e+03 steps"), std::string::npos)
            << x.what();
        EXPECT_GT(x.steps, 5000);
        EXPECT_LE(x.steps, 5000 + 4096.0 * 64);  // 4096 steps a thread at most
        EXPECT_EQ(x.budget, 5000);
    }
    // the walk counts every step of every ray: its total is what the budget is charged
    EXPECT_EQ(h.steps, h.steps_mean * double(cv.rays.size()));
    EXPECT_NO_THROW((void)CurvedTracer(flat, 0.05, 1, *base).trace(cv.rays, h.steps));
    EXPECT_THROW((void)CurvedTracer(flat, 0.05, 1, *base).trace(cv.rays, h.steps - 1),
                 CurvedWalkTooLong);
}

// Issue 59, item 3, the 4-ray case: the same grazing cylinder with 2 x 2 samples passed the
// estimate under the old limit (2^32; about 1e9 steps) and then walked for minutes on one
// thread. Under kMaxCurvedWalkSteps = 2^28 (a view's work, both walks) it is refused when the
// experiment is read, at the field's entry, naming the estimate, the limit and the knobs; a
// quarter of the scale passes (about 2.6e8 steps).
TEST(CurvedBase, GrazingCylinderWithFourRaysIsRefusedBeforeTheRun) {
    auto toml = [](const std::string& samples, const std::string& scale) {
        return "samples = " + samples +
               "\ntiming_repeats = 0\nbackends = [\"cpu\"]\n[views]\ntheta_deg = [88.9]\n"
               "phi_deg = [90]\n[[heightfields]]\nname = \"f\"\ngenerator = \"fbm\"\n"
               "size = 4096\nscale = " +
               scale + "\nbias = 1.0\nbase = \"cylinder\"\nradius = 1000\n" + kMethods;
    };
    const std::string err = parse_error(toml("2", "100"));
    EXPECT_EQ(err.rfind("e.toml:7: heightfield 'f' (base cylinder radius 1000, s = 100) at theta "
                        "88.9 phi 90: the curved truth's walk would take about 5.1",
                        0),
              0u)
        << err;
    EXPECT_NE(err.find("e+08 steps for the 4 rays of this view"), std::string::npos) << err;
    EXPECT_NE(err.find("the check walk at half the step on one ray in 16 (truth_check = "
                       "\"subset\"): 1.5 walks"),
              std::string::npos)
        << err;
    EXPECT_NE(err.find("over the limit of 2^28 = 2.68e+08 steps a view (kMaxCurvedWalkSteps"),
              std::string::npos)
        << err;
    EXPECT_NE(err.find("lower theta, the scale, the field's size or samples"), std::string::npos)
        << err;
    EXPECT_EQ(err.find('\n'), std::string::npos) << err;  // one line
    // the estimate for these 4 rays, and for a quarter of the scale (under the limit)
    const auto base = make_base("cylinder", 1000);
    const OrthographicCamera cam(88.9, 90, 2);
    const CurvedWalkEstimate e = curved_walk_estimate(*base, 100, 1, 4096, 4096, cam, 4);
    EXPECT_GT(e.steps, kMaxCurvedWalkSteps);
    EXPECT_NEAR(e.chord_max, 100 / std::cos(88.9 * M_PI / 180), 100);  // about 5200 tiles
    EXPECT_EQ(e.steps, 3 * e.walk_steps);
    EXPECT_LT(curved_walk_estimate(*base, 25, 1, 4096, 4096, cam, 4).steps, kMaxCurvedWalkSteps);
}

// Issue 59, item 3, during the run: a view the estimate lets through whose walks take far more
// steps than it (a cliff one texel wide over a floor: the steps shrink as g / L all the way down
// to the floor, L = 1 + 2 s |grad h| = 1 + 2 s 1024 per tile; 6755 steps a ray against the
// estimate's 1180) stops once both walks together pass 2^28 steps, and the run is refused at the
// field's entry with the count, the limit and the knobs, never a walk of unbounded length (the
// old budget, 2^32 for each walk, let it run to its end). About 2^28 steps of work: 10 to 25 s
// on 2 cores, hence a suite of its own labelled slow. The check walk takes every ray here
// (truth_check = "all"): on its default subset the view stays within its budget.
TEST(CurvedBudget, WalkOverItsBudgetStopsTheRun) {
    const std::string toml =
        "samples = 192\ntiming_repeats = 0\nbackends = [\"cpu\"]\ntruth_check = \"all\"\n"
        "[views]\ntheta_deg = [80]\nphi_deg = [90]\n[[heightfields]]\nname = \"f\"\n"
        "generator = \"step\"\nsize = 1024\n"
        "scale = 0.05\nbias = 1.0\nbase = \"cylinder\"\nradius = 1000\n[[methods]]\n"
        "name = \"parallax\"\n";
    const Experiment ex = parse_experiment(toml, "e.toml");  // within the estimate
    const auto base = make_base("cylinder", 1000);
    const CurvedWalkEstimate e = curved_walk_estimate(*base, 0.05, 1, 1024, 1024,
                                                      OrthographicCamera(80, 90, 192), 192 * 192);
    EXPECT_LT(e.steps, 0.5 * kMaxCurvedWalkSteps);
    try {
        (void)run_experiment(ex, {});
        ADD_FAILURE() << "the walks did not stop at the view's budget";
    } catch (const InputError& x) {
        const std::string err = x.what();
        const std::string head =
            "e.toml:8: heightfield 'f' (base cylinder radius 1000) at theta 80 phi 90: the curved "
            "truth's walk stopped after ";
        ASSERT_EQ(err.rfind(head, 0), 0u) << err;
        const double steps = std::stod(err.substr(head.size()));
        EXPECT_GT(steps, kMaxCurvedWalkSteps) << err;
        EXPECT_LE(steps, kMaxCurvedWalkSteps + 4096.0 * 256) << err;  // 4096 a thread at most
        EXPECT_NE(err.find("steps for the 36864 rays of this view (the walk and its check "
                           "together), over the limit of 2^28 steps a view (kMaxCurvedWalkSteps"),
                  std::string::npos)
            << err;
        EXPECT_NE(err.find("lower theta, the scale, the field's size or samples"),
                  std::string::npos)
            << err;
        EXPECT_EQ(err.find('\n'), std::string::npos) << err;
    }
}

// Issue 59, item 8: a curved view where no pixel is covered by both the method and the truth
// fails its rows with the reason, never an ok row of empty error columns. A sphere of radius
// 0.01 between the rays of a 64^2 grid at theta 0 (the nearest pass 0.011 from its axis) under a
// flat relief standing 0.002 above it (b = 0): 4 rays meet the relief and none the base, so the
// truth shows surface at 4 pixels and the method at none (cover_missing_frac 1).
TEST(CurvedBase, NothingCoveredByBothFailsTheRow) {
    const auto rows =
        run("samples = 64\ntiming_repeats = 0\nbackends = [\"cpu\"]\n[views]\ntheta_deg = [0]\n"
            "[[heightfields]]\nname = \"flat\"\ngenerator = \"flat\"\nlevel = 1.0\nsize = 64\n"
            "scale = 0.002\nbias = 0.0\nbase = \"sphere\"\nradius = 0.01\n" +
            kMethods);
    ASSERT_EQ(rows.size(), 3u);
    for (const ResultRow& r : rows) {
        EXPECT_FALSE(r.ok()) << r.text("method");
        EXPECT_NE(r.text("error").find("no pixel is covered by both the method and the truth "
                                       "(cover_extra_frac 0, cover_missing_frac 1, "
                                       "samples_outside 4092 of 4096)"),
                  std::string::npos)
            << r.text("error");
    }
}

// Issue 59, item 9: ground_truth = "embree" on a curved base is refused at its key (the rows
// would say embree while their numbers are the curved walk's); "exact" stays.
TEST(CurvedBase, EmbreeGroundTruthOnACurvedBaseIsRefused) {
    const std::string err = parse_error("ground_truth = \"embree\"\n" + kHead +
                                        field("base = \"sphere\"\nradius = 1\n") + kMethods);
    EXPECT_EQ(err.rfind("e.toml:1", 0), 0u) << err;
    EXPECT_NE(err.find("ground_truth = \"embree\" does not apply to heightfield 'f'"),
              std::string::npos)
        << err;
    EXPECT_EQ(parse_error("ground_truth = \"exact\"\n" + kHead +
                          field("base = \"sphere\"\nradius = 1\n") + kMethods),
              "(no error)");
    EXPECT_EQ(parse_error("ground_truth = \"embree\"\n" + kHead + field("") + kMethods),
              "(no error)");  // the plane keeps Embree
}

}  // namespace
}  // namespace pxh
