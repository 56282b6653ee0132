// HLSL plug-ins (harness/backends/converted_shader.h, hlsl_shader.cpp) through the binary: the same
// POM in GLSL, HLSL and WGSL gives identical rows, half is computed as float, the engine's height
// texture's SampleLevel reads that level, engine uniforms in a cbuffer bind, and the refusals land
// at the HLSL file's FILE:LINE.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "harness/results/csv_table.h"
#include "tests/cli_util.h"

namespace fs = std::filesystem;

namespace {

class HlslShader : public pxh::test::CliTest {
  protected:
    pxh::CsvTable run_ok(const std::string& toml) {
        write("exp.toml", toml);
        const auto r =
            pxh("run " + (dir / "exp.toml").string() + " --quiet --out " + (dir / "r").string());
        EXPECT_EQ(r.status, 0) << r.err;
        return pxh::read_csv((dir / "r" / "results.csv").string());
    }
    std::string refused(const std::string& toml) {
        write("exp.toml", toml);
        const auto r =
            pxh("run " + (dir / "exp.toml").string() + " --quiet --out " + (dir / "r").string());
        EXPECT_EQ(r.status, 2) << r.out << r.err;
        EXPECT_FALSE(fs::exists(dir / "r")) << "nothing written";
        return r.err;
    }
    // A file of examples/shader_gate, copied beside the experiment.
    std::string example(const std::string& name) {
        std::ifstream f(fs::path(PXH_SOURCE_DIR) / "examples/shader_gate" / name);
        std::ostringstream s;
        s << f.rdbuf();
        write(name, s.str());
        return s.str();
    }
    static double num(const pxh::CsvTable& t, size_t r, const char* c) {
        return std::stod(t.get(r, c));
    }
};

std::string head() {
    return pxh::test::ExperimentToml()
        .samples(16)
        .backends("\"glsl\"")
        .theta("[0, 30, 60, 85]")
        .phi("[0, 135]")
        .field("fbm", 64, "scale = 0.05\nbias = 1.0")
        .str();
}

std::string pom_entry(const std::string& name, const std::string& shader) {
    return "[[methods]]\nname = \"" + name + "\"\nshader = \"" + shader +
           "\"\nmax_fetches = 34\nuniforms = { p_steps = 32.0 }\nreference = \"pom\"\n"
           "reference_params = { layers = 32 }\n";
}

// Every column a wrong uv or fetch count would move, equal as written in results.csv.
const char* const kSampleColumns[] = {"status",         "err_mean",         "err_max",
                                      "fetches_mean",   "fetches_max",      "cpu_diff_max",
                                      "cpu_diff_mean",  "cpu_diff_p95",     "cpu_diff_worst_sample",
                                      "cpu_diff_first", "decision_mismatch"};

// examples/shader_gate's POM in GLSL, HLSL and WGSL (and the HLSL with half for float): one row
// each per view, equal in every sample's statistics, and within float rounding of pom's twin.
TEST_F(HlslShader, SamePomInGlslHlslAndWgslGivesIdenticalRows) {
    example("my_pom.frag.glsl");
    example("my_pom.wgsl");
    std::string hlsl = example("my_pom.hlsl");
    for (size_t at = hlsl.find("float"); at != std::string::npos; at = hlsl.find("float", at))
        hlsl.replace(at, 5, "half");
    write("my_pom_half.hlsl", hlsl);
    const pxh::CsvTable t =
        run_ok(head() + pom_entry("g", "my_pom.frag.glsl") + pom_entry("h", "my_pom.hlsl") +
               pom_entry("half", "my_pom_half.hlsl"));
    ASSERT_EQ(t.rows.size(), 24u);
    std::map<std::string, std::map<std::string, std::string>> glsl;
    for (size_t i = 0; i < t.rows.size(); ++i) {
        const std::string view = t.get(i, "theta_deg") + "/" + t.get(i, "phi_deg");
        if (t.get(i, "method") != "g") continue;
        for (const char* c : kSampleColumns) glsl[view][c] = t.get(i, c);
        EXPECT_LE(num(t, i, "cpu_diff_max"), 1e-3) << view;
        EXPECT_GT(num(t, i, "fetches_mean"), 15.0) << view;
    }
    ASSERT_EQ(glsl.size(), 8u);
    for (size_t i = 0; i < t.rows.size(); ++i) {
        const std::string view = t.get(i, "theta_deg") + "/" + t.get(i, "phi_deg");
        if (t.get(i, "method") == "g") continue;
        for (const char* c : kSampleColumns)
            EXPECT_EQ(t.get(i, c), glsl[view][c]) << t.get(i, "method") << " " << view << " " << c;
    }
}

// examples/engines/hdrp as committed: the HDRP-style POM (three files, one included by HDRP's
// package path through the entry's includes) against hdrp_pom's CPU twin, every sample within
// float rounding and every fetch count equal.
TEST_F(HlslShader, HdrpExampleMatchesHdrpPomPreset) {
    const fs::path ex = fs::path(PXH_SOURCE_DIR) / "examples/engines/hdrp/experiment.toml";
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
        worst = std::max(worst, num(t, i, "cpu_diff_max"));
        fetches = std::max(fetches, num(t, i, "fetches_max"));
    }
    EXPECT_LE(worst, 1e-4) << "float rounding (measured: 2.8e-5 texel)";
    EXPECT_EQ(fetches, 9) << "the most fetches of a sample (theta 85 on fbm), as the preset";
}

// An engine's HLSL: the height texture sampled by SampleLevel at the level a cbuffer uniform
// gives, the scale bound from the cbuffer; level 2 is the CPU twin's level on the 16 x 16 grid.
// In the same run, a define sweep: MODE compared by name in #if, CHANNEL a swizzle macro, a
// bound uniform the NONE mode does not read.
TEST_F(HlslShader, SampleLevelReadsThatLevelAndCbufferUniformsBind) {
    write("modes.hlsl", R"(Texture2D heightTex;
SamplerState samp;
float parallaxScale;
float2 pxh_method(float2 P) {
#if MODE == OFFSET
    return P + pxh_V.xy * (parallaxScale * (heightTex.Sample(samp, P).CHANNEL - 1.0) / pxh_V.z);
#else
    return P;
#endif
}
)");
    const std::string modes =
        "[[methods]]\nname = \"modes\"\nshader = \"modes.hlsl\"\nheight_sampler = "
        "\"heightTex\"\nheight_channel = \"g\"\nbind = { parallaxScale = \"scale\" }\n"
        "defines = { MODE = [\"OFFSET\", \"NONE\"], CHANNEL = \"g\" }\nmax_fetches = 1\n"
        "lod = \"level\"\nreference = \"parallax\"\n";
    write("lod.hlsl", R"(Texture2D _HeightMap;
SamplerState sampler_HeightMap;
cbuffer UnityPerMaterial {
    float _HeightAmplitude;
    float _ReadLevel;
    bool _Enabled;
};
float2 pxh_method(float2 P) {
    float h = _HeightMap.SampleLevel(sampler_HeightMap, P, _ReadLevel).r;
    if (!_Enabled) return P;
    return P + pxh_V.xy * (_HeightAmplitude * (h - 1.0) / pxh_V.z);
}
)");
    const auto entry = [](const char* name, const char* level, const char* on) {
        return std::string("[[methods]]\nname = \"") + name +
               "\"\nshader = \"lod.hlsl\"\nheight_sampler = \"_HeightMap\"\n"
               "bind = { _HeightAmplitude = \"scale\", _ReadLevel = " +
               level + ", _Enabled = " + on +
               " }\nmax_fetches = 1\nlod = \"level\"\nreference = \"parallax\"\n";
    };
    const pxh::CsvTable t =
        run_ok(head() + entry("at2", "2.0", "true") + entry("at0", "0.0", "true") +
               entry("off", "2.0", "false") + modes);
    ASSERT_EQ(t.rows.size(), 40u);
    double worst2 = 0, worst0 = 0;
    for (size_t i = 0; i < t.rows.size(); ++i) {
        ASSERT_EQ(t.get(i, "status"), "ok");
        const std::string m = t.get(i, "method");
        if (m == "modes") {
            const bool offset = t.get(i, "params").find("MODE=OFFSET") != std::string::npos;
            EXPECT_EQ(t.get(i, "fetches_max"), offset ? "1" : "0") << t.get(i, "params");
            if (offset) {
                EXPECT_LE(num(t, i, "cpu_diff_max"), 1e-4) << t.get(i, "theta_deg");
            }
            continue;
        }
        EXPECT_EQ(t.get(i, "fetches_max"), "1") << m;
        if (m == "off" && t.get(i, "theta_deg") != "0") {
            EXPECT_GT(num(t, i, "err_max"), 0.1) << "uv = P when _Enabled is false";
        }
        if (m == "off" || t.get(i, "theta_deg") == "0") continue;
        double& w = m == "at2" ? worst2 : worst0;
        w = std::max(w, num(t, i, "cpu_diff_max"));
    }
    EXPECT_LE(worst2, 1e-4) << "level 2 is the CPU twin's level";
    EXPECT_GT(worst0, 0.05) << "level 0 differs from level 2 on fbm";
}

// Refusals at the HLSL file's FILE:LINE[:COL]: glslang's syntax error, explicit 16-bit types,
// DX9 samplers, a texture pxh does not bind, an engine uniform nothing sets (located in the
// converted GLSL, with the fix).
TEST_F(HlslShader, RefusalsNameTheHlslFileAndLine) {
    write("syntax.hlsl", "float2 pxh_method(float2 P) {\n    float2 uv = P\n    return uv;\n}\n");
    write("f16.hlsl",
          "float2 pxh_method(float2 P) {\n    float16_t2 q = P;\n    return (float2)q;\n}\n");
    write("dx9.hlsl",
          "sampler2D hm;\nfloat2 pxh_method(float2 P) { return P + tex2Dlod(hm, float4(P, 0, "
          "0)).r; }\n");
    write("unset.hlsl", "float gain;\nfloat2 pxh_method(float2 P) { return P * gain; }\n");
    write("other.hlsl",
          "Texture2D bump;\nSamplerState s;\nfloat2 pxh_method(float2 P) {\n    return P + "
          "bump.SampleLevel(s, P, 0.0).r;\n}\n");
    const auto entry = [](const char* shader) {
        return std::string("[[methods]]\nname = \"e\"\nshader = \"") + shader +
               "\"\nheight_sampler = \"hm\"\nmax_fetches = 1\n";
    };
    const std::string syntax = refused(head() + entry("syntax.hlsl"));
    EXPECT_NE(syntax.find("syntax.hlsl:3:10: error: ';' : Expected"), std::string::npos) << syntax;
    EXPECT_NE(refused(head() + entry("f16.hlsl"))
                  .find("f16.hlsl:2:5: 'float16_t2' is an explicit 16-bit type"),
              std::string::npos);
    EXPECT_NE(refused(head() + entry("dx9.hlsl"))
                  .find("dx9.hlsl:1:1: 'sampler2D' is a DX9-style "
                        "sampler"),
              std::string::npos);
    EXPECT_NE(refused(head() + entry("other.hlsl"))
                  .find("other.hlsl:4:16: texture 'bump' is sampled here, and pxh binds no "
                        "texture but the height map: if it is the engine's height texture, name "
                        "it in the entry (height_sampler = \"bump\")"),
              std::string::npos);
    const std::string unset = refused(head() + entry("unset.hlsl"));
    EXPECT_NE(unset.find("unset.hlsl:1:7: the shader reads float uniform 'gain'"),
              std::string::npos)
        << unset;  // at the HLSL file's declaration, not the GLSL made of it
    EXPECT_NE(unset.find("'gain' but nothing sets it"), std::string::npos) << unset;
    EXPECT_NE(unset.find("bind = { gain = VALUE }"), std::string::npos) << unset;
}

}  // namespace
