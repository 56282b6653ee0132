// WGSL plug-ins (harness/backends/wgsl_shader.cpp, naga) through the binary: the Bevy-style
// example against bevy_occlusion and bevy_relief sample by sample, and the refusals at the WGSL
// file's FILE:LINE:COL. (The same POM in GLSL, HLSL and WGSL: HlslShader.)
#include <gtest/gtest.h>

#include <filesystem>
#include <map>

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

// examples/engines/bevy as committed (three files joined through naga_oil's #import, the
// relief mode through #ifdef RELIEF_MAPPING): every sample within float rounding of
// bevy_occlusion's and bevy_relief's CPU twins (occlusion's unclamped interpolation weight
// multiplies rounding: measured 3.7e-4 texel at most, as the preset against the literal loop;
// relief 1.1e-4), every fetch count equal.
TEST_F(WgslShader, BevyExampleMatchesBevyPresets) {
    const fs::path ex = fs::path(PXH_SOURCE_DIR) / "examples/engines/bevy/experiment.toml";
    const auto r = pxh("run " + ex.string() + " --quiet --out " + (dir / "r").string());
    ASSERT_EQ(r.status, 0) << r.err;
    const pxh::CsvTable t = pxh::read_csv((dir / "r" / "results.csv").string());
    ASSERT_EQ(t.rows.size(), 60u);
    std::map<std::string, double> worst, fetches;
    for (size_t i = 0; i < t.rows.size(); ++i) {
        const std::string m = t.get(i, "method");
        const std::string at = m + " " + t.get(i, "heightfield") + " theta " +
                               t.get(i, "theta_deg") + " phi " + t.get(i, "phi_deg");
        EXPECT_EQ(t.get(i, "status"), "ok") << at;
        EXPECT_EQ(t.get(i, "decision_mismatch"), "0") << at;
        EXPECT_EQ(t.get(i, "cpu_diff_first"), "") << at;
        worst[m] = std::max(worst[m], std::stod(t.get(i, "cpu_diff_max")));
        fetches[m] = std::max(fetches[m], std::stod(t.get(i, "fetches_max")));
    }
    EXPECT_LE(worst["bevy_style_occlusion"], 1e-3);
    EXPECT_LE(worst["bevy_style_relief"], 1e-3);
    EXPECT_GT(worst["bevy_style_occlusion"], 1e-6) << "the twins differ in rounding somewhere";
    EXPECT_EQ(fetches["bevy_style_occlusion"], 16) << "the most of a sample, as the preset";
    EXPECT_EQ(fetches["bevy_style_relief"], 20) << "relief: 5 probes after the same search";
}

// Refusals at the WGSL file's FILE:LINE:COL: naga's parse error, a module the entry does not
// map, a naga_oil directive pxh does not read, the height texture used otherwise than sampled.
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
    EXPECT_NE(refused(head + entry("import.wgsl"))
                  .find("import.wgsl:1: #import bevy_pbr::pbr_bindings: no such module in the "
                        "entry's includes (map it to a file: includes = { "
                        "\"bevy_pbr::pbr_bindings\" = \"FILE\" })"),
              std::string::npos);
    EXPECT_NE(refused(head + entry("load.wgsl"))
                  .find("load.wgsl:3:28: the height texture 'hm' is used here other than as the "
                        "first argument of a sampling call pxh counts"),
              std::string::npos);
    write("if.wgsl",
          "#if MODE == 1\nfn pxh_method(P: vec2<f32>) -> vec2<f32> { return P; }\n#endif\n");
    EXPECT_NE(refused(head + entry("if.wgsl"))
                  .find("if.wgsl:1: #if: pxh reads naga_oil's #define_import_path, #import, "
                        "#ifdef, #ifndef, #else and #endif"),
              std::string::npos);
}

}  // namespace
