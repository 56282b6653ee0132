// Engine shaders as written ([[methods]] shader = FILE with height_sampler, bind, defines,
// includes: harness/backends/engine_shader.h) through the binary, against CPU twins: the web
// engine example (examples/engines/webgl) against the three.js presets sample by sample, an
// explicit texture2DLod level against the CPU twin at that level, a define sweep that compares
// names, includes in both forms, and the refusals at the engine file's FILE:LINE.
#include <gtest/gtest.h>

#include <filesystem>
#include <map>

#include "harness/results/csv_table.h"
#include "tests/cli_util.h"

namespace fs = std::filesystem;

namespace {

class EngineShader : public pxh::test::CliTest {
  protected:
    pxh::CsvTable run_ok(const std::string& toml) {
        write("exp.toml", toml);
        const auto r =
            pxh("run " + (dir / "exp.toml").string() + " --quiet --out " + (dir / "r").string());
        EXPECT_EQ(r.status, 0) << r.err;
        return pxh::read_csv((dir / "r" / "results.csv").string());
    }
    // Exit 2 and the error lines.
    std::string refused(const std::string& toml) {
        write("exp.toml", toml);
        const auto r =
            pxh("run " + (dir / "exp.toml").string() + " --quiet --out " + (dir / "r").string());
        EXPECT_EQ(r.status, 2) << r.out << r.err;
        EXPECT_FALSE(fs::exists(dir / "r")) << "nothing written";
        return r.err;
    }
    static double num(const pxh::CsvTable& t, size_t r, const char* c) {
        return std::stod(t.get(r, c));
    }
};

// One 64^2 field at s = 0.05, b = 1; 16 x 16 samples (lambda = log2(64 / 16) = 2 on the
// orthographic grid), four views.
std::string head(const std::string& field = "fbm") {
    return pxh::test::ExperimentToml()
        .samples(16)
        .backends("\"glsl\"")
        .theta("[0, 30, 60, 80]")
        .phi("[0, 135]")
        .field(field, 64, "scale = 0.05\nbias = 1.0")
        .str();
}

// The example as committed: each mode of the web engine's chunk against its three.js preset's
// CPU twin. The chunk accumulates its uv where the presets compute it from the layer index, so
// a layer decision may flip at a float near-tie on a sample or two; everything else agrees to
// float rounding.
TEST_F(EngineShader, WebglExampleMatchesThreejsPresets) {
    const fs::path ex = fs::path(PXH_SOURCE_DIR) / "examples/engines/webgl/experiment.toml";
    const auto r = pxh("run " + ex.string() + " --quiet --out " + (dir / "r").string());
    ASSERT_EQ(r.status, 0) << r.err;
    const pxh::CsvTable t = pxh::read_csv((dir / "r" / "results.csv").string());
    std::map<std::string, int> rows;
    for (size_t i = 0; i < t.rows.size(); ++i) {
        const std::string m = t.get(i, "method");
        ++rows[m];
        const std::string at = m + " " + t.get(i, "heightfield") + " theta " +
                               t.get(i, "theta_deg") + " phi " + t.get(i, "phi_deg");
        EXPECT_EQ(t.get(i, "status"), "ok") << at;
        EXPECT_LE(num(t, i, "cpu_diff_p999"), 1e-3) << at;
        EXPECT_LE(num(t, i, "decision_mismatch"), 2) << at;
        if (m == "web_basic") {
            EXPECT_LE(num(t, i, "cpu_diff_max"), 1e-4) << at;
            EXPECT_EQ(t.get(i, "fetches_max"), "1") << at;
        }
    }
    EXPECT_EQ(
        rows,
        (std::map<std::string, int>{
            {"web_basic", 30}, {"web_occlusion", 30}, {"web_relief", 30}, {"web_steep", 30}}));
}

// The example's string-mode chunk (#if PARALLAX_MODE == OCCLUSION, {NAME} chunk parameters,
// #include <name>) against the PlayCanvas 2.22+ presets: both modes within float rounding of
// their CPU twins on every sample (the chunk computes what the presets do in the same order),
// every fetch count equal, the occlusion mode at the levels it derives itself.
TEST_F(EngineShader, WebglModesExampleMatchesPlayCanvasPresets) {
    const fs::path ex = fs::path(PXH_SOURCE_DIR) / "examples/engines/webgl/modes.toml";
    const auto r = pxh("run " + ex.string() + " --quiet --out " + (dir / "r").string());
    ASSERT_EQ(r.status, 0) << r.err;
    const pxh::CsvTable t = pxh::read_csv((dir / "r" / "results.csv").string());
    ASSERT_EQ(t.rows.size(), 60u);
    double steps = 0;
    for (size_t i = 0; i < t.rows.size(); ++i) {
        const std::string at = t.get(i, "method") + " " + t.get(i, "heightfield") + " theta " +
                               t.get(i, "theta_deg") + " phi " + t.get(i, "phi_deg");
        EXPECT_EQ(t.get(i, "status"), "ok") << at;
        EXPECT_LE(num(t, i, "cpu_diff_max"), 1e-4) << at;
        EXPECT_EQ(t.get(i, "decision_mismatch"), "0") << at;
        EXPECT_EQ(t.get(i, "cpu_diff_first"), "") << at;
        if (t.get(i, "method") == "modes_occlusion")
            steps = std::max(steps, num(t, i, "fetches_max"));
    }
    EXPECT_EQ(steps, 22) << "the occlusion mode marches (16 steps and 5 taps at its longest)";
}

// texture2DLod at an explicit level reads that level: at level 2 it is pxh's parallax at
// lod = level (lambda = 2 here) sample by sample; at level 0 it is not.
TEST_F(EngineShader, ExplicitLevelReadsThatLevel) {
    write("lod.frag.glsl", R"(uniform sampler2D heightMap;
uniform float heightScale;
uniform float readLevel;
vec2 pxh_method(vec2 P) {
    float h = texture2DLod(heightMap, P, readLevel).r;
    return P + pxh_V.xy * (heightScale * (h - 1.0) / pxh_V.z);
}
)");
    const auto entry = [](const char* name, const char* level) {
        return std::string("[[methods]]\nname = \"") + name +
               "\"\nshader = \"lod.frag.glsl\"\nheight_sampler = \"heightMap\"\n"
               "bind = { heightScale = \"scale\", readLevel = " +
               level + " }\nmax_fetches = 1\nlod = \"level\"\nreference = \"parallax\"\n";
    };
    const pxh::CsvTable t = run_ok(head() + entry("at2", "2.0") + entry("at0", "0.0"));
    ASSERT_EQ(t.rows.size(), 16u);
    double worst2 = 0, worst0 = 0;
    for (size_t i = 0; i < t.rows.size(); ++i) {
        ASSERT_EQ(t.get(i, "status"), "ok");
        EXPECT_EQ(t.get(i, "fetches_max"), "1");
        double& w = t.get(i, "method") == "at2" ? worst2 : worst0;
        if (t.get(i, "theta_deg") != "0") w = std::max(w, num(t, i, "cpu_diff_max"));
    }
    EXPECT_LE(worst2, 1e-4) << "level 2 is the CPU twin's level";
    EXPECT_GT(worst0, 0.05) << "level 0 differs from level 2 on fbm";
}

// Under lod = "base" only level 0 exists: an explicit level is refused where it is read.
TEST_F(EngineShader, ExplicitLevelUnderBaseIsRefusedAtItsLine) {
    write("lod.frag.glsl", R"(uniform sampler2D heightMap;
vec2 pxh_method(vec2 P) {
    return P + 0.01 * texture2DLod(heightMap, P, 2.0).r;
}
)");
    const std::string err = refused(head() + R"([[methods]]
name = "l"
shader = "lod.frag.glsl"
height_sampler = "heightMap"
max_fetches = 1
)");
    EXPECT_NE(err.find("lod.frag.glsl:3:23: 'texture2DLod' reads the height at an explicit "
                       "texture level"),
              std::string::npos)
        << err;
}

// Every uniform nothing sets is its own line, at its declaration, with the fix.
TEST_F(EngineShader, EveryUnsetUniformIsNamedWithTheFix) {
    write("u.frag.glsl", R"(uniform float parallaxScale;
uniform float parallaxMinLayers;
uniform  float parallaxMaxLayers;
uniform float p_gain;
vec2 pxh_method(vec2 P) {
    return P + vec2(parallaxScale + parallaxMinLayers + parallaxMaxLayers + p_gain);
}
)");
    const std::string err = refused(head() + R"([[methods]]
name = "u"
shader = "u.frag.glsl"
max_fetches = 1
)");
    for (const char* line :
         {"u.frag.glsl:1:15: the shader reads float uniform 'parallaxScale' but nothing sets it "
          "(not declared by the method, not the harness's): bind it in the entry: bind = { "
          "parallaxScale = VALUE }",
          "u.frag.glsl:2:15: the shader reads float uniform 'parallaxMinLayers'",
          "u.frag.glsl:3:16: the shader reads float uniform 'parallaxMaxLayers'",
          "u.frag.glsl:4:15: the shader reads float uniform 'p_gain' but nothing sets it (not "
          "declared by the method, not the harness's): give it in the entry: uniforms = { "
          "p_gain = VALUE }"})
        EXPECT_NE(err.find(line), std::string::npos) << line << "\n" << err;
    EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 4) << err;
}

// A define sweep whose values are names compared with == (PlayCanvas's `#if MODE == NAME`), a
// `{NAME}` chunk parameter, `#include <name>` through the entry's table and `#include "file"`
// relative to the including file: one row per mode, each the method it selects.
TEST_F(EngineShader, DefineSweepComparesNamesAndIncludesResolve) {
    fs::create_directories(dir / "chunks");
    write("chunks/offset.glsl", R"(#include "common_part.glsl"
vec2 engineOffset(vec2 uv, vec3 V) {
#if MODE == OFFSET
    return uv + V.xy * (parallaxScale * ({HEIGHT_FETCH}(heightTex, uv).{CHANNEL} - 1.0) / V.z);
#else
    return uv;
#endif
}
)");
    write("chunks/common_part.glsl",
          "uniform sampler2D heightTex;\nuniform float parallaxScale;\n");
    write("main.frag.glsl", R"(#include <offsetPS>
vec2 pxh_method(vec2 P) { return engineOffset(P, pxh_V); }
)");
    const pxh::CsvTable t = run_ok(head() + R"([[methods]]
name = "modes"
shader = "main.frag.glsl"
height_sampler = "heightTex"
height_channel = "g"
includes = { offsetPS = "chunks/offset.glsl" }
bind = { parallaxScale = "scale" }
defines = { MODE = ["OFFSET", "NONE"], HEIGHT_FETCH = "texture2D", CHANNEL = "g" }
max_fetches = 1
reference = "parallax"
)");
    ASSERT_EQ(t.rows.size(), 16u);
    for (size_t i = 0; i < t.rows.size(); ++i) {
        const bool offset = t.get(i, "params").find("MODE=OFFSET") != std::string::npos;
        EXPECT_EQ(t.get(i, "fetches_max"), offset ? "1" : "0") << t.get(i, "params");
        if (offset) {
            EXPECT_LE(num(t, i, "cpu_diff_max"), 1e-4) << t.get(i, "theta_deg");
        } else if (t.get(i, "theta_deg") != "0") {
            EXPECT_GT(num(t, i, "err_max"), 0.1) << "uv = P is far off at an angle";
        }
    }
}

// pxh list methods shows the release each preset follows.
TEST_F(EngineShader, ListMethodsShowsTheReleaseAPresetFollows) {
    const auto r = pxh("list methods");
    ASSERT_EQ(r.status, 0) << r.err;
    const size_t at = r.out.find("playcanvas_basic  -- ");
    ASSERT_NE(at, std::string::npos) << r.out;
    const size_t next = r.out.find("\n", r.out.find("    source: ", at));
    EXPECT_EQ(r.out.substr(next + 1, 42), "    follows: PlayCanvas 2.22.0 and later (") << r.out;
}

// Refusals, each one line at the engine file's FILE:LINE (or the entry's line).
TEST_F(EngineShader, RefusalsNameTheEngineFileAndLine) {
    fs::create_directories(dir / "inc");
    write("inc/broken.glsl", "float broken() {\n    return 1.0 +;\n}\n");
    write("uses_broken.frag.glsl",
          "#include \"inc/broken.glsl\"\nvec2 pxh_method(vec2 P) { "
          "return P * broken(); }\n");
    write("passes.frag.glsl", R"(uniform sampler2D bumpMap;
float h(sampler2D s, vec2 uv) { return texture2D(s, uv).r; }
vec2 pxh_method(vec2 P) { return P + 0.01 * h(bumpMap, P); }
)");
    write("fetch.frag.glsl", R"(uniform sampler2D bumpMap;
vec2 pxh_method(vec2 P) { return P + 0.01 * texelFetch(bumpMap, ivec2(P), 0).r; }
)");
    write("clean.frag.glsl", R"(uniform sampler2D bumpMap;
vec2 pxh_method(vec2 P) { return P + 0.01 * texture2D(bumpMap, P).r; }
)");
    write("missing.frag.glsl",
          "\n#include \"nowhere.glsl\"\nvec2 pxh_method(vec2 P) { return P; }\n");
    const auto entry = [](const char* shader, const std::string& more = "") {
        return std::string("[[methods]]\nname = \"e\"\nshader = \"") + shader +
               "\"\nheight_sampler = \"bumpMap\"\nmax_fetches = 1\n" + more;
    };
    EXPECT_NE(refused(head() + entry("uses_broken.frag.glsl")).find("inc/broken.glsl:2:"),
              std::string::npos);
    EXPECT_NE(refused(head() + entry("passes.frag.glsl"))
                  .find("passes.frag.glsl:3:47: the height sampler 'bumpMap' is used here other "
                        "than as the first argument of a sampling call pxh counts"),
              std::string::npos);
    EXPECT_NE(refused(head() + entry("fetch.frag.glsl"))
                  .find("fetch.frag.glsl:2:45: 'texelFetch' on the height sampler 'bumpMap' is "
                        "not a call pxh counts"),
              std::string::npos);
    EXPECT_NE(refused(head() + entry("missing.frag.glsl")).find("missing.frag.glsl:2: shader "),
              std::string::npos);
    const std::string unbound =
        refused(head() + entry("clean.frag.glsl", "bind = { heightMapBase = \"bias\" }\n"));
    EXPECT_NE(unbound.find("exp.toml:"), std::string::npos) << unbound;
    EXPECT_NE(unbound.find("bind: 'heightMapBase' is not a uniform the shader or its includes "
                           "declare"),
              std::string::npos)
        << unbound;
    EXPECT_NE(refused(head() + entry("clean.frag.glsl", "bind = { s = \"scale * \" }\n"))
                  .find("is not a scene quantity"),
              std::string::npos);
}

}  // namespace
