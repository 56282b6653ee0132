#include "harness/truth/curved_tracer.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "harness/truth/curved_pyramid.h"

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

std::string number(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.3g", v);
    return buf;
}

}  // namespace

std::string base_radius_problem(const std::string& base, double radius, int width, int height) {
    const double n = double(std::max(width, height));
    const double bound = kMaxBaseRadiusCells / n;
    if (!(radius > bound)) return "";  // NaN: the plane (a curved base refuses it in make_base)
    return "radius = " + number(radius) + " on base '" + base + "' of the " +
           std::to_string(width) + " x " + std::to_string(height) +
           " field is over the precision bound R max(W, H) <= 2^30 cells (kMaxBaseRadiusCells): "
           "radius <= " +
           number(bound) +
           " tiles here. The base is computed about its centre R tiles away, where doubles "
           "resolve only about " +
           number(std::ldexp(radius, -52) * n) +
           " texels (eps R), which grazing views magnify up to 57 times (the numbers would be "
           "wrong with status ok); over a tile the base sags only " +
           number(n / (2 * radius)) +
           " texels from its tangent plane: use base = \"plane\" or a radius within the bound";
}

CurvedWalkEstimate curved_walk_estimate(const BaseSurface& base, double scale, double bias,
                                        int width, int height, const Camera& camera, size_t rays,
                                        double step_texels, double walks) {
    CurvedWalkEstimate e;
    e.rays = rays;
    e.walks = walks;
    if (rays == 0) return e;
    const double top = scale * (1 - bias), bottom = -scale * bias;
    const double step = step_texels / double(std::max(width, height));  // tiles
    const size_t stride = std::max<size_t>(1, rays / 4096);
    double sum = 0;
    size_t sampled = 0;
    for (size_t k = 0; k < rays; k += stride, ++sampled) {
        const WorldRay r = camera.world_ray(k, 0, 0, top);
        double t0 = 0;
        if (base.coords(r.o).height > top) {
            t0 = base.hit(r.o, r.d, top, 0, false);
            if (!std::isfinite(t0)) continue;
        }
        const double t_leave = base.hit(r.o, r.d, top, t0, true);
        const double t_floor = base.hit(r.o, r.d, bottom, t0, false);
        double t_end = std::isfinite(t_floor) ? t_floor : t_leave;
        if (std::isfinite(t_floor) && std::isfinite(t_leave)) t_end = std::min(t_floor, t_leave);
        if (!std::isfinite(t_end)) continue;
        e.chord_max = std::max(e.chord_max, t_end - t0);
        sum += std::ceil((t_end - t0) / step);  // the walk's speed of (u, v) is at least 1
    }
    e.walk_steps = sum * double(rays) / double(sampled);
    e.steps = walks * e.walk_steps;  // e.g. the walk and its check at half the step: 3
    return e;
}

std::vector<size_t> truth_check_rays(size_t n, const std::string& mode) {
    std::vector<size_t> ks;
    if (mode == "none" || n == 0) return ks;
    if (mode == "all") {
        ks.resize(n);
        for (size_t k = 0; k < n; ++k) ks[k] = k;
        return ks;
    }
    const auto side = size_t(std::llround(std::sqrt(double(n))));
    if (side * side == n) {
        const size_t o = std::min<size_t>(2, side - 1);  // views under 3 x 3: one ray
        for (size_t j = o; j < side; j += 4)
            for (size_t i = o; i < side; i += 4) ks.push_back(j * side + i);
    } else {
        for (size_t k = std::min<size_t>(8, n - 1); k < n; k += 16) ks.push_back(k);
    }
    return ks;
}

double curved_walks(const std::string& mode, size_t rays) {
    if (rays == 0) return 1;
    const std::string m = mode.empty() ? std::string(kCurvedTruthCheck) : mode;
    return 1 + 2 * double(truth_check_rays(rays, m).size()) / double(rays);
}

std::string curved_walk_problem(const CurvedWalkEstimate& e, const std::string& walks_said,
                                const std::string& knobs) {
    if (e.steps <= kMaxCurvedWalkSteps) return "";
    return "the curved truth's walk would take about " + number(e.steps) + " steps for the " +
           std::to_string(e.rays) + " rays of this view (rays cross up to " + number(e.chord_max) +
           " tiles of the relief's shell in steps of a quarter texel, " + walks_said +
           "), over the limit of 2^28 = " + number(kMaxCurvedWalkSteps) +
           " steps a view (kMaxCurvedWalkSteps, 10 to 25 s of one core): " + knobs;
}

struct CurvedTracer::Budget {
    double max_steps;
    std::atomic<long long> used{0};
    std::atomic<bool> over{false};
    // Adds n steps; false once the budget is spent (every walk then stops).
    bool spend(long long n) {
        if (over.load(std::memory_order_relaxed)) return false;
        if (double(used.fetch_add(n, std::memory_order_relaxed) + n) > max_steps) over = true;
        return !over.load(std::memory_order_relaxed);
    }
};

CurvedTracer::~CurvedTracer() = default;

std::string CurvedTracer::method_name() const { return pyramid_ ? "pyramid" : "walk"; }

CurvedTracer::CurvedTracer(const HeightField& hf, double scale, double bias,
                           const BaseSurface& base, double step_texels, CurvedMethod method)
    : hf_(hf),
      s_(scale),
      b_(bias),
      base_(base),
      step_(step_texels),
      slope_(scale * gradient_bound(hf)) {
    // the last line of defence: experiments and pxh bench refuse it first
    if (const std::string why =
            base_radius_problem(base.name(), base.radius(), hf.width, hf.height);
        !why.empty())
        throw std::invalid_argument(why);
    if (method == CurvedMethod::pyramid && CurvedPyramid::supports(base))
        pyramid_ = std::make_unique<CurvedPyramid>(hf, scale, bias, base);
}

double CurvedTracer::g(Vec3d p) const {
    const BaseCoord c = base_.coords(p);
    HeightSampler<double> hs(hf_, s_, b_);
    return c.height - hs.z(c.uv);
}

CurvedTracer::One CurvedTracer::trace_one(const WorldRay& r, Budget& budget) const {
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
        // the budget is checked every 4096 steps (and at the end of the ray)
        if ((++out.steps & 4095) == 0 && !budget.spend(4096)) return out;
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

CurvedHits CurvedTracer::trace(const std::vector<WorldRay>& rays, double max_steps) const {
    const size_t n = rays.size();
    std::vector<One> one(n);
    Budget budget{max_steps};
    // chunks of up to 64 rays (the pyramid's: up to kPyramidChunk, which its vector lanes fill),
    // finer for small views (a handful of long rays still spread over the threads); each ray's
    // walk is its own, so the hits do not depend on the chunks
    constexpr size_t kPyramidChunk = 1024;
    const size_t grain = pyramid_ ? std::clamp<size_t>(n / 32, 1, kPyramidChunk)
                                  : std::clamp<size_t>(n / 256, 1, 64);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, grain), [&](const auto& rg) {
        if (pyramid_) {
            // a ray's steps are few: the chunk's rays, in vector lanes where the CPU has them,
            // may take what the budget had left when they began (each ray what was left of that
            // when it began, plus 4096), and are charged after them
            if (budget.over.load(std::memory_order_relaxed)) return;
            const double left = budget.max_steps - double(budget.used.load());
            const size_t m = rg.end() - rg.begin();
            std::vector<CurvedPyramid::One> o(m);
            pyramid_->trace_many(&rays[rg.begin()], m, o.data(),
                                 (long long)std::clamp(left, 0.0, 4e18),
                                 CurvedPyramid::default_path(), &budget.over);
            for (size_t i = 0; i < m; ++i) {
                one[rg.begin() + i] = {
                    o[i].hit, o[i].t, o[i].residual, o[i].steps, {o[i].u, o[i].v}};
                budget.spend(o[i].steps);
            }
            return;
        }
        for (size_t k = rg.begin(); k != rg.end(); ++k) {
            if (budget.over.load(std::memory_order_relaxed)) return;
            one[k] = trace_one(rays[k], budget);
            budget.spend(one[k].steps & 4095);
        }
    });
    if (budget.over)
        throw CurvedWalkTooLong("the curved truth's walk stopped after " +
                                    number(double(budget.used.load())) + " steps for the " +
                                    std::to_string(n) + " rays of this view, over its budget of " +
                                    number(max_steps) + " steps",
                                double(budget.used.load()), max_steps);
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
        // the pyramid's own coordinates of its hit (base_.coords(p).uv, the same expressions
        // on the same point), else the base's
        h.uv[k] = std::isnan(one[k].uv.x) ? base_.coords(p).uv : one[k].uv;
        h.z[k] = hs.z(h.uv[k]);
        h.hit[k] = 1;
        h.residual_max = std::max(h.residual_max, one[k].residual);
    }
    h.steps = steps;
    h.steps_mean = n ? steps / double(n) : 0;
    return h;
}

}  // namespace pxh
