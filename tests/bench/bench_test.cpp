// pxh bench (harness/bench/) in process: it tells a curved base by the base registry's entry, not
// by its name, and takes its cameras from the registry and its own table of sweeps, refusing
// any other in one line before any measurement.
#include "harness/bench/bench.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "harness/bench/bench_util.h"
#include "harness/core/error.h"
#include "harness/scene/base_surface.h"
#include "harness/truth/curved_pyramid.h"

namespace pxh {
namespace {

std::string scratch(const std::string& name) {
    return (std::filesystem::temp_directory_path() /
            ("pxh_bench_test_" + std::to_string(::getpid()) + "_" + name))
        .string();
}

BenchOptions tiny(const std::string& out) {
    BenchOptions o;
    o.sizes = {16};
    o.thetas = {30};
    o.samples = 4;
    o.repeats = 1;
    o.threads = 1;
    o.out = out;
    return o;
}

// The plane's entry under another name: a flat base whatever it is called.
BaseEntry plane_twin_entry() {
    BaseEntry e = base_entry("plane");
    e.name = "plane_twin";
    return e;
}

// The cylinder's entry under another name: a curved base whatever it is called.
BaseEntry cylinder_twin_entry() {
    BaseEntry e = base_entry("cylinder");
    e.name = "cylinder_twin";
    return e;
}

nlohmann::json read_json(const std::string& path) {
    std::ifstream f(path);
    return nlohmann::json::parse(f);
}

TEST(Bench, AFlatBaseOfAnyNameTimesTheFlatTracersOnly) {
    const BaseRegistration reg(plane_twin_entry());
    BenchOptions o = tiny(scratch("flat.json"));
    o.base = "plane_twin";
    testing::internal::CaptureStdout();
    const int rc = run_bench(o);
    const std::string out = testing::internal::GetCapturedStdout();
    ASSERT_EQ(rc, 0);
    const auto doc = read_json(o.out);
    ASSERT_EQ(doc["results"].size(), 1u);
    // no curved tracer timed: no base fields, no curved lines
    EXPECT_FALSE(doc["results"][0].contains("base")) << doc["results"][0].dump();
    EXPECT_FALSE(doc["results"][0].contains("curved_pyramid_mrays_per_s"));
    EXPECT_EQ(out.find("pyramid"), std::string::npos) << out;
    std::filesystem::remove(o.out);
}

TEST(Bench, ACurvedBaseOfAnyNameTimesTheCurvedTracers) {
    const BaseRegistration reg(cylinder_twin_entry());
    BenchOptions o = tiny(scratch("curved.json"));
    o.base = "cylinder_twin";
    o.radii = {2, 3};  // --radius 2 3: each radius in turn
    testing::internal::CaptureStdout();
    const int rc = run_bench(o);
    const std::string out = testing::internal::GetCapturedStdout();
    ASSERT_EQ(rc, 0);
    const auto doc = read_json(o.out);
    ASSERT_EQ(doc["results"].size(), 2u);
    for (int i = 0; i < 2; ++i) {
        const auto& row = doc["results"][size_t(i)];
        EXPECT_EQ(row["base"], "cylinder");  // the surface the entry makes
        EXPECT_EQ(row["radius"].get<double>(), 2.0 + i);
        EXPECT_EQ(row["curved_pyramid_vs_walk_hit_miss"].get<size_t>(), 0u);
        EXPECT_EQ(row["curved_pyramid_path"], CurvedPyramid::path_name());  // the widest here
    }
    EXPECT_NE(out.find("on cylinder R=2 ("), std::string::npos) << out;
    EXPECT_NE(out.find("on cylinder R=3 ("), std::string::npos) << out;
    std::filesystem::remove(o.out);
}

TEST(Bench, CamerasComeFromTheRegistry) {
    // an unknown camera: the registry's one line, before any measurement (no file written)
    BenchOptions o = tiny(scratch("camera.json"));
    o.camera = "fisheye";
    try {
        run_bench(o);
        ADD_FAILURE() << "bench accepted camera 'fisheye'";
    } catch (const InputError& e) {
        const std::string what = e.what();
        EXPECT_EQ(what.find('\n'), std::string::npos) << what;
        EXPECT_NE(what.find("--camera"), std::string::npos) << what;
        EXPECT_NE(what.find("fisheye"), std::string::npos) << what;
        EXPECT_NE(what.find("orthographic"), std::string::npos) << what;
    }
    EXPECT_FALSE(std::filesystem::exists(o.out));
    // the views of the two cameras it sweeps: one orthographic grid, a perspective view per
    // distance (with its eye)
    o.camera = "orthographic";
    const std::vector<BenchView> ortho = bench_views(o, 60);
    ASSERT_EQ(ortho.size(), 1u);
    EXPECT_FALSE(ortho[0].eye);
    EXPECT_EQ(ortho[0].camera->name(), "orthographic");
    EXPECT_EQ(ortho[0].at, "theta 60");
    o.camera = "perspective";
    o.distances = {1.5, 4};
    const std::vector<BenchView> persp = bench_views(o, 60);
    ASSERT_EQ(persp.size(), 2u);
    EXPECT_TRUE(persp[1].eye);
    EXPECT_EQ(persp[1].camera->name(), "perspective");
    EXPECT_EQ(persp[1].distance, 4);
    EXPECT_EQ(persp[1].at, "theta 60 distance 4");
}

TEST(Bench, Statistics) {
    EXPECT_EQ(bench_median({3, 1, 2}), 2);
    EXPECT_EQ(bench_median({4, 1, 2, 3}), 2.5);
    EXPECT_TRUE(std::isnan(bench_median({})));
    EXPECT_DOUBLE_EQ(bench_spread({1, 2, 4}), 1.5);  // (4 - 1) / 2
}

}  // namespace
}  // namespace pxh
