// Base surfaces (docs/conventions.md section 12): the surface a height field displaces, a plane
// (sections 1-11) or a curved one, each passing through the look-at point (0.5, 0.5, 0) with
// normal +z there. A base gives, for texture coordinates (u, v), its point B, its unit normal N
// and tangent frame (T = dB/du / |dB/du|, Bt = dB/dv / |dB/dv|); for a point in space, the base
// coordinates (u, v) of its foot and its height above the base along N (the displaced surface
// X = B + s (h - b) N is where that height equals s (h(u, v) - b)); and the first hit of a ray
// with the base offset along N by a constant (the shells that bound the relief).
//
// Adding a base: one file harness/scene/bases/NAME.cpp defining a BaseSurface and a factory,
// plus one line in base_registry() (harness/scene/bases/registry.cpp).
#pragma once
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "harness/core/vec.h"

namespace pxh {

inline Vec3d v3_add(Vec3d a, Vec3d b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline Vec3d v3_sub(Vec3d a, Vec3d b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline Vec3d v3_scale(Vec3d a, double k) { return {a.x * k, a.y * k, a.z * k}; }
inline double v3_dot(Vec3d a, Vec3d b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline Vec3d v3_unit(Vec3d a) { return v3_scale(a, 1.0 / std::sqrt(v3_dot(a, a))); }

struct BaseFrame {
    Vec3d B, T, Bt, N;
};

// A point in the base's own coordinates: the (u, v) of its foot on the base, unwrapped, and its
// height above the base along N.
struct BaseCoord {
    Vec2d uv;
    double height;
};

class BaseSurface {
  public:
    virtual ~BaseSurface() = default;
    virtual std::string name() const = 0;
    virtual double radius() const = 0;  // R in tiles; NaN for the plane
    virtual BaseFrame frame(Vec2d uv) const = 0;
    virtual BaseCoord coords(Vec3d p) const = 0;
    // The smallest t > t_min with o + t d on the base offset by `offset` along N (d unit), or
    // NaN when there is none; with `leaving`, the t where the ray leaves that shell instead
    // (NaN when it never is inside it after t_min).
    virtual double hit(Vec3d o, Vec3d d, double offset, double t_min, bool leaving) const = 0;
    // An upper bound of |d(u, v)/dt| at p along any unit direction: how fast texture coordinates
    // change per unit of distance travelled there (1 on the plane).
    virtual double uv_speed(Vec3d p) const = 0;
    // The normal curvatures along T and Bt (1/tile, > 0 where the base bends away from the
    // normal's side): (0, 0), (1/R, 0), (1/R, 1/R). Uniform over these bases.
    virtual Vec2d curvature() const = 0;
};

// The first and second roots of a t^2 + 2 h t + c = 0 (a > 0), NaN when there are none;
// computed without cancellation.
struct QuadRoots {
    double t0 = NAN, t1 = NAN;
};
inline QuadRoots quad_roots(double a, double h, double c) {
    const double disc = h * h - a * c;
    if (!(disc >= 0) || !(a > 0)) return {};
    const double q = -(h + std::copysign(std::sqrt(disc), h));
    double r0 = q / a, r1 = q != 0 ? c / q : 0.0;
    if (r0 > r1) std::swap(r0, r1);
    return {r0, r1};
}

struct BaseEntry {
    const char* name;
    bool curved;  // takes a radius
    std::unique_ptr<BaseSurface> (*make)(double radius);
};
const std::vector<BaseEntry>& base_registry();
std::vector<std::string> base_names();  // in registry order
// nullptr for an unknown name.
const BaseEntry* find_base(const std::string& name);
// The base NAME (radius ignored by the plane); throws std::invalid_argument for an unknown
// name or a radius that is not finite and positive on a curved base.
std::unique_ptr<BaseSurface> make_base(const std::string& name, double radius);

}  // namespace pxh
