#include "harness/ground_truth.h"

#include <tbb/parallel_for.h>
#include <xmmintrin.h>

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
    const int W = hf.width, H = hf.height;
    for (int j = 0; j < H; ++j)
        for (int i = 0; i < W; ++i)
            cell_max_[size_t(j) * W + i] =
                std::max({hf.wrapped(i, j), hf.wrapped(i + 1, j), hf.wrapped(i, j + 1),
                          hf.wrapped(i + 1, j + 1)});
    cell_max_t_.resize(cell_max_.size());
    for (int j = 0; j < H; ++j)
        for (int i = 0; i < W; ++i) cell_max_t_[size_t(i) * H + j] = cell_max_[size_t(j) * W + i];
    std::vector<std::vector<float>> level_max{cell_max_};  // max over each level's blocks
    level_w_.push_back(W);
    level_h_.push_back(H);
    while (level_w_.back() > 1 || level_h_.back() > 1) {
        const int pw = level_w_.back(), ph = level_h_.back();
        const int w = (pw + 1) / 2, h = (ph + 1) / 2;
        const auto& prev = level_max.back();
        std::vector<float> next(size_t(w) * h);
        for (int j = 0; j < h; ++j)
            for (int i = 0; i < w; ++i) {
                float m = prev[size_t(2 * j) * pw + 2 * i];
                if (2 * i + 1 < pw) m = std::max(m, prev[size_t(2 * j) * pw + 2 * i + 1]);
                if (2 * j + 1 < ph) {
                    m = std::max(m, prev[size_t(2 * j + 1) * pw + 2 * i]);
                    if (2 * i + 1 < pw) m = std::max(m, prev[size_t(2 * j + 1) * pw + 2 * i + 1]);
                }
                next[size_t(j) * w + i] = m;
            }
        level_max.push_back(std::move(next));
        level_w_.push_back(w);
        level_h_.push_back(h);
    }
    // The same maxima as surface heights z = s (max - b), ready for the ray test.
    for (const auto& lm : level_max) {
        std::vector<double> z(lm.size());
        for (size_t k = 0; k < lm.size(); ++k) z[k] = scale * (double(lm[k]) - bias);
        level_z_.push_back(std::move(z));
    }
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

int64_t floor_div(int64_t a, int64_t n) {
    int64_t q = a / n;
    return (a % n != 0 && ((a < 0) != (n < 0))) ? q - 1 : q;
}

}  // namespace

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

ExactTracer::Ray ExactTracer::make_ray(Vec2d P, Vec3d V) const {
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

ExactTracer::Ray ExactTracer::make_ray(Vec2d P, const Ray& like) const {
    // Bit for bit what make_ray(P, V) computes, without repeating the direction's divisions.
    Ray r = like;
    r.ex = P.x + r.vx / r.vz * r.zt;
    r.ey = P.y + r.vy / r.vz * r.zt;
    r.X0 = r.ex * hf_.width - 0.5;
    r.Y0 = r.ey * hf_.height - 0.5;
    return r;
}

TruthHit ExactTracer::hit_at(const Ray& r, double tau, int cells) const {
    TruthHit h;
    h.uv = {r.ex - tau * r.vx, r.ey - tau * r.vy};
    h.z = r.zt - tau * r.vz;
    h.cells = cells;
    return h;
}

double ExactTracer::solve_cell(const Ray& r, int64_t ci, int64_t cj, double tau_out) const {
    const int W = hf_.width, H = hf_.height;
    const int64_t wi = wrap_index(ci, W), wj = wrap_index(cj, H);
    if (r.zt - tau_out * r.vz > s_ * (double(cell_max_[size_t(wj) * W + wi]) - b_)) return -1;
    const double tau_in = r.enter(ci, cj);
    const int64_t wi1 = wi + 1 == W ? 0 : wi + 1, wj1 = wj + 1 == H ? 0 : wj + 1;
    const float* row0 = hf_.texels.data() + wj * W;
    const float* row1 = hf_.texels.data() + wj1 * W;
    const double h00 = row0[wi], h10 = row0[wi1], h01 = row1[wi], h11 = row1[wi1];
    // Local parameter t = tau - tau_in; fractional cell position is linear in t.
    const double fx0 = r.X0 + tau_in * r.dX - double(ci), fy0 = r.Y0 + tau_in * r.dY - double(cj);
    const double A = h10 - h00, B = h01 - h00, C = h00 - h10 - h01 + h11;
    const double h0 = h00 + A * fx0 + B * fy0 + C * fx0 * fy0;
    const double h1 = A * r.dX + B * r.dY + C * (fx0 * r.dY + fy0 * r.dX);
    const double h2 = C * r.dX * r.dY;
    const double c0 = (r.zt - tau_in * r.vz) - s_ * (h0 - b_);
    if (c0 <= 0) return tau_in;
    const double t = first_root(c0, -r.vz - s_ * h1, -s_ * h2, tau_out - tau_in);
    return t >= 0 ? tau_in + t : -1;
}

TruthHit ExactTracer::trace_naive(Vec2d P, Vec3d V) const {
    const Ray r = make_ray(P, V);
    int64_t ci = int64_t(std::floor(r.X0)), cj = int64_t(std::floor(r.Y0));
    for (int cells = 1;; ++cells) {
        const double ex = r.exit_x(ci, ci + 1), ey = r.exit_y(cj, cj + 1);
        const double tau_out = std::min({ex, ey, r.tau_max});
        const double t = solve_cell(r, ci, cj, tau_out);
        if (t >= 0) return hit_at(r, t, cells);
        if (tau_out >= r.tau_max) return hit_at(r, r.tau_max, cells);  // z_bot: on or below
        if (ex <= ey) ci += r.sx; else cj += r.sy;
    }
}

TruthHit ExactTracer::trace(Vec2d P, Vec3d V) const {
    const Ray r = make_ray(P, V);
    const int W = hf_.width, H = hf_.height;
    const int top = int(level_z_.size()) - 1;
    const double inf = std::numeric_limits<double>::infinity();
    const double inv_vz = 1 / r.vz;
    const bool has_x = r.dX != 0, has_y = r.dY != 0;
    // The current cell as tile (ti, tj) and tile-local (li, lj), kept without divisions;
    // (ox, oy) is the ray's start in the current tile's local grid coordinates.
    const int64_t ci0 = int64_t(std::floor(r.X0)), cj0 = int64_t(std::floor(r.Y0));
    int64_t ti = floor_div(ci0, W), tj = floor_div(cj0, H);
    int li = int(ci0 - ti * W), lj = int(cj0 - tj * H);
    double ox = r.X0 - double(ti * W), oy = r.Y0 - double(tj * H);
    const double* level_z[64];
    int level_w[64];
    for (int l = 0; l <= top; ++l) {
        level_z[l] = level_z_[l].data();
        level_w[l] = level_w_[l];
    }
    // Start at the level whose blocks are about half the ray's horizontal travel (in
    // cells): coarser blocks hold most of the ray and their test rarely skips anything.
    const double travel = r.tau_max * std::max(std::abs(r.dX), std::abs(r.dY));
    int level = std::clamp(int(std::ceil(std::log2(std::max(travel, 1.0)))) - 1, 0, top);
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
        const double z_block = level_z[level][size_t(bj) * size_t(level_w[level]) + size_t(bi)];
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
        bool new_tile = false;
        if (li >= W) { li -= W; ++ti; ox -= W; new_tile = true; }
        else if (li < 0) { li += W; --ti; ox += W; new_tile = true; }
        if (lj >= H) { lj -= H; ++tj; oy -= H; new_tile = true; }
        else if (lj < 0) { lj += H; --tj; oy += H; new_tile = true; }
        if (new_tile) level = std::min(level + 1, top);
        else if (diff) level = std::max(level, std::min({31 - __builtin_clz(diff), level + 1, top}));
    }
}

// ---- All rays of a view at once -------------------------------------------------------------
//
// Every eye ray of a view has the same direction, so its path across the grid is the same line
// shifted sideways. Let the major axis be the one the ray crosses faster, p the coordinate along
// it (increasing as the ray advances: column c spans p in [c, c + 1]), q the other one, and
// eta = q - m p (m = dq/dp) the ray's lateral offset, constant along the ray. The ray's height
// is z = C - k p with C = z_top + k p0 fixed per ray. Rays are grouped in bands of lateral
// width w; in column c a band's rays cover q in [eta_lo + m p, eta_lo + w + m p], p in
// [c, c + 1], so its cells there are known, and
//     U(c) = s (max of their corner maxima - b) + k (c + 1)
// bounds what any of its rays can meet: a ray reaches the surface in column c only if
// U(c) >= C (its lowest point in the column is C - k (c + 1)). A ray scans U (with maxima over
// blocks of 16 columns to skip fast) for the first such column, walks that column's cells as
// trace_naive does (same cell order, same tie rule, same solve_cell), and resumes the scan if
// the ray clears them. Columns skipped hold no cell trace_naive would solve (a margin of 1e-9
// relative absorbs rounding), so the hits are trace_naive's own.
namespace {
// Maximum of p[0 .. n), n >= 1.
inline float range_max(const float* p, int64_t n) {
    if (n < 4) {
        float mx = p[0];
        for (int64_t q = 1; q < n; ++q) mx = std::max(mx, p[q]);
        return mx;
    }
    __m128 m = _mm_loadu_ps(p);
    for (int64_t q = 4; q + 4 <= n; q += 4) m = _mm_max_ps(m, _mm_loadu_ps(p + q));
    m = _mm_max_ps(m, _mm_loadu_ps(p + n - 4));
    m = _mm_max_ps(m, _mm_movehl_ps(m, m));
    m = _mm_max_ss(m, _mm_shuffle_ps(m, m, 1));
    return _mm_cvtss_f32(m);
}
}  // namespace

class ViewTracer {
  public:
    using Ray = ExactTracer::Ray;

    ViewTracer(const ExactTracer& tr, Vec2d P0, Vec3d V) : t_(tr), like_(tr.make_ray(P0, V)) {
        const Ray& r = like_;
        major_x_ = std::abs(r.dX) >= std::abs(r.dY);
        const double dM = major_x_ ? r.dX : r.dY, dm = major_x_ ? r.dY : r.dX;
        dmaj_ = std::abs(dM);
        sa_ = dM > 0 ? 1 : -1;
        m_ = dmaj_ > 0 ? dm / dmaj_ : 0;
        k_ = dmaj_ > 0 ? r.vz / dmaj_ : 0;
        z_max_ = tr.level_z_.back()[0];
        nmaj_ = major_x_ ? tr.hf_.width : tr.hf_.height;
        nmin_ = major_x_ ? tr.hf_.height : tr.hf_.width;
        cmax_ = major_x_ ? tr.cell_max_t_.data() : tr.cell_max_.data();
    }
    // Worth it once a ray crosses a few columns; else the per-ray walk is as good.
    bool useful() const { return dmaj_ * like_.tau_max >= 2; }
    Ray ray(Vec2d P) const { return t_.make_ray(P, like_); }
    double p0(const Ray& r) const { return sa_ * major(r); }
    double eta(const Ray& r) const { return minor(r) - m_ * (sa_ * major(r)); }

    struct Scan {
        int64_t c0;       // the column trace_naive starts in
        int64_t c_first;  // columns before lie wholly above the highest surface point
        int64_t c_last;   // the column holding the slab bottom (plus one)
        double Cm;        // C less the rounding margin
    };
    Scan scan(const Ray& r) const {
        Scan sc;
        const int64_t i0 = int64_t(std::floor(major(r)));
        sc.c0 = sa_ > 0 ? i0 : -i0 - 1;
        const double p0 = this->p0(r);
        const double C = r.zt + k_ * p0;
        sc.Cm = C - 1e-9 * (std::abs(C) + t_.s_);
        sc.c_last = int64_t(std::floor(p0 + r.tau_max * dmaj_)) + 1;
        const double first = std::ceil((sc.Cm - z_max_) / k_) - 2;
        sc.c_first = first > double(sc.c0) ? (first < double(sc.c_last) ? int64_t(first) : sc.c_last)
                                           : sc.c0;
        return sc;
    }

    struct Band {
        // U with maxima over blocks of 16 and 256 columns, built 256 columns at a time.
        double eta_lo = 0, w = 1;
        int64_t base = 0;          // column of U[0]
        int64_t built = 0;         // U[0 .. built) are valid
        std::vector<double> U;     // bound per column
        std::vector<double> blk;   // max of U over blocks of 16 columns
        std::vector<double> sblk;  // ... and of 256 columns
    };

    // Extends the band's U through the 256-column chunk holding offset `o`.
    void build(Band& band, int64_t o) const {
        const int64_t end = ((o >> 8) + 1) << 8;
        band.U.resize(size_t(end));
        band.blk.resize(size_t(end >> 4));
        band.sblk.resize(size_t(end >> 8));
        const double eps = 1e-6;  // grid units: cells touched only by rounding are included too
        const double eta_hi = band.eta_lo + band.w;
        int64_t i = wrap_index(sa_ > 0 ? band.base + band.built : -(band.base + band.built) - 1, nmaj_);
        for (int64_t o = band.built; o < end; ++o) {
            const int64_t c = band.base + o;
            const double qa = m_ * double(c), qb = m_ * double(c + 1);
            const int64_t j0 = int64_t(std::floor(band.eta_lo + std::min(qa, qb) - eps));
            const int64_t j1 = int64_t(std::floor(eta_hi + std::max(qa, qb) + eps));
            const float* col = cmax_ + i * nmin_;
            const int64_t jw = wrap_index(j0, nmin_), n = j1 - j0 + 1;
            float mx;
            if (jw + n <= nmin_) {
                mx = range_max(col + jw, n);
            } else {
                mx = col[jw];
                for (int64_t q = 1, jq = jw; q < n; ++q) {
                    if (++jq == nmin_) jq = 0;
                    mx = std::max(mx, col[jq]);
                }
            }
            band.U[size_t(o)] = t_.s_ * (double(mx) - t_.b_) + k_ * double(c + 1);
            i += sa_;  // the next column's cells
            if (i == nmaj_) i = 0;
            else if (i < 0) i = nmaj_ - 1;
        }
        auto reduce = [](const double* u, int n) {
            double mx = u[0];
            for (int q = 1; q < n; ++q) mx = std::max(mx, u[q]);
            return mx;
        };
        for (int64_t b = band.built >> 4; b < end >> 4; ++b) band.blk[size_t(b)] = reduce(&band.U[size_t(b << 4)], 16);
        for (int64_t b = band.built >> 8; b < end >> 8; ++b) band.sblk[size_t(b)] = reduce(&band.blk[size_t(b << 4)], 16);
        band.built = end;
    }

    // The first offset in [o, o_last] whose bound reaches Cm, or o_last + 1.
    int64_t find(Band& band, int64_t o, int64_t o_last, double Cm) const {
        while (o <= o_last) {
            if (o >= band.built) build(band, o);
            if (band.sblk[size_t(o >> 8)] < Cm) { o = (o | 255) + 1; continue; }
            if (band.blk[size_t(o >> 4)] < Cm) { o = (o | 15) + 1; continue; }
            const double* U = band.U.data();
            for (const int64_t e = std::min(o | 15, o_last); o <= e; ++o)
                if (U[o] >= Cm) return o;
        }
        return o_last + 1;
    }

    // Traces one ray; lb (in: a column no later than its first candidate, out: that candidate).
    TruthHit trace(Band& band, const Ray& r, const Scan& sc, int64_t& lb) const {
        const double Q0 = minor(r), dq = major_x_ ? r.dY : r.dX;
        const int s_minor = major_x_ ? r.sy : r.sx;
        const int64_t j_start = int64_t(std::floor(Q0));
        auto exit_minor = [&](int64_t g) { return major_x_ ? r.exit_y(g, g + 1) : r.exit_x(g, g + 1); };
        int cells = 0;
        const int64_t o_last = sc.c_last - band.base;
        int64_t o = find(band, std::max(sc.c_first, lb) - band.base, o_last, sc.Cm);
        lb = band.base + o;
        for (; o <= o_last; o = find(band, o + 1, o_last, sc.Cm)) {
            const int64_t c = band.base + o;
            // Walk column c as trace_naive does, from the cell it is in on entering it.
            const int64_t i = sa_ > 0 ? c : -c - 1;
            int64_t ci, cj;
            if (c == sc.c0) {
                ci = int64_t(std::floor(r.X0));
                cj = int64_t(std::floor(r.Y0));
            } else {
                const double T = major_x_ ? r.tx(r.sx > 0 ? i : i + 1) : r.ty(r.sy > 0 ? i : i + 1);
                if (T >= r.tau_max) return t_.hit_at(r, r.tau_max, cells);
                // trace_naive's minor cell at T: the first from its start whose exit is not
                // passed (on a tie trace_naive steps in x first).
                int64_t g = int64_t(std::floor(Q0 + T * dq));
                if (major_x_) {
                    while (exit_minor(g) < T) g += s_minor;
                    while (g != j_start && exit_minor(g - s_minor) >= T) g -= s_minor;
                } else {
                    while (exit_minor(g) <= T) g += s_minor;
                    while (g != j_start && exit_minor(g - s_minor) > T) g -= s_minor;
                }
                ci = major_x_ ? i : g;
                cj = major_x_ ? g : i;
            }
            for (;;) {
                ++cells;
                const double ex = r.exit_x(ci, ci + 1), ey = r.exit_y(cj, cj + 1);
                const double tau_out = std::min({ex, ey, r.tau_max});
                const double t = t_.solve_cell(r, ci, cj, tau_out);
                if (t >= 0) return t_.hit_at(r, t, cells);
                if (tau_out >= r.tau_max) return t_.hit_at(r, r.tau_max, cells);
                if (ex <= ey) {
                    if (major_x_) break;
                    ci += r.sx;
                } else {
                    if (!major_x_) break;
                    cj += r.sy;
                }
            }
        }
        return t_.hit_at(r, r.tau_max, cells);
    }

  private:
    double major(const Ray& r) const { return major_x_ ? r.X0 : r.Y0; }
    double minor(const Ray& r) const { return major_x_ ? r.Y0 : r.X0; }

    const ExactTracer& t_;
    Ray like_;  // the direction-dependent part of every ray
    bool major_x_;
    int sa_;
    double dmaj_, m_, k_, z_max_;
    int64_t nmaj_, nmin_;
    const float* cmax_;  // cell maxima, minor-contiguous: [major * nmin + minor]
};

std::vector<TruthHit> ExactTracer::trace_view(const std::vector<Vec2d>& P, Vec3d V) const {
    std::vector<TruthHit> out(P.size());
    if (P.empty()) return out;
    const ViewTracer vt(*this, P[0], V);
    if (!vt.useful()) {
        tbb::parallel_for(tbb::blocked_range<size_t>(0, P.size(), 256), [&](const auto& rg) {
            for (size_t k = rg.begin(); k < rg.end(); ++k) out[k] = trace_naive(P[k], V);
        });
        return out;
    }
    // Each ray's lateral offset, and the extent of the rays and of their start points.
    const size_t n = P.size(), chunk = 16384, chunks = (n + chunk - 1) / chunk;
    struct Extent {
        double eta_lo = std::numeric_limits<double>::infinity(), eta_hi = -eta_lo;
        double x_lo = eta_lo, x_hi = -eta_lo, y_lo = eta_lo, y_hi = -eta_lo;
        void add(const Extent& e) {
            eta_lo = std::min(eta_lo, e.eta_lo), eta_hi = std::max(eta_hi, e.eta_hi);
            x_lo = std::min(x_lo, e.x_lo), x_hi = std::max(x_hi, e.x_hi);
            y_lo = std::min(y_lo, e.y_lo), y_hi = std::max(y_hi, e.y_hi);
        }
    };
    std::vector<double> eta(n);
    std::vector<Extent> ext(chunks);
    tbb::parallel_for(size_t(0), chunks, [&](size_t c) {
        Extent& e = ext[c];
        for (size_t k = c * chunk; k < std::min(n, (c + 1) * chunk); ++k) {
            eta[k] = vt.eta(vt.ray(P[k]));
            e.eta_lo = std::min(e.eta_lo, eta[k]), e.eta_hi = std::max(e.eta_hi, eta[k]);
            e.x_lo = std::min(e.x_lo, P[k].x), e.x_hi = std::max(e.x_hi, P[k].x);
            e.y_lo = std::min(e.y_lo, P[k].y), e.y_hi = std::max(e.y_hi, P[k].y);
        }
    });
    Extent all;
    for (const Extent& e : ext) all.add(e);
    // Band width: about the rays' spacing (the side of the grid area per ray), so that a band
    // holds a row of rays: narrower bands bound more tightly but cost a bound per column each.
    const double area = std::max(1.0, (all.x_hi - all.x_lo) * hf_.width) *
                        std::max(1.0, (all.y_hi - all.y_lo) * hf_.height);
    double w = std::clamp(std::floor(std::sqrt(area / double(n))), 1.0, 8.0);
    if (getenv("PXH_W")) w = atof(getenv("PXH_W"));
    const size_t bands = size_t(std::floor((all.eta_hi - all.eta_lo) / w)) + 1;
    // Counting sort by band (per chunk, then scattered in parallel): rays keep their order.
    std::vector<uint32_t> band_of(n), order(n), start(bands + 1, 0);
    std::vector<uint32_t> count(chunks * bands, 0);
    tbb::parallel_for(size_t(0), chunks, [&](size_t c) {
        uint32_t* cnt = count.data() + c * bands;
        for (size_t k = c * chunk; k < std::min(n, (c + 1) * chunk); ++k) {
            band_of[k] = uint32_t(std::min(bands - 1, size_t((eta[k] - all.eta_lo) / w)));
            ++cnt[band_of[k]];
        }
    });
    for (size_t b = 0, at = 0; b < bands; ++b) {
        start[b] = uint32_t(at);
        for (size_t c = 0; c < chunks; ++c) {
            const uint32_t m = count[c * bands + b];
            count[c * bands + b] = uint32_t(at);
            at += m;
        }
    }
    start[bands] = uint32_t(n);
    tbb::parallel_for(size_t(0), chunks, [&](size_t c) {
        uint32_t* pos = count.data() + c * bands;
        for (size_t k = c * chunk; k < std::min(n, (c + 1) * chunk); ++k) order[pos[band_of[k]]++] = uint32_t(k);
    });
    tbb::parallel_for(tbb::blocked_range<size_t>(0, bands, 1), [&](const auto& rg) {
        ViewTracer::Band band;
        std::vector<std::pair<double, uint32_t>> sorted;
        for (size_t b = rg.begin(); b < rg.end(); ++b) {
            if (start[b] == start[b + 1]) continue;
            // In order of p0, C and the first column only grow, and so does the first column
            // whose bound reaches a ray (the columns before held nothing for a lower ray).
            sorted.clear();
            for (uint32_t q = start[b]; q < start[b + 1]; ++q)
                sorted.push_back({vt.p0(vt.ray(P[order[q]])), order[q]});
            std::sort(sorted.begin(), sorted.end());
            band.eta_lo = all.eta_lo + double(b) * w;
            band.w = w;
            band.built = 0;
            band.base = vt.scan(vt.ray(P[sorted.front().second])).c_first;  // the earliest
            int64_t lb = band.base;
            for (const auto& [p0, k] : sorted) {
                const ExactTracer::Ray r = vt.ray(P[k]);
                out[k] = vt.trace(band, r, vt.scan(r), lb);
            }
        }
    });
    return out;
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
    const std::vector<TruthHit> hits = tracer.trace_view(P, V);
    if (L) gt.lit.resize(P.size());
    tbb::parallel_for(tbb::blocked_range<size_t>(0, P.size(), 256), [&](const auto& r) {
        for (size_t k = r.begin(); k < r.end(); ++k) {
            gt.uv[k] = hits[k].uv;
            gt.z[k] = hits[k].z;
            if (L) gt.lit[k] = !tracer.occluded(hits[k].uv, hits[k].z, *L);
        }
    });
    double sum = 0;
    for (const TruthHit& h : hits) sum += h.cells;
    gt.cells_mean = P.empty() ? 0 : sum / double(P.size());
    return gt;
}

}  // namespace pxh
