// Pass A of the AVX2 path (ray_walk_simd.cpp's square walk) at 8 rays to a vector, in float:
// the square walk only has to be conservative (every cell the DDA leaves before the t_safe it
// returns is one cell_below rejects), not trace_naive's arithmetic, so it may compute in any
// precision whose errors it bounds. In float, 8 lanes to an AVX2 vector take the instructions
// 4 lanes of double take (ray_walk_avx2.cpp's square_pass, which rays outside the bounds below
// still take). Where it departs from the double walk, and why each step stays conservative:
//   - positions relative to the ray's start cell: X0 = Xi + Xf (Xi = floor(X0) an integer,
//     Xf in [0, 1) rounded to float), so the ray's column floor(Xf + t dX + 1/2) is off by
//     |delta| <= 3 2^-24 (T + 1) cells, T the ray's travel in cells (below 2^15: delta < 0.01);
//     the square's first column g - 1 is behind the DDA's column for any delta < 1/2 (ray_walk_
//     simd.cpp's argument: the ray lies half a cell past g - 1's near line at least), and its far
//     line half a cell less delta ahead of the ray;
//   - the far line's crossing time te, (line - X0) / dX, is computed as ((line - Xi) - Xf) iX in
//     float (relative error below 5 2^-24: the difference is at least 0.49 cells) and taken
//     times (1 - 2^-20): below trace_naive's double value, so every cell beyond the far line is
//     entered, hence left, no earlier; the slab bottom tau_max and a start time t0 are rounded
//     down to float;
//   - heights: the square's bound s (M - b) is taken plus a margin z_margin (2^-16 of the
//     heights' scale, far above float's and double's rounding of either side of cell_below's
//     test), so a ray above it in float lies above it in cell_below's double arithmetic at every
//     earlier time; the time the ray comes down to it is taken times (1 - 2^-20) and checked;
//   - a walk that clears down to the rounded-down tau_max returns that time as t_safe (not a
//     bottom): the DDA walks the last cells itself.
// Each clear step moves t on by at least 0.45 / |dX| (the far line's half cell less delta, less
// the margin t |dX| 2^-20 < 2^-5), so every walk ends. Rays whose |X0| or |Y0| is 2^20 cells or
// more, or whose travel is 2^15 cells or more along an axis, take the double walk.
#include <immintrin.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

#include "harness/truth/ray_walk_vector.h"

#define PXH_AVX2 __attribute__((target("avx2,fma")))
#define PXH_AVX2_INLINE __attribute__((target("avx2,fma"), always_inline)) inline

namespace pxh::vector_walk::avx2 {

namespace {

// Vectors of 8 rays stepped in turn (AVX-512's 4 vectors of 8 doubles).
constexpr int kLaneSetsF = 4;
constexpr double kMaxStart = 1 << 20;   // cells: |X0|, |Y0| below it
constexpr double kMaxTravel = 1 << 15;  // cells: tau_max |dX|, tau_max |dY| below it
constexpr float kShrink = 1.0f - 0x1p-20f;

using F = __m256;  // 8 floats; a mask: all-ones or zero lanes
using I = __m256i;

PXH_AVX2_INLINE F set1(float x) { return _mm256_set1_ps(x); }
PXH_AVX2_INLINE F add(F a, F b) { return _mm256_add_ps(a, b); }
PXH_AVX2_INLINE F sub(F a, F b) { return _mm256_sub_ps(a, b); }
PXH_AVX2_INLINE F mul(F a, F b) { return _mm256_mul_ps(a, b); }
PXH_AVX2_INLINE F and_(F a, F b) { return _mm256_and_ps(a, b); }
PXH_AVX2_INLINE F or_(F a, F b) { return _mm256_or_ps(a, b); }
PXH_AVX2_INLINE F andnot(F m, F a) { return _mm256_andnot_ps(m, a); }         // ~m & a
PXH_AVX2_INLINE F blend(F m, F a, F b) { return _mm256_blendv_ps(a, b, m); }  // m ? b : a
PXH_AVX2_INLINE F lt(F a, F b) { return _mm256_cmp_ps(a, b, _CMP_LT_OQ); }
PXH_AVX2_INLINE F gt(F a, F b) { return _mm256_cmp_ps(a, b, _CMP_GT_OQ); }
PXH_AVX2_INLINE F ge(F a, F b) { return _mm256_cmp_ps(a, b, _CMP_GE_OQ); }
PXH_AVX2_INLINE F eq(F a, F b) { return _mm256_cmp_ps(a, b, _CMP_EQ_OQ); }
PXH_AVX2_INLINE int bits(F m) { return _mm256_movemask_ps(m); }
PXH_AVX2_INLINE F floor_ps(F x) {
    return _mm256_round_ps(x, _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC);
}
// a - n floor((a + 1/2) / n) for integer-valued a, |a| < 2^22, in [0, n): (a + 1/2) / n lies
// 1 / (2 n) or more from an integer, more than the float product's error |a / n| 2^-23.
PXH_AVX2_INLINE F wrap_ps(F a, F n, F inv_n) {
    return sub(a, mul(n, floor_ps(mul(add(a, set1(0.5f)), inv_n))));
}
PXH_AVX2_INLINE I lookup(I table, I k) { return _mm256_permutevar8x32_epi32(table, k); }

// The rays in float (per ray; conversions in to_float).
struct FloatRays {
    std::vector<float> Xf, Yf, dX, dY, iX, iY, vz, ivz, tm, t0;
    std::vector<int32_t> Xi, Yi;
    void resize(size_t n) {
        for (auto* v : {&Xf, &Yf, &dX, &dY, &iX, &iY, &vz, &ivz, &tm, &t0}) v->resize(n + 8);
        for (auto* v : {&Xi, &Yi}) v->resize(n + 8);
    }
};

struct Lanes {
    F Xf, Yf, dX, dY, iX, iY, vz, ivz, tm, t, k;
    I Xi, Yi;
    F hx, hy, fx, fy, sx, sy, px, py, mx, my;  // ray_walk_avx2.cpp's SquareLanes' (signs)
    F te;
    F active;
    int active_bits;
    int slot[8];
    alignas(32) int32_t at[8];  // square_read's entries, for square_step's loads
};

struct Consts {
    F W, H, iW, iH, zt, s, b, K, lo, step, zmargin;
    I cols, base, last;
    const uint8_t* squares;
};

PXH_AVX2_INLINE void set_signs(Lanes& L) {
    const F zero = _mm256_setzero_ps(), one = set1(1), mone = set1(-1);
    L.px = gt(L.dX, zero);
    L.py = gt(L.dY, zero);
    L.mx = _mm256_cmp_ps(L.dX, zero, _CMP_NEQ_OQ);
    L.my = _mm256_cmp_ps(L.dY, zero, _CMP_NEQ_OQ);
    L.hx = blend(L.px, set1(-0.5f), set1(0.5f));
    L.hy = blend(L.py, set1(-0.5f), set1(0.5f));
    L.fx = blend(L.px, set1(2), mone);
    L.fy = blend(L.py, set1(2), mone);
    L.sx = blend(L.px, mone, one);
    L.sy = blend(L.py, mone, one);
}

// The step's first half: the square, its far lines' time te (a lower bound), and a prefetch of
// each lane's table entry.
PXH_AVX2_INLINE void square_read(const Consts& c, Lanes& L) {
    const F inf = set1(std::numeric_limits<float>::infinity());
    const F t = L.t;
    const F gx = floor_ps(add(add(L.Xf, mul(t, L.dX)), L.hx));  // relative to Xi
    const F gy = floor_ps(add(add(L.Yf, mul(t, L.dY)), L.hy));
    const I level = _mm256_cvttps_epi32(L.k);
    const F n = _mm256_castsi256_ps(
        _mm256_slli_epi32(_mm256_add_epi32(level, _mm256_set1_epi32(127)), 23));  // 2^k
    const F lx = add(add(gx, L.fx), mul(L.sx, n)), ly = add(add(gy, L.fy), mul(L.sy, n));
    const F ax = sub(lx, and_(L.px, n)), ay = sub(ly, and_(L.py, n));
    const F tx = blend(L.mx, inf, mul(mul(sub(lx, L.Xf), L.iX), set1(kShrink)));
    const F ty = blend(L.my, inf, mul(mul(sub(ly, L.Yf), L.iY), set1(kShrink)));
    L.te = _mm256_min_ps(_mm256_min_ps(tx, ty), L.tm);
    // The first cell, global (integers below 2^22: exact in float), wrapped into the tile.
    const F gax = _mm256_cvtepi32_ps(_mm256_add_epi32(L.Xi, _mm256_cvttps_epi32(ax)));
    const F gay = _mm256_cvtepi32_ps(_mm256_add_epi32(L.Yi, _mm256_cvttps_epi32(ay)));
    const I shift =
        _mm256_max_epi32(_mm256_sub_epi32(level, _mm256_set1_epi32(2)), _mm256_setzero_si256());
    const I Ix = _mm256_srlv_epi32(_mm256_cvttps_epi32(wrap_ps(gax, c.W, c.iW)), shift);
    const I Jy = _mm256_srlv_epi32(_mm256_cvttps_epi32(wrap_ps(gay, c.H, c.iH)), shift);
    const I at = _mm256_min_epu32(
        _mm256_add_epi32(
            _mm256_add_epi32(lookup(c.base, level), _mm256_mullo_epi32(Jy, lookup(c.cols, level))),
            Ix),
        c.last);
    int32_t* a = L.at;
    _mm256_store_si256(reinterpret_cast<I*>(a), at);
    for (int q = 0; q < 8; ++q)
        _mm_prefetch(reinterpret_cast<const char*>(c.squares + a[q]), _MM_HINT_T0);
}

// The step's second half: returns the lanes whose walk ended (t is their t_safe). The entries
// are read by 8 byte loads from the places square_read stored (a gather is slower on Zen 3).
PXH_AVX2_INLINE F square_step(const Consts& c, Lanes& L) {
    const F zero = _mm256_setzero_ps(), one = set1(1);
    const F t = L.t, te = L.te;
    const uint8_t* sq = c.squares;
    const int32_t* a = L.at;
    const I code = _mm256_setr_epi32(sq[a[0]], sq[a[1]], sq[a[2]], sq[a[3]], sq[a[4]], sq[a[5]],
                                     sq[a[6]], sq[a[7]]);
    const F M = add(c.lo, mul(_mm256_cvtepi32_ps(code), c.step));
    const F zM = add(mul(c.s, sub(M, c.b)), c.zmargin);  // above s (M - b) by the margin
    const F clear = and_(L.active, gt(sub(c.zt, mul(te, L.vz)), zM));
    const F fail = andnot(clear, L.active);
    const F ta = _mm256_min_ps(mul(mul(sub(c.zt, zM), L.ivz), set1(kShrink)), te);
    const F on = and_(and_(fail, gt(sub(c.zt, mul(ta, L.vz)), zM)), gt(ta, t));
    L.t = blend(on, blend(clear, t, te), ta);
    const F k = blend(and_(clear, lt(L.k, c.K)), L.k, add(L.k, one));
    L.k = blend(fail, k, sub(k, one));
    return or_(and_(fail, eq(L.k, zero)), and_(clear, ge(te, L.tm)));
}

// AVX-512's expand for 8 lanes: for the free lanes f (bit q: lane q), the element of a load
// each lane takes (the r-th free lane the r-th element; the others keep their own).
struct ExpandTable8 {
    alignas(32) int32_t idx[256][8];
    ExpandTable8() {
        for (int f = 0; f < 256; ++f) {
            int r = 0;
            for (int q = 0; q < 8; ++q) idx[f][q] = (f >> q) & 1 ? r++ : q;
        }
    }
};
const ExpandTable8 kExpand8;

PXH_AVX2_INLINE void take(F& x, F m, I perm, const float* col) {
    x = blend(m, x, _mm256_permutevar8x32_ps(_mm256_loadu_ps(col), perm));
}
PXH_AVX2_INLINE void take(I& x, F m, I perm, const int32_t* col) {
    const I loaded =
        _mm256_permutevar8x32_epi32(_mm256_loadu_si256(reinterpret_cast<const I*>(col)), perm);
    x = _mm256_castps_si256(blend(m, _mm256_castsi256_ps(x), _mm256_castsi256_ps(loaded)));
}

// The largest float at or below x (x >= 0, finite).
float down(double x) {
    float f = float(x);
    if (double(f) > x) f = std::nextafter(f, -std::numeric_limits<float>::infinity());
    return f;
}

// The rays in float, or false where one lies outside the bounds (the double walk takes them).
bool to_float(const RayColumns& rays, const double* t0, int n, FloatRays& f) {
    f.resize(size_t(n));
    for (int q = 0; q < n; ++q) {
        const double X0 = rays.X0[q], Y0 = rays.Y0[q], tm = rays.tm[q];
        if (!(std::abs(X0) < kMaxStart && std::abs(Y0) < kMaxStart &&
              tm * std::abs(rays.dX[q]) < kMaxTravel && tm * std::abs(rays.dY[q]) < kMaxTravel &&
              t0[q] >= 0))
            return false;
        const double xi = std::floor(X0), yi = std::floor(Y0);
        f.Xi[q] = int32_t(xi);
        f.Yi[q] = int32_t(yi);
        f.Xf[q] = float(X0 - xi);  // exact in double: X0 and xi within 2^20 of each other
        f.Yf[q] = float(Y0 - yi);
        f.dX[q] = float(rays.dX[q]);
        f.dY[q] = float(rays.dY[q]);
        f.iX[q] = float(rays.iX[q]);
        f.iY[q] = float(rays.iY[q]);
        f.vz[q] = float(rays.vz[q]);
        f.ivz[q] = float(rays.ivz[q]);
        f.tm[q] = down(tm);
        f.t0[q] = down(t0[q]);
    }
    return true;
}

}  // namespace

PXH_AVX2 void square_pass(const SquareScene& sc, const RayColumns& rays, const double* t0, int n,
                          double* t_safe, uint8_t* bottom) {
    thread_local FloatRays fr;
    if (!to_float(rays, t0, n, fr)) return square_pass_f64(sc, rays, t0, n, t_safe, bottom);
    Consts c;
    c.W = set1(float(sc.W));
    c.H = set1(float(sc.H));
    c.iW = set1(float(1.0 / sc.W));
    c.iH = set1(float(1.0 / sc.H));
    alignas(32) int32_t cols[8], base[8];
    for (int k = 0; k < 8; ++k) {
        cols[k] = int32_t(sc.cols[k]);
        base[k] = int32_t(sc.base[k]);
    }
    c.cols = _mm256_load_si256(reinterpret_cast<const I*>(cols));
    c.base = _mm256_load_si256(reinterpret_cast<const I*>(base));
    c.last = _mm256_set1_epi32(int32_t(sc.entries - 1));
    c.zt = set1(float(sc.zt));
    c.s = set1(float(sc.s));
    c.b = set1(float(sc.b));
    c.K = set1(float(sc.levels));
    c.lo = set1(float(sc.lo));
    c.step = set1(float(sc.step));
    // The heights' scale: |zt|, |z_bot| and the bounds' s |M - b| are at most this.
    const double scale =
        std::abs(sc.zt) + sc.s * (std::abs(sc.lo) + 255 * sc.step + std::abs(sc.b) + 1);
    c.zmargin = set1(float(scale * 0x1p-16));
    c.squares = sc.squares;
    const float k0 = float(std::min(kSquareStart, sc.levels));
    Lanes lanes[kLaneSetsF];
    for (Lanes& L : lanes) {
        L.Xf = L.Yf = L.dX = L.dY = L.iX = L.iY = L.tm = L.t = _mm256_setzero_ps();
        L.vz = L.ivz = L.k = set1(1);
        L.Xi = L.Yi = _mm256_setzero_si256();
        set_signs(L);
        L.active = _mm256_setzero_ps();
        L.active_bits = 0;
        for (int& s : L.slot) s = 0;
    }
    int next = 0;
    for (;;) {
        bool any = false;
        for (Lanes& L : lanes) {
            unsigned free = ~unsigned(L.active_bits) & 255u;
            if (free && next < n) {
                while (__builtin_popcount(free) > n - next)
                    free &= ~(1u << (31 - __builtin_clz(free)));
                const F m = _mm256_castsi256_ps(_mm256_cmpeq_epi32(
                    _mm256_and_si256(_mm256_set1_epi32(int(free)),
                                     _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128)),
                    _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128)));
                const I perm = _mm256_load_si256(reinterpret_cast<const I*>(kExpand8.idx[free]));
                take(L.Xf, m, perm, fr.Xf.data() + next);
                take(L.Yf, m, perm, fr.Yf.data() + next);
                take(L.Xi, m, perm, fr.Xi.data() + next);
                take(L.Yi, m, perm, fr.Yi.data() + next);
                take(L.dX, m, perm, fr.dX.data() + next);
                take(L.dY, m, perm, fr.dY.data() + next);
                take(L.iX, m, perm, fr.iX.data() + next);
                take(L.iY, m, perm, fr.iY.data() + next);
                take(L.vz, m, perm, fr.vz.data() + next);
                take(L.ivz, m, perm, fr.ivz.data() + next);
                take(L.tm, m, perm, fr.tm.data() + next);
                take(L.t, m, perm, fr.t0.data() + next);
                L.k = blend(m, L.k, set1(k0));
                set_signs(L);
                for (unsigned f = free; f; f &= f - 1) L.slot[__builtin_ctz(f)] = next++;
                L.active = or_(L.active, m);
                L.active_bits |= int(free);
            }
            any |= L.active_bits != 0;
        }
        if (!any) return;
        for (int v = 0; v < kLaneSetsF; ++v) square_read(c, lanes[v]);
        F done[kLaneSetsF];
        for (int v = 0; v < kLaneSetsF; ++v) done[v] = square_step(c, lanes[v]);
        for (int v = 0; v < kLaneSetsF; ++v) {
            const int d = bits(done[v]);
            if (!d) continue;
            Lanes& L = lanes[v];
            alignas(32) float t[8];
            _mm256_store_ps(t, L.t);
            for (unsigned m = unsigned(d); m; m &= m - 1) {
                const int q = __builtin_ctz(m);
                t_safe[L.slot[q]] = double(t[q]);
                bottom[L.slot[q]] = 0;  // the DDA walks the last cells (see the top)
            }
            L.active = andnot(done[v], L.active);
            L.active_bits &= ~d;
        }
    }
}

}  // namespace pxh::vector_walk::avx2
