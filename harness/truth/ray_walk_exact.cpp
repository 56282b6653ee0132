// The per-ray fast path (trace_ray): a walk over the maximum mipmap that visits, of the cells
// trace_naive's DDA would visit, only those the block maxima do not rule out, and solves each
// with trace_naive's own closed forms, hence trace_naive's hits bit for bit.
//
// Why the same bits: the DDA's cell sequence is the merge of the column-entry times tx(line)
// and the row-entry times ty(line) (ties to x), both non-decreasing in the line index, so the
// DDA's cell at any event is found from those times alone (the fix-ups below), and a block is
// skipped only when the ray at the block's exit time lies above the block's maximum: every
// cell of the block, exiting no later (the same formulas, monotone in floating point) and
// lying no higher, is one solve_cell would reject by the same test.
#include <algorithm>
#include <cmath>
#include <limits>

#include "harness/truth/cell_solver.h"




namespace pxh {

namespace {

// One axis of the DDA in global grid coordinates: the time the ray enters column (or row) c
// crossing its near line, as trace_naive computes the exit of the previous one.
struct Axis {
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
        if ((guess - c) * step < 0) guess = c;
        while (guess != c && !entered(guess)) guess -= step;
        while (entered(guess + step)) guess += step;
        return guess;
    }
};

// Rays shorter than this (horizontal travel through the slab, in cells) take the DDA.
constexpr double kDdaTravelCells = 96;

}  // namespace

TruthHit ExactTracer::trace_ray(Vec2d P, Vec3d V) const {
    return walk(make_ray(P, V), kDdaTravelCells);
}

TruthHit ExactTracer::trace_ray_unchecked(Vec2d P, Vec3d V) const {
    return walk(make_ray_unchecked(P, V), kDdaTravelCells);
}

TruthHit ExactTracer::trace_walk(Vec2d P, Vec3d V) const { return walk(make_ray(P, V), -1); }

TruthHit ExactTracer::local_dda(const Ray& r) const {
    // trace_naive's DDA (dda, ray_walk.cpp) step for step: the same cells, the same exit times
    // ((double(k) - X0) / dX with k the cell's far line, here kept as a double that counts
    // lines exactly) and the same solver; the cell's index in the tile is kept as the ray moves
    // (no division per cell for rays that start tiles away).
    const int W = hf_.width, H = hf_.height;
    const double inf = std::numeric_limits<double>::infinity();
    int64_t ci = int64_t(std::floor(r.X0)), cj = int64_t(std::floor(r.Y0));
    int li = int(wrap_index(ci, W)), lj = int(wrap_index(cj, H));
    const bool mx = r.dX != 0, my = r.dY != 0;
    double kx = double(r.sx > 0 ? ci + 1 : ci), ky = double(r.sy > 0 ? cj + 1 : cj);
    const double stx = r.sx, sty = r.sy;
    for (int cells = 1;; ++cells) {
        const double ex = mx ? (kx - r.X0) * r.inv_dX : inf;
        const double ey = my ? (ky - r.Y0) * r.inv_dY : inf;
        const double tau_out = std::min({ex, ey, r.tau_max});
        const double t = solve_cell(r, ci, cj, li, lj, tau_out);
        if (t >= 0) return hit_at(r, t, cells);
        if (tau_out >= r.tau_max) return hit_at(r, r.tau_max, cells);
        // The DDA's step (x on a tie), without a branch: which axis steps is unpredictable.
        const bool step_x = ex <= ey;
        const int dx = step_x ? r.sx : 0, dy = step_x ? 0 : r.sy;
        ci += dx;
        cj += dy;
        kx += step_x ? stx : 0.0;
        ky += step_x ? 0.0 : sty;
        li += dx;
        lj += dy;
        li = li == W ? 0 : li < 0 ? W - 1 : li;
        lj = lj == H ? 0 : lj < 0 ? H - 1 : lj;
    }
}

TruthHit ExactTracer::walk(const Ray& r, double dda_travel) const {
    // A short ray crosses few cells: the DDA itself is faster than the walk's block tests
    // (measured with pxh bench --naive: the DDA ahead at 44 cells of travel, behind at 178).
    const double travel = r.tau_max * std::max(std::abs(r.dX), std::abs(r.dY));
    if (travel <= dda_travel) return local_dda(r);
    const int W = hf_.width, H = hf_.height;
    const int top = int(level_max_.size()) - 1;
    const double inf = std::numeric_limits<double>::infinity();
    const Axis ax{r.X0, r.inv_dX, r.sx, r.dX != 0}, ay{r.Y0, r.inv_dY, r.sy, r.dY != 0};
    // The DDA's cell: global (ci, cj) = tile (ti, tj) * (W, H) + tile-local (li, lj).
    int64_t ci = int64_t(std::floor(r.X0)), cj = int64_t(std::floor(r.Y0));
    int64_t ti = cell_solver::floor_div(ci, W), tj = cell_solver::floor_div(cj, H);
    int li = int(ci - ti * W), lj = int(cj - tj * H);
    const float* level_max[64];
    int level_w[64];
    for (int l = 0; l <= top; ++l) {
        level_max[l] = level_max_[l].data();
        level_w[l] = level_w_[l];
    }
    // Start with blocks about half the ray's horizontal travel (as trace does).
    int level = std::clamp(int(std::ceil(std::log2(std::max(travel, 1.0)))) - 1, 0, top);
    const double inv_vz = 1 / r.vz;
    int cells = 0;  // cells solved
    for (;;) {
        double ex, ey, tau_out;
        if (level == 0) {
            // trace_naive's cell, its exits and its solver.
            ex = ax.moves ? ax.exit(ci) : inf;
            ey = ay.moves ? ay.exit(cj) : inf;
            tau_out = std::min({ex, ey, r.tau_max});
            ++cells;
            const double t = solve_cell(r, ci, cj, li, lj, tau_out);
            if (t >= 0) return hit_at(r, t, cells);
            if (tau_out >= r.tau_max) return hit_at(r, r.tau_max, cells);
            if (ex <= ey) ci += r.sx;
            else cj += r.sy;
        } else {
            const int bi = li >> level, bj = lj >> level;
            const int lx0 = bi << level, ly0 = bj << level;
            const int lx1 = std::min(lx0 + (1 << level), W);
            const int ly1 = std::min(ly0 + (1 << level), H);
            // The block's cells, global: [gx0, gx1) x [gy0, gy1).
            const int64_t gx0 = ti * W + lx0, gx1 = ti * W + lx1;
            const int64_t gy0 = tj * H + ly0, gy1 = tj * H + ly1;
            // The exit times of the block's last column and row, as trace_naive computes them.
            ex = ax.moves ? ax.at_line(r.sx > 0 ? gx1 : gx0) : inf;
            ey = ay.moves ? ay.at_line(r.sy > 0 ? gy1 : gy0) : inf;
            tau_out = std::min({ex, ey, r.tau_max});
            const double z_block =
                s_ *
                (double(level_max[level][size_t(bj) * size_t(level_w[level]) + size_t(bi)]) - b_);
            if (r.zt - tau_out * r.vz <= z_block) {
                // The surface may reach the ray in this block. Cells the ray leaves while still
                // above the block's maximum cannot hold the hit: move to the DDA's cell at the
                // time the ray comes down to it (if every cell skipped provably lies below the
                // ray), then look closer.
                const double t = std::min((r.zt - z_block) * inv_vz, tau_out);
                const int64_t nci =
                    ax.moves ? ax.last_entered(ci, int64_t(std::floor(r.X0 + t * r.dX)), t, false)
                             : ci;
                const int64_t ncj =
                    ay.moves ? ay.last_entered(cj, int64_t(std::floor(r.Y0 + t * r.dY)), t, false)
                             : cj;
                if (nci != ci || ncj != cj) {
                    // The last event before t: every skipped cell was left no later.
                    const double t_last = std::max(nci != ci ? ax.entry(nci) : -inf,
                                                   ncj != cj ? ay.entry(ncj) : -inf);
                    if (r.zt - t_last * r.vz > z_block) {
                        li += int(nci - ci);
                        lj += int(ncj - cj);
                        ci = nci;
                        cj = ncj;
                    }
                }
                level = level > 2 ? level - 2 : level - 1;
                continue;
            }
            if (tau_out >= r.tau_max) return hit_at(r, r.tau_max, cells);
            // Skip the block: the DDA leaves it across the face it reaches first (x on a tie).
            if (ex <= ey) {
                const int64_t nci = r.sx > 0 ? gx1 : gx0 - 1;
                if (ay.moves)
                    cj = ay.last_entered(cj, int64_t(std::floor(r.Y0 + ex * r.dY)), ex, false);
                ci = nci;
            } else {
                const int64_t ncj = r.sy > 0 ? gy1 : gy0 - 1;
                if (ax.moves)
                    ci = ax.last_entered(ci, int64_t(std::floor(r.X0 + ey * r.dX)), ey, true);
                cj = ncj;
            }
        }
        // The new cell's tile and local indices; climb one level at most, and only once the
        // ray has left the current block's parent (inside it, the parent's test would fail
        // again), as trace does.
        const int oli = li, olj = lj;
        li = int(ci - ti * W);
        lj = int(cj - tj * H);
        bool new_tile = false;
        if (li >= W || li < 0 || lj >= H || lj < 0) {
            ti = cell_solver::floor_div(ci, W);
            tj = cell_solver::floor_div(cj, H);
            li = int(ci - ti * W);
            lj = int(cj - tj * H);
            new_tile = true;
        }
        if (new_tile) level = std::min(level + 1, top);
        else if (const unsigned diff = unsigned(oli ^ li) | unsigned(olj ^ lj); diff)
            level = std::max(level, std::min({31 - __builtin_clz(diff), level + 1, top}));
    }
}

}  // namespace pxh
