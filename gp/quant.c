/* quant.c — the GP's output arithmetic: culling of edge lines (eq. 18), the
 * U|R|X1|X2 format with the +3 shift (§6), block floating-point forms, and
 * the solution of system (11).  Double precision, no fused multiply-add
 * (the Makefile passes -ffp-contract=off); every rounding is the one of
 * docs/number-formats.md. */
#include "gp_internal.h"
#include "../common/vec3.h"
#include "../common/fix.h"

#include <math.h>

gp_line_class gp_classify_line(gp_line l)
{
    /* eq. (18): the line misses the square |x|,|y| <= 1 iff |A| + |B| < |C|;
     * then f(0,0) = C tells on which side the screen lies (Fig. 1). */
    if (fabs(l.a) + fabs(l.b) < fabs(l.c))
        return l.c > 0 ? LINE_DROP_EDGE : LINE_DROP_FACE;
    return LINE_CROSSES;
}

uint32_t gp_quantise_intercept(double x, unsigned frac_bits)
{
    /* Round half up: floor(v * 2^F + 1/2).  v * 2^F is exact (a power of two
     * scale) and below 2^31, so adding 1/2 is exact too. */
    double v = (x + EDGE_ORIGIN) * ldexp(1.0, (int)frac_bits);
    double max = ldexp(1.0, (int)(EDGE_INT_BITS + frac_bits)) - 1;
    if (!(v >= 0))          /* negative or NaN */
        return 0;
    double q = floor(v + 0.5);
    return (uint32_t)(q > max ? max : q);
}

alb_ws_edge gp_edge_format(gp_line l, unsigned frac_bits)
{
    alb_ws_edge e;
    e.u = (uint8_t)gp_line_u(l);
    if (e.u) {
        /* vertical: x at y = -1 and y = +1 */
        e.r = (uint8_t)gp_sgn(l.a);
        e.x1 = gp_quantise_intercept((l.b - l.c) / l.a, frac_bits);
        e.x2 = gp_quantise_intercept((-l.b - l.c) / l.a, frac_bits);
    } else {
        /* horizontal: y at x = -1 and x = +1 */
        e.r = (uint8_t)gp_sgn(l.b);
        e.x1 = gp_quantise_intercept((l.a - l.c) / l.b, frac_bits);
        e.x2 = gp_quantise_intercept((-l.a - l.c) / l.b, frac_bits);
    }
    return e;
}

alb_ws_edge gp_bound_format(unsigned u, unsigned r, double v, unsigned frac_bits)
{
    alb_ws_edge e;
    e.u = (uint8_t)u;
    e.r = (uint8_t)r;
    e.x1 = e.x2 = gp_quantise_intercept(v, frac_bits);
    return e;
}

/* Round half away from zero. */
static int64_t round_away(double v) { return (int64_t)(v < 0 ? -floor(-v + 0.5) : floor(v + 0.5)); }

alb_ws_form gp_quantise_form(double a, double b, double c, unsigned coef_bits, int *saturated)
{
    alb_ws_form f = {0, {0, 0, 0}};
    double v[3] = {a, b, c};
    double m = fmax(fabs(a), fmax(fabs(b), fabs(c)));
    int64_t lim = ((int64_t)1 << (coef_bits - 1)) - 1;
    if (m == 0 || !isfinite(m)) {
        if (!isfinite(m) && saturated)
            *saturated = 1;
        f.exp = 0;
        return f;
    }
    /* m = g * 2^k, g in [0.5, 1): the smallest exponent with every mantissa
     * below 2^(coef_bits-1) is k - (coef_bits - 1), one more if rounding the
     * largest reaches 2^(coef_bits-1). */
    int k;
    frexp(m, &k);
    int e = k - (int)(coef_bits - 1);
    if (round_away(ldexp(m, -e)) > lim)
        e++;
    if (e < FORM_EXP_MIN)
        e = FORM_EXP_MIN;   /* tiny values lose bits toward zero */
    if (e > FORM_EXP_MAX) {
        e = FORM_EXP_MAX;
        if (saturated)
            *saturated = 1;
    }
    f.exp = e;
    for (int i = 0; i < 3; i++) {
        /* clamped as a double: past the exponent's range a value may exceed
         * int64, and converting it first would be undefined (on x86 it
         * turns the largest positive value into the most negative) */
        double s = ldexp(v[i], -e);
        f.m[i] = (int32_t)(s >= (double)lim ? lim : s <= -(double)lim ? -lim : round_away(s));
    }
    return f;
}

int gp_solve_linear(const vec3 r[3], const double val[3], vec3 n, double out[4])
{
    /* Gaussian elimination with partial pivoting on the 4x4 system (11). */
    double m[4][5] = {
        {r[0].x, r[0].y, r[0].z, 1, val[0]},
        {r[1].x, r[1].y, r[1].z, 1, val[1]},
        {r[2].x, r[2].y, r[2].z, 1, val[2]},
        {n.x, n.y, n.z, 0, 0},
    };
    double scale = 0;
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++)
            scale = fmax(scale, fabs(m[i][j]));
    for (int col = 0; col < 4; col++) {
        int piv = col;
        for (int i = col + 1; i < 4; i++)
            if (fabs(m[i][col]) > fabs(m[piv][col]))
                piv = i;
        if (!(fabs(m[piv][col]) > 1e-300) || !(fabs(m[piv][col]) > scale * 1e-14))
            return -1;
        if (piv != col)
            for (int j = 0; j < 5; j++) {
                double t = m[col][j];
                m[col][j] = m[piv][j];
                m[piv][j] = t;
            }
        for (int i = col + 1; i < 4; i++) {
            double f = m[i][col] / m[col][col];
            for (int j = col; j < 5; j++)
                m[i][j] -= f * m[col][j];
        }
    }
    for (int i = 3; i >= 0; i--) {
        double s = m[i][4];
        for (int j = i + 1; j < 4; j++)
            s -= m[i][j] * out[j];
        out[i] = s / m[i][i];
    }
    return 0;
}
