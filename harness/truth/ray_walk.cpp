// One ray at a time: the per-cell DDA (trace_naive, the reference) and the walk over the
// maximum mipmap (trace).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

#include "harness/truth/cell_solver.h"

namespace pxh {

void cell_solver::walk_stalled(double X0, double Y0, int cells) {
    char buf[320];
    std::snprintf(buf, sizeof buf,
                  "exact tracer: the ray from grid point (%.17g, %.17g) walked %d cells, more than "
                  "it crosses: its exit lines stopped moving (beyond kMaxSampleCells)",
                  X0, Y0, cells);
    throw std::runtime_error(buf);
}

TruthHit ExactTracer::trace_naive(Vec2d P, Vec3d V) const { return dda(make_ray(P, V)); }

TruthHit ExactTracer::dda(const Ray& r) const {
    int64_t ci = int64_t(std::floor(r.X0)), cj = int64_t(std::floor(r.Y0));
    // At most |dX| + |dY| + 2 line crossings (walk_dda's bound): never an endless loop.
    const double cells_bound = r.tau_max * (std::abs(r.dX) + std::abs(r.dY)) + 9;
    for (int cells = 1;; ++cells) {
        if (cells > cells_bound) cell_solver::walk_stalled(r.X0, r.Y0, cells);
        const double ex = r.exit_x(ci, ci + 1), ey = r.exit_y(cj, cj + 1);
        const double tau_out = std::min({ex, ey, r.tau_max});
        const double t = solve_cell(r, ci, cj, tau_out);
        if (t >= 0) return hit_at(r, t, cells);
        if (tau_out >= r.tau_max) return hit_at(r, r.tau_max, cells);  // z_bot: on or below
        if (ex <= ey) ci += r.sx;
        else cj += r.sy;
    }
}

namespace {

// The mipmap walk's current cell: tile (ti, tj) and tile-local (li, lj), kept without
// divisions; (ox, oy) is the ray's start in the current tile's local grid coordinates.
struct TileCell {
    int64_t ti, tj;
    int li, lj;
    double ox, oy;
    // A local index that left the tile moves into the neighbouring tile; true if one did.
    bool wrap(int W, int H) {
        bool new_tile = false;
        if (li >= W) {
            li -= W;
            ++ti;
            ox -= W;
            new_tile = true;
        } else if (li < 0) {
            li += W;
            --ti;
            ox += W;
            new_tile = true;
        }
        if (lj >= H) {
            lj -= H;
            ++tj;
            oy -= H;
            new_tile = true;
        } else if (lj < 0) {
            lj += H;
            --tj;
            oy += H;
            new_tile = true;
        }
        return new_tile;
    }
};

// The level to start at: blocks about half the ray's horizontal travel (in cells); coarser
// blocks hold most of the ray and their test rarely skips anything.
int start_level(double travel, int top) {
    return std::clamp(int(std::ceil(std::log2(std::max(travel, 1.0)))) - 1, 0, top);
}

}  // namespace

TruthHit ExactTracer::trace(Vec2d P, Vec3d V) const {
    const Ray r = make_ray(P, V);
    const int W = hf_.width, H = hf_.height;
    const int top = int(level_max_.size()) - 1;
    const double inf = std::numeric_limits<double>::infinity();
    const double inv_vz = 1 / r.vz;
    const bool has_x = r.dX != 0, has_y = r.dY != 0;
    const int64_t ci0 = int64_t(std::floor(r.X0)), cj0 = int64_t(std::floor(r.Y0));
    const int64_t ti0 = cell_solver::floor_div(ci0, W), tj0 = cell_solver::floor_div(cj0, H);
    TileCell cur{ti0,
                 tj0,
                 int(ci0 - ti0 * W),
                 int(cj0 - tj0 * H),
                 r.X0 - double(ti0 * W),
                 r.Y0 - double(tj0 * H)};
    auto& [ti, tj, li, lj, ox, oy] = cur;
    const float* level_max[64];
    int level_w[64];
    for (int l = 0; l <= top; ++l) {
        level_max[l] = level_max_[l].data();
        level_w[l] = level_w_[l];
    }
    int level = start_level(r.tau_max * std::max(std::abs(r.dX), std::abs(r.dY)), top);
    int steps = 0;
    double tau_cur = 0;  // the ray's parameter at the current cell
    for (;;) {
        ++steps;
        const int bi = li >> level, bj = lj >> level;
        const int lx0 = bi << level, ly0 = bj << level;
        const int lx1 = std::min(lx0 + (1 << level), W), ly1 = std::min(ly0 + (1 << level), H);
        const double ex = has_x ? (double(r.sx > 0 ? lx1 : lx0) - ox) * r.inv_dX : inf;
        const double ey = has_y ? (double(r.sy > 0 ? ly1 : ly0) - oy) * r.inv_dY : inf;
        const double tau_out = std::min(std::min(ex, ey), r.tau_max);
        const double z_block =
            s_ * (double(level_max[level][size_t(bj) * size_t(level_w[level]) + size_t(bi)]) - b_);
        if (r.zt - tau_out * r.vz <= z_block) {
            if (level > 0) {
                // The surface may reach the ray in this block, but not before the ray has come
                // down to the block's maximum: move there, then look closer.
                const double t_cross = (r.zt - z_block) * inv_vz;
                if (t_cross > tau_cur) {
                    tau_cur = t_cross;
                    li = std::clamp(int(std::floor(ox + t_cross * r.dX)), lx0, lx1 - 1);
                    lj = std::clamp(int(std::floor(oy + t_cross * r.dY)), ly0, ly1 - 1);
                }
                --level;
                continue;
            }
            const double t = solve_cell(r, ti * W + li, tj * H + lj, tau_out);
            if (t >= 0) return hit_at(r, t, steps);
        }
        if (tau_out >= r.tau_max) return hit_at(r, r.tau_max, steps);
        tau_cur = tau_out;
        // Step into the neighbouring cell across the block's exit face (the naive DDA's
        // choice on a tie).
        int nli = li, nlj = lj;
        if (ex <= ey) {
            nli = r.sx > 0 ? lx1 : lx0 - 1;
            if (level > 0) nlj = std::clamp(int(std::floor(oy + ex * r.dY)), ly0, ly1 - 1);
        } else {
            nlj = r.sy > 0 ? ly1 : ly0 - 1;
            if (level > 0) nli = std::clamp(int(std::floor(ox + ey * r.dX)), lx0, lx1 - 1);
        }
        // Coarser levels are worth a test only once the ray has left their block (inside the
        // same parent, the parent's test would fail again): the parents differ up to the
        // highest bit in which the old and new cell indices differ. Climb one level at most
        // (measured: climbing higher costs more failed tests than it saves).
        const unsigned diff = unsigned(nli ^ li) | unsigned(nlj ^ lj);
        li = nli;
        lj = nlj;
        if (cur.wrap(W, H)) level = std::min(level + 1, top);
        else if (diff)
            level = std::max(level, std::min({31 - __builtin_clz(diff), level + 1, top}));
    }
}

}  // namespace pxh
