/* bound.c — the Albatros bounding-edge rule (§7, Fig. 2, code (20)): the
 * sector table and the 64-entry table memory that the 6-bit code of a vertex's
 * two edges addresses, as the hardware GP does.  tests/test_bound.c checks every
 * entry against a geometric computation of the angle between the edges. */
#include "gp_internal.h"

/* Fig. 2, indexed by SgnA << 2 | SgnB << 1 | U. */
static const unsigned char sector_of[8] = {
    /* A+ B+ U0 */ 4, /* A+ B+ U1 */ 3, /* A+ B- U0 */ 1, /* A+ B- U1 */ 2,
    /* A- B+ U0 */ 5, /* A- B+ U1 */ 6, /* A- B- U0 */ 8, /* A- B- U1 */ 7,
};

unsigned gp_sector(unsigned sgn_a, unsigned sgn_b, unsigned u)
{
    return sector_of[(sgn_a & 1) << 2 | (sgn_b & 1) << 1 | (u & 1)];
}

/* A bounding edge is generated when (N1 + 4 - N2) mod 8 < 2: the second edge
 * lies in the sector opposite the first or the one before it, so no whole
 * sector fits in the angle.  Its orientation is the opposite of the first
 * edge's (U = not U1): both vertical gives a horizontal edge, both horizontal a
 * vertical one, as the paper requires; for the mixed pairs, where the paper
 * allows either, this choice keeps both new angles at least 45 degrees.  R
 * puts the polygon on the inside.  Entries: GEN=4 | U=2 | R=1. */
#define G(u, r) (BOUND_ROM_GEN | (u) * BOUND_ROM_U | (r) * BOUND_ROM_R)
const unsigned char gp_bound_rom[64] = {
    /* N1=4 (A+B+U0) x N2 = 4 3 1 2 5 6 8 7 */ 0, 0, 0, 0, 0, 0, G(1, 1), G(1, 1),
    /* N1=3 (A+B+U1) */ 0, 0, 0, 0, 0, G(0, 0), 0, G(0, 0),
    /* N1=1 (A+B-U0) */ G(1, 0), 0, 0, 0, G(1, 0), 0, 0, 0,
    /* N1=2 (A+B-U1) */ 0, 0, 0, 0, G(0, 0), G(0, 0), 0, 0,
    /* N1=5 (A-B+U0) */ 0, 0, G(1, 1), 0, 0, 0, G(1, 1), 0,
    /* N1=6 (A-B+U1) */ 0, 0, G(0, 1), G(0, 1), 0, 0, 0, 0,
    /* N1=8 (A-B-U0) */ G(1, 0), G(1, 0), 0, 0, 0, 0, 0, 0,
    /* N1=7 (A-B-U1) */ 0, G(0, 1), 0, G(0, 1), 0, 0, 0, 0,
};
#undef G
