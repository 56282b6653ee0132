// The backends come from one list (PXH_BACKENDS in harness/backends/registry.cpp), each entry
// from its own file; what a row of each costs and records follows from its entry.
#include <gtest/gtest.h>

#include <any>
#include <string>
#include <vector>

#include "harness/backends/backend.h"
#include "harness/core/error.h"

namespace pxh {
namespace {

TEST(BackendRegistry, TheListsBackendsInOrderEachWithItsTiming) {
    EXPECT_EQ(backend_names(), (std::vector<std::string>{"cpu", "glsl"}));
    EXPECT_EQ(backend_timing("cpu").unit, "ns/sample");
    EXPECT_EQ(backend_timing("glsl").unit, "ms/frame");
    BackendSettings s;
    s.timing_repeats = 7;
    s.gl_frames = 3;
    EXPECT_EQ(backend_repeats("cpu", s), 7);
    EXPECT_EQ(backend_repeats("glsl", s), 3);
    s.precisions = {"float", "double"};
    s.texture_formats = {"r16", "r8", "r32f"};
    EXPECT_EQ(backend_variants("cpu", s).size(), 2u);
    EXPECT_EQ(backend_variants("glsl", s).size(), 3u);
    EXPECT_THROW(backend_repeats("gpu", s), InputError);
}

// A backend's own settings travel in BackendSettings::own, in a type of its own, through the
// copies the run makes of the settings.
TEST(BackendRegistry, OwnSettingsKeepTheirTypeThroughCopies) {
    struct Mine {
        int queue_depth;
    };
    BackendSettings s;
    s.own["mine"] = Mine{12};
    const BackendSettings copy = s;
    ASSERT_EQ(copy.own.count("mine"), 1u);
    EXPECT_EQ(std::any_cast<Mine>(copy.own.at("mine")).queue_depth, 12);
    EXPECT_THROW(std::any_cast<int>(copy.own.at("mine")), std::bad_any_cast);
}

}  // namespace
}  // namespace pxh
