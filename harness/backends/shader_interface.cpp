#include "harness/backends/shader_interface.h"

#include <glad/gl.h>

#include <algorithm>
#include <set>

namespace pxh {

const std::vector<std::string>& harness_uniforms() {
    static const std::vector<std::string> names = {"u_height",
                                                   "u_scale",
                                                   "u_bias",
                                                   "u_view",
                                                   "u_curvature",
                                                   "u_view_per_sample",
                                                   "u_view_map",
                                                   "u_point_map",
                                                   "u_lod_map",
                                                   "u_grad_map",
                                                   "u_size",
                                                   "u_samples",
                                                   "u_light_on",
                                                   "u_light",
                                                   "u_shadow_layers_min",
                                                   "u_shadow_layers_max",
                                                   "u_depth_mode",
                                                   "u_hit_height",
                                                   "u_depth_axis",
                                                   "u_depth_axis_per_sample",
                                                   "u_axis_map",
                                                   "u_depth_span"};
    return names;
}

std::map<std::string, ActiveUniform> active_uniforms(unsigned program) {
    std::map<std::string, ActiveUniform> out;
    GLint count = 0, longest = 0;
    glGetProgramiv(program, GL_ACTIVE_UNIFORMS, &count);
    glGetProgramiv(program, GL_ACTIVE_UNIFORM_MAX_LENGTH, &longest);
    std::string name(size_t(std::max(longest, 1)), '\0');
    for (GLint i = 0; i < count; ++i) {
        GLsizei len = 0;
        GLint size = 0;
        GLenum type = 0;
        glGetActiveUniform(program, GLuint(i), GLsizei(name.size()), &len, &size, &type,
                           name.data());
        out[name.substr(0, size_t(len))] = {unsigned(type), int(size)};
    }
    return out;
}

std::vector<DeclaredUniform> required_uniforms(const std::map<std::string, ActiveUniform>& active,
                                               const std::vector<DeclaredUniform>& declared,
                                               bool plugin) {
    std::vector<DeclaredUniform> out;
    for (const DeclaredUniform& d : declared)
        if (!plugin || d.name.rfind("p_", 0) == 0 || active.count(d.name)) out.push_back(d);
    return out;
}

std::string gl_type_name(unsigned t) {
    switch (t) {
        case GL_FLOAT:
            return "float";
        case GL_FLOAT_VEC2:
            return "vec2";
        case GL_FLOAT_VEC3:
            return "vec3";
        case GL_FLOAT_VEC4:
            return "vec4";
        case GL_INT:
            return "int";
        case GL_INT_VEC2:
            return "ivec2";
        case GL_INT_VEC3:
            return "ivec3";
        case GL_INT_VEC4:
            return "ivec4";
        case GL_UNSIGNED_INT:
            return "uint";
        case GL_BOOL:
            return "bool";
        case GL_SAMPLER_2D:
            return "sampler2D";
        default:
            return "GL type " + std::to_string(t);
    }
}

std::string interface_problem(const std::map<std::string, ActiveUniform>& active,
                              const std::vector<DeclaredUniform>& declared,
                              const std::string& what) {
    const std::vector<std::string> all = interface_problems(active, declared, what);
    return all.empty() ? "" : all[0];
}

std::vector<std::string> interface_problems(const std::map<std::string, ActiveUniform>& active,
                                            const std::vector<DeclaredUniform>& declared,
                                            const std::string& what) {
    std::vector<std::string> out;
    std::set<std::string> seen;
    for (const auto& d : declared) {
        if (!seen.insert(d.name).second) {
            out.push_back(what + ": uniform '" + d.name + "' is declared twice by the method");
            continue;
        }
        const auto it = active.find(d.name);
        if (it == active.end())
            out.push_back(what + ": the method declares " + d.glsl_type + " uniform '" + d.name +
                          "' but the shader does not use it (no active uniform of that name: "
                          "misspelt, undeclared, or optimised away)");
        else if (gl_type_name(it->second.gl_type) != d.glsl_type)
            out.push_back(what + ": uniform '" + d.name + "' is " +
                          gl_type_name(it->second.gl_type) +
                          " in the shader but the method declares it " + d.glsl_type);
    }
    for (const auto& h : harness_uniforms()) seen.insert(h);
    for (const auto& [name, u] : active)
        if (!seen.count(name))
            out.push_back(what + ": the shader reads " + gl_type_name(u.gl_type) + " uniform '" +
                          name +
                          "' but nothing sets it (not declared by the method, not the "
                          "harness's)");
    return out;
}

void set_method_uniforms(unsigned program, const GlUniforms& uniforms) {
    for (const GlUniform& u : uniforms) {
        const GLint loc = glGetUniformLocation(program, u.name.c_str());
        switch (u.type) {
            case GlslType::Float:
                glUniform1f(loc, float(u.value));
                break;
            case GlslType::Int:
                glUniform1i(loc, int(u.value));
                break;
            case GlslType::Bool:
                glUniform1i(loc, u.value != 0 ? 1 : 0);
                break;
        }
    }
}

}  // namespace pxh
