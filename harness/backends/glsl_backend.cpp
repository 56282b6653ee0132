#include "harness/backends/glsl_backend.h"

#include <glad/gl.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <map>
#include <sstream>
#include <stdexcept>

#include "harness/backends/glsl_entry.h"
#include "harness/backends/plugin_source.h"
#include "harness/backends/shaders.h"
#include "harness/core/error.h"
#include "harness/core/param_dict.h"
#include "harness/core/sha256.h"
#include "harness/gl/context.h"
#include "harness/scene/perspective_camera.h"
#include "harness/truth/ground_truth.h"

namespace pxh {

GlslProgramError::GlslProgramError(const std::string& what, std::vector<std::string> l)
    : std::runtime_error(what), lines(std::move(l)) {}

GlslMethod GlslMethod::of(const MethodInfo& m) {
    GlslMethod g;
    g.name = m.name;
    g.shader_file = m.shader_file();
    g.has_builtin_text = m.shader_text != nullptr;
    if (m.shader_text) g.builtin_text = m.shader_text;
    g.declarations = m.shader_declarations;
    g.plugin_shader = m.plugin_shader;
    g.plugin_source = m.plugin_source;
    g.plugin_display = m.plugin_display;
    for (const ResourceSpec& r : m.resources) {
        ResourceSpec c;
        c.name = r.name;
        c.format = r.format;
        c.filter = r.filter;
        c.wrap = r.wrap;
        g.resources.push_back(c);
    }
    return g;
}

namespace {

const char* kVertexShader = R"(#version 450 core
// A full-screen triangle; the fragment shader derives P from gl_FragCoord.
void main() {
    vec2 p = vec2(gl_VertexID == 1 ? 3.0 : -1.0, gl_VertexID == 2 ? 3.0 : -1.0);
    gl_Position = vec4(p, 0.0, 1.0);
}
)";

constexpr long kBodyLine = 100000;  // the method's file starts at line kBodyLine + 1

// The raw log (several lines) of a shader or program.
std::string raw_log(GLuint object, bool program) {
    GLint len = 0;
    (program ? glGetProgramiv : glGetShaderiv)(object, GL_INFO_LOG_LENGTH, &len);
    std::string log(size_t(std::max(len, 1)), '\0');
    (program ? glGetProgramInfoLog : glGetShaderInfoLog)(object, len, nullptr, log.data());
    return log.c_str();
}

// The method file's line of a line of the compiled method text: the generated declarations
// (`count` lines written in place of line `at`, shaders.h) are reported at that line.
struct BodyLines {
    long at = 0, count = 0;
    long file_line(long ln) const {
        if (count == 0 || ln < at) return ln;
        return ln < at + count ? at : ln - count + 1;
    }
};

// The driver's messages, one per line, with Mesa's "S:L(C): " (source string S, line L, column
// C) or "S:L: " written as "FILE:L:C: " for the files the source strings are (`files`, by
// string number: 1 = common.glsl, 2 = the method's file, after pxh's #line directives).
std::vector<std::string> located(const std::string& log, const std::map<int, std::string>& files,
                                 const BodyLines& body = {}) {
    std::vector<std::string> out;
    std::istringstream in(log);
    std::string line;
    while (std::getline(in, line)) {
        while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.pop_back();
        if (line.empty()) continue;
        size_t i = 0;
        auto number = [&](long& v) {
            const size_t start = i;
            v = 0;
            while (i < line.size() && std::isdigit(static_cast<unsigned char>(line[i])) &&
                   i < 9 + start)
                v = v * 10 + (line[i++] - '0');
            return i > start;
        };
        long src = 0, ln = 0, col = 0;
        bool ok = number(src) && i < line.size() && line[i++] == ':' && number(ln);
        if (ok && i < line.size() && line[i] == '(') {
            ++i;
            ok = number(col) && i < line.size() && line[i++] == ')';
        }
        ok = ok && i < line.size() && line[i++] == ':';
        if (ln > kBodyLine) {  // the method's file, whatever string number Mesa gives
            src = 2;
            ln = body.file_line(ln - kBodyLine);
        } else if (src == 0) {
            src = 1;
        }
        const auto f = files.find(int(src));
        if (!ok || f == files.end()) {
            out.push_back(line);
            continue;
        }
        while (i < line.size() && line[i] == ' ') ++i;
        out.push_back(f->second + ":" + std::to_string(ln) +
                      (col > 0 ? ":" + std::to_string(col) : "") + ": " + line.substr(i));
    }
    if (out.empty()) out.push_back("(the driver gave no log)");
    return out;
}

std::string joined(const std::vector<std::string>& lines) {
    std::string s;
    for (const auto& l : lines) s += (s.empty() ? "" : "; ") + l;
    return s;
}

unsigned compile(GLenum type, const std::string& src, const std::string& what,
                 const std::map<int, std::string>& files = {}, const BodyLines& body = {}) {
    const GLuint sh = glCreateShader(type);
    const char* p = src.c_str();
    glShaderSource(sh, 1, &p, nullptr);
    glCompileShader(sh);
    GLint ok = 0;
    glGetShaderiv(sh, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        std::vector<std::string> lines = located(raw_log(sh, false), files, body);
        glDeleteShader(sh);
        // Errors only, when the log has any (Mesa's warnings would bury them).
        std::vector<std::string> errors;
        for (const auto& l : lines)
            if (l.find("error") != std::string::npos) errors.push_back(l);
        if (!errors.empty()) lines = errors;
        throw GlslProgramError(what + ": shader compile failed: " + joined(lines), lines);
    }
    return sh;
}

}  // namespace

GlslBackend::GlslBackend(GlslOptions opt) : opt_(std::move(opt)) {
    if (!opt_.shader_dir.empty()) {
        // A typo must not silently give the built-in shaders' numbers.
        std::error_code ec;
        if (!std::filesystem::is_directory(opt_.shader_dir, ec))
            throw InputError("--shader-dir " + opt_.shader_dir, "no such folder");
    }
    ctx_ = make_gl_context(opt_.gl);
    use_gl_context(*ctx_);
    const GlInfo info = current_gl_info();
    renderer_ = info.renderer;
    version_ = info.version;
    vendor_ = info.vendor;
    timer_bits_ = info.timer_bits;
    glGenVertexArrays(1, &vao_);  // a core context needs a bound VAO even without attributes
    glBindVertexArray(vao_);
    glGenTextures(1, &texture_);
    glBindTexture(GL_TEXTURE_2D, texture_);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_REPEAT);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_REPEAT);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, 0);
    glGenFramebuffers(1, &fbo_);
    glGenTextures(2, color_);
}

GlslBackend::~GlslBackend() {
    if (!ctx_) return;
    try {
        use_gl_context(*ctx_);
    } catch (const std::exception&) {
        return;  // the context is gone with its objects
    }
    for (auto& [k, p] : programs_) glDeleteProgram(p.id);
    resource_textures_.release();
    glDeleteTextures(2, color_);
    glDeleteTextures(1, &texture_);
    if (view_map_) glDeleteTextures(1, &view_map_);
    for (unsigned t : {point_map_, lod_map_, grad_map_})
        if (t) glDeleteTextures(1, &t);
    glDeleteFramebuffers(1, &fbo_);
    glDeleteVertexArrays(1, &vao_);
}

std::string GlslBackend::context_name() const { return ctx_->name(); }
std::map<std::string, std::string> GlslBackend::driver() const { return ctx_->driver(); }

namespace {

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
    const std::string base_key = m.name + "\n" + defines;
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
        const std::map<int, std::string> files = {
            {1, common_name}, {2, m.plugin_display.empty() ? body_name : m.plugin_display}};
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

namespace {

// One level of the height texture in the row's format (r8, r16: each texel rounded to the
// nearest step, the quantisation every level gets).
void upload_level(int level, const HeightField& hf, const std::string& format) {
    // Rows go up unchanged: row j = 0 of the field is texture row 0 (v near 0).
    if (format == "r32f") {
        glTexImage2D(GL_TEXTURE_2D, level, GL_R32F, hf.width, hf.height, 0, GL_RED, GL_FLOAT,
                     hf.texels.data());
    } else if (format == "r16") {
        std::vector<uint16_t> q(hf.texels.size());
        for (size_t i = 0; i < q.size(); ++i) q[i] = uint16_t(std::lround(hf.texels[i] * 65535.0));
        glTexImage2D(GL_TEXTURE_2D, level, GL_R16, hf.width, hf.height, 0, GL_RED,
                     GL_UNSIGNED_SHORT, q.data());
    } else if (format == "r8") {
        std::vector<uint8_t> q(hf.texels.size());
        for (size_t i = 0; i < q.size(); ++i) q[i] = uint8_t(std::lround(hf.texels[i] * 255.0));
        glTexImage2D(GL_TEXTURE_2D, level, GL_R8, hf.width, hf.height, 0, GL_RED, GL_UNSIGNED_BYTE,
                     q.data());
    } else {
        throw std::runtime_error("unknown texture format '" + format + "'");
    }
    if (glGetError() != GL_NO_ERROR)
        throw std::runtime_error("cannot upload a " + std::to_string(hf.width) + " x " +
                                 std::to_string(hf.height) + " " + format + " texture" +
                                 (level > 0 ? " level " + std::to_string(level) : ""));
}

}  // namespace

void GlslBackend::upload(const HeightField& hf, const std::string& format,
                         const TextureLevels* levels) {
    // Uploaded on every call: a cache keyed on the data pointer can see a freed field's
    // address reused by the next one, and an upload costs little next to rendering.
    glBindTexture(GL_TEXTURE_2D, texture_);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    if (!levels) {  // level 0 alone, bilinear (lod = base)
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, 0);
        upload_level(0, hf, format);
        return;
    }
    // pxh's own levels as the texture's mip chain (never glGenerateMipmap: both twins sample
    // the same levels), GL's LINEAR_MIPMAP_LINEAR between them.
    if (levels->levels.empty() || levels->levels[0].width != hf.width ||
        levels->levels[0].height != hf.height)
        throw std::logic_error("glsl: texture levels of another field");
    for (int L = 0; L <= levels->last(); ++L) upload_level(L, levels->levels[size_t(L)], format);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, levels->last());
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
}

std::vector<float> GlslBackend::height_texture_level(int level, int& width, int& height) {
    use_gl_context(*ctx_);
    glBindTexture(GL_TEXTURE_2D, texture_);
    glGetTexLevelParameteriv(GL_TEXTURE_2D, level, GL_TEXTURE_WIDTH, &width);
    glGetTexLevelParameteriv(GL_TEXTURE_2D, level, GL_TEXTURE_HEIGHT, &height);
    std::vector<float> texels(size_t(std::max(width, 0)) * size_t(std::max(height, 0)));
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    if (!texels.empty()) glGetTexImage(GL_TEXTURE_2D, level, GL_RED, GL_FLOAT, texels.data());
    return texels;
}

int GlslBackend::height_texture_max_level() {
    use_gl_context(*ctx_);
    glBindTexture(GL_TEXTURE_2D, texture_);
    GLint q = 0;
    glGetTexParameteriv(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, &q);
    return q;
}

void GlslBackend::ensure_framebuffer(int n) {
    if (fb_size_ == n) return;
    glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
    for (int i = 0; i < 2; ++i) {
        glBindTexture(GL_TEXTURE_2D, color_[i]);
        glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, n, n, 0, GL_RGBA, GL_FLOAT, nullptr);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0 + i, GL_TEXTURE_2D, color_[i],
                               0);
    }
    const GLenum bufs[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
    glDrawBuffers(2, bufs);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        throw std::runtime_error("cannot create a " + std::to_string(n) + " x " +
                                 std::to_string(n) + " RGBA32F framebuffer");
    fb_size_ = n;
}

void GlslBackend::upload_view_map(const std::vector<Vec3d>& V, int samples) {
    if (V.size() != size_t(samples) * size_t(samples))
        throw std::logic_error("glsl: " + std::to_string(V.size()) + " directions for " +
                               std::to_string(samples) + " x " + std::to_string(samples) +
                               " samples");
    if (!view_map_) {
        glGenTextures(1, &view_map_);
        glBindTexture(GL_TEXTURE_2D, view_map_);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, 0);
    }
    // Texel (i, j) is sample k = j N + i, the fragment at gl_FragCoord (i + 0.5, j + 0.5).
    std::vector<float> texels(V.size() * 4);
    for (size_t k = 0; k < V.size(); ++k) {
        texels[4 * k] = float(V[k].x);
        texels[4 * k + 1] = float(V[k].y);
        texels[4 * k + 2] = float(V[k].z);
        texels[4 * k + 3] = 0;
    }
    glBindTexture(GL_TEXTURE_2D, view_map_);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, samples, samples, 0, GL_RGBA, GL_FLOAT,
                 texels.data());
    if (glGetError() != GL_NO_ERROR)
        throw std::runtime_error("cannot upload the view's " + std::to_string(samples) + " x " +
                                 std::to_string(samples) + " directions");
}

namespace {

// An N x N RGBA32F (channels 4) or R32F (channels 1) texture read with texelFetch at the
// fragment's pixel (texel (i, j) is sample j N + i), left bound to texture unit `unit`.
void upload_sample_map(unsigned& tex, int unit, int n, int channels,
                       const std::vector<float>& texels, const char* what) {
    glActiveTexture(GLenum(GL_TEXTURE0 + unit));
    if (!tex) {
        glGenTextures(1, &tex);
        glBindTexture(GL_TEXTURE_2D, tex);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, 0);
    }
    glBindTexture(GL_TEXTURE_2D, tex);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glTexImage2D(GL_TEXTURE_2D, 0, channels == 4 ? GL_RGBA32F : GL_R32F, n, n, 0,
                 channels == 4 ? GL_RGBA : GL_RED, GL_FLOAT, texels.data());
    if (glGetError() != GL_NO_ERROR)
        throw std::runtime_error("cannot upload the view's " + std::to_string(n) + " x " +
                                 std::to_string(n) + " " + what);
}

// Texture units: 0 the heights, 1 the view map, 2 - 4 the per-sample maps, then resources.
constexpr int kPointUnit = 2, kLodUnit = 3, kGradUnit = 4, kFirstResourceUnit = 5;

}  // namespace

// The per-sample maps the program reads (PXH_POINT_MAP, PXH_LOD_MAP, PXH_LOD_GRAD), bound to
// their units.
void GlslBackend::upload_sample_maps(const GlslDraw& d, const Program& program) {
    const int n = d.samples;
    const size_t count = size_t(n) * size_t(n);
    if (d.P) {
        if (d.P->size() != count || (d.inside && !d.inside->empty() && d.inside->size() != count))
            throw std::logic_error("glsl: the view's points do not match its " + std::to_string(n) +
                                   " x " + std::to_string(n) + " pixels");
        std::vector<float> t(count * 4);
        for (size_t k = 0; k < count; ++k) {
            t[4 * k] = float((*d.P)[k].x);
            t[4 * k + 1] = float((*d.P)[k].y);
            t[4 * k + 2] = !d.inside || d.inside->empty() || (*d.inside)[k] ? 1.0f : 0.0f;
        }
        upload_sample_map(point_map_, kPointUnit, n, 4, t, "sample points");
    }
    // The footprints as given, or the grid's (one shared by every sample).
    const std::vector<Footprint> grid_J = {orthographic_footprint(n)};
    const std::vector<Footprint>& J = d.J && !d.J->empty() ? *d.J : grid_J;
    if (J.size() != 1 && J.size() != count)
        throw std::logic_error("glsl: " + std::to_string(J.size()) + " footprints for " +
                               std::to_string(count) + " samples");
    auto footprint = [&](size_t k) -> const Footprint& { return J[J.size() == 1 ? 0 : k]; };
    if (program.lod_map) {
        if (d.lambda && d.lambda->size() != count)
            throw std::logic_error("glsl: " + std::to_string(d.lambda->size()) + " lambdas for " +
                                   std::to_string(count) + " samples");
        // None given: 0 for every sample, as the CPU twin takes it (run_cpu, HeightSampler).
        std::vector<float> t(count, 0.0f);
        if (d.lambda)
            for (size_t k = 0; k < count; ++k) t[k] = float((*d.lambda)[k]);
        upload_sample_map(lod_map_, kLodUnit, n, 1, t, "levels of detail");
    }
    if (d.lod == LodMode::grad) {
        std::vector<float> t(count * 4);
        for (size_t k = 0; k < count; ++k) {
            const Footprint& f = footprint(k);
            t[4 * k] = float(f.dPdi.x);
            t[4 * k + 1] = float(f.dPdi.y);
            t[4 * k + 2] = float(f.dPdj.x);
            t[4 * k + 3] = float(f.dPdj.y);
        }
        upload_sample_map(grad_map_, kGradUnit, n, 4, t, "footprints");
    }
    glActiveTexture(GL_TEXTURE0);
}

// The harness's uniforms (common.glsl's u_*), then the method's, checked against the linked
// program's active ones (a misspelt or unused uniform is an error, not a value GL drops).
void GlslBackend::set_uniforms(const Program& program, const GlslDraw& f) {
    const GLuint prog = program.id;
    auto loc = [&](const char* n) { return glGetUniformLocation(prog, n); };
    const Scene<float> sc = scene_cast<float>(f.scene);
    glUniform1i(loc("u_height"), 0);
    glUniform1f(loc("u_scale"), sc.scale);
    glUniform1f(loc("u_bias"), sc.bias);
    glUniform3f(loc("u_view"), sc.V.x, sc.V.y, sc.V.z);
    glUniform1i(loc("u_view_per_sample"), f.V ? 1 : 0);
    glUniform1i(loc("u_view_map"), 1);
    glUniform1i(loc("u_point_map"), kPointUnit);
    glUniform1i(loc("u_lod_map"), kLodUnit);
    glUniform1i(loc("u_grad_map"), kGradUnit);
    glUniform2i(loc("u_size"), f.hf->width, f.hf->height);
    glUniform1f(loc("u_samples"), float(f.samples));
    glUniform1i(loc("u_light_on"), f.light ? 1 : 0);
    if (f.light) {
        const Vec3<float> L(view_vector(f.light->theta_deg, f.light->phi_deg));
        glUniform3f(loc("u_light"), L.x, L.y, L.z);
        glUniform1f(loc("u_shadow_layers_min"), float(f.light->layers_min));
        glUniform1f(loc("u_shadow_layers_max"), float(f.light->layers_max));
    }
    std::vector<DeclaredUniform> declared;
    for (const GlUniform& u : f.uniforms) declared.push_back({u.name, glsl_type_name(u.type)});
    for (const ResourceSpec& r : f.method.resources) declared.push_back({r.name, "sampler2D"});
    if (const std::string why = interface_problem(program.active, declared, program.what);
        !why.empty())
        throw std::runtime_error(why);
    set_method_uniforms(prog, f.uniforms);
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
        if (const std::string why = interface_problem(program.active, declared, what);
            !why.empty()) {
            // A plug-in's: at the shader's declaration of the uniform named, when it has one.
            const size_t q = why.find(" uniform '");
            if (m.plugin_display.empty() || q == std::string::npos) return {why};
            const size_t start = q + 10, end = why.find('\'', start);
            const std::string at =
                uniform_declaration(m.plugin_source, why.substr(start, end - start));
            if (at.empty()) return {why};
            return {m.plugin_display + ":" + at + why.substr(m.plugin_display.size())};
        }
    } catch (const GlslProgramError& e) {
        return e.lines;
    } catch (const std::exception& e) {
        return {e.what()};
    }
    return {};
}

// One untimed frame (the shader JIT), then `frames` timed ones: wall time, and GL_TIME_ELAPSED
// (the GPU's own clock) around each timed draw, read after the wall time is taken.
void GlslBackend::draw_frames(int frames, MethodOutput& out) {
    std::vector<double> ms, gpu_ms;
    GLuint query = 0;
    if (timer_bits_ > 0 && frames > 0) glGenQueries(1, &query);
    for (int frame = 0; frame <= frames; ++frame) {
        const bool timed = frame > 0;
        // Every draw starts from targets whose clear value means "no output" (alpha 0; main()
        // writes alpha 1): a sample the shader discards or leaves unwritten cannot keep what an
        // earlier draw, another method's, left there.
        static const float kNoOutput[4] = {0, 0, 0, 0};
        glClearBufferfv(GL_COLOR, 0, kNoOutput);
        glClearBufferfv(GL_COLOR, 1, kNoOutput);
        const auto t0 = std::chrono::steady_clock::now();
        if (query && timed) glBeginQuery(GL_TIME_ELAPSED, query);
        glDrawArrays(GL_TRIANGLES, 0, 3);
        if (query && timed) glEndQuery(GL_TIME_ELAPSED);
        glFinish();
        const auto t1 = std::chrono::steady_clock::now();
        if (!timed) continue;
        ms.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
        if (query) {
            GLuint64 ns = 0;
            glGetQueryObjectui64v(query, GL_QUERY_RESULT, &ns);
            gpu_ms.push_back(double(ns) * 1e-6);
        }
    }
    if (query) glDeleteQueries(1, &query);
    out.timing = timing_of(glsl_timing().unit, std::move(ms));
    if (!gpu_ms.empty()) out.counters.push_back({kGpuTimeCounter, spread(std::move(gpu_ms))});
}

// The two render targets back into uv, fetches and (with a light) the shadow factors.
void GlslBackend::read_back(int samples, bool light, const std::vector<uint8_t>* inside,
                            MethodOutput& out) {
    const size_t n = size_t(samples) * samples;
    std::vector<float> px(n * 4), sh(n * 4);
    glReadBuffer(GL_COLOR_ATTACHMENT0);
    glReadPixels(0, 0, samples, samples, GL_RGBA, GL_FLOAT, px.data());
    glReadBuffer(GL_COLOR_ATTACHMENT1);
    glReadPixels(0, 0, samples, samples, GL_RGBA, GL_FLOAT, sh.data());
    out.uv.resize(n);
    out.fetches.resize(n);
    out.samples_discarded = 0;
    for (size_t k = 0; k < n; ++k) {  // row 0 of the read-back is gl_FragCoord.y = 0.5: j = 0
        if (px[4 * k + 3] != 1.0f) {  // discarded or unwritten: no uv (counted, never scored)
            out.uv[k] = {NAN, NAN};
            out.fetches[k] = 0;
            // An outside sample is masked by main() (counted as outside by the metrics).
            if (!inside || inside->empty() || (*inside)[k]) ++out.samples_discarded;
            continue;
        }
        out.uv[k] = {px[4 * k], px[4 * k + 1]};
        out.fetches[k] = int(px[4 * k + 2]);
    }
    if (!light) return;
    out.shadow_hard.resize(n);
    out.shadow_soft.resize(n);
    for (size_t k = 0; k < n; ++k) {
        out.shadow_hard[k] = sh[4 * k];
        out.shadow_soft[k] = sh[4 * k + 1];
    }
}

MethodOutput GlslBackend::run(const MethodSpec& m, const Scene<double>& scene,
                              const HeightField& hf, int samples, const std::string& texture_format,
                              const LightSpec* light, int frames, const MethodResources* resources,
                              const std::vector<Vec3d>* V) {
    GlslDraw d;
    d.method = GlslMethod::of(*m.method);
    d.uniforms = method_uniforms(*m.method, m.params);
    d.scene = scene;
    d.hf = &hf;
    d.samples = samples;
    d.texture_format = texture_format;
    d.light = light;
    d.frames = frames;
    d.resources = resources;
    d.V = V;
    return draw(d);
}

MethodOutput GlslBackend::draw(const GlslDraw& d) {
    const HeightField& hf = *d.hf;
    const int samples = d.samples;
    const LightSpec* light = d.light;
    const int frames = d.frames;
    const MethodResources* resources = d.resources;
    const std::vector<Vec3d>* V = d.V;
    use_gl_context(*ctx_);
    const Program& program = program_for(d.method, {d.P != nullptr, d.lod});
    if (d.lod != LodMode::base && !d.levels)
        throw std::logic_error("method '" + d.method.name + "': lod = " + lod_name(d.lod) +
                               " without the field's texture levels");
    upload(hf, d.texture_format, d.lod == LodMode::base ? nullptr : d.levels);
    if (V) upload_view_map(*V, samples);
    upload_sample_maps(d, program);
    ensure_framebuffer(samples);
    glUseProgram(program.id);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, texture_);
    glActiveTexture(GL_TEXTURE1);  // u_view_map: bound (the sampler is active) even when unused
    glBindTexture(GL_TEXTURE_2D, V ? view_map_ : texture_);
    set_uniforms(program, d);
    if (!d.method.resources.empty()) {
        if (!resources || resources->items.size() != d.method.resources.size())
            throw std::logic_error("method '" + d.method.name + "': resources not built");
        resource_textures_.bind(program.id, *resources, kFirstResourceUnit);
    }
    glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
    glViewport(0, 0, samples, samples);
    glBindVertexArray(vao_);
    MethodOutput out;
    draw_frames(frames < 0 ? opt_.frames : frames, out);
    if (const GLenum err = glGetError(); err != GL_NO_ERROR)
        throw std::runtime_error("method '" + d.method.name + "': GL error " + std::to_string(err) +
                                 " while rendering");
    read_back(samples, light != nullptr, d.inside, out);
    out.shader = program.shader;
    out.shader_sha256 = program.sha256;
    return out;
}

// The experiment's top-level gl (the GL context), gl_time_limit_s (seconds per row) and
// texture_format (r32f | r16 | r8, a value or a list: the height texture's variants).
void read_glsl_settings(const ParamDict& ex, BackendSettings& s) {
    s.gl = ex.string("gl", s.gl);
    if (ex.has("gl") && !find_gl_context(s.gl))
        throw InputError(ex.where("gl"),
                         "unknown GL context '" + s.gl + "' (known: " + gl_context_names() + ")");
    s.gl_time_limit_s = ex.number("gl_time_limit_s", s.gl_time_limit_s);
    if (!(s.gl_time_limit_s > 0 && s.gl_time_limit_s <= kMaxGlTimeLimitS))
        throw InputError(ex.where("gl_time_limit_s"),
                         "gl_time_limit_s = " + format_number(s.gl_time_limit_s) +
                             " is outside (0, 86400] (seconds per row)");
    s.texture_formats = ex.strings("texture_format", s.texture_formats);
    for (const auto& f : s.texture_formats)
        if (f != "r32f" && f != "r16" && f != "r8")
            throw InputError(ex.where("texture_format"),
                             "unknown texture_format '" + f + "' (known: r32f, r16, r8)");
}

const TimingSpec& glsl_timing() {
    static const TimingSpec t{
        "ms/frame",
        "wall time (steady_clock) of one frame: clear, draw, glFinish; after one untimed frame "
        "(the shader JIT)",
        {{kGpuTimeCounter, "ms/frame",
          "frame time by GL_TIME_ELAPSED timer query (the GPU's own clock; empty without timer "
          "queries)"}}};
    return t;
}

int glsl_repeats(const BackendSettings& s) { return s.gl_frames; }

std::vector<Variant> glsl_variants(const BackendSettings& settings) {
    std::vector<Variant> out;
    for (const auto& f : settings.texture_formats) out.push_back({"float", f});
    return out;
}

// Its registry entry (harness/backends/registry.cpp's PXH_BACKENDS). The backend itself runs in
// a GL process of its own (make_glsl_backend, harness/backends/gl_worker.cpp).
std::unique_ptr<Backend> make_glsl_backend(const BackendSettings& settings);
const BackendEntry& glsl_backend_entry() {
    static const BackendEntry e = [] {
        BackendEntry b{"glsl",         &read_glsl_settings, &make_glsl_backend,
                       &glsl_variants, &glsl_timing,        &glsl_repeats};
        b.preflight = &glsl_preflight;  // harness/backends/glsl_entry.cpp
        b.warnings = &glsl_warnings;
        b.record = &glsl_record;
        return b;
    }();
    return e;
}

std::vector<Variant> GlslBackend::variants() const {
    BackendSettings s;
    s.texture_formats = opt_.texture_formats;
    return glsl_variants(s);
}

GlslDraw glsl_draw_of(const MethodSpec& m, const ViewInput& view, const Variant& v) {
    const View& rays = view.rays;
    // Sample j N + i is drawn at pixel (i, j): the grid's P from the fragment, any other
    // view's from a per-sample map; either way N x N samples.
    int n = rays.grid;
    if (n <= 0) {
        n = int(std::lround(std::sqrt(double(rays.size()))));
        if (n <= 0 || size_t(n) * size_t(n) != rays.size())
            throw std::runtime_error("the glsl backend draws N x N pixels; this view has " +
                                     std::to_string(rays.size()) + " samples, not a square number");
    }
    if (m.lod != LodMode::base && !view.levels)
        throw std::logic_error("lod = " + std::string(lod_name(m.lod)) +
                               " without the view's texture levels");
    GlslDraw d;
    d.method = GlslMethod::of(*m.method);
    d.uniforms = method_uniforms(*m.method, m.params);
    d.scene = view.scene;
    d.hf = &view.hf;
    d.samples = n;
    d.texture_format = v.texture_format;
    d.light = view.light;
    d.frames = view.timed ? -1 : 0;
    d.resources = view.resources;
    d.V = rays.parallel ? nullptr : &rays.V;
    d.P = rays.grid > 0 && rays.inside.empty() ? nullptr : &rays.P;
    d.inside = rays.inside.empty() ? nullptr : &rays.inside;
    d.lod = m.lod;
    d.levels = m.lod == LodMode::base ? nullptr : view.levels;
    d.lambda = view.lambda;
    d.J = rays.J.empty() ? nullptr : &rays.J;
    return d;
}

MethodOutput GlslBackend::run(const MethodSpec& m, const ViewInput& view, const Variant& v) {
    return draw(glsl_draw_of(m, view, v));
}

std::map<std::string, std::string> GlslBackend::facts() const {
    std::map<std::string, std::string> f = {{"gl_renderer", renderer_},
                                            {"gl_version", version_},
                                            {"gl_context", ctx_->name()},
                                            {"gl_vendor", vendor_},
                                            {"gl_timer_bits", std::to_string(timer_bits_)}};
    for (const auto& [k, v] : ctx_->driver()) f["gl_driver." + k] = v;
    return f;
}

}  // namespace pxh
