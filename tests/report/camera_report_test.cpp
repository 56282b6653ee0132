// The report of a perspective camera run (issue 46, item 4): its tables one per camera view
// (the camera's keys: distance, fov_deg, resolution), pixel error beside texel error, budgets
// ranked by pixel error first, sliding_dist / shimmering_dist in sweep.md, and the pictures'
// and maps' data carrying the view and the level mode.
#include <OpenImageIO/imagebuf.h>
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "harness/report/report.h"
#include "harness/results/csv_table.h"
#include "harness/results/error_maps.h"
#include "harness/results/results.h"
#include "tests/cli_util.h"
#include "tests/report/report_folder.h"

namespace {

namespace fs = std::filesystem;
using pxh::test::Cells;
using pxh::test::slurp;

const std::vector<std::string> kColumns = {
    "method",       "params",          "heightfield",    "scale",        "bias",
    "backend",      "precision",       "texture_format", "theta_deg",    "phi_deg",
    "samples",      "camera",          "distance",       "fov_deg",      "resolution",
    "lod",          "err_mean",        "err_p50",        "err_p95",      "err_p99",
    "frac_gt_1",    "nonfinite",       "fetches_mean",   "err_px_mean",  "err_px_p95",
    "sliding_dist", "shimmering_dist", "picture",        "picture_diff", "picture_truth",
    "picture_use",  "img_psnr_db",     "img_ssim",       "time",         "time_unit",
    "status"};

std::string num(double v) {
    char b[32];
    std::snprintf(b, sizeof b, "%.17g", v);
    return b;
}

// An ok CPU row of a perspective camera at θ and eye distance D (fov 45, resolution 64).
Cells row(const std::string& method, const std::string& lod, double theta, double distance,
          double err_mean, double err_p95, double px_mean, double px_p95, double fetches = 8) {
    return {{"method", method},
            {"params", ""},
            {"heightfield", "bricks"},
            {"scale", "0.05"},
            {"bias", "1"},
            {"backend", "cpu"},
            {"precision", "float"},
            {"theta_deg", num(theta)},
            {"phi_deg", "30"},
            {"samples", "64"},
            {"camera", "perspective"},
            {"distance", num(distance)},
            {"fov_deg", "45"},
            {"resolution", "64"},
            {"lod", lod},
            {"err_mean", num(err_mean)},
            {"err_p50", num(err_mean)},
            {"err_p95", num(err_p95)},
            {"err_p99", num(err_p95)},
            {"frac_gt_1", "0"},
            {"nonfinite", "0"},
            {"fetches_mean", num(fetches)},
            {"err_px_mean", num(px_mean)},
            {"err_px_p95", num(px_p95)},
            {"time", "10"},
            {"time_unit", "ns/sample"},
            {"status", "ok"}};
}

class CameraReport : public pxh::test::CliTest {
  protected:
    fs::path results(const std::vector<Cells>& rows) {
        return pxh::test::write_results_folder(dir, kColumns, rows);
    }
    static fs::path report(const fs::path& res) { return pxh::test::report_tables_of(res); }
    // The text of a Markdown section: from the line `heading` to the next heading of its level.
    static std::string section(const std::string& md, const std::string& heading) {
        const size_t at = md.find("\n" + heading + "\n");
        if (at == std::string::npos) return "";
        const std::string level = heading.substr(0, heading.find(' ') + 1);
        const size_t end = md.find("\n" + level, at + heading.size() + 2);
        return md.substr(at, end == std::string::npos ? std::string::npos : end - at);
    }
    static std::vector<std::string> md_row(const std::string& md, const std::string& first) {
        return pxh::test::markdown_row(md, first);
    }
};

// Two distances whose errors differ a hundredfold: a table each (never their mean), the pixel
// error beside the texel error, summary.csv and fields.csv keyed by the view.
TEST_F(CameraReport, SummaryIsPerViewWithPixelError) {
    const fs::path rep = report(results({
        row("pom", "base", 60, 1, 0.5, 1.0, 0.25, 0.5),
        row("pom", "base", 60, 16, 50, 100, 0.002, 0.004),
    }));
    const std::string md = slurp(rep / "summary.md");
    const std::string near = section(md, "## distance = 1, fov_deg = 45, resolution = 64");
    const std::string far = section(md, "## distance = 16, fov_deg = 45, resolution = 64");
    ASSERT_FALSE(near.empty()) << md;
    ASSERT_FALSE(far.empty()) << md;
    EXPECT_NE(near.find("60 <= θ < 75 † texel mean / p95 | 60 <= θ < 75 † pixel mean / p95"),
              std::string::npos)
        << near;
    EXPECT_EQ(md_row(near, "pom [cpu/float]").at(0), "0.500 / 1.000") << near;
    EXPECT_EQ(md_row(near, "pom [cpu/float]").at(1), "0.250 / 0.500") << near;
    EXPECT_EQ(md_row(far, "pom [cpu/float]").at(0), "50.000 / 100.000") << far;
    EXPECT_EQ(md_row(far, "pom [cpu/float]").at(1), "0.00200 / 0.00400") << far;
    EXPECT_EQ(md.find("25.250"), std::string::npos) << "a mean over distances: " << md;

    const pxh::CsvTable csv = pxh::read_csv((rep / "summary.csv").string());
    ASSERT_GE(csv.index("distance"), 0);
    ASSERT_GE(csv.index("err_px_p95"), 0);
    int lines = 0;
    for (size_t r = 0; r < csv.rows.size(); ++r) {
        if (csv.get(r, "band") != "all") continue;
        ++lines;
        const std::string d = csv.get(r, "distance");
        EXPECT_EQ(csv.get(r, "fov_deg"), "45");
        EXPECT_EQ(csv.get(r, "resolution"), "64");
        EXPECT_EQ(csv.get(r, "err_mean"), d == "1" ? "0.5" : "50") << d;
        EXPECT_EQ(csv.get(r, "err_px_p95"), d == "1" ? "0.5" : "0.004") << d;
    }
    EXPECT_EQ(lines, 2);

    const std::string fields = slurp(rep / "fields.md");
    EXPECT_NE(fields.find("### distance = 16, fov_deg = 45, resolution = 64"), std::string::npos)
        << fields;
    EXPECT_TRUE(fs::exists(rep / "fields" / "bricks_s_0.05_b_1_d1_f45_r64.tex"));
    EXPECT_TRUE(fs::exists(rep / "fields" / "bricks_s_0.05_b_1_d16_f45_r64.tex"));
    const std::string tex = slurp(rep / "summary.tex");
    EXPECT_NE(tex.find("Camera view: distance = 16, fov\\_deg = 45"), std::string::npos) << tex;
}

// Far away a cheap method's texel error is large but its pixel error small: the pixel budget
// picks it, the texel budget the dear one; both tables, per view.
TEST_F(CameraReport, BudgetRanksByPixelErrorThenTexelError) {
    const fs::path rep = report(results({
        row("parallax", "base", 60, 16, 3, 6, 0.01, 0.02, 1),
        row("pom", "base", 60, 16, 0.05, 0.1, 0.001, 0.002, 32),
        row("parallax", "base", 60, 1, 3, 6, 1.5, 3, 1),
        row("pom", "base", 60, 1, 0.05, 0.1, 0.02, 0.04, 32),
    }));
    const std::string md = slurp(rep / "budget.md");
    const std::string far = section(md, "## distance = 16, fov_deg = 45, resolution = 64");
    const std::string near = section(md, "## distance = 1, fov_deg = 45, resolution = 64");
    ASSERT_FALSE(far.empty()) << md;
    ASSERT_FALSE(near.empty()) << md;
    // pixel table first, then texel; the first row of each for budget 0.1
    const size_t px = far.find("| p95 budget (pixels) |"), tx = far.find("| p95 budget (texels) |");
    ASSERT_NE(px, std::string::npos) << far;
    ASSERT_NE(tx, std::string::npos) << far;
    EXPECT_LT(px, tx);
    EXPECT_EQ(md_row(far.substr(px, tx - px), "0.1").at(0), "parallax (1.0 fetches)") << far;
    EXPECT_EQ(md_row(far.substr(tx), "0.1").at(0), "pom (32.0 fetches)") << far;
    // near: parallax's pixel p95 of 3 meets only the budget 4
    const size_t npx = near.find("| p95 budget (pixels) |"),
                 ntx = near.find("| p95 budget (texels) |");
    EXPECT_EQ(md_row(near.substr(npx, ntx - npx), "0.1").at(0), "pom (32.0 fetches)") << near;
    EXPECT_EQ(md_row(near.substr(npx, ntx - npx), "4").at(0), "parallax (1.0 fetches)") << near;
    EXPECT_NE(md.find("`err_px_p95`"), std::string::npos);
}

// sliding_dist / shimmering_dist (on the nearer view's row) in sweep.md, a table per view.
TEST_F(CameraReport, SweepHasTheDistanceSweep) {
    auto a = row("pom", "base", 60, 1, 0.5, 1, 0.2, 0.4);
    a["sliding_dist"] = "0.125";
    a["shimmering_dist"] = "0.375";
    const fs::path rep = report(results({a, row("pom", "base", 60, 4, 0.5, 1, 0.05, 0.1)}));
    ASSERT_TRUE(fs::exists(rep / "sweep.md"));
    const std::string md = slurp(rep / "sweep.md");
    const std::string near = section(md, "## distance = 1, fov_deg = 45, resolution = 64");
    const std::string far = section(md, "## distance = 4, fov_deg = 45, resolution = 64");
    EXPECT_NE(near.find("sliding_dist / shimmering_dist"), std::string::npos) << md;
    EXPECT_EQ(md_row(near, "pom [cpu/float]").at(0), "0.125 / 0.375") << md;
    EXPECT_EQ(md_row(far, "pom [cpu/float]").at(0), "- / -") << md;
}

// pictures.csv, maps.csv and images.md carry the camera view and the level mode, so the
// pictures of D = 1 and 16 are never one montage, nor lod base and level one strip.
TEST_F(CameraReport, PicturesCarryTheViewAndLevelMode) {
    std::vector<Cells> rows;
    for (double d : {1.0, 16.0})
        for (const char* lod : {"base", "level"}) {
            Cells r = row("pom", lod, 60, d, 0.5, 1, 0.2, 0.4);
            const std::string tag = "_d" + num(d) + "_f45_r64";
            r["picture"] = "pictures/p" + tag + "_" + lod + ".png";
            r["picture_diff"] = "pictures/p" + tag + "_" + lod + "_diff.png";
            r["picture_truth"] = "pictures/truth_bricks_t60_p30" + tag + ".png";
            r["picture_use"] = "montage strip";
            r["img_psnr_db"] = d == 1 ? "20" : "40";
            r["img_ssim"] = "0.9";
            rows.push_back(r);
        }
    const fs::path rep = report(results(rows));
    const pxh::CsvTable pics = pxh::read_csv((rep / "data" / "pictures.csv").string());
    ASSERT_EQ(pics.rows.size(), 4u);
    for (const char* c : {"camera_view", "camera_tag", "lod", "distance", "fov_deg", "resolution"})
        ASSERT_GE(pics.index(c), 0) << c;
    for (size_t r = 0; r < pics.rows.size(); ++r) {
        const std::string d = pics.get(r, "distance");
        EXPECT_EQ(pics.get(r, "camera_view"), "distance=" + d + " fov_deg=45 resolution=64");
        EXPECT_EQ(pics.get(r, "camera_tag"), "_d" + d + "_f45_r64");
        EXPECT_NE(pics.get(r, "lod"), "");
    }
    const std::string md = slurp(rep / "images.md");
    EXPECT_NE(md.find("bricks θ=60 φ=30 distance=1 fov_deg=45 resolution=64 PSNR dB / SSIM"),
              std::string::npos)
        << md;
    EXPECT_NE(md.find("bricks θ=60 φ=30 distance=16 fov_deg=45 resolution=64 PSNR dB / SSIM"),
              std::string::npos)
        << md;
    // each distance's own numbers, lod level its own row
    EXPECT_EQ(md_row(md, "pom [cpu/float]").at(0), "20.0 / 0.900") << md;
    EXPECT_EQ(md_row(md, "pom [cpu/float]").at(1), "40.0 / 0.900") << md;
    EXPECT_EQ(md_row(md, "pom lod=level [cpu/float]").size(), 2u) << md;
}

// data/vs_theta.csv: a line per camera view (never a mean over distances), with its pixel
// error, so error_vs_theta and sweep_vs_theta are drawn per view.
TEST_F(CameraReport, VsThetaIsPerViewWithPixelError) {
    const fs::path rep = report(results({
        row("pom", "base", 60, 1, 0.5, 1.0, 0.25, 0.5),
        row("pom", "base", 60, 16, 50, 100, 0.002, 0.004),
    }));
    const pxh::CsvTable t = pxh::read_csv((rep / "data" / "vs_theta.csv").string());
    ASSERT_EQ(t.rows.size(), 2u);
    for (size_t r = 0; r < t.rows.size(); ++r) {
        const bool near = t.get(r, "camera_view") == "distance=1 fov_deg=45 resolution=64";
        EXPECT_EQ(t.get(r, "camera_tag"), near ? "_d1_f45_r64" : "_d16_f45_r64");
        EXPECT_EQ(t.get(r, "err_p95"), near ? "1" : "100");
        EXPECT_EQ(t.get(r, "err_px_p95"), near ? "0.5" : "0.004");
    }
}

// data/cost_vs_error_bands.csv: the points and Pareto fronts per camera view. Near, pom is on
// the front (less error than parallax); far away both are, each view on its own numbers.
TEST_F(CameraReport, CostPointsAndFrontsPerView) {
    const fs::path rep = report(results({
        row("parallax", "base", 60, 1, 3, 6, 1.5, 3, 1),
        row("pom", "base", 60, 1, 0.05, 0.1, 0.02, 0.04, 32),
        row("parallax", "base", 60, 16, 0.01, 6, 0.01, 0.02, 1),
        row("pom", "base", 60, 16, 0.05, 0.1, 0.001, 0.002, 32),
    }));
    const pxh::CsvTable t = pxh::read_csv((rep / "data" / "cost_vs_error_bands.csv").string());
    ASSERT_EQ(t.rows.size(), 4u);
    ASSERT_GE(t.index("camera_view"), 0);
    for (size_t r = 0; r < t.rows.size(); ++r) {
        const bool far = t.get(r, "camera_tag") == "_d16_f45_r64";
        const bool pom = t.get(r, "setting") == "pom";
        EXPECT_EQ(t.get(r, "err_mean"), far ? (pom ? "0.05" : "0.01") : (pom ? "0.05" : "3"));
        // far: parallax is cheaper and better, pom off the front; near both on it
        EXPECT_EQ(t.get(r, "pareto_fetches"), far && pom ? "0" : "1") << r;
    }
}

// A camera's error map lies as its pictures do: sample row j is PNG row n - 1 - j, and the
// samples outside the view are grey, not the magenta of a non-finite error.
TEST_F(CameraReport, CameraMapsAreAsSeenAndGreyOutside) {
    const int n = 16;
    std::vector<pxh::Vec2d> errors(size_t(n) * n);
    std::vector<uint8_t> inside(errors.size(), 1);
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const size_t at = size_t(j) * n + i;
            errors[at] = j < 8 ? pxh::Vec2d{16, 0} : pxh::Vec2d{1.0 / 16, 0};
            if (j < 4) {
                inside[at] = 0;
                errors[at] = {NAN, NAN};
            }
        }
    pxh::write_error_map(errors, n, (dir / "maps").string(), "cam", "a title", inside, true);
    OIIO::ImageBuf png((dir / "maps" / "cam.png").string());
    ASSERT_TRUE(png.read()) << png.geterror();
    const pxh::ErrorMapBox box = pxh::error_map_box(n);
    const int k = box.side / n;
    float lo[3], hi[3];
    pxh::error_colour(1.0 / 16, lo);
    pxh::error_colour(16, hi);
    const auto at = [&](int sample_row) {  // the colour of sample (0, sample_row) in the PNG
        float px[4];
        png.getpixel(box.x0 + k / 2, box.y0 + (n - 1 - sample_row) * k + k / 2, px);
        return std::vector<float>{px[0], px[1], px[2]};
    };
    const auto near = [](const std::vector<float>& a, const float* c) {
        for (int q = 0; q < 3; ++q)
            if (std::abs(a[size_t(q)] - c[q]) > 1.0f / 255) return false;
        return true;
    };
    const float grey[3] = {0.5f, 0.5f, 0.5f};
    EXPECT_TRUE(near(at(0), grey));
    EXPECT_TRUE(near(at(3), grey));
    EXPECT_TRUE(near(at(5), hi));
    EXPECT_TRUE(near(at(12), lo));
}

}  // namespace
