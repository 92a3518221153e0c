/* gp.h — the geometry processor: from the 3-D database (scene) to the VP's
 * word stream, frame by frame (digest §2-§7, docs/gp.md). */
#ifndef ALBATROS_GP_H
#define ALBATROS_GP_H

#include "diag.h"
#include "profile.h"
#include "words.h"
#include "scene.h"

/* The library exports what its public headers declare, nothing else. */
#pragma GCC visibility push(default)
#ifdef __cplusplus
extern "C" {
#endif

typedef struct alb_gp alb_gp;

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
    unsigned bound_excess;      /* bound=albatros: vertices past a face's second that the
                                   table generates for, left out (docs/gp.md) */
    unsigned coef_saturated;    /* forms whose exponent had to be clamped */
    unsigned long long words;   /* words emitted */
    /* the first face with a clamped form (0: none): its scene line, which
     * form ("depth", "intensity", "texture") and the frame */
    unsigned saturated_line, saturated_frame;
    const char *saturated_form;
} alb_gp_stats;

/* Offline database preparation (eqs. 9-11, interpolation matrices, texture
 * coefficients).  The scene must outlive the GP. */
alb_err alb_gp_create(alb_gp **gp, const alb_scene *scene, const alb_profile *prof, alb_diag *d);
void alb_gp_destroy(alb_gp *gp);
unsigned alb_gp_frame_count(const alb_gp *gp);

/* CONFIG packet and the TEXTURE packets of every scene texture. */
void alb_gp_stream_header(alb_gp *gp, alb_ws_buf *out);
/* One frame: FRAME, the FACE packets, FRAME_END. */
alb_err alb_gp_frame(alb_gp *gp, unsigned frame, alb_ws_buf *out, alb_gp_stats *st, alb_diag *d);
/* The whole stream: header, every frame, END.  st (may be NULL) gets sums. */
alb_err alb_gp_run(alb_gp *gp, alb_ws_buf *out, alb_gp_stats *st, alb_diag *d);

void alb_gp_stats_add(alb_gp_stats *sum, const alb_gp_stats *s);

/* The whole road from a scene file to its word stream in one call, for
 * testbenches and bindings: scene (docs/scene-format.md; NULL: the built-in
 * scene) through the GP of the named profile with "key=value" overrides
 * (NULL-terminated, or NULL).  *w is malloc'd (alb_free), *n its words.
 * OBJ files need a camera: load them with alb_scene_load_obj. */
alb_err alb_gp_compile_file(const char *scene, const char *profile, const char *const *sets,
                            uint32_t **w, size_t *n, alb_diag *d);

#ifdef __cplusplus
}
#endif
#pragma GCC visibility pop

#endif
