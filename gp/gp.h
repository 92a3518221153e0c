/* gp.h — the geometry processor: from the 3-D database (scene) to the VP's
 * word stream, frame by frame (digest §2-§7, docs/gp.md). */
#ifndef ALBATROS_GP_H
#define ALBATROS_GP_H

#include "../common/diag.h"
#include "../common/profile.h"
#include "../common/words.h"
#include "scene.h"

typedef struct gp gp_t;

/* What the GP did with one frame (or, summed, a run). */
typedef struct {
    unsigned faces_in;          /* faces in the database */
    unsigned faces_out;         /* FACE packets emitted */
    unsigned faces_behind;      /* every vertex at Z <= 0 */
    unsigned faces_backfacing;  /* observer sees the back (profile backface=1) */
    unsigned faces_edge_on;     /* plane through the observer */
    unsigned faces_offscreen;   /* eq. (18): an edge with the screen outside */
    unsigned edges_out;         /* edges emitted, bounding edges included */
    unsigned edges_behind;      /* both vertices at Z <= 0 */
    unsigned edges_degenerate;  /* projects to a point (R1 x R2 = 0) */
    unsigned edges_offscreen;   /* eq. (18): line misses the screen, screen inside */
    unsigned bound_added;       /* bounding edges emitted */
    unsigned bound_culled;      /* bounding edges outside the screen, dropped */
    unsigned coef_saturated;    /* forms whose exponent had to be clamped */
    unsigned long long words;   /* words emitted */
} gp_stats;

/* Offline database preparation (eqs. 9-11, interpolation matrices, texture
 * coefficients).  The scene must outlive the GP. */
alb_err gp_create(gp_t **gp, const scene_t *scene, const profile_t *prof, diag_t *d);
void gp_destroy(gp_t *gp);
unsigned gp_frame_count(const gp_t *gp);

/* CONFIG packet and the TEXTURE packets of every scene texture. */
void gp_stream_header(gp_t *gp, ws_buf *out);
/* One frame: FRAME, the FACE packets, FRAME_END. */
alb_err gp_frame(gp_t *gp, unsigned frame, ws_buf *out, gp_stats *st, diag_t *d);
/* The whole stream: header, every frame, END.  st (may be NULL) gets sums. */
alb_err gp_run(gp_t *gp, ws_buf *out, gp_stats *st, diag_t *d);

void gp_stats_add(gp_stats *sum, const gp_stats *s);

#endif
