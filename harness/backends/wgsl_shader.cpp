#include "harness/backends/hlsl_shader.h"
#include "harness/core/error.h"

namespace pxh {

ConvertedShader wgsl_to_glsl(const std::string&, const std::string&, const std::string&,
                             const std::string& display, const EngineAdapter&) {
    throw InputError(display, "WGSL plug-ins are not supported yet");
}

}  // namespace pxh
