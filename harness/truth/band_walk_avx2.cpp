// The band tracer's vector walk at 4 rays to a vector (AVX2 and FMA, checked at run time:
// ExactTracer::band_path): band_walk_engine.h over 4 doubles. Masks are vectors of all-ones
// lanes; FMA is not used for arithmetic (no contraction: each product rounded, as in the scalar
// walk), only required with AVX2 as the per-ray path requires it.
// GCC 12's gather intrinsics start from _mm256_undefined_*(), which its -Wmaybe-uninitialized
// reports once they are inlined here (a known false positive, as in ray_walk_avx2.cpp).
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#include <immintrin.h>

#include <cstdint>
#include <limits>

#include "harness/truth/band_tracer.h"

// Only what follows takes AVX2 and FMA: every header above (the standard library's, the
// tracer's) is compiled for the baseline, so no inline function shared with other files is.
#if defined(__clang__)
#pragma clang attribute push(__attribute__((target("avx2,fma"))), apply_to = function)
#else
#pragma GCC push_options
#pragma GCC target("avx2,fma")
#endif

namespace pxh::band_walk {
namespace {

struct Avx2 {
    using D = __m256d;
    using M = __m256d;  // all-ones or zero lanes
    static constexpr int N = 4;
    static D set1(double x) { return _mm256_set1_pd(x); }
    static D load(const double* p) { return _mm256_load_pd(p); }
    static void store(double* p, D a) { _mm256_store_pd(p, a); }
    static D add(D a, D b) { return _mm256_add_pd(a, b); }
    static D sub(D a, D b) { return _mm256_sub_pd(a, b); }
    static D mul(D a, D b) { return _mm256_mul_pd(a, b); }
    static D div(D a, D b) { return _mm256_div_pd(a, b); }
    static D sqrt(D a) { return _mm256_sqrt_pd(a); }
    static D min(D a, D b) { return _mm256_min_pd(a, b); }  // a < b ? a : b
    static D max(D a, D b) { return _mm256_max_pd(a, b); }  // a > b ? a : b
    static D neg(D a) { return _mm256_xor_pd(a, _mm256_set1_pd(-0.0)); }
    static D abs(D a) { return _mm256_andnot_pd(_mm256_set1_pd(-0.0), a); }
    static D copysign(D x, D y) {
        const D sign = _mm256_set1_pd(-0.0);
        return _mm256_or_pd(_mm256_andnot_pd(sign, x), _mm256_and_pd(sign, y));
    }
    static M lt(D a, D b) { return _mm256_cmp_pd(a, b, _CMP_LT_OQ); }
    static M le(D a, D b) { return _mm256_cmp_pd(a, b, _CMP_LE_OQ); }
    static M gt(D a, D b) { return _mm256_cmp_pd(a, b, _CMP_GT_OQ); }
    static M ge(D a, D b) { return _mm256_cmp_pd(a, b, _CMP_GE_OQ); }
    static M eq(D a, D b) { return _mm256_cmp_pd(a, b, _CMP_EQ_OQ); }
    static M ne(D a, D b) { return _mm256_cmp_pd(a, b, _CMP_NEQ_UQ); }  // C++'s != (NaN: true)
    static M mand(M a, M b) { return _mm256_and_pd(a, b); }
    static M mor(M a, M b) { return _mm256_or_pd(a, b); }
    static M andnot(M a, M b) { return _mm256_andnot_pd(a, b); }  // ~a & b
    static D blend(M m, D a, D b) { return _mm256_blendv_pd(a, b, m); }  // m ? b : a
    static int bits(M m) { return _mm256_movemask_pd(m); }
    // A cell's corners h00, h10, h01, h11 per lane from column_pairs_ (read as 8-byte pairs
    // (h(i, j), h(i, j + 1))): pairs i0 (column wi) and i1 (column wi + 1, wrapped).
    static void corners(const double* pairs, D i0, D i1, D f[4]) {
        // Loads, not gathers: a gather holds up what follows until every lane's read is in.
        alignas(16) int32_t a[4], b[4];
        _mm_store_si128(reinterpret_cast<__m128i*>(a), _mm256_cvttpd_epi32(i0));
        _mm_store_si128(reinterpret_cast<__m128i*>(b), _mm256_cvttpd_epi32(i1));
        auto pair = [pairs](int32_t k) { return _mm_load_sd(pairs + k); };
        const __m256d g0 = _mm256_setr_m128d(_mm_unpacklo_pd(pair(a[0]), pair(a[1])),
                                            _mm_unpacklo_pd(pair(a[2]), pair(a[3])));
        const __m256d g1 = _mm256_setr_m128d(_mm_unpacklo_pd(pair(b[0]), pair(b[1])),
                                            _mm_unpacklo_pd(pair(b[2]), pair(b[3])));
        const __m256i lo_hi = _mm256_setr_epi32(0, 2, 4, 6, 1, 3, 5, 7);
        const __m256 x = _mm256_permutevar8x32_ps(_mm256_castpd_ps(g0), lo_hi);
        const __m256 y = _mm256_permutevar8x32_ps(_mm256_castpd_ps(g1), lo_hi);
        f[0] = _mm256_cvtps_pd(_mm256_castps256_ps128(x));
        f[1] = _mm256_cvtps_pd(_mm256_castps256_ps128(y));
        f[2] = _mm256_cvtps_pd(_mm256_extractf128_ps(x, 1));
        f[3] = _mm256_cvtps_pd(_mm256_extractf128_ps(y, 1));
    }
};

}  // namespace
}  // namespace pxh::band_walk

#include "harness/truth/band_walk_engine.h"

namespace pxh::band_walk {

void walk_avx2(const ViewTracer& vt, ViewTracer::Band& band, const ViewTracer::Start* st,
               const size_t* ks, size_t n, Hits& out) {
    if (n == 0) return;
    Batch<Avx2>(vt, band, st, ks, n, out).run();
}

}  // namespace pxh::band_walk

#if defined(__clang__)
#pragma clang attribute pop
#else
#pragma GCC pop_options
#endif
