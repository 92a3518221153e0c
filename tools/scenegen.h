/* scenegen.h — seeded scene generators: random scenes for the VP-against-
 * reference tests and measurements (docs/reference.md).  Each returns scene
 * text (docs/scene-format.md) in a malloc'd string, NULL if out of memory. */
#ifndef ALBATROS_SCENEGEN_H
#define ALBATROS_SCENEGEN_H

#include <stdbool.h>
#include <stdint.h>

typedef struct {
    unsigned faces;          /* how many */
    double behind;           /* fraction of faces with a vertex behind the observer */
    double backfacing;       /* fraction wound away from the observer */
    double max_vertices;     /* polygons have 3 .. this many vertices (<= 8) */
    double size;             /* mean radius as a fraction of the distance */
    bool flat;               /* one colour per face: no per-vertex intensity */
} scenegen_params;

/* Defaults: 12 faces, 10% crossing Z = 0, 10% back-facing, up to 6 vertices,
 * intensity per vertex. */
scenegen_params scenegen_defaults(void);
char *scenegen_random(uint64_t seed, const scenegen_params *p);
/* Slivers: `per_angle` triangles for each tip angle 10, 5, 2, 1, 0.5, 0.2,
 * 0.1, 0.05, 0.02, 0.01 degrees, random orientation and length, facing the
 * observer (fov 90) at distance 5. */
char *scenegen_slivers(uint64_t seed, unsigned per_angle);

#endif
