// Every key --help lists filters: pxh run --only by base and radius (and depth, cut, the camera's
// keys), numeric ones also as KEY=LO..HI, and the same spec as a test of result rows (pxh compare
// --only), where an empty base cell is the plane.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "harness/core/error.h"
#include "harness/experiment/experiment.h"
#include "harness/experiment/only_rows.h"
#include "harness/metrics/row.h"
#include "tests/test_util.h"

namespace pxh {
namespace {

const char* kCurved =
    "[views]\ntheta_deg = [0, 30, 60]\ncut = [0.3, 0.7]\n"
    "[[heightfields]]\nname = \"flat\"\ngenerator = \"sine\"\nsize = 8\n"
    "[[heightfields]]\nname = \"round\"\ngenerator = \"sine\"\nsize = 8\n"
    "base = [\"cylinder\", \"sphere\"]\nradius = [1.5, 4, 8]\n"
    "[[methods]]\nname = \"pom\"\ndepth = [\"base\", \"hit\"]\n";

std::vector<std::string> fields(const Experiment& ex) {
    std::vector<std::string> v;
    for (const HeightfieldSpec& h : ex.heightfields)
        v.push_back(h.base + (h.base == "plane" ? "" : "R" + format_number(h.radius)));
    return v;
}

TEST(OnlyKeys, BaseAndRadiusSelectTheFieldsOnTheirBases) {
    Experiment ex = parse_experiment(kCurved, "e.toml");
    ASSERT_EQ(ex.heightfields.size(), 7u);  // the plane, 2 bases x 3 radii
    Experiment a = ex;
    apply_only(a, "base=cylinder");
    EXPECT_EQ(fields(a), (std::vector<std::string>{"cylinderR1.5", "cylinderR4", "cylinderR8"}));
    Experiment b = ex;
    apply_only(b, "base=plane");  // the plane, by its name
    EXPECT_EQ(fields(b), (std::vector<std::string>{"plane"}));
    Experiment c = ex;
    apply_only(c, "radius=4");  // the plane has no radius: not kept
    EXPECT_EQ(fields(c), (std::vector<std::string>{"cylinderR4", "sphereR4"}));
    Experiment d = ex;
    apply_only(d, "radius=1.5..4,base=sphere");  // a range, ends included
    EXPECT_EQ(fields(d), (std::vector<std::string>{"sphereR1.5", "sphereR4"}));
    Experiment e = ex;
    apply_only(e, "radius=5..");  // an open end
    EXPECT_EQ(fields(e), (std::vector<std::string>{"cylinderR8", "sphereR8"}));
    Experiment f = ex;
    apply_only(f, "radius_max=1.5");  // the older spelling of the range
    EXPECT_EQ(fields(f), (std::vector<std::string>{"cylinderR1.5", "sphereR1.5"}));
    // Depth and cut narrow the method settings; theta as a range.
    Experiment g = ex;
    apply_only(g, "depth=hit,cut=0.3,theta_deg=10..60");
    ASSERT_EQ(g.methods.size(), 1u);
    EXPECT_EQ(depth_name(g.methods[0].depth), std::string("hit"));
    EXPECT_EQ(g.methods[0].cut, 0.3);
    EXPECT_EQ(g.theta_deg, (std::vector<double>{30, 60}));
    // What matches nothing is named with what there is; a bad range is refused.
    Experiment h = ex;
    EXPECT_EQ(test::input_error([&] { apply_only(h, "radius=100..200"); }),
              "--only: no radius matches (the experiment has: flat (s=0.05 b=1), round (s=0.05 "
              "b=1 cylinder R=1.5), round (s=0.05 b=1 cylinder R=4), round (s=0.05 b=1 cylinder "
              "R=8), round (s=0.05 b=1 sphere R=1.5), round (s=0.05 b=1 sphere R=4), round "
              "(s=0.05 b=1 sphere R=8))");
    EXPECT_NE(
        test::input_error([&] { apply_only(h, "radius=.."); }).find("a range is radius=LO..HI"),
        std::string::npos);
    EXPECT_NE(test::input_error([&] { apply_only(h, "radius=1..x"); }).find("a range is"),
              std::string::npos);
    EXPECT_NE(test::input_error([&] { apply_only(h, "base=torus"); }).find("no base matches"),
              std::string::npos);
    // Every key offered is one --only takes: base and radius among them.
    const std::vector<std::string> keys = only_keys();
    for (const char* k : {"base", "radius", "depth", "cut", "distance", "fov_deg"})
        EXPECT_EQ(std::count(keys.begin(), keys.end(), k), 1) << k;
}

TEST(OnlyKeys, TheSameSpecFiltersResultRows) {
    ResultRow plane, cyl4, cyl8;
    for (ResultRow* r : {&plane, &cyl4, &cyl8}) {
        r->set_text("method", "pom");
        r->set("theta_deg", 30);
        r->set_text("depth", "hit");
    }
    cyl4.set_text("base", "cylinder");
    cyl4.set("radius", 4);
    cyl8.set_text("base", "cylinder");
    cyl8.set("radius", 8);
    cyl8.set_text("depth", "");  // an empty depth is the base mode
    const auto matching = [&](const std::string& spec) {
        const OnlyRows only(spec);
        std::string m;
        if (only.matches(plane)) m += "plane ";
        if (only.matches(cyl4)) m += "cyl4 ";
        if (only.matches(cyl8)) m += "cyl8 ";
        return m;
    };
    EXPECT_EQ(matching(""), "plane cyl4 cyl8 ");
    EXPECT_EQ(matching("base=plane"), "plane ");
    EXPECT_EQ(matching("base=cylinder"), "cyl4 cyl8 ");
    EXPECT_EQ(matching("radius=1.5..4"), "cyl4 ");
    EXPECT_EQ(matching("radius_min=5"), "cyl8 ");
    EXPECT_EQ(matching("depth=base"), "cyl8 ");
    EXPECT_EQ(matching("depth=hit,theta_deg=30|60"), "plane cyl4 ");
    EXPECT_EQ(matching("samples=64"), "");  // every axis, samples too (the rows leave it empty)
    EXPECT_THROW(OnlyRows("radius=a..b"), InputError);
    EXPECT_THROW(OnlyRows("colour=red"), InputError);
}

}  // namespace
}  // namespace pxh
