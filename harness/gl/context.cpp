#include "harness/gl/context.h"

#include <glad/gl.h>

#include <stdexcept>

namespace pxh {
namespace {

GLADapiproc load_entry(void* ctx, const char* name) {
    return reinterpret_cast<GLADapiproc>(static_cast<const GlContext*>(ctx)->proc_address(name));
}

std::string gl_string(GLenum what) {
    const GLubyte* s = glGetString(what);
    return s ? reinterpret_cast<const char*>(s) : "unknown";
}

}  // namespace

void use_gl_context(GlContext& ctx) {
    // The type whose entry points glad holds now. glad's pointers are process-wide: GL calls
    // for two context types must not run on two threads at once (the backend draws on one).
    static std::string loaded;
    ctx.make_current();
    const std::string type = ctx.name();
    if (loaded == type) return;
    loaded.clear();
    if (!gladLoadGLUserPtr(&load_entry, &ctx))
        throw std::runtime_error(type + ": cannot load the OpenGL 4.5 entry points");
    loaded = type;
}

GlInfo current_gl_info() {
    GlInfo info;
    info.vendor = gl_string(GL_VENDOR);
    info.renderer = gl_string(GL_RENDERER);
    info.version = gl_string(GL_VERSION);
    GLint bits = 0;
    glGetQueryiv(GL_TIME_ELAPSED, GL_QUERY_COUNTER_BITS, &bits);
    info.timer_bits = glGetError() == GL_NO_ERROR ? bits : 0;
    return info;
}

}  // namespace pxh
