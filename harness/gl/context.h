// An OpenGL 4.5 core context that renders off screen: the backend draws into its own framebuffer
// object, so a context needs no window and no surface. Implementations, one file each, are
// listed in harness/gl/registry.cpp (one line per context): osmesa_context.cpp (the default),
// egl_context.cpp (headless EGL).
// No GL or EGL header here: OSMesa's header includes the system gl.h, which clashes with the
// GL loader's (glad) in the files that draw.
#pragma once
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace pxh {

using GlProc = void (*)();

class GlContext {
  public:
    virtual ~GlContext() = default;
    // Makes this context current on the calling thread (several may exist in one process);
    // throws std::runtime_error on failure. Use use_gl_context() to also point the loader at it.
    virtual void make_current() = 0;
    // A GL entry point by name (nullptr when absent), for the loader.
    virtual GlProc proc_address(const char* name) const = 0;
    // The registered name ("osmesa", "egl").
    virtual std::string name() const = 0;
    // What run.json records about the driver behind the context, key -> value (for EGL:
    // EGL_VENDOR, EGL_VERSION, the platform used, the device's extensions; for OSMesa: its
    // version).
    virtual std::map<std::string, std::string> driver() const = 0;
};

// ---- The registry (harness/gl/registry.cpp) ----
struct GlContextType {
    std::string name, summary;
    std::unique_ptr<GlContext> (*make)();  // creates the context, current on the calling thread
};
const std::vector<GlContextType>& gl_context_types();  // sorted by name
const GlContextType* find_gl_context(const std::string& name);
std::string gl_context_names();  // "egl, osmesa": for messages
// Creates the named context, current on the calling thread. Throws InputError("--gl", ...) for
// an unknown name, std::runtime_error (one line: what failed) when no context can be made.
std::unique_ptr<GlContext> make_gl_context(const std::string& name);
// Whether this process has made a GL context (make_gl_context was called). (The glsl backend's
// GL process is pxh exec'd afresh, harness/backends/gl_worker.h, so it inherits none of this
// process's GL or lock state whether or not a context was made here.)
bool gl_context_made_in_process();

// ---- Loading GL (harness/gl/context.cpp) ----
// Makes `ctx` current and points the GL loader (glad's global entry points) at its
// implementation; they are reloaded only when the last context loaded was of another type
// (entry points are context-independent within one implementation). Throws std::runtime_error.
void use_gl_context(GlContext& ctx);

// What the current context says about itself (glGetString, glGetQueryiv).
struct GlInfo {
    std::string vendor, renderer, version;
    int timer_bits = 0;  // GL_QUERY_COUNTER_BITS of GL_TIME_ELAPSED: 0 = no usable timer queries
};
GlInfo current_gl_info();

}  // namespace pxh
