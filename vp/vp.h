/* vp.h — the video processor: faces as intersections of half-planes,
 * rasterised by recursive subdivision of the screen into cells, in fixed
 * point, with depth, shading (eq. 7), texture and fog (docs/vp.md). */
#ifndef ALBATROS_VP_H
#define ALBATROS_VP_H

#include "../common/diag.h"
#include "../common/profile.h"
#include "../common/words.h"
#include "frame.h"

#include <stdint.h>

#define VP_MAX_LEVELS 17   /* 8192 pixels x 8 samples = 2^16: levels 0..16 */

typedef struct vp vp_t;

/* What the VP did in one frame. */
typedef struct {
    uint64_t cells[VP_MAX_LEVELS];   /* cells visited, per subdivision level */
    uint64_t cells_inside;           /* cells every active edge had wholly inside */
    uint64_t cells_outside;          /* cells rejected by an edge */
    uint64_t cells_split;            /* cells subdivided */
    uint64_t samples_tested;         /* single samples tested at their centre */
    uint64_t samples_covered;        /* samples inside a face (before depth) */
    uint64_t samples_written;        /* samples that won the depth test */
    uint64_t depth_saturated;        /* covered samples nearer than `near` (store at max) */
    uint64_t depth_underflow;        /* covered samples too far for the store (d = 0) */
    uint64_t faces;                  /* FACE packets drawn */
    uint64_t edges;                  /* edges of those faces */
    uint64_t faces_shaded;           /* ... using the intensity unit (eq. 7) */
    uint64_t faces_textured;         /* ... using texture */
    uint64_t faces_fogged;           /* ... fogged (the face's flag, in a fogged frame) */
} vp_stats;

alb_err vp_create(vp_t **vp, const profile_t *prof, diag_t *d);
void vp_destroy(vp_t *vp);

/* The packets of the stream, in order (the input parser's job). */
alb_err vp_config(vp_t *vp, const ws_config *c, diag_t *d);
alb_err vp_texture(vp_t *vp, const ws_texture *t, diag_t *d);
void vp_frame_begin(vp_t *vp, const ws_frame *f);
/* Draw one face; ALB_ERR_STREAM if it uses a texture never loaded. */
alb_err vp_face(vp_t *vp, const ws_face *f, diag_t *d);
/* Resolve the samples into pixels; out must be allocated at the screen size. */
void vp_frame_end(vp_t *vp, frame_t *out);
const vp_stats *vp_stats_get(const vp_t *vp);

/* Threads of the functional renderer (vp_face, vp_run_stream): 1 draws
 * face by face on the caller's thread; more split the screen into tiles
 * (vp/parallel.c), with bit-identical frames and statistics; 0 means one per
 * core.  -1 if out of memory (the VP stays on one thread). */
#define VP_MAX_THREADS 64
int vp_set_threads(vp_t *vp, unsigned n);
unsigned vp_threads(const vp_t *vp);
unsigned vp_cores(void);

/* Allocate a frame of this VP's screen size. */
int vp_frame_alloc(const vp_t *vp, frame_t *f, bool with_cycles);

/* Run a whole word stream; sink is called with each finished frame. */
typedef int (*vp_frame_sink)(void *ctx, const frame_t *f, const vp_stats *st);
alb_err vp_run_stream(vp_t *vp, const uint32_t *w, size_t n, const char *name,
                      vp_frame_sink sink, void *ctx, diag_t *d);

#endif
