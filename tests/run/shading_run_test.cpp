// [shading] through pxh run: every ok row gets flip_mean, flip_p95 and flip_max; a flat field
// (every method shows the truth's uv) gives FLIP 0 up to 8-bit rounding, bricks do not; the
// [render] views' shaded PNGs give the column's FLIP back when recomputed from the files; the
// columns reach pxh check, budget.md and the image family's table; bad [shading] keys are one
// line naming the file and line.
#include <OpenImageIO/imagebuf.h>

#include <cmath>

#include "harness/core/error.h"
#include "harness/experiment/experiment.h"
#include "harness/metrics/flip.h"
#include "harness/results/csv_table.h"
#include "tests/cli_util.h"

namespace {

namespace fs = std::filesystem;

const std::string kExperiment = std::string(pxh::test::ExperimentToml("shading")
                                                .samples(48)
                                                .backends("\"cpu\"")
                                                .theta("[0, 60]")
                                                .field("bricks", 64)
                                                .field("flat", 16)
                                                .method("parallax")
                                                .method("pom", "layers = 32")) +
                                "[shading]\nalbedo_size = 128\n";

std::vector<float> pixels(const fs::path& p) {
    OIIO::ImageBuf b(p.string());
    std::vector<float> v(size_t(b.spec().width) * size_t(b.spec().height) * 3);
    EXPECT_TRUE(b.get_pixels(OIIO::ROI(0, b.spec().width, 0, b.spec().height, 0, 1, 0, 3),
                             OIIO::TypeDesc::FLOAT, v.data()))
        << p;
    return v;
}

class ShadingRun : public pxh::test::CliTest {};

TEST_F(ShadingRun, FlipColumnsFilesCheckAndBudget) {
    const std::string exp = write("exp.toml", kExperiment +
                                                  "[render]\nheightfields = "
                                                  "[\"bricks\"]\ntheta_deg = [60]\n");
    const fs::path res = dir / "res";
    ASSERT_EQ(pxh("run " + exp + " --quiet --out " + res.string()).status, 0);
    const pxh::CsvTable t = pxh::read_csv((res / "results.csv").string());
    std::map<std::string, double> bricks60;
    int files = 0;
    for (size_t r = 0; r < t.rows.size(); ++r) {
        const std::string what =
            t.get(r, "method") + " " + t.get(r, "heightfield") + " θ" + t.get(r, "theta_deg");
        const double mean = t.number(r, "flip_mean"), p95 = t.number(r, "flip_p95"),
                     mx = t.number(r, "flip_max");
        ASSERT_TRUE(std::isfinite(mean) && std::isfinite(p95) && std::isfinite(mx)) << what;
        EXPECT_TRUE(mean >= 0 && mean <= mx && p95 <= mx && mx <= 1) << what;
        if (t.get(r, "heightfield") == "flat" || t.number(r, "theta_deg") == 0) {
            EXPECT_LT(mean, 1e-3) << what;  // the method shows the truth's uv
        }
        if (t.get(r, "heightfield") == "bricks" && t.number(r, "theta_deg") == 60)
            bricks60[t.get(r, "method")] = mean;
        if (t.get(r, "flip_map").empty()) continue;
        ++files;
        // The files hold the values FLIP was computed on: recomputed from them, the column.
        const auto img = pixels(res / t.get(r, "shaded"));
        const auto truth = pixels(res / t.get(r, "shaded_truth"));
        ASSERT_EQ(img.size(), 48u * 48u * 3u);
        const pxh::FlipResult f =
            pxh::flip_ldr({truth, 48, 48, pxh::FlipEncoding::srgb},
                          {img, 48, 48, pxh::FlipEncoding::srgb}, pxh::kFlipDefaultPpd);
        EXPECT_NEAR(f.mean, mean, 1e-5) << what;
        EXPECT_NEAR(f.max, mx, 1e-5) << what;
        EXPECT_TRUE(fs::is_regular_file(res / t.get(r, "flip_map"))) << what;
    }
    EXPECT_EQ(files, 2);  // bricks at 60: parallax and pom
    // The authors' tool (NVlabs/flip 1eb247ca, flip-tool v1.6, default 67 ppd) on these two
    // shaded PNG pairs printed Mean / Max: parallax 0.095065 / 0.668292, pom 0.001502 /
    // 0.023245 (to its six decimals): a shaded parallax picture's FLIP, recorded to issue 63's
    // tolerances, 1e-4 in the mean and an 8-bit step in a pixel (pxh's agree to 1e-6 and 3e-6;
    // one pixel of pom's map lies one magma entry from the tool's, a float rounding apart).
    const std::map<std::string, std::pair<double, double>> authors = {
        {"parallax", {0.095065, 0.668292}}, {"pom", {0.001502, 0.023245}}};
    for (size_t r = 0; r < t.rows.size(); ++r) {
        if (t.get(r, "flip_map").empty()) continue;
        const auto& [mean, mx] = authors.at(t.get(r, "method"));
        EXPECT_NEAR(t.number(r, "flip_mean"), mean, 1e-4) << t.get(r, "method");
        EXPECT_NEAR(t.number(r, "flip_max"), mx, 1.0 / 255) << t.get(r, "method");
    }
    EXPECT_GT(bricks60["parallax"], 2 * bricks60["pom"]);
    // pxh check takes flip limits like any column's.
    const std::string lim = write("lim.toml",
                                  "[[limit]]\nmethod = \"pom\"\ncolumn = "
                                  "\"flip_mean\"\nmax = 0.5\n[[limit]]\nmethod = "
                                  "\"parallax\"\ncolumn = \"flip_max\"\nmax = 1e-9\n");
    const pxh::test::CliResult c = pxh("check " + res.string() + " --thresholds " + lim);
    EXPECT_EQ(c.status, 1) << c.out << c.err;
    EXPECT_NE(c.out.find("1 passed, 1 failed"), std::string::npos) << c.out;
    // The report: budget.md ranks by flip_mean too; the image family tables it.
    ASSERT_EQ(pxh("report --no-plots " + res.string()).status, 0);
    const std::string budget = pxh::test::slurp(res / "report" / "budget.md");
    EXPECT_NE(budget.find("# Perceptual budgets (flip_mean)"), std::string::npos) << budget;
    EXPECT_NE(budget.find("| 0.05 |"), std::string::npos) << budget;
    const std::string image = pxh::test::slurp(res / "report" / "families" / "image.md");
    EXPECT_NE(image.find("## flip_mean"), std::string::npos) << image;
}

// The GLSL backend shades its rows with the GLSL twin in its GL process: every GLSL row's image
// within one 8-bit step of the CPU twin's shading of the same uv (shade_cpu_diff_max), and its
// FLIP next to the CPU row's.
TEST_F(ShadingRun, GlslRowsShadeInTheirOwnShader) {
    const std::string exp = write(
        "exp.toml", std::string(pxh::test::ExperimentToml("shading_gl")
                                    .samples(32)
                                    .backends("\"cpu\", \"glsl\"")
                                    .theta("[60]")
                                    .view("camera", "\"perspective\"")
                                    .view("distance", "[1.5]")
                                    .field("bricks", 64)
                                    .method("pom", "layers = 16\nlod = [\"base\", \"level\"]")) +
                        "[shading]\nalbedo_size = 128\n");
    const fs::path res = dir / "res";
    ASSERT_EQ(pxh("run " + exp + " --quiet --out " + res.string()).status, 0);
    const pxh::CsvTable t = pxh::read_csv((res / "results.csv").string());
    std::map<std::string, double> cpu, glsl;
    for (size_t r = 0; r < t.rows.size(); ++r) {
        const std::string lod = t.get(r, "lod");
        if (t.get(r, "backend") == "cpu") {
            EXPECT_EQ(t.get(r, "shade_cpu_diff_max"), "") << lod;  // shaded by the CPU twin
            cpu[lod] = t.number(r, "flip_mean");
            continue;
        }
        EXPECT_LE(t.number(r, "shade_cpu_diff_max"), 1) << lod;
        glsl[lod] = t.number(r, "flip_mean");
    }
    ASSERT_EQ(glsl.size(), 2u);
    for (const auto& [lod, f] : glsl) EXPECT_NEAR(f, cpu[lod], 2e-3) << lod;
}

// Under a `samples` subset of a camera's image the whole image is shaded: the flip columns
// are the full run's, to the digit, while the texel statistics are the subset's.
TEST_F(ShadingRun, SubsetShadesTheWholeImage) {
    const std::string exp =
        write("exp.toml", std::string(pxh::test::ExperimentToml("shading_subset")
                                          .samples(32)
                                          .backends("\"cpu\"")
                                          .theta("[60]")
                                          .view("camera", "\"perspective\"")
                                          .view("distance", "[1.5]")
                                          .field("bricks", 64)
                                          .method("parallax")
                                          .method("pom", "layers = 16")) +
                              "[shading]\nalbedo_size = 128\n");
    ASSERT_EQ(pxh("run " + exp + " --quiet --out " + (dir / "all").string()).status, 0);
    ASSERT_EQ(pxh("run " + exp + " --quiet --samples 16 --out " + (dir / "sub").string()).status,
              0);
    const pxh::CsvTable all = pxh::read_csv((dir / "all" / "results.csv").string());
    const pxh::CsvTable sub = pxh::read_csv((dir / "sub" / "results.csv").string());
    ASSERT_EQ(all.rows.size(), sub.rows.size());
    for (size_t r = 0; r < all.rows.size(); ++r) {
        EXPECT_EQ(sub.get(r, "samples"), "16");
        EXPECT_NE(sub.get(r, "flip_mean"), "") << r;
        for (const char* c : {"flip_mean", "flip_p95", "flip_max"})
            EXPECT_EQ(sub.get(r, c), all.get(r, c)) << r << " " << c;
    }
}

TEST(ShadingKeys, BadKeysAndFilesNameTheirLine) {
    struct Case {
        const char* shading;
        const char* expect;
    };
    const Case cases[] = {
        {"light = 3\n", "unknown key 'light' in [shading]"},
        {"albedo = \"no_such_albedo.png\"\n", "albedo file"},
        {"elevation_deg = 95\n", "elevation_deg = 95 must lie in [0, 90]"},
        {"ppd = 1\n", "ppd = 1 must lie in [2, 1000]"},
        {"albedo = \"tile.png\"\nalbedo_size = 64\n", "albedo_size is the checker's size"},
    };
    for (const auto& c : cases) {
        const std::string base = kExperiment.substr(0, kExperiment.find("[shading]"));
        const std::string text = base + "[shading]\n" + c.shading;
        std::string err;
        try {
            pxh::parse_experiment(text, "bad.toml");
        } catch (const pxh::InputError& e) {
            err = e.what();
        }
        EXPECT_NE(err.find(c.expect), std::string::npos) << c.shading << ": " << err;
        EXPECT_NE(err.find("bad.toml:"), std::string::npos) << err;
        EXPECT_EQ(err.find('\n'), std::string::npos) << err;  // one line
    }
}

}  // namespace
