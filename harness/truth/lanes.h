// Lanes of doubles (issue 62, item 2): one small type per vector width, with the same
// operations, so that a kernel written once over `L` (L::N lanes) is compiled for each width
// without a per-ISA copy. Each operation is the IEEE operation of the scalar code, lane by lane
// (no fused multiply-add; min and max as std::min and std::max: the first argument unless the
// second is strictly smaller or larger), so a lane computes the scalar expression's double to
// the bit.
//
// Include this header only after `#pragma GCC target(...)` has enabled the width's
// instructions, with PXH_LANES_AVX512 or PXH_LANES_AVX2 defined to say which (the kernel's
// translation unit: see curved_pyramid_avx512.cpp; GCC 12 does not define __AVX512F__ after the
// pragma): a type is defined only there, and everything here has internal linkage, so no inline
// function compiled for one width can stand in for another's.
#pragma once
#include <immintrin.h>

#include <cstdint>

namespace pxh {
namespace {

#if defined(PXH_LANES_AVX512)
// 8 doubles (AVX-512F and DQ).
struct Lanes8 {
    static constexpr int N = 8;
    using D = __m512d;
    using M = __mmask8;
    static D load(const double* p) { return _mm512_loadu_pd(p); }
    static void store(double* p, D a) { _mm512_storeu_pd(p, a); }
    static D set(double a) { return _mm512_set1_pd(a); }
    static D add(D a, D b) { return _mm512_add_pd(a, b); }
    static D sub(D a, D b) { return _mm512_sub_pd(a, b); }
    static D mul(D a, D b) { return _mm512_mul_pd(a, b); }
    static D div(D a, D b) { return _mm512_div_pd(a, b); }
    static D sqrt(D a) { return _mm512_sqrt_pd(a); }
    static D abs(D a) {
        return _mm512_castsi512_pd(
            _mm512_and_si512(_mm512_castpd_si512(a), _mm512_set1_epi64(0x7fffffffffffffffLL)));
    }
    static D neg(D a) {
        return _mm512_castsi512_pd(
            _mm512_xor_si512(_mm512_castpd_si512(a), _mm512_set1_epi64(int64_t(1ULL << 63))));
    }
    // the magnitude of a with the sign of b (std::copysign)
    static D copysign(D a, D b) {
        const __m512i m = _mm512_set1_epi64(int64_t(1ULL << 63));
        return _mm512_castsi512_pd(_mm512_or_si512(_mm512_andnot_si512(m, _mm512_castpd_si512(a)),
                                                   _mm512_and_si512(m, _mm512_castpd_si512(b))));
    }
    static D floor(D a) {
        return _mm512_roundscale_pd(a, _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC);
    }
    // comparisons as C's operators: false with a NaN, except ne
    static M lt(D a, D b) { return _mm512_cmp_pd_mask(a, b, _CMP_LT_OQ); }
    static M le(D a, D b) { return _mm512_cmp_pd_mask(a, b, _CMP_LE_OQ); }
    static M gt(D a, D b) { return _mm512_cmp_pd_mask(a, b, _CMP_GT_OQ); }
    static M ge(D a, D b) { return _mm512_cmp_pd_mask(a, b, _CMP_GE_OQ); }
    static M eq(D a, D b) { return _mm512_cmp_pd_mask(a, b, _CMP_EQ_OQ); }
    static M ne(D a, D b) { return _mm512_cmp_pd_mask(a, b, _CMP_NEQ_UQ); }
    static M mand(M a, M b) { return M(a & b); }
    static M mor(M a, M b) { return M(a | b); }
    static M mnot(M a) { return M(~a); }
    static M mandnot(M a, M b) { return M(a & ~b); }  // a and not b
    static bool any(M a) { return a != 0; }
    static unsigned bits(M a) { return unsigned(a); }
    static M from_bits(unsigned b) { return M(b); }
    // m ? a : b, lane by lane
    static D select(M m, D a, D b) { return _mm512_mask_blend_pd(m, b, a); }
    // table[i], i the lanes' values (whole numbers in the table's range)
    static D lookup(const double* table, D i) {
        return _mm512_i64gather_pd(_mm512_cvttpd_epi64(i), table, 8);
    }
    // double(table[i])
    static D lookup(const float* table, D i) {
        return _mm512_cvtps_pd(_mm512_i64gather_ps(_mm512_cvttpd_epi64(i), table, 4));
    }
    // table[i] of a table of 16 (i in 0 .. 15): a permute of two registers, not a gather
    static D lookup16(const double* table, D i) {
        return _mm512_permutex2var_pd(_mm512_loadu_pd(table), _mm512_cvttpd_epi64(i),
                                      _mm512_loadu_pd(table + 8));
    }
};
#endif

#if defined(PXH_LANES_AVX2)
// 4 doubles (AVX2).
struct Lanes4 {
    static constexpr int N = 4;
    using D = __m256d;
    using M = __m256d;  // all ones or all zeros per lane
    static D load(const double* p) { return _mm256_loadu_pd(p); }
    static void store(double* p, D a) { _mm256_storeu_pd(p, a); }
    static D set(double a) { return _mm256_set1_pd(a); }
    static D add(D a, D b) { return _mm256_add_pd(a, b); }
    static D sub(D a, D b) { return _mm256_sub_pd(a, b); }
    static D mul(D a, D b) { return _mm256_mul_pd(a, b); }
    static D div(D a, D b) { return _mm256_div_pd(a, b); }
    static D sqrt(D a) { return _mm256_sqrt_pd(a); }
    static D abs(D a) { return _mm256_andnot_pd(_mm256_set1_pd(-0.0), a); }
    static D neg(D a) { return _mm256_xor_pd(a, _mm256_set1_pd(-0.0)); }
    static D copysign(D a, D b) {
        const D m = _mm256_set1_pd(-0.0);
        return _mm256_or_pd(_mm256_andnot_pd(m, a), _mm256_and_pd(m, b));
    }
    static D floor(D a) { return _mm256_floor_pd(a); }
    static M lt(D a, D b) { return _mm256_cmp_pd(a, b, _CMP_LT_OQ); }
    static M le(D a, D b) { return _mm256_cmp_pd(a, b, _CMP_LE_OQ); }
    static M gt(D a, D b) { return _mm256_cmp_pd(a, b, _CMP_GT_OQ); }
    static M ge(D a, D b) { return _mm256_cmp_pd(a, b, _CMP_GE_OQ); }
    static M eq(D a, D b) { return _mm256_cmp_pd(a, b, _CMP_EQ_OQ); }
    static M ne(D a, D b) { return _mm256_cmp_pd(a, b, _CMP_NEQ_UQ); }
    static M mand(M a, M b) { return _mm256_and_pd(a, b); }
    static M mor(M a, M b) { return _mm256_or_pd(a, b); }
    static M mnot(M a) { return _mm256_xor_pd(a, _mm256_castsi256_pd(_mm256_set1_epi64x(-1))); }
    static M mandnot(M a, M b) { return _mm256_andnot_pd(b, a); }
    static bool any(M a) { return _mm256_movemask_pd(a) != 0; }
    static unsigned bits(M a) { return unsigned(_mm256_movemask_pd(a)); }
    static M from_bits(unsigned b) {
        const __m256i lane = _mm256_set_epi64x(8, 4, 2, 1);
        const __m256i m = _mm256_and_si256(_mm256_set1_epi64x(int64_t(b)), lane);
        return _mm256_castsi256_pd(_mm256_cmpeq_epi64(m, lane));
    }
    static D select(M m, D a, D b) { return _mm256_blendv_pd(b, a, m); }
    // four loads, not a gather (on AMD's Zen 3 the quicker, measured)
    static D lookup(const double* table, D i) {
        alignas(16) int32_t k[4];
        _mm_store_si128(reinterpret_cast<__m128i*>(k), _mm256_cvttpd_epi32(i));
        return _mm256_setr_pd(table[k[0]], table[k[1]], table[k[2]], table[k[3]]);
    }
    static D lookup(const float* table, D i) {
        alignas(16) int32_t k[4];
        _mm_store_si128(reinterpret_cast<__m128i*>(k), _mm256_cvttpd_epi32(i));
        return _mm256_cvtps_pd(_mm_setr_ps(table[k[0]], table[k[1]], table[k[2]], table[k[3]]));
    }
    static D lookup16(const double* table, D i) { return lookup(table, i); }
};
#endif

}  // namespace
}  // namespace pxh
