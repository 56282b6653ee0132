// Base surfaces (docs/conventions.md section 12): the surface a height field displaces, a plane
// (sections 1-11) or a curved one, each passing through the look-at point (0.5, 0.5, 0) with
// normal +z there. A base gives, for texture coordinates (u, v), its point B, its unit normal N
// and tangent frame (T = dB/du / |dB/du|, Bt = dB/dv / |dB/dv|); for a point in space, the base
// coordinates (u, v) of its foot and its height above the base along N (the displaced surface
// X = B + s (h - b) N is where that height equals s (h(u, v) - b)); and the first hit of a ray
// with the base offset along N by a constant (the shells that bound the relief).
//
// Adding a base: one file harness/scene/bases/NAME.cpp defining a BaseSurface and a factory,
// plus one line in base_registry() (harness/scene/bases/registry.cpp): its name, whether it
// takes a radius, the factory, the reader of its keys, its view and its truth.
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

class Camera;
class ParamDict;
struct BaseView;  // harness/scene/curved_view.h

// A base's registry entry (harness/scene/bases/registry.cpp): everything the experiment's
// reader and the runner ask of a base, so that neither names one.
struct BaseEntry {
    const char* name;
    bool curved;  // takes a radius (`radius`, tiles) and bends: its settings are its radii
    std::unique_ptr<BaseSurface> (*make)(double radius);
    // Reads its own keys of a [[heightfields]] entry (`t`; `name` is the base as given): its
    // settings, one radius each (NaN for a base without one). An InputError at the key's line.
    std::vector<double> (*read)(const ParamDict& t, const std::string& name);
    // The view a camera sees of it (per sample P, V, footprint and frame; the world rays and
    // base hits its truth traces); `top` = s (1 - b), the relief's top.
    BaseView (*view)(const Camera& camera, const BaseSurface& base, double top);
    // The truth that traces it, by name (harness/run/truth_stage.cpp): "exact", the tracer
    // registry's references on the flat relief (harness/truth/registry.cpp), or "curved_walk",
    // the walk through the displaced surface (harness/truth/curved_tracer.h) and its check.
    const char* truth;
};
const std::vector<BaseEntry>& base_registry();
std::vector<std::string> base_names();  // in registry order
// The base a [[heightfields]] entry without `base` has, and an empty base cell of results
// written before the column said it (the registry's first: the plane).
std::string default_base_name();
// nullptr for an unknown name.
const BaseEntry* find_base(const std::string& name);
// The entry called `name`; an InputError(where, "unknown base ...") otherwise.
const BaseEntry& base_entry(const std::string& name, const std::string& where = "base");
// The one check of a radius: "" when base `name` may take it over a relief of scale s and bias
// b (finite, > 0 and > s b, the relief's bottom shell; s = b = 0: the radius alone), else the
// reason. The precision bound over a field's size is the truth's (base_radius_problem,
// harness/truth/curved_tracer.h).
std::string radius_problem(const std::string& name, double radius, double scale = 0,
                           double bias = 0);
// The base NAME (radius ignored by a base without one); throws std::invalid_argument for an
// unknown name or a radius radius_problem refuses.
std::unique_ptr<BaseSurface> make_base(const std::string& name, double radius);

// Registers a base for as long as it lives (tests; a base linked into another binary): it
// joins the registry after the built-in ones.
class BaseRegistration {
  public:
    explicit BaseRegistration(BaseEntry entry);
    ~BaseRegistration();
    BaseRegistration(const BaseRegistration&) = delete;
    BaseRegistration& operator=(const BaseRegistration&) = delete;

  private:
    std::string name_;
};

}  // namespace pxh
