// The point a method setting writes the depth of (docs/conventions.md section 8), as the C++
// twin computes it from the method's answer: MethodOutput::depth. The GLSL twin computes the same
// in methods/common.glsl's main() and writes it to gl_FragDepth.
#pragma once
#include <vector>

#include "harness/backends/backend.h"

namespace pxh {

// The written depth of every sample for the setting's depth mode into o.depth (NaN where o.uv
// is not finite), from the method's own answer: o.uv and the height z_m it handed back beside it
// (o.hit_z, MethodHit::z in the twin's precision; never rebuilt from uv), and for `engine` its
// engine's formula on them (o.engine_z: the height that formula reads). `as_float`: the method
// ran in float, so it saw float(P), and o.depth_tol holds per sample how far float rounding alone
// moves the written point (2^-21 max(|P.x|, |P.y|, 1): four float steps); in double o.depth_tol
// stays empty.
void add_written_depths(const MethodSpec& m, const ViewInput& view, MethodOutput& o, bool as_float);

// The span of depth (tiles) the GL twin's depth target holds around P: gl_FragDepth = 0.5 +
// depth / span, so [-span / 2, span / 2]; span = 4 (1 + |s| / max(min V.z, 1e-3)) over the view's
// inside samples: four times the deepest ray's travel through the slab.
double depth_target_span(const View& rays, double scale);

// Per sample, four float steps of its coordinates (2^-21 max(|P.x|, |P.y|, 1)): how far float
// rounding alone moves a written depth computed in float.
std::vector<double> float_depth_tol(const View& rays);

}  // namespace pxh
