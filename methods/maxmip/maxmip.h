// The maxmip method's traversal (methods/maxmip/maxmip.cpp; its GLSL twin maxmip.frag.glsl does
// the same operations in the same order): the eye ray through the maximum mipmap r_maxmip,
// exact ray / bilinear-patch intersection at the leaf cell. Generic over float and double.
//
// Grid coordinates as in docs/conventions.md section 4: X = u W - 0.5, Y = v H - 0.5; cell
// (ci, cj) is the unit square [ci, ci + 1] x [cj, cj + 1] of the unwrapped grid, whose corners are
// texels (ci, cj) ... (ci + 1, cj + 1) taken modulo the size. The ray E - tau V runs from the
// slab top (tau = 0) to the slab bottom (tau_max = s / V.z).
#pragma once
#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>

#include "harness/core/vec.h"
#include "harness/scene/scene.h"
#include "methods/depth.h"
#include "methods/resource.h"

namespace pxh::maxmip {

// floor(a / n) for n > 0, without dividing a negative number (GLSL leaves that undefined).
inline int floor_div(int a, int n) { return a >= 0 ? a / n : -((-a - 1) / n) - 1; }
// Level L of a side of n cells has max(1, n >> L) nodes; node k covers cells [k 2^L, (k + 1) 2^L),
// the last one up to n (an odd size's extra row or column joins the last node: reduce_pyramid).
inline int nodes_at(int n, int L) { return std::max(1, n >> L); }
inline int node_of(int l, int L, int n) { return std::min(l >> L, nodes_at(n, L) - 1); }
inline int node_end(int k, int L, int n) { return k == nodes_at(n, L) - 1 ? n : (k + 1) << L; }
// The coarsest level (1 x 1): msb(max(W, H)).
inline int top_level(int W, int H) { return int(std::bit_width(unsigned(std::max(W, H)))) - 1; }

template <typename T>
struct Ray {
    T ex, ey, zt, vx, vy, vz, tau_max;
    T X0, Y0, dX, dY, inv_dX, inv_dY;
    int sx, sy;
    Vec2<T> at(T tau) const { return {ex - tau * vx, ey - tau * vy}; }
    // The parameter where the ray crosses grid line k (x) or l (y).
    T tx(int k) const { return (T(k) - X0) * inv_dX; }
    T ty(int l) const { return (T(l) - Y0) * inv_dY; }
    // Where the ray enters cell (ci, cj) (0 if it starts inside).
    T enter(int ci, int cj) const {
        T t = T(0);
        if (dX != T(0)) t = std::max(t, tx(sx > 0 ? ci : ci + 1));
        if (dY != T(0)) t = std::max(t, ty(sy > 0 ? cj : cj + 1));
        return t;
    }
};

template <typename T>
Ray<T> make_ray(const Scene<T>& sc, Vec2<T> P) {
    Ray<T> r;
    r.zt = sc.z_top();
    r.vx = sc.V.x;
    r.vy = sc.V.y;
    r.vz = sc.V.z;
    r.ex = P.x + sc.V.x / sc.V.z * r.zt;
    r.ey = P.y + sc.V.y / sc.V.z * r.zt;
    r.tau_max = sc.scale / sc.V.z;
    r.X0 = r.ex * T(sc.width) - T(0.5);
    r.Y0 = r.ey * T(sc.height) - T(0.5);
    r.dX = -sc.V.x * T(sc.width);
    r.dY = -sc.V.y * T(sc.height);
    r.inv_dX = r.dX != T(0) ? T(1) / r.dX : T(0);
    r.inv_dY = r.dY != T(0) ? T(1) / r.dY : T(0);
    r.sx = r.dX > T(0) ? 1 : -1;
    r.sy = r.dY > T(0) ? 1 : -1;
    return r;
}

// Smallest t in [0, len] with c0 + c1 t + c2 t^2 <= 0, given c0 > 0; -1 if none (the exact
// tracer's cell_solver::first_root, in T).
template <typename T>
T first_root(T c0, T c1, T c2, T len) {
    if (c0 + (c1 + c2 * len) * len > T(0) &&
        (c2 <= T(0) || c1 >= T(0) || c1 + T(2) * c2 * len <= T(0)))
        return T(-1);
    T best = T(-1);
    auto consider = [&](T t) {
        if (t >= T(0) && t <= len && (best < T(0) || t < best)) best = t;
    };
    const T scale = std::abs(c0) + std::abs(c1) * len + std::abs(c2) * len * len;
    if (std::abs(c2) * len * len <= T(1e-14) * scale) {
        if (c1 < T(0)) consider(-c0 / c1);
    } else {
        const T disc = c1 * c1 - T(4) * c2 * c0;
        if (disc >= T(0)) {
            const T root = std::sqrt(disc);
            const T q = T(-0.5) * (c1 + (c1 >= T(0) ? root : -root));
            if (q != T(0)) {
                consider(q / c2);
                consider(c0 / q);
            }
        }
    }
    if (best < T(0) && c0 + (c1 + c2 * len) * len <= T(0)) {
        // Rounding hid a crossing the end value proves: bisect.
        T lo = T(0), hi = len;
        for (int it = 0; it < 80; ++it) {
            const T mid = T(0.5) * (lo + hi);
            if (c0 + (c1 + c2 * mid) * mid > T(0)) lo = mid;
            else hi = mid;
        }
        best = hi;
    }
    return best;
}

// The first hit in cell (ci, cj) on [enter, tau_out], corners f = (h00, h10, h01, h11); -1: none.
template <typename T>
T solve_cell(const Ray<T>& r, const Scene<T>& sc, const std::array<T, 4>& f, int ci, int cj,
             T tau_out) {
    const T tau_in = r.enter(ci, cj);
    const T fx0 = r.X0 + tau_in * r.dX - T(ci), fy0 = r.Y0 + tau_in * r.dY - T(cj);
    const T A = f[1] - f[0], B = f[2] - f[0], C = f[0] - f[1] - f[2] + f[3];
    const T h0 = f[0] + A * fx0 + B * fy0 + C * fx0 * fy0;
    const T h1 = A * r.dX + B * r.dY + C * (fx0 * r.dY + fy0 * r.dX);
    const T h2 = C * r.dX * r.dY;
    const T c0 = (r.zt - tau_in * r.vz) - sc.scale * (h0 - sc.bias);
    if (c0 <= T(0)) return tau_in;
    const T t = first_root(c0, -r.vz - sc.scale * h1, -sc.scale * h2, tau_out - tau_in);
    return t >= T(0) ? tau_in + t : T(-1);
}

// The level to start at: blocks of about the ray's horizontal travel (in cells), 2^msb(travel).
template <typename T>
int start_level(const Ray<T>& r, int top) {
    const T travel = r.tau_max * std::max(std::abs(r.dX), std::abs(r.dY));
    const int n = int(std::min(travel, T(1e9)));
    return std::clamp(int(std::bit_width(unsigned(std::max(n, 1)))) - 1, 0, top);
}

// One block of the traversal: level L, the node holding cell (ci, cj), its unwrapped cell range
// [x0, x1) x [y0, y1).
struct Block {
    int L, x0, x1, y0, y1, nx, ny;
};

inline Block block_at(int ci, int cj, int L, int W, int H) {
    const int ti = floor_div(ci, W), tj = floor_div(cj, H);
    const int nx = node_of(ci - ti * W, L, W), ny = node_of(cj - tj * H, L, H);
    return {L,
            ti * W + (nx << L),
            ti * W + node_end(nx, L, W),
            tj * H + (ny << L),
            tj * H + node_end(ny, L, H),
            nx,
            ny};
}

// The parent (level L + 1) of cell (ci, cj), as unwrapped node indices.
inline std::array<int, 2> parent_of(int ci, int cj, int L, int W, int H) {
    const int ti = floor_div(ci, W), tj = floor_div(cj, H);
    const int px = node_of(ci - ti * W, L + 1, W), py = node_of(cj - tj * H, L + 1, H);
    return {ti * nodes_at(W, L + 1) + px, tj * nodes_at(H, L + 1) + py};
}

// The traversal. tex: r_maxmip. Returns the hit's uv (unwrapped) and the ray's height there; at
// the slab bottom R(tau_max) when no cell is hit; after max_iterations the ray point where it
// stood. *iterations (if given): the iterations (= fetches) it took.
template <typename T>
MethodHit<T> traverse(const Scene<T>& sc, TextureSampler<T>& tex, Vec2<T> P, int max_iterations,
                      int* iterations) {
    const Ray<T> r = make_ray(sc, P);
    const int W = sc.width, H = sc.height, top = top_level(W, H);
    const T inf = std::numeric_limits<T>::infinity();
    int L = start_level(r, top);
    int ci = int(std::floor(r.X0)), cj = int(std::floor(r.Y0));
    T tau_cur = T(0);
    int it = 0;
    T t_out = r.tau_max;
    bool done = false;
    while (!done && it < max_iterations) {
        ++it;
        const Block b = block_at(ci, cj, L, W, H);
        const T ex = r.dX != T(0) ? (T(r.sx > 0 ? b.x1 : b.x0) - r.X0) * r.inv_dX : inf;
        const T ey = r.dY != T(0) ? (T(r.sy > 0 ? b.y1 : b.y0) - r.Y0) * r.inv_dY : inf;
        const T tau_out = std::min(std::min(ex, ey), r.tau_max);
        const Vec2<T> uv{(T(b.nx) + T(0.5)) / T(nodes_at(W, L)),
                         (T(b.ny) + T(0.5)) / T(nodes_at(H, L))};
        const std::array<T, 4> f = tex.fetch(uv, L);
        const T z_block =
            sc.scale * (std::max(std::max(f[0], f[1]), std::max(f[2], f[3])) - sc.bias);
        if (r.zt - tau_out * r.vz <= z_block) {
            if (L > 0) {
                // The surface may reach the ray in this block, but not before the ray has come
                // down to the block's maximum: move there, then look closer.
                const T t_cross = (r.zt - z_block) / r.vz;
                if (t_cross > tau_cur) {
                    tau_cur = t_cross;
                    ci = std::clamp(int(std::floor(r.X0 + t_cross * r.dX)), b.x0, b.x1 - 1);
                    cj = std::clamp(int(std::floor(r.Y0 + t_cross * r.dY)), b.y0, b.y1 - 1);
                }
                --L;
                continue;
            }
            const T t = solve_cell(r, sc, f, ci, cj, tau_out);
            if (t >= T(0)) {
                t_out = t;
                done = true;
                continue;
            }
        }
        if (tau_out >= r.tau_max) {
            done = true;  // R(tau_max): at the slab bottom the ray is on or below
            continue;
        }
        tau_cur = tau_out;
        // Across the block's exit face into the neighbouring cell (x first on a tie).
        int nci = ci, ncj = cj;
        if (ex <= ey) {
            nci = r.sx > 0 ? b.x1 : b.x0 - 1;
            if (L > 0) ncj = std::clamp(int(std::floor(r.Y0 + ex * r.dY)), b.y0, b.y1 - 1);
        } else {
            ncj = r.sy > 0 ? b.y1 : b.y0 - 1;
            if (L > 0) nci = std::clamp(int(std::floor(r.X0 + ey * r.dX)), b.x0, b.x1 - 1);
        }
        // Climb one level once the ray has left the parent block (inside it, the parent's test
        // would pass again).
        if (L < top && parent_of(nci, ncj, L, W, H) != parent_of(ci, cj, L, W, H)) ++L;
        ci = nci;
        cj = ncj;
    }
    if (!done) t_out = tau_cur;
    if (iterations) *iterations = it;
    return {r.at(t_out), r.zt - t_out * r.vz};
}

}  // namespace pxh::maxmip
