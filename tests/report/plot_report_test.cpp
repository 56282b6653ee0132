// harness/report/plot_report.py on small hand-written data files: every figure is written (PNG,
// SVG, PDF), with the panels and series the data call for (report/figures.json, the script's
// manifest of what it drew), series equal within 0.1% drawn once and unequal ones apart, the
// width asked for, TrueType fonts embedded in the PDF.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "harness/core/error.h"
#include "harness/report/report.h"
#include "tests/cli_util.h"

namespace {

namespace fs = std::filesystem;

using pxh::test::slurp;

// vs_theta.csv: two fields, two settings, CPU and GLSL. pom's GLSL numbers equal its CPU ones
// within 1e-5 relative (drawn once); parallax's GLSL p50 on "rock" is 10% higher (drawn apart).
const char* kVsTheta =
    "heightfield,series,method,params,backend,precision,texture_format,theta_deg,err_p50,err_p95,"
    "sliding,shimmering\n"
    "sand,s,pom,layers=8,cpu,float,,0,0,0,0.01,0.02\n"
    "sand,s,pom,layers=8,cpu,float,,60,0.5,1.5,,\n"
    "sand,s,pom,layers=8,glsl,float,r32f,0,0,0,0.01,0.02\n"
    "sand,s,pom,layers=8,glsl,float,r32f,60,0.500005,1.5,,\n"
    "sand,s,parallax,,cpu,float,,0,0,0,0.1,0.2\n"
    "sand,s,parallax,,cpu,float,,60,5,9,,\n"
    "sand,s,parallax,,glsl,float,r32f,0,0,0,0.1,0.2\n"
    "sand,s,parallax,,glsl,float,r32f,60,5,9,,\n"
    "rock,s,pom,layers=8,cpu,float,,0,0,0,0.01,0.02\n"
    "rock,s,pom,layers=8,cpu,float,,60,0.7,2,,\n"
    "rock,s,pom,layers=8,glsl,float,r32f,0,0,0,0.01,0.02\n"
    "rock,s,pom,layers=8,glsl,float,r32f,60,0.7,2,,\n"
    "rock,s,parallax,,cpu,float,,0,0,0,0.1,0.2\n"
    "rock,s,parallax,,cpu,float,,60,6,9,,\n"
    "rock,s,parallax,,glsl,float,r32f,0,0,0,0.1,0.2\n"
    "rock,s,parallax,,glsl,float,r32f,60,6.6,9,,\n";

const char* kCost =
    "series,setting,method,group,err_mean,err_p95,fetches_mean,time[ns/sample],time[ms/frame],"
    "pareto_fetches,pareto_time[ns/sample],pareto_time[ms/frame],params,backend,precision,"
    "texture_format\n"
    "a,pom layers=8,pom,cpu/float,0.3,1,17,50,,1,1,,layers=8,cpu,float,\n"
    "b,parallax,parallax,cpu/float,3,9,1,5,,1,1,,,cpu,float,\n"
    "c,pom layers=8,pom,glsl/r32f,0.3,1,17,,2,1,,1,layers=8,glsl,float,r32f\n"
    "d,parallax,parallax,glsl/r32f,3,9,1,,3,1,,0,,glsl,float,r32f\n";

// Two bands; fetches and errors equal on both backends (one row of panels for fetches), CPU
// ns/sample and GLSL ms/frame (two rows for time, one per unit). In band 1 a third setting,
// dominated, is off the fronts.
const char* kBands =
    "band,band_lo,band_hi,band_label,series,setting,group,err_mean,err_p95,fetches_mean,"
    "time[ns/sample],time[ms/frame],pareto_fetches,pareto_time[ns/sample],"
    "pareto_time[ms/frame],method,params,backend,precision,texture_format\n"
    "0,0,30,0 <= θ < 30 †,a,x,cpu/float,0.1,1,17,50,,1,1,,pom,layers=8,cpu,float,\n"
    "0,0,30,0 <= θ < 30 †,b,x,cpu/float,1,9,1,5,,1,1,,parallax,,cpu,float,\n"
    "0,0,30,0 <= θ < 30 †,c,x,glsl/r32f,0.1,1,17,,2,1,,1,pom,layers=8,glsl,float,r32f\n"
    "0,0,30,0 <= θ < 30 †,d,x,glsl/r32f,1,9,1,,3,1,,0,parallax,,glsl,float,r32f\n"
    "1,30,90,30 <= θ <= 90,a,x,cpu/float,0.5,1,17,50,,1,1,,pom,layers=8,cpu,float,\n"
    "1,30,90,30 <= θ <= 90,b,x,cpu/float,5,9,1,5,,1,1,,parallax,,cpu,float,\n"
    "1,30,90,30 <= θ <= 90,e,x,cpu/float,6,9,2,9,,0,0,,steep,layers=8,cpu,float,\n"
    "1,30,90,30 <= θ <= 90,c,x,glsl/r32f,0.5,1,17,,2,1,,1,pom,layers=8,glsl,float,r32f\n"
    "1,30,90,30 <= θ <= 90,d,x,glsl/r32f,5,9,1,,3,1,,0,parallax,,glsl,float,r32f\n"
    "1,30,90,30 <= θ <= 90,f,x,glsl/r32f,6,9,2,,4,0,,0,steep,layers=8,glsl,float,r32f\n";

class PlotScript : public ::testing::Test {
  protected:
    fs::path dir, drawn;
    int drawings = 0;
    void SetUp() override {
        dir =
            fs::temp_directory_path() / ("pxh_plot_test_" + std::to_string(::getpid())) / "report";
        fs::remove_all(dir.parent_path());
        fs::create_directories(dir / "data");
        std::ofstream(dir / "data" / "vs_theta.csv") << kVsTheta;
        std::ofstream(dir / "data" / "cost_vs_error.csv") << kCost;
        std::ofstream(dir / "data" / "cost_vs_error_bands.csv") << kBands;
    }
    void TearDown() override { fs::remove_all(dir.parent_path()); }
    // Runs the script, drawing into a new folder (`drawn`: it creates only new files); returns
    // its manifest's figures by name.
    std::map<std::string, nlohmann::json> plot(const std::string& width,
                                               const std::string& formats = "png,svg,pdf") {
        drawn = dir / ("drawn" + std::to_string(++drawings));
        fs::create_directories(drawn);
        const std::string cmd = "/usr/bin/python3 " + std::string(PXH_SOURCE_DIR) +
                                "/harness/report/plot_report.py " + dir.string() + " --into " +
                                drawn.string() + " --width " + width + " --formats " + formats +
                                " >" + (dir / "out.txt").string() + " 2>&1";
        EXPECT_EQ(std::system(cmd.c_str()), 0) << slurp(dir / "out.txt");
        const auto manifest = nlohmann::json::parse(slurp(drawn / "figures.json"));
        EXPECT_EQ(manifest.at("width_in").get<double>(), std::stod(width));
        std::map<std::string, nlohmann::json> out;
        for (const auto& f : manifest.at("figures")) out[f.at("name")] = f;
        return out;
    }
    // A PNG's width in pixels (IHDR, bytes 16..19, big-endian).
    int png_width(const std::string& name) {
        const std::string b = slurp(drawn / name);
        if (b.size() < 24) return 0;
        return (uint8_t(b[16]) << 24) | (uint8_t(b[17]) << 16) | (uint8_t(b[18]) << 8) |
               uint8_t(b[19]);
    }
};

TEST_F(PlotScript, EveryFigureWithItsPanelsAndSeries) {
    auto figs = plot("7");
    ASSERT_EQ(figs.size(), 4u);
    for (const auto& [name, f] : figs)
        for (const char* ext : {".png", ".svg", ".pdf"})
            EXPECT_GT(fs::file_size(drawn / (name + ext)), 1000u) << name << ext;
    // error vs θ: a panel per field; sand: pom and parallax once each (GLSL = CPU within
    // 0.1%); rock: pom once, parallax twice (10% apart) -> 5 lines.
    EXPECT_EQ(figs["error_vs_theta"]["panels"], 2);
    EXPECT_EQ(figs["error_vs_theta"]["series"], 5);
    const std::string note = figs["error_vs_theta"]["note"];
    EXPECT_NE(note.find("cpu/float = glsl/r32f"), std::string::npos) << note;
    const auto legend = figs["error_vs_theta"]["legend"].dump();
    for (const char* l : {"\"pom layers=8\"", "\"parallax\"", "\"cpu/float\"", "\"glsl/r32f\""})
        EXPECT_NE(legend.find(l), std::string::npos) << l << " not in " << legend;
    // sweeps: sliding and shimmering per field, every curve equal on both backends.
    EXPECT_EQ(figs["sweep_vs_theta"]["panels"], 4);
    EXPECT_EQ(figs["sweep_vs_theta"]["series"], 8);
    // error vs fetches: both backends' points equal -> one row of panels, one per band;
    // the fronts drawn through the flagged points of each panel (2 in band 0, 2 in band 1).
    EXPECT_EQ(figs["cost_vs_error"]["panels"], 2);
    EXPECT_EQ(figs["cost_vs_error"]["rows"].dump(), "[\"cpu/float = glsl/r32f\"]");
    EXPECT_EQ(figs["cost_vs_error"]["front_points"].dump(), "[2,2]");
    EXPECT_EQ(figs["cost_vs_error"]["series"], 3);
    // error vs time: a row of two bands per time unit, labelled with it.
    EXPECT_EQ(figs["time_vs_error"]["panels"], 4);
    EXPECT_EQ(figs["time_vs_error"]["x_labels"].dump(),
              "[\"time (ns/sample)\",\"time (ms/frame)\"]");
    EXPECT_EQ(figs["cost_vs_error"]["x_labels"].dump(), "[\"fetches / sample\"]");
    EXPECT_EQ(figs["time_vs_error"]["front_points"].dump(), "[2,2,1,1]");
    // Width: 7 in at 300 dpi (the tight box trims the margins only).
    const int w = png_width("error_vs_theta.png");
    EXPECT_GT(w, 0.85 * 7 * 300);
    EXPECT_LT(w, 1.05 * 7 * 300);
    // Fonts embedded as TrueType (Type 42): FontFile2 streams, no Type 3 fonts.
    const std::string pdf = slurp(drawn / "error_vs_theta.pdf");
    EXPECT_NE(pdf.find("/FontFile2"), std::string::npos);
    EXPECT_EQ(pdf.find("/Type3"), std::string::npos);
}

TEST_F(PlotScript, SingleColumnWidthAndBadWidth) {
    auto figs = plot("3.5", "png");  // PNG only: the test stays short
    EXPECT_EQ(figs["error_vs_theta"]["panels"], 2);
    const int w = png_width("cost_vs_error.png");
    EXPECT_GT(w, 0.85 * 3.5 * 300);
    EXPECT_LT(w, 1.05 * 3.5 * 300);
    for (const char* bad : {" --width 0.5", " --formats png,jpg"}) {
        const std::string cmd = "/usr/bin/python3 " + std::string(PXH_SOURCE_DIR) +
                                "/harness/report/plot_report.py " + dir.string() + bad +
                                " >/dev/null 2>&1";
        EXPECT_NE(std::system(cmd.c_str()), 0) << bad;
    }
}

// Any name draws: a 3000-character parameter (a plug-in's uniform) and a field named outside
// Latin-1; legend entries are shortened in the middle to fit the width.
TEST_F(PlotScript, LongAndNonLatinNamesDraw) {
    const std::string longp = "layers=8;p_" + std::string(3000, 'u') + "=1";
    for (const char* f : {"vs_theta.csv", "cost_vs_error.csv", "cost_vs_error_bands.csv"}) {
        std::string t = slurp(dir / "data" / f);
        for (size_t at = 0; (at = t.find("layers=8", at)) != std::string::npos; at += longp.size())
            t.replace(at, 8, longp);
        for (size_t at = 0; (at = t.find("sand,", at)) != std::string::npos; at += 7)
            t.replace(at, 5, "砂岩,");
        std::ofstream(dir / "data" / f, std::ios::binary) << t;
    }
    auto figs = plot("3.5", "png");
    ASSERT_EQ(figs.size(), 4u);
    for (const auto& [name, f] : figs)
        for (const auto& label : f["legend"]) {
            const std::string l = label;
            EXPECT_LT(l.size(), 120u) << name << ": " << l.substr(0, 200);
        }
    const std::string legend = figs["error_vs_theta"]["legend"].dump();
    EXPECT_NE(legend.find("pom layers=8, p_uuu"), std::string::npos) << legend;
    EXPECT_NE(legend.find("…"), std::string::npos) << legend;
    EXPECT_LT(png_width("error_vs_theta.png"), 1.05 * 3.5 * 300);
}

// A camera run's pictures: a montage per view (D = 1 and 16 never under one truth), a strip
// per view and level mode (never six panels "θ = 45°"), named and titled by the view.
TEST_F(PlotScript, CameraPicturesPerViewAndLevelMode) {
    std::string csv =
        "heightfield,theta_deg,phi_deg,series,method,params,backend,precision,texture_format,"
        "img_psnr_db,img_ssim,picture,picture_diff,picture_truth,picture_use,camera_view,"
        "camera_tag,lod,distance,fov_deg,resolution\n";
    for (const char* d : {"1", "16"})
        for (const char* lod : {"base", "level"})
            for (const char* th : {"30", "60"}) {
                const std::string tag = std::string("_d") + d + "_f45_r64";
                const std::string params =
                    std::string(lod) == "base" ? "layers=8" : "layers=8;lod=level";
                csv += std::string("bricks,") + th + ",30,s,pom," + params +
                       ",cpu,float,,30,0.9,pictures/a.png,pictures/b.png,pictures/t" + tag +
                       ".png," + (std::string(th) == "60" ? "montage strip" : "strip") +
                       ",distance=" + d + " fov_deg=45 resolution=64," + tag + "," + lod + "," + d +
                       ",45,64\n";
            }
    std::ofstream(dir / "data" / "pictures.csv") << csv;
    auto figs = plot("3.5", "png");
    for (const char* d : {"1", "16"}) {
        const std::string tag = std::string("_d") + d + "_f45_r64";
        ASSERT_TRUE(figs.count("picture_bricks_t60_p30" + tag)) << tag;
        // the truth, then base and level each over its difference
        EXPECT_EQ(figs["picture_bricks_t60_p30" + tag]["panels"], 5);
        for (const std::string lod : {"", "_level"}) {
            ASSERT_TRUE(figs.count("strip_bricks_p30" + tag + lod)) << tag << lod;
            EXPECT_EQ(figs["strip_bricks_p30" + tag + lod]["panels"], 6);  // 3 x two θ
        }
    }
    EXPECT_FALSE(figs.count("picture_bricks_t60_p30"));
    EXPECT_FALSE(figs.count("strip_bricks_p30"));
}

// A camera run's vs_theta.csv: error_vs_theta and sweep_vs_theta per camera view, named by its
// tag; error_vs_theta with the pixel error below the texel error (a panel each per field).
TEST_F(PlotScript, ErrorVsThetaPerCameraView) {
    std::string csv = slurp(dir / "data" / "vs_theta.csv");
    std::istringstream in(csv);
    std::string header, out;
    std::getline(in, header);
    out = header + ",camera_view,camera_tag,err_px_p50,err_px_p95\n";
    for (std::string line; std::getline(in, line);)
        for (const char* d : {"1", "16"})
            out += line + ",distance=" + d + " fov_deg=45,_d" + d + "_f45," +
                   (std::string(d) == "1" ? "0.1,0.2" : "0.001,0.002") + "\n";
    std::ofstream(dir / "data" / "vs_theta.csv") << out;
    auto figs = plot("3.5", "png");
    for (const std::string d : {"1", "16"}) {
        const std::string tag = "_d" + d + "_f45";
        ASSERT_TRUE(figs.count("error_vs_theta" + tag)) << tag;
        EXPECT_EQ(figs["error_vs_theta" + tag]["panels"], 4);  // 2 fields x texel, pixel
        ASSERT_TRUE(figs.count("sweep_vs_theta" + tag)) << tag;
        const std::string note = figs["error_vs_theta" + tag]["note"];
        EXPECT_NE(note.find("camera: distance = " + d + ", fov_deg = 45"), std::string::npos)
            << note;
    }
    EXPECT_FALSE(figs.count("error_vs_theta"));
}

// A camera run's cost_vs_error_bands.csv: cost_vs_error and time_vs_error per camera view.
TEST_F(PlotScript, CostFiguresPerCameraView) {
    std::istringstream in(slurp(dir / "data" / "cost_vs_error_bands.csv"));
    std::string header, out;
    std::getline(in, header);
    out = header + ",camera_view,camera_tag\n";
    for (std::string line; std::getline(in, line);)
        for (const char* d : {"1", "16"}) out += line + ",distance=" + d + ",_d" + d + "\n";
    std::ofstream(dir / "data" / "cost_vs_error_bands.csv") << out;
    auto figs = plot("3.5", "png");
    for (const char* name :
         {"cost_vs_error_d1", "cost_vs_error_d16", "time_vs_error_d1", "time_vs_error_d16"})
        EXPECT_TRUE(figs.count(name)) << name;
    EXPECT_FALSE(figs.count("cost_vs_error"));
    EXPECT_EQ(figs["cost_vs_error_d16"]["panels"], 2);  // a panel per band, as before
    EXPECT_NE(figs["cost_vs_error_d16"]["legend"].dump().find("pom"), std::string::npos);
}

// error_vs_distance: one figure per field, named by it; the pixel panels ticked down to their
// smallest values (1e-3 here), not 0 and 0.1 only.
TEST_F(PlotScript, ErrorVsDistanceNamedByFieldAndTickedToItsValues) {
    std::string csv =
        "heightfield,theta_deg,series,method,params,backend,precision,texture_format,distance,"
        "err_p50,err_p95,err_px_p50,err_px_p95,lod_mean\n";
    for (const char* f : {"bricks s=0.05 b=1", "fbm s=0.05 b=1"})
        for (const char* th : {"30", "60"})
            for (const auto& [d, px] : std::vector<std::pair<const char*, const char*>>{
                     {"1", "0.08"}, {"4", "0.01"}, {"16", "0.0015"}})
                csv += std::string("\"") + f + "\"," + th + ",s,pom,layers=8,cpu,float,," + d +
                       ",0.5,1," + px + "," + px + ",0\n";
    std::ofstream(dir / "data" / "vs_distance.csv") << csv;
    for (const char* width : {"3.5", "7"}) {
        auto figs = plot(width, "png");
        ASSERT_TRUE(figs.count("error_vs_distance_bricks_s_0.05_b_1")) << width;
        ASSERT_TRUE(figs.count("error_vs_distance_fbm_s_0.05_b_1")) << width;
        EXPECT_FALSE(figs.count("error_vs_distance_1"));
        const auto ticks = figs["error_vs_distance_bricks_s_0.05_b_1"]["y_ticks"]["pixel error"];
        double smallest = 1;
        for (const auto& t : ticks)
            if (t.get<double>() > 0) smallest = std::min(smallest, t.get<double>());
        EXPECT_LE(smallest, 0.0015) << ticks.dump();
        EXPECT_GE(ticks.size(), 3u) << ticks.dump();
    }
}

// Error maps of many view angles (θ 0 to 85 in steps of 5): the column heads fit at single
// and double width, no two touching (tests/figure_text_check.py on the drawn figure).
TEST_F(PlotScript, ErrorMapHeadsFitAtManyAngles) {
    std::string maps =
        "heightfield,phi_deg,series,method,params,backend,precision,texture_format,theta_deg,"
        "map,map_x0,map_y0,map_side,camera_view,camera_tag,lod\n";
    for (const char* m : {"pom", "parallax"})
        for (int th = 0; th <= 85; th += 5)
            maps += std::string("bricks,0,s,") + m + ",,cpu,float,," + std::to_string(th) +
                    ",maps/x.png,0,28,384,,,base\n";
    std::ofstream(dir / "data" / "maps.csv") << maps;
    std::string scale = "log2_texels,r,g,b\n";
    for (int k = 0; k <= 8; ++k) scale += std::to_string(k - 4) + ",0.5,0.5,0.5\n";
    std::ofstream(dir / "data" / "error_scale.csv") << scale;
    for (const char* width : {"3.5", "7"}) {
        const fs::path log = dir.parent_path() / "check.txt";
        const std::string cmd = "/usr/bin/python3 " + std::string(PXH_SOURCE_DIR) +
                                "/tests/figure_text_check.py " + std::string(PXH_SOURCE_DIR) +
                                "/harness/report/plot_report.py " + dir.string() + " " + width +
                                " >" + log.string() + " 2>&1";
        const int rc = std::system(cmd.c_str());
        const std::string out = slurp(log);
        EXPECT_EQ(rc, 0) << width << ": " << out;
        EXPECT_EQ(out.find("collision"), std::string::npos) << width << ": " << out;
        EXPECT_NE(out.find("checked "), std::string::npos) << out;
    }
}

}  // namespace

namespace {

TEST(FigureWidth, PresetsAndInches) {
    EXPECT_EQ(pxh::parse_figure_width("single"), 3.5);
    EXPECT_EQ(pxh::parse_figure_width("double"), 7.0);
    EXPECT_EQ(pxh::parse_figure_width("4.75"), 4.75);
    for (const char* bad : {"", "Single", "7in", "1.9", "20.5", "nan", "inf", "-3"})
        EXPECT_THROW(pxh::parse_figure_width(bad), pxh::InputError) << bad;
}

}  // namespace
