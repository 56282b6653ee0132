// [render]: a run writes pictures and the image-space columns for the render views only, the
// pictures agree with the columns, the report draws a montage per view and a strip (with a
// GIF), and every bad [render] key is one line naming the file and line.
#include <OpenImageIO/imagebuf.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "harness/core/error.h"
#include "harness/experiment/experiment.h"
#include "harness/results/csv_table.h"
#include "tests/cli_util.h"

namespace {

namespace fs = std::filesystem;

const std::string kExperiment = pxh::test::ExperimentToml("render")
                                    .samples(32)
                                    .backends("\"cpu\"")
                                    .theta("[0, 60, 80]")
                                    .field("bricks", 64)
                                    .field("sine", 64)
                                    .method("parallax")
                                    .method("pom", "layers = 32");

class Render : public pxh::test::CliTest {
  protected:
    std::vector<float> pixels(const fs::path& p) {
        OIIO::ImageBuf b(p.string());
        std::vector<float> v(size_t(b.spec().width) * size_t(b.spec().height) * 3);
        EXPECT_TRUE(b.get_pixels(OIIO::ROI(0, b.spec().width, 0, b.spec().height, 0, 1, 0, 3),
                                 OIIO::TypeDesc::FLOAT, v.data()))
            << p;
        return v;
    }
};

TEST_F(Render, PicturesColumnsAndFigures) {
    const std::string exp = write("exp.toml", std::string(kExperiment) + R"([render]
heightfields = ["bricks"]
theta_deg = [60]
strip_method = "pom"
)");
    const fs::path res = dir / "res";
    ASSERT_EQ(pxh("run " + exp + " --quiet --out " + res.string()).status, 0);
    const pxh::CsvTable t = pxh::read_csv((res / "results.csv").string());
    int pictures = 0;
    std::map<std::string, double> psnr60;
    for (size_t r = 0; r < t.rows.size(); ++r) {
        const std::string what = t.get(r, "method") + " " + t.get(r, "heightfield") + " θ" +
                                 t.get(r, "theta_deg") + " " + t.get(r, "backend");
        const double theta = t.number(r, "theta_deg");
        if (t.get(r, "heightfield") != "bricks") {  // not a render view: nothing
            for (const char* c : {"img_psnr_db", "img_ssim", "picture", "picture_use"})
                EXPECT_EQ(t.get(r, c), "") << what << " " << c;
            continue;
        }
        const double p = t.number(r, "img_psnr_db"), s = t.number(r, "img_ssim");
        if (std::isinf(p)) {  // identical pictures
            EXPECT_NEAR(s, 1.0, 1e-12) << what;
        } else {
            EXPECT_TRUE(std::isfinite(p) && s > 0 && s < 1) << what << " " << p << " " << s;
        }
        // Normal incidence: every method shows the truth; parallax never does at 60 and 80.
        if (theta == 0) {
            EXPECT_EQ(p, INFINITY) << what;
        } else if (t.get(r, "method") == "parallax") {
            EXPECT_TRUE(std::isfinite(p)) << what;
        }
        if (theta == 60) psnr60[t.get(r, "method") + t.get(r, "backend")] = p;
        const bool pom = t.get(r, "method") == "pom";
        const std::string use =
            theta == 60 ? (pom ? "montage strip" : "montage") : (pom ? "strip" : "");
        EXPECT_EQ(t.get(r, "picture_use"), use) << what;
        if (use.empty()) {
            EXPECT_EQ(t.get(r, "picture"), "") << what;
            continue;
        }
        ++pictures;
        // The files agree with the columns: diff = |picture - truth| (8-bit rounding), and
        // the PSNR of the written pictures is the column's (to quantisation).
        const auto pic = pixels(res / t.get(r, "picture"));
        const auto truth = pixels(res / t.get(r, "picture_truth"));
        const auto diff = pixels(res / t.get(r, "picture_diff"));
        ASSERT_EQ(pic.size(), 32u * 32u * 3u);
        double mse = 0, worst = 0;
        for (size_t i = 0; i < pic.size(); ++i) {
            mse += (pic[i] - truth[i]) * (pic[i] - truth[i]);
            worst = std::max(worst, double(std::fabs(diff[i] - std::fabs(pic[i] - truth[i]))));
        }
        EXPECT_LE(worst, 1.5 / 255) << what;
        mse /= double(pic.size());
        if (std::isfinite(p)) {
            EXPECT_NEAR(10 * std::log10(1 / mse), p, 0.2) << what;
        } else {
            EXPECT_EQ(mse, 0) << what;
        }
    }
    EXPECT_EQ(pictures, 3 + 1);                              // pom at 3 θ and parallax at 60
    EXPECT_GT(psnr60["pomcpu"], psnr60["parallaxcpu"] + 3);  // pom is far closer at 60°
    // The report: a montage of the view, a strip of pom with its GIF, images.md.
    ASSERT_EQ(pxh("report --no-plots " + res.string()).status, 0);
    EXPECT_NE(slurp(res / "report" / "images.md").find("bricks θ=60 φ=0"), std::string::npos);
    const std::string cmd = "/usr/bin/python3 " + std::string(PXH_SOURCE_DIR) +
                            "/harness/report/plot_report.py " + (res / "report").string() +
                            " --formats png >" + (dir / "plot.txt").string() + " 2>&1";
    ASSERT_EQ(std::system(cmd.c_str()), 0) << slurp(dir / "plot.txt");
    const auto manifest = nlohmann::json::parse(slurp(res / "report" / "figures.json"));
    std::map<std::string, nlohmann::json> figs;
    for (const auto& f : manifest.at("figures")) figs[f.at("name")] = f;
    ASSERT_TRUE(figs.count("picture_bricks_t60_p0")) << manifest.dump();
    EXPECT_EQ(figs["picture_bricks_t60_p0"]["series"], 2);  // parallax and pom
    EXPECT_EQ(figs["picture_bricks_t60_p0"]["panels"], 5);  // the truth, 2 x (picture, diff)
    ASSERT_TRUE(figs.count("strip_bricks_p0"));
    EXPECT_EQ(figs["strip_bricks_p0"]["panels"], 9);  // truth, pom, difference x 3 θ
    EXPECT_GT(fs::file_size(res / "report" / "strip_bricks_p0.gif"), 1000u);
    EXPECT_EQ(slurp(res / "report" / "strip_bricks_p0.gif").substr(0, 6), "GIF89a");
}

TEST(RenderKeys, BadKeysNameTheirLine) {
    struct Case {
        const char* render;
        const char* expect;
    };
    const Case cases[] = {
        {"heightfields = [\"nope\"]\ntheta_deg = [60]\n", "'nope' is no [[heightfields]]"},
        {"heightfields = [\"bricks\"]\ntheta_deg = [61]\n", "not one of [views] theta_deg"},
        {"heightfields = [\"bricks\"]\ntheta_deg = [60]\nphi_deg = 30\n",
         "not one of [views] phi_deg"},
        {"heightfields = [\"bricks\"]\ntheta_deg = [60]\nstrip_method = \"relief\"\n",
         "'relief' is no [[methods]]"},
        {"heightfields = [\"bricks\"]\ntheta_deg = [60]\nstrip = \"pom\"\n", "unknown key 'strip'"},
        {"heightfields = [\"bricks\"]\n", "[render] needs theta_deg"},
    };
    for (const auto& c : cases) {
        const std::string text = std::string(kExperiment) + "[render]\n" + c.render;
        std::string err;
        try {
            pxh::parse_experiment(text, "bad.toml");
        } catch (const pxh::InputError& e) {
            err = e.what();
        }
        EXPECT_NE(err.find(c.expect), std::string::npos) << c.render << ": " << err;
        EXPECT_NE(err.find("bad.toml:"), std::string::npos) << err;
    }
}

}  // namespace
