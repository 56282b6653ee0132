#include <algorithm>
#include <set>
#include <stdexcept>

#include "methods/method.h"

namespace pxh {

static std::vector<MethodInfo>& registry() {
    static std::vector<MethodInfo> methods;
    return methods;
}

const char* glsl_type_name(GlslType t) {
    switch (t) {
        case GlslType::Float:
            return "float";
        case GlslType::Int:
            return "int";
        case GlslType::Bool:
            return "bool";
    }
    return "?";
}

GlUniforms method_uniforms(const MethodInfo& m, const ParamValues& p) {
    GlUniforms out;
    for (const ParamSpec& s : m.params) {
        if (s.uniform.empty()) continue;
        const ParamValue& v = p.value(s.name);
        switch (s.type) {
            case ParamType::Real:
                out.push_back(GlUniform::real(s.uniform, v.number()));
                break;
            case ParamType::Integer:
                out.push_back(GlUniform::integer(s.uniform, int(v.number())));
                break;
            case ParamType::Bool:
                out.push_back(GlUniform::boolean(s.uniform, v.boolean()));
                break;
            case ParamType::Choice: {
                const auto it = std::find(s.names.begin(), s.names.end(), v.name());
                out.push_back(GlUniform::integer(s.uniform, int(it - s.names.begin())));
                break;
            }
        }
    }
    if (m.gl_uniforms)
        for (GlUniform& u : m.gl_uniforms(p)) out.push_back(std::move(u));
    return out;
}

static void check_declarations(const MethodInfo& info) {
    auto fail = [&](const std::string& why) {
        throw std::logic_error("method '" + info.name + "': " + why);
    };
    std::set<std::string> names;
    for (const ParamSpec& s : info.params) {
        if (!names.insert(s.name).second) fail("parameter '" + s.name + "' declared twice");
        if (s.uniform.empty()) continue;
        if (s.uniform.rfind("p_", 0) != 0)
            fail("parameter '" + s.name + "': uniform '" + s.uniform + "' must start with p_");
        if (!s.default_value)
            fail("parameter '" + s.name + "' reaches the shader, so it needs a default");
        if (s.type != ParamType::Choice && !s.names.empty())
            fail("parameter '" + s.name +
                 "' can be a name, so its uniform must be computed "
                 "(gl_uniforms), not declared on the parameter");
    }
    std::set<std::string> resources;
    for (const ResourceSpec& r : info.resources) {
        if (r.name.rfind("r_", 0) != 0)
            fail("resource '" + r.name + "': its sampler name must start with r_");
        if (!resources.insert(r.name).second) fail("resource '" + r.name + "' declared twice");
        if (r.int_param.empty() && !r.build_with) {
            if (!r.build) fail("resource '" + r.name + "' has no builder");
            continue;
        }
        // A resource built per value of one integer parameter (ResourceSpec::int_param).
        if (r.int_param.empty() || !r.build_with || r.build)
            fail("resource '" + r.name + "': int_param needs build_with and no build");
        const ParamSpec* p = nullptr;
        for (const ParamSpec& s : info.params)
            if (s.name == r.int_param) p = &s;
        if (!p || p->type != ParamType::Integer || !p->default_value)
            fail("resource '" + r.name + "': int_param '" + r.int_param +
                 "' is not an integer parameter with a default");
        if (p->default_value->number() != r.int_param_default)
            fail("resource '" + r.name + "': int_param_default is not the parameter's default");
    }
}

bool register_method(MethodInfo info) {
    check_declarations(info);
    auto& r = registry();
    for (const auto& m : r)
        if (m.name == info.name) throw std::logic_error("method registered twice: " + info.name);
    r.push_back(std::move(info));
    std::stable_sort(r.begin(), r.end(), [](const MethodInfo& a, const MethodInfo& b) {
        return a.order != b.order ? a.order < b.order : a.name < b.name;
    });
    return true;
}

const std::vector<MethodInfo>& all_methods() { return registry(); }

const char* lod_name(LodMode mode) {
    switch (mode) {
        case LodMode::base:
            return "base";
        case LodMode::level:
            return "level";
        case LodMode::grad:
            return "grad";
        case LodMode::implicit:
            return "implicit";
    }
    return "base";
}

std::vector<std::string> lod_names() { return {"base", "level", "grad", "implicit"}; }

const char* depth_name(DepthMode mode) {
    switch (mode) {
        case DepthMode::base:
            return "base";
        case DepthMode::hit:
            return "hit";
        case DepthMode::engine:
            return "engine";
    }
    return "base";
}

std::vector<std::string> depth_names() { return {"base", "hit", "engine"}; }

const MethodInfo* find_method(const std::string& name) {
    for (const auto& m : registry())
        if (m.name == name) return &m;
    return nullptr;
}

}  // namespace pxh
