/* vp.h — the video processor: faces as intersections of half-planes,
 * rasterised by recursive subdivision of the screen into cells, in fixed
 * point, with depth, shading (eq. 7), texture and fog (docs/vp.md). */
#ifndef ALBATROS_VP_H
#define ALBATROS_VP_H

#include "diag.h"
#include "profile.h"
#include "words.h"
#include "frame.h"

#include <stdint.h>

/* The library exports what its public headers declare, nothing else. */
#pragma GCC visibility push(default)
#ifdef __cplusplus
extern "C" {
#endif

#define ALB_VP_MAX_LEVELS 17   /* 8192 pixels x 8 samples = 2^16: levels 0..16 */

typedef struct alb_vp alb_vp;

/* What the VP did in one frame. */
typedef struct {
    uint64_t cells[ALB_VP_MAX_LEVELS];   /* cells visited, per subdivision level */
    uint64_t cells_inside;           /* cells every active edge had wholly inside */
    uint64_t cells_outside;          /* cells rejected by an edge */
    uint64_t cells_split;            /* cells subdivided */
    uint64_t samples_tested;         /* single samples tested at their centre */
    uint64_t samples_covered;        /* samples inside a face (before depth) */
    uint64_t samples_written;        /* samples that won the depth test */
    uint64_t depth_saturated;        /* covered samples nearer than `near` (store at max) */
    uint64_t depth_underflow;        /* covered samples too far for the store (d = 0) */
    uint64_t depth_ties;             /* covered samples whose d (0 < d < max) equalled the
                                        stored d of an earlier face, which kept them
                                        (docs/vp.md §4) */
    /* The tie at the lowest sample index (raster order), if depth_ties:
     * the sample, the face that kept it, the face that lost, the depth. */
    uint64_t tie_sample, tie_kept, tie_lost, tie_depth;
    uint64_t depth_nearest;          /* the largest depth a covered sample had: the
                                        frame's nearest surface (0: none) */
    uint64_t faces;                  /* FACE packets drawn */
    uint64_t edges;                  /* edges of those faces */
    uint64_t faces_shaded;           /* ... using the intensity unit (eq. 7) */
    uint64_t faces_textured;         /* ... using texture */
    uint64_t faces_fogged;           /* ... fogged (the face's flag, in a fogged frame) */
} alb_vp_stats;

alb_err alb_vp_create(alb_vp **vp, const alb_profile *prof, alb_diag *d);
void alb_vp_destroy(alb_vp *vp);

/* The packets of the stream, in order (the input parser's job). */
alb_err alb_vp_config(alb_vp *vp, const alb_ws_config *c, alb_diag *d);
alb_err alb_vp_texture(alb_vp *vp, const alb_ws_texture *t, alb_diag *d);
void alb_vp_frame_begin(alb_vp *vp, const alb_ws_frame *f);
/* Draw one face; ALB_ERR_STREAM if it uses a texture never loaded. */
alb_err alb_vp_face(alb_vp *vp, const alb_ws_face *f, alb_diag *d);
/* Resolve the samples into pixels; out must be allocated at the screen size.
 * Only the planes out has are resolved (alb_vp_frame_alloc_planes): a NULL
 * plane costs nothing and stays NULL. */
void alb_vp_frame_end(alb_vp *vp, alb_frame *out);
const alb_vp_stats *alb_vp_stats_get(const alb_vp *vp);

/* Threads of the functional renderer (alb_vp_face, alb_vp_run_stream): 1 draws
 * face by face on the caller's thread; more split the screen into tiles
 * (vp/parallel.c), with bit-identical frames and statistics; 0 means one per
 * core.  The n - 1 worker threads are started here and run until the count
 * changes or alb_vp_destroy; they take no signals.  alb_vp_threads is the
 * count in use: fewer than asked if the system would not start them all
 * (one if it started none).  -1 if out of memory (the VP stays on one
 * thread).  One VP is used from one thread at a time. */
#define ALB_VP_MAX_THREADS 64
int alb_vp_set_threads(alb_vp *vp, unsigned n);
unsigned alb_vp_threads(const alb_vp *vp);
unsigned alb_vp_cores(void);

/* Allocate a frame of this VP's screen size: every plane, or the planes
 * given (ALB_FRAME_* bits, frame.h). */
int alb_vp_frame_alloc(const alb_vp *vp, alb_frame *f, bool with_cycles);
int alb_vp_frame_alloc_planes(const alb_vp *vp, alb_frame *f, unsigned planes);

/* Run a whole word stream; sink is called with each finished frame. */
typedef int (*alb_vp_frame_sink)(void *ctx, const alb_frame *f, const alb_vp_stats *st);
alb_err alb_vp_run_stream(alb_vp *vp, const uint32_t *w, size_t n, const char *name,
                      alb_vp_frame_sink sink, void *ctx, alb_diag *d);
/* The same stream in pieces as it is made (render's functional fidelity
 * takes the GP's frames one at a time, so its memory does not grow with
 * the frames): each piece is whole packets; the frames go to sink as their
 * FRAME_END arrives. */
typedef struct alb_vp_feed alb_vp_feed;
alb_err alb_vp_feed_open(alb_vp_feed **f, alb_vp *vp, const char *name, alb_vp_frame_sink sink,
                         void *ctx, alb_diag *d);
alb_err alb_vp_feed_words(alb_vp_feed *f, const uint32_t *w, size_t n, alb_diag *d);
void alb_vp_feed_close(alb_vp_feed *f);

#ifdef __cplusplus
}
#endif
#pragma GCC visibility pop

#endif
