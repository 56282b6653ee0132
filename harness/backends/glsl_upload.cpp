// The GLSL backend's uploads: the height texture (and its levels), the framebuffer, the view's
// per-sample maps (directions, points, levels of detail, footprints) and the uniforms.
#include <glad/gl.h>

#include <cmath>
#include <stdexcept>

#include "harness/backends/glsl_backend.h"
#include "harness/backends/glsl_parts.h"
#include "harness/gl/context.h"
#include "harness/scene/perspective_camera.h"

namespace pxh {

using namespace glsl_detail;

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
    // The depth target: 32-bit float (what main() writes to gl_FragDepth: the written depth).
    glBindTexture(GL_TEXTURE_2D, depth_);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_DEPTH_COMPONENT32F, n, n, 0, GL_DEPTH_COMPONENT, GL_FLOAT,
                 nullptr);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, depth_, 0);
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
    // u_axis_map is always declared: the axes, or any texture bound to its unit
    if (d.axes) {
        if (d.axes->size() != count)
            throw std::logic_error("glsl: " + std::to_string(d.axes->size()) + " depth axes for " +
                                   std::to_string(count) + " samples");
        std::vector<float> t(count * 4);
        for (size_t k = 0; k < count; ++k) {
            t[4 * k] = float((*d.axes)[k].x);
            t[4 * k + 1] = float((*d.axes)[k].y);
            t[4 * k + 2] = float((*d.axes)[k].z);
        }
        upload_sample_map(axis_map_, kAxisUnit, n, 4, t, "depth axes");
    } else {
        glActiveTexture(GLenum(GL_TEXTURE0 + kAxisUnit));
        glBindTexture(GL_TEXTURE_2D, texture_);
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
    glUniform2f(loc("u_curvature"), float(sc.curvature.x), float(sc.curvature.y));
    glUniform1i(loc("u_view_per_sample"), f.V ? 1 : 0);
    glUniform1i(loc("u_view_map"), 1);
    glUniform1i(loc("u_point_map"), kPointUnit);
    glUniform1i(loc("u_lod_map"), kLodUnit);
    glUniform1i(loc("u_grad_map"), kGradUnit);
    glUniform2i(loc("u_size"), f.hf->width, f.hf->height);
    glUniform1f(loc("u_samples"), float(f.samples));
    glUniform1i(loc("u_light_on"), f.light ? 1 : 0);
    glUniform1i(loc("u_depth_mode"), f.depth.mode);
    glUniform1i(loc("u_hit_height"), f.depth.hit);
    glUniform3f(loc("u_depth_axis"), float(f.depth.axis.x), float(f.depth.axis.y),
                float(f.depth.axis.z));
    glUniform1f(loc("u_depth_span"), float(f.depth.span));
    glUniform1i(loc("u_depth_axis_per_sample"), f.axes ? 1 : 0);
    glUniform1i(loc("u_axis_map"), kAxisUnit);
    if (f.light) {
        const Vec3<float> L(view_vector(f.light->theta_deg, f.light->phi_deg));
        glUniform3f(loc("u_light"), L.x, L.y, L.z);
        glUniform1f(loc("u_shadow_layers_min"), float(f.light->layers_min));
        glUniform1f(loc("u_shadow_layers_max"), float(f.light->layers_max));
    }
    std::vector<DeclaredUniform> declared;
    for (const GlUniform& u : f.uniforms) declared.push_back({u.name, glsl_type_name(u.type)});
    for (const ResourceSpec& r : f.method.resources) declared.push_back({r.name, "sampler2D"});
    if (const std::string why = interface_problem(
            program.active,
            required_uniforms(program.active, declared, !f.method.plugin_display.empty()),
            program.what);
        !why.empty())
        throw std::runtime_error(why);
    set_method_uniforms(prog, f.uniforms);
}

}  // namespace pxh
