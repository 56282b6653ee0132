// The OSMesa context: an OpenGL 4.5 core context from Mesa's off-screen library (software,
// llvmpipe), the default. No display, no EGL: works on any machine with libosmesa6.
//
// libOSMesa is loaded (dlopen) when the first context is made, not linked: it brings LLVM and
// its dependencies, whose relocation took about 0.08 s of every pxh process's start (0.10 s of
// `pxh --version`), though most processes (every command but a GLSL run's GL worker and
// preflight) draw nothing.
#include <GL/osmesa.h>
#include <dlfcn.h>

#include <stdexcept>
#include <string>

#include "harness/gl/context.h"

namespace pxh {
namespace {

// The four entry points pxh calls, from the library loaded on first use.
struct OsmesaApi {
    decltype(&OSMesaCreateContextAttribs) create_context_attribs;
    decltype(&OSMesaMakeCurrent) make_current;
    decltype(&OSMesaGetProcAddress) get_proc_address;
    decltype(&OSMesaDestroyContext) destroy_context;
};

OsmesaApi load_osmesa() {
    void* h = dlopen("libOSMesa.so.8", RTLD_NOW | RTLD_LOCAL);
    if (!h) {
        const char* why = dlerror();
        throw std::runtime_error(
            std::string("OSMesa: cannot load libOSMesa.so.8 (is libosmesa6 from Mesa "
                        "installed?): ") +
            (why ? why : "unknown error"));
    }
    auto sym = [&](const char* name) {
        void* f = dlsym(h, name);
        if (!f) {
            dlclose(h);
            throw std::runtime_error(std::string("OSMesa: libOSMesa.so.8 has no ") + name);
        }
        return f;
    };
    OsmesaApi a;
    a.create_context_attribs =
        reinterpret_cast<decltype(a.create_context_attribs)>(sym("OSMesaCreateContextAttribs"));
    a.make_current = reinterpret_cast<decltype(a.make_current)>(sym("OSMesaMakeCurrent"));
    a.get_proc_address =
        reinterpret_cast<decltype(a.get_proc_address)>(sym("OSMesaGetProcAddress"));
    a.destroy_context = reinterpret_cast<decltype(a.destroy_context)>(sym("OSMesaDestroyContext"));
    return a;  // the library stays loaded for the process's life
}

const OsmesaApi& osmesa() {
    static const OsmesaApi api = load_osmesa();  // a throw leaves it to the next call
    return api;
}

class OsmesaContext final : public GlContext {
  public:
    OsmesaContext() {
        const int attribs[] = {OSMESA_FORMAT,
                               OSMESA_RGBA,
                               OSMESA_DEPTH_BITS,
                               0,
                               OSMESA_STENCIL_BITS,
                               0,
                               OSMESA_ACCUM_BITS,
                               0,
                               OSMESA_PROFILE,
                               OSMESA_CORE_PROFILE,
                               OSMESA_CONTEXT_MAJOR_VERSION,
                               4,
                               OSMESA_CONTEXT_MINOR_VERSION,
                               5,
                               0};
        ctx_ = osmesa().create_context_attribs(attribs, nullptr);
        if (!ctx_)
            throw std::runtime_error(
                "OSMesa: cannot create an OpenGL 4.5 core context "
                "(is libosmesa6 from Mesa installed?)");
        try {
            make_current();
        } catch (...) {
            osmesa().destroy_context(ctx_);
            throw;
        }
    }
    ~OsmesaContext() override { osmesa().destroy_context(ctx_); }
    OsmesaContext(const OsmesaContext&) = delete;
    OsmesaContext& operator=(const OsmesaContext&) = delete;

    // The 4 x 4 buffer only satisfies OSMesaMakeCurrent: the backend renders into its own FBO.
    void make_current() override {
        if (!osmesa().make_current(ctx_, buffer_, GL_UNSIGNED_BYTE, 4, 4))
            throw std::runtime_error("OSMesa: cannot make the context current");
    }
    GlProc proc_address(const char* name) const override {
        return reinterpret_cast<GlProc>(osmesa().get_proc_address(name));
    }
    std::string name() const override { return "osmesa"; }
    std::map<std::string, std::string> driver() const override {
        return {{"OSMESA_VERSION", std::to_string(OSMESA_MAJOR_VERSION) + "." +
                                       std::to_string(OSMESA_MINOR_VERSION) + "." +
                                       std::to_string(OSMESA_PATCH_VERSION)}};
    }

  private:
    OSMesaContext ctx_ = nullptr;
    unsigned char buffer_[4 * 4 * 4] = {};
};

}  // namespace

std::unique_ptr<GlContext> make_osmesa_context() { return std::make_unique<OsmesaContext>(); }

}  // namespace pxh
