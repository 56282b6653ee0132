// The view stage: cameras make the per-sample rays (P_k, V_k) of a view.
#include "harness/scene/view.h"

#include <gtest/gtest.h>

#include "harness/core/error.h"

namespace pxh {
namespace {

TEST(View, OrthographicCameraIsOneDirectionOnTheSampleGrid) {
    const OrthographicCamera cam(63.0, 211.0, 7);
    const View v = cam.view();
    const std::vector<Vec2d> grid = sample_grid(7);
    const Vec3d V = view_vector(63.0, 211.0);
    ASSERT_EQ(v.size(), 49u);
    for (size_t k = 0; k < v.size(); ++k) {
        EXPECT_EQ(v.P[k].x, grid[k].x);
        EXPECT_EQ(v.P[k].y, grid[k].y);
        EXPECT_EQ(v.dir(k).x, V.x);
        EXPECT_EQ(v.dir(k).y, V.y);
        EXPECT_EQ(v.dir(k).z, V.z);
    }
    EXPECT_EQ(v.V.size(), 1u);
    EXPECT_TRUE(v.parallel);
    EXPECT_EQ(v.grid, 7);
    EXPECT_TRUE(v.orthographic_grid());
    EXPECT_EQ(cam.direction().z, V.z);
    EXPECT_EQ(cam.name(), "orthographic");
    EXPECT_EQ(view_problem(v), "");
}

TEST(View, PerSampleRaysAreNotTheGridFastPath) {
    View v;
    v.P = {{0.1, 0.2}, {0.7, 0.4}};
    v.V = {view_vector(10, 0), view_vector(20, 90)};
    EXPECT_FALSE(v.orthographic_grid());
    EXPECT_EQ(view_problem(v), "");
    EXPECT_DOUBLE_EQ(v.dir(1).y, std::sin(20 * M_PI / 180));  // per sample, not V[0]
    v.parallel = true;                                        // two directions for parallel rays
    EXPECT_NE(view_problem(v).find("2 ray directions (expected 1"), std::string::npos)
        << view_problem(v);
    v.parallel = false;
    v.V.pop_back();  // one direction for two rays that are not parallel
    EXPECT_NE(view_problem(v).find("expected 2"), std::string::npos) << view_problem(v);
    View g = orthographic_view(view_vector(30, 0), 4);
    g.P.pop_back();  // a grid of 4 x 4 holds 16 samples
    EXPECT_NE(view_problem(g).find("4 x 4 sample grid has 15 samples"), std::string::npos)
        << view_problem(g);
}

TEST(View, EmptyGridIsAnEmptyView) {
    for (int n : {0, -3}) {
        const View v = orthographic_view(view_vector(30, 0), n);
        EXPECT_EQ(v.size(), 0u);
        EXPECT_FALSE(v.orthographic_grid());
        EXPECT_EQ(view_problem(v), "");
    }
}

TEST(View, CameraRegistryByName) {
    const std::vector<std::string> names = camera_names();
    ASSERT_EQ(names, (std::vector<std::string>{"orthographic", "perspective"}));
    CameraSpec spec;
    spec.theta_deg = 45;
    spec.phi_deg = 30;
    spec.samples = 5;
    const auto cam = make_camera("orthographic", spec);
    ASSERT_NE(cam, nullptr);
    EXPECT_EQ(cam->name(), "orthographic");
    const View a = cam->view(), b = OrthographicCamera(45, 30, 5).view();
    ASSERT_EQ(a.size(), b.size());
    EXPECT_EQ(a.V[0].x, b.V[0].x);
    EXPECT_EQ(a.P[24].y, b.P[24].y);
    try {
        (void)make_camera("fisheye", spec);
        ADD_FAILURE() << "an unknown camera was made";
    } catch (const InputError& e) {
        EXPECT_STREQ(e.what(),
                     "camera: unknown camera 'fisheye' (known: orthographic, perspective)");
    }
    try {  // the perspective camera's distance has no default
        (void)make_camera("perspective", spec);
        ADD_FAILURE() << "a perspective camera was made without a distance";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("camera 'perspective' needs distance"),
                  std::string::npos)
            << e.what();
    }
}

}  // namespace
}  // namespace pxh
