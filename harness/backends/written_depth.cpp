#include "harness/backends/written_depth.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace pxh {

namespace {

double surface_at(const MethodSpec& m, const ViewInput& view, size_t k, Vec2d uv) {
    const Scene<double>& sc = view.scene;
    const bool levels = m.lod == LodMode::level && view.levels && view.lambda;
    HeightSampler<double> hs =
        levels ? HeightSampler<double>(view.hf, sc.scale, sc.bias, view.levels, (*view.lambda)[k])
               : HeightSampler<double>(view.hf, sc.scale, sc.bias);
    return hs.z(uv);
}

}  // namespace

double hit_height_at(const MethodSpec& m, const ViewInput& view, size_t k, Vec2d P, Vec2d uv) {
    const View& rays = view.rays;
    const HitHeight rule = m.method->hit_height_of(m.params);
    if (rule == HitHeight::shader)
        throw std::logic_error("method '" + m.method->name + "': a plug-in has no C++ twin");
    if (rule == HitHeight::ray) {
        const Vec3d V = rays.dir(k);
        const Vec2d d = m.method->hit_direction
                            ? m.method->hit_direction(m.params, V, view.scene.scale)
                            : eye_ray_direction(V);
        const double z = line_height_at(P, d, uv);
        if (std::isfinite(z)) return z;
    }
    return surface_at(m, view, k, uv);
}

void add_written_depths(const MethodSpec& m, const ViewInput& view, MethodOutput& o,
                        bool as_float) {
    const std::vector<Vec2d>& uv = o.uv;
    std::vector<double>& out = o.depth;
    std::vector<double>& tol = o.depth_tol;
    const View& rays = view.rays;
    const bool engine = m.depth == DepthMode::engine && m.method->engine_depth;
    out.assign(uv.size(), 0.0);
    tol.clear();
    if (as_float) tol.assign(uv.size(), 0.0);
    for (size_t k = 0; k < uv.size(); ++k) {
        if (!std::isfinite(uv[k].x) || !std::isfinite(uv[k].y)) {
            out[k] = NAN;
            continue;
        }
        if (m.depth == DepthMode::base || (m.depth == DepthMode::engine && !engine)) continue;
        const Vec3d f = rays.depth_axis(k);
        const Vec2d P =
            as_float ? Vec2d{double(float(rays.P[k].x)), double(float(rays.P[k].y))} : rays.P[k];
        // four float steps of the sample's coordinates (2^-21 |P|: float's epsilon is 2^-23)
        if (as_float) tol[k] = std::ldexp(std::max({std::abs(P.x), std::abs(P.y), 1.0}), -21);
        const double z = hit_height_at(m, view, k, P, uv[k]);
        if (!engine) {
            out[k] = depth_offset(P, f, uv[k], z);
            continue;
        }
        const EngineDepthInput e{P,
                                 rays.dir(k),
                                 f,
                                 uv[k],
                                 z,
                                 surface_at(m, view, k, uv[k]),
                                 view.scene.scale,
                                 view.scene.bias};
        out[k] = m.method->engine_depth(m.params, e);
    }
}

}  // namespace pxh
