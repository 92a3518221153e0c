/* gp_internal.h — the GP's building blocks, exposed to its tests only. */
#ifndef ALBATROS_GP_INTERNAL_H
#define ALBATROS_GP_INTERNAL_H

#include "albatros/gp.h"
#include "../common/vec3.h"

#include <math.h>

/* A screen line A x + B y + C = 0, inside A x + B y + C >= 0 (eq. 17). */
typedef struct {
    double a, b, c;
} gp_line;

/* Sgn of the paper: 0 for positive (and for zero), 1 for negative. */
static inline unsigned gp_sgn(double v) { return v < 0; }

/* U of §6: 1 (vertical) if |A| > |B|; the tie |A| = |B| is horizontal
 * (docs/gp.md, "Ties"). */
static inline unsigned gp_line_u(gp_line l) { return fabs(l.a) > fabs(l.b); }

/* Sector 1..8 of an edge direction from SgnA, SgnB, U (Fig. 2). */
unsigned gp_sector(unsigned sgn_a, unsigned sgn_b, unsigned u);
/* The 3-bit half of code (20) for one edge: SgnA SgnB U. */
static inline unsigned gp_edge_code3(gp_line l)
{
    return gp_sgn(l.a) << 2 | gp_sgn(l.b) << 1 | gp_line_u(l);
}

/* The bounding-edge table memory addressed by the 6-bit code (20):
 * SgnA1 SgnB1 U1 SgnA2 SgnB2 U2.  Entry bits: GEN | U | R of the bounding
 * edge (docs/gp.md, "Bounding edges"). */
#define BOUND_ROM_GEN 4u
#define BOUND_ROM_U   2u
#define BOUND_ROM_R   1u
extern const unsigned char gp_bound_rom[64];

/* Where a line lies with respect to the screen square (eq. 18, Fig. 1). */
typedef enum {
    LINE_CROSSES,    /* |A| + |B| >= |C|: keep the edge */
    LINE_DROP_EDGE,  /* misses the screen, screen inside (C > 0) */
    LINE_DROP_FACE   /* misses the screen, screen outside (C < 0) */
} gp_line_class;
gp_line_class gp_classify_line(gp_line l);

/* Intercept quantisation to unsigned 3.F after the +3 shift: round half up,
 * saturate to [0, 2^(3+F) - 1] (docs/number-formats.md §1). */
uint32_t gp_quantise_intercept(double x, unsigned frac_bits);
/* U | R | X1 | X2 of a line that crosses the screen (§6). */
alb_ws_edge gp_edge_format(gp_line l, unsigned frac_bits);
/* An axis-parallel bounding edge through screen coordinate v (§7). */
alb_ws_edge gp_bound_format(unsigned u, unsigned r, double v, unsigned frac_bits);

/* Block floating-point form of (a, b, c) with coef_bits signed mantissas
 * (docs/number-formats.md §2).  *saturated set if the exponent clamped. */
alb_ws_form gp_quantise_form(double a, double b, double c, unsigned coef_bits, int *saturated);

/* Solve system (11): X_k A + Y_k B + Z_k C + D = val_k (k = 1..3) and
 * N.(A, B, C) = 0.  Returns 0, or -1 if the determinant k.N vanishes. */
int gp_solve_linear(const vec3 r[3], const double val[3], vec3 n, double out[4]);

/* A closed planar polygon given by its n edge vectors (dx[k], dy[k]), edge k
 * leaving vertex k, in a plane frame where the polygon runs counter-clockwise
 * if convex (gp/polygon.c).  REFLEX: *vertex is a vertex turning right by a
 * sine below -tol_sin (or by 90 degrees or more, or doubling back); otherwise
 * *vertex is how many times the polygon winds, CONVEX when once. */
typedef enum { GP_TURNS_CONVEX, GP_TURNS_REFLEX, GP_TURNS_NOT_SIMPLE } gp_turns;
gp_turns gp_polygon_turns(const double *dx, const double *dy, unsigned n, double tol_sin,
                          unsigned *vertex);

#endif
