/* fix.h — the named fixed-point formats shared by the GP's output and the VP,
 * and the exact integer helpers both sides use.  Every format here is
 * described bit by bit in docs/number-formats.md; a change here is a change
 * to the golden vectors. */
#ifndef ALBATROS_FIX_H
#define ALBATROS_FIX_H

#include <stdint.h>

/* Edge intercepts (docs/number-formats.md §1): unsigned 3.F after the +3
 * origin shift of the paper (§6 of the digest), F = profile edge_frac_bits. */
#define EDGE_INT_BITS   3
#define EDGE_ORIGIN     3            /* X -> X + 3 puts (-3,3) into (0,6) */
#define EDGE_FRAC_MIN   4
#define EDGE_FRAC_MAX   27           /* 3 + F <= 30 bits of the edge word */

/* Linear forms (docs/number-formats.md §2): block floating point, three signed
 * mantissas of coef_bits sharing one exponent. */
#define COEF_BITS_MIN   8
#define COEF_BITS_MAX   30
#define FORM_EXP_MIN    (-128)
#define FORM_EXP_MAX    127

/* floor(x / 2^s) without relying on the implementation-defined right shift of
 * negative numbers (C11 6.5.7p5): the VP's rounding rule "truncate toward
 * minus infinity" must not depend on the compiler. */
static inline int64_t fix_floor_shr(int64_t x, unsigned s)
{
    if (s >= 63)
        return x < 0 ? -1 : 0;
    return x >= 0 ? x >> s : -(int64_t)(((uint64_t)(-(x + 1)) >> s) + 1);
}

/* Number of significant bits of v (0 for 0): a priority encoder. */
static inline unsigned fix_bitlen(uint64_t v)
{
    return v ? 64u - (unsigned)__builtin_clzll(v) : 0;
}

/* Saturating x * 2^s for s >= 0, clamped to [lo, hi]. */
static inline int64_t fix_shl_sat(int64_t x, unsigned s, int64_t lo, int64_t hi)
{
    if (x == 0)
        return 0;
    if (s >= 62)
        return x > 0 ? hi : lo;
    if (x > 0)
        return x > (hi >> s) ? hi : x << s;
    return x < -((-lo) >> s) ? lo : -((-x) << s);
}

static inline int64_t fix_clamp(int64_t x, int64_t lo, int64_t hi)
{
    return x < lo ? lo : x > hi ? hi : x;
}

static inline int fix_is_pow2(unsigned v) { return v && !(v & (v - 1)); }

static inline unsigned fix_log2(unsigned v)
{
    unsigned n = 0;
    while (v > 1) {
        v >>= 1;
        n++;
    }
    return n;
}

#endif
