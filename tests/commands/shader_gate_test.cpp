// examples/shader_gate/gate.sh against the shader mistakes it exists to catch: a copy of the
// example whose shader flips V.y (a handedness bug, invisible at phi = 0) and one whose shader
// returns NaN where its search misses (err_* leave NaN samples out: only the nonfinite limit
// sees them). gate.sh runs both gates whatever the first says, prints both verdicts and exits 1.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>

#include "tests/cli_util.h"

namespace fs = std::filesystem;

namespace {

class ShaderGate : public pxh::test::CliTest {
  protected:
    const fs::path ex = fs::path(PXH_SOURCE_DIR) / "examples" / "shader_gate";

    // A copy of the example (experiment, thresholds, baseline) with the shader's text edited.
    fs::path copy_with(const std::string& from, const std::string& to) {
        const fs::path d = dir / "gate";
        fs::create_directories(d);
        for (const char* f : {"experiment.toml", "thresholds.toml", "gate.sh", "camera.toml",
                              "camera_thresholds.toml"})
            fs::copy_file(ex / f, d / f);
        for (const char* b : {"baseline", "camera_baseline", "camera_baseline_quick"})
            fs::copy(ex / b, d / b, fs::copy_options::recursive);
        std::string shader = slurp(ex / "my_pom.frag.glsl");
        const size_t at = shader.find(from);
        EXPECT_NE(at, std::string::npos) << "the example's shader lacks: " << from;
        if (at != std::string::npos) shader.replace(at, from.size(), to);
        write("gate/my_pom.frag.glsl", shader);
        return d;
    }
    // `sh gate.sh PXH DIR OUT` of the example itself: exit status, stdout + stderr in out.
    int gate(const fs::path& d, std::string& out, const std::string& mode = "") {
        fs::remove_all(dir / "run");
        for (const char* f : {"run.check.xml", "run.check.json", "run.compare.xml",
                              "run.compare.json", "run.run.xml", "run.run.json"})
            fs::remove(dir / f);
        const int rc = pxh::test::shell("sh " + (ex / "gate.sh").string() + " " + PXH_BINARY + " " +
                                            d.string() + " " + (dir / "run").string() + " " + mode,
                                        dir / "gate.txt", dir / "gate.txt");
        out = slurp(dir / "gate.txt");
        return rc;
    }
};

TEST_F(ShaderGate, ExampleCoversAzimuthsAndTheGrazingBand) {
    // Several azimuths and the grazing band, and the limits look at every one of them.
    const std::string exp = slurp(ex / "experiment.toml");
    EXPECT_NE(exp.find("phi_deg = [0, 30, 135]"), std::string::npos) << exp;
    EXPECT_NE(exp.find("theta_deg = [0, 30, 60, 75, 85, 88]"), std::string::npos) << exp;
    const std::string th = slurp(ex / "thresholds.toml");
    EXPECT_NE(th.find("column = \"nonfinite\""), std::string::npos) << th;
    // The committed baseline is this experiment's run: its rows hold every view of it.
    const std::string csv = slurp(ex / "baseline" / "results.csv");
    for (const char* view : {",88,135,64,", ",30,30,64,", ",0,0,64,"})
        EXPECT_NE(csv.find(view), std::string::npos) << "baseline lacks theta,phi " << view;
    const std::string gate_sh = slurp(ex / "gate.sh");
    EXPECT_EQ(gate_sh.find("set -e"), std::string::npos) << "gate.sh must run both gates";
}

TEST_F(ShaderGate, FlippedVyFailsBothGatesWithBothVerdicts) {
    const fs::path d = copy_with("vec2 dir = pxh_V.xy / pxh_V.z;",
                                 "vec2 dir = vec2(pxh_V.x, -pxh_V.y) / pxh_V.z;");
    std::string out;
    EXPECT_EQ(gate(d, out), 1) << out;
    // pxh check's table and pxh compare's verdict are both there, and the gate's summary.
    EXPECT_NE(out.find("FAIL: "), std::string::npos) << out;
    EXPECT_NE(out.find(" regression(s) beyond --fail-on"), std::string::npos) << out;
    EXPECT_NE(out.find(" failed\n"), std::string::npos) << out;
    EXPECT_NE(out.find("gate: pxh check FAIL, pxh compare FAIL"), std::string::npos) << out;
    // Caught where the bug shows: an oblique azimuth at a moderate angle (limit 0.05 texel).
    EXPECT_NE(out.find("method=my_pom theta in [0, 60]"), std::string::npos) << out;
    EXPECT_NE(out.find("phi=30"), std::string::npos) << out;
}

// docs/guide/plugin-shaders.md's camera recipe: the same shader through a perspective camera at
// texture levels, gated in screen pixels; the full run and the quick one (--samples 32 of the same
// 64 x 64 image, against its own baseline) both pass as committed and both fail with V.y flipped,
// with both verdicts, and the JUnit and JSON files a CI system reads.
TEST_F(ShaderGate, CameraGateFullAndQuickCatchAFlippedVy) {
    const fs::path same =
        copy_with("vec2 dir = pxh_V.xy / pxh_V.z;", "vec2 dir = pxh_V.xy / pxh_V.z;");
    std::string out;
    for (const std::string mode : {"camera", "camera-quick"}) {
        EXPECT_EQ(gate(same, out, mode), 0) << mode << "\n" << out;
        EXPECT_NE(out.find("gate: pxh check pass, pxh compare pass"), std::string::npos) << out;
    }
    fs::remove_all(same);
    const fs::path d = copy_with("vec2 dir = pxh_V.xy / pxh_V.z;",
                                 "vec2 dir = vec2(pxh_V.x, -pxh_V.y) / pxh_V.z;");
    for (const std::string mode : {"camera", "camera-quick"}) {
        EXPECT_EQ(gate(d, out, mode), 1) << mode << "\n" << out;
        EXPECT_NE(out.find("gate: pxh check FAIL, pxh compare FAIL"), std::string::npos) << out;
        EXPECT_NE(out.find(" regression(s) beyond --fail-on"), std::string::npos) << out;
        // The worst row names its view, distance included.
        EXPECT_NE(out.find("  worst: my_pom p_steps=32 lod=level [glsl/r32f] on "),
                  std::string::npos)
            << out;
        EXPECT_NE(out.find(" fov_deg=45 resolution=64: "), std::string::npos) << out;
        EXPECT_NE(slurp(dir / "run.check.xml").find("<failure message=\"err_px_p95 worst"),
                  std::string::npos);
        EXPECT_NE(slurp(dir / "run.compare.json").find("\"passed\": false"), std::string::npos);
    }
}

TEST_F(ShaderGate, NanOnMissFailsTheNonfiniteLimit) {
    const fs::path d = copy_with("if (k == 0 || g > 0.0) return uv;",
                                 "if (g > 0.0) return vec2(intBitsToFloat(0x7fc00000));\n"
                                 "    if (k == 0) return uv;");
    std::string out;
    EXPECT_EQ(gate(d, out), 1) << out;
    // The nonfinite limit fails (the err_p95 limits alone would not see these samples).
    const size_t nf = out.find("method=my_pom ");
    ASSERT_NE(nf, std::string::npos) << out;
    bool nonfinite_fails = false;
    for (size_t at = out.find("nonfinite"); at != std::string::npos;
         at = out.find("nonfinite", at + 1)) {
        const size_t eol = out.find('\n', at);
        if (out.substr(at, eol - at).find("FAIL") != std::string::npos) nonfinite_fails = true;
    }
    EXPECT_TRUE(nonfinite_fails) << out;
    EXPECT_NE(out.find(": nonfinite 0 -> "), std::string::npos) << "compare names it too: " << out;
    EXPECT_NE(out.find("gate: pxh check FAIL, pxh compare FAIL"), std::string::npos) << out;
}

// A one-line bug's log is short and says each verdict once; the details are in the files.
size_t count(const std::string& s, const std::string& what) {
    size_t n = 0;
    for (size_t at = s.find(what); at != std::string::npos; at = s.find(what, at + 1)) ++n;
    return n;
}

TEST_F(ShaderGate, OneLineBugLogIsShortAndSaysTheVerdictOnce) {
    const fs::path d = copy_with("vec2 dir = pxh_V.xy / pxh_V.z;",
                                 "vec2 dir = vec2(pxh_V.x, -pxh_V.y) / pxh_V.z;");
    std::string out;
    EXPECT_EQ(gate(d, out), 1) << out;
    EXPECT_LT(count(out, "\n"), 30u) << out;
    EXPECT_EQ(count(out, "regression(s) beyond --fail-on"), 1u) << out;
    EXPECT_EQ(count(out, "gate: pxh check FAIL, pxh compare FAIL"), 1u) << out;
    // The whole outputs are in the files the log names.
    EXPECT_NE(slurp(dir / "run.compare.txt").find("Regressions beyond --fail-on"),
              std::string::npos);
    EXPECT_NE(slurp(dir / "run.check.txt").find("FAIL"), std::string::npos);
    EXPECT_NE(slurp(dir / "run.run.xml").find("failures=\"0\""), std::string::npos);
}

// A plug-in shader with a syntax error: the run stops (exit 2), and the CI page still gets
// JUnit and JSON, one failure naming the shader's file and line as the compiler gave them.
TEST_F(ShaderGate, ShaderThatDoesNotCompileFailsInJUnitWithItsLine) {
    const fs::path d =
        copy_with("float dz = u_scale / p_steps;", "float dz = u_scale / / p_steps;");
    std::string out;
    EXPECT_EQ(gate(d, out), 2) << out;
    EXPECT_LT(count(out, "\n"), 30u) << out;
    EXPECT_NE(out.find("gate: pxh run exited 2: "), std::string::npos) << out;
    EXPECT_NE(out.find("my_pom.frag.glsl:9"), std::string::npos) << out;
    const std::string xml = slurp(dir / "run.run.xml");
    EXPECT_EQ(count(xml, "<failure "), 1u) << xml;
    EXPECT_NE(xml.find("failures=\"1\""), std::string::npos) << xml;
    const size_t msg = xml.find("<failure message=\"");
    ASSERT_NE(msg, std::string::npos) << xml;
    EXPECT_NE(xml.substr(msg, xml.find('"', msg + 18) - msg).find("my_pom.frag.glsl:9"),
              std::string::npos)
        << xml;
    const std::string json = slurp(dir / "run.run.json");
    EXPECT_NE(json.find("\"passed\": false"), std::string::npos) << json;
    EXPECT_NE(json.find("\"exit_code\": 2"), std::string::npos) << json;
    EXPECT_NE(json.find("my_pom.frag.glsl:9"), std::string::npos) << json;
    // Both files parse as what they claim to be (JSON by Python's reader).
    EXPECT_EQ(sh("python3 -m json.tool " + (dir / "run.run.json").string()).status, 0) << json;
    // No gate ran: no verdict of theirs is left to mislead.
    EXPECT_FALSE(fs::exists(dir / "run.check.xml"));
    EXPECT_FALSE(fs::exists(dir / "run.compare.xml"));
}

TEST_F(ShaderGate, BadInputIsExit2) {
    // An experiment that cannot be read: the gate stops there, with pxh's exit 2.
    const fs::path d = copy_with("uniform float p_steps;", "uniform float p_steps;");
    write("gate/experiment.toml", "name = \n");
    std::string out;
    EXPECT_EQ(gate(d, out), 2) << out;
    EXPECT_NE(out.find("gate: pxh run exited 2"), std::string::npos) << out;
}

}  // namespace
