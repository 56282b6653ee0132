// What one view of one field is, for the methods: per-view constants (docs/conventions.md
// sections 2, 3) in the method's precision, and the optional light of the self-shadowing
// metrics.
#pragma once
#include "harness/core/vec.h"

namespace pxh {

template <typename T>
struct Scene {
    T scale = T(0.05), bias = T(1);  // s, b: surface z = s (h - b)
    Vec3<T> V{T(0), T(0), T(1)};     // unit vector from the surface toward the eye
    int width = 1, height = 1;       // texels of the height field
    // The base's normal curvatures along T and Bt (1/tile, > 0 convex; docs/conventions.md
    // section 12): (0, 0) on the plane. What the silhouette-aware methods bend their ray by.
    Vec2<T> curvature{T(0), T(0)};
    T z_top() const { return scale * (T(1) - bias); }
    T z_bot() const { return -scale * bias; }
};

template <typename T>
Scene<T> scene_cast(const Scene<double>& s) {
    return {T(s.scale), T(s.bias), Vec3<T>(s.V),
            s.width,    s.height,  {T(s.curvature.x), T(s.curvature.y)}};
}

// Optional directional light for the self-shadowing metrics.
struct LightSpec {
    double theta_deg = 45, phi_deg = 180;
    double layers_min = 8, layers_max = 32;  // the shadow march's layer counts
};

}  // namespace pxh
