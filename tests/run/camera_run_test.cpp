// Runs through a camera (docs/conventions.md section 10): the perspective camera's keys read
// and checked by the camera, its settings swept between phi and theta, outside pixels counted
// and left out, the pixel error and lambda in closed form under the orthographic grid, the
// texture levels' `level` mode where it must equal `base`, and the limits of s -> 0 and of a
// far eye.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "harness/backends/cpu_backend.h"
#include "harness/core/error.h"
#include "harness/experiment/experiment.h"
#include "harness/run/runner.h"
#include "harness/scene/perspective_camera.h"
#include "heightfields/heightfields.h"
#include "tests/test_util.h"

namespace pxh {
namespace {

using test::parse_error;
using test::run;

std::string experiment(const std::string& views, const std::string& methods,
                       const std::string& field = "fbm", double scale = 0.05, int size = 64,
                       int samples = 32) {
    return "samples = " + std::to_string(samples) +
           "\ntiming_repeats = 0\nbackends = [\"cpu\"]\n[views]\n" + views +
           "\n[[heightfields]]\nname = \"f\"\ngenerator = \"" + field +
           "\"\nwidth = " + std::to_string(size) + "\nheight = " + std::to_string(size) +
           "\nscale = " + format_number(scale) + "\n" + methods;
}

const std::string kPom = "[[methods]]\nname = \"pom\"\nlayers = 16\n";

TEST(CameraRun, OrthographicRowsCarryTheClosedForms) {
    // Field 64, samples 32: lambda = log2(64 / 32) = 1 on every sample; one pixel step is 2
    // texels, so the pixel error is the texel error / 2, sample by sample.
    const auto rows = run(experiment("theta_deg = [60]", kPom));
    ASSERT_EQ(rows.size(), 1u);
    const ResultRow& r = rows[0];
    ASSERT_TRUE(r.ok()) << r.text("error");
    EXPECT_EQ(r.text("camera"), "orthographic");
    EXPECT_EQ(r.text("lod"), "base");
    EXPECT_TRUE(std::isnan(r.num("distance")));
    EXPECT_TRUE(std::isnan(r.num("fov_deg")));
    EXPECT_EQ(r.num("samples_outside"), 0);
    EXPECT_EQ(r.num("lod_mean"), 1.0);
    EXPECT_NEAR(r.num("err_px_mean"), r.num("err_mean") / 2, 1e-12 * r.num("err_mean"));
    EXPECT_NEAR(r.num("err_px_max"), r.num("err_max") / 2, 1e-12 * r.num("err_max"));
    EXPECT_NEAR(r.num("err_px_p50"), r.num("err_p50") / 2, 1e-12 * r.num("err_p50"));
    // More samples than texels: lambda < 0, lod_mean counts max(lambda, 0).
    const auto fine = run(experiment("theta_deg = [60]", kPom, "fbm", 0.05, 16, 64));
    EXPECT_EQ(fine[0].num("lod_mean"), 0.0);
    EXPECT_NEAR(fine[0].num("err_px_mean"), fine[0].num("err_mean") * 4,
                1e-12 * fine[0].num("err_mean"));
}

TEST(CameraRun, PerspectiveKeysAreTheCamerasOwn) {
    const std::string m = kPom;
    EXPECT_EQ(parse_error(experiment("theta_deg = [60]\ncamera = \"perspective\"", m)),
              "e.toml:4: camera 'perspective' needs distance (the eye's distance from the "
              "look-at point, in tiles: a value, a list or { from, to, step })");
    EXPECT_EQ(parse_error(
                  experiment("theta_deg = [60]\ncamera = \"perspective\"\ndistance = [2, -1]", m)),
              "e.toml:7: distance = -1 is not a positive number of tiles");
    EXPECT_EQ(parse_error(experiment(
                  "theta_deg = [60]\ncamera = \"perspective\"\ndistance = 2\nfov_deg = 180", m)),
              "e.toml:8: fov_deg = 180 is impossible: the full field of view lies in (0, 180)");
    const std::string typo = parse_error(
        experiment("theta_deg = [60]\ncamera = \"perspective\"\ndistance = 2\nfov = 30", m));
    EXPECT_EQ(typo.rfind("e.toml:8: unknown key 'fov' in [views] (known: ", 0), 0u) << typo;
    EXPECT_NE(typo.find("camera 'perspective' reads"), std::string::npos) << typo;
    EXPECT_NE(typo.find("fov_deg"), std::string::npos) << typo;
    // The orthographic camera reads none of them.
    const std::string ortho = parse_error(experiment("theta_deg = [60]\ndistance = 2", m));
    EXPECT_EQ(ortho.rfind("e.toml:6: unknown key 'distance' in [views]", 0), 0u) << ortho;
}

TEST(CameraRun, AnEyeInsideTheSlabIsRefused) {
    // s (1 - b) = 0.5 with b = 0.5; D cos 60 = 0.9 cos 60 = 0.45 < 0.5.
    std::string toml = experiment("theta_deg = [0, 60]\ncamera = \"perspective\"\ndistance = 0.9",
                                  kPom, "fbm", 1.0);
    toml.replace(toml.find("scale = 1"), 9, "scale = 1\nbias = 0.5");
    const std::string err = parse_error(toml);
    EXPECT_EQ(err.rfind("e.toml:7: heightfield 'f' (s = 1, b = 0.5): the eye is not above the "
                        "slab: distance 0.9 at theta 60",
                        0),
              0u)
        << err;
}

TEST(CameraRun, LodModesAreCheckedWhereTheyAreGiven) {
    const std::string v = "theta_deg = [60]";
    EXPECT_EQ(parse_error(experiment(v, kPom + "lod = \"mip\"\n")),
              "e.toml:15: unknown lod 'mip' (known: base, level, grad, implicit)");
    EXPECT_EQ(parse_error(experiment(v, "[[methods]]\nname = \"maxmip\"\nlod = \"level\"\n")),
              "e.toml:14: method 'maxmip' reads precomputed maps that keep their own levels "
              "(docs/conventions.md section 10): its lod is 'base' only");
    EXPECT_EQ(parse_error(experiment(v, kPom + "lod = [\"grad\"]\n")),
              "e.toml:15: lod 'grad' samples through the GPU's own level selection and runs on "
              "the glsl backend only; the experiment's backends are cpu");
}

// Outside pixels from the geometry alone: pixel (i, j) at x = 2 (i + 0.5) / N - 1,
// y = 2 (j + 0.5) / N - 1 has d = f + a x r + a y w with d.z = -cos t + a y sin t (r.z = 0)
// and |d|^2 = 1 + a^2 (x^2 + y^2) (f, r, w orthonormal); it is outside when -d.z / |d| <= cos 89.
size_t predicted_outside(double theta_deg, double fov_deg, int n) {
    const double t = theta_deg * M_PI / 180, a = std::tan(fov_deg * M_PI / 360);
    size_t count = 0;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const double x = 2 * (i + 0.5) / n - 1, y = 2 * (j + 0.5) / n - 1;
            const double dz = -std::cos(t) + a * y * std::sin(t);
            count += -dz / std::sqrt(1 + a * a * (x * x + y * y)) <= std::cos(89 * M_PI / 180);
        }
    return count;
}

TEST(CameraRun, DistanceSweepsBetweenPhiAndThetaAndCountsTheOutside) {
    const auto rows =
        run(experiment("theta_deg = [45, 80]\ncamera = \"perspective\"\ndistance = [1.5, 4]\n"
                       "fov_deg = 60",
                       kPom + "[[methods]]\nname = \"parallax\"\n"));
    ASSERT_EQ(rows.size(), 8u);  // 2 distances x 2 theta x 2 methods, distance outer
    const double want_d[] = {1.5, 1.5, 1.5, 1.5, 4, 4, 4, 4};
    const double want_t[] = {45, 45, 80, 80, 45, 45, 80, 80};
    for (size_t i = 0; i < rows.size(); ++i) {
        const ResultRow& r = rows[i];
        ASSERT_TRUE(r.ok()) << r.text("error");
        EXPECT_EQ(r.text("camera"), "perspective");
        EXPECT_EQ(r.num("distance"), want_d[i]) << i;
        EXPECT_EQ(r.num("theta_deg"), want_t[i]) << i;
        EXPECT_EQ(r.num("fov_deg"), 60);
        EXPECT_EQ(r.num("samples_outside"), double(predicted_outside(want_t[i], 60, 32))) << i;
        EXPECT_GT(r.num("lod_mean"), 0);
        EXPECT_TRUE(std::isfinite(r.num("err_px_mean")));
        // Sliding pairs consecutive theta at one distance: the theta-45 rows have it, the last
        // theta of each distance has none.
        EXPECT_EQ(std::isnan(r.num("sliding")), want_t[i] == 80) << i;
    }
    EXPECT_GT(rows[2].num("samples_outside"), 0);  // 80 degrees, fov 60: past the horizon
    EXPECT_EQ(rows[0].num("samples_outside"), 0);
    // Farther away, a pixel covers more texels.
    EXPECT_GT(rows[4].num("lod_mean"), rows[0].num("lod_mean"));
}

TEST(CameraRun, VanishingReliefIsExactUnderPerspective) {
    // s -> 0 (1e-6, the smallest scale accepted): the surface is the plane z = 0 and every
    // method returns the sample itself, to s tan(85 deg) W = 7e-4 texel at the most grazing pixel.
    const std::string methods = kPom +
                                "[[methods]]\nname = \"parallax\"\n[[methods]]\nname = "
                                "\"steep\"\n[[methods]]\nname = \"relief\"\n";
    const auto rows = run(experiment(
        "theta_deg = [30, 60]\ncamera = \"perspective\"\ndistance = [1.2, 3]\nfov_deg = 50",
        methods, "fbm", 1e-6));
    ASSERT_EQ(rows.size(), 16u);
    for (const ResultRow& r : rows) {
        ASSERT_TRUE(r.ok()) << r.text("error");
        EXPECT_LT(r.num("err_max"), 1e-3) << r.text("method") << " theta " << r.num("theta_deg");
        EXPECT_LT(r.num("err_px_max"), 1e-3) << r.text("method");
    }
}

TEST(CameraRun, LevelEqualsBaseWhereTheLevelsDoNotDiffer) {
    // A constant field has the same texels on every level; on the orthographic grid with as
    // many samples as texels lambda = 0 and a level fetch is the level-0 fetch: bit for bit.
    const std::string m = kPom + "lod = [\"base\", \"level\"]\n";
    for (const auto& [toml, what] :
         {std::pair{experiment("theta_deg = [60]\ncamera = \"perspective\"\ndistance = 3", m,
                               "flat", 0.05),
                    "constant field"},
          std::pair{experiment("theta_deg = [60]", m, "fbm", 0.05, 32, 32), "lambda = 0"}}) {
        const auto rows = run(toml);
        ASSERT_EQ(rows.size(), 2u) << what;
        EXPECT_EQ(rows[0].text("lod"), "base");
        EXPECT_EQ(rows[1].text("lod"), "level");
        for (const char* c : {"err_mean", "err_max", "err_px_mean", "fetches_mean"})
            EXPECT_EQ(rows[0].num(c), rows[1].num(c)) << what << " " << c;
    }
    // On fbm seen from afar the levels do differ, and so do the rows.
    const auto far = run(experiment("theta_deg = [60]\ncamera = \"perspective\"\ndistance = 6", m));
    EXPECT_NE(far[0].num("err_mean"), far[1].num("err_mean"));
}

TEST(CameraRun, AFarEyeLooksAlongOneDirection) {
    // D -> infinity with the image kept one tile wide: every pixel's V tends to the look-at
    // direction, so a method fed each pixel's own V tends to the same method fed V0 at every
    // sample (what the orthographic camera does), with the gap shrinking like 1 / D.
    const HeightField hf =
        generate_heightfield(*find_generator("fbm"), 64, 64,
                             resolve_params(find_generator("fbm")->params, {}, "t", "t"));
    const MethodInfo& info = test::method("pom");
    const MethodSpec pom{&info, test::params_for(info, {{"layers", ParamValue(16.0)}})};
    double prev = INFINITY;
    for (double D : {10.0, 100.0, 1000.0, 10000.0}) {
        PerspectiveParams p{60, 30, D, 2 * std::atan(0.5 / D) * 180 / M_PI, 24};
        const View v = PerspectiveCamera(p).view();
        const Scene<double> sc{0.05, 1.0, view_vector(60, 30), 64, 64};
        const MethodOutput own = run_cpu(pom, "double", sc, hf, v.P, 0, nullptr, &v.V);
        const MethodOutput along = run_cpu(pom, "double", sc, hf, v.P, 0, nullptr, nullptr);
        double gap = 0;
        for (size_t k = 0; k < v.size(); ++k)
            gap = std::max(
                gap, std::hypot(own.uv[k].x - along.uv[k].x, own.uv[k].y - along.uv[k].y) * 64);
        EXPECT_LT(gap, prev / 5) << "D " << D;  // at least 5x smaller per decade
        prev = gap;
    }
    EXPECT_LT(prev, 1e-3);
}

}  // namespace
}  // namespace pxh
