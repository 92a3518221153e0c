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

/* What a pixel is, for judging the VP there (docs/reference.md, "Classes").
 * The first that applies, in this order after CLEAR. */
typedef enum {
    ACC_CLEAR,      /* outside every bound: the VP must give the reference's face */
    ACC_EDGE,       /* within half an intercept LSB of an edge: quantisation, excused */
    ACC_NEAR,       /* the nearest face nearer than near: the depth store saturates */
    ACC_FAR,        /* the nearest face beyond near 2^depth_bits: the store underflows */
    ACC_TIE,        /* the two nearest within their depth rounding: excused */
    ACC_NCLASSES
} accuracy_class;

/* The classes judged unless the user excuses them: differences there are
 * errors.  Near clamp and underflow are the VP's limits, not rounding: a
 * pixel drawn wrong there is wrong, and is counted unless excused. */
#define ACC_JUDGED (1u << ACC_CLEAR | 1u << ACC_NEAR | 1u << ACC_FAR)

typedef struct {
    size_t pixels;
    size_t covered;                      /* pixels where the reference has a face */
    size_t face_diff;                    /* pixels whose face differs from the reference */
    size_t in_class[ACC_NCLASSES];       /* pixels of each class */
    size_t diff_in_class[ACC_NCLASSES];  /* ... whose face differs */
    size_t first_diff[ACC_NCLASSES];     /* pixel index of the first such, in frame */
    unsigned first_frame[ACC_NCLASSES];  /* ... this frame (valid if diff_in_class) */
    unsigned first_scene[ACC_NCLASSES];  /* ... of this scene, counting from 0 */
    unsigned scenes;                     /* scenes summed */
} accuracy;

/* "clear", "edge-band", "near-clamp", "underflow", "depth-tie" */
const char *accuracy_class_name(accuracy_class c);
/* Pixels of the classes in `judged` (a mask of 1 << class), and how many of
 * them differ: the errors. */
size_t accuracy_judged(const accuracy *a, unsigned judged);
size_t accuracy_errors(const accuracy *a, unsigned judged);
/* sum += a (the first differences kept from sum if it has them) */
void accuracy_add(accuracy *sum, const accuracy *a);
/* An empty sum. */
void accuracy_init(accuracy *a);

/* Compare vp (frame `frame` rendered from `stream`) with the reference of the
 * scene.  aa_levels must be 0.  Returns -1 if out of memory. */
int accuracy_measure(const alb_scene *s, const alb_profile *p, unsigned frame, const uint32_t *stream,
                     size_t nwords, const alb_frame *vp, const alb_frame *ref, accuracy *out);

/* Run GP, VP and reference on a scene (ready for the GP: screen-space
 * scenes resolved); sums its frames into *acc as one scene.  -1 with d
 * saying why on failure. */
int accuracy_of_scene(const alb_scene *s, const alb_profile *p, accuracy *acc, alb_diag *d);
/* The same on scene text. */
int accuracy_of_text(const char *text, const alb_profile *p, accuracy *acc, char *err, size_t len);

#endif
