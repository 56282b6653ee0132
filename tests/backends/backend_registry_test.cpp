// The backends come from one list (PXH_BACKENDS in harness/backends/registry.cpp), each entry
// from its own file; what a row of each costs and records follows from its entry.
#include <gtest/gtest.h>

#include <any>
#include <string>
#include <vector>

#include "harness/backends/backend.h"
#include "harness/core/error.h"
#include "harness/core/param_dict.h"

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

// Every registered backend reads its keys of the experiment into the settings (whichever
// backends the run uses): each sets what its keys say, and none touches what another owns
// (its fields, or another backend's entry in BackendSettings::own, copied with the settings).
TEST(BackendRegistry, EachBackendReadsItsOwnKeysAndLeavesTheRest) {
    struct Mine {
        int queue_depth;
    };
    BackendSettings s;
    s.own["mine"] = Mine{12};
    s.gl_frames = 9;
    const ParamDict e = ParamDict::parse(
        "timing_repeats = 4\nprecision = \"double\"\ntexture_format = [\"r8\", \"r16\"]\n",
        "e.toml", "experiment");
    read_backend_settings(e, s);
    EXPECT_EQ(s.timing_repeats, 4);
    EXPECT_EQ(s.precisions, (std::vector<std::string>{"double"}));
    EXPECT_EQ(s.texture_formats, (std::vector<std::string>{"r8", "r16"}));
    EXPECT_EQ(s.gl_frames, 9);  // no key: left as it was
    EXPECT_EQ(backend_variants("cpu", s).size(), 1u);
    EXPECT_EQ(backend_variants("glsl", s).size(), 2u);
    const BackendSettings copy = s;
    ASSERT_EQ(copy.own.count("mine"), 1u);
    EXPECT_EQ(std::any_cast<Mine>(copy.own.at("mine")).queue_depth, 12);
    // A key a backend reads, refused there with its file and line.
    const ParamDict bad = ParamDict::parse("\ntiming_repeats = -1\n", "bad.toml", "experiment");
    try {
        read_backend_settings(bad, s);
        ADD_FAILURE() << "timing_repeats = -1 accepted";
    } catch (const InputError& err) {
        EXPECT_NE(std::string(err.what()).find("bad.toml:2"), std::string::npos) << err.what();
    }
}

}  // namespace
}  // namespace pxh
