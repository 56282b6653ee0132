// The per-ray fast path (trace_ray, and every view that is not the orthographic grid): a walk
// over the maximum mipmap that visits, of the cells trace_naive's DDA would visit, only those
// the block maxima do not rule out, and solves each with trace_naive's own closed forms, hence
// trace_naive's hits bit for bit.
//
// Why the same bits: the DDA's cell sequence is the merge of the column-entry times tx(line)
// and the row-entry times ty(line) (ties to x), both non-decreasing in the line index, so the
// DDA's cell at any event is found from those times alone (the fix-ups below), and a block is
// skipped only when the ray at the block's exit time lies above the block's maximum: every
// cell of the block, exiting no later (the same formulas, monotone in floating point) and
// lying no higher, is one solve_cell would reject by the same test.
//
// Speed (single thread, pxh bench --camera perspective): the walk is a state machine
// (walk_start, walk_step) whose state is kept in one place, short rays are walked at level 0
// only (the DDA itself, its tile-local cell kept as it moves: no division per cell), the
// descent goes two levels at a time above level 2, and in a view a run of identical rays (a
// perspective view's outside pixels all carry the look-at ray) is traced once. Tried and
// dropped: walking several rays at a time, one step of each in turn (twice as slow: the
// branch predictor loses each ray's pattern), tracing the image in 8 x 8 pixel tiles (no
// measurable change), descending without moving to the crossing (slower). Kept: requesting a
// cell's texels (and the next block's maximum) a step or two before they are read.
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstring>
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

// Rays shorter than this (horizontal travel through the slab, in cells) are walked at level 0
// (the DDA): their few cells cost no more than the block tests (measured with pxh bench
// --camera perspective: 0 to 24 alike, 48 and 96 slower).
constexpr double kDdaTravelCells = 16;

// floor(log2(x)) for a finite x >= 1, from the exponent bits (no library call).
int floor_log2(double x) {
    uint64_t bits;
    std::memcpy(&bits, &x, sizeof bits);
    return int((bits >> 52) & 0x7ff) - 1023;
}

// Whether sample k of the view has exactly (bit for bit) the ray P, V.
bool same_ray(const View& view, size_t k, Vec2d P, Vec3d V) {
    const Vec2d p = view.P[k];
    const Vec3d v = view.dir(k);
    return p.x == P.x && p.y == P.y && v.x == V.x && v.y == V.y && v.z == V.z;
}

}  // namespace

// One ray's walk, between steps.
struct ExactTracer::WalkState {
    Ray r;
    Axis ax, ay;
    double inv_vz;
    // The DDA's cell: global (ci, cj) = tile (ti, tj) * (W, H) + tile-local (li, lj).
    int64_t ci, cj, ti, tj;
    int li, lj, level, cells;
    bool dda;  // a short ray: level 0 throughout
};

void ExactTracer::walk_start(WalkState& w, const Ray& r, double dda_travel) const {
    const int W = hf_.width, H = hf_.height;
    const int top = int(level_ptr_.size()) - 1;
    w.r = r;
    w.ax = {r.X0, r.inv_dX, r.sx, r.dX != 0};
    w.ay = {r.Y0, r.inv_dY, r.sy, r.dY != 0};
    w.inv_vz = 1 / r.vz;
    w.ci = int64_t(std::floor(r.X0));
    w.cj = int64_t(std::floor(r.Y0));
    w.ti = cell_solver::floor_div(w.ci, W);
    w.tj = cell_solver::floor_div(w.cj, H);
    w.li = int(w.ci - w.ti * W);
    w.lj = int(w.cj - w.tj * H);
    w.cells = 0;
    const double travel = r.tau_max * std::max(std::abs(r.dX), std::abs(r.dY));
    w.dda = travel <= dda_travel;
    // Start with blocks about half the ray's horizontal travel (as trace does).
    w.level = w.dda ? 0 : std::clamp(floor_log2(std::max(travel, 1.0)) - 1, 0, top);
}

inline void ExactTracer::prefetch_cell(int li, int lj) const {
    __builtin_prefetch(column_pairs_.data() + 2 * (size_t(lj) * size_t(hf_.width) + size_t(li)));
}

[[gnu::always_inline]] inline bool ExactTracer::walk_step(WalkState& w, TruthHit& out) const {
    const Ray& r = w.r;
    const Axis &ax = w.ax, &ay = w.ay;
    const int W = hf_.width, H = hf_.height;
    const int top = int(level_ptr_.size()) - 1;
    const double inf = std::numeric_limits<double>::infinity();
    int64_t &ci = w.ci, &cj = w.cj;
    int &li = w.li, &lj = w.lj, &level = w.level;
    if (level == 0) {
        // trace_naive's cell, its exits and its solver.
        const double ex = ax.moves ? ax.exit(ci) : inf;
        const double ey = ay.moves ? ay.exit(cj) : inf;
        const double tau_out = std::min({ex, ey, r.tau_max});
        ++w.cells;
        const double t = solve_cell(r, ci, cj, li, lj, tau_out);
        if (t >= 0) {
            out = hit_at(r, t, w.cells);
            return true;
        }
        if (tau_out >= r.tau_max) {
            out = hit_at(r, r.tau_max, w.cells);
            return true;
        }
        if (ex <= ey) ci += r.sx;
        else cj += r.sy;
    } else {
        const int bi = li >> level, bj = lj >> level;
        const int lx0 = bi << level, ly0 = bj << level;
        const int lx1 = std::min(lx0 + (1 << level), W);
        const int ly1 = std::min(ly0 + (1 << level), H);
        // The block's cells, global: [gx0, gx1) x [gy0, gy1).
        const int64_t gx0 = w.ti * W + lx0, gx1 = w.ti * W + lx1;
        const int64_t gy0 = w.tj * H + ly0, gy1 = w.tj * H + ly1;
        // The exit times of the block's last column and row, as trace_naive computes them.
        const double ex = ax.moves ? ax.at_line(r.sx > 0 ? gx1 : gx0) : inf;
        const double ey = ay.moves ? ay.at_line(r.sy > 0 ? gy1 : gy0) : inf;
        const double tau_out = std::min({ex, ey, r.tau_max});
        const double z_block =
            s_ *
            (double(level_ptr_[level][size_t(bj) * size_t(level_w_[level]) + size_t(bi)]) - b_);
        if (r.zt - tau_out * r.vz <= z_block) {
            // The surface may reach the ray in this block. Cells the ray leaves while still
            // above the block's maximum cannot hold the hit: move to the DDA's cell at the
            // time the ray comes down to it (if every cell skipped provably lies below the
            // ray), then look closer.
            const double t = std::min((r.zt - z_block) * w.inv_vz, tau_out);
            const int64_t nci =
                ax.moves ? ax.last_entered(ci, int64_t(std::floor(r.X0 + t * r.dX)), t, false) : ci;
            const int64_t ncj =
                ay.moves ? ay.last_entered(cj, int64_t(std::floor(r.Y0 + t * r.dY)), t, false) : cj;
            if (nci != ci || ncj != cj) {
                // The last event before t: every skipped cell was left no later.
                const double t_last =
                    std::max(nci != ci ? ax.entry(nci) : -inf, ncj != cj ? ay.entry(ncj) : -inf);
                if (r.zt - t_last * r.vz > z_block) {
                    li += int(nci - ci);
                    lj += int(ncj - cj);
                    ci = nci;
                    cj = ncj;
                }
            }
            // Two levels down at a time above level 2 (measured: fewer tests than one).
            level = level > 2 ? level - 2 : level - 1;
            // The cell's texels and the next block's maximum, read a step or two later
            // (measured: 5-10% faster).
            prefetch_cell(li, lj);
            __builtin_prefetch(level_ptr_[level] + size_t(lj >> level) * size_t(level_w_[level]) +
                               size_t(li >> level));
            return false;
        }
        if (tau_out >= r.tau_max) {
            out = hit_at(r, r.tau_max, w.cells);
            return true;
        }
        // Skip the block: the DDA leaves it across the face it reaches first (x on a tie).
        if (ex <= ey) {
            const int64_t nci = r.sx > 0 ? gx1 : gx0 - 1;
            if (ay.moves)
                cj = ay.last_entered(cj, int64_t(std::floor(r.Y0 + ex * r.dY)), ex, false);
            ci = nci;
        } else {
            const int64_t ncj = r.sy > 0 ? gy1 : gy0 - 1;
            if (ax.moves) ci = ax.last_entered(ci, int64_t(std::floor(r.X0 + ey * r.dX)), ey, true);
            cj = ncj;
        }
    }
    // The new cell's tile and local indices; climb one level at most, and only once the ray
    // has left the current block's parent (inside it, the parent's test would fail again), as
    // trace does. A short ray stays at level 0.
    const int oli = li, olj = lj;
    li = int(ci - w.ti * W);
    lj = int(cj - w.tj * H);
    bool new_tile = false;
    if (li >= W || li < 0 || lj >= H || lj < 0) {
        w.ti = cell_solver::floor_div(ci, W);
        w.tj = cell_solver::floor_div(cj, H);
        li = int(ci - w.ti * W);
        lj = int(cj - w.tj * H);
        new_tile = true;
    }
    if (w.dda) return false;
    if (new_tile) level = std::min(level + 1, top);
    else if (const unsigned diff = unsigned(oli ^ li) | unsigned(olj ^ lj); diff)
        level = std::max(level, std::min({31 - __builtin_clz(diff), level + 1, top}));
    // Near the surface, the cell's texels are read a step or two later: request them now.
    if (level <= 2) prefetch_cell(li, lj);
    return false;
}

TruthHit ExactTracer::walk(const Ray& r, double dda_travel) const {
    WalkState w;
    walk_start(w, r, dda_travel);
    TruthHit hit;
    while (!walk_step(w, hit)) {
    }
    return hit;
}

TruthHit ExactTracer::trace_ray(Vec2d P, Vec3d V) const {
    return walk(make_ray(P, V), kDdaTravelCells);
}

TruthHit ExactTracer::trace_ray_unchecked(Vec2d P, Vec3d V) const {
    return walk(make_ray_unchecked(P, V), kDdaTravelCells);
}

TruthHit ExactTracer::trace_walk(Vec2d P, Vec3d V) const { return walk(make_ray(P, V), -1); }

void ExactTracer::trace_rays(const View& view, Hits& out) const {
    // Every direction was checked against the travel limit (trace).
    const size_t n = view.size();
    out.resize_all(n);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 1024), [&](const auto& rg) {
        TruthHit hit;
        for (size_t k = rg.begin(); k < rg.end(); ++k) {
            // A ray equal to the one before it (a perspective view's outside pixels all carry
            // the look-at ray) has its hit: the walk is a function of P and V alone.
            const Vec2d P = view.P[k];
            const Vec3d V = view.dir(k);
            if (k == rg.begin() || !same_ray(view, k - 1, P, V))
                hit = walk(make_ray_unchecked(P, V), kDdaTravelCells);
            out.set(k, hit);
        }
    });
}

}  // namespace pxh
