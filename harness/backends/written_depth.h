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
// P is the sample's point as the method saw it (see written_depths).
double hit_height_at(const MethodSpec& m, const ViewInput& view, size_t k, Vec2d P, Vec2d uv);

// The written depth of every sample for the setting's depth mode into o.depth (NaN where o.uv
// is not finite). `as_float`: the method ran in float, so its search line starts at float(P),
// the point it saw, and o.depth_tol holds per sample how far float rounding alone moves the
// written point (2^-21 max(|P.x|, |P.y|, 1): four float steps; the HDRP preset's offset faded
// to nearly nothing past its LOD threshold lands a step or two off its line, on either side);
// in double o.depth_tol stays empty.
void add_written_depths(const MethodSpec& m, const ViewInput& view, MethodOutput& o, bool as_float);

}  // namespace pxh
