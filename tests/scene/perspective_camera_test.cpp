// The perspective camera and pixel footprints (docs/conventions.md section 10): samples and view
// vectors against the parallel-projection limit, the closed-form footprint against finite
// differences, the outside count against the angles of the pixel rows, the eye/slab check.
#include "harness/scene/perspective_camera.h"

#include <gtest/gtest.h>

#include <cmath>

#include "harness/core/error.h"

namespace pxh {
namespace {

constexpr double kDeg = M_PI / 180.0;

PerspectiveParams params(double theta, double phi, double distance, double fov, int n) {
    return {theta, phi, distance, fov, n};
}

double len2(Vec2d v) { return std::sqrt(v.x * v.x + v.y * v.y); }
double len3(Vec3d v) { return std::sqrt(v.x * v.x + v.y * v.y + v.z * v.z); }
Vec3d sub(Vec3d a, Vec3d b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
double dot(Vec3d a, Vec3d b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

TEST(PerspectiveCamera, BasisIsRightHandedAndLooksAtTheCentre) {
    const PerspectiveCamera cam(params(63, 211, 2.5, 45, 9));
    const Vec3d V0 = view_vector(63, 211), E = cam.eye();
    EXPECT_NEAR(E.x, 0.5 + 2.5 * V0.x, 1e-15);
    EXPECT_NEAR(E.y, 0.5 + 2.5 * V0.y, 1e-15);
    EXPECT_NEAR(E.z, 2.5 * V0.z, 1e-15);
    const Vec3d f = cam.forward(), r = cam.right(), w = cam.up();
    // r x f = w, orthonormal.
    EXPECT_NEAR(r.y * f.z - r.z * f.y, w.x, 1e-15);
    EXPECT_NEAR(r.z * f.x - r.x * f.z, w.y, 1e-15);
    EXPECT_NEAR(r.x * f.y - r.y * f.x, w.z, 1e-15);
    EXPECT_NEAR(dot(r, w), 0, 1e-15);
    EXPECT_NEAR(dot(r, f), 0, 1e-15);
    EXPECT_NEAR(dot(w, f), 0, 1e-15);
    EXPECT_NEAR(len3(w), 1, 1e-15);
    // The centre pixel of an odd image is the look-at ray.
    const PerspectivePixel c = cam.pixel(4, 4);
    EXPECT_NEAR(c.P.x, 0.5, 1e-14);
    EXPECT_NEAR(c.P.y, 0.5, 1e-14);
    EXPECT_NEAR(c.V.x, V0.x, 1e-15);
    EXPECT_NEAR(c.V.z, V0.z, 1e-15);
    EXPECT_TRUE(c.inside);
    EXPECT_NEAR(cam.half_tan(), std::tan(22.5 * kDeg), 1e-15);
}

TEST(PerspectiveCamera, EverySampleLiesOnItsRayThroughTheEye) {
    const PerspectiveCamera cam(params(72, 40, 1.5, 60, 24));
    const View v = cam.view();
    const std::vector<uint8_t> in = cam.inside();
    ASSERT_EQ(v.size(), 24u * 24u);
    ASSERT_EQ(v.V.size(), v.P.size());
    EXPECT_FALSE(v.parallel);
    EXPECT_EQ(v.grid, 0);
    EXPECT_EQ(view_problem(v), "");
    const Vec3d E = cam.eye();
    size_t inside = 0;
    for (int j = 0; j < 24; ++j)
        for (int i = 0; i < 24; ++i) {
            const size_t k = size_t(j) * 24 + i;
            if (!in[k]) {
                // The placeholder of an outside sample: the look-at ray.
                EXPECT_EQ(v.P[k].x, 0.5);
                EXPECT_EQ(v.V[k].z, view_vector(72, 40).z);
                continue;
            }
            ++inside;
            const Vec3d P{v.P[k].x, v.P[k].y, 0.0}, V = v.V[k];
            EXPECT_NEAR(len3(V), 1, 1e-15);
            EXPECT_GT(V.z, std::cos(89 * kDeg));
            // E = P + |E - P| V: the sample is where the pixel's ray from the eye meets z = 0.
            const double t = len3(sub(E, P));
            EXPECT_NEAR(P.x + t * V.x, E.x, 1e-12);
            EXPECT_NEAR(P.y + t * V.y, E.y, 1e-12);
            EXPECT_NEAR(t * V.z, E.z, 1e-12);
            // Columns grow to the right, rows upward (toward the horizon: farther from the eye).
            const Vec3d to_p = sub(P, E);
            const double xr = dot(to_p, cam.right()) / dot(to_p, cam.forward());
            const double yw = dot(to_p, cam.up()) / dot(to_p, cam.forward());
            EXPECT_NEAR(xr, cam.half_tan() * (2 * (i + 0.5) / 24 - 1), 1e-12);
            EXPECT_NEAR(yw, cam.half_tan() * (2 * (j + 0.5) / 24 - 1), 1e-12);
        }
    EXPECT_EQ(inside + cam.outside_count(), v.size());
    EXPECT_GT(inside, 0u);
}

// Far eye, tiny field of view, the image D tan(F/2) = h tiles half-wide at the look-at point:
// the pinhole tends to the parallel projection of the same pixel grid along V0,
//   P_lim(i, j) = C + h x r + h y (-cos phi, -sin phi) / cos theta,   V -> V0,
// with an error that falls as 1/D.
TEST(PerspectiveCamera, FarEyeTinyFovConvergesToTheParallelProjection) {
    const double theta = 60, phi = 30, h = 0.5;
    const int n = 16;
    const double ct = std::cos(theta * kDeg), cp = std::cos(phi * kDeg), sp = std::sin(phi * kDeg);
    const Vec3d V0 = view_vector(theta, phi);
    double prev_p = 0, prev_v = 0;
    for (double D : {1e2, 1e3, 1e4, 1e5}) {
        const double fov = 2 * std::atan(h / D) / kDeg;
        const PerspectiveCamera cam(params(theta, phi, D, fov, n));
        const View v = cam.view();
        double err_p = 0, err_v = 0;
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                const size_t k = size_t(j) * n + i;
                const double x = 2 * (i + 0.5) / n - 1, y = 2 * (j + 0.5) / n - 1;
                const Vec2d lim{0.5 + h * x * -sp + h * y * -cp / ct,
                                0.5 + h * x * cp + h * y * -sp / ct};
                err_p = std::max(err_p, len2({v.P[k].x - lim.x, v.P[k].y - lim.y}));
                err_v = std::max(err_v, len3(sub(v.V[k], V0)));
            }
        EXPECT_EQ(cam.outside_count(), 0u);
        // |V - V0| <= the corner's angle, sqrt(2) h / D. P - C = (P_lim - C) / (1 - eps) with
        // eps = h y tan(theta) / D, so |P - P_lim| <= |P_lim - C| eps / (1 - eps), at most
        // h sqrt(1 + 1 / cos^2 theta) h tan(theta) / D / (1 - eps).
        const double eps = h * std::tan(theta * kDeg) / D;
        EXPECT_LE(err_v, std::sqrt(2.0) * h / D) << D;
        EXPECT_LE(err_p, h * std::sqrt(1 + 1 / (ct * ct)) * eps / (1 - eps)) << D;
        if (prev_p > 0) {
            EXPECT_NEAR(prev_p / err_p, 10, 0.5) << D;  // first order in 1/D
            EXPECT_NEAR(prev_v / err_v, 10, 0.5) << D;
        }
        prev_p = err_p;
        prev_v = err_v;
    }
}

// Looking straight down with the image's columns along +u (phi = 270) and D tan(F/2) = 0.5, the
// samples are the N x N grid of section 3 at any distance.
TEST(PerspectiveCamera, AtTheNadirTheSamplesAreTheGrid) {
    const int n = 12;
    const std::vector<Vec2d> grid = sample_grid(n);
    for (double D : {0.8, 1.5, 40.0}) {
        const double fov = 2 * std::atan(0.5 / D) / kDeg;
        const View v = PerspectiveCamera(params(0, 270, D, fov, n)).view();
        for (size_t k = 0; k < grid.size(); ++k) {
            EXPECT_NEAR(v.P[k].x, grid[k].x, 1e-14) << D << " " << k;
            EXPECT_NEAR(v.P[k].y, grid[k].y, 1e-14) << D << " " << k;
        }
    }
}

// P is linear in i (r.z = 0), so the central difference over one column is J.dPdi up to
// rounding. Along j, P = A + B / (u + c y) with u = d.z, c = a w.z and y = 2 (j + 0.5) / N - 1;
// the central difference over one row is exactly f'(y) / (1 - q^2), q = c (2 / N) / d.z, so it
// is compared with dPdj / (1 - q^2). Both to 1e-9 relative: the differences of P lose
// about |P| / |J| of 1e-16 (|P| at most tens of tiles, |J| above 1e-3 tile here).
TEST(Footprint, ClosedFormEqualsFiniteDifferencesInTheInterior) {
    struct Case {
        double theta, phi, D, fov;
        int n;
    };
    for (const Case c : {Case{45, 0, 1.5, 60, 32}, Case{70, 123, 4, 45, 48},
                         Case{80, -30, 10, 30, 40}, Case{20, 200, 0.7, 90, 17}}) {
        const PerspectiveCamera cam(params(c.theta, c.phi, c.D, c.fov, c.n));
        const double a = cam.half_tan(), wz = cam.up().z;
        int checked = 0;
        for (int j = 1; j + 1 < c.n; ++j)
            for (int i = 1; i + 1 < c.n; ++i) {
                if (!cam.pixel(i, j).inside || !cam.pixel(i, j + 1).inside ||
                    !cam.pixel(i, j - 1).inside || !cam.pixel(i - 1, j).inside ||
                    !cam.pixel(i + 1, j).inside)
                    continue;
                const Footprint J = cam.footprint(i, j);
                const Vec2d pl = cam.pixel(i - 1, j).P, pr = cam.pixel(i + 1, j).P;
                const Vec2d pd = cam.pixel(i, j - 1).P, pu = cam.pixel(i, j + 1).P;
                const Vec2d fdi{(pr.x - pl.x) / 2, (pr.y - pl.y) / 2};
                const Vec2d fdj{(pu.x - pd.x) / 2, (pu.y - pd.y) / 2};
                const double q = a * wz * (2.0 / c.n) / cam.pixel(i, j).d.z;
                const double gain = 1 / (1 - q * q);
                const double tol_i = 1e-9 * len2(J.dPdi), tol_j = 1e-9 * len2(J.dPdj) * gain;
                EXPECT_NEAR(fdi.x, J.dPdi.x, tol_i) << i << " " << j;
                EXPECT_NEAR(fdi.y, J.dPdi.y, tol_i) << i << " " << j;
                EXPECT_NEAR(fdj.x, J.dPdj.x * gain, tol_j) << i << " " << j;
                EXPECT_NEAR(fdj.y, J.dPdj.y * gain, tol_j) << i << " " << j;
                // A small step (1e-3 pixel): relative truncation (q / 1000)^2 < 1e-6 at most,
                // rounding |P| 1e-16 / 1e-3 / |J| below 1e-7.
                const double e = 1e-3;
                const Vec2d su = cam.pixel(i, j + e).P, sd = cam.pixel(i, j - e).P;
                EXPECT_NEAR((su.x - sd.x) / (2 * e), J.dPdj.x, 1e-6 * len2(J.dPdj));
                EXPECT_NEAR((su.y - sd.y) / (2 * e), J.dPdj.y, 1e-6 * len2(J.dPdj));
                ++checked;
            }
        EXPECT_GT(checked, (c.n - 2) * (c.n - 2) / 3) << c.theta;
    }
}

// At the centre ray d = f: |dP/di| = 2 a D / N across, |dP/dj| = 2 a D / (N cos theta) along
// the tilt, so rho = W 2 a D / (N cos theta) for a square field.
TEST(Footprint, CentrePixelInClosedForm) {
    const double theta = 55, D = 3, fov = 40;
    const int n = 21, W = 512;
    const PerspectiveCamera cam(params(theta, 17, D, fov, n));
    const Footprint J = cam.footprint(10, 10);
    const double a = std::tan(20 * kDeg), ct = std::cos(theta * kDeg);
    EXPECT_NEAR(len2(J.dPdi), 2 * a * D / n, 1e-14);
    EXPECT_NEAR(len2(J.dPdj), 2 * a * D / (n * ct), 1e-14);
    EXPECT_NEAR(J.dPdi.x * J.dPdj.x + J.dPdi.y * J.dPdj.y, 0, 1e-14);  // r is horizontal
    EXPECT_NEAR(footprint_scale(J, W, W), W * 2 * a * D / (n * ct), 1e-10);
    EXPECT_NEAR(footprint_lod(J, W, W), std::log2(W * 2 * a * D / (n * ct)), 1e-13);
}

// d does not depend on D and J is proportional to E.z = D cos theta: doubling the distance
// doubles every footprint, one level more at every pixel.
TEST(Footprint, DoublingTheDistanceAddsOneLevelEverywhere) {
    const int W = 1024, H = 256;
    const PerspectiveCamera cam_d(params(65, 10, 1.5, 50, 32)), cam_2d(params(65, 10, 3, 50, 32));
    const std::vector<double> a = sample_lods(cam_d.footprints(), W, H);
    const std::vector<double> b = sample_lods(cam_2d.footprints(), W, H);
    const std::vector<uint8_t> in = cam_d.inside();
    ASSERT_EQ(a.size(), 32u * 32u);
    for (size_t k = 0; k < a.size(); ++k) {
        if (!in[k]) continue;
        EXPECT_NEAR(b[k] - a[k], 1.0, 1e-12) << k;
        EXPECT_EQ(a[k], footprint_lod(cam_d.footprint(double(k % 32), double(k / 32)), W, H));
    }
    // Farther up the image (toward the horizon) a pixel covers more texture.
    EXPECT_GT(a[31 * 32 + 16], a[16 * 32 + 16]);
    EXPECT_GT(a[16 * 32 + 16], a[0 * 32 + 16]);
}

TEST(Footprint, LodUnderTheOrthographicGridIsLog2OfTexelsPerSample) {
    struct Case {
        int W, H, n;
        double lod;
    };
    for (const Case c : {Case{512, 512, 256, 1}, Case{1024, 256, 256, 2}, Case{256, 1024, 256, 2},
                         Case{256, 256, 1024, -2}, Case{64, 64, 64, 0}, Case{4096, 8, 16, 8}}) {
        const Footprint J = orthographic_footprint(c.n);
        EXPECT_EQ(J.dPdi.y, 0.0);
        EXPECT_EQ(J.dPdj.x, 0.0);
        EXPECT_EQ(footprint_lod(J, c.W, c.H), c.lod) << c.W << "x" << c.H << " N=" << c.n;
        EXPECT_EQ(footprint_lod(J, c.W, c.H), std::log2(double(std::max(c.W, c.H)) / c.n));
    }
    // Other sizes: 1/N is rounded once, so rho = W (1/N) is within one ulp of W / N.
    for (const Case c : {Case{300, 200, 256, 0}, Case{640, 480, 300, 0}, Case{97, 101, 7, 0}}) {
        const double want = std::log2(double(std::max(c.W, c.H)) / c.n);
        EXPECT_NEAR(footprint_lod(orthographic_footprint(c.n), c.W, c.H), want, 1e-15);
    }
}

TEST(Footprint, PixelErrorCountsScreenPixels) {
    // Orthographic: |e_uv| N.
    EXPECT_NEAR(pixel_error(orthographic_footprint(200), {0.003, -0.004}), 1.0, 1e-13);
    // Perspective: an error of (2.5 columns, -1.5 rows) is sqrt(2.5^2 + 1.5^2) pixels.
    const PerspectiveCamera cam(params(75, 300, 2, 50, 64));
    const Footprint J = cam.footprint(20, 30);
    const Vec2d e{2.5 * J.dPdi.x - 1.5 * J.dPdj.x, 2.5 * J.dPdi.y - 1.5 * J.dPdj.y};
    EXPECT_NEAR(pixel_error(J, e), std::sqrt(2.5 * 2.5 + 1.5 * 1.5), 1e-12);
    EXPECT_TRUE(std::isnan(pixel_error(Footprint{{1, 2}, {2, 4}}, {0.1, 0.1})));  // singular
    EXPECT_TRUE(std::isnan(pixel_error(J, {NAN, 0.0})));
}

// Independent of the camera's vectors: row j's central ray points atan(a y_j) above the optical
// axis, which is 90 - theta below the horizon, so it descends at dep_j = 90 - theta - atan(a y_j)
// degrees. The row's rays lie in the plane through that ray and the horizontal r; the ray of
// column i is gamma = atan(a x_i / sqrt(1 + a^2 y_j^2)) off the row's central ray within that
// plane, so its V.z = sin(dep_j) cos(gamma). Outside: V.z <= cos(89 degrees).
size_t outside_from_row_angles(double theta, double fov, int n, double* margin) {
    const double a = std::tan(0.5 * fov * kDeg), c89 = std::cos(89 * kDeg);
    size_t count = 0;
    *margin = 1;
    for (int j = 0; j < n; ++j) {
        const double y = 2 * (j + 0.5) / n - 1;
        const double dep = (90 - theta) * kDeg - std::atan(a * y);
        for (int i = 0; i < n; ++i) {
            const double x = 2 * (i + 0.5) / n - 1;
            const double gamma = std::atan(a * x / std::sqrt(1 + a * a * y * y));
            const double vz = std::sin(dep) * std::cos(gamma);
            *margin = std::min(*margin, std::abs(vz - c89));
            count += vz <= c89 ? 1 : 0;
        }
    }
    return count;
}

TEST(PerspectiveCamera, OutsideCountIsWhatTheRowAnglesPredict) {
    // theta 80, F 60, N 64 by hand: the horizon is at atan(a y) = 10 degrees, y = 0.3054, so rows
    // 42 ... 63 look past it; row 41 (y = 0.2969) descends 0.27 degrees, within the 1-degree cut
    // for every column; row 40 descends 1.28 degrees and even its corners (29.3 degrees off)
    // keep V.z = 0.0195 > cos 89. 23 rows of 64: 1472 outside, rows 41 ... 63.
    {
        const PerspectiveCamera cam(params(80, 15, 2, 60, 64));
        EXPECT_EQ(cam.outside_count(), 1472u);
        const std::vector<uint8_t> in = cam.inside();
        for (int j = 0; j < 64; ++j)
            for (int i = 0; i < 64; ++i) EXPECT_EQ(in[size_t(j) * 64 + i], j < 41 ? 1 : 0);
        double margin;
        EXPECT_EQ(outside_from_row_angles(80, 60, 64, &margin), 1472u);
    }
    // Wide fields of view: the cut crosses a row (its corners are out, its middle in).
    struct Case {
        double theta, fov;
        int n;
    };
    for (const Case c : {Case{70, 120, 128}, Case{80, 90, 200}, Case{60, 150, 120}}) {
        double margin;
        const size_t want = outside_from_row_angles(c.theta, c.fov, c.n, &margin);
        ASSERT_GT(margin, 1e-6) << "a pixel on the cut: the count would be rounding";
        for (double phi : {0.0, 77.0, 250.0}) {
            const PerspectiveCamera cam(params(c.theta, phi, 3, c.fov, c.n));
            EXPECT_EQ(cam.outside_count(), want) << c.theta << " " << c.fov << " " << phi;
            const std::vector<uint8_t> in = cam.inside();
            int partial_rows = 0;
            for (int j = 0; j < c.n; ++j) {
                int out = 0;
                for (int i = 0; i < c.n; ++i) out += in[size_t(j) * c.n + i] ? 0 : 1;
                partial_rows += out > 0 && out < c.n ? 1 : 0;
            }
            EXPECT_GE(partial_rows, 1) << c.theta << " " << c.fov;
        }
    }
    // Nothing near the horizon in view: nothing outside.
    EXPECT_EQ(PerspectiveCamera(params(30, 0, 2, 45, 32)).outside_count(), 0u);
}

TEST(PerspectiveCamera, AnEyeInsideTheSlabIsRefused) {
    // b = 0: the top of the slab is s. theta 0: the eye is D high.
    EXPECT_NE(eye_slab_problem(params(0, 0, 0.05, 45, 8), 0.05, 0), "");  // on the top: refused
    EXPECT_NE(eye_slab_problem(params(0, 0, 0.03, 45, 8), 0.05, 0), "");
    EXPECT_EQ(eye_slab_problem(params(0, 0, 0.0501, 45, 8), 0.05, 0), "");
    // b = 0.5, s = 0.2: top 0.1; theta 80: height D cos 80 = 0.0868 D.
    EXPECT_NE(eye_slab_problem(params(80, 0, 0.5, 45, 8), 0.2, 0.5), "");
    EXPECT_EQ(eye_slab_problem(params(80, 0, 1.0, 45, 8), 0.2, 0.5), "");
    // b = 1: the relief lies below the polygon, any eye above the polygon is above it.
    EXPECT_EQ(eye_slab_problem(params(89, 0, 0.01, 45, 8), 0.3, 1), "");
    try {
        check_eye_above_slab(params(60, 0, 0.07, 45, 8), 0.05, 0.2, "exp.toml:7");
        ADD_FAILURE() << "an eye inside the slab was accepted";
    } catch (const InputError& e) {
        EXPECT_STREQ(e.what(),
                     "exp.toml:7: the eye is not above the slab: distance 0.07 at theta 60 puts "
                     "it at height 0.035, at or below the top of the relief s (1 - b) = 0.04");
    }
}

TEST(PerspectiveCamera, BadParametersAreRefused) {
    EXPECT_EQ(perspective_problem(params(45, 0, 2, 45, 8)), "");
    EXPECT_EQ(perspective_problem(params(90, 0, 2, 45, 8)), "theta_deg = 90 is not in [0, 90)");
    EXPECT_EQ(perspective_problem(params(45, 0, 0, 45, 8)),
              "distance = 0 is not a positive number of tiles");
    EXPECT_EQ(perspective_problem(params(45, 0, INFINITY, 45, 8)),
              "distance = inf is not a positive number of tiles");
    EXPECT_EQ(perspective_problem(params(45, 0, 2, 180, 8)), "fov_deg = 180 is not in (0, 180)");
    EXPECT_EQ(perspective_problem(params(45, NAN, 2, 45, 8)), "phi_deg = nan is not finite");
    EXPECT_EQ(perspective_problem(params(45, 0, 2, 45, 0)), "samples = 0 is not at least 1");
    try {
        PerspectiveCamera cam(params(45, 0, 2, 0, 8));
        ADD_FAILURE() << "a zero field of view made a camera";
    } catch (const InputError& e) {
        EXPECT_STREQ(e.what(), "camera: perspective: fov_deg = 0 is not in (0, 180)");
    }
}

// samples N < resolution R: the view's samples are pixels of the R x R image, spread evenly
// (floor((a + 0.5) R / N) per axis), each with the full image's ray, footprint and inside flag,
// bit for bit; N = R is the whole image in its order.
TEST(PerspectiveCamera, SubsetPixelsKeepTheFullImagesRaysAndFootprints) {
    EXPECT_EQ(subset_pixel(0, 8, 32), 2);
    EXPECT_EQ(subset_pixel(7, 8, 32), 30);
    EXPECT_EQ(subset_pixel(0, 3, 10), 1);  // floor(10/6)
    EXPECT_EQ(subset_pixel(1, 3, 10), 5);  // floor(30/6)
    EXPECT_EQ(subset_pixel(2, 3, 10), 8);  // floor(50/6)
    for (int n = 1; n <= 9; ++n)
        for (int a = 0; a < n; ++a) EXPECT_EQ(subset_pixel(a, n, n), a);
    for (const int n : {5, 16, 37}) {
        PerspectiveParams full = params(78, 40, 1.5, 60, 37), sub = full;
        sub.samples = n;
        sub.resolution = 37;
        const View vf = PerspectiveCamera(full).view(), vs = PerspectiveCamera(sub).view();
        ASSERT_EQ(vs.size(), size_t(n) * n);
        size_t outside = 0;
        for (int b = 0; b < n; ++b)
            for (int a = 0; a < n; ++a) {
                const size_t k = size_t(b) * n + a;
                const size_t f = size_t(subset_pixel(b, n, 37)) * 37 + subset_pixel(a, n, 37);
                EXPECT_TRUE(vs.has_ray(k, vf.P[f], vf.V[f])) << n << " " << a << " " << b;
                EXPECT_EQ(vs.J[k].dPdi.x, vf.J[f].dPdi.x);
                EXPECT_EQ(vs.J[k].dPdj.y, vf.J[f].dPdj.y);
                EXPECT_EQ(vs.inside[k], vf.inside[f]);
                outside += !vs.is_inside(k);
            }
        EXPECT_GT(outside, 0u) << "the view should reach past the horizon at 78 deg, fov 60";
    }
    PerspectiveParams over = params(45, 0, 2, 45, 33);
    over.resolution = 32;
    EXPECT_EQ(perspective_problem(over),
              "samples = 33 exceeds the image's resolution 32 (samples picks N x N of its pixels)");
}

}  // namespace
}  // namespace pxh
