/* accuracy.h — the VP measured against the exact reference on one frame:
 * which pixels differ in face, and whether each lies farther than the
 * documented quantisation bounds from every edge and depth tie (a "clear"
 * pixel, where the VP must agree exactly).  docs/reference.md. */
#ifndef ALBATROS_ACCURACY_H
#define ALBATROS_ACCURACY_H

#include "albatros/profile.h"
#include "albatros/gp.h"
#include "albatros/vp.h"

#include <stddef.h>
#include <stdint.h>

typedef struct {
    size_t pixels;
    size_t face_diff;         /* pixels whose face differs from the reference */
    size_t clear;             /* pixels outside every quantisation bound */
    size_t clear_diff;        /* clear pixels whose face differs: must be 0 */
    size_t first_clear_diff;  /* index of the first such pixel */
} accuracy;

/* Compare vp (frame `frame` rendered from `stream`) with the reference of the
 * scene.  aa_levels must be 0.  Returns -1 if out of memory. */
int accuracy_measure(const alb_scene *s, const alb_profile *p, unsigned frame, const uint32_t *stream,
                     size_t nwords, const alb_frame *vp, const alb_frame *ref, accuracy *out);

/* Run GP, VP and reference on a scene (ready for the GP: screen-space
 * scenes resolved); sums into *acc.  -1 with d saying why on failure. */
int accuracy_of_scene(const alb_scene *s, const alb_profile *p, accuracy *acc, alb_diag *d);
/* The same on scene text. */
int accuracy_of_text(const char *text, const alb_profile *p, accuracy *acc, char *err, size_t len);

#endif
