// Every figure `pxh report` draws, at single and double width, checked on the figure itself
// (tests/figure_text_check.py: matplotlib's renderer extents of every Text artist drawn): no two
// pieces of text overlap or touch, none leaves the canvas, no figure is wider than asked for.
// On a reduced copy of the default experiment (its six fields, ten settings, seven angles, two
// azimuths, both backends and [render]; fewer samples, smaller fields) and on a "wide" one
// (many settings, long parameter strings, scans, a plug-in shader with a long uniform name), on a
// perspective camera run (three distances, two level modes, maps and pictures) and on error maps
// of eighteen view angles.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "tests/cli_util.h"

namespace fs = std::filesystem;

namespace {

using pxh::test::ExperimentToml;

const char* kSb = "scale = 0.05\nbias = 1.0";

std::string default_reduced() {
    ExperimentToml t("default_reduced");
    t.samples(24).backends("\"cpu\", \"glsl\"").set("precision", "\"float\"").timing_repeats(1);
    t.theta("[0, 30, 45, 60, 70, 80, 85]").phi("[0, 30]");
    t.field("sine", 64, kSb).field("bricks", 64, kSb).field("fbm", 64, kSb);
    t.scan("jacksboro", kSb).scan("lidar_b9", kSb).field("spikes", 64, kSb);
    for (const char* m : {"none", "parallax", "parallax_limited", "parallax_clamped",
                          "parallax_halved", "pixel_step"})
        t.method(m);
    t.method("steep", "layers = 32").method("pom", "layers = 32");
    t.method("pom", "layers_min = 8\nlayers_max = 32");
    t.method("relief", "layers = 32\nbinary_steps = 5");
    return t.tail(R"([light]
theta_deg = 50
phi_deg = 200
[render]
heightfields = ["bricks", "scan:jacksboro"]
phi_deg = 0
theta_deg = [60, 80]
strip_method = "pom")");
}

// A plug-in with a long uniform name (the legend and the tables carry it) beside many settings.
const char* kPlugin = R"(
uniform float p_sample_count_of_the_linear_search_for_the_first_intersection;
vec2 pxh_method(vec2 P) {
    float n = p_sample_count_of_the_linear_search_for_the_first_intersection;
    vec2 dir = pxh_V.xy / pxh_V.z;
    float dz = u_scale / n;
    float z = pxh_z_top();
    vec2 uv = P + dir * z;
    int k = 0;
    while (z - pxh_z(uv) > 0.0 && k < int(ceil(n))) {
        k += 1;
        uv -= dir * dz;
        z -= dz;
    }
    return uv;
}
)";

std::string wide_experiment() {
    ExperimentToml t("wide");
    t.samples(16).backends("\"cpu\", \"glsl\"").timing_repeats(1).set("maps", "true");
    t.theta("[0, 40, 65, 75, 85]").phi("[30]");
    t.field("sine", 48, "scale = 0.04\nbias = 1.0").field("bricks", 48, "scale = 0.08\nbias = 0.5");
    t.scan("jacksboro", kSb).scan("lidar_b9", kSb);
    t.method("parallax").method("parallax_clamped");
    t.method("steep", "layers = 8").method("steep", "layers = 64");
    for (int l : {4, 8, 16, 32, 64}) t.method("pom", "layers = " + std::to_string(l));
    t.method("pom", "layers_min = 4\nlayers_max = 48");
    t.method("relief", "layers = 16\nbinary_steps = 3");
    t.method("relief", "layers_min = 8\nlayers_max = 64\nbinary_steps = 8");
    t.method("my_linear_search_plugin", R"(shader = "plugin.frag.glsl"
max_fetches = 70
uniforms = { p_sample_count_of_the_linear_search_for_the_first_intersection = 24.0 })");
    return t.tail(R"([render]
heightfields = ["bricks"]
phi_deg = 30
theta_deg = [40, 85]
strip_method = "pom")");
}

// A perspective camera at three distances, two level modes, error maps and pictures: a montage
// per view, a strip per view and level mode, error_vs_distance per field (issue 46).
const char* kCamera = R"(name = "camera"
samples = 32
backends = ["cpu"]
precision = "float"
timing_repeats = 1
maps = true
[views]
camera = "perspective"
theta_deg = [30, 60, 80]
phi_deg = [30]
distance = [1, 4, 16]
fov_deg = 45
[render]
heightfields = ["bricks"]
phi_deg = 30
theta_deg = [60]
strip_method = "pom"
[[heightfields]]
generator = "bricks"
size = 64
scale = 0.05
bias = 1.0
[[heightfields]]
generator = "fbm"
size = 64
scale = 0.05
bias = 1.0
[[methods]]
name = "parallax"
lod = ["base", "level"]
[[methods]]
name = "pom"
layers = 32
lod = ["base", "level"]
)";

// Error maps at many view angles (θ 0 to 85 in steps of 5): the montage's column heads.
const char* kAngles = R"(name = "angles"
samples = 8
backends = ["cpu"]
precision = "float"
timing_repeats = 1
maps = true
[views]
theta_deg = { from = 0, to = 85, step = 5 }
[[heightfields]]
generator = "bricks"
size = 32
scale = 0.05
bias = 1.0
[[methods]]
name = "parallax"
[[methods]]
name = "pom"
layers = 16
)";

class FigureCollisions : public ::testing::Test {
  protected:
    static fs::path root;
    static std::string failure;  // set when a run could not be made
    // CMD through the shell, stdout and stderr both into LOG.
    static int sh(const std::string& cmd, const fs::path& log) {
        return pxh::test::shell(cmd, log, log);
    }
    static std::string slurp(const fs::path& p) { return pxh::test::slurp(p); }
    static void SetUpTestSuite() {
        root = fs::temp_directory_path() / ("pxh_figures_" + std::to_string(::getpid()));
        fs::remove_all(root);
        fs::create_directories(root);
        std::ofstream(root / "default.toml") << default_reduced();
        std::ofstream(root / "wide.toml") << wide_experiment();
        std::ofstream(root / "plugin.frag.glsl") << kPlugin;
        std::ofstream(root / "camera.toml") << kCamera;
        std::ofstream(root / "angles.toml") << kAngles;
        for (const char* name : {"default", "wide", "camera", "angles"}) {
            const fs::path log = root / (std::string(name) + "_run.txt");
            const std::string cmd = std::string(PXH_BINARY) + " run " +
                                    (root / (std::string(name) + ".toml")).string() +
                                    " --quiet --out " + (root / name).string();
            if (sh(cmd, log) != 0) {
                failure += std::string(name) + ": " + slurp(log) + "\n";
                continue;
            }
            // the tables and data/ once per run: both widths draw from the same data
            const fs::path rep_log = root / (std::string(name) + "_report.txt");
            if (sh(std::string(PXH_BINARY) + " report --no-plots " + (root / name).string(),
                   rep_log) != 0)
                failure += std::string(name) + " report: " + slurp(rep_log) + "\n";
        }
    }
    static void TearDownTestSuite() { fs::remove_all(root); }
    // The checker draws every figure from the run's `pxh report --no-plots` data.
    void check(const std::string& run, const std::string& width) {
        ASSERT_TRUE(failure.empty()) << failure;
        const fs::path dir = root / run;
        const fs::path log = root / (run + "_" + width + ".txt");
        const std::string w = width == "single" ? "3.5" : "7";
        const int rc =
            sh("/usr/bin/python3 " + std::string(PXH_SOURCE_DIR) + "/tests/figure_text_check.py " +
                   std::string(PXH_SOURCE_DIR) + "/harness/report/plot_report.py " +
                   (dir / "report").string() + " " + w,
               log);
        const std::string out = slurp(log);
        EXPECT_EQ(rc, 0) << out;
        EXPECT_NE(out.find("checked "), std::string::npos) << out;
        EXPECT_EQ(out.find("collision:"), std::string::npos) << out;
    }
};
fs::path FigureCollisions::root;
std::string FigureCollisions::failure;

TEST_F(FigureCollisions, DefaultSingle) { check("default", "single"); }
TEST_F(FigureCollisions, DefaultDouble) { check("default", "double"); }
TEST_F(FigureCollisions, WideSingle) { check("wide", "single"); }
TEST_F(FigureCollisions, WideDouble) { check("wide", "double"); }
TEST_F(FigureCollisions, CameraSingle) { check("camera", "single"); }
TEST_F(FigureCollisions, CameraDouble) { check("camera", "double"); }
TEST_F(FigureCollisions, ManyAnglesSingle) { check("angles", "single"); }
TEST_F(FigureCollisions, ManyAnglesDouble) { check("angles", "double"); }

}  // namespace
