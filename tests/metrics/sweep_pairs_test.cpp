// The sweep pairer (harness/metrics/sweep_pairs.h) against the pair metrics called directly: it
// writes each pair's columns into the right rows, keeps a nearer view only until its successor
// runs, and forgets across sweeps and fields.
#include "harness/metrics/sweep_pairs.h"

#include <gtest/gtest.h>

#include <random>

namespace pxh {
namespace {

// One row's error vectors at a view: n samples, random in a texel, seeded per view.
std::vector<Vec2d> errors(unsigned seed, size_t n = 64) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> d(-1, 1);
    std::vector<Vec2d> e(n);
    for (auto& v : e) v = {d(rng), d(rng)};
    return e;
}

// A row of a 16 x 16 field (the pair metrics read its width and height).
ResultRow row() {
    ResultRow r;
    r.set("width", 16);
    r.set("height", 16);
    return r;
}

TEST(SweepPairs, ConsecutiveThetasPairOnTheLowerViewsRows) {
    SweepPairer pairs({0, 30, 70}, 0, {CameraSetting{}}, "");
    std::vector<ResultRow> run;
    pairs.start_field();
    pairs.start_sweep();
    for (size_t t = 0; t < 3; ++t) {
        const ViewErrors e = {errors(unsigned(t))};
        pairs.pair_earlier(0, 0, t, e, run);
        run.push_back(row());
        pairs.keep(0, 0, t, e, {run.size() - 1}, false);
    }
    for (size_t t = 0; t < 2; ++t) {
        ResultRow expect = row();
        add_sweep(errors(unsigned(t)), errors(unsigned(t + 1)), t == 0 ? 30 : 40, expect);
        EXPECT_EQ(run[t].num("sliding"), expect.num("sliding")) << t;
        EXPECT_EQ(run[t].num("shimmering"), expect.num("shimmering")) << t;
        EXPECT_EQ(run[t].num("sweep_dt_deg"), t == 0 ? 30 : 40);
    }
    EXPECT_TRUE(std::isnan(run[2].num("sliding")));  // the last view has no next
    // A new sweep does not pair with the last one's view.
    pairs.start_sweep();
    pairs.pair_earlier(0, 0, 1, {errors(9)}, run);
    EXPECT_TRUE(std::isnan(run[2].num("sliding")));
}

TEST(SweepPairs, CompanionViewsLieDtAboveOrBelowNinety) {
    const SweepPairer pairs({45, 80}, 15, {CameraSetting{}}, "");
    EXPECT_EQ(*pairs.theta_companion(45), 60);
    EXPECT_EQ(*pairs.theta_companion(80), 65);  // 95 would pass 90: the one below
    std::vector<ResultRow> rows = {row()};
    pairs.pair_companion(80, {errors(1)}, {errors(2)}, rows);
    ResultRow expect = row();
    add_sweep(errors(2), errors(1), 15, expect);  // the companion is the lower view
    EXPECT_EQ(rows[0].num("sliding"), expect.num("sliding"));
    EXPECT_FALSE(SweepPairer({45}, 0, {CameraSetting{}}, "").theta_companion(45));
}

TEST(SweepPairs, ANearerViewWaitsForItsSuccessorSetting) {
    // distance outer: (1, 30) (1, 45) (3, 30) (3, 45); the pair key is the distance.
    std::vector<CameraSetting> s;
    for (double d : {1.0, 3.0})
        for (double f : {30.0, 45.0}) s.push_back({{{"distance", d}, {"fov_deg", f}}});
    SweepPairer pairs({60}, 0, s, "distance");
    EXPECT_EQ(pairs.successor(0).next, 2u);
    EXPECT_EQ(pairs.successor(0).dd, 2.0);
    EXPECT_FALSE(pairs.successor(2).pairs());
    std::vector<ResultRow> run;
    pairs.start_field();
    for (size_t c = 0; c < 4; ++c) {
        pairs.start_sweep();
        const ViewErrors e = {errors(unsigned(10 + c))};
        pairs.pair_earlier(0, c, 0, e, run);
        run.push_back(row());
        pairs.keep(0, c, 0, e, {run.size() - 1}, pairs.successor(c).pairs());
    }
    for (size_t c = 0; c < 2; ++c) {
        ResultRow expect = row();
        add_distance_sweep(errors(unsigned(10 + c)), errors(unsigned(12 + c)), 2, expect);
        EXPECT_EQ(run[c].num("sliding_dist"), expect.num("sliding_dist")) << c;
        EXPECT_EQ(run[c].num("sweep_dd"), 2);
        EXPECT_TRUE(std::isnan(run[c + 2].num("sliding_dist")));  // the farthest: none
    }
    // Taken once: the same view again pairs with nothing; a new field forgets what waits.
    const double paired = run[0].num("sliding_dist");
    pairs.pair_earlier(0, 2, 0, {errors(99)}, run);
    EXPECT_EQ(run[0].num("sliding_dist"), paired);
    pairs.keep(0, 0, 0, {errors(1)}, {0}, true);
    pairs.start_field();
    std::vector<ResultRow> other = {row()};
    pairs.pair_earlier(0, 2, 0, {errors(5)}, other);
    EXPECT_TRUE(std::isnan(other[0].num("sliding_dist")));
}

}  // namespace
}  // namespace pxh
