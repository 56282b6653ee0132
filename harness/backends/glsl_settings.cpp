// The GLSL backend's settings and registry entry: the experiment's gl, gl_time_limit_s and
// texture_format, the variants (one per texture format), and glsl_backend_entry() with the
// hooks of harness/backends/glsl_entry.h.
#include "harness/backends/glsl_backend.h"
#include "harness/backends/glsl_entry.h"
#include "harness/core/error.h"
#include "harness/core/param_dict.h"
#include "harness/gl/context.h"

namespace pxh {

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

int glsl_repeats(const BackendSettings& s) { return s.timing_repeats == 0 ? 0 : s.gl_frames; }

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

}  // namespace pxh
