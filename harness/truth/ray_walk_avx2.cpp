// The per-ray path's kernels on CPUs with AVX2 and FMA but no AVX-512 (checked at run time:
// ExactTracer::ray_path): ray_walk_simd.cpp's two passes, operation for operation, at 4 rays
// to a vector, so trace_naive's hits bit for bit. Masks are vectors of all-ones lanes (AVX2 has
// no mask registers): m ? b : a is blendv(a, b, m), and the AVX-512 code's masked operations
// are blends of their unmasked results. The AVX-512 file describes the passes; what differs:
//   - the square's lines come from values kept per ray (sx / 2, sx, the far line's offset), and
//     its table entry is computed in 32-bit integers (one permute per layout table, a shift for
//     the spacing); the same squares and entries: integers, exact either way;
//   - each square walk step is split in two halves over all lane sets: the first prefetches each
//     lane's table entry, the second reads it; the DDA prefetches its next cell's two rows a step
//     ahead (a gather holds up the instructions after it until memory answers, a prefetch does
//     not, so every lane's request is under way at once); the reads themselves are scalar
//     loads, not gathers, and so are the DDA's rays where four are consecutive (on AMD's Zen 3,
//     quicker: docs/internals/tracers.md, "Issue 62, seventh session");
//   - a lane set takes the next rays into its free lanes by a permute from a table of the 16
//     masks (AVX-512's expand), and 8 lane sets (4 DDA groups) are stepped in turn, not 4 (2);
//   - arithmetic that the AVX-512 code does on 64-bit integers is done on 32-bit ones (indices
//     below 2^31: ExactTracer takes the scalar walk on larger fields).
// FMA is not used for arithmetic (the build does not contract: each product is rounded, as in
// trace_naive); it is part of the path's requirement as the CPUs that have AVX2 have it.
// GCC 12's gather intrinsics start from _mm256_undefined_*(), which its -Wmaybe-uninitialized
// reports once they are inlined here (a known false positive, as in ray_walk_simd.cpp).
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#include <immintrin.h>

#include <cmath>
#include <limits>

#include "harness/truth/cell_solver.h"
#include "harness/truth/ray_walk_vector.h"

#define PXH_AVX2 __attribute__((target("avx2,fma")))
#define PXH_AVX2_INLINE __attribute__((target("avx2,fma"), always_inline)) inline

namespace pxh::vector_walk::avx2 {

namespace {

// Vectors of 4 rays stepped in turn by the square walk.
constexpr int kLaneSets = 8;
// Groups of 4 rays pass B walks in turn.
constexpr int kDdaGroups = 4;

using V = __m256d;  // 4 doubles; a mask: all-ones or zero lanes

PXH_AVX2_INLINE V set1(double x) { return _mm256_set1_pd(x); }
PXH_AVX2_INLINE V add(V a, V b) { return _mm256_add_pd(a, b); }
PXH_AVX2_INLINE V sub(V a, V b) { return _mm256_sub_pd(a, b); }
PXH_AVX2_INLINE V mul(V a, V b) { return _mm256_mul_pd(a, b); }
PXH_AVX2_INLINE V div(V a, V b) { return _mm256_div_pd(a, b); }
PXH_AVX2_INLINE V and_(V a, V b) { return _mm256_and_pd(a, b); }
PXH_AVX2_INLINE V or_(V a, V b) { return _mm256_or_pd(a, b); }
PXH_AVX2_INLINE V andnot(V m, V a) { return _mm256_andnot_pd(m, a); }  // ~m & a
PXH_AVX2_INLINE V xor_(V a, V b) { return _mm256_xor_pd(a, b); }
// m ? b : a (_mm512_mask_blend_pd(m, a, b)).
PXH_AVX2_INLINE V blend(V m, V a, V b) { return _mm256_blendv_pd(a, b, m); }
PXH_AVX2_INLINE V lt(V a, V b) { return _mm256_cmp_pd(a, b, _CMP_LT_OQ); }
PXH_AVX2_INLINE V le(V a, V b) { return _mm256_cmp_pd(a, b, _CMP_LE_OQ); }
PXH_AVX2_INLINE V gt(V a, V b) { return _mm256_cmp_pd(a, b, _CMP_GT_OQ); }
PXH_AVX2_INLINE V ge(V a, V b) { return _mm256_cmp_pd(a, b, _CMP_GE_OQ); }
PXH_AVX2_INLINE V eq(V a, V b) { return _mm256_cmp_pd(a, b, _CMP_EQ_OQ); }
PXH_AVX2_INLINE V ne(V a, V b) { return _mm256_cmp_pd(a, b, _CMP_NEQ_OQ); }
PXH_AVX2_INLINE int bits(V m) { return _mm256_movemask_pd(m); }
PXH_AVX2_INLINE V lanes_mask(int m) {  // lane q all-ones where bit q of m
    const __m256i bit = _mm256_set_epi64x(8, 4, 2, 1);
    return _mm256_castsi256_pd(
        _mm256_cmpeq_epi64(_mm256_and_si256(_mm256_set1_epi64x(m), bit), bit));
}

PXH_AVX2_INLINE V floor_pd(V x) {
    return _mm256_round_pd(x, _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC);
}
// a - n floor((a + 1/2) / n) for integers a, in [0, n) (ray_walk_simd.cpp's).
PXH_AVX2_INLINE V wrap_pd(V a, V n, V inv_n) {
    return sub(a, mul(n, floor_pd(mul(add(a, set1(0.5)), inv_n))));
}
// std::min(a, b) and std::max(a, b), operand for operand: (b < a) ? b : a, (a < b) ? b : a,
// which are minpd(b, a) and maxpd(b, a) (each returns its second operand unless the first is
// strictly below, or above).
PXH_AVX2_INLINE V std_min(V a, V b) { return _mm256_min_pd(b, a); }
PXH_AVX2_INLINE V std_max(V a, V b) { return _mm256_max_pd(b, a); }
PXH_AVX2_INLINE __m128 std_max_ps(__m128 a, __m128 b) { return _mm_max_ps(b, a); }
// Integer-valued doubles (|x| < 2^31) as 32-bit integers.
PXH_AVX2_INLINE __m128i to_i32(V x) { return _mm256_cvttpd_epi32(x); }

// 2^k for integers 0 <= k < 1023.
PXH_AVX2_INLINE V pow2(__m128i k) {
    return _mm256_castsi256_pd(_mm256_slli_epi64(
        _mm256_add_epi64(_mm256_cvtepu32_epi64(k), _mm256_set1_epi64x(1023)), 52));
}
// Entry k[q] of an 8-entry table of 32-bit integers, per lane.
PXH_AVX2_INLINE __m128i lookup(__m256i table, __m128i k) {
    return _mm256_castsi256_si128(_mm256_permutevar8x32_epi32(table, _mm256_castsi128_si256(k)));
}

// ---- Pass A: the square walk ----

struct SquareLanes {
    V X0, Y0, dX, dY, iX, iY, vz, ivz, tm, t, k;
    // Per ray, from dX and dY (lanes set when they take a ray): sx / 2, the far line's offset
    // from the ray's column less sx n (fx: -1 where sx > 0, else 2), sx, and the masks sx > 0
    // and dX != 0 (the same in y).
    V hx, hy, fx, fy, sx, sy, px, py, mx, my;
    V te;  // the time the ray leaves the step's square (square_read)
    V active;
    int slot[4];  // the ray's place in the pass's list
    int active_bits;
};

struct SquareConsts {
    V W, H, iW, iH, zt, s, b, K, lo, step;
    __m256i cols, base;  // SquareLayout's by level k (entry k), as 32-bit integers
    __m128i last;        // the tables' last entry
    const uint8_t* squares;
};

// One step of every active lane, in two halves (square_read, then square_step): the first
// prefetches each lane's table entry, the second reads them, so that the lane sets' reads of
// the tables are all under way before the first is used. The
// square's first column and far line are ray_walk_simd.cpp's (sx > 0: g - 1 and g - 1 + n;
// sx < 0: g + 2 - n for both), and its table entry the same (base + J cols + I, with
// I = wrap(first column) >> max(0, k - 2), J likewise): integers, exact in either arithmetic.
PXH_AVX2_INLINE __m128i square_read(const SquareConsts& c, SquareLanes& L) {
    const V inf = set1(std::numeric_limits<double>::infinity());
    const V t = L.t;
    const V x = add(L.X0, mul(t, L.dX));
    const V y = add(L.Y0, mul(t, L.dY));
    const V gx = floor_pd(add(x, L.hx));
    const V gy = floor_pd(add(y, L.hy));
    const __m128i level = to_i32(L.k);
    const V n = pow2(level);
    // The square's far line and first column.
    const V lx = add(add(gx, L.fx), mul(L.sx, n)), ly = add(add(gy, L.fy), mul(L.sy, n));
    const V ax = sub(lx, and_(L.px, n)), ay = sub(ly, and_(L.py, n));
    const V tx = blend(L.mx, inf, mul(sub(lx, L.X0), L.iX));
    const V ty = blend(L.my, inf, mul(sub(ly, L.Y0), L.iY));
    const V te = _mm256_min_pd(_mm256_min_pd(tx, ty), L.tm);
    // The square's maximum, from level k at its wrapped first cell (every lane's entry is in
    // the tables: the index is clamped to them whatever a free lane holds).
    const __m128i shift =
        _mm_max_epi32(_mm_sub_epi32(level, _mm_set1_epi32(2)), _mm_setzero_si128());
    const __m128i I = _mm_srlv_epi32(to_i32(wrap_pd(ax, c.W, c.iW)), shift);
    const __m128i J = _mm_srlv_epi32(to_i32(wrap_pd(ay, c.H, c.iH)), shift);
    const __m128i at = _mm_min_epu32(
        _mm_add_epi32(
            _mm_add_epi32(lookup(c.base, level), _mm_mullo_epi32(J, lookup(c.cols, level))), I),
        c.last);
    L.te = te;
    alignas(16) int32_t a[4];
    _mm_store_si128(reinterpret_cast<__m128i*>(a), at);
    for (int q = 0; q < 4; ++q)
        _mm_prefetch(reinterpret_cast<const char*>(c.squares + a[q]), _MM_HINT_T0);
    return at;
}

// The step's second half, from the square's entry in the tables (square_read's): returns the
// lanes whose walk ended (t is their t_safe).
PXH_AVX2_INLINE V square_step(const SquareConsts& c, SquareLanes& L, __m128i at) {
    const V zero = _mm256_setzero_pd(), one = set1(1);
    const V t = L.t, te = L.te;
    const __m128i code = _mm_and_si128(
        _mm_i32gather_epi32(reinterpret_cast<const int*>(c.squares), at, 1), _mm_set1_epi32(0xff));
    const V M = add(c.lo, mul(_mm256_cvtepi32_pd(code), c.step));
    const V zM = mul(c.s, sub(M, c.b));
    const V clear = and_(L.active, gt(sub(c.zt, mul(te, L.vz)), zM));
    const V fail = andnot(clear, L.active);
    // A failure: on to where the ray comes down to zM, if it provably lies above zM there.
    const V ta = _mm256_min_pd(mul(sub(c.zt, zM), L.ivz), te);
    const V on = and_(and_(fail, gt(sub(c.zt, mul(ta, L.vz)), zM)), gt(ta, t));
    L.t = blend(on, blend(clear, t, te), ta);
    const V k = blend(and_(clear, lt(L.k, c.K)), L.k, add(L.k, one));
    L.k = blend(fail, k, sub(k, one));
    return or_(and_(fail, eq(L.k, zero)), and_(clear, ge(te, L.tm)));
}

// The per-ray values SquareLanes keeps from dX and dY.
PXH_AVX2_INLINE void set_signs(SquareLanes& L) {
    const V zero = _mm256_setzero_pd(), one = set1(1), mone = set1(-1);
    L.px = gt(L.dX, zero);
    L.py = gt(L.dY, zero);
    L.mx = ne(L.dX, zero);
    L.my = ne(L.dY, zero);
    L.hx = blend(L.px, set1(-0.5), set1(0.5));
    L.hy = blend(L.py, set1(-0.5), set1(0.5));
    L.fx = blend(L.px, set1(2), mone);
    L.fy = blend(L.py, set1(2), mone);
    L.sx = blend(L.px, mone, one);
    L.sy = blend(L.py, mone, one);
}

// Lane permutations of AVX-512's expand: for the free lanes f (bit q: lane q), the dword pairs
// that bring element r of a load into the r-th free lane.
struct ExpandTable {
    alignas(32) int32_t idx[16][8];
    ExpandTable() {
        for (int f = 0; f < 16; ++f) {
            int r = 0;
            for (int q = 0; q < 4; ++q) {
                const int e = (f >> q) & 1 ? r++ : q;
                idx[f][2 * q] = 2 * e;
                idx[f][2 * q + 1] = 2 * e + 1;
            }
        }
    }
};
const ExpandTable kExpand;

// The next rays of `col` into the free lanes `m` (mask), in lane order.
PXH_AVX2_INLINE void take(V& x, V m, __m256i perm, const double* col) {
    const V loaded =
        _mm256_castps_pd(_mm256_permutevar8x32_ps(_mm256_castpd_ps(_mm256_loadu_pd(col)), perm));
    x = blend(m, x, loaded);
}

}  // namespace

PXH_AVX2 void square_pass_f64(const SquareScene& sc, const RayColumns& rays, const double* t0,
                              int n, double* t_safe, uint8_t* bottom) {
    SquareConsts c;
    c.W = set1(sc.W);
    c.H = set1(sc.H);
    c.iW = set1(1.0 / sc.W);
    c.iH = set1(1.0 / sc.H);
    alignas(32) int32_t cols[8], base[8];
    for (int k = 0; k < 8; ++k) {
        cols[k] = int32_t(sc.cols[k]);  // below 2^31: ExactTracer's square_levels_
        base[k] = int32_t(sc.base[k]);
    }
    c.cols = _mm256_load_si256(reinterpret_cast<const __m256i*>(cols));
    c.base = _mm256_load_si256(reinterpret_cast<const __m256i*>(base));
    c.last = _mm_set1_epi32(int32_t(sc.entries - 1));
    c.zt = set1(sc.zt);
    c.s = set1(sc.s);
    c.b = set1(sc.b);
    c.K = set1(sc.levels);
    c.squares = sc.squares;
    c.lo = set1(sc.lo);
    c.step = set1(sc.step);
    const double k0 = std::min(kSquareStart, sc.levels);
    SquareLanes lanes[kLaneSets];
    for (SquareLanes& L : lanes) {
        L.X0 = L.Y0 = L.dX = L.dY = L.iX = L.iY = L.tm = L.t = _mm256_setzero_pd();
        L.vz = L.ivz = L.k = set1(1);
        set_signs(L);
        L.active = _mm256_setzero_pd();
        L.active_bits = 0;
        for (int& s : L.slot) s = 0;
    }
    int next = 0;
    for (;;) {
        bool any = false;
        for (SquareLanes& L : lanes) {
            // Free lanes take the next rays, in order (loads of 4, spread over the free lanes).
            unsigned free = ~unsigned(L.active_bits) & 15u;
            if (free && next < n) {
                while (__builtin_popcount(free) > n - next)
                    free &= ~(1u << (31 - __builtin_clz(free)));
                const V m = lanes_mask(int(free));
                const __m256i perm =
                    _mm256_load_si256(reinterpret_cast<const __m256i*>(kExpand.idx[free]));
                take(L.X0, m, perm, rays.X0.data() + next);
                take(L.Y0, m, perm, rays.Y0.data() + next);
                take(L.dX, m, perm, rays.dX.data() + next);
                take(L.dY, m, perm, rays.dY.data() + next);
                take(L.iX, m, perm, rays.iX.data() + next);
                take(L.iY, m, perm, rays.iY.data() + next);
                take(L.vz, m, perm, rays.vz.data() + next);
                take(L.ivz, m, perm, rays.ivz.data() + next);
                take(L.tm, m, perm, rays.tm.data() + next);
                take(L.t, m, perm, t0 + next);
                L.k = blend(m, L.k, set1(k0));
                set_signs(L);
                for (unsigned f = free; f; f &= f - 1) L.slot[__builtin_ctz(f)] = next++;
                L.active = or_(L.active, m);
                L.active_bits |= int(free);
            }
            any |= L.active_bits != 0;
        }
        if (!any) return;
        __m128i entry[kLaneSets];
        for (int v = 0; v < kLaneSets; ++v) entry[v] = square_read(c, lanes[v]);
        V done[kLaneSets];
        for (int v = 0; v < kLaneSets; ++v) done[v] = square_step(c, lanes[v], entry[v]);
        for (int v = 0; v < kLaneSets; ++v) {
            const int d = bits(done[v]);
            if (!d) continue;
            SquareLanes& L = lanes[v];
            const int at_bottom = d & bits(ge(L.t, L.tm));
            alignas(32) double t[4];
            _mm256_store_pd(t, L.t);
            for (unsigned m = unsigned(d); m; m &= m - 1) {
                const int q = __builtin_ctz(m);
                t_safe[L.slot[q]] = t[q];
                bottom[L.slot[q]] = uint8_t((at_bottom >> q) & 1);
            }
            L.active = andnot(done[v], L.active);
            L.active_bits &= ~d;
        }
    }
}

namespace {

// ---- Pass B: the DDA ----

// ray_walk_simd.cpp's entered and last_entered (DdaAxis::last_entered from a guess).
PXH_AVX2_INLINE V entered(V k, V O, V inv, V p, V t) {
    const V line = blend(p, add(k, set1(1)), k);
    return lt(mul(sub(line, O), inv), t);
}
PXH_AVX2_INLINE V last_entered(V O, V d, V inv, V p, V mv, V step, V t, V& slow) {
    const V c = floor_pd(O);
    V g = floor_pd(add(O, mul(t, d)));
    const V behind = or_(and_(p, lt(g, c)), andnot(p, gt(g, c)));
    g = blend(behind, g, c);
    const V back = andnot(entered(g, O, inv, p, t), ne(g, c));
    g = blend(back, g, sub(g, step));
    slow = or_(slow, and_(mv, andnot(entered(g, O, inv, p, t), ne(g, c))));
    const V fwd = entered(add(g, step), O, inv, p, t);
    g = blend(fwd, g, add(g, step));
    slow = or_(slow, and_(mv, entered(add(g, step), O, inv, p, t)));
    return blend(mv, c, g);
}

// One pass B group: 4 rays (lanes beyond m repeat the last), their walks' state.
struct DdaGroup {
    V X0, Y0, dX, dY, iX, iY, vz, tm, sx, sy, ci, cj, li, lj, xl, yl, ex, ey;
    V counted, answer, last_exit;
    __m256i walked;
    alignas(16) int32_t at[4];  // the first corner of cell (li, lj) in the texels (fetch)
    V px, py, mx, my, active, done;
    int m, steps, active_bits;
    alignas(16) int32_t idx[4];
};

// Where cell (li, lj)'s corners lie in the texels, and a prefetch of its two rows' corner pairs
// for the next step (issued a step ahead; prefetches, unlike gathers, do not hold up the steps
// after them while the memory answers, so many cells are requested at once).
PXH_AVX2_INLINE void fetch(DdaGroup& G, const SquareScene& sc) {
    const __m128i a00 =
        _mm_add_epi32(_mm_mullo_epi32(to_i32(G.lj), _mm_set1_epi32(sc.up)), to_i32(G.li));
    int32_t* a = G.at;
    _mm_store_si128(reinterpret_cast<__m128i*>(a), a00);
    for (int q = 0; q < 4; ++q) {
        _mm_prefetch(reinterpret_cast<const char*>(sc.texels + a[q]), _MM_HINT_T0);
        _mm_prefetch(reinterpret_cast<const char*>(sc.texels + sc.up + a[q]), _MM_HINT_T0);
    }
}

// A column's values for the rays vi: four consecutive ones (seq) by a plain load.
PXH_AVX2_INLINE V ray_lanes(const std::vector<double>& a, __m128i vi, bool seq) {
    return seq ? _mm256_loadu_pd(a.data() + _mm_cvtsi128_si32(vi))
               : _mm256_i32gather_pd(a.data(), vi, 8);
}

// The group of rays list[g0 ..], from their t_safe: the DDA's cell at t_safe, its exits.
PXH_AVX2_INLINE void dda_start(DdaGroup& G, const SquareScene& sc, const RayColumns& rays,
                               const int* list, const double* t_safe, int g0, int n) {
    const V zero = _mm256_setzero_pd(), one = set1(1), mone = set1(-1);
    const V inf = set1(std::numeric_limits<double>::infinity());
    const V W = set1(sc.W), H = set1(sc.H), iW = set1(1.0 / sc.W), iH = set1(1.0 / sc.H);
    const int m = G.m = std::min(4, n - g0);
    const V valid = lanes_mask((1 << m) - 1);
    for (int q = 0; q < 4; ++q) G.idx[q] = list[g0 + std::min(q, m - 1)];
    const __m128i vi = _mm_load_si128(reinterpret_cast<const __m128i*>(G.idx));
    // four consecutive rays (the band tracer's first pass lists them in order): plain loads
    const bool seq =
        _mm_movemask_epi8(_mm_cmpeq_epi32(
            vi, _mm_add_epi32(_mm_set1_epi32(G.idx[0]), _mm_setr_epi32(0, 1, 2, 3)))) == 0xFFFF;
    G.X0 = ray_lanes(rays.X0, vi, seq);
    G.Y0 = ray_lanes(rays.Y0, vi, seq);
    G.dX = ray_lanes(rays.dX, vi, seq);
    G.dY = ray_lanes(rays.dY, vi, seq);
    G.iX = ray_lanes(rays.iX, vi, seq);
    G.iY = ray_lanes(rays.iY, vi, seq);
    G.vz = ray_lanes(rays.vz, vi, seq);
    G.tm = ray_lanes(rays.tm, vi, seq);
    const V t = _mm256_maskload_pd(t_safe + g0, _mm256_castpd_si256(valid));
    G.counted = ray_lanes(rays.counted, vi, seq);
    G.px = gt(G.dX, zero);
    G.py = gt(G.dY, zero);
    G.mx = ne(G.dX, zero);
    G.my = ne(G.dY, zero);
    G.sx = blend(G.px, mone, one);
    G.sy = blend(G.py, mone, one);
    // The DDA's cell at t.
    V slow = zero;
    G.ci = last_entered(G.X0, G.dX, G.iX, G.px, G.mx, G.sx, t, slow);
    G.cj = last_entered(G.Y0, G.dY, G.iY, G.py, G.my, G.sy, t, slow);
    const int slow_bits = bits(slow) & ((1 << m) - 1);
    if (slow_bits) {
        alignas(32) double a[4], c[4];
        _mm256_store_pd(a, G.ci);
        _mm256_store_pd(c, G.cj);
        for (unsigned mm = unsigned(slow_bits); mm; mm &= mm - 1) {
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
        G.ci = _mm256_load_pd(a);
        G.cj = _mm256_load_pd(c);
    }
    // Tile-local cell, exit lines and exit times (walk_dda's).
    G.li = wrap_pd(G.ci, W, iW);
    G.lj = wrap_pd(G.cj, H, iH);
    G.xl = blend(G.px, G.ci, add(G.ci, one));
    G.yl = blend(G.py, G.cj, add(G.cj, one));
    G.ex = blend(G.mx, inf, mul(sub(G.xl, G.X0), G.iX));
    G.ey = blend(G.my, inf, mul(sub(G.yl, G.Y0), G.iY));
    G.active = valid;
    G.active_bits = (1 << m) - 1;
    G.done = zero;
    G.walked = _mm256_setzero_si256();
    G.answer = zero;
    G.last_exit = t;
    G.steps = 0;
    fetch(G, sc);
}

// One axis of walk_dda's step, for the lanes `m` (ray_walk_simd.cpp's dda_advance).
PXH_AVX2_INLINE void dda_advance(V& c, V& l, V& el, V& e, V m, V step, V origin, V inv, V n) {
    const V zero = _mm256_setzero_pd();
    c = blend(m, c, add(c, step));
    l = blend(m, l, add(l, step));
    l = blend(and_(m, eq(l, n)), l, zero);
    l = blend(and_(m, lt(l, zero)), l, sub(n, set1(1)));
    el = blend(m, el, add(el, step));
    e = blend(m, e, mul(sub(el, origin), inv));
}

// cell_solver::first_root(c0, c1, c2, len) for the lanes `roots` (ray_walk_simd.cpp's
// dda_roots): the first root in [0, len], or -1 where none is found.
PXH_AVX2_INLINE V dda_roots(V c0, V c1, V c2, V len, V f_end, V roots) {
    const V zero = _mm256_setzero_pd();
    const V sign = _mm256_castsi256_pd(_mm256_set1_epi64x(int64_t(0x8000000000000000ULL)));
    const V magnitude = _mm256_castsi256_pd(_mm256_set1_epi64x(0x7fffffffffffffffLL));
    V best = set1(-1);
    const V c2ll = mul(mul(and_(c2, magnitude), len), len);
    const V scale = add(add(and_(c0, magnitude), mul(and_(c1, magnitude), len)), c2ll);
    const V linear = and_(roots, le(c2ll, mul(set1(1e-14), scale)));
    // consider(t): 0 <= t <= len and (best < 0 or t < best).
    V cand[3], ok[3];
    cand[0] = div(xor_(c0, sign), c1);
    ok[0] = and_(linear, lt(c1, zero));
    const V quad = andnot(linear, roots);
    const V disc = sub(mul(c1, c1), mul(mul(set1(4), c2), c0));
    const V root = _mm256_sqrt_pd(disc);
    const V q = mul(set1(-0.5), add(c1, or_(and_(root, magnitude), and_(c1, sign))));
    const V two_roots = and_(and_(quad, ge(disc, zero)), ne(q, zero));
    cand[1] = div(q, c2);
    cand[2] = div(c0, q);
    ok[1] = ok[2] = two_roots;
    for (int r = 0; r < 3; ++r) {
        const V take = and_(and_(and_(ok[r], ge(cand[r], zero)), le(cand[r], len)),
                            or_(lt(best, zero), lt(cand[r], best)));
        best = blend(take, best, cand[r]);
    }
    // No root found but the end value proves a crossing: first_root's bisection.
    const int bisect = bits(and_(and_(roots, lt(best, zero)), le(f_end, zero)));
    if (bisect) {
        alignas(32) double bq[4], a0[4], a1[4], a2[4], al[4];
        _mm256_store_pd(bq, best);
        _mm256_store_pd(a0, c0);
        _mm256_store_pd(a1, c1);
        _mm256_store_pd(a2, c2);
        _mm256_store_pd(al, len);
        for (unsigned mm = unsigned(bisect); mm; mm &= mm - 1) {
            const int r = __builtin_ctz(mm);
            bq[r] = cell_solver::first_root(a0[r], a1[r], a2[r], al[r]);
        }
        best = _mm256_load_pd(bq);
    }
    return best;
}

// One cell of the DDA for every active lane (walk_dda's, cell_below's test, solve_patch).
PXH_AVX2_INLINE void dda_step(DdaGroup& G, const SquareScene& sc) {
    const V zero = _mm256_setzero_pd(), one = set1(1), mone = set1(-1);
    const V W = set1(sc.W), H = set1(sc.H);
    const V zt = set1(sc.zt), s = set1(sc.s), b = set1(sc.b), neg_s = set1(-sc.s);
    const V sign = _mm256_castsi256_pd(_mm256_set1_epi64x(int64_t(0x8000000000000000ULL)));
    const V tau_out = std_min(std_min(G.ex, G.ey), G.tm);
    const V fresh = and_(G.active, gt(tau_out, G.counted));
    G.walked = _mm256_sub_epi64(G.walked, _mm256_castpd_si256(fresh));  // + 1 where fresh
    G.counted = blend(fresh, G.counted, tau_out);
    // Each corner pair (i, i + 1) of the cell's rows as one 8-byte element, by scalar loads
    // from the places fetch stored (quicker than a gather on Zen 3).
    auto pair = [](const float* p) {
        long long v;
        __builtin_memcpy(&v, p, sizeof v);
        return v;
    };
    const float* t0 = sc.texels;
    const float* t1 = sc.texels + sc.up;
    const __m256i row0 = _mm256_setr_epi64x(pair(t0 + G.at[0]), pair(t0 + G.at[1]),
                                            pair(t0 + G.at[2]), pair(t0 + G.at[3]));
    const __m256i row1 = _mm256_setr_epi64x(pair(t1 + G.at[0]), pair(t1 + G.at[1]),
                                            pair(t1 + G.at[2]), pair(t1 + G.at[3]));
    // Even dwords (the first corner) to the low half, odd ones to the high half.
    const __m256i split = _mm256_setr_epi32(0, 2, 4, 6, 1, 3, 5, 7);
    const __m256 r0 = _mm256_castsi256_ps(_mm256_permutevar8x32_epi32(row0, split));
    const __m256 r1 = _mm256_castsi256_ps(_mm256_permutevar8x32_epi32(row1, split));
    const __m128 f00 = _mm256_castps256_ps128(r0), f10 = _mm256_extractf128_ps(r0, 1);
    const __m128 f01 = _mm256_castps256_ps128(r1), f11 = _mm256_extractf128_ps(r1, 1);
    // cell_below.
    const __m128 top = std_max_ps(std_max_ps(f00, f10), std_max_ps(f01, f11));
    const V z_top = mul(s, sub(_mm256_cvtps_pd(top), b));
    const V z_ray = sub(zt, mul(tau_out, G.vz));
    const V solve = andnot(gt(z_ray, z_top), G.active);
    V hit = zero;
    V t_hit = zero;
    if (bits(solve)) {
        // solve_patch_inline, operation for operation.
        V tin = zero;
        const V ex_in = mul(sub(blend(G.px, add(G.ci, one), G.ci), G.X0), G.iX);
        tin = blend(G.mx, tin, std_max(tin, ex_in));
        const V ey_in = mul(sub(blend(G.py, add(G.cj, one), G.cj), G.Y0), G.iY);
        tin = blend(G.my, tin, std_max(tin, ey_in));
        const V h00 = _mm256_cvtps_pd(f00), h10 = _mm256_cvtps_pd(f10);
        const V h01 = _mm256_cvtps_pd(f01), h11 = _mm256_cvtps_pd(f11);
        const V fx0 = sub(add(G.X0, mul(tin, G.dX)), G.ci);
        const V fy0 = sub(add(G.Y0, mul(tin, G.dY)), G.cj);
        const V A = sub(h10, h00), B = sub(h01, h00);
        const V C = add(sub(sub(h00, h10), h01), h11);
        const V h0 = add(add(add(h00, mul(A, fx0)), mul(B, fy0)), mul(mul(C, fx0), fy0));
        const V h1 =
            add(add(mul(A, G.dX), mul(B, G.dY)), mul(C, add(mul(fx0, G.dY), mul(fy0, G.dX))));
        const V h2 = mul(mul(C, G.dX), G.dY);
        const V c0 = sub(sub(zt, mul(tin, G.vz)), mul(s, sub(h0, b)));
        const V at_entry = and_(solve, le(c0, zero));
        // cell_solver::first_root(c0, c1, c2, len).
        const V c1 = sub(xor_(G.vz, sign), mul(s, h1));
        const V c2 = mul(neg_s, h2);
        const V len = sub(tau_out, tin);
        const V f_end = add(c0, mul(add(c1, mul(c2, len)), len));
        const V slope_end = add(c1, mul(mul(set1(2), c2), len));
        const V clears =
            and_(gt(f_end, zero), or_(or_(le(c2, zero), ge(c1, zero)), le(slope_end, zero)));
        const V roots = andnot(clears, andnot(at_entry, solve));
        V best = mone;
        if (bits(roots)) best = dda_roots(c0, c1, c2, len, f_end, roots);
        const V found = and_(roots, ge(best, zero));
        t_hit = blend(found, t_hit, add(tin, best));
        t_hit = blend(at_entry, t_hit, tin);
        hit = or_(found, at_entry);
    }
    G.answer = blend(hit, G.answer, t_hit);
    const V at_bottom = and_(andnot(hit, G.active), ge(tau_out, G.tm));
    G.answer = blend(at_bottom, G.answer, G.tm);
    const V finished = or_(hit, at_bottom);
    G.done = or_(G.done, finished);
    G.active = andnot(finished, G.active);
    G.active_bits = bits(G.active);
    if (!G.active_bits) return;
    // The next cell: x on G.ex <= G.ey (walk_dda's step, tile-local indices wrapped).
    G.last_exit = blend(G.active, G.last_exit, tau_out);
    const V xs = and_(G.active, le(G.ex, G.ey));
    const V ys = andnot(xs, G.active);
    dda_advance(G.ci, G.li, G.xl, G.ex, xs, G.sx, G.X0, G.iX, W);
    dda_advance(G.cj, G.lj, G.yl, G.ey, ys, G.sy, G.Y0, G.iY, H);
    if (++G.steps == kDdaCells) {  // resumed by pass A
        G.active = zero;
        G.active_bits = 0;
        return;
    }
    fetch(G, sc);
}

// The group's answers.
PXH_AVX2_INLINE void dda_finish(DdaGroup& G, int g0, double* out_t, uint8_t* resolved,
                                RayColumns& rays) {
    const int m = G.m;
    const int done = bits(G.done);
    // Not resolved: resume pass A from the last exit (every cell walked was rejected).
    G.answer = blend(G.done, G.last_exit, G.answer);
    alignas(32) double ans[4], upto[4];
    alignas(32) int64_t cnt[4];
    _mm256_store_pd(ans, G.answer);
    _mm256_store_pd(upto, G.counted);
    _mm256_store_si256(reinterpret_cast<__m256i*>(cnt), G.walked);
    for (int q = 0; q < m; ++q) {
        out_t[g0 + q] = ans[q];
        resolved[g0 + q] = (done >> q) & 1;
        rays.cells[G.idx[q]] += int(cnt[q]);
        rays.counted[G.idx[q]] = upto[q];
    }
}

}  // namespace

PXH_AVX2 void dda_pass(const SquareScene& sc, RayColumns& rays, const int* list,
                       const double* t_safe, int n, double* out_t, uint8_t* resolved) {
    for (int g0 = 0; g0 < n; g0 += 4 * kDdaGroups) {
        DdaGroup groups[kDdaGroups];
        const int count = std::min(kDdaGroups, (n - g0 + 3) / 4);
        for (int k = 0; k < count; ++k) dda_start(groups[k], sc, rays, list, t_safe, g0 + 4 * k, n);
        for (bool any = true; any;) {
            any = false;
            for (int k = 0; k < count; ++k)
                if (groups[k].active_bits) {
                    dda_step(groups[k], sc);
                    any |= groups[k].active_bits != 0;
                }
        }
        for (int k = 0; k < count; ++k) dda_finish(groups[k], g0 + 4 * k, out_t, resolved, rays);
    }
}

PXH_AVX2 void make_rays(const View& view, size_t k0, const int* where, int n, const SquareScene& sc,
                        RayColumns& c, double* ex_out, double* ey_out) {
    const V zero = _mm256_setzero_pd(), one = set1(1);
    const V W = set1(sc.W), H = set1(sc.H), half = set1(0.5);
    const V zt = set1(sc.zt), s = set1(sc.s);
    const V sign = _mm256_castsi256_pd(_mm256_set1_epi64x(int64_t(0x8000000000000000ULL)));
    const double* P = &view.P[0].x;
    const double* Vs = &view.V[0].x;
    for (int p = 0; p < n; p += 4) {
        // Lanes beyond the last ray repeat it.
        const int live = std::min(4, n - p);
        const __m256i m = _mm256_castpd_si256(lanes_mask((1 << live) - 1));
        const __m256i k = _mm256_setr_epi64x(int64_t(k0) + where[p],
                                             int64_t(k0) + where[p + std::min(1, live - 1)],
                                             int64_t(k0) + where[p + std::min(2, live - 1)],
                                             int64_t(k0) + where[p + std::min(3, live - 1)]);
        const __m256i kp = _mm256_add_epi64(k, k);
        const V Px = _mm256_i64gather_pd(P, kp, 8);
        const V Py = _mm256_i64gather_pd(P + 1, kp, 8);
        V Vx, Vy, Vz;
        if (view.parallel) {
            Vx = set1(Vs[0]);
            Vy = set1(Vs[1]);
            Vz = set1(Vs[2]);
        } else {
            const __m256i kv = _mm256_add_epi64(kp, k);
            Vx = _mm256_i64gather_pd(Vs, kv, 8);
            Vy = _mm256_i64gather_pd(Vs + 1, kv, 8);
            Vz = _mm256_i64gather_pd(Vs + 2, kv, 8);
        }
        const V ex = add(Px, mul(div(Vx, Vz), zt));
        const V ey = add(Py, mul(div(Vy, Vz), zt));
        const V dX = mul(xor_(Vx, sign), W);
        const V dY = mul(xor_(Vy, sign), H);
        _mm256_maskstore_pd(ex_out + p, m, ex);
        _mm256_maskstore_pd(ey_out + p, m, ey);
        _mm256_maskstore_pd(c.X0.data() + p, m, sub(mul(ex, W), half));
        _mm256_maskstore_pd(c.Y0.data() + p, m, sub(mul(ey, H), half));
        _mm256_maskstore_pd(c.dX.data() + p, m, dX);
        _mm256_maskstore_pd(c.dY.data() + p, m, dY);
        _mm256_maskstore_pd(c.iX.data() + p, m, and_(ne(dX, zero), div(one, dX)));
        _mm256_maskstore_pd(c.iY.data() + p, m, and_(ne(dY, zero), div(one, dY)));
        _mm256_maskstore_pd(c.vz.data() + p, m, Vz);
        _mm256_maskstore_pd(c.ivz.data() + p, m, div(one, Vz));
        _mm256_maskstore_pd(c.tm.data() + p, m, div(s, Vz));
    }
}

}  // namespace pxh::vector_walk::avx2
