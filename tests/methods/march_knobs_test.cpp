// The marcher's knob table (methods/march/knobs.h) seen from its three outputs: the GLSL
// declarations (parsed here as text), the `march` method's parameters and the uniforms the GLSL
// backend sets name the same knobs, in the same order, with the same types and defaults; the
// shader gets the declarations in place of its marker line (and errors keep the file's lines);
// a preset row's parameters set its knobs.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include "harness/backends/glsl_backend.h"
#include "harness/backends/shaders.h"
#include "methods/march/knobs.h"
#include "methods/march/preset.h"
#include "tests/test_util.h"

namespace pxh {
namespace {

struct GlslDecl {
    std::string type, name, comment;
};

// `uniform TYPE NAME;` lines, with an optional trailing comment.
std::vector<GlslDecl> parse_declarations(const std::string& text) {
    static const std::regex line(R"(uniform (float|int|bool) (\w+);(?: +// (.*))?)");
    std::vector<GlslDecl> out;
    std::istringstream in(text);
    std::string l;
    while (std::getline(in, l)) {
        std::smatch m;
        EXPECT_TRUE(std::regex_match(l, m, line)) << "not a declaration: '" << l << "'";
        out.push_back({m[1], m[2], m[3]});
    }
    return out;
}

// The uniform value a parameter's default stands for (a choice: its index; a bool: 0 / 1).
double default_as_uniform(const ParamSpec& p) {
    const ParamValue& v = *p.default_value;
    if (p.type == ParamType::Choice)
        return double(std::find(p.names.begin(), p.names.end(), v.name()) - p.names.begin());
    if (p.type == ParamType::Bool) return v.boolean() ? 1 : 0;
    return v.number();
}

std::string type_for(ParamType t) {
    return t == ParamType::Real ? "float" : t == ParamType::Bool ? "bool" : "int";
}

const char* kShader = "methods/march/march.frag.glsl";

std::string embedded_march_shader() {
    for (const EmbeddedShader& s : embedded_shaders())
        if (std::string(s.path) == kShader) return s.source;
    ADD_FAILURE() << "no embedded " << kShader;
    return "";
}

TEST(MarchKnobs, DeclarationsParametersAndUniformsNameTheSameKnobs) {
    const MethodInfo& march = *find_method("march");
    const std::vector<GlslDecl> glsl = parse_declarations(march_glsl_declarations());
    const std::vector<ParamSpec>& params = march.params;
    // What the backend sets for the `march` method at its defaults, and for the default config.
    const GlUniforms set = method_uniforms(march, test::params_for(march));
    const GlUniforms of_defaults = march_uniforms(MarchConfig{});
    ASSERT_EQ(glsl.size(), 32u);
    ASSERT_EQ(params.size(), glsl.size());
    ASSERT_EQ(set.size(), glsl.size());
    ASSERT_EQ(of_defaults.size(), glsl.size());
    for (size_t i = 0; i < glsl.size(); ++i) {
        const ParamSpec& p = params[i];
        SCOPED_TRACE(p.name);
        EXPECT_EQ(glsl[i].name, "pm_" + p.name);
        EXPECT_EQ(set[i].name, glsl[i].name);
        EXPECT_EQ(glsl[i].type, type_for(p.type));
        EXPECT_EQ(glsl_type_name(set[i].type), glsl[i].type);
        ASSERT_TRUE(p.default_value.has_value());
        EXPECT_EQ(set[i].value, default_as_uniform(p));
        // MarchConfig's field initialisers give the parameters' defaults.
        EXPECT_EQ(of_defaults[i].value, set[i].value);
        EXPECT_EQ(of_defaults[i].type, set[i].type);
        std::string names;  // a choice's comment: its indices' names
        if (p.type == ParamType::Choice)
            for (size_t k = 0; k < p.names.size(); ++k)
                names += (k ? ", " : "") + std::to_string(k) + " " + p.names[k];
        EXPECT_EQ(glsl[i].comment, names);
    }
    // A few rows pinned: the defaults are pxh's view-adaptive POM (methods/pom).
    EXPECT_EQ(glsl[3].name, "pm_count");
    EXPECT_EQ(glsl[3].comment,
              "0 fixed, 1 mix, 2 mix_trunc, 3 mix_negated, 4 angle_scaled, "
              "5 mix_scaled, 6 texels");
    EXPECT_EQ(set[3].value, 1.0);  // mix
    EXPECT_EQ(set[5].name, "pm_layers_min");
    EXPECT_EQ(set[5].value, 8.0);
    EXPECT_EQ(set[15].name, "pm_refine");
    EXPECT_EQ(set[15].value, 1.0);  // lerp
    EXPECT_EQ(set[16].name, "pm_clamp_weight");
    EXPECT_EQ(set[16].value, 1.0);
    // The rows after the search: what engines do around it, all off by default.
    EXPECT_EQ(set[23].name, "pm_pad_fetches");
    EXPECT_EQ(set[23].value, 0.0);
    EXPECT_EQ(set[24].name, "pm_lod_fade");
    EXPECT_EQ(glsl[24].comment, "0 none, 1 hdrp, 2 dxsdk, 3 texels");
    EXPECT_EQ(set[24].value, 0.0);  // none
    EXPECT_EQ(set[27].name, "pm_max_slope");
    EXPECT_EQ(set[27].value, 0.0);  // no cap
    EXPECT_EQ(set[28].name, "pm_clamp_depth");
    EXPECT_EQ(set[28].value, 0.0);
}

// Every preset is the marcher: the same shader, the same generated declarations, every knob's
// uniform set.
TEST(MarchKnobs, EveryPresetSetsEveryKnobUniform) {
    std::vector<std::string> knob_uniforms;
    for (const MarchKnobSpec& k : march_knobs()) knob_uniforms.push_back(k.uniform);
    int presets = 0;
    for (const MethodInfo& m : all_methods()) {
        if (m.shader_file() != kShader) continue;
        ++presets;
        EXPECT_EQ(m.shader_declarations, march_glsl_declarations()) << m.name;
        std::vector<std::string> names;
        for (const GlUniform& u : method_uniforms(m, test::params_for(m))) names.push_back(u.name);
        EXPECT_EQ(names, knob_uniforms) << m.name;
    }
    EXPECT_EQ(
        presets,
        27);  // march, the 25 engine presets (playcanvas_basic_v2_21 among them) and the test's
}

TEST(MarchKnobs, ShaderGetsTheDeclarationsInPlaceOfItsMarkerLine) {
    const std::string text = embedded_march_shader();
    EXPECT_EQ(text.find("uniform "), std::string::npos) << "the shader declares a uniform by hand";
    const std::string decls = march_glsl_declarations();
    long line = 0;
    const std::string built = with_declarations(text, decls, kShader, line);
    EXPECT_EQ(line, 2);
    EXPECT_EQ(built.find(kDeclarationsLine), std::string::npos);
    const size_t at = built.find(decls);
    ASSERT_NE(at, std::string::npos);
    EXPECT_EQ(built.substr(0, at), text.substr(0, text.find(kDeclarationsLine)));
    EXPECT_EQ(built.size(), text.size() -
                                (text.find('\n', text.find(kDeclarationsLine)) + 1 -
                                 text.find(kDeclarationsLine)) +
                                decls.size());
    try {
        with_declarations("vec2 pxh_method(vec2 P) { return P; }\n", decls, "x.frag.glsl", line);
        FAIL() << "no error";
    } catch (const std::runtime_error& e) {
        EXPECT_EQ(std::string(e.what()),
                  "x.frag.glsl: no '// @pxh-declarations' line for the method's generated "
                  "declarations");
    }
}

// A compile error in an override of the shader names the file's own line, not the line in the
// text with the declarations written in.
TEST(MarchKnobs, CompileErrorsNameTheShaderFilesLines) {
    const auto dir =
        std::filesystem::temp_directory_path() / ("pxh_knobs_" + std::to_string(getpid()));
    std::filesystem::create_directories(dir);
    std::string text = embedded_march_shader();
    // Line 3 of the file (below the marker on line 2; line 25 of the text compiled) gets an
    // undeclared name.
    size_t at = 0;
    for (int i = 0; i < 2; ++i) at = text.find('\n', at) + 1;
    text.insert(at, "float pm_broken() { return oops; }\n");
    std::ofstream(dir / "march.frag.glsl") << text;
    GlslBackend gl(GlslOptions{dir.string(), 1});
    const HeightField hf = test::random_field(16, 16, 3, 0.0f, 1.0f);
    const Scene<double> sc{0.05, 1.0, view_vector(30, 0), 16, 16};
    const MethodInfo& m = *find_method("march");
    try {
        gl.run({&m, test::params_for(m)}, sc, hf, 8, "r32f", nullptr);
        FAIL() << "a broken shader rendered";
    } catch (const std::runtime_error& e) {
        const std::string msg = e.what();
        EXPECT_NE(msg.find("march.frag.glsl:3:"), std::string::npos) << msg;
        EXPECT_NE(msg.find("oops"), std::string::npos) << msg;
    }
    std::filesystem::remove_all(dir);
}

// A preset row: the knobs it fixes, its parameters setting knobs (a choice through its values),
// then the knobs derived from them (O3DE relief: iterations = n - 1).
TEST(MarchKnobs, PresetRowParametersSetTheirKnobs) {
    auto uniform = [](const char* method, const GivenParams& g, const char* name) {
        const MethodInfo& m = *find_method(method);
        for (const GlUniform& u : method_uniforms(m, test::params_for(m, g)))
            if (u.name == name) return u.value;
        ADD_FAILURE() << name;
        return -1.0;
    };
    EXPECT_EQ(uniform("o3de_relief", {}, "pm_layers"), 16.0);
    EXPECT_EQ(uniform("o3de_relief", {}, "pm_iterations"), 15.0);
    EXPECT_EQ(uniform("o3de_relief", {{"quality", "High"}}, "pm_layers"), 64.0);
    EXPECT_EQ(uniform("o3de_relief", {{"quality", "High"}}, "pm_iterations"), 63.0);
    EXPECT_EQ(uniform("o3de_relief", {}, "pm_tie"), 1.0);  // stay
    EXPECT_EQ(uniform("godot_deep", {{"heightmap_min_layers", 5}}, "pm_layers_min"), 5.0);
    EXPECT_EQ(uniform("godot_deep", {{"heightmap_flip_binormal", true}}, "pm_mirror_v"), 1.0);
    EXPECT_EQ(uniform("godot_deep", {}, "pm_step"), 1.0);  // sin
    EXPECT_EQ(uniform("bevy_relief", {{"max_steps", 9}}, "pm_iterations"), 9.0);
    EXPECT_EQ(uniform("bevy_relief", {}, "pm_layers_min"), 1.0);
    // Knobs a row leaves alone keep the table's defaults.
    EXPECT_EQ(uniform("babylon_pom", {}, "pm_tolerance"), 0.01);
    EXPECT_EQ(uniform("babylon_pom", {}, "pm_max_steps"), 14.0);
}

}  // namespace
}  // namespace pxh
