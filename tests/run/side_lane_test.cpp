// The side lane (harness/run/side_lane.h): rows come back in the order added whatever the
// drawing's timing, never more than the window ahead, a row's exception is that row's failure,
// and a view left early skips what it had not begun. End to end: a run whose GLSL rows are drawn
// on the lane (timing_repeats = 0) writes the same rows, in the same order, with the same
// numbers, as the run that draws them on its own thread (timed), on a plane and a cylinder.
#include "harness/run/side_lane.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <stdexcept>
#include <thread>

#include "harness/results/csv_table.h"
#include "tests/cli_util.h"

namespace pxh {
namespace {

MethodOutput output_of(double x) {
    MethodOutput o;
    o.uv = {{x, -x}};
    return o;
}

TEST(SideLane, RowsComeBackInOrderAndNeverMoreThanTheWindowAhead) {
    SideLane lane;
    std::atomic<int> drawn{0};
    std::atomic<int> taken{0};
    std::atomic<int> most_ahead{0};
    {
        SideRows side(lane, 3);
        for (int i = 0; i < 40; ++i)
            side.add(
                [&, i] {
                    // later rows quicker than earlier ones: order comes from the lane, not luck
                    std::this_thread::sleep_for(std::chrono::microseconds(200 * ((i * 7) % 5)));
                    const int ahead = ++drawn - taken.load();
                    int m = most_ahead.load();
                    while (ahead > m && !most_ahead.compare_exchange_weak(m, ahead)) {
                    }
                    if (i == 13) throw std::runtime_error("row 13 cannot be drawn");
                    return output_of(i);
                },
                [] { return std::string("shader.glsl"); });
        for (int i = 0; i < 40; ++i) {
            std::this_thread::sleep_for(std::chrono::microseconds(i % 3 == 0 ? 500 : 0));
            SideRows::Row r = side.take();
            ++taken;
            if (i == 13) {
                EXPECT_FALSE(r.out);
                EXPECT_EQ(r.error, "row 13 cannot be drawn");
                EXPECT_EQ(r.shader, "shader.glsl");
                continue;
            }
            ASSERT_TRUE(r.out) << i << ": " << r.error;
            EXPECT_EQ(r.out->uv[0].x, double(i));
        }
    }
    EXPECT_EQ(drawn.load(), 40);
    // drawn - taken counts the row being taken too: the window (3) plus that one
    EXPECT_LE(most_ahead.load(), 4);
    EXPECT_GE(most_ahead.load(), 2);  // it did draw ahead
}

TEST(SideLane, AViewLeftEarlySkipsWhatItHadNotBegun) {
    SideLane lane;
    std::atomic<int> drawn{0};
    {
        SideRows side(lane, 2);
        for (int i = 0; i < 50; ++i)
            side.add(
                [&] {
                    ++drawn;
                    std::this_thread::sleep_for(std::chrono::milliseconds(1));
                    return output_of(0);
                },
                [] { return std::string(); });
        (void)side.take();
    }  // left after one row: the destructor waits for what began, skips the rest
    EXPECT_LE(drawn.load(), 4);
    // the lane is free for the next view
    SideRows next(lane, 2);
    next.add([] { return output_of(7); }, [] { return std::string(); });
    EXPECT_EQ(next.take().out->uv[0].x, 7.0);
}

class SideLaneRun : public test::CliTest {};

// The same experiment timed (every row drawn on the calling thread) and untimed (the GLSL rows
// on the lane): the same rows and every column equal, except the timing columns.
TEST_F(SideLaneRun, UntimedRunsGiveTheTimedRunsRowsAndNumbers) {
    auto experiment = [](int repeats) {
        return test::ExperimentToml("lane")
            .samples(16)
            .timing_repeats(repeats)
            .backends("\"cpu\", \"glsl\"")
            .theta("[0, 50, 75]")
            .view("camera", "\"perspective\"")
            .view("distance", "2")
            .field("bricks", 32,
                   "scale = 0.05\nbias = 1.0\nbase = [\"plane\", \"cylinder\"]\nradius = 0.5")
            .method("parallax")
            .method("pom", "layers = 16")
            .method("relief", "layers = 16")
            .method("curved_relief")
            .str();
    };
    ASSERT_EQ(pxh("run " + write("timed.toml", experiment(1)) + " --out " +
                  (dir / "timed").string() + " --quiet")
                  .status,
              0);
    ASSERT_EQ(pxh("run " + write("untimed.toml", experiment(0)) + " --out " +
                  (dir / "untimed").string() + " --quiet")
                  .status,
              0);
    const CsvTable a = read_csv((dir / "timed" / "results.csv").string());
    const CsvTable b = read_csv((dir / "untimed" / "results.csv").string());
    ASSERT_EQ(a.rows.size(), b.rows.size());
    ASSERT_EQ(a.columns, b.columns);
    ASSERT_EQ(a.rows.size(), 2u * 3 * 4 * 2);  // bases x angles x methods x backends
    size_t compared = 0, glsl = 0;
    for (size_t r = 0; r < a.rows.size(); ++r) {
        glsl += a.get(r, "backend") == "glsl";
        for (const std::string& c : a.columns) {
            // what a timed run measures or says of its timing
            if (c.rfind("time", 0) == 0 || c.rfind("gpu_ms", 0) == 0 || c == "precompute_ms" ||
                c.find("spread") != std::string::npos)
                continue;
            EXPECT_EQ(a.get(r, c), b.get(r, c)) << "row " << r << " column " << c;
            ++compared;
        }
    }
    EXPECT_EQ(glsl, a.rows.size() / 2);
    EXPECT_GT(compared, a.rows.size() * 50);
}

}  // namespace
}  // namespace pxh
