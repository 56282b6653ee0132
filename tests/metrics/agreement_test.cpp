// The GLSL/CPU agreement of one row (harness/metrics/agreement.h): its statistics, the worst
// sample's index and the first differing samples, on outputs built by hand.
#include "harness/metrics/agreement.h"

#include <gtest/gtest.h>

#include <cmath>

namespace pxh {
namespace {

// Ten samples on a 100 x 100 texel field: sample k differs by k / 10 texel in u (0 ... 0.9),
// sample 7 also by one fetch; sample 3 is discarded by both (left out).
TEST(Agreement, MeanP95WorstAndFirstDiffs) {
    std::vector<Vec2d> a(10), b(10);
    std::vector<int> fa(10, 4), fb(10, 4);
    for (int k = 0; k < 10; ++k) {
        a[size_t(k)] = {0.5, 0.25};
        b[size_t(k)] = {0.5 + k / 10.0 / 100.0, 0.25};
    }
    a[3] = b[3] = {NAN, NAN};
    fb[7] = 5;
    const OutputDiff d = compare_uv(a, fa, b, fb, 100, 100);
    EXPECT_EQ(d.skipped, 1);
    EXPECT_EQ(d.decision_mismatch, 1);
    EXPECT_NEAR(d.max, 0.9, 1e-9);
    EXPECT_NEAR(d.mean, (0.0 + 0.1 + 0.2 + 0.4 + 0.5 + 0.6 + 0.7 + 0.8 + 0.9) / 9, 1e-9);
    EXPECT_GT(d.p95, 0.8);
    EXPECT_LE(d.p95, d.max);
    EXPECT_EQ(d.worst, 9);
    // Beyond 1e-3 texel: every sample from 1 on but the skipped one.
    EXPECT_EQ(d.first, (std::vector<size_t>{1, 2, 4, 5, 6, 7, 8, 9}));
    EXPECT_NE(d.first_text.find("7: 0.5 0.25 | 0.507 0.25 fetches 4 | 5"), std::string::npos)
        << d.first_text;
    // Equal outputs: nothing differs, the worst is the first sample compared.
    const OutputDiff same = compare_uv(a, fa, a, fa, 100, 100);
    EXPECT_EQ(same.max, 0.0);
    EXPECT_EQ(same.worst, 0);
    EXPECT_TRUE(same.first.empty());
    EXPECT_EQ(same.first_text, "");
}

}  // namespace
}  // namespace pxh
