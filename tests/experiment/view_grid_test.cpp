// The view grid (harness/experiment/view_grid.h): its order is the runner's (field, phi, camera
// setting, theta, theta innermost), its sweeps invert its index, and a sharded run's slices
// take every view exactly once, each in the unit whose theta range holds it.
#include "harness/experiment/view_grid.h"

#include <gtest/gtest.h>

#include "harness/experiment/shard.h"
#include "harness/run/runner.h"
#include "tests/cli_util.h"

namespace pxh {
namespace {

// 2 fields x 2 azimuths x 2 camera settings x 3 thetas.
Experiment grid_experiment() {
    return parse_experiment(test::ExperimentToml("grid")
                                .theta("[10, 40, 70]")
                                .phi("[0, 90]")
                                .view("camera", "\"perspective\"")
                                .view("distance", "[2, 4]")
                                .field("fbm", 16)
                                .field("bricks", 16)
                                .method("none")
                                .str(),
                            "grid.toml");
}

TEST(ViewGrid, IndexIsRunOrderThetaInnermost) {
    const Experiment ex = grid_experiment();
    const ViewGrid g(ex);
    EXPECT_EQ(g.views(), 24u);
    EXPECT_EQ(g.sweeps(), 8u);
    EXPECT_EQ(g.views_per_field(), 12u);
    size_t expect = 0;
    for (size_t f = 0; f < 2; ++f)
        for (size_t p = 0; p < 2; ++p)
            for (size_t c = 0; c < 2; ++c)
                for (size_t t = 0; t < 3; ++t) {
                    EXPECT_EQ(g.index({f, p, c, t}), expect++);
                    if (t) continue;
                    const size_t s = g.sweep_index({f, p, c, 0});
                    const ViewAt back = g.sweep(s);
                    EXPECT_EQ(back.field, f);
                    EXPECT_EQ(back.phi, p);
                    EXPECT_EQ(back.camera, c);
                    EXPECT_EQ(back.theta, 0u);
                }
}

// The runner meets the views in the grid's order: RunInfo's views, in run order, have
// increasing indices, one per view.
TEST(ViewGrid, TheRunnerMeetsTheViewsInGridOrder) {
    const Experiment ex = grid_experiment();
    const ViewGrid g(ex);
    RunInfo info;
    (void)run_experiment(ex, {}, &info);
    ASSERT_EQ(info.views.size(), g.views());
    for (size_t i = 0; i < info.views.size(); ++i) EXPECT_EQ(g.index(info.views[i].at), i);
}

TEST(ViewGrid, SlicesTakeEveryViewOnceInItsUnit) {
    const Experiment ex = grid_experiment();
    const ViewGrid g(ex);
    std::vector<int> taken(g.views(), 0);
    for (size_t i = 0; i < 3; ++i) {
        const Slice s = make_slice(ex, {i, 3}, {});
        for (size_t v = 0; v < g.views(); ++v) {
            const ViewAt at = g.sweep(v / g.thetas);
            const ViewAt view{at.field, at.phi, at.camera, v % g.thetas};
            if (!s.includes(view)) continue;
            ++taken[v];
            const WorkUnit& u = s.units[s.unit(view)];
            EXPECT_EQ(u.field, view.field);
            EXPECT_EQ(u.phi, view.phi);
            EXPECT_EQ(u.camera, view.camera);
            EXPECT_LE(u.theta_begin, view.theta);
            EXPECT_LT(view.theta, u.theta_end);
        }
    }
    for (size_t v = 0; v < g.views(); ++v) EXPECT_EQ(taken[v], 1) << v;
}

}  // namespace
}  // namespace pxh
