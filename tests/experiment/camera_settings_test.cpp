// The perspective camera's settings as the experiment file gives them: resolution (a key of its
// own, default the file's samples), repeated settings dropped with a warning like repeated
// angles, values that results.csv would print alike refused (their rows would share keys), and
// samples against the image's resolution (lod implicit needs every pixel).
#include <gtest/gtest.h>

#include <string>

#include "harness/core/error.h"
#include "harness/experiment/experiment.h"

namespace pxh {
namespace {

std::string exp_with(const std::string& views, const std::string& methods = "", int samples = 16) {
    return "name = \"c\"\nsamples = " + std::to_string(samples) +
           "\nbackends = [\"cpu\", \"glsl\"]\n[views]\ntheta_deg = [30]\ncamera = "
           "\"perspective\"\n" +
           views +
           "\n[[heightfields]]\ngenerator = \"fbm\"\nsize = 16\n[[methods]]\nname = \"pom\"\n" +
           methods;
}

std::string error_of(const std::string& text) {
    try {
        parse_experiment(text, "c.toml");
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

TEST(CameraSettings, ResolutionDefaultsToTheFilesSamplesAndSweeps) {
    const Experiment a = parse_experiment(exp_with("distance = [2, 4]"), "c.toml");
    ASSERT_EQ(a.camera_settings.size(), 2u);
    EXPECT_EQ(a.camera_settings[0].get("resolution"), 16);
    EXPECT_EQ(a.camera_settings[1].label(), "distance=4 fov_deg=45 resolution=16");
    const Experiment b =
        parse_experiment(exp_with("distance = 2\nresolution = [64, 128]"), "c.toml");
    ASSERT_EQ(b.camera_settings.size(), 2u);
    EXPECT_EQ(b.camera_settings[1].get("resolution"), 128);
    EXPECT_EQ(error_of(exp_with("distance = 2\nresolution = 12.5")),
              "c.toml:8: resolution = 12.5 is not a whole number of pixels per side in [1, 8192]");
    EXPECT_EQ(error_of(exp_with("distance = 2\nresolution = 8")),
              "c.toml:4: samples = 16 exceeds the perspective image's resolution 8: samples "
              "picks N x N of the image's R x R pixels (N <= R)");
    // lod implicit takes the GPU's derivatives between neighbouring fragments: N = R only.
    const std::string implicit = "lod = [\"base\", \"implicit\"]\n";
    EXPECT_EQ(error_of(exp_with("distance = 2\nresolution = 16", implicit)), "");
    EXPECT_NE(error_of(exp_with("distance = 2\nresolution = 32", implicit))
                  .find("lod 'implicit' takes the GPU's derivatives between neighbouring "
                        "fragments, which are neighbouring pixels only when samples = "
                        "resolution (here 16 of 32)"),
              std::string::npos);
}

TEST(CameraSettings, RepeatsAreDroppedAndAlikeValuesRefused) {
    const Experiment ex =
        parse_experiment(exp_with("distance = [2, 2, 3]\nfov_deg = [45, 45]"), "c.toml");
    ASSERT_EQ(ex.camera_settings.size(), 2u);
    EXPECT_EQ(ex.camera_settings[0].label(), "distance=2 fov_deg=45 resolution=16");
    EXPECT_EQ(ex.camera_settings[1].label(), "distance=3 fov_deg=45 resolution=16");
    ASSERT_EQ(ex.warnings.size(), 1u);
    EXPECT_EQ(ex.warnings[0],
              "c.toml:4: camera 'perspective' settings repeat (4 duplicate(s) of distance, "
              "fov_deg, resolution dropped): each view is measured once");
    EXPECT_EQ(error_of(exp_with("distance = [2, 2.00000000001]")),
              "c.toml:7: distance values 2.00000000001 and 2 both print as 2 in "
              "results.csv (10 significant digits): their rows would share their keys; give "
              "values that differ there");
    EXPECT_NE(
        error_of(exp_with("distance = 2\nfov_deg = [45, 45.000000000001]")).find("fov_deg values "),
        std::string::npos);
    // Angles as well: theta and phi values that print alike, and a phi that prints as 360.
    std::string t = exp_with("distance = 2");
    t.replace(t.find("theta_deg = [30]"), 16, "theta_deg = [30, 30.0000000000001]");
    EXPECT_NE(error_of(t).find("theta_deg values "), std::string::npos) << error_of(t);
    std::string p = exp_with("distance = 2\nphi_deg = [0, 359.99999999999]");
    EXPECT_NE(error_of(p).find("phi_deg = 359.99999999999 prints as 360 in results.csv"),
              std::string::npos)
        << error_of(p);
}

}  // namespace
}  // namespace pxh
