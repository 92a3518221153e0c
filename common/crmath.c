/* crmath.c — correctly rounded sin, cos, tan and hypot (crmath.h).
 *
 * sin, cos, tan: Ziv's strategy in multi-precision fixed point.  At a
 * precision of n 32-bit limbs of fraction the argument is reduced by k pi/2
 * (pi computed here by Machin's formula, pi/4 = 4 atan 1/5 - atan 1/239, so
 * the file holds no table of digits), the Taylor series is summed, and every
 * truncation is counted into an error bound E in units of the last place.  If
 * the value minus E and the value plus E round to the same double, that
 * double is the correctly rounded result (rounding is monotonic); if not, the
 * precision doubles.  sin, cos and tan of a non-zero double are
 * transcendental (Lindemann), so they are never a midpoint and the loop ends.
 *
 * hypot: exact integer arithmetic, sqrt(A^2 2^2d + B^2) by the digit-by-digit
 * integer square root, rounded once.
 *
 * frexp and ldexp only split and scale by powers of two, exactly; nothing
 * else of the C library's maths is used. */
#include "crmath.h"

#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include <string.h>

#define LIMBS_MIN 4
#define LIMBS_MAX 64
/* Below these the result is x (sin, tan) or 1 (cos): the next term of the
 * series changes it by less than half its spacing (see trig). */
#define TINY_SIN 0x1p-26
#define TINY     0x1p-27          /* cos, tan */
#define DOMAIN   0x1p30

/* ---- unsigned fixed point: w[0..n-1] the fraction (little-endian limbs),
 * w[n] the integer part; value = sum w[i] 2^(32 (i - n)).  One unit of w[0]
 * is an "ulp" below. ---- */

typedef struct {
    unsigned n;
    uint32_t w[LIMBS_MAX + 1];
} fx;

static void fx_zero(fx *a, unsigned n)
{
    a->n = n;
    memset(a->w, 0, sizeof a->w);
}

static bool fx_is_zero(const fx *a)
{
    for (unsigned i = 0; i <= a->n; i++)
        if (a->w[i])
            return false;
    return true;
}

static int fx_cmp(const fx *a, const fx *b)
{
    for (unsigned i = a->n + 1; i-- > 0;)
        if (a->w[i] != b->w[i])
            return a->w[i] < b->w[i] ? -1 : 1;
    return 0;
}

static void fx_add(fx *r, const fx *a, const fx *b)
{
    uint64_t carry = 0;
    r->n = a->n;
    for (unsigned i = 0; i <= a->n; i++) {
        uint64_t s = (uint64_t)a->w[i] + b->w[i] + carry;
        r->w[i] = (uint32_t)s;
        carry = s >> 32;
    }
}

/* r = a - b, a >= b */
static void fx_sub(fx *r, const fx *a, const fx *b)
{
    uint64_t borrow = 0;
    r->n = a->n;
    for (unsigned i = 0; i <= a->n; i++) {
        uint64_t d = (uint64_t)a->w[i] - b->w[i] - borrow;
        r->w[i] = (uint32_t)d;
        borrow = d >> 63;
    }
}

/* r = a * b truncated: error below one ulp.  Values stay below 2^32. */
static void fx_mul(fx *r, const fx *a, const fx *b)
{
    uint32_t t[2 * (LIMBS_MAX + 1)];
    unsigned n = a->n;
    memset(t, 0, sizeof t);
    for (unsigned i = 0; i <= n; i++) {
        uint64_t carry = 0;
        for (unsigned j = 0; j <= n; j++) {
            uint64_t p = (uint64_t)a->w[i] * b->w[j] + t[i + j] + carry;
            t[i + j] = (uint32_t)p;
            carry = p >> 32;
        }
        t[i + n + 1] = (uint32_t)carry;
    }
    r->n = n;
    for (unsigned k = 0; k <= n; k++)
        r->w[k] = t[k + n];
}

/* r = a * m, exact while it fits */
static void fx_mul_small(fx *r, const fx *a, uint32_t m)
{
    uint64_t carry = 0;
    r->n = a->n;
    for (unsigned i = 0; i <= a->n; i++) {
        uint64_t p = (uint64_t)a->w[i] * m + carry;
        r->w[i] = (uint32_t)p;
        carry = p >> 32;
    }
}

/* r = a / d truncated: error below one ulp */
static void fx_div_small(fx *r, const fx *a, uint32_t d)
{
    uint64_t rem = 0;
    r->n = a->n;
    for (unsigned i = a->n + 1; i-- > 0;) {
        uint64_t cur = rem << 32 | a->w[i];
        r->w[i] = (uint32_t)(cur / d);
        rem = cur % d;
    }
}

/* r = a small integer number of ulps */
static void fx_ulps(fx *r, unsigned n, uint64_t e)
{
    fx_zero(r, n);
    r->w[0] = (uint32_t)e;
    r->w[1] = (uint32_t)(e >> 32);
}

/* x >= 0 below 2^32 with no bit below 2^(-32 n): exactly */
static void fx_from_double(fx *r, double x, unsigned n)
{
    int e;
    fx_zero(r, n);
    if (x == 0)
        return;
    uint64_t m = (uint64_t)ldexp(frexp(x, &e), 53);   /* x = m 2^(e - 53) */
    int s = e - 53 + 32 * (int)n;                       /* position of m's bit 0 */
    for (int b = 0; b < 53; b++)
        if (m >> b & 1)
            r->w[(unsigned)(s + b) / 32] |= 1u << ((unsigned)(s + b) % 32);
}

/* ---- big unsigned integers, little-endian limbs, and their rounding ---- */

static unsigned big_bit(const uint32_t *w, unsigned i) { return w[i / 32] >> (i % 32) & 1; }

/* Index of the top set bit, -1 for zero. */
static int big_top(const uint32_t *w, unsigned nl)
{
    for (unsigned i = nl; i-- > 0;)
        if (w[i])
            for (int b = 31; b >= 0; b--)
                if (w[i] >> b & 1)
                    return (int)i * 32 + b;
    return -1;
}

/* The integer w[0..nl) times 2^exp2, rounded to nearest even; `sticky` says
 * that non-zero bits follow below w (an inexact value above w). */
static double big_to_double(const uint32_t *w, unsigned nl, int exp2, bool sticky)
{
    int top = big_top(w, nl);
    if (top < 0)
        return 0;
    uint64_t m = 0;
    int low = top - 52;           /* the last bit kept */
    for (int i = top; i >= low && i >= 0; i--)
        m = m << 1 | big_bit(w, (unsigned)i);
    if (low <= 0)
        return ldexp((double)m, exp2 + (low < 0 ? 0 : low));
    bool half = big_bit(w, (unsigned)(low - 1)), rest = sticky;
    for (int i = low - 2; i >= 0 && !rest; i--)
        rest = big_bit(w, (unsigned)i);
    if (half && (rest || (m & 1)))
        m++;                      /* 2^53 stays exact */
    return ldexp((double)m, exp2 + low);
}

/* The rounding test: value a with error at most e ulps, as a double, or NaN
 * when a - e and a + e round apart. */
static double fx_round_test(const fx *a, uint64_t e)
{
    fx ef, lo, hi;
    fx_ulps(&ef, a->n, e);
    if (fx_cmp(a, &ef) < 0)
        return NAN;
    fx_sub(&lo, a, &ef);
    fx_add(&hi, a, &ef);
    int exp2 = -32 * (int)a->n;
    double dl = big_to_double(lo.w, a->n + 1, exp2, false);
    double dh = big_to_double(hi.w, a->n + 1, exp2, false);
    return dl == dh ? dl : NAN;
}

/* ---- pi/2 and the series ---- */

/* atan(1/m) = sum (-1)^k / ((2k + 1) m^(2k + 1)); *err += its error bound.
 * The power p carries under 2 ulps (e' <= e/m^2 + 1), a term under 3, and
 * the series stops at a term that truncates to 0 (so is under 3 ulps). */
static void atan_inv(fx *r, uint32_t m, unsigned n, uint64_t *err)
{
    fx p, t, pos, neg;
    fx_zero(&p, n);
    p.w[n] = 1;
    fx_div_small(&p, &p, m);
    pos = p;
    fx_zero(&neg, n);
    uint64_t terms = 1;
    for (uint32_t k = 1;; k++) {
        fx_div_small(&p, &p, m * m);
        fx_div_small(&t, &p, 2 * k + 1);
        if (fx_is_zero(&t))
            break;
        fx_add(k & 1 ? &neg : &pos, k & 1 ? &neg : &pos, &t);
        terms++;
    }
    fx_sub(r, &pos, &neg);
    *err += 3 * terms + 3;
}

/* pi/2 = 8 atan(1/5) - 2 atan(1/239) */
static void half_pi(fx *r, unsigned n, uint64_t *err)
{
    fx a, b;
    uint64_t ea = 0, eb = 0;
    atan_inv(&a, 5, n, &ea);
    atan_inv(&b, 239, n, &eb);
    fx_mul_small(&a, &a, 8);
    fx_mul_small(&b, &b, 2);
    fx_sub(r, &a, &b);
    *err += 8 * ea + 2 * eb;
}

/* Taylor series of sin r (odd = 1) or cos r (odd = 0) for 0 <= r < 1, r
 * exact; *err += the arithmetic's error bound.  Each term is the previous
 * times r^2 / ((j+1)(j+2)): with r^2 under one ulp off, a term's error obeys
 * e' <= e/6 + 1/6 + 2, so stays under 3 ulps; the sum is exact, and the
 * alternating tail after a term that truncates to 0 is under 3 ulps. */
static void series(fx *out, const fx *r, bool odd, uint64_t *err)
{
    unsigned n = r->n;
    fx r2, t, pos, neg;
    fx_mul(&r2, r, r);
    if (odd) {
        t = *r;
    } else {
        fx_zero(&t, n);
        t.w[n] = 1;
    }
    pos = t;
    fx_zero(&neg, n);
    uint64_t terms = 1;
    for (uint32_t j = odd ? 1 : 0, sign = 1;; j += 2, sign ^= 1) {
        fx_mul(&t, &t, &r2);
        fx_div_small(&t, &t, (j + 1) * (j + 2));
        if (fx_is_zero(&t))
            break;
        fx_add(sign ? &neg : &pos, sign ? &neg : &pos, &t);
        terms++;
    }
    fx_sub(out, &pos, &neg);
    *err += 3 * terms + 3;
}

/* The quotient a / b of two fixed-point values with errors ea, eb (ulps) as
 * a double, or NaN when its rounding is not decided at this precision:
 * Q = floor(a 2^sh / b) by long division, sh = 32 n + 64 bits so that Q has
 * at least 32 n bits for every quotient of this domain (above 2^-62). */
#define QLIMBS (2 * LIMBS_MAX + 4)
static double fx_div_round(const fx *a, uint64_t ea, const fx *b, uint64_t eb)
{
    unsigned n = a->n, nl = 2 * n + 3, sh = 32 * n + 64;
    uint32_t num[QLIMBS], q[QLIMBS], rem[LIMBS_MAX + 3];
    memset(num, 0, sizeof num);
    memset(q, 0, sizeof q);
    memset(rem, 0, sizeof rem);
    for (unsigned i = 0; i <= n; i++)
        num[i + sh / 32] = a->w[i];
    unsigned rl = n + 2;          /* rem < 2 b: one limb above b */
    for (int i = big_top(num, nl); i >= 0; i--) {
        uint32_t carry = big_bit(num, (unsigned)i);
        for (unsigned k = 0; k < rl; k++) {
            uint32_t out = rem[k] >> 31;
            rem[k] = rem[k] << 1 | carry;
            carry = out;
        }
        /* rem >= b ? */
        int c = 0;
        for (unsigned k = rl; k-- > 0 && !c;) {
            uint32_t bk = k <= n ? b->w[k] : 0;
            c = rem[k] != bk ? (rem[k] > bk ? 1 : -1) : 0;
        }
        if (c >= 0) {
            uint64_t borrow = 0;
            for (unsigned k = 0; k < rl; k++) {
                uint64_t d = (uint64_t)rem[k] - (k <= n ? b->w[k] : 0) - borrow;
                rem[k] = (uint32_t)d;
                borrow = d >> 63;
            }
            q[(unsigned)i / 32] |= 1u << ((unsigned)i % 32);
        }
    }
    /* relative error of a/b at most (ea/a + eb/b) ulp (to first order; the
     * factor 2 covers the second order and the doubles' own rounding),
     * computed on values scaled to about 1 so that no double overflows */
    int ulp = -32 * (int)n;
    double ad = big_to_double(a->w, n + 1, ulp, false), bd = big_to_double(b->w, n + 1, ulp, false);
    double qd = big_to_double(q, nl, -(int)sh, false);
    double rel = 2 * ((double)ea / ad + (double)eb / bd);   /* in ulps */
    if (!(ldexp(rel, ulp) < 0.125))
        return NAN;               /* not even the leading bits are known */
    double eq = ldexp(qd * rel, (int)sh + ulp) + 2;          /* in units of Q */
    /* E = eq rounded up to an integer of at most 53 significant bits */
    int ee;
    uint64_t em = (uint64_t)ldexp(frexp(eq, &ee), 53) + 1;
    uint32_t ebig[QLIMBS], lo[QLIMBS], hi[QLIMBS];
    memset(ebig, 0, sizeof ebig);
    for (int bit = 0; bit < 54; bit++)
        if (em >> bit & 1 && ee - 53 + bit >= 0)
            ebig[(unsigned)(ee - 53 + bit) / 32] |= 1u << ((unsigned)(ee - 53 + bit) % 32);
    if (ee - 53 < 0)
        ebig[0] |= 1;             /* the bits shifted out, rounded up */
    uint64_t borrow = 0, carry = 0;
    for (unsigned k = 0; k < nl; k++) {
        uint64_t d = (uint64_t)q[k] - ebig[k] - borrow, s = (uint64_t)q[k] + ebig[k] + carry;
        lo[k] = (uint32_t)d;
        borrow = d >> 63;
        hi[k] = (uint32_t)s;
        carry = s >> 32;
    }
    if (borrow)
        return NAN;
    double dl = big_to_double(lo, nl, -(int)sh, false), dh = big_to_double(hi, nl, -(int)sh, false);
    return dl == dh ? dl : NAN;
}

/* One step of the Ziv loop at n limbs for |x| in [TINY, DOMAIN): the
 * magnitude of the result (the caller applies the sign), or NaN. */
static double trig_step(char fn, double ax, unsigned n, bool *negate)
{
    fx hp, kp, x, r, s, c;
    uint64_t ehp = 0;
    half_pi(&hp, n, &ehp);
    /* k = nearest integer to x / (pi/2): any k leaves |r| < 1 here */
    double kd = floor(ax * 0.63661977236758134 + 0.5);
    uint32_t k = (uint32_t)kd;
    fx_mul_small(&kp, &hp, k);
    fx_from_double(&x, ax, n);
    bool rneg = fx_cmp(&x, &kp) < 0;
    if (rneg)
        fx_sub(&r, &kp, &x);
    else
        fx_sub(&r, &x, &kp);
    /* r is off by at most k ehp ulps; sin, cos are 1-Lipschitz, so that adds
     * to each series' own error */
    uint64_t er = (uint64_t)k * ehp, es = er, ec = er;
    unsigned q = k & 3;
    *negate = false;
    if (fn == 's' || fn == 'c') {
        /* sin(k pi/2 + r), cos(k pi/2 + r) by the quadrant */
        bool use_sin = fn == 's' ? (q & 1) == 0 : (q & 1) == 1;
        if (use_sin) {
            series(&s, &r, true, &es);
            *negate = (fn == 's' ? q == 2 : q == 1) != rneg;
            return fx_round_test(&s, es);
        }
        series(&c, &r, false, &ec);
        *negate = fn == 's' ? q == 3 : q == 2;
        return fx_round_test(&c, ec);
    }
    /* tan(k pi/2 + r) = tan r (k even), -1 / tan r (k odd) */
    series(&s, &r, true, &es);
    series(&c, &r, false, &ec);
    if (fx_is_zero(&s) || fx_is_zero(&c))
        return NAN;
    *negate = (q & 1) != rneg;
    return q & 1 ? fx_div_round(&c, ec, &s, es) : fx_div_round(&s, es, &c, ec);
}

int cr_trig_step(char fn, double x, unsigned limbs, double *out)
{
    double ax = fabs(x);
    if (!(ax >= TINY && ax < DOMAIN) || limbs < LIMBS_MIN || limbs > LIMBS_MAX)
        return -1;
    bool negate;
    double v = trig_step(fn, ax, limbs, &negate);
    if (isnan(v))
        return -1;
    if (fn != 'c' && x < 0)
        negate = !negate;       /* sin and tan are odd, cos even */
    *out = negate ? -v : v;
    return 0;
}

static double trig(char fn, double x)
{
    double ax = fabs(x), v;
    if (!(ax < DOMAIN))
        return NAN;             /* infinities, NaNs and the unreduced */
    /* Tiny x: sin x = x (1 - x^2/6 ...) for |x| < 2^-26, tan x = x (1 +
     * x^2/3 ...) and cos x = 1 - x^2/2 ... for |x| < 2^-27: the change is
     * below 2^-54 of the result, less than half its spacing on either side
     * (at least 2^-54 relative), so rounding gives x or 1 (x = 0 keeps its
     * sign). */
    if (fn == 's' ? ax < TINY_SIN : ax < TINY)
        return fn == 'c' ? 1 : x;
    for (unsigned n = LIMBS_MIN; n <= LIMBS_MAX; n *= 2)
        if (!cr_trig_step(fn, x, n, &v))
            return v;
    return NAN;   /* not reached: a transcendental value is decided by 2048 bits */
}

double cr_sin(double x) { return trig('s', x); }
double cr_cos(double x) { return trig('c', x); }
double cr_tan(double x) { return trig('t', x); }

/* ---- hypot ---- */

#define HL 10   /* limbs: 2 * 53 + 2 * 60 + 2 bits and the square root's work */

static void big_shl(uint32_t *a, unsigned s)
{
    for (; s >= 32; s -= 32) {
        memmove(a + 1, a, (HL - 1) * sizeof *a);
        a[0] = 0;
    }
    if (!s)
        return;
    for (unsigned i = HL; i-- > 1;)
        a[i] = a[i] << s | a[i - 1] >> (32 - s);
    a[0] <<= s;
}

static void big_shr(uint32_t *a, unsigned s)
{
    for (unsigned i = 0; i < HL; i++)
        a[i] = a[i] >> s | (i + 1 < HL && s ? a[i + 1] << (32 - s) : 0);
}

static int big_cmp(const uint32_t *a, const uint32_t *b)
{
    for (unsigned i = HL; i-- > 0;)
        if (a[i] != b[i])
            return a[i] < b[i] ? -1 : 1;
    return 0;
}

static void big_add(uint32_t *r, const uint32_t *a, const uint32_t *b)
{
    uint64_t carry = 0;
    for (unsigned i = 0; i < HL; i++) {
        uint64_t s = (uint64_t)a[i] + b[i] + carry;
        r[i] = (uint32_t)s;
        carry = s >> 32;
    }
}

static void big_sub(uint32_t *r, const uint32_t *a, const uint32_t *b)
{
    uint64_t borrow = 0;
    for (unsigned i = 0; i < HL; i++) {
        uint64_t d = (uint64_t)a[i] - b[i] - borrow;
        r[i] = (uint32_t)d;
        borrow = d >> 63;
    }
}

static void big_square53(uint32_t *r, uint64_t m)
{
    uint32_t a[2] = {(uint32_t)m, (uint32_t)(m >> 32)};
    memset(r, 0, HL * sizeof *r);
    for (unsigned i = 0; i < 2; i++) {
        uint64_t carry = 0;
        for (unsigned j = 0; j < 2; j++) {
            uint64_t p = (uint64_t)a[i] * a[j] + r[i + j] + carry;
            r[i + j] = (uint32_t)p;
            carry = p >> 32;
        }
        r[i + 2] = (uint32_t)carry;
    }
}

double cr_hypot(double x, double y)
{
    double a = fabs(x), b = fabs(y);
    if (isinf(a) || isinf(b))
        return INFINITY;
    if (isnan(a) || isnan(b))
        return a + b;
    if (a < b) {
        double t = a;
        a = b;
        b = t;
    }
    if (b == 0)
        return a;
    int ea, eb;
    uint64_t ma = (uint64_t)ldexp(frexp(a, &ea), 53), mb = (uint64_t)ldexp(frexp(b, &eb), 53);
    /* b below 2^-60 of a: hypot = a (1 + (b/a)^2/2 ...), a change under
     * 2^-119 of a, far below half an ulp */
    if (ea - eb > 60)
        return a;
    /* a^2 + b^2 = S 2^(2 (eb - 53)), S = ma^2 4^(ea - eb) + mb^2 exactly */
    uint32_t s[HL], t[HL];
    big_square53(s, ma);
    big_shl(s, 2 * (unsigned)(ea - eb));
    big_square53(t, mb);
    big_add(s, s, t);
    /* scale by 4^j so that the root has at least 56 bits, then take
     * floor(sqrt) digit by digit, with the remainder's sticky bit */
    int top = big_top(s, HL), j = top < 112 ? (112 - top) / 2 + 1 : 0;
    big_shl(s, 2 * (unsigned)j);
    top = big_top(s, HL);
    uint32_t bit[HL], root[HL], sum[HL];
    memset(bit, 0, sizeof bit);
    memset(root, 0, sizeof root);
    unsigned bpos = (unsigned)top & ~1u;
    bit[bpos / 32] = 1u << (bpos % 32);
    for (;;) {
        big_add(sum, root, bit);
        big_shr(root, 1);
        if (big_cmp(s, sum) >= 0) {
            big_sub(s, s, sum);
            big_add(root, root, bit);
        }
        if (bpos < 2)
            break;
        big_shr(bit, 2);
        bpos -= 2;
    }
    bool inexact = big_top(s, HL) >= 0;
    return big_to_double(root, HL, eb - 53 - j, inexact);
}

/* ---- degrees ---- */

double cr_deg_reduce(double deg)
{
    double r = fabs(deg);
    if (!(r >= 360) || isinf(r))
        return isinf(r) ? NAN : deg;
    double m = 360;
    while (m <= r / 2)
        m *= 2;                 /* 360 2^k <= r < 360 2^(k+1) */
    for (; m >= 360; m /= 2)
        if (r >= m)
            r -= m;             /* m <= r < 2m: exact (Sterbenz) */
    return deg < 0 ? -r : r;
}
