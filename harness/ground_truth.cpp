#include "harness/ground_truth.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace pxh {

std::vector<Vec2d> sample_grid(int n) {
    std::vector<Vec2d> p(size_t(n) * n);
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) p[size_t(j) * n + i] = {(i + 0.5) / n, (j + 0.5) / n};
    return p;
}

Vec3d view_vector(double theta_deg, double phi_deg) {
    const double t = theta_deg * M_PI / 180.0, p = phi_deg * M_PI / 180.0;
    return {std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t)};
}

ExactTracer::ExactTracer(const HeightField& hf, double scale, double bias)
    : hf_(hf), s_(scale), b_(bias), cell_max_(hf.texels.size()) {
    for (int j = 0; j < hf.height; ++j)
        for (int i = 0; i < hf.width; ++i)
            cell_max_[size_t(j) * hf.width + i] =
                std::max({hf.wrapped(i, j), hf.wrapped(i + 1, j), hf.wrapped(i, j + 1),
                          hf.wrapped(i + 1, j + 1)});
}

namespace {

// Smallest t in [0, len] with c0 + c1 t + c2 t^2 <= 0, given c0 > 0; -1 if none.
double first_root(double c0, double c1, double c2, double len) {
    double best = -1;
    auto consider = [&](double t) {
        if (t >= 0 && t <= len && (best < 0 || t < best)) best = t;
    };
    const double scale = std::abs(c0) + std::abs(c1) * len + std::abs(c2) * len * len;
    if (std::abs(c2) * len * len <= 1e-14 * scale) {
        if (c1 < 0) consider(-c0 / c1);
    } else {
        const double disc = c1 * c1 - 4 * c2 * c0;
        if (disc >= 0) {
            const double q = -0.5 * (c1 + std::copysign(std::sqrt(disc), c1));
            if (q != 0) {
                consider(q / c2);
                consider(c0 / q);
            }
        }
    }
    if (best < 0) {
        // Rounding can hide a crossing that the end value proves: f(len) <= 0 < f(0).
        const double f_end = c0 + (c1 + c2 * len) * len;
        if (f_end <= 0) {
            double lo = 0, hi = len;
            for (int it = 0; it < 80; ++it) {
                const double mid = 0.5 * (lo + hi);
                (c0 + (c1 + c2 * mid) * mid > 0 ? lo : hi) = mid;
            }
            best = hi;
        }
    }
    return best;
}

}  // namespace

TruthHit ExactTracer::trace(Vec2d P, Vec3d V) const {
    const int W = hf_.width, H = hf_.height;
    const double zt = z_top();
    // Entry point E at z_top; the ray is E - tau V, tau in [0, tau_max] (tau_max: z_bot).
    const double ex = P.x + V.x / V.z * zt, ey = P.y + V.y / V.z * zt;
    const double tau_max = s_ / V.z;
    // Grid coordinates: X = u W - 0.5, cell i spans X in [i, i + 1].
    const double X0 = ex * W - 0.5, Y0 = ey * H - 0.5;
    const double dX = -V.x * W, dY = -V.y * H;
    int64_t ci = int64_t(std::floor(X0)), cj = int64_t(std::floor(Y0));
    const int step_i = dX > 0 ? 1 : -1, step_j = dY > 0 ? 1 : -1;
    const double inf = std::numeric_limits<double>::infinity();
    const double tdx = dX != 0 ? 1.0 / std::abs(dX) : inf, tdy = dY != 0 ? 1.0 / std::abs(dY) : inf;
    double tmx = dX > 0 ? (double(ci) + 1 - X0) / dX : (dX < 0 ? (X0 - double(ci)) / -dX : inf);
    double tmy = dY > 0 ? (double(cj) + 1 - Y0) / dY : (dY < 0 ? (Y0 - double(cj)) / -dY : inf);

    TruthHit hit;
    double tau_in = 0;
    auto make_hit = [&](double tau) {
        hit.uv = {ex - tau * V.x, ey - tau * V.y};
        hit.z = zt - tau * V.z;
        return hit;
    };
    for (;;) {
        ++hit.cells;
        const double tau_out = std::min({tmx, tmy, tau_max});
        const int64_t wi = wrap_index(ci, W), wj = wrap_index(cj, H);
        const double z_out = zt - tau_out * V.z;  // the ray's lowest point in this cell
        if (z_out <= s_ * (double(cell_max_[size_t(wj) * W + wi]) - b_)) {
            const double h00 = hf_.at(int(wi), int(wj));
            const double h10 = hf_.wrapped(wi + 1, wj), h01 = hf_.wrapped(wi, wj + 1);
            const double h11 = hf_.wrapped(wi + 1, wj + 1);
            // Local parameter t = tau - tau_in; fractional cell position is linear in t.
            const double fx0 = X0 + tau_in * dX - double(ci), fy0 = Y0 + tau_in * dY - double(cj);
            const double A = h10 - h00, B = h01 - h00, C = h00 - h10 - h01 + h11;
            const double h0 = h00 + A * fx0 + B * fy0 + C * fx0 * fy0;
            const double h1 = A * dX + B * dY + C * (fx0 * dY + fy0 * dX);
            const double h2 = C * dX * dY;
            const double c0 = (zt - tau_in * V.z) - s_ * (h0 - b_);
            if (c0 <= 0) return make_hit(tau_in);
            const double t = first_root(c0, -V.z - s_ * h1, -s_ * h2, tau_out - tau_in);
            if (t >= 0) return make_hit(tau_in + t);
        }
        if (tau_out >= tau_max) return make_hit(tau_max);  // at z_bot: on or below any surface
        tau_in = tau_out;
        if (tmx <= tmy) { ci += step_i; tmx += tdx; } else { cj += step_j; tmy += tdy; }
    }
}

bool ExactTracer::occluded(Vec2d uv, double z0, Vec3d L) const {
    if (!(L.z > 0)) return true;  // light at or below the horizon
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
    double tau_in = 0;
    for (;;) {
        const double tau_out = std::min({tmx, tmy, tau_max});
        const int64_t wi = wrap_index(ci, W), wj = wrap_index(cj, H);
        const double z_in = z0 + tau_in * L.z;  // the ray's lowest point in this cell
        if (z_in < s_ * (double(cell_max_[size_t(wj) * W + wi]) - b_)) {
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
        if (tmx <= tmy) { ci += step_i; tmx += tdx; } else { cj += step_j; tmy += tdy; }
    }
}

GroundTruth trace_ground_truth(const HeightField& hf, double scale, double bias, Vec3d V, int n,
                               const Vec3d* L) {
    const ExactTracer tracer(hf, scale, bias);
    const auto P = sample_grid(n);
    GroundTruth gt;
    gt.uv.resize(P.size());
    gt.z.resize(P.size());
    std::vector<int> cells(P.size());
    if (L) gt.lit.resize(P.size());
    tbb::parallel_for(tbb::blocked_range<size_t>(0, P.size(), 256), [&](const auto& r) {
        for (size_t k = r.begin(); k < r.end(); ++k) {
            const TruthHit h = tracer.trace(P[k], V);
            gt.uv[k] = h.uv;
            gt.z[k] = h.z;
            cells[k] = h.cells;
            if (L) gt.lit[k] = !tracer.occluded(h.uv, h.z, *L);
        }
    });
    double sum = 0;
    for (int c : cells) sum += c;
    gt.cells_mean = P.empty() ? 0 : sum / double(P.size());
    return gt;
}

}  // namespace pxh
