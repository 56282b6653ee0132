#include "harness/truth/curved_tracer.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace pxh {

namespace {

// An upper bound of |grad h| (per tile) of the bilinear surface: on each cell it is bounded by
// the larger of its two edge differences in each axis, times the texel count.
double gradient_bound(const HeightField& hf) {
    double gx = 0, gy = 0;
    const int w = hf.width, h = hf.height;
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) {
            const double a = hf.at(i, j);
            gx = std::max(gx, std::abs(double(hf.at((i + 1) % w, j)) - a));
            gy = std::max(gy, std::abs(double(hf.at(i, (j + 1) % h)) - a));
        }
    return std::hypot(gx * w, gy * h);
}

}  // namespace

CurvedTracer::CurvedTracer(const HeightField& hf, double scale, double bias,
                           const BaseSurface& base, double step_texels)
    : hf_(hf),
      s_(scale),
      b_(bias),
      base_(base),
      step_(step_texels),
      slope_(scale * gradient_bound(hf)) {}

double CurvedTracer::g(Vec3d p) const {
    const BaseCoord c = base_.coords(p);
    HeightSampler<double> hs(hf_, s_, b_);
    return c.height - hs.z(c.uv);
}

CurvedTracer::One CurvedTracer::trace_one(const WorldRay& r) const {
    One out;
    const double top = s_ * (1 - b_), bottom = -s_ * b_;
    auto at = [&](double t) { return v3_add(r.o, v3_scale(r.d, t)); };
    // enter the shell under the top (or start in it)
    double t0 = 0;
    if (base_.coords(r.o).height > top) {
        t0 = base_.hit(r.o, r.d, top, 0, false);
        if (!std::isfinite(t0)) return out;
    }
    // where it ends for sure: leaving the shell through the top again, or meeting the bottom
    const double t_leave = base_.hit(r.o, r.d, top, t0, true);
    const double t_floor = base_.hit(r.o, r.d, bottom, t0, false);
    double t_end = std::isfinite(t_floor) ? t_floor : t_leave;
    if (std::isfinite(t_floor) && std::isfinite(t_leave)) t_end = std::min(t_floor, t_leave);
    if (!std::isfinite(t_end)) return out;
    const bool floor_ends = std::isfinite(t_floor) && t_end == t_floor;
    const double texel = 1.0 / double(std::max(hf_.width, hf_.height));
    double t = t0;
    double g1 = g(at(t));
    for (;;) {
        const Vec3d p = at(t);
        // |g'| <= 1 + s |grad h| |d(u, v)/dt| (the height above the base changes at most as
        // fast as the point moves): no crossing within g / that bound. The speed of (u, v) is
        // taken at twice its value here (steps are short against the radius).
        const double speed = base_.uv_speed(p);
        const double lip = 1 + slope_ * 2 * speed;
        const double dt_max = step_ * texel / speed;
        const double dt = std::clamp(g1 / lip, dt_max * 1e-9, dt_max);
        const double t2 = std::min(t + dt, t_end);
        ++out.steps;
        const bool last = t2 >= t_end;
        const double g2 = g(at(t2));
        g1 = g2;
        if (g2 <= 0 || (last && floor_ends)) {
            // bisect [t, t2]: g(t) > 0 (or t is where the walk started), g(t2) <= 0
            double lo = t, hi = t2;
            for (int i = 0; i < 200 && hi - lo > 0; ++i) {
                const double mid = lo + 0.5 * (hi - lo);
                if (mid <= lo || mid >= hi) break;
                (g(at(mid)) <= 0 ? hi : lo) = mid;
            }
            out.hit = true;
            out.t = hi;
            out.residual = std::abs(g(at(hi)));
            return out;
        }
        if (last) return out;
        t = t2;
    }
}

CurvedHits CurvedTracer::trace(const std::vector<WorldRay>& rays) const {
    const size_t n = rays.size();
    std::vector<One> one(n);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 64), [&](const auto& rg) {
        for (size_t k = rg.begin(); k != rg.end(); ++k) one[k] = trace_one(rays[k]);
    });
    CurvedHits h;
    h.uv.assign(n, {NAN, NAN});
    h.z.assign(n, NAN);
    h.point.assign(n, {NAN, NAN, NAN});
    h.hit.assign(n, 0);
    double steps = 0;
    HeightSampler<double> hs(hf_, s_, b_);
    for (size_t k = 0; k < n; ++k) {
        steps += one[k].steps;
        if (!one[k].hit) continue;
        const Vec3d p = v3_add(rays[k].o, v3_scale(rays[k].d, one[k].t));
        h.point[k] = p;
        h.uv[k] = base_.coords(p).uv;
        h.z[k] = hs.z(h.uv[k]);
        h.hit[k] = 1;
        h.residual_max = std::max(h.residual_max, one[k].residual);
    }
    h.steps_mean = n ? steps / double(n) : 0;
    return h;
}

}  // namespace pxh
