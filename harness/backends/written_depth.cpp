#include "harness/backends/written_depth.h"

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

double hit_height_at(const MethodSpec& m, const ViewInput& view, size_t k, Vec2d uv) {
    const View& rays = view.rays;
    const HitHeight rule = m.method->hit_height_of(m.params);
    if (rule == HitHeight::shader)
        throw std::logic_error("method '" + m.method->name + "': a plug-in has no C++ twin");
    if (rule == HitHeight::ray) {
        const Vec3d V = rays.dir(k);
        const Vec2d d = m.method->hit_direction
                            ? m.method->hit_direction(m.params, V, view.scene.scale)
                            : eye_ray_direction(V);
        const double z = line_height_at(rays.P[k], d, uv);
        if (std::isfinite(z)) return z;
    }
    return surface_at(m, view, k, uv);
}

std::vector<double> written_depths(const MethodSpec& m, const ViewInput& view,
                                   const std::vector<Vec2d>& uv) {
    const View& rays = view.rays;
    const Vec3d f = rays.depth_axis();
    const bool engine = m.depth == DepthMode::engine && m.method->engine_depth;
    std::vector<double> out(uv.size(), 0.0);
    for (size_t k = 0; k < uv.size(); ++k) {
        if (!std::isfinite(uv[k].x) || !std::isfinite(uv[k].y)) {
            out[k] = NAN;
            continue;
        }
        if (m.depth == DepthMode::base || (m.depth == DepthMode::engine && !engine)) continue;
        const double z = hit_height_at(m, view, k, uv[k]);
        if (!engine) {
            out[k] = depth_offset(rays.P[k], f, uv[k], z);
            continue;
        }
        const EngineDepthInput e{
            rays.P[k],        rays.dir(k),    f, uv[k], z, surface_at(m, view, k, uv[k]),
            view.scene.scale, view.scene.bias};
        out[k] = m.method->engine_depth(m.params, e);
    }
    return out;
}

}  // namespace pxh
