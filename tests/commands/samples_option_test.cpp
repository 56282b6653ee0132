// `pxh run --samples N`: given is checked. 0 used to mean "the file's" and was silently
// ignored; now it (and anything outside 1..8192) is one line, exit 2, nothing written.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>

#include "tests/cli_util.h"

namespace {

class SamplesOption : public pxh::test::CliTest {};

TEST_F(SamplesOption, ZeroAndOutOfRangeAreRefused) {
    const std::string exp = write("e.toml",
                                  "name = \"s\"\nsamples = 16\nbackends = [\"cpu\"]\n"
                                  "timing_repeats = 0\n[views]\ntheta_deg = [30]\n"
                                  "[[heightfields]]\ngenerator = \"sine\"\nsize = 32\n"
                                  "scale = 0.05\nbias = 1.0\n[[methods]]\nname = \"parallax\"\n");
    for (const char* n : {"0", "-1", "8193"}) {
        const auto r =
            pxh("run " + exp + " --samples " + n + " --quiet --out " + (dir / "out").string());
        EXPECT_EQ(r.status, 2) << n << r.err;
        EXPECT_EQ(r.err, "pxh: error: --samples: " + std::string(n) + " is not in [1, 8192]\n");
        EXPECT_FALSE(std::filesystem::exists(dir / "out")) << n;
    }
    // A valid one overrides the file's 16.
    const auto r = pxh("run " + exp + " --samples 8 --quiet --out " + (dir / "out").string());
    ASSERT_EQ(r.status, 0) << r.err;
    const std::string csv = slurp(dir / "out" / "results.csv");
    EXPECT_NE(csv.find(",30,0,8,32,32,"), std::string::npos) << csv;
}

}  // namespace
