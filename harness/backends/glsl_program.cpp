// The GLSL backend's programs: the method's sources (common.glsl, its file, generated
// declarations), each program compiled and linked once per method and kind (the PXH_* defines of
// its preamble), and the check of a program's interface before any row draws.
#include <glad/gl.h>

#include <algorithm>
#include <cstdio>
#include <map>
#include <sstream>
#include <stdexcept>

#include "harness/backends/glsl_backend.h"
#include "harness/backends/glsl_parts.h"
#include "harness/backends/plugin_source.h"
#include "harness/backends/shaders.h"
#include "harness/core/sha256.h"
#include "harness/gl/context.h"

namespace pxh {

using namespace glsl_detail;

namespace {

const char* kVertexShader = R"(#version 450 core
// A full-screen triangle; the fragment shader derives P from gl_FragCoord.
void main() {
    vec2 p = vec2(gl_VertexID == 1 ? 3.0 : -1.0, gl_VertexID == 2 ? 3.0 : -1.0);
    gl_Position = vec4(p, 0.0, 1.0);
}
)";

struct MethodSources {
    ShaderSource common, body;
    std::string common_name, body_name;  // "builtin:PATH" or the file read
    BodyLines body_lines;                // where generated declarations went into body.text
    std::string description() const {    // the results' shader column
        if (body.origin == "builtin" && common.origin == "builtin") return "builtin";
        return body_name + (common.origin == "builtin" ? "" : " + " + common_name);
    }
};

MethodSources method_sources(const GlslMethod& m, const std::string& shader_dir) {
    const std::string method_path = m.shader_file;
    MethodSources s;
    try {
        s.common = shader_source("methods/common.glsl", shader_dir);
        // A plug-in's text as read when the experiment was parsed (--shader-dir does not
        // apply to it).
        if (!m.plugin_shader.empty()) {
            s.body = {m.plugin_source, m.plugin_shader};
        } else {
            s.body = shader_source(method_path, shader_dir,
                                   m.has_builtin_text ? m.builtin_text.c_str() : nullptr);
            if (!m.declarations.empty()) {
                const std::string file =
                    s.body.origin == "builtin" ? "builtin:" + method_path : s.body.origin;
                s.body.text = with_declarations(s.body.text, m.declarations, file, s.body_lines.at);
                s.body_lines.count =
                    long(std::count(m.declarations.begin(), m.declarations.end(), '\n'));
            }
        }
    } catch (const std::exception& e) {
        throw std::runtime_error("method '" + m.name + "': " + e.what());
    }
    s.common_name = s.common.origin == "builtin" ? "builtin:methods/common.glsl" : s.common.origin;
    s.body_name = s.body.origin == "builtin" ? "builtin:" + method_path : s.body.origin;
    return s;
}

// "FILE:LINE:COL" of a plug-in's declaration of uniform `name` in the file it was written in
// ("" when none): its place in the compiled text, mapped through the text's #line directives
// (an engine shader's includes and pxh's adapter: harness/backends/engine_shader.h).
std::string plugin_declaration(const GlslMethod& m, const std::string& name) {
    const std::string lc = uniform_declaration(m.plugin_source, name);
    if (lc.empty()) return "";
    const long target = std::stol(lc);
    long logical = kBodyLine + 1;  // program_for's #line before the plug-in's text
    std::istringstream in(m.plugin_source);
    std::string l;
    for (long n = 1; n < target && std::getline(in, l); ++n) {
        long x = 0, s = 0;
        if (std::sscanf(l.c_str(), "#line %ld %ld", &x, &s) == 2) logical = x;
        else ++logical;
    }
    const long k = logical / kBodyLine - 1;
    if (k < 0 || size_t(k) > m.plugin_files.size()) return "";
    const std::string& file = k == 0 ? m.plugin_display : m.plugin_files[size_t(k) - 1];
    return file + ":" + std::to_string(logical - (k + 1) * kBodyLine) + lc.substr(lc.find(':'));
}

// A plug-in's interface problem at its declaration, with the fix for a uniform nothing sets.
std::string plugin_problem(const GlslMethod& m, const std::string& why, const std::string& what) {
    const size_t q = why.find(" uniform '");
    if (q == std::string::npos) return why;
    const size_t start = q + 10, end = why.find('\'', start);
    const std::string name = why.substr(start, end - start);
    std::string line = why;
    if (why.find("nothing sets it") != std::string::npos) {
        const bool sampler = why.find("sampler") < q;
        line += sampler ? ": pxh binds no texture but the height map (name the engine's height "
                          "sampler in the entry: height_sampler = \"" +
                              name + "\")"
                : name.rfind("p_", 0) == 0
                    ? ": give it in the entry: uniforms = { " + name + " = VALUE }"
                    : ": bind it in the entry: bind = { " + name +
                          " = VALUE } (a number, a list of them, or \"scale\", \"bias\")";
    }
    // An HLSL or WGSL plug-in: where its own text first names the uniform (its declaration)
    const std::string own =
        m.plugin_original.empty() ? "" : identifier_position(m.plugin_original, name);
    const std::string at =
        own.empty() ? plugin_declaration(m, name) : m.plugin_original_display + ":" + own;
    if (at.empty()) return line;
    return at + line.substr(std::min(line.size(), what.size()));
}

}  // namespace

std::string glsl_shader_description(const GlslMethod& m, const std::string& shader_dir) {
    try {
        return method_sources(m, shader_dir).description();
    } catch (const std::exception&) {
        return "";
    }
}

const GlslBackend::Program& GlslBackend::program_for(const GlslMethod& m, ProgramKind kind) {
    // common.glsl's PXH_* defines, in a preamble before its first line (the line numbers stay
    // the files'): none for the N x N grid at level 0, whose program after preprocessing is,
    // token for token, the one before these modes existed (the same numbers; the shader_sha256
    // column is the method's own file's, unchanged).
    std::string defines;
    if (kind.point_map) defines += "#define PXH_POINT_MAP\n";
    if (kind.lod == LodMode::level) defines += "#define PXH_LOD_LEVEL\n";
    if (kind.lod == LodMode::grad) defines += "#define PXH_LOD_GRAD\n";
    if (kind.lod == LodMode::implicit) defines += "#define PXH_LOD_IMPLICIT\n";
    // A plug-in's settings of its defines are programs of their own (one name, other texts).
    const std::string base_key =
        m.name + "\n" + defines + (m.plugin_source.empty() ? "" : sha256_hex(m.plugin_source));
    if (auto it = programs_.find(base_key); it != programs_.end()) return it->second;
    const MethodSources ms = method_sources(m, opt_.shader_dir);
    // Each sample's lambda: what lod = level fetches at, and what pxh_lod() returns to a
    // method whose file calls it (in any mode).
    const bool lod_map =
        kind.lod == LodMode::level || ms.body.text.find("pxh_lod") != std::string::npos;
    if (lod_map) defines += "#define PXH_LOD_MAP\n";
    const ShaderSource &common = ms.common, &body = ms.body;
    const std::string &common_name = ms.common_name, &body_name = ms.body_name;
    // Every source compiled is recorded with its sha256 (run.json), builtin or read from a file.
    compiled_sources_[common_name] = sha256_hex(common.text);
    compiled_sources_[body_name] = sha256_hex(body.text);
    // The method's lines are numbered from kBodyLine + 1: Mesa reports some errors with source
    // string 0 instead of #line's, so the line itself tells the files apart.
    const std::string src = "#version 450 core\n" + defines + "#line 1 1\n" + common.text +
                            "\n#line " + std::to_string(kBodyLine + 1) + " 2\n" + body.text;
    // Errors name the files actually compiled (source string 1 = common.glsl, 2 = the method).
    const std::string what =
        "method '" + m.name + "' (" + body_name + ", with " + common_name + ")";
    const GLuint vs = compile(GL_VERTEX_SHADER, kVertexShader, "pxh vertex shader");
    GLuint fs = 0;
    try {
        // The driver's locations, mapped to the files: a plug-in's as the user reaches it.
        std::map<int, std::string> files = {
            {1, common_name}, {2, m.plugin_display.empty() ? body_name : m.plugin_display}};
        for (size_t k = 0; k < m.plugin_files.size(); ++k) files[int(k) + 3] = m.plugin_files[k];
        fs = compile(GL_FRAGMENT_SHADER, src, what, files, ms.body_lines);
    } catch (...) {
        glDeleteShader(vs);
        throw;
    }
    const GLuint prog = glCreateProgram();
    glAttachShader(prog, vs);
    glAttachShader(prog, fs);
    glLinkProgram(prog);
    glDeleteShader(vs);
    glDeleteShader(fs);
    GLint ok = 0;
    glGetProgramiv(prog, GL_LINK_STATUS, &ok);
    if (!ok) {
        const std::vector<std::string> lines =
            located(raw_log(prog, true), {{1, common_name}, {2, body_name}}, ms.body_lines);
        glDeleteProgram(prog);
        throw GlslProgramError(what + ": program link failed: " + joined(lines), lines);
    }
    Program& p = programs_[base_key];
    p.id = prog;
    p.lod_map = lod_map;
    p.shader = ms.description();
    p.sha256 = sha256_hex(body.text);
    p.what = what;
    p.active = active_uniforms(prog);
    return p;
}

std::vector<std::string> GlslBackend::check(const GlslMethod& m, const GlUniforms& uniforms,
                                            const std::vector<uint8_t>& kinds) {
    use_gl_context(*ctx_);
    std::vector<ProgramKind> programs;  // each program the rows compile (the grid's: none given)
    for (const uint8_t k : kinds) programs.push_back({(k & 1) != 0, LodMode(k >> 1)});
    if (programs.empty()) programs.push_back(ProgramKind());
    for (const ProgramKind& kind : programs)
        if (std::vector<std::string> problems = check_program(m, uniforms, kind); !problems.empty())
            return problems;
    return {};
}

std::vector<std::string> GlslBackend::check_program(const GlslMethod& m, const GlUniforms& uniforms,
                                                    ProgramKind kind) {
    try {
        const Program& program = program_for(m, kind);
        std::vector<DeclaredUniform> declared;
        for (const GlUniform& u : uniforms) declared.push_back({u.name, glsl_type_name(u.type)});
        for (const ResourceSpec& r : m.resources) declared.push_back({r.name, "sampler2D"});
        const std::string what = m.plugin_display.empty() ? program.what : m.plugin_display;
        if (m.plugin_display.empty()) {
            if (const std::string why = interface_problem(program.active, declared, what);
                !why.empty())
                return {why};
        } else {
            // A plug-in's, every one: each at the shader's declaration of the uniform named. An
            // engine uniform bound by the entry (not p_NAME) may be unused: one of the engine's
            // modes reads it, another does not.
            std::vector<std::string> out;
            for (const std::string& why : interface_problems(
                     program.active, required_uniforms(program.active, declared, true), what))
                out.push_back(plugin_problem(m, why, what));
            return out;
        }
    } catch (const GlslProgramError& e) {
        return e.lines;
    } catch (const std::exception& e) {
        return {e.what()};
    }
    return {};
}

}  // namespace pxh
