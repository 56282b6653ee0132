// Typed parameters: real, integer, bool and choice values checked where they are read (the key
// and the accepted values in one line), kept typed, spelled as before in `params`; the seed
// methods' modes as names; the uniforms a method's shader gets, typed, from one place.
#include <gtest/gtest.h>

#include "harness/core/error.h"
#include "harness/experiment/experiment.h"
#include "methods/method.h"
#include "tests/test_util.h"

namespace pxh {
namespace {

std::vector<ParamSpec> typed_specs() {
    return {ParamSpec::real("a", 1.5, 0, 10, "a real"),
            ParamSpec::integer("n", 3, 1, 8, "an integer"),
            ParamSpec::boolean("flag", false, "a bool"),
            ParamSpec::choice("mode", {"slow", "fast"}, "slow", "a choice"),
            ParamSpec::real("m", std::nullopt, 0, 1, "a real or a name")
                .or_names({"auto"})
                .unset_as("auto")};
}

std::string error_of(const GivenParams& given) {
    try {
        resolve_params(typed_specs(), given, "f.toml:7", "method 'x'");
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

TEST(TypedParams, ValuesKeepTheirTypeAndSpelling) {
    const ParamValues p = resolve_params(
        typed_specs(), {{"n", 5}, {"flag", true}, {"mode", "fast"}, {"m", "auto"}}, "f", "x");
    EXPECT_EQ(p.canonical(), "a=1.5;n=5;flag=true;mode=fast;m=auto");
    EXPECT_EQ(p.get_int("n"), 5);
    EXPECT_TRUE(p.get_bool("flag"));
    EXPECT_EQ(p.get_name("mode"), "fast");
    EXPECT_TRUE(p.is_name("m", "auto"));
    EXPECT_FALSE(p.is_number("m"));
    EXPECT_THROW(p.get("mode"), std::logic_error);  // a name is not a number
    const ParamValues d = resolve_params(typed_specs(), {}, "f", "x");
    EXPECT_EQ(d.canonical(), "a=1.5;n=3;flag=false;mode=slow;m=auto");
    EXPECT_FALSE(d.has("m"));  // unset, spelled by its unset spelling
}

TEST(TypedParams, WrongTypeOrNameNamesTheKeyAndTheAcceptedValues) {
    EXPECT_EQ(error_of({{"a", true}}),
              "f.toml:7: method 'x' parameter 'a' = true must be a number in [0, 10] (got a bool)");
    EXPECT_EQ(error_of({{"flag", 1}}),
              "f.toml:7: method 'x' parameter 'flag' = 1 must be true or false (got a number)");
    EXPECT_EQ(error_of({{"mode", "medium"}}),
              "f.toml:7: method 'x' parameter 'mode' = \"medium\" must be one of \"slow\", "
              "\"fast\" (got a string)");
    EXPECT_EQ(error_of({{"m", "automatic"}}),
              "f.toml:7: method 'x' parameter 'm' = \"automatic\" must be a number in [0, 1] or "
              "\"auto\" (got a string)");
    EXPECT_EQ(error_of({{"n", 2.5}}),
              "f.toml:7: method 'x' parameter 'n' = 2.5 must be an integer");
    EXPECT_EQ(error_of({{"n", 9}}), "f.toml:7: method 'x' parameter 'n' = 9 is outside [1, 8]");
    EXPECT_EQ(error_of({{"n", 4}}), "");
}

TEST(TypedParams, ChoiceNeedsItsDefaultAmongItsNames) {
    EXPECT_THROW(ParamSpec::choice("c", {"a", "b"}, "z", ""), std::logic_error);
}

TEST(TypedParams, DescribedForList) {
    const auto s = typed_specs();
    EXPECT_EQ(describe_param(s[2]), "flag (default false, bool): a bool");
    EXPECT_EQ(describe_param(s[3]), "mode (default slow, one of \"slow\", \"fast\"): a choice");
    EXPECT_EQ(
        describe_param(s[4]),
        "m (unset by default (params: m=auto), number in [0, 1] or \"auto\"): a real or a name");
    EXPECT_EQ(describe_param(s[1]), "n (default 3, integer in [1, 8]): an integer");
}

// ---- the seed methods' modes: names in place of the former sentinels, same `params` ----

std::string canon(const char* method, const GivenParams& given) {
    return resolve_method_params(*find_method(method), given, "x").canonical();
}

TEST(TypedParams, ModeNamesReadBackMeanTheSameSetting) {
    // What `params` writes can be given back and means the same setting.
    EXPECT_EQ(canon("pom", {{"layers", "adaptive"}}), "layers=adaptive;layers_min=8;layers_max=32");
    EXPECT_EQ(canon("pom", {{"layers", "adaptive"}, {"layers_min", 4}}),
              "layers=adaptive;layers_min=4;layers_max=32");
    EXPECT_EQ(canon("pom", {{"layers", 16}, {"layers_min", "off"}, {"layers_max", "off"}}),
              "layers=16;layers_min=off;layers_max=off");
    EXPECT_EQ(canon("pom", {{"layers_min", "off"}}), canon("pom", {}));
    EXPECT_EQ(canon("parallax_clamped", {{"max_offset", "scale"}}), "max_offset=scale");
    EXPECT_EQ(canon("relief", {{"layers", 12.5}}),
              "layers=12.5;layers_min=off;layers_max=off;binary_steps=5");
    // Mixed modes are still refused, also when spelled with names.
    EXPECT_THROW(resolve_method_params(*find_method("pom"),
                                       {{"layers", "adaptive"}, {"layers_max", "off"}}, "x"),
                 InputError);
    EXPECT_THROW(
        resolve_method_params(*find_method("pom"), {{"layers", 8}, {"layers_min", 4}}, "x"),
        InputError);
    // A name that is not the parameter's: refused, naming what is accepted.
    EXPECT_EQ(test::input_error([&] {
                  resolve_method_params(*find_method("pom"), {{"layers", "off"}}, "f.toml:3");
              }),
              "f.toml:3: method 'pom' parameter 'layers' = \"off\" must be a number in [1, "
              "4096] or \"adaptive\" (got a string)");
}

// The experiment file: a value of the wrong type is refused at its own line.
TEST(TypedParams, ExperimentFileNamesTheLineTheKeyAndTheAcceptedValues) {
    const std::string head =
        "name = \"t\"\nsamples = 8\n[views]\ntheta_deg = [0]\n"
        "[[heightfields]]\ngenerator = \"flat\"\nsize = 8\n"
        "[[methods]]\nname = \"relief\"\n";
    auto error = [&](const std::string& tail) {
        try {
            parse_experiment(head + tail, "e.toml");
        } catch (const InputError& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    EXPECT_EQ(
        error("binary_steps = \"many\"\n"),
        "e.toml:10: method 'relief' parameter 'binary_steps' = \"many\" must be an integer in "
        "[0, 64] (got a string)");
    EXPECT_EQ(error("layers = [8, true]\n"),
              "e.toml:10: method 'relief' parameter 'layers' = true must be a number in [1, 4096] "
              "or \"adaptive\" (got a bool)");
    EXPECT_EQ(error("layers = [8, \"adaptive\"]\n"), "");
    const Experiment ex = parse_experiment(head + "layers = [8, \"adaptive\"]\n", "e.toml");
    ASSERT_EQ(ex.methods.size(), 2u);
    EXPECT_EQ(ex.methods[0].params.canonical(),
              "layers=8;layers_min=off;layers_max=off;binary_steps=5");
    EXPECT_EQ(ex.methods[1].params.canonical(),
              "layers=adaptive;layers_min=8;layers_max=32;binary_steps=5");
    // Generators' parameters are typed the same way.
    EXPECT_EQ(test::input_error([&] {
                  parse_experiment(
                      "name = \"t\"\n[views]\ntheta_deg = [0]\n[[heightfields]]\ngenerator = "
                      "\"flat\"\nlevel "
                      "= \"high\"\n"
                      "[[methods]]\nname = \"none\"\n",
                      "g.toml");
              }),
              "g.toml:6: generator 'flat' parameter 'level' = \"high\" "
              "must be a number in [0, 1] (got a string)");
}

// ---- uniforms: declared on the parameter or computed by the method, typed ----

std::string uniforms_of(const char* method, const GivenParams& given = {}) {
    const MethodInfo& m = *find_method(method);
    std::string out;
    for (const GlUniform& u : method_uniforms(m, resolve_method_params(m, given, "x")))
        out += std::string(out.empty() ? "" : " ") + glsl_type_name(u.type) + " " + u.name + "=" +
               format_number(u.value);
    return out;
}

TEST(MethodUniforms, TypedFromOnePlace) {
    EXPECT_EQ(uniforms_of("parallax"), "");
    EXPECT_EQ(uniforms_of("pixel_step"), "int p_max_steps=16384");
    EXPECT_EQ(
        uniforms_of("pom"),
        "bool p_layers_adaptive=0 float p_layers=32 float p_layers_min=8 float p_layers_max=32");
    EXPECT_EQ(uniforms_of("relief", {{"layers_max", 64}, {"binary_steps", 3}}),
              "int p_binary_steps=3 bool p_layers_adaptive=1 float p_layers=32 float "
              "p_layers_min=8 float p_layers_max=64");
    EXPECT_EQ(uniforms_of("parallax_clamped"), "bool p_max_offset_is_scale=1 float p_max_offset=0");
    EXPECT_EQ(uniforms_of("parallax_clamped", {{"max_offset", 0.25}}),
              "bool p_max_offset_is_scale=0 float p_max_offset=0.25");
}

TEST(MethodUniforms, ChoiceReachesTheShaderAsItsIndex) {
    MethodInfo m;
    m.name = "t";
    m.params = {ParamSpec::choice("mode", {"a", "b", "c"}, "a", "").to_uniform("p_mode"),
                ParamSpec::boolean("on", true, "").to_uniform("p_on")};
    const ParamValues p = resolve_params(m.params, {{"mode", "c"}}, "x", "t");
    const GlUniforms u = method_uniforms(m, p);
    ASSERT_EQ(u.size(), 2u);
    EXPECT_EQ(u[0].type, GlslType::Int);
    EXPECT_EQ(u[0].value, 2);
    EXPECT_EQ(u[1].type, GlslType::Bool);
    EXPECT_EQ(u[1].value, 1);
}

TEST(MethodUniforms, BadDeclarationsAreRefusedAtRegistration) {
    auto refused = [](ParamSpec s) {
        MethodInfo m;
        m.name = "bad_declaration";
        m.params = {std::move(s)};
        try {
            register_method(m);
        } catch (const std::logic_error& e) {
            return std::string(e.what());
        }
        return std::string("registered");
    };
    EXPECT_NE(
        refused(ParamSpec::integer("n", 1, 0, 9, "").to_uniform("n")).find("must start with p_"),
        std::string::npos);
    EXPECT_NE(refused(ParamSpec::integer("n", std::nullopt, 0, 9, "").to_uniform("p_n"))
                  .find("needs a default"),
              std::string::npos);
    EXPECT_NE(refused(ParamSpec::real("n", 1, 0, 9, "").or_names({"auto"}).to_uniform("p_n"))
                  .find("can be a name"),
              std::string::npos);
    EXPECT_EQ(find_method("bad_declaration"), nullptr);
}

}  // namespace
}  // namespace pxh
