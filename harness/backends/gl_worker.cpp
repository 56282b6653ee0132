// The glsl backend as a run uses it (harness/backends/gl_worker.h): draws and checks sent to the
// GL process (or drawn in this one when no pxh binary is named), answers read back.
#include "harness/backends/gl_worker.h"

#include <filesystem>
#include <stdexcept>

#include "harness/backends/gl_wire.h"
#include "harness/backends/glsl_entry.h"
#include "harness/backends/written_depth.h"
#include "harness/core/error.h"

namespace pxh {

using namespace gl_wire;

GlslChildBackend::GlslChildBackend(const BackendSettings& settings) : settings_(settings) {
    settings_.gl_frames = glsl_repeats(settings_);  // timing_repeats = 0 times no frame either
    if (!settings_.shader_dir.empty()) {
        // A typo must not silently give the built-in shaders' numbers.
        std::error_code ec;
        if (!std::filesystem::is_directory(settings_.shader_dir, ec))
            throw InputError("--shader-dir " + settings_.shader_dir, "no such folder");
    }
    if (gl_worker_program().empty()) {  // no pxh binary to start: draw here
        local_ = std::make_unique<GlslBackend>(GlslOptions{
            settings_.shader_dir, settings_.gl_frames, settings_.texture_formats, settings_.gl});
        facts_ = local_->facts();
        return;
    }
    start();
}

GlslChildBackend::~GlslChildBackend() { stop(); }

std::vector<Variant> GlslChildBackend::variants() const {
    std::vector<Variant> out;
    for (const auto& f : settings_.texture_formats) out.push_back({"float", f});
    return out;
}

std::string GlslChildBackend::shader_of(const MethodInfo& m) const {
    return glsl_shader_description(GlslMethod::of(m), settings_.shader_dir);
}

MethodOutput GlslChildBackend::draw(const GlslDraw& d) {
    if (local_) return local_->draw(d);
    Out req;
    write_draw(req, d);
    const std::string answer = exchange(req.buf);
    In in(answer);
    uint8_t status = 0;
    in(status);
    if (status != 1) {
        std::string why;
        in(why);
        if (status == 2) throw std::logic_error(why);
        throw std::runtime_error(why);
    }
    MethodOutput out;
    in(out);
    in(sources_);
    return out;
}

MethodOutput GlslChildBackend::run(const MethodSpec& m, const ViewInput& view, const Variant& v) {
    MethodOutput out = draw(glsl_draw_of(m, view, v));
    out.depth_tol = float_depth_tol(view.rays);  // the shader computes its depth in float
    return out;
}

std::vector<std::string> GlslChildBackend::check(const GlslMethod& m, const GlUniforms& uniforms,
                                                 const std::vector<uint8_t>& kinds) {
    if (local_) return local_->check(m, uniforms, kinds);
    Out req;
    req(uint8_t(kCheck));
    req(m), req(uniforms), req(kinds);
    const std::string answer = exchange(req.buf);
    In in(answer);
    uint8_t status = 0;
    in(status);
    if (status != 1) {
        std::string why;
        in(why);
        return {why};
    }
    std::vector<std::string> problems;
    in(problems);
    in(sources_);
    return problems;
}

std::unique_ptr<Backend> make_glsl_backend(const BackendSettings& s) {
    return std::make_unique<GlslChildBackend>(s);
}

}  // namespace pxh