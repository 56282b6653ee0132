// The point a method setting writes the depth of (docs/conventions.md section 11), as the C++
// twin computes it from the method's uv: MethodOutput::depth. The GLSL twin computes the same in
// methods/common.glsl's main() and writes it to gl_FragDepth.
#pragma once
#include <vector>

#include "harness/backends/backend.h"

namespace pxh {

// The hit's height z_m of a method setting at sample k (methods/depth.h): its search line's
// height at uv for a `ray` method (the surface's where that line is within 1e-6 of vertical),
// else s (h(uv) - b) at the level the setting sampled; not counted as a fetch.
double hit_height_at(const MethodSpec& m, const ViewInput& view, size_t k, Vec2d uv);

// depth(X_w) of every sample for the setting's depth mode (NaN where uv is not finite).
std::vector<double> written_depths(const MethodSpec& m, const ViewInput& view,
                                   const std::vector<Vec2d>& uv);

}  // namespace pxh
