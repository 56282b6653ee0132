// The per-ray fast path (trace_ray, and every view that is not the orthographic grid): a walk
// over the maximum mipmap that visits, of the cells trace_naive's DDA would visit, only those
// the block maxima do not rule out, and solves each with trace_naive's own closed forms, hence
// trace_naive's hits bit for bit. On CPUs with AVX-512 a view's rays take ray_walk_simd.cpp's
// vector path instead (trace_rays); single rays (trace_ray) always take this walk.
//
// Why the same bits: the DDA's cell sequence is the merge of the column-entry times tx(line)
// and the row-entry times ty(line) (ties to x), both non-decreasing in the line index, so the
// DDA's cell at any event is found from those times alone (the fix-ups below), and a block is
// skipped only when the ray at the block's exit time lies above the block's maximum: every
// cell of the block, exiting no later (the same formulas, monotone in floating point) and
// lying no higher, is one solve_cell would reject by the same test.
//
// Structure: the walk is a state machine (walk_start, walk_blocks) whose state is kept in one
// place; short rays are walked at level 0 only (the DDA itself, walk_dda, its tile-local cell
// kept as it moves: no division per cell); the descent goes two levels at a time above level 2;
// a cell's texels (and the next block's maximum) are requested a step or two before they are
// read, and on a descent the blocks of every level below at the crossing at once; the walk
// reads row-major texels padded to (W + 1) x (H + 1) (a cell's corners at fixed offsets, no
// wrap per cell), in tables on huge pages (harness/core/huge_pages.h); in a view a run of
// identical rays (a perspective view's outside pixels all carry the look-at ray) is traced
// once. Its measurements, and every variant tried and dropped: docs/internals/tracers.md.
//
// Packets (trace_rays): 4 x 4 neighbouring pixels of a view descend through the slab together
// (packet_floor): over a depth range [zt - u_lo, zt - u_hi] every ray of the packet lies in
// one box (from the rays' extreme starts and slopes, widened by eps in depth and a cell each
// side); when the maximum mipmap's bound over that box lies strictly below zt - u_lo, every
// cell any of them leaves within that range lies below it there, and the range is passed
// (the next one twice as deep, else half as deep, down to a cell of travel). Each ray then
// starts at the DDA's cell where it comes down to the packet's floor (walk_start_below):
// every cell skipped is left at a height at or above the floor (checked per ray in the DDA's
// arithmetic; where it fails the ray starts at its first cell), so inside some passed range,
// inside its box, below the ray: one solve_cell rejects by its own test. After the descent a
// ray near its hit (128 cells of travel left at most) takes the DDA (walk_dda: cheaper per
// cell than the walk's block steps). What was measured and dropped (other packet sizes,
// descents per quarter or per ray): docs/internals/tracers.md.
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "harness/truth/cell_solver.h"

namespace pxh {

namespace {

using Axis = cell_solver::DdaAxis;

// Rays shorter than this (horizontal travel through the slab, in cells) are walked at level 0
// (the DDA, walk_dda): their cells cost no more than the block tests (the value measured:
// docs/internals/tracers.md).
constexpr double kDdaTravelCells = 64;

// Packets (trace_rays): kPacketSide x kPacketSide neighbouring pixels share one descent
// through the slab (packet_floor) before each ray goes on alone from where the packet
// stopped. A packet whose rays start more than kPacketMaxSpread cells apart (a far eye: its
// box would be too wide to rule anything out) skips it. The descent's
// first depth range spans kPacketStartCells cells of travel of its fastest ray; it tests at most
// kPacketTests ranges, none shorter than kPacketStopCells cells. After it a ray with at most
// kPacketDdaCells cells of travel left takes the DDA (cheaper per cell than the walk's
// block steps), a longer one the walk from level kPacketResumeLevel at most. The values
// measured against their alternatives: docs/internals/tracers.md.
constexpr int kPacketSide = 4;
constexpr double kPacketMaxSpread = 32;
constexpr double kPacketStartCells = 8, kPacketStopCells = 1;
constexpr int kPacketTests = 16;
constexpr double kPacketDdaCells = 128;
constexpr int kPacketResumeLevel = 2;

// floor(log2(x)) for a finite x >= 1, from the exponent bits (no library call).
int floor_log2(double x) {
    uint64_t bits;
    std::memcpy(&bits, &x, sizeof bits);
    return int((bits >> 52) & 0x7ff) - 1023;
}

}  // namespace

// One ray's walk, between steps.
struct ExactTracer::WalkState {
    Ray r;
    Axis ax, ay;
    double inv_vz;
    // The DDA's cell: global (ci, cj) = its tile's first cell (ox, oy) + tile-local (li, lj).
    int64_t ci, cj, ox, oy;
    int li, lj, level, cells;
    bool dda;  // level 0 throughout (walk_dda): a short ray, or one near its hit
};

// The walk's cell (ci, cj), its tile and its tile-local indices.
inline void ExactTracer::walk_at_cell(WalkState& w, int64_t ci, int64_t cj) const {
    const int W = hf_.width, H = hf_.height;
    w.ci = ci;
    w.cj = cj;
    w.ox = cell_solver::floor_div(ci, W) * W;
    w.oy = cell_solver::floor_div(cj, H) * H;
    w.li = int(ci - w.ox);
    w.lj = int(cj - w.oy);
}

void ExactTracer::walk_start(WalkState& w, const Ray& r, double dda_travel) const {
    walk_start_ray(w, r, dda_travel);
    walk_at_cell(w, w.ci, w.cj);
}

// walk_start without the tile of the start cell (ci, cj): walk_at_cell's.
void ExactTracer::walk_start_ray(WalkState& w, const Ray& r, double dda_travel) const {
    const int top = top_level_;
    w.r = r;
    w.ax = {r.X0, r.inv_dX, r.sx, r.dX != 0};
    w.ay = {r.Y0, r.inv_dY, r.sy, r.dY != 0};
    w.inv_vz = 1 / r.vz;
    w.ci = int64_t(std::floor(r.X0));
    w.cj = int64_t(std::floor(r.Y0));
    w.cells = 0;
    const double travel = r.tau_max * std::max(std::abs(r.dX), std::abs(r.dY));
    w.dda = travel <= dda_travel;
    // Start with blocks about half the ray's horizontal travel (as trace does).
    w.level = w.dda ? 0 : std::clamp(floor_log2(std::max(travel, 1.0)) - 1, 0, top);
}

inline void ExactTracer::prefetch_cell(int li, int lj) const {
    // The cell's two rows of texels.
    const float* c = texel_row(lj) + li;
    __builtin_prefetch(c);
    __builtin_prefetch(c + texel_stride());
}

namespace {

// walk_blocks's skip of a block across the face it reaches first, at time t: `c` moves to the
// cell beyond the face, `oc` to the other axis' cell at t (o, with origin O0 and step d:
// DdaAxis::last_entered; `on_y`, the face is a row: ties go to x).
[[gnu::always_inline]] inline void skip_block(const Axis& o, double O0, double d, double t,
                                              int64_t beyond, int64_t& c, int64_t& oc,
                                              bool on_y = false) {
    if (o.moves) oc = o.last_entered(oc, int64_t(std::floor(O0 + t * d)), t, on_y);
    c = beyond;
}

// walk_blocks's new cell (ci, cj): its tile (ox, oy) and local indices (li, lj); the level
// climbs one at most, and only once the ray has left the current block's parent (inside it,
// the parent's test would fail again), as trace does.
[[gnu::always_inline]] inline void move_to_cell(int64_t ci, int64_t cj, int W, int H, int top,
                                                int64_t& ox, int64_t& oy, int& li, int& lj,
                                                int& level) {
    const int oli = li, olj = lj;
    li = int(ci - ox);
    lj = int(cj - oy);
    if (li >= W || li < 0 || lj >= H || lj < 0) {
        ox = cell_solver::floor_div(ci, W) * W;
        oy = cell_solver::floor_div(cj, H) * H;
        li = int(ci - ox);
        lj = int(cj - oy);
        level = std::min(level + 1, top);
    } else if (const unsigned diff = unsigned(oli ^ li) | unsigned(olj ^ lj); diff) {
        level = std::max(level, std::min(std::min(31 - __builtin_clz(diff), level + 1), top));
    }
}

}  // namespace

TruthHit ExactTracer::walk_blocks(const WalkState& w) const {
    // The walk's state in locals (registers), not in `w`: stores to it would make the compiler
    // reload the tracer's sizes and tables after each (they could alias).
    const Ray& r = w.r;
    const Axis ax = w.ax, ay = w.ay;
    const int W = hf_.width, H = hf_.height;
    const int top = top_level_;
    const float* const* const levels = level_ptr_.data();
    const int* const level_w = level_w_.data();
    const double inf = std::numeric_limits<double>::infinity();
    const double zt = r.zt, vz = r.vz, inv_vz = w.inv_vz, tau_max = r.tau_max;
    const double s = s_, b = b_;
    const int sx = r.sx, sy = r.sy;
    int64_t ci = w.ci, cj = w.cj, ox = w.ox, oy = w.oy;
    int li = w.li, lj = w.lj, level = w.level, cells = w.cells;
    const size_t up = texel_stride();
    for (;;) {
        if (level == 0) {
            // trace_naive's cell, its exits and its solver.
            const double ex = ax.moves ? ax.exit(ci) : inf;
            const double ey = ay.moves ? ay.exit(cj) : inf;
            const double tau_out = std::min(std::min(ex, ey), tau_max);
            ++cells;
            const float* c = texel_row(lj) + li;
            if (!cell_below(r, c[0], c[1], c[up], c[up + 1], tau_out)) {
                const double t = solve_patch(r, ci, cj, c[0], c[1], c[up], c[up + 1], tau_out);
                if (t >= 0) return hit_at(r, t, cells);
            }
            if (tau_out >= tau_max) return hit_at(r, tau_max, cells);
            if (ex <= ey) ci += sx;
            else cj += sy;
        } else {
            const int bi = li >> level, bj = lj >> level;
            const int lx0 = bi << level, ly0 = bj << level;
            const int lx1 = std::min(lx0 + (1 << level), W);
            const int ly1 = std::min(ly0 + (1 << level), H);
            // The block's cells, global: [gx0, gx1) x [gy0, gy1).
            const int64_t gx0 = ox + lx0, gx1 = ox + lx1;
            const int64_t gy0 = oy + ly0, gy1 = oy + ly1;
            // The exit times of the block's last column and row, as trace_naive computes them.
            const double ex = ax.moves ? ax.at_line(sx > 0 ? gx1 : gx0) : inf;
            const double ey = ay.moves ? ay.at_line(sy > 0 ? gy1 : gy0) : inf;
            const double tau_out = std::min(std::min(ex, ey), tau_max);
            const double z_block =
                s * (double(levels[level][size_t(bj) * size_t(level_w[level]) + size_t(bi)]) - b);
            if (zt - tau_out * vz <= z_block) {
                // The surface may reach the ray in this block. Cells the ray leaves while still
                // above the block's maximum cannot hold the hit: move to the DDA's cell at the
                // time the ray comes down to it (if every cell skipped provably lies below the
                // ray), then look closer.
                const double t = std::min((zt - z_block) * inv_vz, tau_out);
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
                    if (zt - t_last * vz > z_block) {
                        li += int(nci - ci);
                        lj += int(ncj - cj);
                        ci = nci;
                        cj = ncj;
                    }
                }
                // Two levels down at a time above level 2 (measured: fewer tests than one).
                level = level > 2 ? level - 2 : level - 1;
                // The cell's texels and the blocks of every level below at the crossing, read
                // by the descent's next tests (measured: 5-10% faster, and the lower levels at
                // once 5-10% more in most settings with caches warm).
                prefetch_cell(li, lj);
                for (int l = std::min(level, 3); l >= 0; --l)
                    __builtin_prefetch(levels[l] + size_t(lj >> l) * size_t(level_w[l]) +
                                       size_t(li >> l));
                continue;
            }
            if (tau_out >= tau_max) return hit_at(r, tau_max, cells);
            // Skip the block: the DDA leaves it across the face it reaches first (x on a tie).
            if (ex <= ey) skip_block(ay, r.Y0, r.dY, ex, sx > 0 ? gx1 : gx0 - 1, ci, cj);
            else skip_block(ax, r.X0, r.dX, ey, sy > 0 ? gy1 : gy0 - 1, cj, ci, true);
        }
        move_to_cell(ci, cj, W, H, top, ox, oy, li, lj, level);
        // Near the surface, the cell's texels are read a step or two later: request them now.
        if (level <= 2) prefetch_cell(li, lj);
    }
}

TruthHit ExactTracer::walk_dda(const WalkState& w) const {
    // walk_blocks's level 0, in a loop of its own: each exit time computed once (as walk_blocks
    // computes it, from the exit line kept as a double: the same value as double(line)); the
    // cell's corners read at fixed offsets from a pointer kept as the cell moves. The cell's
    // own first test (cell_below: its corner maximum against the ray's height at the exit)
    // rejects most cells: no separate read of level 0 (measured: as fast or faster, one table
    // fewer in cache); solve_patch, out of line, solves the others.
    const Ray& r = w.r;
    const Axis &ax = w.ax, &ay = w.ay;
    const int W = hf_.width, H = hf_.height;
    const ptrdiff_t up = ptrdiff_t(texel_stride());
    const double inf = std::numeric_limits<double>::infinity();
    int64_t ci = w.ci, cj = w.cj;
    int li = w.li, lj = w.lj, cells = w.cells;
    const int sx = r.sx, sy = r.sy;
    const float* c = texel_row(lj) + li;
    // The exit lines: the line the ray leaves the current column (row) across.
    double xl = double(sx > 0 ? ci + 1 : ci), yl = double(sy > 0 ? cj + 1 : cj);
    const double dxl = sx, dyl = sy;
    const double xo = ax.origin, xi = ax.inv_d, yo = ay.origin, yi = ay.inv_d;
    double ex = ax.moves ? (xl - xo) * xi : inf;
    double ey = ay.moves ? (yl - yo) * yi : inf;
    const double tau_max = r.tau_max;
    // The ray crosses at most |dX| + |dY| + 2 lines over its travel; past that (and a rounding
    // margin) its exit lines have stopped moving (a sample beyond kMaxSampleCells, which the
    // entry points refuse): an error, never an endless loop.
    const double cells_bound = double(cells) + tau_max * (std::abs(r.dX) + std::abs(r.dY)) + 8;
    for (;;) {
        const double tau_out = std::min(std::min(ex, ey), tau_max);
        if (++cells > cells_bound) cell_solver::walk_stalled(r.X0, r.Y0, cells);
        const float f00 = c[0], f10 = c[1], f01 = c[up], f11 = c[up + 1];
        if (!cell_below(r, f00, f10, f01, f11, tau_out)) {
            const double t = solve_patch(r, ci, cj, f00, f10, f01, f11, tau_out);
            if (t >= 0) return hit_at(r, t, cells);
        }
        if (tau_out >= tau_max) return hit_at(r, tau_max, cells);
        if (ex <= ey) {
            ci += sx;
            li += sx;
            c += sx;
            if (li == W) {
                li = 0;
                c -= W;
            } else if (li < 0) {
                li = W - 1;
                c += W;
            }
            xl += dxl;
            ex = (xl - xo) * xi;
        } else {
            cj += sy;
            lj += sy;
            c += sy * up;
            if (lj == H) {
                lj = 0;
                c -= H * up;
            } else if (lj < 0) {
                lj = H - 1;
                c += H * up;
            }
            yl += dyl;
            ey = (yl - yo) * yi;
        }
    }
}

TruthHit ExactTracer::finish(WalkState& w) const { return w.dda ? walk_dda(w) : walk_blocks(w); }

TruthHit ExactTracer::walk(const Ray& r, double dda_travel) const {
    WalkState w;
    walk_start(w, r, dda_travel);
    return finish(w);
}

TruthHit ExactTracer::trace_ray(Vec2d P, Vec3d V) const {
    return walk(make_ray(P, V), kDdaTravelCells);
}

TruthHit ExactTracer::trace_ray_unchecked(Vec2d P, Vec3d V) const {
    return walk(make_ray_unchecked(P, V), kDdaTravelCells);
}

TruthHit ExactTracer::trace_walk(Vec2d P, Vec3d V) const { return walk(make_ray(P, V), -1); }

float ExactTracer::cells_max(int64_t gx0, int64_t gx1, int64_t gy0, int64_t gy1) const {
    const int W = hf_.width, H = hf_.height;
    const int top = top_level_;
    const int64_t nx = gx1 - gx0 + 1, ny = gy1 - gy0 + 1;
    if (nx >= W || ny >= H) return level_ptr_[top][0];  // the whole tile
    // The level below the one whose blocks are at least as wide as the range (blocks at least
    // half as wide): at most three blocks per axis in each of the (at most two) tiles the
    // range reaches, as it is narrower than a tile. (Measured: tighter than the wider blocks,
    // as fast as blocks a quarter as wide.)
    int L = 0;
    while (L < top && (int64_t(1) << L) < std::max(nx, ny)) ++L;
    L = std::max(L - 1, 0);
    auto blocks = [L](int64_t first, int64_t n, int64_t size, int* out) {
        int c = 0;
        const int64_t l0 = wrap_index(first, size), end = l0 + n;
        const int64_t e0 = std::min(end, size);
        for (int64_t b = l0 >> L; b <= (e0 - 1) >> L; ++b) out[c++] = int(b);
        if (end > size)
            for (int64_t b = 0; b <= (end - size - 1) >> L; ++b) out[c++] = int(b);
        return c;
    };
    int bx[8], by[8];
    const int cx = blocks(gx0, nx, W, bx), cy = blocks(gy0, ny, H, by);
    const float* level = level_ptr_[L];
    const size_t lw = size_t(level_w_[L]);
    float m = level[size_t(by[0]) * lw + size_t(bx[0])];
    for (int b = 0; b < cy; ++b)
        for (int a = 0; a < cx; ++a) m = std::max(m, level[size_t(by[b]) * lw + size_t(bx[a])]);
    return m;
}

double ExactTracer::packet_floor(const Ray* rays, int m) const {
    // Ray k at depth u = zt - z below the slab top lies at X0 + u gX, Y0 + u gY (grid
    // coordinates, gX = dX / vz): over depths [ua, ub] the packet lies in the box spanned by
    // the smallest and largest X0 (Y0) and the extreme gX (gY) at either end.
    const double inf = std::numeric_limits<double>::infinity();
    double x0 = inf, x1 = -inf, y0 = inf, y1 = -inf;
    double gx0 = inf, gx1 = -inf, gy0 = inf, gy1 = -inf;
    for (int k = 0; k < m; ++k) {
        const Ray& r = rays[k];
        const double gx = r.dX / r.vz, gy = r.dY / r.vz;
        x0 = std::min(x0, r.X0);
        x1 = std::max(x1, r.X0);
        y0 = std::min(y0, r.Y0);
        y1 = std::max(y1, r.Y0);
        gx0 = std::min(gx0, gx);
        gx1 = std::max(gx1, gx);
        gy0 = std::min(gy0, gy);
        gy1 = std::max(gy1, gy);
    }
    const double zt = z_top();
    if (std::max(x1 - x0, y1 - y0) > kPacketMaxSpread) return zt;
    // Depths are widened by eps on both sides (far more than the rounding of any height the
    // DDA computes), boxes by one cell (more than the rounding of any position).
    const double eps = 1e-9 * (s_ + std::abs(zt));
    const double u_end = s_ * (1 - 1e-6);  // short of the slab bottom (tau_max)
    const double g = std::max({std::abs(gx0), std::abs(gx1), std::abs(gy0), std::abs(gy1)});
    // The depth over which the fastest ray moves kPacketStopCells cells: no finer test.
    const double du_min = g > 0 ? kPacketStopCells / g : u_end;
    double u_hi = 0, du = g > 0 ? std::max(du_min, kPacketStartCells / g) : u_end;
    for (int test = 0; test < kPacketTests && u_hi < u_end; ++test) {
        const double u_lo = std::min(u_hi + du, u_end);
        const double ua = std::max(u_hi - eps, 0.0), ub = u_lo + eps;
        const double bx0 = x0 + std::min(ua * gx0, ub * gx0),
                     bx1 = x1 + std::max(ua * gx1, ub * gx1);
        const double by0 = y0 + std::min(ua * gy0, ub * gy0),
                     by1 = y1 + std::max(ua * gy1, ub * gy1);
        const float top = cells_max(int64_t(std::floor(bx0)) - 1, int64_t(std::floor(bx1)) + 1,
                                    int64_t(std::floor(by0)) - 1, int64_t(std::floor(by1)) + 1);
        if (s_ * (double(top) - b_) < zt - u_lo) {
            u_hi = u_lo;  // every ray clears [zt - u_lo, zt - u_hi]
            du *= 2;
        } else {
            if (du <= du_min) break;
            du *= 0.5;
        }
    }
    return zt - u_hi;
}

void ExactTracer::walk_start_below(WalkState& w, const Ray& r, double z_floor) const {
    walk_start_ray(w, r, kDdaTravelCells);
    if (!(z_floor < r.zt)) return walk_at_cell(w, w.ci, w.cj);
    const double inf = std::numeric_limits<double>::infinity();
    const double t = (r.zt - z_floor) * w.inv_vz;  // about where the ray is at z_floor
    const Axis &ax = w.ax, &ay = w.ay;
    const int64_t nci =
        ax.moves ? ax.last_entered(w.ci, int64_t(std::floor(r.X0 + t * r.dX)), t, false) : w.ci;
    const int64_t ncj =
        ay.moves ? ay.last_entered(w.cj, int64_t(std::floor(r.Y0 + t * r.dY)), t, false) : w.cj;
    if (nci == w.ci && ncj == w.cj) return walk_at_cell(w, w.ci, w.cj);
    // Every cell the DDA leaves before (nci, ncj) is left no later than t_last, at a height
    // no lower than the ray's at t_last (the same formulas, monotone): at or above z_floor.
    const double t_last =
        std::max(nci != w.ci ? ax.entry(nci) : -inf, ncj != w.cj ? ay.entry(ncj) : -inf);
    if (!(t_last < r.tau_max) || !(r.zt - t_last * r.vz >= z_floor))
        return walk_at_cell(w, w.ci, w.cj);
    walk_at_cell(w, nci, ncj);
    const double travel_left = (r.tau_max - t_last) * std::max(std::abs(r.dX), std::abs(r.dY));
    if (travel_left <= kPacketDdaCells) w.dda = true;
    w.level = w.dda ? 0 : std::min(w.level, kPacketResumeLevel);
}

void ExactTracer::trace_rays(const View& view, Hits& out) const {
    // Every direction was checked against the travel limit (trace).
    if (simd_path()) return trace_rays_simd(view, out);
    const size_t n = view.size();
    out.resize_all(n);
    // Packets: kPacketSide x kPacketSide pixel tiles of a square row-major image, else runs
    // of kPacketSide^2 samples. Any grouping gives the same hits (each is trace_naive's);
    // neighbouring pixels make packets whose rays stay close.
    size_t side = size_t(std::sqrt(double(n)));
    while (side * side > n) --side;
    while ((side + 1) * (side + 1) <= n) ++side;
    const bool tiled = side * side == n && side > 0;
    const size_t T = kPacketSide;
    const size_t row_len = tiled ? side : n;  // samples per image row
    const size_t rows = tiled ? side : 1;
    const size_t tiles_x = (row_len + (tiled ? T : T * T) - 1) / (tiled ? T : T * T);
    const size_t tiles_y = (rows + T - 1) / T;
    const size_t tw = tiled ? T : T * T, th = tiled ? T : 1;
    tbb::parallel_for(tbb::blocked_range<size_t>(0, tiles_y * tiles_x, 64), [&](const auto& rg) {
        // A ray equal to a neighbour in the view (a perspective view's outside pixels all
        // carry the look-at ray) is traced alone, once per run of such rays (the walk is a
        // function of P and V alone), and kept out of the packets.
        bool cached = false;
        Vec2d cP{};
        Vec3d cV{};
        TruthHit chit;
        Ray rays[kPacketSide * kPacketSide];
        size_t idx[kPacketSide * kPacketSide];
        for (size_t tile = rg.begin(); tile < rg.end(); ++tile) {
            const size_t ty = tile / tiles_x, tx = tile % tiles_x;
            int m = 0;
            for (size_t j = ty * th; j < std::min(rows, ty * th + th); ++j)
                for (size_t i = tx * tw; i < std::min(row_len, tx * tw + tw); ++i) {
                    const size_t k = j * row_len + i;
                    const Vec2d P = view.P[k];
                    const Vec3d V = view.dir(k);
                    const bool run = (k > 0 && view.has_ray(k - 1, P, V)) ||
                                     (k + 1 < n && view.has_ray(k + 1, P, V));
                    if (!run) {
                        idx[m] = k;
                        rays[m++] = make_ray_unchecked(P, V);
                        continue;
                    }
                    if (!cached || !(cP.x == P.x && cP.y == P.y && cV.x == V.x && cV.y == V.y &&
                                     cV.z == V.z)) {
                        chit = walk(make_ray_unchecked(P, V), kDdaTravelCells);
                        cached = true;
                        cP = P;
                        cV = V;
                    }
                    out.set(k, chit);
                }
            if (m == 0) continue;
            const double z_floor = m > 1 ? packet_floor(rays, m) : z_top();
            for (int q = 0; q < m; ++q) {
                WalkState w;
                walk_start_below(w, rays[q], z_floor);
                out.set(idx[q], finish(w));
            }
        }
    });
}

}  // namespace pxh
