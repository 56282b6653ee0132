// An offscreen OpenGL 4.5 core context through OSMesa (software rendering, llvmpipe).
// Kept apart from the GL loader's headers: OSMesa's header includes the system gl.h.
#pragma once
#include <string>

namespace pxh {

using GlProc = void (*)();

class OsmesaContext {
  public:
    // Creates and makes current a 4.5 core context; throws std::runtime_error on failure.
    OsmesaContext();
    ~OsmesaContext();
    OsmesaContext(const OsmesaContext&) = delete;
    OsmesaContext& operator=(const OsmesaContext&) = delete;
    static GlProc proc_address(const char* name);
    // Makes this context current on the calling thread (several may exist in one process).
    void make_current();

  private:
    void* ctx_ = nullptr;
    unsigned char buffer_[4 * 4 * 4] = {};
};

}  // namespace pxh
