/* stress.h — seeded scenes for named stress families, each with one severity
 * parameter, to measure where the VP and the classic methods (methods.h) part
 * from the exact reference (docs/methods.md).  Every scene has the observer at
 * the origin looking along +z with a 90-degree square view (screen x = X/Z,
 * y = Y/Z) and only faces that parse (planar, convex).
 *
 *   family            severity                       range (clamped)
 *   sliver            tip angle, degrees             1e-4 .. 60
 *   crossing-z0       fraction of each crossing       0 .. 1
 *                     face's depth behind Z = 0
 *   far               distance of the front face      1 .. 1e12
 *                     (gap to the face behind: 1)
 *   texture-far       distance of the textured face   0 .. 2^50
 *                     from its texture origin, periods
 *   interpenetrating  angle between the two planes,   0.001 .. 80
 *                     degrees
 *   cyclic            bar width / distance between    0.01 .. 0.4
 *                     crossings (overlap of the three
 *                     bars at each crossing)
 *   degenerate        height / base of the triangles  1e-9 .. 1
 *   tjunction         rows (and coarse columns) n     1 .. 64
 *   deep              depth complexity at the centre  1 .. 64
 *   coords            log10 of the scale of every     -60 .. 60
 *                     coordinate (and of near)
 *
 * The first line after the header is a comment "# stress FAMILY severity S
 * seed N" with the severity used (after clamping). */
#ifndef ALBATROS_STRESS_H
#define ALBATROS_STRESS_H

#include <stdint.h>

/* Scene text (docs/scene-format.md) in a malloc'd string; NULL if the family
 * is unknown, the severity is NaN, or out of memory. */
char *stress_scene(const char *family, double severity, uint64_t seed);

/* 10^e as the coords family scales (|e| <= 300): the same bits under any C
 * library, unlike pow(10, e). */
double stress_pow10(double e);

/* The family names, NULL-terminated. */
const char *const *stress_families(void);

#endif
