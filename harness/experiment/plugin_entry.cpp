// A plug-in entry's engine keys (docs/guide/plugin-shaders.md, "Engine shaders as written"):
// height_sampler, height_channel, height_convention, bind, defines, includes; each read and
// checked where it is written, and the program text of each setting of the defines.
#include <algorithm>
#include <cctype>
#include <cfloat>
#include <set>

#include "harness/core/error.h"
#include "harness/experiment/entries.h"

namespace pxh {
namespace {

bool identifier(const std::string& s) {
    if (s.empty() || !(std::isalpha(static_cast<unsigned char>(s[0])) || s[0] == '_')) return false;
    for (char c : s)
        if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_')) return false;
    return true;
}

// A define's value as `#define NAME VALUE` writes it: numbers as format_number, true/false as
// 1/0, a string as it is (one line, no '#', '{' or '}').
std::string define_text(const ParamValue& v, const std::string& where) {
    if (v.is_bool()) return v.boolean() ? "1" : "0";
    if (v.is_number()) return format_number(v.number());
    const std::string& s = v.name();
    if (s.empty() || s.find_first_of("\n\r#{}\\") != std::string::npos)
        throw InputError(
            where, "define value '" + s + "': one line of GLSL without '#', '{', '}' or '\\'");
    return s;
}

// `defines = { NAME = VALUE or [VALUES] }`: the sweep of each (a parameter of the plug-in's
// rows, named as the define, not a uniform) and the names its string values take.
void read_defines(const ParamDict& t, PluginEngine& out) {
    auto d = t.table("defines", "'defines'", "'defines' must be a table");
    if (!d) return;
    std::set<std::string> names;
    for (const std::string& key : d->keys()) {
        if (!identifier(key))
            throw InputError(d->where(key), "define '" + key + "' is not a GLSL identifier");
        std::vector<ParamValue> values;
        std::vector<std::string> choices;
        bool all_names = true, all_numbers = true, all_integers = true, all_bools = true;
        for (const auto& e : d->elements(key)) {
            if (!e.value)
                throw InputError(e.where, "define '" + key +
                                              "' takes a number, true/false, a string, or a "
                                              "list of them");
            define_text(*e.value, e.where);
            all_names = all_names && e.value->is_name();
            all_numbers = all_numbers && e.value->is_number();
            all_integers = all_integers && e.integer;
            all_bools = all_bools && e.value->is_bool();
            if (e.value->is_name()) {
                choices.push_back(e.value->name());
                if (identifier(e.value->name())) names.insert(e.value->name());
            }
            values.push_back(*e.value);
        }
        if (!all_names && !all_numbers && !all_bools)
            throw InputError(d->where(key), "define '" + key +
                                                "': its values are all strings, all numbers or "
                                                "all true/false");
        ParamSpec spec =
            all_names   ? ParamSpec::choice(key, choices, std::nullopt, "define")
            : all_bools ? ParamSpec::boolean(key, false, "define")
            : all_integers
                ? ParamSpec::integer(key, std::nullopt, -2147483647.0, 2147483647.0, "define")
                : ParamSpec::real(key, std::nullopt, -DBL_MAX, DBL_MAX, "define");
        spec.default_value.reset();
        out.define_specs.push_back(spec);
        out.define_sweeps.emplace_back(key, std::move(values));
    }
    out.base.define_names.assign(names.begin(), names.end());
}

// `bind = { NAME = "QUANTITY" or VALUE or [VALUES] }`: an engine uniform set from the scene
// (scale, bias, an expression of them) or from the entry's value(s), as plug-in uniforms are.
void read_binds(const ParamDict& t, PluginEngine& out) {
    auto b = t.table("bind", "'bind'", "'bind' must be a table");
    if (!b) return;
    out.binds = *b;
    for (const std::string& key : b->keys()) {
        if (!identifier(key))
            throw InputError(b->where(key), "bind: '" + key + "' is not a GLSL identifier");
        if (key.rfind("u_", 0) == 0 || key.rfind("pxh_", 0) == 0)
            throw InputError(b->where(key),
                             "bind: '" + key + "' is a reserved name (u_*, pxh_*: pxh's own)");
        const auto elements = b->elements(key);
        if (elements.size() == 1 && elements[0].value && elements[0].value->is_name()) {
            std::string problem;
            const std::string glsl = quantity_glsl(elements[0].value->name(), problem);
            if (!problem.empty())
                throw InputError(elements[0].where, "bind: " + key + ": " + problem);
            out.base.quantities[key] = glsl;
            (void)b->string(key);  // read
            continue;
        }
        out.bound_values.push_back({key, b->where(key)});
    }
}

}  // namespace

PluginEngine read_plugin_engine(const ParamDict& t) {
    PluginEngine out;
    out.base.height_sampler = t.string("height_sampler", "");
    if (!out.base.height_sampler.empty() && !identifier(out.base.height_sampler))
        throw InputError(t.where("height_sampler"),
                         "height_sampler '" + out.base.height_sampler + "' is not a GLSL name");
    const std::string channel = t.string("height_channel", "");
    if (!channel.empty()) {
        const std::string rgba = "rgba", xyzw = "xyzw";
        const size_t c = channel.size() == 1
                             ? std::min(rgba.find(channel[0]), xyzw.find(channel[0]))
                             : std::string::npos;
        if (c == std::string::npos)
            throw InputError(t.where("height_channel"),
                             "height_channel '" + channel + "': one of r, g, b, a (or x, y, z, w)");
        out.base.channel = int(c);
    }
    const std::string convention = t.string("height_convention", "height");
    if (convention != "height" && convention != "depth")
        throw InputError(t.where("height_convention"),
                         "height_convention '" + convention +
                             "': height (the map holds h) or depth (it holds 1 - h)");
    out.base.depth = convention == "depth";
    if ((t.has("height_channel") || t.has("height_convention")) && out.base.height_sampler.empty())
        throw InputError(t.where("height_channel"),
                         "height_channel and height_convention describe the engine's height "
                         "sampler: name it (height_sampler = \"NAME\")");
    if (auto inc = t.table("includes", "'includes'", "'includes' must be a table"))
        for (const std::string& key : inc->keys()) out.base.includes[key] = *inc->string(key);
    read_defines(t, out);
    read_binds(t, out);
    return out;
}

std::vector<ParamSpec> bound_value_specs(const PluginEngine& e, const EngineShader& shader) {
    std::vector<ParamSpec> out;
    for (const auto& [key, where] : e.bound_values) {
        const auto it = shader.uniform_types.find(key);
        if (it == shader.uniform_types.end())
            throw InputError(
                where, "bind: '" + key + "' is not a uniform the shader or its includes declare");
        const std::string& type = it->second;
        ParamSpec spec;
        if (type == "float")
            spec = ParamSpec::real(key, std::nullopt, -double(FLT_MAX), double(FLT_MAX),
                                   "engine uniform (a GLSL float)");
        else if (type == "int")
            spec = ParamSpec::integer(key, std::nullopt, -2147483647.0, 2147483647.0,
                                      "engine uniform (a GLSL int)");
        else if (type == "bool")
            spec = ParamSpec::boolean(key, false, "engine uniform (a GLSL bool)");
        else
            throw InputError(where, "bind: '" + key + "' is a " + type +
                                        " uniform; a value binds float, int and bool uniforms "
                                        "(scale and bias bind float and int ones)");
        spec.default_value.reset();
        spec.to_uniform(key);
        out.push_back(spec);
    }
    return out;
}

std::vector<std::pair<std::string, std::string>> define_setting(const PluginEngine& e,
                                                                const GivenParams& given,
                                                                const std::string& where) {
    std::vector<std::pair<std::string, std::string>> out;
    for (const auto& [key, values] : e.define_sweeps)
        if (const auto it = given.find(key); it != given.end())
            out.emplace_back(key, define_text(it->second, where));
    return out;
}

}  // namespace pxh
