#include "harness/scene/curved_view.h"

#include <cmath>

#include "harness/scene/perspective_camera.h"

namespace pxh {

namespace {

// The base hit's (u, v) of sample k's ray moved (di, dj) pixels; NaN where it misses.
Vec2d base_uv(const Camera& cam, const BaseSurface& base, size_t k, double di, double dj,
              double top) {
    const WorldRay r = cam.world_ray(k, di, dj, top);
    const double t = base.hit(r.o, r.d, 0, 0, false);
    if (!std::isfinite(t)) return {NAN, NAN};
    return base.coords(v3_add(r.o, v3_scale(r.d, t))).uv;
}

// d(u, v) per pixel step along one image axis at sample k.
Vec2d uv_step(const Camera& cam, const BaseSurface& base, size_t k, bool along_i, Vec2d at,
              double top) {
    constexpr double h = 0.25;
    const Vec2d plus = base_uv(cam, base, k, along_i ? h : 0, along_i ? 0 : h, top);
    const Vec2d minus = base_uv(cam, base, k, along_i ? -h : 0, along_i ? 0 : -h, top);
    const bool p = std::isfinite(plus.x), m = std::isfinite(minus.x);
    if (p && m) return (plus - minus) * (1 / (2 * h));
    if (p) return (plus - at) * (1 / h);
    if (m) return (at - minus) * (1 / h);
    return {0, 0};
}

}  // namespace

CurvedView curved_view(const Camera& camera, const BaseSurface& base, double top) {
    const View flat = camera.view();
    const size_t n = flat.size();
    CurvedView cv;
    View& v = cv.view;
    v.P.assign(n, {0.5, 0.5});
    v.V.assign(n, {0, 0, 1});
    v.J.assign(n, Footprint{{0, 0}, {0, 0}});
    v.inside.assign(n, 0);
    v.parallel = false;
    v.grid = 0;
    v.forward = flat.depth_axis();
    cv.forward = v.forward;
    v.axes.assign(n, cv.forward);
    cv.rays.resize(n);
    cv.base_hit.assign(n, 0);
    cv.base_point.assign(n, {NAN, NAN, NAN});
    for (size_t k = 0; k < n; ++k) {
        const WorldRay r = camera.world_ray(k, 0, 0, top);
        cv.rays[k] = r;
        const double t = base.hit(r.o, r.d, 0, 0, false);
        if (!std::isfinite(t)) continue;
        const Vec2d uv = base.coords(v3_add(r.o, v3_scale(r.d, t))).uv;
        const BaseFrame f = base.frame(uv);
        const Vec3d V{-v3_dot(r.d, f.T), -v3_dot(r.d, f.Bt), -v3_dot(r.d, f.N)};
        cv.base_hit[k] = 1;
        cv.base_point[k] = v3_add(r.o, v3_scale(r.d, t));
        v.axes[k] = {v3_dot(cv.forward, f.T), v3_dot(cv.forward, f.Bt), v3_dot(cv.forward, f.N)};
        v.P[k] = uv;
        v.V[k] = V;
        v.inside[k] = V.z > outside_cos() ? 1 : 0;
        v.J[k] = {uv_step(camera, base, k, true, uv, top),
                  uv_step(camera, base, k, false, uv, top)};
    }
    return cv;
}

BaseView flat_view(const Camera& camera, const BaseSurface&, double) {
    BaseView bv;
    bv.view = camera.view();
    bv.forward = bv.view.depth_axis();
    return bv;
}

}  // namespace pxh
