// The true hard shadow query: does the ray from a surface point toward the light dip below
// the surface before leaving the slab?
#include <algorithm>
#include <cmath>
#include <limits>

#include "harness/truth/exact_tracer.h"
#include "harness/truth/travel_limit.h"

namespace pxh {

bool ExactTracer::occluded(Vec2d uv, double z0, Vec3d L) const {
    if (!(L.z > 0)) return true;                  // light at or below the horizon
    throw_if_problem(ray_travel_problem(s_, L));  // the walk below is as long as the travel
    const int W = hf_.width, H = hf_.height;
    const double zt = z_top();
    if (z0 >= zt) return false;
    const double tau_max = (zt - z0) / L.z;  // the ray leaves the slab here
    const double X0 = uv.x * W - 0.5, Y0 = uv.y * H - 0.5;
    const double dX = L.x * W, dY = L.y * H;
    int64_t ci = int64_t(std::floor(X0)), cj = int64_t(std::floor(Y0));
    const int step_i = dX > 0 ? 1 : -1, step_j = dY > 0 ? 1 : -1;
    const double inf = std::numeric_limits<double>::infinity();
    const double tdx = dX != 0 ? 1.0 / std::abs(dX) : inf, tdy = dY != 0 ? 1.0 / std::abs(dY) : inf;
    double tmx = dX > 0 ? (double(ci) + 1 - X0) / dX : (dX < 0 ? (X0 - double(ci)) / -dX : inf);
    double tmy = dY > 0 ? (double(cj) + 1 - Y0) / dY : (dY < 0 ? (Y0 - double(cj)) / -dY : inf);
    // The start lies on the surface (f = 0 there): only a clear dip below counts.
    const double eps = 1e-12 * std::max(s_, 1e-300);
    // The highest surface point: once the ray is at or above it, no later cell's test below can
    // pass (the ray only rises), so the answer is known without walking the rest of the travel.
    const double z_max = s_ * (double(level_max_.back()[0]) - b_);
    double tau_in = 0;
    for (;;) {
        const double tau_out = std::min({tmx, tmy, tau_max});
        const int64_t wi = wrap_index(ci, W), wj = wrap_index(cj, H);
        const double z_in = z0 + tau_in * L.z;  // the ray's lowest point in this cell
        if (z_in >= z_max) return false;
        if (z_in < s_ * (double(level_max_[0][size_t(wj) * W + wi]) - b_)) {
            const double h00 = hf_.at(int(wi), int(wj));
            const double h10 = hf_.wrapped(wi + 1, wj), h01 = hf_.wrapped(wi, wj + 1);
            const double h11 = hf_.wrapped(wi + 1, wj + 1);
            const double fx0 = X0 + tau_in * dX - double(ci), fy0 = Y0 + tau_in * dY - double(cj);
            const double A = h10 - h00, B = h01 - h00, C = h00 - h10 - h01 + h11;
            const double h0 = h00 + A * fx0 + B * fy0 + C * fx0 * fy0;
            const double h1 = A * dX + B * dY + C * (fx0 * dY + fy0 * dX);
            const double h2 = C * dX * dY;
            // f(t) = ray z - surface z, t in [0, len]; occluded if f < -eps somewhere.
            const double c0 = z_in - s_ * (h0 - b_), c1 = L.z - s_ * h1, c2 = -s_ * h2;
            const double len = tau_out - tau_in;
            auto f = [&](double t) { return c0 + (c1 + c2 * t) * t; };
            if (f(len) < -eps) return true;
            if (c2 > 0) {
                const double tv = -c1 / (2 * c2);
                if (tv > 0 && tv < len && f(tv) < -eps) return true;
            }
            // Leaving the start point downhill into the surface (f(0) = 0, f' < 0).
            if (tau_in == 0 && c0 <= eps && c1 < 0) return true;
        }
        if (tau_out >= tau_max) return false;
        tau_in = tau_out;
        if (tmx <= tmy) {
            ci += step_i;
            tmx += tdx;
        } else {
            cj += step_j;
            tmy += tdy;
        }
    }
}

}  // namespace pxh
