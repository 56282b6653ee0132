// A camera's view of a base surface (docs/conventions.md section 12), what a base's entry gives
// (BaseEntry::view): on a curved base, where each sample's eye ray first meets the base, the
// method's inputs there (the base hit's (u, v) as the sample's P, the view vector in the tangent
// frame V_ts = (V . T, V . Bt, V . N) and the footprint of u per pixel step by central
// differences of the base hit), and the rays themselves, which the truth
// (harness/truth/curved_tracer.h) traces against the displaced surface; on the plane, the
// camera's own view.
#pragma once
#include <cstdint>
#include <vector>

#include "harness/scene/base_surface.h"
#include "harness/scene/view.h"

namespace pxh {

struct BaseView {
    // The methods' view: P, V (tangent space, per sample), J per sample; inside = the ray meets
    // the base with V_ts.z > cos(89 degrees) (a sample that misses the base carries the look-at
    // point's P = (0.5, 0.5) and V = (0, 0, 1), and is outside). forward: the camera's depth
    // axis (world space).
    View view;
    std::vector<WorldRay> rays;     // per sample, from the camera
    std::vector<uint8_t> base_hit;  // 1 where the ray meets the base (inside or not)
    std::vector<Vec3d> base_point;  // the base hit in space (NaN where it misses)
    Vec3d forward;                  // the camera's depth axis in space
};
using CurvedView = BaseView;  // a curved base's

// `top`: the highest z of anything in the scene (s (1 - b): the displaced surface's top).
// Central differences of the base hit at +-0.25 pixel; one-sided where one side misses the
// base; (0, 0) per step where both do.
CurvedView curved_view(const Camera& camera, const BaseSurface& base, double top);
// The plane's: the camera's view itself (rays, base hits and points empty; forward its depth
// axis). Base and top are not used.
BaseView flat_view(const Camera& camera, const BaseSurface& base, double top);

}  // namespace pxh
