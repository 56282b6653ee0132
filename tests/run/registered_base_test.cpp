// A base registered only in this test (BaseRegistration) runs end to end through the runner on
// both backends, the runner and the experiment's reader knowing it by its entry alone: the
// cylinder turned a quarter about the normal at the look-at point (its axis along x), written
// here from its own formulas. On a field the quarter turn maps to itself, seen from an azimuth
// a quarter turn further, its rows are the registry's cylinder's (the same samples, rotated);
// and the plane's geometry registered under another name gives the plane's rows cell for cell.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "harness/core/params.h"
#include "harness/experiment/experiment.h"
#include "harness/metrics/columns.h"
#include "harness/run/runner.h"
#include "harness/scene/base_surface.h"
#include "harness/scene/curved_view.h"
#include "tests/test_util.h"

namespace pxh {
namespace {

using test::run;

// The axis along x through (*, 0.5, -R): B = (u, 0.5 + R sin(v'/R), R cos(v'/R) - R),
// N = (0, sin(v'/R), cos(v'/R)), v' = v - 0.5; arc length along v equals v.
class CylinderAlongX final : public BaseSurface {
  public:
    explicit CylinderAlongX(double R) : R_(R) {}
    std::string name() const override { return "cylinder_x"; }
    double radius() const override { return R_; }
    BaseFrame frame(Vec2d uv) const override {
        const double a = (uv.y - 0.5) / R_, s = std::sin(a), c = std::cos(a);
        return {{uv.x, 0.5 + R_ * s, R_ * c - R_}, {1, 0, 0}, {0, c, -s}, {0, s, c}};
    }
    BaseCoord coords(Vec3d p) const override {
        const double y = p.y - 0.5, z = p.z + R_;
        return {{p.x, 0.5 + R_ * std::atan2(y, z)}, std::hypot(y, z) - R_};
    }
    double hit(Vec3d o, Vec3d d, double offset, double t_min, bool leaving) const override {
        const double y = o.y - 0.5, z = o.z + R_, r = R_ + offset;
        const QuadRoots q =
            quad_roots(d.y * d.y + d.z * d.z, y * d.y + z * d.z, y * y + z * z - r * r);
        const double t = leaving ? q.t1 : q.t0;
        return t > t_min ? t : NAN;
    }
    Vec2d curvature() const override { return {0, 1 / R_}; }
    double uv_speed(Vec3d p) const override {
        const double rho = std::hypot(p.y - 0.5, p.z + R_);
        return std::max(1.0, R_ / std::max(rho, 1e-12 * R_));
    }

  private:
    double R_;
};

std::unique_ptr<BaseSurface> make_cylinder_x(double R) {
    return std::make_unique<CylinderAlongX>(R);
}

// Its entry: the registry's own pieces for its keys, its view and its truth.
BaseEntry cylinder_x_entry() {
    const BaseEntry& cylinder = base_entry("cylinder");
    return {"cylinder_x", true, &make_cylinder_x, cylinder.read, &curved_view, cylinder.truth};
}

BaseEntry plane_twin_entry() {
    BaseEntry e = base_entry("plane");
    e.name = "plane_twin";
    return e;
}

std::string experiment(const std::string& phi, const std::string& field) {
    return "samples = 24\ntiming_repeats = 0\nbackends = [\"cpu\", \"glsl\"]\n"
           "precision = [\"float\", \"double\"]\n[views]\n"
           "theta_deg = [0, 40, 70]\nphi_deg = [" +
           phi + "]\n[[heightfields]]\nname = \"f\"\nsize = 32\nscale = 0.08\nbias = 1.0\n" +
           field +
           "[[methods]]\nname = \"pom\"\nlayers = 16\n[[methods]]\nname = \"curved_relief\"\n";
}

// The measured columns compared, and how near: the rotated samples are the same points, but
// their coordinates are computed from other formulas (float rows: float's rounding of them);
// fetches_mean within 0.05 of a fetch a sample: on the pyramids' ridges pom's layer test ties at
// a few mirrored samples, which the rounding breaks one way or the other.
const char* const kCompared[] = {"err_mean",           "err_max",         "err_p50",
                                 "err_px_mean",        "samples_outside", "cover_extra_frac",
                                 "cover_missing_frac", "fetches_mean",    "lod_mean"};

TEST(RegisteredBase, TurnedCylinderGivesTheCylindersRowsOnBothBackends) {
    const BaseRegistration reg(cylinder_x_entry());
    // A flat relief (level 0.5, sunk s / 2 below the base) and pyramids, square in the tile:
    // both map to themselves under the quarter turn (u, v) -> (1 - v, u).
    for (const std::string gen : {"generator = \"flat\"\n", "generator = \"pyramids\"\n"}) {
        const auto along_y = run(experiment("0", gen + "base = \"cylinder\"\nradius = 0.6\n"));
        const auto along_x = run(experiment("90", gen + "base = \"cylinder_x\"\nradius = 0.6\n"));
        ASSERT_EQ(along_y.size(), along_x.size());
        ASSERT_EQ(along_y.size(), 3u * 2 * 3);  // theta x methods x (cpu float, double, glsl)
        size_t glsl = 0;
        for (size_t i = 0; i < along_y.size(); ++i) {
            const ResultRow &y = along_y[i], &x = along_x[i];
            ASSERT_TRUE(y.ok()) << y.text("error");
            ASSERT_TRUE(x.ok()) << x.text("error");
            EXPECT_EQ(x.text("base"), "cylinder_x");
            EXPECT_EQ(x.text("backend"), y.text("backend"));
            EXPECT_EQ(x.text("method"), y.text("method"));
            glsl += x.text("backend") == "glsl";
            const bool dbl = x.text("precision") == "double";
            const std::string at = gen + x.text("method") + " " + x.text("backend") + " " +
                                   x.text("precision") + " theta " +
                                   format_number(x.num("theta_deg"));
            EXPECT_GT(y.num("err_mean"), 1e-3) << at;  // the flat methods miss the curve
            for (const char* c : kCompared)
                EXPECT_NEAR(x.num(c), y.num(c),
                            std::string(c) == "fetches_mean" ? 0.05
                            : dbl                            ? 1e-9
                                                             : 2e-4)
                    << at << " " << c;
        }
        EXPECT_EQ(glsl, 6u);
    }
    // The control: the turned cylinder seen from the cylinder's own azimuth is another view.
    const auto y0 =
        run(experiment("0", "generator = \"flat\"\nbase = \"cylinder\"\nradius = 0.6\n"));
    const auto x0 =
        run(experiment("0", "generator = \"flat\"\nbase = \"cylinder_x\"\nradius = 0.6\n"));
    double most = 0;
    for (size_t i = 0; i < y0.size(); ++i)
        most = std::max(most, std::abs(x0[i].num("err_mean") - y0[i].num("err_mean")));
    EXPECT_GT(most, 0.01);
}

TEST(RegisteredBase, ThePlanesTwinGivesThePlanesRows) {
    const BaseRegistration reg(plane_twin_entry());
    const auto plane = run(experiment("25", "generator = \"bricks\"\n"));
    const auto twin = run(experiment("25", "generator = \"bricks\"\nbase = \"plane_twin\"\n"));
    ASSERT_EQ(plane.size(), twin.size());
    for (size_t i = 0; i < plane.size(); ++i) {
        ASSERT_TRUE(twin[i].ok()) << twin[i].text("error");
        EXPECT_EQ(plane[i].text("base"), "plane");
        EXPECT_EQ(twin[i].text("base"), "plane_twin");
        for (const ColumnSpec* c : result_column_specs()) {
            if (c->name == "base" || c->name.rfind("time", 0) == 0 ||
                c->name.rfind("gpu_ms", 0) == 0 || c->name == "precompute_ms")
                continue;
            EXPECT_EQ(twin[i].cell(c->name), plane[i].cell(c->name)) << i << " " << c->name;
        }
    }
}

TEST(RegisteredBase, ItsKeysAreReadByItsEntry) {
    const BaseRegistration reg(cylinder_x_entry());
    EXPECT_EQ(test::parse_error(experiment("0", "generator = \"flat\"\nbase = \"cylinder_x\"\n")),
              "e.toml:14: base 'cylinder_x' needs a radius (tiles)");
    const auto rows = run(experiment("0",
                                     "generator = \"flat\"\nbase = [\"plane\", \"cylinder_x\"]\n"
                                     "radius = [0.6, 2]\n"));
    ASSERT_EQ(rows.size(), 3u * 3 * 2 * 3);  // bases and radii x theta x methods x variants
    EXPECT_EQ(rows.front().text("base"), "plane");
    EXPECT_TRUE(std::isnan(rows.front().num("radius")));
    EXPECT_EQ(rows.back().text("base"), "cylinder_x");
    EXPECT_EQ(rows.back().num("radius"), 2);
}

}  // namespace
}  // namespace pxh
