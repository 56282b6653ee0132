// WGSL plug-ins (harness/backends/wgsl_shader.cpp, naga) through the binary: the Bevy-style
// example against bevy_occlusion sample by sample, and the refusals at the WGSL file's
// FILE:LINE:COL. (The same POM in GLSL, HLSL and WGSL: HlslShader.)
#include <gtest/gtest.h>

#include <filesystem>

#include "harness/results/csv_table.h"
#include "tests/cli_util.h"

namespace fs = std::filesystem;

namespace {

class WgslShader : public pxh::test::CliTest {
  protected:
    std::string refused(const std::string& toml) {
        write("exp.toml", toml);
        const auto r =
            pxh("run " + (dir / "exp.toml").string() + " --quiet --out " + (dir / "r").string());
        EXPECT_EQ(r.status, 2) << r.out << r.err;
        EXPECT_FALSE(fs::exists(dir / "r")) << "nothing written";
        return r.err;
    }
};

// examples/engines/bevy as committed: every sample within float rounding of bevy_occlusion's CPU
// twin (its unclamped interpolation weight multiplies rounding: measured 3.7e-4 texel at most,
// as the preset against the literal loop), every fetch count equal.
TEST_F(WgslShader, BevyExampleMatchesBevyOcclusionPreset) {
    const fs::path ex = fs::path(PXH_SOURCE_DIR) / "examples/engines/bevy/experiment.toml";
    const auto r = pxh("run " + ex.string() + " --quiet --out " + (dir / "r").string());
    ASSERT_EQ(r.status, 0) << r.err;
    const pxh::CsvTable t = pxh::read_csv((dir / "r" / "results.csv").string());
    ASSERT_EQ(t.rows.size(), 30u);
    double worst = 0, fetches = 0;
    for (size_t i = 0; i < t.rows.size(); ++i) {
        const std::string at = t.get(i, "heightfield") + " theta " + t.get(i, "theta_deg") +
                               " phi " + t.get(i, "phi_deg");
        EXPECT_EQ(t.get(i, "status"), "ok") << at;
        EXPECT_EQ(t.get(i, "decision_mismatch"), "0") << at;
        EXPECT_EQ(t.get(i, "cpu_diff_first"), "") << at;
        worst = std::max(worst, std::stod(t.get(i, "cpu_diff_max")));
        fetches = std::max(fetches, std::stod(t.get(i, "fetches_max")));
        if (t.get(i, "theta_deg") == "0") {
            EXPECT_EQ(t.get(i, "fetches_max"), "3") << at << ": one layer head-on";
        }
    }
    EXPECT_LE(worst, 1e-3);
    EXPECT_GT(worst, 1e-6) << "the two twins differ in rounding somewhere";
    EXPECT_EQ(fetches, 16) << "the most fetches of a sample (theta 85 on fbm), as the preset";
}

// Refusals at the WGSL file's FILE:LINE:COL: naga's parse error, naga_oil's preprocessor
// lines, the height texture used otherwise than sampled; defines at the file.
TEST_F(WgslShader, RefusalsNameTheWgslFileAndLine) {
    const std::string head = pxh::test::ExperimentToml()
                                 .samples(8)
                                 .backends("\"glsl\"")
                                 .theta("[30]")
                                 .phi("[0]")
                                 .field("fbm", 64, "scale = 0.05\nbias = 1.0")
                                 .str();
    const auto entry = [](const char* shader, const std::string& more = "") {
        return std::string("[[methods]]\nname = \"w\"\nshader = \"") + shader +
               "\"\nheight_sampler = \"hm\"\nmax_fetches = 3\n" + more;
    };
    write("syntax.wgsl",
          "fn pxh_method(P: vec2<f32>) -> vec2<f32> {\n    let a = P\n    return a;\n}\n");
    write(
        "import.wgsl",
        "#import bevy_pbr::pbr_bindings\nfn pxh_method(P: vec2<f32>) -> vec2<f32> { return P; }\n");
    write("load.wgsl",
          "@group(0) @binding(0) var hm: texture_2d<f32>;\nfn pxh_method(P: vec2<f32>) -> "
          "vec2<f32> {\n    return P + textureLoad(hm, vec2<i32>(0, 0), 0).r;\n}\n");
    const std::string syntax = refused(head + entry("syntax.wgsl"));
    EXPECT_NE(syntax.find("syntax.wgsl:3:5: error: expected `;`, found \"return\" (naga)"),
              std::string::npos)
        << syntax;
    EXPECT_NE(
        refused(head + entry("import.wgsl")).find("import.wgsl:1:1: a WGSL plug-in is plain WGSL"),
        std::string::npos);
    EXPECT_NE(refused(head + entry("load.wgsl"))
                  .find("load.wgsl:3:28: the height texture 'hm' is used here other than as the "
                        "first argument of a sampling call pxh counts"),
              std::string::npos);
    EXPECT_NE(refused(head + entry("syntax.wgsl", "defines = { MODE = 1 }\n"))
                  .find("defines and includes apply to GLSL and HLSL plug-ins"),
              std::string::npos);
}

}  // namespace
