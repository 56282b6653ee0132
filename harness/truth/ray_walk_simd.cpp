// The per-ray vector paths (ExactTracer::ray_path, chosen at run time; the tables need a field
// of at least 2 x 2 cells): every ray of a view traced 8 to a vector where the CPU has AVX-512
// (avx512f and avx512dq: the kernels here), 4 to a vector where it has AVX2 and FMA (the same
// passes in ray_walk_avx2.cpp; the square walk there in float, 8 to a vector), trace_naive's hits
// bit for bit, as the scalar walk (ray_walk_exact.cpp), which every other CPU takes. This file also
// holds what both vector paths share: the square tables (build_squares) and the driver
// (trace_rays_simd).
//
// Two passes, in turn, until every ray of a chunk is resolved:
//
// A. The square walk (square_pass), in conservative arithmetic of its own: it finds a time
//    t_safe such that every cell trace_naive's DDA leaves before t_safe is one its first
//    test (cell_below) rejects. Its tables (ExactTracer::square_code_): for k = 1 .. K, an
//    upper bound M (one byte: one of 256 heights) of the cells' corner maxima over every
//    n x n square of cells, n = 2^k, at every first cell (i, j) of the tile, wrapped; levels
//    k >= 3 keep one entry per d x d first cells (d = 2^(k - 2): SquareLayout), the bound of
//    their union, a square of n + d - 1 cells, and so of each (2.33 bytes per texel in all).
//    A step from
//    time t: g = floor(x(t) + sx/2) (and the same in y) is the ray's column, or the one behind it
//    where the ray lies in the first half of its cell; the square's columns run from g - 1 (sx > 0:
//    [g - 1, g - 1 + n)) or from g + 1 back (sx < 0: [g + 2 - n, g + 1]), so they hold the DDA's
//    column at any time from t on until the ray crosses the square's far line, whichever side of a
//    line rounding puts the DDA's cell, and the far line is half a cell or more ahead of the ray
//    (every step moves on). Its crossing time te (the lower of the two far lines' and
//    tau_max) is computed with trace_naive's own formula, (line - X0) / dX as (line - X0)
//    * inv_dX, so a DDA cell beyond a far line is entered, hence left, no earlier than te
//    (the formula is monotone in the line): every cell the DDA leaves in [t, te) lies in the
//    square. When the ray at te lies above the square's maximum, zt - te vz > s (M - b),
//    each of them is one cell_below rejects by its own test (the same expressions, monotone
//    in the time and in the corner maximum): t moves to te, and the next square is twice as
//    wide (up to 2^K). Otherwise t moves on to the time the ray comes down to s (M - b),
//    where the ray provably lies above it there (that time is then before te), and the next
//    square is half as wide; a failure at n = 2 ends the walk: t_safe = t. So every cell the
//    DDA leaves before t_safe is rejected; where te reaches tau_max every cell is (the DDA
//    stops in the cell it leaves at tau_max), and the ray's answer is tau_max.
// B. The DDA (dda_pass) from the DDA's cell at t_safe (the last cell entered strictly before
//    t_safe, found with trace_naive's entry times from a guess, as walk_start_below does; the
//    cells before it were left before t_safe: rejected by cell_below), with trace_naive's
//    exit times, cell_below's test and solve_patch's closed form, operation for operation in
//    double, for up to kDdaCells cells. A ray it resolves (a hit, or tau_max) is done; any
//    other goes back to pass A from the exit time of the last cell walked (rejected, as were
//    all before it). Rare lanes take scalar code: a cell entry that is not found within one
//    cell of the guess (DdaAxis::last_entered), and the bisection of cell_solver::first_root.
//
// Why vectors: the scalar walk is bound by its chains of dependent steps and branches on
// each ray's data (ray_walk_exact.cpp's notes); here 4 independent vectors of 8 rays are
// stepped in turn, without a branch on any ray's data, and a lane whose ray is done takes
// the next ray of the chunk. The tables' and texels' reads are prefetched a half-step (pass A)
// or a step (pass B) before the gathers that use them, so that misses overlap. Measurements
// against the scalar walk and Embree, and what was tried and dropped: docs/internals/tracers.md.
// GCC 12's AVX-512 headers start some conversions from _mm512_undefined_*(), which its
// -Wmaybe-uninitialized reports once they are inlined here (a known false positive).
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#include <immintrin.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

#include "harness/truth/cell_solver.h"
#include "harness/truth/ray_walk_vector.h"

#define PXH_AVX512 __attribute__((target("avx512f,avx512dq,avx2")))
#define PXH_AVX512_INLINE __attribute__((target("avx512f,avx512dq,avx2"), always_inline)) inline

namespace pxh {

namespace {

using namespace vector_walk;

// Vectors of 8 rays stepped in turn by the square walk (1 and 2 slower, 3 and 6 no faster).
constexpr int kLaneSets = 4;
// Groups of 8 rays pass B walks in turn (1: 5-10% slower at 512 x 512, 60 deg; 3 and 4 as 2).
constexpr int kDdaGroups = 2;
// Rays per work chunk (tbb).
constexpr size_t kChunk = 1024;

PXH_AVX512_INLINE __m512d floor_pd(__m512d x) {
    return _mm512_roundscale_pd(x, _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC);
}
// a - n floor((a + 1/2) / n) for integers a (exact: (a + 1/2) / n is never within rounding of
// an integer), in [0, n).
PXH_AVX512_INLINE __m512d wrap_pd(__m512d a, __m512d n, __m512d inv_n) {
    const __m512d half = _mm512_set1_pd(0.5);
    return _mm512_sub_pd(a,
                         _mm512_mul_pd(n, floor_pd(_mm512_mul_pd(_mm512_add_pd(a, half), inv_n))));
}
// std::min(a, b) and std::max(a, b), operand for operand: (b < a) ? b : a, (a < b) ? b : a.
PXH_AVX512_INLINE __m512d std_min(__m512d a, __m512d b) {
    return _mm512_mask_blend_pd(_mm512_cmp_pd_mask(b, a, _CMP_LT_OQ), a, b);
}
PXH_AVX512_INLINE __m512d std_max(__m512d a, __m512d b) {
    return _mm512_mask_blend_pd(_mm512_cmp_pd_mask(a, b, _CMP_LT_OQ), a, b);
}
PXH_AVX512_INLINE __m256 std_max_ps(__m256 a, __m256 b) {
    return _mm256_blendv_ps(a, b, _mm256_cmp_ps(a, b, _CMP_LT_OQ));
}

// ---- Pass A: the square walk ----

struct SquareLanes {
    __m512d X0, Y0, dX, dY, iX, iY, vz, ivz, tm, t, k;
    __m512d te;    // the time the ray leaves the step's square (square_read)
    __m512i slot;  // the ray's place in the pass's list
    __mmask8 active;
};

struct SquareConsts {
    __m512d W, H, iW, iH, zt, s, b, K, lo, step;
    __m512d inv_spacing, cols, base;  // SquareLayout's, by level
    const uint8_t* squares;
};

// One step of every active lane, in two halves (square_read, then square_step): the first
// finds the square and prefetches each lane's table entry, the second reads them, so that the
// lane sets' reads of the tables are all under way before the first is used.
PXH_AVX512_INLINE __m512i square_read(const SquareConsts& c, SquareLanes& L) {
    const __m512d zero = _mm512_setzero_pd(), one = _mm512_set1_pd(1), two = _mm512_set1_pd(2);
    const __m512d half = _mm512_set1_pd(0.5), mhalf = _mm512_set1_pd(-0.5);
    const __m512d inf = _mm512_set1_pd(std::numeric_limits<double>::infinity());
    const __m512d t = L.t;
    const __m512d x = _mm512_add_pd(L.X0, _mm512_mul_pd(t, L.dX));
    const __m512d y = _mm512_add_pd(L.Y0, _mm512_mul_pd(t, L.dY));
    const __mmask8 px = _mm512_cmp_pd_mask(L.dX, zero, _CMP_GT_OQ);
    const __mmask8 py = _mm512_cmp_pd_mask(L.dY, zero, _CMP_GT_OQ);
    const __mmask8 mx = _mm512_cmp_pd_mask(L.dX, zero, _CMP_NEQ_OQ);
    const __mmask8 my = _mm512_cmp_pd_mask(L.dY, zero, _CMP_NEQ_OQ);
    const __m512d gx = floor_pd(_mm512_add_pd(x, _mm512_mask_blend_pd(px, mhalf, half)));
    const __m512d gy = floor_pd(_mm512_add_pd(y, _mm512_mask_blend_pd(py, mhalf, half)));
    const __m512d n = _mm512_scalef_pd(one, L.k);
    // The square's first column (row) and far line.
    const __m512d ax =
        _mm512_mask_blend_pd(px, _mm512_sub_pd(_mm512_add_pd(gx, two), n), _mm512_sub_pd(gx, one));
    const __m512d ay =
        _mm512_mask_blend_pd(py, _mm512_sub_pd(_mm512_add_pd(gy, two), n), _mm512_sub_pd(gy, one));
    const __m512d lx = _mm512_mask_add_pd(ax, px, ax, n), ly = _mm512_mask_add_pd(ay, py, ay, n);
    const __m512d tx = _mm512_mask_mul_pd(inf, mx, _mm512_sub_pd(lx, L.X0), L.iX);
    const __m512d ty = _mm512_mask_mul_pd(inf, my, _mm512_sub_pd(ly, L.Y0), L.iY);
    const __m512d te = _mm512_min_pd(_mm512_min_pd(tx, ty), L.tm);
    // The square's maximum, from level k at its wrapped first cell.
    const __m512i level = _mm512_cvttpd_epi64(L.k);
    const __m512d inv_d = _mm512_permutexvar_pd(level, c.inv_spacing);
    const __m512d at = _mm512_add_pd(
        _mm512_add_pd(_mm512_permutexvar_pd(level, c.base),
                      _mm512_mul_pd(floor_pd(_mm512_mul_pd(wrap_pd(ay, c.H, c.iH), inv_d)),
                                    _mm512_permutexvar_pd(level, c.cols))),
        floor_pd(_mm512_mul_pd(wrap_pd(ax, c.W, c.iW), inv_d)));
    L.te = te;
    // Inactive lanes may hold any index: a prefetch does not fault, the gather skips them.
    const __m512i entry = _mm512_cvttpd_epi64(at);
    alignas(64) int64_t a[8];
    _mm512_store_si512(a, entry);
    for (int q = 0; q < 8; ++q)
        _mm_prefetch(reinterpret_cast<const char*>(c.squares + a[q]), _MM_HINT_T0);
    return entry;
}
// The step's second half, from the square's entry in the tables (square_read's): returns the
// lanes whose walk ended (t is their t_safe).
PXH_AVX512_INLINE __mmask8 square_step(const SquareConsts& c, SquareLanes& L, __m512i at) {
    const __m512d zero = _mm512_setzero_pd(), one = _mm512_set1_pd(1);
    const __m512d t = L.t, te = L.te;
    const __m256i code = _mm256_and_si256(
        _mm512_mask_i64gather_epi32(_mm256_setzero_si256(), L.active, at, c.squares, 1),
        _mm256_set1_epi32(0xff));
    const __m512d M = _mm512_add_pd(c.lo, _mm512_mul_pd(_mm512_cvtepi32_pd(code), c.step));
    const __m512d zM = _mm512_mul_pd(c.s, _mm512_sub_pd(M, c.b));
    const __mmask8 clear = _mm512_mask_cmp_pd_mask(
        L.active, _mm512_sub_pd(c.zt, _mm512_mul_pd(te, L.vz)), zM, _CMP_GT_OQ);
    const __mmask8 fail = L.active & __mmask8(~clear);
    // A failure: on to where the ray comes down to zM, if it provably lies above zM there.
    const __m512d ta = _mm512_min_pd(_mm512_mul_pd(_mm512_sub_pd(c.zt, zM), L.ivz), te);
    const __mmask8 on = _mm512_mask_cmp_pd_mask(fail, _mm512_sub_pd(c.zt, _mm512_mul_pd(ta, L.vz)),
                                                zM, _CMP_GT_OQ) &
                        _mm512_cmp_pd_mask(ta, t, _CMP_GT_OQ);
    L.t = _mm512_mask_mov_pd(_mm512_mask_mov_pd(t, clear, te), on, ta);
    const __m512d k =
        _mm512_mask_add_pd(L.k, clear & _mm512_cmp_pd_mask(L.k, c.K, _CMP_LT_OQ), L.k, one);
    L.k = _mm512_mask_sub_pd(k, fail, k, one);
    return (fail & _mm512_cmp_pd_mask(L.k, zero, _CMP_EQ_OQ)) |
           (clear & _mm512_cmp_pd_mask(te, L.tm, _CMP_GE_OQ));
}

// The next ray of `col` into each lane of m, in lane order.
PXH_AVX512_INLINE void take(__m512d& x, __mmask8 m, const double* col) {
    x = _mm512_mask_expand_pd(x, m, _mm512_loadu_pd(col));
}

// Rays 0 .. n of `rays`, starting at times t0[q]: t_safe[q], and bottom[q] = 1 where every
// cell down to the slab bottom is rejected (the ray's answer is tau_max).
PXH_AVX512 void square_pass(const SquareScene& sc, const RayColumns& rays, const double* t0, int n,
                            double* t_safe, uint8_t* bottom) {
    SquareConsts c;
    c.W = _mm512_set1_pd(sc.W);
    c.H = _mm512_set1_pd(sc.H);
    c.iW = _mm512_set1_pd(1.0 / sc.W);
    c.iH = _mm512_set1_pd(1.0 / sc.H);
    c.inv_spacing = _mm512_load_pd(sc.inv_spacing);
    c.cols = _mm512_load_pd(sc.cols);
    c.base = _mm512_load_pd(sc.base);
    c.zt = _mm512_set1_pd(sc.zt);
    c.s = _mm512_set1_pd(sc.s);
    c.b = _mm512_set1_pd(sc.b);
    c.K = _mm512_set1_pd(sc.levels);
    c.squares = sc.squares;
    c.lo = _mm512_set1_pd(sc.lo);
    c.step = _mm512_set1_pd(sc.step);
    const double k0 = std::min(kSquareStart, sc.levels);
    SquareLanes lanes[kLaneSets];
    for (SquareLanes& L : lanes) {
        L.X0 = L.Y0 = L.dX = L.dY = L.iX = L.iY = L.tm = L.t = _mm512_setzero_pd();
        L.vz = L.ivz = L.k = _mm512_set1_pd(1);
        L.slot = _mm512_setzero_si512();
        L.active = 0;
    }
    int next = 0;
    for (;;) {
        bool any = false;
        for (SquareLanes& L : lanes) {
            // Free lanes take the next rays, in order (loads of 8, spread over the free lanes).
            unsigned free = __mmask8(~L.active);
            if (free && next < n) {
                while (__builtin_popcount(free) > n - next)
                    free &= ~(1u << (31 - __builtin_clz(free)));
                const __mmask8 m = __mmask8(free);
                take(L.X0, m, rays.X0.data() + next);
                take(L.Y0, m, rays.Y0.data() + next);
                take(L.dX, m, rays.dX.data() + next);
                take(L.dY, m, rays.dY.data() + next);
                take(L.iX, m, rays.iX.data() + next);
                take(L.iY, m, rays.iY.data() + next);
                take(L.vz, m, rays.vz.data() + next);
                take(L.ivz, m, rays.ivz.data() + next);
                take(L.tm, m, rays.tm.data() + next);
                take(L.t, m, t0 + next);
                L.k = _mm512_mask_mov_pd(L.k, m, _mm512_set1_pd(k0));
                L.slot = _mm512_mask_expand_epi64(
                    L.slot, m,
                    _mm512_add_epi64(_mm512_set1_epi64(next),
                                     _mm512_set_epi64(7, 6, 5, 4, 3, 2, 1, 0)));
                L.active |= m;
                next += __builtin_popcount(free);
            }
            any |= L.active != 0;
        }
        if (!any) return;
        __mmask8 done[kLaneSets];
        __m512i at[kLaneSets];
        for (int v = 0; v < kLaneSets; ++v) at[v] = square_read(c, lanes[v]);
        for (int v = 0; v < kLaneSets; ++v) done[v] = square_step(c, lanes[v], at[v]);
        for (int v = 0; v < kLaneSets; ++v) {
            if (!done[v]) continue;
            SquareLanes& L = lanes[v];
            // Scalar stores: a scatter of the one or two lanes done costs more (measured).
            const __mmask8 at_bottom = done[v] & _mm512_cmp_pd_mask(L.t, L.tm, _CMP_GE_OQ);
            alignas(64) int64_t slot[8];
            alignas(64) double t[8];
            _mm512_store_si512(slot, L.slot);
            _mm512_store_pd(t, L.t);
            for (unsigned m = done[v]; m; m &= m - 1) {
                const int q = __builtin_ctz(m);
                t_safe[slot[q]] = t[q];
                bottom[slot[q]] = uint8_t((at_bottom >> q) & 1);
            }
            L.active &= __mmask8(~done[v]);
        }
    }
}

// ---- Pass B: the DDA ----

// DdaAxis::last_entered(floor(O), floor(O + t d), t, false) for the moving lanes `mv` (step
// +1 where `p`), moving the guess by one cell each way at most; lanes that need more are
// added to `slow` (their answer is then computed in scalar code).
PXH_AVX512_INLINE __mmask8 entered(__m512d k, __m512d O, __m512d inv, __mmask8 p, __m512d t) {
    const __m512d line = _mm512_mask_blend_pd(p, _mm512_add_pd(k, _mm512_set1_pd(1)), k);
    return _mm512_cmp_pd_mask(_mm512_mul_pd(_mm512_sub_pd(line, O), inv), t, _CMP_LT_OQ);
}
PXH_AVX512_INLINE __m512d last_entered(__m512d O, __m512d d, __m512d inv, __mmask8 p, __mmask8 mv,
                                       __m512d step, __m512d t, __mmask8& slow) {
    const __m512d c = floor_pd(O);
    __m512d g = floor_pd(_mm512_add_pd(O, _mm512_mul_pd(t, d)));
    const __mmask8 behind = (p & _mm512_cmp_pd_mask(g, c, _CMP_LT_OQ)) |
                            (__mmask8(~p) & _mm512_cmp_pd_mask(g, c, _CMP_GT_OQ));
    g = _mm512_mask_mov_pd(g, behind, c);
    const __mmask8 back =
        _mm512_cmp_pd_mask(g, c, _CMP_NEQ_OQ) & __mmask8(~entered(g, O, inv, p, t));
    g = _mm512_mask_sub_pd(g, back, g, step);
    slow |= mv & _mm512_cmp_pd_mask(g, c, _CMP_NEQ_OQ) & __mmask8(~entered(g, O, inv, p, t));
    const __mmask8 fwd = entered(_mm512_add_pd(g, step), O, inv, p, t);
    g = _mm512_mask_add_pd(g, fwd, g, step);
    slow |= mv & entered(_mm512_add_pd(g, step), O, inv, p, t);
    return _mm512_mask_mov_pd(c, mv, g);
}

// One pass B group: 8 rays (lanes beyond m repeat the last), their walks' state.
struct DdaGroup {
    __m512d X0, Y0, dX, dY, iX, iY, vz, tm, sx, sy, ci, cj, li, lj, xl, yl, ex, ey;
    __m512d counted, answer, last_exit;
    __m512i walked;
    __m256i a00;  // cell (li, lj)'s first corner in the texels (dda_fetch)
    __mmask8 px, py, mx, my, active, done;
    int m, steps;
    alignas(32) int32_t idx[8];
};

// Pass B's constants, in each of its functions.
#define PXH_DDA_CONSTS                                                                            \
    const __m512d zero = _mm512_setzero_pd(), one = _mm512_set1_pd(1), mone = _mm512_set1_pd(-1); \
    const __m512d inf = _mm512_set1_pd(std::numeric_limits<double>::infinity());                  \
    const __m512d W = _mm512_set1_pd(sc.W), H = _mm512_set1_pd(sc.H);                             \
    const __m512d iW = _mm512_set1_pd(1.0 / sc.W), iH = _mm512_set1_pd(1.0 / sc.H);               \
    const __m512d zt = _mm512_set1_pd(sc.zt), s = _mm512_set1_pd(sc.s), b = _mm512_set1_pd(sc.b); \
    const __m512d neg_s = _mm512_set1_pd(-sc.s);                                                  \
    const __m512d sign = _mm512_castsi512_pd(_mm512_set1_epi64(int64_t(0x8000000000000000ULL)));  \
    const __m512d magnitude = _mm512_castsi512_pd(_mm512_set1_epi64(0x7fffffffffffffffLL));       \
    const __m256i up = _mm256_set1_epi32(sc.up);                                                  \
    const float* tex = sc.texels;

// Where cell (li, lj)'s corners lie in the texels, and a prefetch of its two rows' corner pairs
// for the next step (a gather holds up the instructions after it until memory answers, a
// prefetch does not, so every group's requests are under way at once).
PXH_AVX512_INLINE void dda_fetch(DdaGroup& G, const SquareScene& sc) {
    G.a00 =
        _mm256_add_epi32(_mm256_mullo_epi32(_mm512_cvttpd_epi32(G.lj), _mm256_set1_epi32(sc.up)),
                         _mm512_cvttpd_epi32(G.li));
    alignas(32) int32_t a[8];
    _mm256_store_si256(reinterpret_cast<__m256i*>(a), G.a00);
    for (int q = 0; q < 8; ++q) {
        _mm_prefetch(reinterpret_cast<const char*>(sc.texels + a[q]), _MM_HINT_T0);
        _mm_prefetch(reinterpret_cast<const char*>(sc.texels + sc.up + a[q]), _MM_HINT_T0);
    }
}

// The group of rays list[g0 ..], from their t_safe: the DDA's cell at t_safe, its exits.
PXH_AVX512_INLINE void dda_start(DdaGroup& G, const SquareScene& sc, const RayColumns& rays,
                                 const int* list, const double* t_safe, int g0, int n) {
    PXH_DDA_CONSTS(void)
    neg_s, (void)sign, (void)magnitude, (void)up, (void)tex, (void)zt, (void)s, (void)b;
    const int m = G.m = std::min(8, n - g0);
    const __mmask8 valid = __mmask8((1u << m) - 1);
    for (int q = 0; q < 8; ++q) G.idx[q] = list[g0 + std::min(q, m - 1)];
    const __m256i vi = _mm256_load_si256(reinterpret_cast<const __m256i*>(G.idx));
    G.X0 = _mm512_i32gather_pd(vi, rays.X0.data(), 8);
    G.Y0 = _mm512_i32gather_pd(vi, rays.Y0.data(), 8);
    G.dX = _mm512_i32gather_pd(vi, rays.dX.data(), 8);
    G.dY = _mm512_i32gather_pd(vi, rays.dY.data(), 8);
    G.iX = _mm512_i32gather_pd(vi, rays.iX.data(), 8);
    G.iY = _mm512_i32gather_pd(vi, rays.iY.data(), 8);
    G.vz = _mm512_i32gather_pd(vi, rays.vz.data(), 8);
    G.tm = _mm512_i32gather_pd(vi, rays.tm.data(), 8);
    const __m512d t = _mm512_maskz_loadu_pd(valid, t_safe + g0);
    G.counted = _mm512_i32gather_pd(vi, rays.counted.data(), 8);
    G.px = _mm512_cmp_pd_mask(G.dX, zero, _CMP_GT_OQ);
    G.py = _mm512_cmp_pd_mask(G.dY, zero, _CMP_GT_OQ);
    G.mx = _mm512_cmp_pd_mask(G.dX, zero, _CMP_NEQ_OQ);
    G.my = _mm512_cmp_pd_mask(G.dY, zero, _CMP_NEQ_OQ);
    G.sx = _mm512_mask_blend_pd(G.px, mone, one);
    G.sy = _mm512_mask_blend_pd(G.py, mone, one);
    // The DDA's cell at t.
    __mmask8 slow = 0;
    G.ci = last_entered(G.X0, G.dX, G.iX, G.px, G.mx, G.sx, t, slow);
    G.cj = last_entered(G.Y0, G.dY, G.iY, G.py, G.my, G.sy, t, slow);
    slow &= valid;
    if (slow) {
        alignas(64) double a[8], c[8];
        _mm512_store_pd(a, G.ci);
        _mm512_store_pd(c, G.cj);
        for (unsigned mm = slow; mm; mm &= mm - 1) {
            const int q = __builtin_ctz(mm), r = G.idx[q];
            const double tq = t_safe[g0 + q];
            const cell_solver::DdaAxis ax{rays.X0[r], rays.iX[r], rays.dX[r] > 0 ? 1 : -1,
                                          rays.dX[r] != 0};
            const cell_solver::DdaAxis ay{rays.Y0[r], rays.iY[r], rays.dY[r] > 0 ? 1 : -1,
                                          rays.dY[r] != 0};
            const int64_t cx = int64_t(std::floor(ax.origin)), cy = int64_t(std::floor(ay.origin));
            a[q] = double(ax.moves
                              ? ax.last_entered(
                                    cx, int64_t(std::floor(ax.origin + tq * rays.dX[r])), tq, false)
                              : cx);
            c[q] = double(ay.moves
                              ? ay.last_entered(
                                    cy, int64_t(std::floor(ay.origin + tq * rays.dY[r])), tq, false)
                              : cy);
        }
        G.ci = _mm512_load_pd(a);
        G.cj = _mm512_load_pd(c);
    }
    // Tile-local cell, exit lines and exit times (walk_dda's).
    G.li = wrap_pd(G.ci, W, iW);
    G.lj = wrap_pd(G.cj, H, iH);
    G.xl = _mm512_mask_add_pd(G.ci, G.px, G.ci, one);
    G.yl = _mm512_mask_add_pd(G.cj, G.py, G.cj, one);
    G.ex = _mm512_mask_mul_pd(inf, G.mx, _mm512_sub_pd(G.xl, G.X0), G.iX);
    G.ey = _mm512_mask_mul_pd(inf, G.my, _mm512_sub_pd(G.yl, G.Y0), G.iY);
    G.active = valid;
    G.done = 0;
    G.walked = _mm512_setzero_si512();
    G.answer = zero;
    G.last_exit = t;
    G.steps = 0;
    dda_fetch(G, sc);
}

// One axis of walk_dda's step, for the lanes `m`: the cell index c and its tile-local index l
// (wrapped into [0, n)) move by `step`, the exit line el with them, and the exit time e is
// computed again from it.
PXH_AVX512_INLINE void dda_advance(__m512d& c, __m512d& l, __m512d& el, __m512d& e, __mmask8 m,
                                   __m512d step, __m512d origin, __m512d inv, __m512d n) {
    const __m512d zero = _mm512_setzero_pd();
    c = _mm512_mask_add_pd(c, m, c, step);
    l = _mm512_mask_add_pd(l, m, l, step);
    l = _mm512_mask_mov_pd(l, m & _mm512_cmp_pd_mask(l, n, _CMP_EQ_OQ), zero);
    l = _mm512_mask_mov_pd(l, m & _mm512_cmp_pd_mask(l, zero, _CMP_LT_OQ),
                           _mm512_sub_pd(n, _mm512_set1_pd(1)));
    el = _mm512_mask_add_pd(el, m, el, step);
    e = _mm512_mask_mul_pd(e, m, _mm512_sub_pd(el, origin), inv);
}

// cell_solver::first_root(c0, c1, c2, len) for the lanes `roots` (dda_step's, where the patch
// may cross the ray inside the cell): the first root in [0, len], or -1 where none is found.
PXH_AVX512_INLINE __m512d dda_roots(__m512d c0, __m512d c1, __m512d c2, __m512d len, __m512d f_end,
                                    __mmask8 roots) {
    const __m512d zero = _mm512_setzero_pd();
    const __m512d sign = _mm512_castsi512_pd(_mm512_set1_epi64(int64_t(0x8000000000000000ULL)));
    const __m512d magnitude = _mm512_castsi512_pd(_mm512_set1_epi64(0x7fffffffffffffffLL));
    __m512d best = _mm512_set1_pd(-1);
    const __m512d c2ll = _mm512_mul_pd(_mm512_mul_pd(_mm512_and_pd(c2, magnitude), len), len);
    const __m512d scale =
        _mm512_add_pd(_mm512_add_pd(_mm512_and_pd(c0, magnitude),
                                    _mm512_mul_pd(_mm512_and_pd(c1, magnitude), len)),
                      c2ll);
    const __mmask8 linear =
        roots & _mm512_cmp_pd_mask(c2ll, _mm512_mul_pd(_mm512_set1_pd(1e-14), scale), _CMP_LE_OQ);
    // consider(t): 0 <= t <= len and (best < 0 or t < best).
    __m512d cand[3];
    __mmask8 ok[3];
    const __mmask8 lin_root = linear & _mm512_cmp_pd_mask(c1, zero, _CMP_LT_OQ);
    cand[0] = _mm512_div_pd(_mm512_xor_pd(c0, sign), c1);
    ok[0] = lin_root;
    const __mmask8 quad = roots & __mmask8(~linear);
    const __m512d disc = _mm512_sub_pd(_mm512_mul_pd(c1, c1),
                                       _mm512_mul_pd(_mm512_mul_pd(_mm512_set1_pd(4), c2), c0));
    const __m512d root = _mm512_sqrt_pd(disc);
    const __m512d q = _mm512_mul_pd(
        _mm512_set1_pd(-0.5),
        _mm512_add_pd(c1, _mm512_or_pd(_mm512_and_pd(root, magnitude), _mm512_and_pd(c1, sign))));
    const __mmask8 two_roots = quad & _mm512_cmp_pd_mask(disc, zero, _CMP_GE_OQ) &
                               _mm512_cmp_pd_mask(q, zero, _CMP_NEQ_OQ);
    cand[1] = _mm512_div_pd(q, c2);
    cand[2] = _mm512_div_pd(c0, q);
    ok[1] = ok[2] = two_roots;
    for (int r = 0; r < 3; ++r) {
        const __mmask8 take = ok[r] & _mm512_cmp_pd_mask(cand[r], zero, _CMP_GE_OQ) &
                              _mm512_cmp_pd_mask(cand[r], len, _CMP_LE_OQ) &
                              (_mm512_cmp_pd_mask(best, zero, _CMP_LT_OQ) |
                               _mm512_cmp_pd_mask(cand[r], best, _CMP_LT_OQ));
        best = _mm512_mask_mov_pd(best, take, cand[r]);
    }
    // No root found but the end value proves a crossing: first_root's bisection.
    const __mmask8 bisect = roots & _mm512_cmp_pd_mask(best, zero, _CMP_LT_OQ) &
                            _mm512_cmp_pd_mask(f_end, zero, _CMP_LE_OQ);
    if (bisect) {
        alignas(64) double bq[8], a0[8], a1[8], a2[8], al[8];
        _mm512_store_pd(bq, best);
        _mm512_store_pd(a0, c0);
        _mm512_store_pd(a1, c1);
        _mm512_store_pd(a2, c2);
        _mm512_store_pd(al, len);
        for (unsigned mm = bisect; mm; mm &= mm - 1) {
            const int r = __builtin_ctz(mm);
            bq[r] = cell_solver::first_root(a0[r], a1[r], a2[r], al[r]);
        }
        best = _mm512_load_pd(bq);
    }
    return best;
}

// One cell of the DDA for every active lane (walk_dda's, cell_below's test, solve_patch).
PXH_AVX512_INLINE void dda_step(DdaGroup& G, const SquareScene& sc) {
    PXH_DDA_CONSTS(void) iW, (void)iH, (void)inf, (void)up, (void)magnitude;
    const __m512d tau_out = std_min(std_min(G.ex, G.ey), G.tm);
    const __mmask8 fresh = G.active & _mm512_cmp_pd_mask(tau_out, G.counted, _CMP_GT_OQ);
    G.walked = _mm512_mask_add_epi64(G.walked, fresh, G.walked, _mm512_set1_epi64(1));
    G.counted = _mm512_mask_mov_pd(G.counted, fresh, tau_out);
    // Each corner pair (i, i + 1) of a row as one 8-byte element (two gathers, not four:
    // measured faster), prefetched a step ahead (dda_fetch).
    const __m512i row0 = _mm512_i32gather_epi64(G.a00, tex, 4);
    const __m512i row1 = _mm512_i32gather_epi64(G.a00, tex + sc.up, 4);
    const __m256 f00 = _mm256_castsi256_ps(_mm512_cvtepi64_epi32(row0));
    const __m256 f10 = _mm256_castsi256_ps(_mm512_cvtepi64_epi32(_mm512_srli_epi64(row0, 32)));
    const __m256 f01 = _mm256_castsi256_ps(_mm512_cvtepi64_epi32(row1));
    const __m256 f11 = _mm256_castsi256_ps(_mm512_cvtepi64_epi32(_mm512_srli_epi64(row1, 32)));
    // cell_below.
    const __m256 top = std_max_ps(std_max_ps(f00, f10), std_max_ps(f01, f11));
    const __m512d z_top = _mm512_mul_pd(s, _mm512_sub_pd(_mm512_cvtps_pd(top), b));
    const __m512d z_ray = _mm512_sub_pd(zt, _mm512_mul_pd(tau_out, G.vz));
    const __mmask8 solve = G.active & __mmask8(~_mm512_cmp_pd_mask(z_ray, z_top, _CMP_GT_OQ));
    __mmask8 hit = 0;
    __m512d t_hit = zero;
    if (solve) {
        // solve_patch_inline, operation for operation.
        __m512d tin = zero;
        const __m512d ex_in = _mm512_mul_pd(
            _mm512_sub_pd(_mm512_mask_blend_pd(G.px, _mm512_add_pd(G.ci, one), G.ci), G.X0), G.iX);
        tin = _mm512_mask_mov_pd(tin, G.mx, std_max(tin, ex_in));
        const __m512d ey_in = _mm512_mul_pd(
            _mm512_sub_pd(_mm512_mask_blend_pd(G.py, _mm512_add_pd(G.cj, one), G.cj), G.Y0), G.iY);
        tin = _mm512_mask_mov_pd(tin, G.my, std_max(tin, ey_in));
        const __m512d h00 = _mm512_cvtps_pd(f00), h10 = _mm512_cvtps_pd(f10);
        const __m512d h01 = _mm512_cvtps_pd(f01), h11 = _mm512_cvtps_pd(f11);
        const __m512d fx0 = _mm512_sub_pd(_mm512_add_pd(G.X0, _mm512_mul_pd(tin, G.dX)), G.ci);
        const __m512d fy0 = _mm512_sub_pd(_mm512_add_pd(G.Y0, _mm512_mul_pd(tin, G.dY)), G.cj);
        const __m512d A = _mm512_sub_pd(h10, h00), B = _mm512_sub_pd(h01, h00);
        const __m512d C = _mm512_add_pd(_mm512_sub_pd(_mm512_sub_pd(h00, h10), h01), h11);
        const __m512d h0 = _mm512_add_pd(
            _mm512_add_pd(_mm512_add_pd(h00, _mm512_mul_pd(A, fx0)), _mm512_mul_pd(B, fy0)),
            _mm512_mul_pd(_mm512_mul_pd(C, fx0), fy0));
        const __m512d h1 = _mm512_add_pd(
            _mm512_add_pd(_mm512_mul_pd(A, G.dX), _mm512_mul_pd(B, G.dY)),
            _mm512_mul_pd(C, _mm512_add_pd(_mm512_mul_pd(fx0, G.dY), _mm512_mul_pd(fy0, G.dX))));
        const __m512d h2 = _mm512_mul_pd(_mm512_mul_pd(C, G.dX), G.dY);
        const __m512d c0 = _mm512_sub_pd(_mm512_sub_pd(zt, _mm512_mul_pd(tin, G.vz)),
                                         _mm512_mul_pd(s, _mm512_sub_pd(h0, b)));
        const __mmask8 at_entry = solve & _mm512_cmp_pd_mask(c0, zero, _CMP_LE_OQ);
        // cell_solver::first_root(c0, c1, c2, len).
        const __m512d c1 = _mm512_sub_pd(_mm512_xor_pd(G.vz, sign), _mm512_mul_pd(s, h1));
        const __m512d c2 = _mm512_mul_pd(neg_s, h2);
        const __m512d len = _mm512_sub_pd(tau_out, tin);
        const __m512d f_end =
            _mm512_add_pd(c0, _mm512_mul_pd(_mm512_add_pd(c1, _mm512_mul_pd(c2, len)), len));
        const __m512d slope_end =
            _mm512_add_pd(c1, _mm512_mul_pd(_mm512_mul_pd(_mm512_set1_pd(2), c2), len));
        const __mmask8 clears =
            _mm512_cmp_pd_mask(f_end, zero, _CMP_GT_OQ) &
            (_mm512_cmp_pd_mask(c2, zero, _CMP_LE_OQ) | _mm512_cmp_pd_mask(c1, zero, _CMP_GE_OQ) |
             _mm512_cmp_pd_mask(slope_end, zero, _CMP_LE_OQ));
        const __mmask8 roots = solve & __mmask8(~at_entry) & __mmask8(~clears);
        __m512d best = mone;
        if (roots) best = dda_roots(c0, c1, c2, len, f_end, roots);
        const __mmask8 found = roots & _mm512_cmp_pd_mask(best, zero, _CMP_GE_OQ);
        t_hit = _mm512_mask_mov_pd(t_hit, found, _mm512_add_pd(tin, best));
        t_hit = _mm512_mask_mov_pd(t_hit, at_entry, tin);
        hit = found | at_entry;
    }
    G.answer = _mm512_mask_mov_pd(G.answer, hit, t_hit);
    const __mmask8 at_bottom =
        G.active & __mmask8(~hit) & _mm512_cmp_pd_mask(tau_out, G.tm, _CMP_GE_OQ);
    G.answer = _mm512_mask_mov_pd(G.answer, at_bottom, G.tm);
    G.done |= hit | at_bottom;
    G.active &= __mmask8(~(hit | at_bottom));
    if (!G.active) return;
    // The next cell: x on G.ex <= G.ey (walk_dda's step, tile-local indices wrapped).
    G.last_exit = _mm512_mask_mov_pd(G.last_exit, G.active, tau_out);
    const __mmask8 xs = G.active & _mm512_cmp_pd_mask(G.ex, G.ey, _CMP_LE_OQ);
    const __mmask8 ys = G.active & __mmask8(~xs);
    dda_advance(G.ci, G.li, G.xl, G.ex, xs, G.sx, G.X0, G.iX, W);
    dda_advance(G.cj, G.lj, G.yl, G.ey, ys, G.sy, G.Y0, G.iY, H);
    if (++G.steps == kDdaCells) {  // resumed by pass A
        G.active = 0;
        return;
    }
    dda_fetch(G, sc);
}

// The group's answers.
PXH_AVX512_INLINE void dda_finish(DdaGroup& G, int g0, double* out_t, uint8_t* resolved,
                                  RayColumns& rays) {
    const int m = G.m;
    // Not resolved: resume pass A from the last exit (every cell walked was rejected).
    const __mmask8 open = __mmask8(((1u << m) - 1) & ~unsigned(G.done));
    G.answer = _mm512_mask_mov_pd(G.answer, open, G.last_exit);
    alignas(64) double ans[8], upto[8];
    alignas(64) int64_t cnt[8];
    _mm512_store_pd(ans, G.answer);
    _mm512_store_pd(upto, G.counted);
    _mm512_store_si512(cnt, G.walked);
    for (int q = 0; q < m; ++q) {
        out_t[g0 + q] = ans[q];
        resolved[g0 + q] = (G.done >> q) & 1;
        rays.cells[G.idx[q]] += int(cnt[q]);
        rays.counted[G.idx[q]] = upto[q];
    }
}

// Rays list[0 .. n) of `rays` from their t_safe[q]: out_t[q] and resolved[q] (1: the answer,
// a hit or tau_max; 0: not resolved in kDdaCells cells, out_t[q] the time to resume pass A
// from); rays.cells counts the cells walked, each once: a cell counts where it is left after
// rays.counted, the exit of the last cell counted (a ray resumed from pass A may walk its last
// cell again). kDdaGroups groups of 8 rays are walked in turn (their chains overlap).
PXH_AVX512 void dda_pass(const SquareScene& sc, RayColumns& rays, const int* list,
                         const double* t_safe, int n, double* out_t, uint8_t* resolved) {
    for (int g0 = 0; g0 < n; g0 += 8 * kDdaGroups) {
        DdaGroup groups[kDdaGroups];
        const int count = std::min(kDdaGroups, (n - g0 + 7) / 8);
        for (int k = 0; k < count; ++k) dda_start(groups[k], sc, rays, list, t_safe, g0 + 8 * k, n);
        for (bool any = true; any;) {
            any = false;
            for (int k = 0; k < count; ++k)
                if (groups[k].active) {
                    dda_step(groups[k], sc);
                    any |= groups[k].active != 0;
                }
        }
        for (int k = 0; k < count; ++k) dda_finish(groups[k], g0 + 8 * k, out_t, resolved, rays);
    }
}

// A chunk's work arrays (trace_rays_simd), one set per thread, kept from chunk to chunk.
// The rays of a pass A are cols' first ones (from times t0), those it hands to pass B
// list_b's (from t_b); those pass B leaves open are copied to the first places of next, which
// then takes cols' place.
struct ChunkScratch {
    RayColumns cols, next;
    std::vector<int> where, list_b, cells;
    std::vector<double> ex, ey, t0, t_safe, t_b, answer;
    std::vector<uint8_t> bottom, resolved;
    void resize(size_t m) {
        if (where.size() >= m) return;
        cols.resize(m);
        next.resize(m);
        for (auto* v : {&where, &list_b, &cells}) v->resize(m);
        for (auto* v : {&ex, &ey, &t_safe, &t_b, &answer}) v->resize(m);
        t0.resize(m + 8);
        bottom.resize(m);
        resolved.resize(m);
    }
};

static_assert(sizeof(Vec2d) == 2 * sizeof(double) && sizeof(Vec3d) == 3 * sizeof(double));

// The rays of the view's samples k0 + where[p], p < n, into cols at p: make_ray_unchecked's
// arithmetic, operation for operation (and ivz = 1 / vz).
PXH_AVX512 void make_rays(const View& view, size_t k0, const int* where, int n,
                          const SquareScene& sc, RayColumns& c, double* ex_out, double* ey_out) {
    const __m512d zero = _mm512_setzero_pd(), one = _mm512_set1_pd(1);
    const __m512d W = _mm512_set1_pd(sc.W), H = _mm512_set1_pd(sc.H), half = _mm512_set1_pd(0.5);
    const __m512d zt = _mm512_set1_pd(sc.zt), s = _mm512_set1_pd(sc.s);
    const __m512d sign = _mm512_castsi512_pd(_mm512_set1_epi64(int64_t(0x8000000000000000ULL)));
    const double* P = &view.P[0].x;
    const double* V = &view.V[0].x;
    for (int p = 0; p < n; p += 8) {
        const __mmask8 m = n - p >= 8 ? __mmask8(0xff) : __mmask8((1u << (n - p)) - 1);
        const __m512i k = _mm512_add_epi64(_mm512_set1_epi64(int64_t(k0)),
                                           _mm512_cvtepi32_epi64(_mm512_castsi512_si256(
                                               _mm512_maskz_loadu_epi32(__mmask16(m), where + p))));
        const __m512i kp = _mm512_add_epi64(k, k);
        const __m512d Px = _mm512_mask_i64gather_pd(zero, m, kp, P, 8);
        const __m512d Py = _mm512_mask_i64gather_pd(zero, m, kp, P + 1, 8);
        __m512d Vx, Vy, Vz;
        if (view.parallel) {
            Vx = _mm512_set1_pd(V[0]);
            Vy = _mm512_set1_pd(V[1]);
            Vz = _mm512_set1_pd(V[2]);
        } else {
            const __m512i kv = _mm512_add_epi64(kp, k);
            Vx = _mm512_mask_i64gather_pd(zero, m, kv, V, 8);
            Vy = _mm512_mask_i64gather_pd(zero, m, kv, V + 1, 8);
            Vz = _mm512_mask_i64gather_pd(one, m, kv, V + 2, 8);
        }
        const __m512d ex = _mm512_add_pd(Px, _mm512_mul_pd(_mm512_div_pd(Vx, Vz), zt));
        const __m512d ey = _mm512_add_pd(Py, _mm512_mul_pd(_mm512_div_pd(Vy, Vz), zt));
        const __m512d dX = _mm512_mul_pd(_mm512_xor_pd(Vx, sign), W);
        const __m512d dY = _mm512_mul_pd(_mm512_xor_pd(Vy, sign), H);
        _mm512_mask_storeu_pd(ex_out + p, m, ex);
        _mm512_mask_storeu_pd(ey_out + p, m, ey);
        _mm512_mask_storeu_pd(c.X0.data() + p, m, _mm512_sub_pd(_mm512_mul_pd(ex, W), half));
        _mm512_mask_storeu_pd(c.Y0.data() + p, m, _mm512_sub_pd(_mm512_mul_pd(ey, H), half));
        _mm512_mask_storeu_pd(c.dX.data() + p, m, dX);
        _mm512_mask_storeu_pd(c.dY.data() + p, m, dY);
        _mm512_mask_storeu_pd(
            c.iX.data() + p, m,
            _mm512_maskz_div_pd(_mm512_cmp_pd_mask(dX, zero, _CMP_NEQ_OQ), one, dX));
        _mm512_mask_storeu_pd(
            c.iY.data() + p, m,
            _mm512_maskz_div_pd(_mm512_cmp_pd_mask(dY, zero, _CMP_NEQ_OQ), one, dY));
        _mm512_mask_storeu_pd(c.vz.data() + p, m, Vz);
        _mm512_mask_storeu_pd(c.ivz.data() + p, m, _mm512_div_pd(one, Vz));
        _mm512_mask_storeu_pd(c.tm.data() + p, m, _mm512_div_pd(s, Vz));
    }
}

// Passes A and B in turn over the first `count` rays of w.cols (from w.t0) until each is
// resolved: w.answer and w.cells at each ray's id (trace_rays_simd's chunk).
[[gnu::always_inline]] inline void run_passes(ChunkScratch& w, const SquareScene& sc, int count,
                                              decltype(&square_pass) square_pass_of,
                                              decltype(&dda_pass) dda_pass_of) {
    while (count > 0) {
        RayColumns& cur = w.cols;
        square_pass_of(sc, cur, w.t0.data(), count, w.t_safe.data(), w.bottom.data());
        int nb = 0;
        for (int q = 0; q < count; ++q) {
            if (w.bottom[q]) {
                w.answer[cur.id[q]] = cur.tm[q];
                w.cells[cur.id[q]] = cur.cells[q];
            } else {
                w.list_b[nb] = q;
                w.t_b[nb++] = w.t_safe[q];
            }
        }
        dda_pass_of(sc, cur, w.list_b.data(), w.t_b.data(), nb, w.t_safe.data(), w.resolved.data());
        count = 0;
        for (int q = 0; q < nb; ++q) {
            const int r = w.list_b[q];
            if (w.resolved[q]) {
                w.answer[cur.id[r]] = w.t_safe[q];
                w.cells[cur.id[r]] = cur.cells[r];
            } else {
                w.next.copy(count, cur, r);
                w.t0[count++] = w.t_safe[q];
            }
        }
        std::swap(w.cols, w.next);
    }
}
}  // namespace

namespace vector_walk::avx512 {
PXH_AVX512 void dda_pass(const SquareScene& sc, RayColumns& rays, const int* list,
                         const double* t_safe, int n, double* out_t, uint8_t* resolved) {
    pxh::dda_pass(sc, rays, list, t_safe, n, out_t, resolved);
}
}  // namespace vector_walk::avx512

ExactTracer::RayPath ExactTracer::cpu_best_path() {
    static const RayPath best =
        __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq") ? RayPath::avx512
        : __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")       ? RayPath::avx2
                                                                                : RayPath::scalar;
    return best;
}

void ExactTracer::build_squares() const {
    // Level 1 from level 0 (the cells' corner maxima), each next one from the one before:
    // the square of side 2h at (i, j) is the four of side h at (i, j), (i + h, j), (i, j + h)
    // and (i + h, j + h), wrapped. Each maximum is then stored as its code (exact_tracer.h).
    const int W = hf_.width, H = hf_.height;
    const int K = square_levels_;  // the constructor's
    if (K == 0) return;
    const size_t WH = size_t(W) * size_t(H);
    const float* cells = level_ptr_[0];
    const float lo = *std::min_element(cells, cells + WH),
                hi = *std::max_element(cells, cells + WH);
    square_lo_ = lo;
    square_step_ = (double(hi) - double(lo)) / 255;
    auto bound = [&](int c) { return square_lo_ + double(c) * square_step_; };
    while (bound(255) < double(hi)) square_step_ = std::nextafter(square_step_, HUGE_VAL);
    auto code = [&](float m) {
        int c = square_step_ > 0 ? int(std::ceil((double(m) - square_lo_) / square_step_)) : 0;
        c = std::clamp(c, 0, 255);
        while (c > 0 && bound(c - 1) >= double(m)) --c;
        while (bound(c) < double(m)) ++c;  // ends by 255 (bound(255) >= hi)
        return uint8_t(c);
    };
    const SquareLayout layout(W, H, K);
    square_code_.assign(layout.total + 4, 0);
    std::vector<float> prev(cells, cells + WH), next(WH);
    for (int k = 1; k <= K; ++k) {
        const int h = 1 << (k - 1);
        for (int j = 0; j < H; ++j) {
            const size_t r0 = size_t(j) * W, r1 = size_t((j + h) % H) * W;
            for (int i = 0; i < W; ++i) {
                const int i1 = (i + h) % W;
                next[r0 + i] = std::max(std::max(prev[r0 + i], prev[r0 + i1]),
                                        std::max(prev[r1 + i], prev[r1 + i1]));
            }
        }
        // Entry (I, J): the maximum over its d x d first cells (wrapped).
        const int d = layout.spacing[k];
        uint8_t* q = square_code_.data() + layout.base[k];
        for (int J = 0; J < layout.rows[k]; ++J)
            for (int I = 0; I < layout.cols[k]; ++I) {
                float m = -HUGE_VALF;
                for (int b = 0; b < d; ++b) {
                    const size_t row = size_t((J * d + b) % H) * W;
                    for (int a = 0; a < d; ++a) m = std::max(m, next[row + (I * d + a) % W]);
                }
                q[size_t(J) * layout.cols[k] + I] = code(m);
            }
        prev.swap(next);
    }
}

void ExactTracer::fill_scene(vector_walk::SquareScene& sc) const {
    sc.texels = texels_.data();
    sc.up = int(texel_stride());
    sc.squares = square_code_.data();
    sc.entries = SquareLayout(hf_.width, hf_.height, square_levels_).total;
    const SquareLayout layout(hf_.width, hf_.height, square_levels_);
    for (int k = 0; k < 8; ++k) {
        sc.inv_spacing[k] = k > 0 && k <= square_levels_ ? 1.0 / layout.spacing[k] : 0;  // exact
        sc.cols[k] = layout.cols[k];
        sc.base[k] = double(layout.base[k]);
    }
    sc.lo = square_lo_;
    sc.step = square_step_;
    sc.levels = square_levels_;
    sc.W = hf_.width;
    sc.H = hf_.height;
    sc.s = s_;
    sc.b = b_;
    sc.zt = z_top();
}

void ExactTracer::trace_rays_simd(const View& view, Hits& out) const {
    const size_t n = view.size();
    out.resize_all(n);
    prepare_rays();
    SquareScene sc{};
    fill_scene(sc);
    // The path's kernels.
    auto* const make_rays_of =
        ray_path() == RayPath::avx512 ? make_rays : vector_walk::avx2::make_rays;
    auto* const square_pass_of =
        ray_path() == RayPath::avx512 ? square_pass : vector_walk::avx2::square_pass;
    auto* const dda_pass_of =
        ray_path() == RayPath::avx512 ? dda_pass : vector_walk::avx2::dda_pass;
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, kChunk), [&](const auto& range) {
        const size_t m = range.size(), k0 = range.begin();
        // Each thread's work arrays, kept from chunk to chunk.
        thread_local ChunkScratch w;
        w.resize(m);
        // A ray equal to a neighbour in the view (a perspective view's outside pixels all carry
        // the look-at ray) is traced once per run of them, by the scalar walk, as trace_rays
        // does; the others go to the passes: chunk position where[p] at p in every array.
        bool cached = false;
        Vec2d cP{};
        Vec3d cV{};
        TruthHit chit;
        int count = 0;
        for (size_t q = 0; q < m; ++q) {
            const size_t k = k0 + q;
            const Vec2d P = view.P[k];
            const Vec3d V = view.dir(k);
            if ((k > 0 && view.has_ray(k - 1, P, V)) || (k + 1 < n && view.has_ray(k + 1, P, V))) {
                if (!cached ||
                    !(cP.x == P.x && cP.y == P.y && cV.x == V.x && cV.y == V.y && cV.z == V.z)) {
                    chit = trace_ray_unchecked(P, V);
                    cached = true;
                    cP = P;
                    cV = V;
                }
                out.set(k, chit);
                continue;
            }
            w.where[count++] = int(q);
        }
        const int rays = count;
        make_rays_of(view, k0, w.where.data(), rays, sc, w.cols, w.ex.data(), w.ey.data());
        for (int p = 0; p < rays; ++p) {
            w.cols.id[p] = p;
            w.cols.cells[p] = 0;
            w.cols.counted[p] = -std::numeric_limits<double>::infinity();
            w.t0[p] = 0;
        }
        run_passes(w, sc, count, square_pass_of, dda_pass_of);
        for (int p = 0; p < rays; ++p) {
            const size_t k = k0 + size_t(w.where[p]);
            out.set(k, hit_at_tau(w.ex[p], w.ey[p], sc.zt, view.dir(k), w.answer[p], w.cells[p]));
        }
    });
}

}  // namespace pxh
