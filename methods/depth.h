// The depth a method setting writes (docs/conventions.md section 11): the point X_w whose view
// depth goes into the depth buffer, chosen by the setting's `depth` mode, and the height z_m at
// which a method places its hit (what `hit` writes).
//
// Depths here are offsets along the view's depth axis f (harness/scene/view.h: the perspective
// camera's forward vector; -V for parallel rays) from the sample's point P on the polygon:
// depth(X) = (X - P) . f, in tiles. Only differences of view depth within one pixel are used, so
// the eye's own depth drops out.
#pragma once
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "harness/core/vec.h"

namespace pxh {

// The [[methods]] key `depth` (a value or a list, swept like lod; default base).
//   base    X_w = P, the polygon's point (engines without a depth offset: Bevy, Godot, three.js)
//   hit     X_w = (uv_m, z_m): the method's own hit, reprojected
//   engine  the preset's engine's own formula (MethodInfo::engine_depth); base for a method
//           whose engine writes no depth offset
enum class DepthMode { base, hit, engine };
const char* depth_name(DepthMode mode);
std::vector<std::string> depth_names();  // base, hit, engine

// Where a method places its hit's height z_m (MethodInfo::hit_height):
//   surface  z_m = s (h(uv_m) - b) at the level of detail it sampled (single-step methods)
//   ray      the height a search hands back with its answer (MethodHit::z): the layer or
//            refined height of its line; checked by tests/methods/depth_test.cpp on every method
//   shader   a plug-in shader: what it passes to pxh_write_hit(z) (methods/common.glsl), else
//            the polygon (X_w = P)
enum class HitHeight { surface, ray, shader };

// What a search hands back (eval's return type for every method whose answer is a point of a
// line it searched): uv_m and the height z_m of its answer (NaN where uv is NaN, and for a
// single-step answer: then z_m is the surface's at uv_m at the level it sampled), and, for an
// engine preset whose depth formula reads a height its engine fetched elsewhere, that surface
// height (engine_z; NaN: the surface's at uv_m).
template <typename T>
struct MethodHit {
    Vec2<T> uv;
    T z = std::numeric_limits<T>::quiet_NaN();
    T engine_z = std::numeric_limits<T>::quiet_NaN();
    static MethodHit none() {
        const T nan = std::numeric_limits<T>::quiet_NaN();
        return {{nan, nan}, nan, nan};
    }
};

// What an engine's depth formula sees of one sample (MethodInfo::engine_depth).
struct EngineDepthInput {
    Vec2d P;          // the sample's point on the polygon
    Vec3d V;          // toward the eye (unit)
    Vec3d f;          // the view's depth axis
    Vec2d uv;         // the method's uv_m
    double z_line;    // z_m: the height it handed back (a one-fetch method: the surface's)
    double z_engine;  // the surface height its engine's formula reads (MethodHit::engine_z;
                      // s (h(uv_m) - b) at the level it sampled where not given)
    double scale, bias;
};

// The eye ray's search line uv = P + d z (through P along -V, V toward the eye): d = V.xy / V.z.
inline Vec2d eye_ray_direction(Vec3d V) { return {V.x / V.z, V.y / V.z}; }

// depth(X) of the point (xy, z): its offset from P along f.
inline double depth_offset(Vec2d P, Vec3d f, Vec2d xy, double z) {
    return (xy.x - P.x) * f.x + (xy.y - P.y) * f.y + z * f.z;
}

// depth() of the eye ray's point at height z (the ray through P along -V).
inline double ray_depth_at_height(Vec3d V, Vec3d f, double z) {
    const double t = -z / V.z;  // X = P - t V, X.z = z
    return -t * (V.x * f.x + V.y * f.y + V.z * f.z);
}

}  // namespace pxh
