// Every ray of an orthographic view on the sample grid at once: the band tracer (trace_grid).
#include <emmintrin.h>
#include <smmintrin.h>
#include <tbb/parallel_for.h>
#include <xmmintrin.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <utility>

#include "harness/truth/cell_solver.h"
#include "harness/truth/ray_walk_vector.h"

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
namespace {
// The smallest double above x (x finite): std::nextafter(x, infinity) without the library call.
inline double next_up(double x) {
    if (x == 0) return std::numeric_limits<double>::denorm_min();
    uint64_t u;
    std::memcpy(&u, &x, sizeof u);
    u += x > 0 ? 1 : uint64_t(-1);
    std::memcpy(&x, &u, sizeof u);
    return x;
}
// Maximum of p[0 .. n), n >= 1.
inline float range_max(const float* p, int64_t n) {
    if (n < 4) return std::max(std::max(p[0], p[n / 2]), p[n - 1]);  // covers n = 1, 2, 3
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
        const auto& table = (major_x_ ? t_.level_max_t_ : t_.level_max_)[size_t(l_)];
        cmax_ = table.data();
        cmax_size_ = int64_t(table.size());
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
        // A new band (its memory kept): no chunk bounded or built yet.
        void reset(double eta_lo_, double w_) {
            eta_lo = eta_lo_;
            w = w_;
            chunks = 0;
            used = 0;
        }
    };
    // Where a band's run 0 starts, given its first ray (the earliest first column), in whole
    // runs.
    int64_t first_column(Vec2d P) const { return scan(ray(P)).c_first & ~((int64_t(1) << l_) - 1); }

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
        // Where runs are aligned to the blocks (nmaj a multiple of 2^l), a run reads one block
        // column, and where its blocks (at most 4) neither wrap nor end the table, they are read
        // as one vector of 4 whose lanes past them are set to -inf: the same maximum, without
        // range_max's branches on the count (which varies from run to run). First every run's
        // place in the table (asked of the memory system at once: consecutive runs read block
        // columns nmin_l_ floats apart, a cache line each), then the maxima.
        const bool aligned = (nmaj_ & (len - 1)) == 0;
        int64_t at[256];
        int32_t count[256];  // 0: the general path
        for (int64_t q = begin; q < end; ++q) {
            const int64_t ca = band.base + (q << l_), cb = ca + len;  // columns [ca, cb)
            const auto [j0, n] = minor_cells(band, ca, cb);
            const int64_t t = wrap_index(sa_ > 0 ? ca : -cb, nmaj_);
            const int64_t jw = wrap_index(j0, nmin_), jl = jw + n - 1;
            const int64_t a = (t >> l_) * nmin_l_ + (jw >> l_);
            const int64_t m = (jl >> l_) - (jw >> l_) + 1;
            const bool fast = aligned && n < nmin_ && jl < nmin_ && m <= 4 && a + 4 <= cmax_size_;
            at[q - begin] = fast ? a : 0;
            count[q - begin] = fast ? int32_t(m) : 0;
            _mm_prefetch(reinterpret_cast<const char*>(cmax_ + at[q - begin]), _MM_HINT_T0);
        }
        const __m128i lane = _mm_setr_epi32(0, 1, 2, 3);
        const __m128 none = _mm_set1_ps(-std::numeric_limits<float>::infinity());
        for (int64_t q = begin; q < end; ++q) {
            const int64_t ca = band.base + (q << l_), cb = ca + len;  // columns [ca, cb)
            float mx = -std::numeric_limits<float>::infinity();
            if (count[q - begin] > 0) {
                const __m128 in =
                    _mm_castsi128_ps(_mm_cmplt_epi32(lane, _mm_set1_epi32(count[q - begin])));
                __m128 v = _mm_blendv_ps(none, _mm_loadu_ps(cmax_ + at[q - begin]), in);
                v = _mm_max_ps(v, _mm_movehl_ps(v, v));
                mx = _mm_cvtss_f32(_mm_max_ss(v, _mm_shuffle_ps(v, v, 1)));
            } else {
                // The run's cell columns: len consecutive ones from t (mod nmaj), through every
                // block column they touch.
                const auto [j0, n] = minor_cells(band, ca, cb);
                int64_t t = wrap_index(sa_ > 0 ? ca : -cb, nmaj_);
                for (int64_t left = std::min(len, nmaj_); left > 0;) {
                    const int64_t I = t >> l_, next = std::min((I + 1) << l_, nmaj_);
                    mx = std::max(mx, block_column_max(I, j0, n));
                    left -= next - t;
                    t = next == nmaj_ ? 0 : next;
                }
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
        if (n >= nmin_) return range_max(col, nmin_l_);
        const int64_t jw = wrap_index(j0, nmin_), jl = jw + n - 1;
        if (jl < nmin_) return range_max(col + (jw >> l_), (jl >> l_) - (jw >> l_) + 1);
        return std::max(range_max(col + (jw >> l_), nmin_l_ - (jw >> l_)),  // wraps once
                        range_max(col, ((jl - nmin_) >> l_) + 1));
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
            // the block's 16 runs against Cm at once (a bit per run), those from q to e kept:
            // the first is the first run whose bound reaches Cm, without a branch per run
            const double* u = band.U.data() + at + size_t(q & 240);
            const __m128d cm = _mm_set1_pd(Cm);
            unsigned bits = 0;
            for (int i = 0; i < 8; ++i)
                bits |= unsigned(_mm_movemask_pd(_mm_cmpge_pd(_mm_loadu_pd(u + 2 * i), cm)))
                        << (2 * i);
            const int64_t e = std::min(q | 15, q_last);
            bits &= (~0u << (q & 15)) & ((2u << (e & 15)) - 1);
            if (bits) return (q & ~int64_t(15)) + __builtin_ctz(bits);
            q = e + 1;
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
    // start, then a request for the texels (column_pairs_) of the cell the ray will most
    // likely solve first: its entry cell in the column found (the scalar walk's).
    void start_walk(Band& band, Vec2d P, int64_t& lb, Start& st) const {
        start(band, P, lb, st);
        const int64_t c = band.base + st.o;
        const double g = std::floor(minor(st.r) + column_time(st.r, c) * minor_step(st.r));
        if (std::abs(g) < 1e15) {
            const int64_t W = t_.hf_.width;
            const auto [ci, cj] = tile_cell(c, int64_t(g));
            _mm_prefetch(reinterpret_cast<const char*>(t_.column_pairs_.data() + 2 * (cj * W + ci)),
                         _MM_HINT_T0);
        }
    }
    // The time the ray enters column c along the major axis: trace_naive's own exit time of
    // the line between columns c - 1 and c (entry_cell's T).
    double column_time(const Ray& r, int64_t c) const {
        const int64_t i = sa_ > 0 ? c : -c - 1;
        return major_x_ ? r.tx(r.sx > 0 ? i : i + 1) : r.ty(r.sy > 0 ? i : i + 1);
    }
    // A time from which the vector DDA may walk on, the ray having left every cell of the
    // columns before c that trace_naive solves (c after the ray's start column, the cells
    // before it ruled out by the bounds): just after column_time(c), the DDA's cell then being
    // column c's entry cell, or column_time(c) itself where the ray crosses a minor line at
    // that very time (trace_naive then steps through a cell of column c it enters and leaves
    // at that time, which the bounds do not rule out).
    double column_start(const Ray& r, int64_t c) const {
        const double T = column_time(r, c);
        const double q0 = minor(r), dq = minor_step(r);
        // The line crossed at T, if any, is g or g + 1 (the ray lies within rounding of it).
        const double g = std::floor(q0 + T * dq);
        if (dq != 0) {
            const double inv = major_x_ ? r.inv_dY : r.inv_dX;
            if ((g - q0) * inv == T || (g + 1 - q0) * inv == T) return T;
        }
        return next_up(T);
    }
    // A column no later than the ray's at time t (one behind floor: rounding either way).
    int64_t column_at(const Ray& r, double t) const {
        return int64_t(std::floor(sa_ * (major(r) + t * (major_x_ ? r.dX : r.dY)))) - 1;
    }
    TruthHit hit(const Ray& r, double tau, int cells) const { return t_.hit_at(r, tau, cells); }
    TruthHit trace(Band& band, const Start& st) const {
        return major_x_ ? walk<true>(band, st) : walk<false>(band, st);
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

    double major(const Ray& r) const { return major_x_ ? r.X0 : r.Y0; }
    double minor(const Ray& r) const { return major_x_ ? r.Y0 : r.X0; }
    double minor_step(const Ray& r) const { return major_x_ ? r.dY : r.dX; }
    // The tile's cell at column c and minor index g.
    std::pair<int64_t, int64_t> tile_cell(int64_t c, int64_t g) const {
        const int64_t i = sa_ > 0 ? c : -c - 1;
        return {wrap_index(major_x_ ? i : g, t_.hf_.width),
                wrap_index(major_x_ ? g : i, t_.hf_.height)};
    }

    const ExactTracer& t_;
    Ray like_;  // the direction-dependent part of every ray
    bool major_x_;
    int sa_;
    double dmaj_, m_, k_, inv_k_, z_max_;
    double off_x_, off_y_, width_, height_;  // ray's: make_ray's offsets and the field's size
    int64_t nmaj_, nmin_;                    // grid cells along the major / minor axis
    int l_ = 0;                              // the mipmap level the bounds are built from
    int coarse_ = 0;                         // the level of the chunks' coarse bounds
    int64_t nmin_l_ = 0;                     // its blocks along the minor axis
    const float* cmax_;  // its block maxima, minor-contiguous: [major block * nmin_l + minor block]
    int64_t cmax_size_ = 0;  // their number
};

namespace {

// Traces the rays of one band, given in order of p0 (ties in order of k), kAhead rays ahead:
// a ray's first candidate is found (and its texels requested) kAhead rays before it walks, so
// that the memory system answers while the rays before it walk. Each ray is started in place,
// in a ring of kAhead + 1 (copying a start cost 3-8%; 2 and 4 rays ahead measured alike).
class BandRun {
  public:
    using Start = ViewTracer::Start;
    static constexpr int kAhead = 1, kSlots = kAhead + 1;
    BandRun(const ViewTracer& vt, ViewTracer::Band& band, Hits& out)
        : vt_(vt), band_(band), out_(out) {}
    void begin(double eta_lo, double w) {
        band_.reset(eta_lo, w);
        held_ = 0;
        head_ = 0;
    }
    void add(Vec2d P, size_t k) {
        if (held_ == 0) {
            // Run 0 starts at the earliest first column (the first ray's), in whole runs.
            band_.base = vt_.first_column(P);
            lb_ = band_.base;
        }
        // Started in place (the slot after the held ones), then the oldest walks.
        const int at = (head_ + held_) % kSlots;
        vt_.start_walk(band_, P, lb_, cur_[at]);
        k_[at] = k;
        if (held_ == kAhead) {
            out_.set(k_[head_], vt_.trace(band_, cur_[head_]));
            head_ = (head_ + 1) % kSlots;
        } else {
            ++held_;
        }
    }
    void end() {
        for (; held_ > 0; --held_, head_ = (head_ + 1) % kSlots)
            out_.set(k_[head_], vt_.trace(band_, cur_[head_]));
        head_ = 0;
    }

  private:
    const ViewTracer& vt_;
    ViewTracer::Band& band_;
    Hits& out_;
    int held_ = 0, head_ = 0;  // rays started and not walked yet: cur_[head_], ... (a ring)
    Start cur_[kSlots]{};
    size_t k_[kSlots]{};
    int64_t lb_ = 0;
};

// A band's rays with the band's bounds as the first pass and the vector DDA (pass B of the
// per-ray vector paths, ray_walk_simd.cpp) as the second: each ray's first candidate run is
// found as BandRun finds it (ViewTracer::start), the DDA walks from the time the ray enters
// that run's first column (every cell left before it lies in runs the bounds rule out: cells
// cell_below rejects), a ray the DDA leaves open finds its next candidate from the column it
// has reached, and so on until every ray of the band is resolved. The same cells trace_naive
// walks from there, its exit times and solver: its hits bit for bit.
using DdaPass = void (*)(const vector_walk::SquareScene&, vector_walk::RayColumns&, const int*,
                         const double*, int, double*, uint8_t*);
class BandDdaRun {
  public:
    using Start = ViewTracer::Start;
    struct Buffers {
        std::vector<Start> st;
        std::vector<size_t> key;
        vector_walk::RayColumns cols;
        std::vector<int> list;
        std::vector<double> t, out_t;
        std::vector<uint8_t> resolved;
    };
    BandDdaRun(const ViewTracer& vt, ViewTracer::Band& band, Hits& out,
               const vector_walk::SquareScene& sc, DdaPass dda, Buffers& buf)
        : vt_(vt), band_(band), out_(out), sc_(sc), dda_(dda), buf_(buf) {}
    void begin(double eta_lo, double w) {
        band_.reset(eta_lo, w);
        n_ = 0;
    }
    void add(Vec2d P, size_t k) {
        if (n_ == 0) {
            band_.base = vt_.first_column(P);
            lb_ = band_.base;
        }
        if (buf_.st.size() <= size_t(n_)) {
            buf_.st.resize(size_t(n_) * 2 + 64);
            buf_.key.resize(buf_.st.size());
        }
        vt_.start(band_, P, lb_, buf_.st[size_t(n_)]);
        buf_.key[size_t(n_++)] = k;
        // the ray's places in the output, written once its walk ends (end): their lines
        // asked for now, so that those writes do not wait on the memory system
        _mm_prefetch(reinterpret_cast<const char*>(out_.uv.data() + k), _MM_HINT_T0);
        _mm_prefetch(reinterpret_cast<const char*>(out_.z.data() + k), _MM_HINT_T0);
        _mm_prefetch(reinterpret_cast<const char*>(out_.cells.data() + k), _MM_HINT_T0);
    }
    void end() {
        const int l = vt_.level();
        Buffers& b = buf_;
        vector_walk::RayColumns& cols = b.cols;
        cols.resize(size_t(n_));
        for (auto* v : {&b.t, &b.out_t}) v->resize(size_t(n_));
        b.list.resize(size_t(n_));
        b.resolved.resize(size_t(n_));
        // The rays with a candidate run before the slab bottom into cols, from the time they
        // enter it; the others' answer is tau_max (every cell rejected).
        int nb = 0;
        for (int q = 0; q < n_; ++q) {
            const Start& st = b.st[size_t(q)];
            const ViewTracer::Ray& r = st.r;
            const int64_t c = band_.base + st.o;
            const double t = st.q > (st.sc.c_last - band_.base) >> l ? r.tau_max
                             : c == st.sc.c0                         ? 0
                                                                     : vt_.column_start(r, c);
            if (t >= r.tau_max) {
                out_.set(b.key[size_t(q)], vt_.hit(r, r.tau_max, 0));
                continue;
            }
            const size_t at = size_t(nb);
            cols.X0[at] = r.X0;
            cols.Y0[at] = r.Y0;
            cols.dX[at] = r.dX;
            cols.dY[at] = r.dY;
            cols.iX[at] = r.inv_dX;
            cols.iY[at] = r.inv_dY;
            cols.vz[at] = r.vz;
            cols.ivz[at] = 1 / r.vz;
            cols.tm[at] = r.tau_max;
            cols.counted[at] = -std::numeric_limits<double>::infinity();
            cols.cells[at] = 0;
            cols.id[at] = q;
            b.list[at] = nb;
            b.t[at] = t;
            ++nb;
        }
        while (nb > 0) {
            dda_(sc_, cols, b.list.data(), b.t.data(), nb, b.out_t.data(), b.resolved.data());
            int m = 0;  // the rays left open, to the front of the list
            for (int p = 0; p < nb; ++p) {
                const int at = b.list[size_t(p)];
                const int q = cols.id[size_t(at)];
                const Start& st = b.st[size_t(q)];
                const ViewTracer::Ray& r = st.r;
                const double t0 = b.out_t[size_t(p)];
                if (b.resolved[size_t(p)]) {
                    out_.set(b.key[size_t(q)], vt_.hit(r, t0, cols.cells[size_t(at)]));
                    continue;
                }
                // On from the column the ray has reached to its next candidate run (the DDA
                // walks on past a candidate run for up to kDdaCells cells: cheaper than a scan
                // and a new start after each run, measured).
                const int64_t q_last = (st.sc.c_last - band_.base) >> l;
                const int64_t o_start = std::max(vt_.column_at(r, t0), st.sc.c_first) - band_.base;
                const int64_t qn = vt_.find(band_, o_start >> l, q_last, st.sc.Cm);
                double t = r.tau_max;
                if (qn <= q_last) {
                    const int64_t c = band_.base + std::max(qn << l, o_start);
                    t = vt_.column_time(r, c) > t0 ? vt_.column_start(r, c) : t0;
                }
                if (t >= r.tau_max) {
                    out_.set(b.key[size_t(q)], vt_.hit(r, r.tau_max, cols.cells[size_t(at)]));
                    continue;
                }
                b.list[size_t(m)] = at;
                b.t[size_t(m++)] = t;
            }
            nb = m;
        }
    }

  private:
    const ViewTracer& vt_;
    ViewTracer::Band& band_;
    Hits& out_;
    const vector_walk::SquareScene& sc_;
    DdaPass dda_;
    int n_ = 0;
    int64_t lb_ = 0;
    Buffers& buf_;  // kept by the thread from band to band
};

// Band width in grid units: about the rays' spacing (the side of the grid area per ray), so
// that a band holds a row of rays. For the scalar walk, twice that where rays lie about 4 cells
// apart or more (the case measured; closer rays keep bands one spacing wide, which solve fewer
// cells). Narrower bands bound more tightly but cost a bound per run, and each band builds its
// own: measured at 2048 x 2048 with 512 x 512 rays (spacing 4; pxh bench, one thread, fbm), the
// scalar walk with bands 8 wide (twice the cells per ray) 1.1-1.25 times as fast as with bands
// 4 wide, bands 16 wide no faster; at 512 x 512 (spacing 1) bands 2 or 4 wide no faster than 1
// (within the machine's noise). The vector DDA walks cells for less, so its balance differs
// (fbm, 85 deg, AVX2 path, exact / Embree, best of 7 repeats, two rounds): at 512 x 512 bands 2
// wide 2.33-2.35 against 2.12-2.15 for 1 wide and 2.11 for 3 wide; at 2048 x 2048 bands 4 wide
// (one spacing) 2.02-2.03 against 1.85-1.89 for 6 or 8 wide. So: one spacing, at least 2.
double band_width(double area, size_t rays, bool vector_dda) {
    const double spacing = std::sqrt(area / double(std::max<size_t>(rays, 1)));
    if (vector_dda) return std::clamp(std::round(spacing), 2.0, 8.0);
    return std::clamp(std::round(spacing >= 3.5 ? 2 * spacing : spacing), 1.0, 8.0);
}

// The mipmap level the bounds come from: blocks about half the band's width (level 0, the
// cells themselves, for bands one cell wide), small arrays that stay in cache.
int band_level(double w) { return std::max(0, int(std::lround(std::log2(w / 2)))); }

// Sample (i, j) of the N x N grid, as sample_grid places it.
Vec2d grid_sample(int n, int64_t i, int64_t j) {
    return {(double(i) + 0.5) / n, (double(j) + 0.5) / n};
}

// The grid's rays in bands, each traced in order of p0 (its start along the major axis),
// enumerated without sorting: a sample's p0 depends only on its major index a, its lateral
// offset eta = q0 - m p0 only grows with its minor index b, so band by band, for each a in
// order of p0, the band's samples are a run of b, followed from one a to the next.
class BandLayout {
  public:
    // Chooses the band width and the mipmap level vt's bounds come from.
    BandLayout(ViewTracer& vt, int n, const HeightField& hf, bool vector_dda) : vt_(vt), n_(n) {
        const bool mx = vt.major_x();
        maj_.resize(size_t(n));  // X0 or Y0 by index
        mnr_.resize(size_t(n));
        for (int64_t t = 0; t < n; ++t) {
            const auto r = vt.ray(grid_sample(n, t, t));
            maj_[size_t(t)] = mx ? r.X0 : r.Y0;
            mnr_[size_t(t)] = mx ? r.Y0 : r.X0;
        }
        // eta is monotone in a and in b: its extremes lie at the corners.
        eta_lo_ = std::numeric_limits<double>::infinity();
        double eta_hi = -eta_lo_;
        for (int64_t a : {int64_t(0), int64_t(n - 1)})
            for (int64_t b : {int64_t(0), int64_t(n - 1)})
                eta_lo_ = std::min(eta_lo_, eta(a, b)), eta_hi = std::max(eta_hi, eta(a, b));
        const double spacing = double(n - 1) / n;  // the samples' extent, in tiles
        const double area = std::max(1.0, spacing * hf.width) * std::max(1.0, spacing * hf.height);
        w_ = band_width(area, size_t(n) * size_t(n), vector_dda);
        vt.use_level(band_level(w_));
        inv_w_ = 1 / w_;
        bands_ = int64_t(std::floor((eta_hi - eta_lo_) * inv_w_)) + 1;
    }
    int64_t bands() const { return bands_; }

    // Traces band bd's rays into `run`.
    template <class Run>
    void trace_band(int64_t bd, Run& run) const {
        const int64_t n = n_;
        run.begin(eta_lo_ + double(bd) * w_, w_);
        int64_t b0 = -1;  // the band's first b at the current a
        for (int64_t step = 0; step < n; ++step) {
            const int64_t a = vt_.sign() > 0 ? step : n - 1 - step;  // p0 grows
            if (b0 < 0) {  // first a: search (band grows with b)
                int64_t lo = 0, hi = n;
                while (lo < hi) {
                    const int64_t mid = (lo + hi) / 2;
                    if (band(a, mid) < bd) lo = mid + 1;
                    else hi = mid;
                }
                b0 = lo;
            } else {
                while (b0 < n && band(a, b0) < bd) ++b0;
                while (b0 > 0 && band(a, b0 - 1) >= bd) --b0;
            }
            for (int64_t b = b0; b < n && band(a, b) == bd; ++b) {
                const int64_t i = vt_.major_x() ? a : b, j = vt_.major_x() ? b : a;
                run.add(grid_sample(n_, i, j), size_t(j) * size_t(n) + size_t(i));
            }
        }
        run.end();
    }

  private:
    double eta(int64_t a, int64_t b) const {
        return mnr_[size_t(b)] - vt_.slope() * (vt_.sign() * maj_[size_t(a)]);
    }
    int64_t band(int64_t a, int64_t b) const {
        return std::min(bands_ - 1, int64_t((eta(a, b) - eta_lo_) * inv_w_));
    }

    const ViewTracer& vt_;
    int n_;
    std::vector<double> maj_, mnr_;
    double eta_lo_ = 0, w_ = 1, inv_w_ = 1;
    int64_t bands_ = 0;
};

}  // namespace

void ExactTracer::trace_grid(int n, Vec3d V, Hits& out) const {
    throw_if_problem(ray_travel_problem(s_, V));  // before any band's bounds grow with the travel
    out.resize_all(size_t(n) * size_t(std::max(n, 0)));
    if (n <= 0) return;
    ViewTracer vt(*this, grid_sample(n, 0, 0), V);
    if (!vt.useful()) {
        tbb::parallel_for(tbb::blocked_range<size_t>(0, out.uv.size(), 256), [&](const auto& rg) {
            for (size_t k = rg.begin(); k < rg.end(); ++k)
                out.set(k, trace_naive(grid_sample(n, int64_t(k % n), int64_t(k / n)), V));
        });
        return;
    }
    // On a vector path the candidates' cells take the path's DDA (BandDdaRun), else the
    // scalar walk (BandRun). Each thread keeps its band's memory from band to band and from
    // view to view (fresh allocations cost page faults: 2048 x 2048, 85 deg, a third of the
    // time).
    const bool vector_dda = ray_path() != RayPath::scalar;
    const BandLayout layout(vt, n, hf_, vector_dda);
    if (vector_dda) {
        vector_walk::SquareScene sc{};
        fill_scene(sc);
        const DdaPass pass_b = ray_path() == RayPath::avx512 ? vector_walk::avx512::dda_pass
                                                             : vector_walk::avx2::dda_pass;
        tbb::parallel_for(tbb::blocked_range<int64_t>(0, layout.bands(), 1), [&](const auto& rg) {
            thread_local ViewTracer::Band mem;
            thread_local BandDdaRun::Buffers buf;
            BandDdaRun run(vt, mem, out, sc, pass_b, buf);
            for (int64_t bd = rg.begin(); bd < rg.end(); ++bd) layout.trace_band(bd, run);
        });
        return;
    }
    tbb::parallel_for(tbb::blocked_range<int64_t>(0, layout.bands(), 1), [&](const auto& rg) {
        thread_local ViewTracer::Band mem;
        BandRun run(vt, mem, out);
        for (int64_t bd = rg.begin(); bd < rg.end(); ++bd) layout.trace_band(bd, run);
    });
}

void ExactTracer::trace_grid(int n, Vec3d V, std::vector<TruthHit>& out) const {
    Hits hits;
    trace_grid(n, V, hits);
    out.resize(hits.uv.size());
    for (size_t k = 0; k < out.size(); ++k) out[k] = {hits.uv[k], hits.z[k], hits.cells[k]};
}

}  // namespace pxh
