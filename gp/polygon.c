/* polygon.c — is a planar polygon convex and simple?  From its edge vectors
 * in the plane, with no angle function: each turn's sign and sine from the
 * cross and dot products, the winding by counting how often the edge
 * direction passes one reference direction.  The scene parser and the OBJ
 * importer share it, so that "convex" means one thing and its answer does not
 * depend on the C library's atan2 (docs/number-formats.md §0). */
#include "gp_internal.h"

#include <math.h>

gp_turns gp_polygon_turns(const double *dx, const double *dy, unsigned n, double tol_sin,
                          unsigned *vertex)
{
    int winding = 0;
    for (unsigned k = 0; k < n; k++) {
        /* the turn at vertex k: from edge k-1 (into it) to edge k (out of it) */
        unsigned j = (k + n - 1) % n;
        double cross = dx[j] * dy[k] - dy[j] * dx[k], dot = dx[j] * dx[k] + dy[j] * dy[k];
        double len = sqrt(dx[j] * dx[j] + dy[j] * dy[j]) * sqrt(dx[k] * dx[k] + dy[k] * dy[k]);
        /* a right turn whose sine is below -tol, a right turn of 90 degrees or
         * more, or an edge doubling back: reflex */
        if (cross < -tol_sin * len || (cross <= 0 && dot <= 0)) {
            *vertex = k;
            return GP_TURNS_REFLEX;
        }
        /* Every turn lies in (-90, 180) degrees now, so the direction passes
         * +x (angle 0) turning left exactly when it goes from below the x
         * axis to on or above it, and turning right in reverse; passing 180
         * degrees has the opposite signs of the turn and is not counted. */
        if (cross > 0 && dy[j] < 0 && dy[k] >= 0)
            winding++;
        else if (cross < 0 && dy[j] >= 0 && dy[k] < 0)
            winding--;
    }
    *vertex = (unsigned)winding;
    return winding == 1 ? GP_TURNS_CONVEX : GP_TURNS_NOT_SIMPLE;
}
