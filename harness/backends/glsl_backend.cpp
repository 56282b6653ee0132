// The GLSL backend (harness/backends/glsl_backend.h): the context and its objects, one row's
// draw, its timing (wall clock and GL_TIME_ELAPSED) and the read-back; the programs, uploads and
// settings are in glsl_program.cpp, glsl_upload.cpp and glsl_settings.cpp.
#include "harness/backends/glsl_backend.h"

#include <glad/gl.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <map>
#include <stdexcept>

#include "harness/backends/glsl_parts.h"
#include "harness/backends/shade_gl.h"
#include "harness/backends/shaders.h"
#include "harness/backends/written_depth.h"
#include "harness/core/error.h"
#include "harness/gl/context.h"
#include "harness/scene/perspective_camera.h"
#include "harness/truth/ground_truth.h"

namespace pxh {

using namespace glsl_detail;

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
    g.plugin_files = m.plugin_files;
    g.plugin_original = m.plugin_original;
    g.plugin_original_display = m.plugin_original_display;
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
    glGenTextures(1, &depth_);
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
    glDeleteTextures(1, &depth_);
    glDeleteTextures(1, &texture_);
    if (view_map_) glDeleteTextures(1, &view_map_);
    for (unsigned t : {point_map_, lod_map_, grad_map_, axis_map_})
        if (t) glDeleteTextures(1, &t);
    glDeleteFramebuffers(1, &fbo_);
    glDeleteVertexArrays(1, &vao_);
}

std::string GlslBackend::context_name() const { return ctx_->name(); }
std::map<std::string, std::string> GlslBackend::driver() const { return ctx_->driver(); }

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
        static const float kFar = 1.0f;
        glClearBufferfv(GL_DEPTH, 0, &kFar);
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
std::vector<float> GlslBackend::read_back(int samples, bool light,
                                          const std::vector<uint8_t>* inside, MethodOutput& out) {
    const size_t n = size_t(samples) * samples;
    std::vector<float> px(n * 4), sh(n * 4);
    glReadBuffer(GL_COLOR_ATTACHMENT0);
    glReadPixels(0, 0, samples, samples, GL_RGBA, GL_FLOAT, px.data());
    glReadBuffer(GL_COLOR_ATTACHMENT1);
    glReadPixels(0, 0, samples, samples, GL_RGBA, GL_FLOAT, sh.data());
    out.uv.resize(n);
    out.fetches.resize(n);
    out.samples_discarded = 0;
    out.discarded.assign(n, 0);
    for (size_t k = 0; k < n; ++k) {  // row 0 of the read-back is gl_FragCoord.y = 0.5: j = 0
        if (px[4 * k + 3] != 1.0f) {  // discarded or unwritten: no uv (counted, never scored)
            out.uv[k] = {NAN, NAN};
            out.fetches[k] = 0;
            // An outside sample is masked by main() (counted as outside by the metrics).
            if (!inside || inside->empty() || (*inside)[k]) {
                ++out.samples_discarded;
                out.discarded[k] = 1;
            }
            continue;
        }
        out.uv[k] = {px[4 * k], px[4 * k + 1]};
        out.fetches[k] = int(px[4 * k + 2]);
    }
    if (light) {
        out.shadow_hard.resize(n);
        out.shadow_soft.resize(n);
        for (size_t k = 0; k < n; ++k) {
            out.shadow_hard[k] = sh[4 * k];
            out.shadow_soft[k] = sh[4 * k + 1];
        }
    }
    return sh;  // its z: the written depth as computed (read_depth)
}

// The depth target back into depth(X_w) (NaN where there is no uv). GL clamps gl_FragDepth to
// the target's [0, 1] and makes a number of a NaN, so main() also writes the depth it computed
// to the second target's z (a float colour target, not clamped): where that is not finite the
// depth is NaN (counted in depth_nonfinite), and where it lies beyond the span the target holds
// it is that value (counted in depth_clamped), not the clamped one.
void GlslBackend::read_depth(int samples, double span, const std::vector<float>& written,
                             MethodOutput& out) {
    const size_t n = size_t(samples) * samples;
    std::vector<float> z(n);
    glReadPixels(0, 0, samples, samples, GL_DEPTH_COMPONENT, GL_FLOAT, z.data());
    out.depth.resize(n);
    out.depth_span = span;
    for (size_t k = 0; k < n; ++k) {
        if (!std::isfinite(out.uv[k].x)) {
            out.depth[k] = NAN;
            continue;
        }
        const double raw = written.size() == 4 * n ? double(written[4 * k + 2]) : 0.0;
        if (!std::isfinite(raw) || std::abs(raw) > 0.5 * span) out.depth[k] = raw;
        else out.depth[k] = (double(z[k]) - 0.5) * span;
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

// [shading]: the uv just read back shaded by the GLSL twin (harness/backends/shade_gl.h) in
// this context, with its own program, textures and target (every draw binds its own again).
void GlslBackend::shade(const GlslDraw& d, MethodOutput& out) {
    const AlbedoLevels& al = *d.albedo;
    const Material m{d.levels, &al, d.scene.scale, d.light_dir,
                     std::log2(double(std::max(al.width, al.height)) /
                               double(std::max(d.hf->width, d.hf->height)))};
    std::vector<uint8_t> covered(out.uv.size(), 1);
    if (d.inside && !d.inside->empty()) covered = *d.inside;
    out.shaded = shade_gl(*ctx_, {m, out.uv, *d.lambda, covered, d.samples});
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
    // Every fragment writes its gl_FragDepth (the test always passes: one triangle).
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_ALWAYS);
    glDepthMask(GL_TRUE);
    MethodOutput out;
    draw_frames(frames < 0 ? opt_.frames : frames, out);
    if (const GLenum err = glGetError(); err != GL_NO_ERROR)
        throw std::runtime_error("method '" + d.method.name + "': GL error " + std::to_string(err) +
                                 " while rendering");
    const std::vector<float> written = read_back(samples, light != nullptr, d.inside, out);
    read_depth(samples, d.depth.span, written, out);
    if (d.albedo && d.levels && d.lambda) shade(d, out);
    out.shader = program.shader;
    out.shader_sha256 = program.sha256;
    return out;
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

GlslDepth glsl_depth_of(const MethodSpec& m, const View& rays, double scale) {
    GlslDepth g;
    g.mode = int(m.depth);
    g.hit = int(m.method->hit_height_of(m.params));
    g.axis = rays.depth_axis();
    g.span = depth_target_span(rays, scale);
    return g;
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
    d.depth = glsl_depth_of(m, rays, view.scene.scale);
    d.axes = rays.axes.empty() ? nullptr : &rays.axes;
    if (view.shading && view.levels && view.lambda) {  // shaded in GL too
        d.levels = view.levels;  // uploaded as the height's mip chain only when lod is not base
        d.albedo = view.shading->levels.get();
        d.light_dir = light_direction(view.shading->elevation_deg, view.shading->azimuth_deg);
    }
    return d;
}

MethodOutput GlslBackend::run(const MethodSpec& m, const ViewInput& view, const Variant& v) {
    MethodOutput out = draw(glsl_draw_of(m, view, v));
    out.depth_tol = float_depth_tol(view.rays);  // the shader computes its depth in float
    return out;
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
