/* ref.h — the exact reference renderer: double precision, straight from the
 * scene (never from the word stream), same conventions as the VP (screen
 * [-1,1]^2, samples at pixel centres, 1/Z depth, eq. 7 shading), no
 * quantisation but the final rounding of colours.  Ground truth for the VP
 * (docs/reference.md). */
#ifndef ALBATROS_REF_H
#define ALBATROS_REF_H

#include "albatros/profile.h"
#include "../common/vec3.h"
#include "albatros/gp.h"
#include "albatros/vp.h"

/* A face of one frame in observer space, as the reference sees it. */
typedef struct {
    uint32_t id;
    const alb_scene_object *obj;
    const alb_scene_face *face;
    unsigned n;               /* edges */
    vec3 v[ALB_SCENE_MAX_FACE_VERTICES];      /* the vertices R_j in observer space */
    vec3 edge[ALB_SCENE_MAX_FACE_VERTICES];   /* R_j x R_j+1: inside n.(x, y, 1) >= 0 */
    vec3 plane_n;             /* plane N.P = d in observer space */
    double plane_d;
    double bbox[4];           /* screen x0 y0 x1 y1 that can hold the face */
    mat3 to_object;           /* observer point -> object point: P_o = M (P - t) */
    vec3 t;
    vec3 light_obj;
    double ambient;
} ref_face;

typedef struct {
    ref_face *faces;
    unsigned n;
} ref_frame;

/* The faces of frame `frame` that the observer can see the front of. */
int ref_prepare(const alb_scene *s, const alb_profile *p, unsigned frame, ref_frame *rf);
void ref_frame_free(ref_frame *rf);

/* Colour (0..255 per channel, before fog) of face f at the observer-space
 * point P of its plane: the scene's fields by barycentric coordinates in the
 * face's field triple (docs/reference.md).  The other renderers of tools/
 * (tools/methods.h) shade through this so that they differ from the
 * reference only in visibility. */
void ref_shade_point(const alb_scene *s, const ref_face *f, vec3 P, double rgb_out[3]);
/* Linear fog in Z (distance along the view axis) applied to rgb in place, if
 * the scene has fog and the face takes it. */
void ref_fog_point(const alb_scene *s, const ref_face *f, double z, double rgb[3]);

/* Render frame `frame` into out (allocated here at the profile's size). */
int ref_render(const alb_scene *s, const alb_profile *p, unsigned frame, alb_frame *out);

/* Screen sample position of column c / row r of a w x h grid (pixel centres). */
static inline double ref_sample_x(unsigned c, unsigned w) { return -1 + (2.0 * c + 1) / w; }
static inline double ref_sample_y(unsigned r, unsigned h) { return 1 - (2.0 * r + 1) / h; }

#endif
