/* simd.h — two 64-bit lanes for the VP's edge and depth arithmetic: SSE2
 * where the host has it (every x86-64), else plain C.  Integer operations
 * only, so both give the same bits; building with -DALB_NO_SIMD takes the
 * plain one everywhere (make crosscheck runs the golden vectors so). */
#ifndef ALBATROS_VP_SIMD_H
#define ALBATROS_VP_SIMD_H

#include <stdint.h>

#if defined(__SSE2__) && !defined(ALB_NO_SIMD)
#define VP_SSE2 1
#include <emmintrin.h>

typedef __m128i v2;
/* lanes (lo, hi) */
static inline v2 v2_set(int64_t lo, int64_t hi) { return _mm_set_epi64x(hi, lo); }
static inline v2 v2_splat(int64_t x) { return _mm_set1_epi64x(x); }
static inline v2 v2_add(v2 a, v2 b) { return _mm_add_epi64(a, b); }
/* bit k set where lane k is negative */
static inline unsigned v2_neg(v2 a) { return (unsigned)_mm_movemask_pd(_mm_castsi128_pd(a)); }

#else
#define VP_SSE2 0

typedef struct {
    int64_t lo, hi;
} v2;
static inline v2 v2_set(int64_t lo, int64_t hi) { return (v2){lo, hi}; }
static inline v2 v2_splat(int64_t x) { return (v2){x, x}; }
/* wrapping, as the SSE2 lanes: unsigned addition */
static inline v2 v2_add(v2 a, v2 b)
{
    return (v2){(int64_t)((uint64_t)a.lo + (uint64_t)b.lo), (int64_t)((uint64_t)a.hi + (uint64_t)b.hi)};
}
static inline unsigned v2_neg(v2 a) { return (unsigned)(a.lo < 0) | (unsigned)(a.hi < 0) << 1; }

#endif

/* Set bits of a mask, in plain C: the baseline x86-64 has no POPCNT, and
 * __builtin_popcount would call the compiler's library. */
static inline unsigned vp_popcount(uint64_t m)
{
    m -= (m >> 1) & 0x5555555555555555ull;
    m = (m & 0x3333333333333333ull) + ((m >> 2) & 0x3333333333333333ull);
    m = (m + (m >> 4)) & 0x0F0F0F0F0F0F0F0Full;
    return (unsigned)((m * 0x0101010101010101ull) >> 56);
}

/* Set bits of a 4-bit mask. */
static inline unsigned vp_bits4(unsigned m) { return (0x4332322132212110ull >> (4 * m)) & 0xF; }

/* AVX2 code compiled where the compiler can target it (gcc, clang on
 * x86-64) and run where the host has it (__builtin_cpu_supports). */
#if VP_SSE2 && defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define VP_AVX2 1
#else
#define VP_AVX2 0
#endif

#endif
