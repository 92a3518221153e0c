/* test_gp.c — the GP against computations made here independently: culling
 * by the screen's corners (Fig. 1), intercepts by substitution, system (11)
 * by its own equations, and whole-pipeline output against ray casting. */
#include "t.h"
#include "../gp/gp_internal.h"
#include "../common/fix.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* ---- eq. (18) and Fig. 1 ---- */

TEST(culling_fig1_against_screen_corners)
{
    uint64_t s = 11;
    unsigned seen[3] = {0, 0, 0};
    for (int i = 0; i < 200000; i++) {
        gp_line l = {t_uniform(&s, -1, 1), t_uniform(&s, -1, 1), t_uniform(&s, -3, 3)};
        int pos = 0, neg = 0;
        for (int cx = -1; cx <= 1; cx += 2)
            for (int cy = -1; cy <= 1; cy += 2) {
                double f = l.a * cx + l.b * cy + l.c;
                pos += f > 0;
                neg += f < 0;
            }
        gp_line_class want = pos == 4 ? LINE_DROP_EDGE : neg == 4 ? LINE_DROP_FACE : LINE_CROSSES;
        gp_line_class got = gp_classify_line(l);
        seen[want]++;
        if (got != want) {
            CHECK_MSG(got == want, "line %g %g %g: class %d, corners say %d", l.a, l.b, l.c, got, want);
            return;
        }
    }
    CHECK(seen[0] > 1000 && seen[1] > 1000 && seen[2] > 1000);
    /* a line through a corner touches the screen: kept */
    CHECK_EQ(gp_classify_line((gp_line){1, 1, 2}), LINE_CROSSES);
    CHECK_EQ(gp_classify_line((gp_line){1, 1, 2.000001}), LINE_DROP_EDGE);
    CHECK_EQ(gp_classify_line((gp_line){1, 1, -2.000001}), LINE_DROP_FACE);
}

/* ---- the edge format (19) ---- */

static double intercept_value(uint32_t q, unsigned frac) { return ldexp(q, -(int)frac) - 3; }

TEST(edge_format_intercepts_lie_on_the_line)
{
    uint64_t s = 5;
    const unsigned frac = 14;
    double half_lsb = ldexp(0.5, -(int)frac);
    int checked = 0;
    for (int i = 0; i < 100000; i++) {
        gp_line l = {t_uniform(&s, -1, 1), t_uniform(&s, -1, 1), t_uniform(&s, -2, 2)};
        if (gp_classify_line(l) != LINE_CROSSES)
            continue;
        ws_edge e = gp_edge_format(l, frac);
        CHECK_EQ(e.u, fabs(l.a) > fabs(l.b));
        double x1 = intercept_value(e.x1, frac), x2 = intercept_value(e.x2, frac);
        /* (X1, -1) and (X2, 1) on the line for a vertical edge; (-1, Y1) and
         * (1, Y2) for a horizontal one: substitute and compare. */
        double r1, r2;
        if (e.u) {
            CHECK_EQ(e.r, l.a < 0);
            r1 = (l.b * 1 - l.c) / l.a; /* x at y = -1 from A x - B + C = 0 */
            r2 = (-l.b - l.c) / l.a;    /* x at y = +1 from A x + B + C = 0 */
        } else {
            CHECK_EQ(e.r, l.b < 0);
            r1 = (l.a - l.c) / l.b;     /* y at x = -1 */
            r2 = (-l.a - l.c) / l.b;    /* y at x = +1 */
        }
        CHECK(fabs(r1) <= 3 && fabs(r2) <= 3);
        if (fabs(x1 - r1) > half_lsb || fabs(x2 - r2) > half_lsb) {
            CHECK_MSG(0, "line %g %g %g: intercepts %g %g, exact %g %g", l.a, l.b, l.c, x1, x2, r1, r2);
            return;
        }
        checked++;
    }
    CHECK(checked > 10000);
}

/* The VP's reading of an edge: is screen point (x, y) inside? (R = 0: the
 * face is on the side of larger x (vertical) or larger y (horizontal).) */
static bool edge_inside(const ws_edge *e, unsigned frac, double x, double y)
{
    double a = intercept_value(e->x1, frac), b = intercept_value(e->x2, frac);
    if (e->u) {
        double xe = a + (b - a) * (y + 1) / 2;
        return e->r ? x <= xe : x >= xe;
    }
    double ye = a + (b - a) * (x + 1) / 2;
    return e->r ? y <= ye : y >= ye;
}

TEST(edge_format_keeps_the_inside)
{
    uint64_t s = 9;
    int checked = 0;
    for (int i = 0; i < 20000; i++) {
        gp_line l = {t_uniform(&s, -1, 1), t_uniform(&s, -1, 1), t_uniform(&s, -1.5, 1.5)};
        if (gp_classify_line(l) != LINE_CROSSES)
            continue;
        ws_edge e = gp_edge_format(l, 16);
        double norm = hypot(l.a, l.b);
        for (int k = 0; k < 20; k++) {
            double x = t_uniform(&s, -1, 1), y = t_uniform(&s, -1, 1);
            double f = (l.a * x + l.b * y + l.c) / norm;
            if (fabs(f) < 1e-3)
                continue;   /* within quantisation of the line */
            CHECK_EQ(edge_inside(&e, 16, x, y), f > 0);
            checked++;
        }
    }
    CHECK(checked > 100000);
}

TEST(intercept_rounding_half_up_and_saturation)
{
    /* 3.F after the +3 shift: -3 -> 0, 0 -> 3 * 2^F, ties round up */
    CHECK_EQ(gp_quantise_intercept(-3, 10), 0);
    CHECK_EQ(gp_quantise_intercept(0, 10), 3 << 10);
    CHECK_EQ(gp_quantise_intercept(ldexp(1, -11), 10), (3 << 10) + 1);       /* half LSB up */
    CHECK_EQ(gp_quantise_intercept(-ldexp(1, -11), 10), 3 << 10);            /* -half LSB up */
    CHECK_EQ(gp_quantise_intercept(-5, 10), 0);                              /* saturates */
    CHECK_EQ(gp_quantise_intercept(9, 10), (8 << 10) - 1);
    CHECK_EQ(gp_quantise_intercept(NAN, 10), 0);
}

/* ---- block floating point ---- */

TEST(form_quantisation_bounds)
{
    uint64_t s = 3;
    for (int i = 0; i < 100000; i++) {
        double v[3];
        for (int k = 0; k < 3; k++)
            v[k] = ldexp(t_uniform(&s, -1, 1), (int)(t_rand(&s) % 80) - 40);
        int sat = 0;
        ws_form f = gp_quantise_form(v[0], v[1], v[2], 24, &sat);
        CHECK(!sat);
        double m = fmax(fabs(v[0]), fmax(fabs(v[1]), fabs(v[2])));
        int32_t big = 0;
        for (int k = 0; k < 3; k++) {
            /* each mantissa within half an LSB of the value; none overflows */
            double err = fabs(ldexp(f.m[k], f.exp) - v[k]);
            if (err > ldexp(0.5, f.exp) * (1 + 1e-12)) {
                CHECK_MSG(0, "value %g: mantissa %d exp %d", v[k], f.m[k], f.exp);
                return;
            }
            if (abs(f.m[k]) > big)
                big = abs(f.m[k]);
        }
        CHECK(big <= (1 << 23) - 1);
        /* and the exponent is the smallest: the largest mantissa uses the top bit */
        CHECK(m == 0 || big >= (1 << 22));
    }
}

/* ---- system (11) ---- */

TEST(intensity_solution_reproduces_vertices_and_lies_in_plane)
{
    uint64_t s = 17;
    for (int i = 0; i < 5000; i++) {
        vec3 r[3];
        double val[3], out[4];
        for (int k = 0; k < 3; k++) {
            r[k] = v3(t_uniform(&s, -10, 10), t_uniform(&s, -10, 10), t_uniform(&s, -10, 10));
            val[k] = t_uniform(&s, 0, 1);
        }
        vec3 n = v3_cross(v3_sub(r[1], r[0]), v3_sub(r[2], r[1]));
        if (v3_len(n) < 1)
            continue;
        CHECK(gp_solve_linear(r, val, n, out) == 0);
        for (int k = 0; k < 3; k++)
            CHECK_NEAR(out[0] * r[k].x + out[1] * r[k].y + out[2] * r[k].z + out[3], val[k], 1e-9);
        /* eq. (10): the gradient is in the face plane */
        CHECK_NEAR(out[0] * n.x + out[1] * n.y + out[2] * n.z, 0, 1e-9 * v3_len(n));
    }
    /* collinear vertices: the determinant k.N vanishes */
    vec3 r[3] = {{0, 0, 0}, {1, 1, 1}, {2, 2, 2}};
    double val[3] = {0, 1, 2}, out[4];
    CHECK(gp_solve_linear(r, val, v3(1, -1, 0), out) != 0);
}
