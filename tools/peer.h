/* peer.h — the rasterizer a user would pick instead of the VP: Mesa's
 * llvmpipe through OSMesa, drawing the same faces as the VP at the same
 * resolution with a depth test, for make bench (docs/performance.md).
 * Each peer runs in a child process of its own, since llvmpipe takes its
 * thread count (LP_NUM_THREADS) when its screen is made. */
#ifndef ALBATROS_PEER_H
#define ALBATROS_PEER_H

#include "albatros/profile.h"
#include "albatros/scene.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/* One frame's front faces as triangles (fans of the convex faces), in
 * clip coordinates: (x, y, Z - 2 n, Z) from observer space, so that the
 * window depth is 1 - n/Z, linear in 1/Z like the VP's depth store. */
typedef struct {
    float *xyzw;              /* 4 per vertex */
    uint8_t *rgba;            /* 4 per vertex */
    size_t nverts;            /* 3 per triangle */
    bool flat;                /* drawn flat (the face ids) */
} peer_mesh;

/* Frame `frame` of the scene as the profile sees it (tools/ref.c's observer
 * space).  gouraud: each vertex its face's colour times its intensity (eq. 7's
 * fields); else each face the colour that encodes its id + 1, drawn flat, so
 * the face map can be read back.  -1 if out of memory. */
int peer_mesh_of(const alb_scene *s, const alb_profile *p, unsigned frame, bool gouraud,
                 peer_mesh *m);
void peer_mesh_free(peer_mesh *m);

/* llvmpipe drawing the mesh on a w x h screen on `threads` threads (0: its
 * rasterizer in the calling thread), in a child process that waits for
 * orders, so that the bench can time it and the VP in turn. */
typedef struct peer peer;
/* NULL with err set if OSMesa or llvmpipe is not there. */
peer *peer_start(const peer_mesh *m, unsigned w, unsigned h, unsigned threads, char *err,
                 size_t len);
/* ms per frame of `frames` frames (a clear, one draw, glFinish each); -1 on
 * failure.  The first call warms up (JIT, first frames). */
double peer_time(peer *p, unsigned frames);
/* The face map of a flat mesh (w * h, row 0 at the top), ALB_FRAME_NO_FACE
 * where none; -1 on failure. */
int peer_faces(peer *p, uint32_t *face);
void peer_stop(peer *p);

#endif
