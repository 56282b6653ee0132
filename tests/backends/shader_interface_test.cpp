// The method/shader interface checked after linking: a declared uniform the shader does not
// use, an active uniform nobody sets, or a type that differs is a one-line error naming the
// method, the uniform and the shader file (GL itself would silently ignore all three).
#include "harness/backends/shader_interface.h"

#include <glad/gl.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "harness/backends/glsl_backend.h"
#include "tests/test_util.h"

namespace pxh {
namespace {

TEST(ShaderInterface, ProblemsNameTheUniform) {
    const std::map<std::string, ActiveUniform> active = {
        {"u_scale", {GL_FLOAT, 1}}, {"p_a", {GL_FLOAT, 1}}, {"p_n", {GL_INT, 1}}};
    EXPECT_EQ(interface_problem(active, {{"p_a", "float"}, {"p_n", "int"}}, "M"), "");
    EXPECT_EQ(interface_problem(active, {{"p_a", "float"}, {"p_n", "int"}, {"p_b", "bool"}}, "M"),
              "M: the method declares bool uniform 'p_b' but the shader does not use it (no "
              "active uniform of that name: misspelt, undeclared, or optimised away)");
    EXPECT_EQ(interface_problem(active, {{"p_a", "float"}}, "M"),
              "M: the shader reads int uniform 'p_n' but nothing sets it (not declared by the "
              "method, not the harness's)");
    EXPECT_EQ(interface_problem(active, {{"p_a", "int"}, {"p_n", "int"}}, "M"),
              "M: uniform 'p_a' is float in the shader but the method declares it int");
    EXPECT_EQ(interface_problem(active, {{"p_a", "float"}, {"p_a", "float"}, {"p_n", "int"}}, "M"),
              "M: uniform 'p_a' is declared twice by the method");
}

// Real programs: relief's shader from an override folder with one edit each.
class MisspeltShader : public ::testing::Test {
  protected:
    std::filesystem::path dir =
        std::filesystem::temp_directory_path() / ("pxh_iface_" + std::to_string(getpid()));
    void SetUp() override { std::filesystem::create_directories(dir); }
    void TearDown() override { std::filesystem::remove_all(dir); }

    std::string error_with(const std::string& from, const std::string& to) {
        std::ifstream in(std::filesystem::path(PXH_SOURCE_DIR) / "methods/relief/relief.frag.glsl");
        std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        if (!from.empty()) {  // every occurrence
            size_t pos = text.find(from);
            EXPECT_NE(pos, std::string::npos) << from;
            for (; pos != std::string::npos; pos = text.find(from, pos + to.size()))
                text.replace(pos, from.size(), to);
        }
        std::ofstream(dir / "relief.frag.glsl") << text;
        GlslBackend gl(GlslOptions{dir.string(), 0});
        const HeightField hf = test::flat_field(8, 8, 0.5f);
        const Scene<double> sc{0.05, 1.0, view_vector(30, 0), 8, 8};
        const MethodInfo& m = *find_method("relief");
        try {
            gl.run({&m, test::params_for(m)}, sc, hf, 4, "r32f", nullptr, 0);
        } catch (const std::runtime_error& e) {
            return e.what();
        }
        return "";
    }
};

TEST_F(MisspeltShader, AsShippedItRuns) { EXPECT_EQ(error_with("", ""), ""); }

TEST_F(MisspeltShader, MisspeltUniformIsAnErrorNamingIt) {
    const std::string msg = error_with("p_binary_steps", "p_binary_step");
    EXPECT_NE(msg.find("method 'relief'"), std::string::npos) << msg;
    EXPECT_NE(msg.find("relief.frag.glsl"), std::string::npos) << msg;
    EXPECT_NE(msg.find("declares int uniform 'p_binary_steps' but the shader does not use it"),
              std::string::npos)
        << msg;
    EXPECT_EQ(msg.find('\n'), std::string::npos);
}

TEST_F(MisspeltShader, UniformNobodySetsIsAnError) {
    const std::string msg = error_with(
        "uniform int p_binary_steps;\nvec2 pxh_method(vec2 P) {",
        "uniform int p_binary_steps;\nuniform float p_extra;\nvec2 pxh_method(vec2 P) {\n"
        "    if (p_extra > 0.0) return P;");
    EXPECT_NE(msg.find("the shader reads float uniform 'p_extra' but nothing sets it"),
              std::string::npos)
        << msg;
    EXPECT_NE(msg.find("relief.frag.glsl"), std::string::npos) << msg;
}

TEST_F(MisspeltShader, TypeMismatchIsAnError) {
    const std::string msg =
        error_with("uniform int p_binary_steps;", "uniform float p_binary_steps;");
    // (i < p_binary_steps still compiles: GLSL converts the int i to float.)
    EXPECT_NE(
        msg.find("uniform 'p_binary_steps' is float in the shader but the method declares it int"),
        std::string::npos)
        << msg;
}

}  // namespace
}  // namespace pxh
