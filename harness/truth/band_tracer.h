// The band tracer's view (internal to harness/truth): ViewTracer, the rays of an orthographic
// view and their bands' bounds, shared by band_tracer.cpp (trace_grid, the scalar walk) and the
// vector walks of a band's rays (band_walk_avx2.cpp, band_walk_avx512.cpp).
#pragma once
#include <xmmintrin.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

#include "harness/truth/cell_solver.h"

namespace pxh {

// ---- All rays of a view at once -------------------------------------------------------------
//
// Every eye ray of a view has the same direction, so its path across the grid is the same line
// shifted sideways. Let the major axis be the one the ray crosses faster, p the coordinate along
// it (increasing as the ray advances: column c spans p in [c, c + 1]), q the other one, and
// eta = q - m p (m = dq/dp) the ray's lateral offset, constant along the ray. The ray's height
// is z = C - k p with C = z_top + k p0 fixed per ray. Rays are grouped in bands of lateral
// width w; over columns [ca, cb) a band's rays cover q in [eta_lo + m p, eta_lo + w + m p], so
// the cells they can cross there are known, and with M the maximum of those cells' maxima
// (read from the maximum mipmap's level l, blocks of 2^l cells, runs of 2^l columns)
//     U = s (M - b) + k cb
// bounds what any of its rays can meet: a ray reaches the surface in the run only if U >= C
// (its lowest point there is C - k cb). A ray scans U (with maxima over blocks of 16 and 256
// runs to skip fast) for the first such run, walks its cells as trace_naive does (same cell
// order, same tie rule, same solve_cell), and resumes the scan if the ray clears them. Runs
// skipped hold no cell trace_naive would solve (a margin of 1e-9 relative absorbs rounding, and
// the band's cells are widened by 1e-6 grid units), so the hits are trace_naive's own.
// Maximum of p[0 .. n), n >= 1.
inline float band_range_max(const float* p, int64_t n) {
    if (n < 4) return std::max(std::max(p[0], p[n / 2]), p[n - 1]);  // covers n = 1, 2, 3
    __m128 m = _mm_loadu_ps(p);
    for (int64_t q = 4; q + 4 <= n; q += 4) m = _mm_max_ps(m, _mm_loadu_ps(p + q));
    m = _mm_max_ps(m, _mm_loadu_ps(p + n - 4));
    m = _mm_max_ps(m, _mm_movehl_ps(m, m));
    m = _mm_max_ss(m, _mm_shuffle_ps(m, m, 1));
    return _mm_cvtss_f32(m);
}

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
        inv_k_ = 1 / k_;
        z_max_ = tr.s_ * (double(tr.level_max_.back()[0]) - tr.b_);
        off_x_ = r.vx / r.vz * r.zt;
        off_y_ = r.vy / r.vz * r.zt;
        width_ = tr.hf_.width;
        height_ = tr.hf_.height;
        nmaj_ = major_x_ ? tr.hf_.width : tr.hf_.height;
        nmin_ = major_x_ ? tr.hf_.height : tr.hf_.width;
        use_level(0);
    }
    // Bounds from the maximum mipmap's level l (blocks of 2^l cells): coarser, fewer misses.
    void use_level(int l) {
        l_ = std::min(l, int(t_.level_max_t_.size()) - 1);
        nmin_l_ = major_x_ ? t_.level_h_[size_t(l_)] : t_.level_w_[size_t(l_)];
        cmax_ = (major_x_ ? t_.level_max_t_ : t_.level_max_)[size_t(l_)].data();
        // Blocks a quarter of a chunk long (256 runs of 2^l columns): a chunk's coarse bound
        // reads about 4 block columns by the few block rows its band crosses there.
        coarse_ = std::min(l_ + 6, int(t_.level_max_.size()) - 1);
    }
    int level() const { return l_; }
    bool major_x() const { return major_x_; }
    int sign() const { return sa_; }
    double slope() const { return m_; }
    // Worth it once a ray crosses a few columns; else the per-ray walk is as good.
    bool useful() const { return dmaj_ * like_.tau_max >= 2; }
    // make_ray(P, V) bit for bit: its offsets from P (vx / vz * zt, the same operations in the
    // same order) computed once per view, not twice per ray (two divisions).
    Ray ray(Vec2d P) const {
        Ray r = like_;
        r.ex = P.x + off_x_;
        r.ey = P.y + off_y_;
        r.X0 = r.ex * width_ - 0.5;
        r.Y0 = r.ey * height_ - 0.5;
        return r;
    }
    double p0(const Ray& r) const { return sa_ * major(r); }

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
        const double first = std::ceil((sc.Cm - z_max_) * inv_k_) - 2;  // 2 to spare for rounding
        sc.c_first = first > double(sc.c0)
                         ? (first < double(sc.c_last) ? int64_t(first) : sc.c_last)
                         : sc.c0;
        return sc;
    }

    struct Band {
        // U per run of 2^l columns (l: the mipmap level), with maxima over blocks of 16 and 256
        // runs, built a chunk of 256 runs at a time when a ray first needs it. Until then the
        // chunk's sblk holds a coarser bound (from a coarser mipmap level), and a chunk whose
        // coarse bound no ray reaches is never built: rays that skim low ground for thousands
        // of tiles (grazing views) cost a bound per chunk there, not one per run, and memory
        // only for the chunks built.
        double eta_lo = 0, w = 1;
        int64_t base = 0;           // column where run 0 starts (a multiple of 2^l)
        int64_t chunks = 0;         // chunks [0, chunks) have a bound in sblk
        std::vector<double> sblk;   // per chunk of 256 runs: the max of its U once built, else
                                    // the coarse bound (never below that max)
        std::vector<int32_t> slot;  // per chunk: where U and blk hold it once built, else -1
        int32_t used = 0;           // chunks held in U and blk
        std::vector<double> U;      // bound per run, chunk by chunk (slot k: U[256 k ..])
        std::vector<double> blk;    // max of U over blocks of 16 runs (slot k: blk[16 k ..])
    };

    // The band's cells over p in [ca, cb]: minor index in [lo0 + m p, hi0 + m p] (widened by
    // 1e-6 grid units, so that cells touched only by rounding are included too); the first
    // such index and their count, for columns [ca, cb).
    std::pair<int64_t, int64_t> minor_cells(const Band& band, int64_t ca, int64_t cb) const {
        const double eps = 1e-6;
        const double lo0 = band.eta_lo - eps, hi0 = band.eta_lo + band.w + eps;
        const double qa = m_ * double(ca), qb = m_ * double(cb);
        const int64_t j0 = int64_t(std::floor(lo0 + std::min(qa, qb)));
        return {j0, int64_t(std::floor(hi0 + std::max(qa, qb))) - j0 + 1};
    }

    // Coarse bounds for chunks [band.chunks, c]: the maximum over the coarse mipmap level's
    // blocks holding the chunk's cells (they hold every level-l block its runs read, so the
    // bound is never below the chunk's U, in floating point too), at the chunk's last column.
    void extend(Band& band, int64_t c) const {
        band.sblk.resize(size_t(c + 1));
        band.slot.resize(size_t(c + 1));
        const int64_t len = int64_t(256) << l_;  // a chunk's columns
        for (int64_t k = band.chunks; k <= c; ++k) {
            const int64_t ca = band.base + k * len, cb = ca + len;
            const auto [j0, n] = minor_cells(band, ca, cb);
            const float mx = region_max(sa_ > 0 ? ca : -cb, len, j0, n);
            band.sblk[size_t(k)] = t_.s_ * (double(mx) - t_.b_) + k_ * double(cb);
            band.slot[size_t(k)] = -1;
        }
        band.chunks = c + 1;
    }

    // Maximum over the blocks of the coarse level holding cells [a0, a0 + na) along the major
    // axis and [b0, b0 + nb) along the minor one (both taken modulo the field).
    float region_max(int64_t a0, int64_t na, int64_t b0, int64_t nb) const {
        const int L = coarse_;
        // Block index ranges along one axis: one, or two where the cells wrap.
        auto ranges = [L](int64_t c0, int64_t n, int64_t cells, int64_t r[4]) {
            if (n >= cells) {
                r[0] = 0;
                r[1] = (cells - 1) >> L;
                return 1;
            }
            const int64_t s = wrap_index(c0, cells), e = s + n - 1;
            if (e < cells) {
                r[0] = s >> L;
                r[1] = e >> L;
                return 1;
            }
            r[0] = s >> L;
            r[1] = (cells - 1) >> L;
            r[2] = 0;
            r[3] = (e - cells) >> L;
            return 2;
        };
        int64_t ra[4], rb[4];
        const int na_r = ranges(a0, na, nmaj_, ra), nb_r = ranges(b0, nb, nmin_, rb);
        const float* lv = t_.level_max_[size_t(L)].data();
        const int64_t lw = t_.level_w_[size_t(L)];
        float mx = -std::numeric_limits<float>::infinity();
        for (int x = 0; x < na_r; ++x)
            for (int y = 0; y < nb_r; ++y)
                for (int64_t A = ra[2 * x]; A <= ra[2 * x + 1]; ++A)
                    for (int64_t B = rb[2 * y]; B <= rb[2 * y + 1]; ++B)
                        mx = std::max(mx, major_x_ ? lv[B * lw + A] : lv[A * lw + B]);
        return mx;
    }

    // Builds chunk c's U and blk (c < band.chunks); its sblk becomes their maximum.
    void build(Band& band, int64_t c) const {
        const int32_t k = band.used++;
        band.slot[size_t(c)] = k;
        if (band.U.size() < size_t(band.used) << 8) {
            band.U.resize(size_t(band.used) << 8);
            band.blk.resize(size_t(band.used) << 4);
        }
        const double s = t_.s_, b = t_.b_;
        const int64_t len = int64_t(1) << l_;
        double* U = band.U.data() + (size_t(k) << 8);  // run q at U[q - begin]
        const int64_t begin = c << 8, end = begin + 256;
        for (int64_t q = begin; q < end; ++q) {
            const int64_t ca = band.base + (q << l_), cb = ca + len;  // columns [ca, cb)
            const auto [j0, n] = minor_cells(band, ca, cb);
            // The run's cell columns: len consecutive ones from t (mod nmaj), through every
            // block column they touch (one when nmaj is a multiple of 2^l: runs are aligned).
            int64_t t = wrap_index(sa_ > 0 ? ca : -cb, nmaj_);
            float mx = -std::numeric_limits<float>::infinity();
            for (int64_t left = std::min(len, nmaj_); left > 0;) {
                const int64_t I = t >> l_, next = std::min((I + 1) << l_, nmaj_);
                mx = std::max(mx, block_column_max(I, j0, n));
                left -= next - t;
                t = next == nmaj_ ? 0 : next;
            }
            U[q - begin] = s * (double(mx) - b) + k_ * double(cb);
        }
        auto reduce = [](const double* u) {
            double mx = u[0];
            for (int e = 1; e < 16; ++e) mx = std::max(mx, u[e]);
            return mx;
        };
        double* blk = band.blk.data() + (size_t(k) << 4);
        for (int i = 0; i < 16; ++i) blk[i] = reduce(U + 16 * i);
        band.sblk[size_t(c)] = reduce(blk);
    }

    // Maximum over the level-l blocks of block column I that hold cells j0 .. j0 + n - 1.
    float block_column_max(int64_t I, int64_t j0, int64_t n) const {
        const float* col = cmax_ + I * nmin_l_;
        if (n >= nmin_) return band_range_max(col, nmin_l_);
        const int64_t jw = wrap_index(j0, nmin_), jl = jw + n - 1;
        if (jl < nmin_) return band_range_max(col + (jw >> l_), (jl >> l_) - (jw >> l_) + 1);
        return std::max(band_range_max(col + (jw >> l_), nmin_l_ - (jw >> l_)),  // wraps once
                        band_range_max(col, ((jl - nmin_) >> l_) + 1));
    }

    // The first run in [q, q_last] whose bound reaches Cm, or q_last + 1.
    int64_t find(Band& band, int64_t q, int64_t q_last, double Cm) const {
        while (q <= q_last) {
            const int64_t c = q >> 8;
            if (c >= band.chunks) extend(band, c);
            if (band.sblk[size_t(c)] < Cm) {
                q = (q | 255) + 1;
                continue;
            }
            const int32_t k = band.slot[size_t(c)];
            if (k < 0) {
                build(band, c);  // then test the chunk's own maximum
                continue;
            }
            const size_t at = size_t(k) << 8;  // the chunk's run 0 in U
            if (band.blk[(at + size_t(q & 255)) >> 4] < Cm) {
                q = (q | 15) + 1;
                continue;
            }
            const double* U = band.U.data() + at;  // run q at U[q & 255]
            for (const int64_t e = std::min(q | 15, q_last); q <= e; ++q)
                if (U[q & 255] >= Cm) return q;
        }
        return q_last + 1;
    }

    // A ray ready to walk: its first candidate run q and column offset o.
    struct Start {
        Ray r;
        Scan sc;
        int64_t q, o;
    };
    // Finds the ray's first candidate (lb: a column no later than it; rays taken in order of
    // p0 pass on their own first candidate) and asks the memory system early for the texels
    // of the cell the ray enters there, which it will most likely solve.
    void start(Band& band, Vec2d P, int64_t& lb, Start& st) const {
        st.r = ray(P);
        st.sc = scan(st.r);
        const int64_t o_start = std::max(st.sc.c_first, lb) - band.base;
        st.q = find(band, o_start >> l_, (st.sc.c_last - band.base) >> l_, st.sc.Cm);
        st.o = std::max(st.q << l_, o_start);
        lb = band.base + st.o;
    }
    // Asks the memory system early for the texels of the cell a started ray enters at its first
    // candidate, which it will most likely solve.
    void prefetch(const Band& band, const Start& st) const {
        const int64_t c = band.base + st.o, i = sa_ > 0 ? c : -c - 1;
        const Ray& r = st.r;
        const double T = major_x_ ? r.tx(r.sx > 0 ? i : i + 1) : r.ty(r.sy > 0 ? i : i + 1);
        const double g = std::floor((major_x_ ? r.Y0 : r.X0) + T * (major_x_ ? r.dY : r.dX));
        if (std::abs(g) < 1e15) {
            const int64_t W = t_.hf_.width, H = t_.hf_.height;
            const int64_t ci = wrap_index(major_x_ ? i : int64_t(g), W);
            const int64_t cj = wrap_index(major_x_ ? int64_t(g) : i, H);
            _mm_prefetch(reinterpret_cast<const char*>(t_.column_pairs_.data() + 2 * (cj * W + ci)),
                         _MM_HINT_T0);
        }
    }
    TruthHit trace(Band& band, const Start& st) const {
        return major_x_ ? walk<true>(band, st) : walk<false>(band, st);
    }

    // The scalar walk (walk) in steps that stop at each cell the solver's first test lets
    // through (a candidate), for the vector walks to solve candidates of several rays at once:
    // begin walks a started ray to its first candidate, resume (after a candidate without a hit)
    // to its next; both false when the ray ends at the slab bottom (hit at tau_max, `cells`),
    // true with the candidate cell (ci, cj; wrapped wi, wj), its exit time and corners. The
    // same cells in the same order as walk, so with the solver's result the same hits.
    struct WalkState {
        const Start* st;
        int64_t o, q, ci, cj, wi, wj;
        int cells;
        bool step_x;     // the step after the candidate: along x (ex <= ey), else along y
        double tau_out;  // the candidate's exit
        float f[4];      // its corners h00, h10, h01, h11
    };
    bool begin(Band& band, WalkState& w) const {
        const Start& st = *w.st;
        w.o = st.o;
        w.q = st.q;
        w.cells = 0;
        if (w.o > last_offset(band, st) || !enter(band, st, w.o, w.ci, w.cj)) return false;
        w.wi = wrap_index(w.ci, t_.hf_.width);
        w.wj = wrap_index(w.cj, t_.hf_.height);
        return major_x_ ? advance<true>(band, w) : advance<false>(band, w);
    }
    bool resume(Band& band, WalkState& w) const {
        if (w.tau_out >= w.st->r.tau_max) return false;
        return major_x_ ? step<true>(band, w, w.step_x) && advance<true>(band, w)
                        : step<false>(band, w, w.step_x) && advance<false>(band, w);
    }

    // For the vector walks (band_walk_*.cpp): the tracer's pieces they read, each as the scalar
    // walk uses it.
    const ExactTracer& tracer() const { return t_; }
    const float* column_pairs() const { return t_.column_pairs_.data(); }
    double scale() const { return t_.s_; }
    int64_t tracer_width() const { return t_.hf_.width; }
    int64_t tracer_height() const { return t_.hf_.height; }
    double bias() const { return t_.b_; }
    TruthHit hit(const Ray& r, double tau, int cells) const { return t_.hit_at(r, tau, cells); }
    double solve(const Ray& r, int64_t ci, int64_t cj, int64_t wi, int64_t wj,
                 double tau_out) const {
        return t_.solve_cell_pairs(r, ci, cj, wi, wj, tau_out);
    }
    // The first column's offset o (from band.base) and run q after a ray leaves column o through
    // its major face, as the scalar walk steps (find resumes the scan where the run ends).
    void next_column(Band& band, const Start& st, int64_t& o, int64_t& q) const {
        const int64_t q_last = (st.sc.c_last - band.base) >> l_;
        if (((o + 1) >> l_) == q) ++o;
        else o = (q = find(band, (o + 1) >> l_, q_last, st.sc.Cm)) << l_;
    }
    int64_t last_offset(const Band& band, const Start& st) const { return st.sc.c_last - band.base; }
    // The entry cell of column o (an offset from band.base): false at the slab bottom.
    bool enter(const Band& band, const Start& st, int64_t o, int64_t& ci, int64_t& cj) const {
        const int64_t c = band.base + o;
        return major_x_ ? entry_cell<true>(st.r, st.sc, c, ci, cj)
                        : entry_cell<false>(st.r, st.sc, c, ci, cj);
    }

  private:
    // trace_naive's cell (ci, cj) on entering column c: the first from its start cell whose
    // minor exit is not passed yet (on a tie trace_naive steps in x first). False when the ray
    // reaches the slab bottom before column c.
    template <bool MX>
    bool entry_cell(const Ray& r, const Scan& sc, int64_t c, int64_t& ci, int64_t& cj) const {
        if (c == sc.c0) {
            ci = int64_t(std::floor(r.X0));
            cj = int64_t(std::floor(r.Y0));
            return true;
        }
        const int64_t i = sa_ > 0 ? c : -c - 1;
        const double Q0 = MX ? r.Y0 : r.X0;
        const int64_t g0 = int64_t(std::floor(Q0));
        const double T = MX ? r.tx(r.sx > 0 ? i : i + 1) : r.ty(r.sy > 0 ? i : i + 1);
        if (T >= r.tau_max) return false;
        auto exit_minor = [&](int64_t q) { return MX ? r.exit_y(q, q + 1) : r.exit_x(q, q + 1); };
        const int sm = MX ? r.sy : r.sx;
        int64_t g = int64_t(std::floor(Q0 + T * (MX ? r.dY : r.dX)));
        if (MX) {
            while (exit_minor(g) < T) g += sm;
            while (g != g0 && exit_minor(g - sm) >= T) g -= sm;
        } else {
            while (exit_minor(g) <= T) g += sm;
            while (g != g0 && exit_minor(g - sm) > T) g -= sm;
        }
        ci = MX ? i : g;
        cj = MX ? g : i;
        return true;
    }

    // Each candidate column's cells as trace_naive walks them; the scan resumes when the ray
    // clears a column.
    template <bool MX>
    TruthHit walk(Band& band, const Start& st) const {
        const Ray& r = st.r;
        const Scan& sc = st.sc;
        const int64_t o_last = sc.c_last - band.base, q_last = o_last >> l_;
        int64_t q = st.q, o = st.o;
        int cells = 0;
        int64_t ci = 0, cj = 0, o_next = -1;  // (ci, cj): the entry cell of column o_next
        const double X0 = r.X0, Y0 = r.Y0, idx = r.inv_dX, idy = r.inv_dY;
        const double tmax = r.tau_max;
        const double inf = std::numeric_limits<double>::infinity();
        const bool hx = r.dX != 0, hy = r.dY != 0;
        const int sx = r.sx, sy = r.sy;
        const int64_t ox = sx > 0 ? 1 : 0, oy = sy > 0 ? 1 : 0;
        const int64_t W = t_.hf_.width, H = t_.hf_.height;
        for (; o <= o_last; o = ((o + 1) >> l_) == q
                                    ? o + 1
                                    : (q = find(band, (o + 1) >> l_, q_last, sc.Cm)) << l_) {
            const int64_t c = band.base + o;
            if (o != o_next && !entry_cell<MX>(r, sc, c, ci, cj))
                return t_.hit_at(r, r.tau_max, cells);
            int64_t wi = wrap_index(ci, W), wj = wrap_index(cj, H);
            for (;;) {
                ++cells;
                // trace_naive's exit_x / exit_y, from locals.
                const double ex = hx ? (double(ci + ox) - X0) * idx : inf;
                const double ey = hy ? (double(cj + oy) - Y0) * idy : inf;
                const double tau_out = std::min({ex, ey, tmax});
                const double t = t_.solve_cell_pairs(r, ci, cj, wi, wj, tau_out);
                if (t >= 0) return t_.hit_at(r, t, cells);
                if (tau_out >= tmax) return t_.hit_at(r, tmax, cells);
                if (ex <= ey) {
                    ci += sx;
                    wi += sx;
                    if (wi == W) wi = 0;
                    else if (wi < 0) wi = W - 1;
                    if (MX) break;
                } else {
                    cj += sy;
                    wj += sy;
                    if (wj == H) wj = 0;
                    else if (wj < 0) wj = H - 1;
                    if (!MX) break;
                }
            }
            o_next = o + 1;  // left through the major face: (ci, cj) is column o + 1's entry cell
        }
        return t_.hit_at(r, r.tau_max, cells);
    }

    // From the cell (ci, cj), not tested yet, to the next candidate (see begin).
    template <bool MX>
    bool advance(Band& band, WalkState& w) const {
        const Ray& r = w.st->r;
        const double tmax = r.tau_max, inf = std::numeric_limits<double>::infinity();
        const int64_t ox = r.sx > 0 ? 1 : 0, oy = r.sy > 0 ? 1 : 0, W = t_.hf_.width;
        for (;;) {
            ++w.cells;
            const double ex = r.dX != 0 ? (double(w.ci + ox) - r.X0) * r.inv_dX : inf;
            const double ey = r.dY != 0 ? (double(w.cj + oy) - r.Y0) * r.inv_dY : inf;
            const double tau_out = std::min({ex, ey, tmax});
            // solve_cell_pairs's corners and its solver's first test.
            const int64_t wi1 = w.wi + 1 == W ? 0 : w.wi + 1;
            const float* row = t_.column_pairs_.data() + 2 * w.wj * W;
            const float f00 = row[2 * w.wi], f10 = row[2 * wi1];
            const float f01 = row[2 * w.wi + 1], f11 = row[2 * wi1 + 1];
            if (!t_.cell_below(r, f00, f10, f01, f11, tau_out)) {
                w.tau_out = tau_out;
                w.step_x = ex <= ey;
                w.f[0] = f00;
                w.f[1] = f10;
                w.f[2] = f01;
                w.f[3] = f11;
                return true;
            }
            if (tau_out >= tmax) return false;
            if (!step<MX>(band, w, ex <= ey)) return false;
        }
    }
    // walk's step to the next cell (along x or y); through the major face, to the next
    // candidate column's entry cell. False when the ray ends.
    template <bool MX>
    bool step(Band& band, WalkState& w, bool along_x) const {
        const Ray& r = w.st->r;
        if (along_x) {
            w.ci += r.sx;
            w.wi += r.sx;
            if (w.wi == t_.hf_.width) w.wi = 0;
            else if (w.wi < 0) w.wi = t_.hf_.width - 1;
            if (!MX) return true;
        } else {
            w.cj += r.sy;
            w.wj += r.sy;
            if (w.wj == t_.hf_.height) w.wj = 0;
            else if (w.wj < 0) w.wj = t_.hf_.height - 1;
            if (MX) return true;
        }
        const int64_t o_next = w.o + 1;
        next_column(band, *w.st, w.o, w.q);
        if (w.o > last_offset(band, *w.st)) return false;
        if (w.o == o_next) return true;  // (ci, cj) is that column's entry cell
        if (!enter(band, *w.st, w.o, w.ci, w.cj)) return false;
        w.wi = wrap_index(w.ci, t_.hf_.width);
        w.wj = wrap_index(w.cj, t_.hf_.height);
        return true;
    }

    double major(const Ray& r) const { return major_x_ ? r.X0 : r.Y0; }

    const ExactTracer& t_;
    Ray like_;  // the direction-dependent part of every ray
    bool major_x_;
    int sa_;
    double dmaj_, m_, k_, inv_k_, z_max_;
    double off_x_, off_y_, width_, height_;  // ray's: make_ray's offsets and the field's size
    int64_t nmaj_, nmin_;  // grid cells along the major / minor axis
    int l_ = 0;            // the mipmap level the bounds are built from
    int coarse_ = 0;       // the level of the chunks' coarse bounds
    int64_t nmin_l_ = 0;   // its blocks along the minor axis
    const float* cmax_;  // its block maxima, minor-contiguous: [major block * nmin_l + minor block]
};

// The vector walks of a band's n started rays st[0 .. n) (hits into out at ks[i]): as the
// scalar walk (ViewTracer::trace) would give them, bit for bit (band_walk_engine.h).
namespace band_walk {
void walk_avx2(const ViewTracer& vt, ViewTracer::Band& band, const ViewTracer::Start* st,
               const size_t* ks, size_t n, Hits& out);
void walk_avx512(const ViewTracer& vt, ViewTracer::Band& band, const ViewTracer::Start* st,
                 const size_t* ks, size_t n, Hits& out);
}  // namespace band_walk

}  // namespace pxh
