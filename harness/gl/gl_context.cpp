#include "harness/gl/gl_context.h"

#include <GL/osmesa.h>

#include <stdexcept>

namespace pxh {

OsmesaContext::OsmesaContext() {
    const int attribs[] = {OSMESA_FORMAT,                OSMESA_RGBA,
                           OSMESA_DEPTH_BITS,            0,
                           OSMESA_STENCIL_BITS,          0,
                           OSMESA_ACCUM_BITS,            0,
                           OSMESA_PROFILE,               OSMESA_CORE_PROFILE,
                           OSMESA_CONTEXT_MAJOR_VERSION, 4,
                           OSMESA_CONTEXT_MINOR_VERSION, 5,
                           0};
    OSMesaContext ctx = OSMesaCreateContextAttribs(attribs, nullptr);
    if (!ctx)
        throw std::runtime_error("OSMesa: cannot create an OpenGL 4.5 core context "
                                 "(is libosmesa6 from Mesa installed?)");
    if (!OSMesaMakeCurrent(ctx, buffer_, GL_UNSIGNED_BYTE, 4, 4)) {
        OSMesaDestroyContext(ctx);
        throw std::runtime_error("OSMesa: cannot make the context current");
    }
    ctx_ = ctx;
}

OsmesaContext::~OsmesaContext() {
    if (ctx_) OSMesaDestroyContext(static_cast<OSMesaContext>(ctx_));
}

void OsmesaContext::make_current() {
    if (!OSMesaMakeCurrent(static_cast<OSMesaContext>(ctx_), buffer_, GL_UNSIGNED_BYTE, 4, 4))
        throw std::runtime_error("OSMesa: cannot make the context current");
}

GlProc OsmesaContext::proc_address(const char* name) {
    return reinterpret_cast<GlProc>(OSMesaGetProcAddress(name));
}

}  // namespace pxh
