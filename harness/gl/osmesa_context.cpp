// The OSMesa context: an OpenGL 4.5 core context from Mesa's off-screen library (software,
// llvmpipe), the default. No display, no EGL: works on any machine with libosmesa6.
#include <GL/osmesa.h>

#include <stdexcept>

#include "harness/gl/context.h"

namespace pxh {
namespace {

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
        ctx_ = OSMesaCreateContextAttribs(attribs, nullptr);
        if (!ctx_)
            throw std::runtime_error(
                "OSMesa: cannot create an OpenGL 4.5 core context "
                "(is libosmesa6 from Mesa installed?)");
        try {
            make_current();
        } catch (...) {
            OSMesaDestroyContext(ctx_);
            throw;
        }
    }
    ~OsmesaContext() override { OSMesaDestroyContext(ctx_); }
    OsmesaContext(const OsmesaContext&) = delete;
    OsmesaContext& operator=(const OsmesaContext&) = delete;

    // The 4 x 4 buffer only satisfies OSMesaMakeCurrent: the backend renders into its own FBO.
    void make_current() override {
        if (!OSMesaMakeCurrent(ctx_, buffer_, GL_UNSIGNED_BYTE, 4, 4))
            throw std::runtime_error("OSMesa: cannot make the context current");
    }
    GlProc proc_address(const char* name) const override {
        return reinterpret_cast<GlProc>(OSMesaGetProcAddress(name));
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
