#include "harness/backends/written_depth.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace pxh {

void add_written_depths(const MethodSpec& m, const ViewInput& view, MethodOutput& o,
                        bool as_float) {
    const std::vector<Vec2d>& uv = o.uv;
    std::vector<double>& out = o.depth;
    std::vector<double>& tol = o.depth_tol;
    const View& rays = view.rays;
    const bool engine = m.depth == DepthMode::engine && m.method->engine_depth;
    if (m.method->hit_height_of(m.params) == HitHeight::shader)
        throw std::logic_error("method '" + m.method->name + "': a plug-in has no C++ twin");
    if ((m.depth != DepthMode::base && o.hit_z.size() != uv.size()) ||
        (engine && o.engine_z.size() != uv.size()))
        throw std::logic_error("method '" + m.method->name + "': no z_m beside its uv");
    out.assign(uv.size(), 0.0);
    tol.clear();
    if (as_float) tol = float_depth_tol(rays);
    o.depth_span = depth_target_span(rays, view.scene.scale);
    for (size_t k = 0; k < uv.size(); ++k) {
        if (!std::isfinite(uv[k].x) || !std::isfinite(uv[k].y)) {
            out[k] = NAN;
            continue;
        }
        if (m.depth == DepthMode::base || (m.depth == DepthMode::engine && !engine)) continue;
        const Vec3d f = rays.depth_axis(k);
        const Vec2d P =
            as_float ? Vec2d{double(float(rays.P[k].x)), double(float(rays.P[k].y))} : rays.P[k];
        const double z = o.hit_z[k];
        if (!engine) {
            out[k] = depth_offset(P, f, uv[k], z);
            continue;
        }
        const EngineDepthInput e{
            P, rays.dir(k), f, uv[k], z, o.engine_z[k], view.scene.scale, view.scene.bias};
        out[k] = m.method->engine_depth(m.params, e);
    }
}

double depth_target_span(const View& rays, double scale) {
    double vz = 1;
    for (size_t k = 0; k < rays.V.size(); ++k)
        if (rays.parallel || rays.is_inside(k)) vz = std::min(vz, rays.V[k].z);
    return 4 * (1 + std::abs(scale) / std::max(vz, 1e-3));
}

std::vector<double> float_depth_tol(const View& rays) {
    std::vector<double> tol(rays.P.size());
    for (size_t k = 0; k < tol.size(); ++k) {
        const double x = double(float(rays.P[k].x)), y = double(float(rays.P[k].y));
        // float's epsilon is 2^-23: four steps are 2^-21 of the magnitude
        tol[k] = std::ldexp(std::max({std::abs(x), std::abs(y), 1.0}), -21);
    }
    return tol;
}

}  // namespace pxh
