// The exact tracer's ray and cell solver (internal to harness/truth): the eye ray in grid
// coordinates and the closed-form first crossing of a ray with one cell's bilinear patch.
// Inline: the per-ray walk and the band tracer solve cells in their innermost loops.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "harness/truth/exact_tracer.h"
#include "harness/truth/travel_limit.h"

namespace pxh {

namespace cell_solver {

// Smallest t in [0, len] with c0 + c1 t + c2 t^2 <= 0, given c0 > 0; -1 if none.
inline double first_root(double c0, double c1, double c2, double len) {
    // Most cells the ray clears end above the surface with no dip in between: f(len) > 0 and
    // f has no minimum inside (concave, or its vertex outside [0, len]).
    if (c0 + (c1 + c2 * len) * len > 0 && (c2 <= 0 || c1 >= 0 || c1 + 2 * c2 * len <= 0)) return -1;
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

// One axis of the DDA in global grid coordinates: the time the ray enters column (or row) c
// crossing its near line, as trace_naive computes the exit of the previous one.
struct DdaAxis {
    double origin, inv_d;  // X0, 1 / dX
    int step;              // +1 or -1
    bool moves;            // d != 0
    double at_line(int64_t k) const { return (double(k) - origin) * inv_d; }
    double entry(int64_t c) const { return at_line(step > 0 ? c : c + 1); }
    double exit(int64_t c) const { return at_line(step > 0 ? c + 1 : c); }
    // The last cell (c or after, along step) entered at a time before t (strictly) or, with
    // `or_equal`, at t too; the start cell counts as entered at -infinity (its entry time is
    // <= 0 < t). `guess` is any nearby cell index.
    int64_t last_entered(int64_t c, int64_t guess, double t, bool or_equal) const {
        auto entered = [&](int64_t k) { return or_equal ? entry(k) <= t : entry(k) < t; };
        // The guess, moved back to c or later (c itself is always entered).
        if (step > 0 ? guess < c : guess > c) guess = c;
        while (guess != c && !entered(guess)) guess -= step;
        while (entered(guess + step)) guess += step;
        return guess;
    }
};

inline int64_t floor_div(int64_t a, int64_t n) {
    int64_t q = a / n;
    return (a % n != 0 && ((a < 0) != (n < 0))) ? q - 1 : q;
}

// Throws std::runtime_error: a DDA from grid point (X0, Y0) walked `cells` cells, more than its
// ray crosses (its exit lines stopped moving). Out of line, off the walks' hot path.
[[noreturn, gnu::cold]] void walk_stalled(double X0, double Y0, int cells);

}  // namespace cell_solver

// The eye ray: E - tau V from the slab top (tau = 0) to the slab bottom (tau_max), in grid
// coordinates X = u W - 0.5 (cell i spans X in [i, i + 1]).
struct ExactTracer::Ray {
    double ex, ey, zt, vx, vy, vz, tau_max;
    double X0, Y0, dX, dY, inv_dX, inv_dY;
    int sx, sy;
    // Closed-form parameters where the ray crosses grid line k (x) or l (y).
    double tx(int64_t k) const { return (double(k) - X0) * inv_dX; }
    double ty(int64_t l) const { return (double(l) - Y0) * inv_dY; }
    double enter(int64_t ci, int64_t cj) const {
        double t = 0;
        if (dX != 0) t = std::max(t, tx(sx > 0 ? ci : ci + 1));
        if (dY != 0) t = std::max(t, ty(sy > 0 ? cj : cj + 1));
        return t;
    }
    // Exit parameters of the box [x0, x1) x [y0, y1) of cells.
    double exit_x(int64_t x0, int64_t x1) const {
        return dX != 0 ? tx(sx > 0 ? x1 : x0) : std::numeric_limits<double>::infinity();
    }
    double exit_y(int64_t y0, int64_t y1) const {
        return dY != 0 ? ty(sy > 0 ? y1 : y0) : std::numeric_limits<double>::infinity();
    }
};

inline ExactTracer::Ray ExactTracer::make_ray(Vec2d P, Vec3d V) const {
    // Within the travel limit every grid coordinate below (start, exits, the slab bottom) is a
    // few times W x kMaxRayTravelTiles at most: all conversions to integers are in range.
    throw_if_problem(ray_travel_problem(s_, V));
    // Within the reach limit the DDA's exit lines keep moving (kMaxSampleCells).
    throw_if_problem(sample_reach_problem(P, hf_.width, hf_.height));
    return make_ray_unchecked(P, V);
}

inline ExactTracer::Ray ExactTracer::make_ray_unchecked(Vec2d P, Vec3d V) const {
    Ray r;
    r.zt = z_top();
    r.vx = V.x;
    r.vy = V.y;
    r.vz = V.z;
    r.ex = P.x + V.x / V.z * r.zt;
    r.ey = P.y + V.y / V.z * r.zt;
    r.tau_max = s_ / V.z;
    r.X0 = r.ex * hf_.width - 0.5;
    r.Y0 = r.ey * hf_.height - 0.5;
    r.dX = -V.x * hf_.width;
    r.dY = -V.y * hf_.height;
    r.inv_dX = r.dX != 0 ? 1 / r.dX : 0;
    r.inv_dY = r.dY != 0 ? 1 / r.dY : 0;
    r.sx = r.dX > 0 ? 1 : -1;
    r.sy = r.dY > 0 ? 1 : -1;
    return r;
}

inline ExactTracer::Ray ExactTracer::make_ray(Vec2d P, const Ray& like) const {
    // Bit for bit what make_ray(P, V) computes, without repeating the direction's divisions.
    Ray r = like;
    r.ex = P.x + r.vx / r.vz * r.zt;
    r.ey = P.y + r.vy / r.vz * r.zt;
    r.X0 = r.ex * hf_.width - 0.5;
    r.Y0 = r.ey * hf_.height - 0.5;
    return r;
}

// The hit at parameter tau of the ray from (ex, ey, zt) along -V (every per-ray path's).
inline TruthHit hit_at_tau(double ex, double ey, double zt, Vec3d V, double tau, int cells) {
    TruthHit h;
    h.uv = {ex - tau * V.x, ey - tau * V.y};
    h.z = zt - tau * V.z;
    h.cells = cells;
    return h;
}

inline TruthHit ExactTracer::hit_at(const Ray& r, double tau, int cells) const {
    return hit_at_tau(r.ex, r.ey, r.zt, {r.vx, r.vy, r.vz}, tau, cells);
}

[[gnu::always_inline]] inline double ExactTracer::solve_cell(const Ray& r, int64_t ci, int64_t cj,
                                                             int64_t wi, int64_t wj,
                                                             double tau_out) const {
    const float* c =
        texel_row(wj) + wi;  // texels (wi, wj), (wi + 1, wj); a row later the pair above
    const size_t up = texel_stride();
    return solve_corners(r, ci, cj, c[0], c[1], c[up], c[up + 1], tau_out);
}

[[gnu::always_inline]] inline double ExactTracer::solve_cell_pairs(const Ray& r, int64_t ci,
                                                                   int64_t cj, int64_t wi,
                                                                   int64_t wj,
                                                                   double tau_out) const {
    const int64_t W = hf_.width;
    const int64_t wi1 = wi + 1 == W ? 0 : wi + 1;
    const float* row = column_pairs_.data() + 2 * wj * W;  // (h(i, j), h(i, j + 1)) pairs
    return solve_corners(r, ci, cj, row[2 * wi], row[2 * wi1], row[2 * wi + 1], row[2 * wi1 + 1],
                         tau_out);
}

[[gnu::always_inline]] inline bool ExactTracer::cell_below(const Ray& r, float f00, float f10,
                                                           float f01, float f11,
                                                           double tau_out) const {
    // The cell's maximum (its corners' maximum, the value the hierarchy is built from).
    const float top = std::max(std::max(f00, f10), std::max(f01, f11));
    return r.zt - tau_out * r.vz > s_ * (double(top) - b_);
}

[[gnu::always_inline]] inline double ExactTracer::solve_corners(const Ray& r, int64_t ci,
                                                                int64_t cj, float f00, float f10,
                                                                float f01, float f11,
                                                                double tau_out) const {
    if (cell_below(r, f00, f10, f01, f11, tau_out)) return -1;
    return solve_patch_inline(r, ci, cj, f00, f10, f01, f11, tau_out);
}

// Out of line for the per-ray walks: most cells are rejected by cell_below, and their loops
// keep their state in registers when the closed form is not inlined into them. Inline in the
// band tracer (solve_corners; measured: out of line 2-4% slower there, pxh bench).
[[gnu::noinline]] inline double ExactTracer::solve_patch(const Ray& r, int64_t ci, int64_t cj,
                                                         float f00, float f10, float f01, float f11,
                                                         double tau_out) const {
    return solve_patch_inline(r, ci, cj, f00, f10, f01, f11, tau_out);
}

[[gnu::always_inline]] inline double ExactTracer::solve_patch_inline(const Ray& r, int64_t ci,
                                                                     int64_t cj, float f00,
                                                                     float f10, float f01,
                                                                     float f11,
                                                                     double tau_out) const {
    const double tau_in = r.enter(ci, cj);
    const double h00 = f00, h10 = f10, h01 = f01, h11 = f11;
    // Local parameter t = tau - tau_in; fractional cell position is linear in t.
    const double fx0 = r.X0 + tau_in * r.dX - double(ci), fy0 = r.Y0 + tau_in * r.dY - double(cj);
    const double A = h10 - h00, B = h01 - h00, C = h00 - h10 - h01 + h11;
    const double h0 = h00 + A * fx0 + B * fy0 + C * fx0 * fy0;
    const double h1 = A * r.dX + B * r.dY + C * (fx0 * r.dY + fy0 * r.dX);
    const double h2 = C * r.dX * r.dY;
    const double c0 = (r.zt - tau_in * r.vz) - s_ * (h0 - b_);
    if (c0 <= 0) return tau_in;
    const double t = cell_solver::first_root(c0, -r.vz - s_ * h1, -s_ * h2, tau_out - tau_in);
    return t >= 0 ? tau_in + t : -1;
}

inline double ExactTracer::solve_cell(const Ray& r, int64_t ci, int64_t cj, double tau_out) const {
    return solve_cell(r, ci, cj, wrap_index(ci, hf_.width), wrap_index(cj, hf_.height), tau_out);
}

}  // namespace pxh
