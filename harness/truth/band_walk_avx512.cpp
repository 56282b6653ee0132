// The band tracer's vector walk at 8 rays to a vector (AVX-512: avx512f and avx512dq, checked
// at run time: ExactTracer::band_path): band_walk_engine.h over 8 doubles, masks in mask
// registers. No contraction: each product rounded, as in the scalar walk.
// GCC 12's AVX-512 intrinsics start from _mm512_undefined_*(), which its -Wmaybe-uninitialized
// (and -Wuninitialized) report once they are inlined here (a known false positive, as in
// ray_walk_simd.cpp).
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Wuninitialized"
#endif
#include <immintrin.h>

#include <cstdint>
#include <limits>

#include "harness/truth/band_tracer.h"

// Only what follows takes AVX-512: every header above (the standard library's, the
// tracer's) is compiled for the baseline, so no inline function shared with other files is.
#if defined(__clang__)
#pragma clang attribute push(__attribute__((target("avx512f,avx512dq"))), apply_to = function)
#else
#pragma GCC push_options
#pragma GCC target("avx512f,avx512dq")
#endif

namespace pxh::band_walk {
namespace {

struct Avx512 {
    using D = __m512d;
    using M = __mmask8;
    static constexpr int N = 8;
    static D set1(double x) { return _mm512_set1_pd(x); }
    static D load(const double* p) { return _mm512_load_pd(p); }
    static void store(double* p, D a) { _mm512_store_pd(p, a); }
    static D add(D a, D b) { return _mm512_add_pd(a, b); }
    static D sub(D a, D b) { return _mm512_sub_pd(a, b); }
    static D mul(D a, D b) { return _mm512_mul_pd(a, b); }
    static D div(D a, D b) { return _mm512_div_pd(a, b); }
    static D sqrt(D a) { return _mm512_sqrt_pd(a); }
    static D min(D a, D b) { return _mm512_min_pd(a, b); }  // a < b ? a : b
    static D max(D a, D b) { return _mm512_max_pd(a, b); }  // a > b ? a : b
    static D neg(D a) { return _mm512_xor_pd(a, _mm512_set1_pd(-0.0)); }
    static D abs(D a) { return _mm512_andnot_pd(_mm512_set1_pd(-0.0), a); }
    static D copysign(D x, D y) {
        const D sign = _mm512_set1_pd(-0.0);
        return _mm512_or_pd(_mm512_andnot_pd(sign, x), _mm512_and_pd(sign, y));
    }
    static M lt(D a, D b) { return _mm512_cmp_pd_mask(a, b, _CMP_LT_OQ); }
    static M le(D a, D b) { return _mm512_cmp_pd_mask(a, b, _CMP_LE_OQ); }
    static M gt(D a, D b) { return _mm512_cmp_pd_mask(a, b, _CMP_GT_OQ); }
    static M ge(D a, D b) { return _mm512_cmp_pd_mask(a, b, _CMP_GE_OQ); }
    static M eq(D a, D b) { return _mm512_cmp_pd_mask(a, b, _CMP_EQ_OQ); }
    static M ne(D a, D b) { return _mm512_cmp_pd_mask(a, b, _CMP_NEQ_UQ); }  // C++'s != (NaN: true)
    static M mand(M a, M b) { return M(a & b); }
    static M mor(M a, M b) { return M(a | b); }
    static M andnot(M a, M b) { return M(~a & b); }
    static D blend(M m, D a, D b) { return _mm512_mask_blend_pd(m, a, b); }  // m ? b : a
    static int bits(M m) { return int(m); }
    static __m256 high(__m512 v) {
        return _mm256_castpd_ps(_mm512_extractf64x4_pd(_mm512_castps_pd(v), 1));
    }
    // A cell's corners h00, h10, h01, h11 per lane from column_pairs_ (read as 8-byte pairs
    // (h(i, j), h(i, j + 1))): pairs i0 (column wi) and i1 (column wi + 1, wrapped).
    static void corners(const double* pairs, D i0, D i1, D f[4]) {
        const __m512i lo_hi = _mm512_setr_epi32(0, 2, 4, 6, 8, 10, 12, 14, 1, 3, 5, 7, 9, 11, 13, 15);
        const __m512 a = _mm512_permutexvar_ps(
            lo_hi, _mm512_castpd_ps(_mm512_i32gather_pd(_mm512_cvttpd_epi32(i0), pairs, 8)));
        const __m512 b = _mm512_permutexvar_ps(
            lo_hi, _mm512_castpd_ps(_mm512_i32gather_pd(_mm512_cvttpd_epi32(i1), pairs, 8)));
        f[0] = _mm512_cvtps_pd(_mm512_castps512_ps256(a));
        f[1] = _mm512_cvtps_pd(_mm512_castps512_ps256(b));
        f[2] = _mm512_cvtps_pd(high(a));
        f[3] = _mm512_cvtps_pd(high(b));
    }
};

}  // namespace
}  // namespace pxh::band_walk

#include "harness/truth/band_walk_engine.h"

namespace pxh::band_walk {

void walk_avx512(const ViewTracer& vt, ViewTracer::Band& band, const ViewTracer::Start* st,
                 const size_t* ks, size_t n, Hits& out) {
    if (n == 0) return;
    Batch<Avx512>(vt, band, st, ks, n, out).run();
}

}  // namespace pxh::band_walk

#if defined(__clang__)
#pragma clang attribute pop
#else
#pragma GCC pop_options
#endif
