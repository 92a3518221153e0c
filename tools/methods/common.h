/* common.h — what the classic methods share (private to tools/methods/):
 * the frame set-up, the face's visible part as a screen polygon, polygon
 * scan conversion, the depth store value and the reference's shading.  The
 * faces come from ref_prepare, so every method sees the same observer-space
 * faces as the reference and differs from it only in how it decides
 * visibility. */
#ifndef ALBATROS_METHODS_COMMON_H
#define ALBATROS_METHODS_COMMON_H

#include "../methods.h"
#include "../../common/vec3.h"
#include "../ref.h"

#include <math.h>
#include <stdbool.h>
#include <stdint.h>

/* The methods, one per file (tools/methods/NAME.c), each a render function
 * and a one-line summary; tools/methods.c lists them. */
#define MTH_METHOD(id)                                                       \
    extern const char mth_##id##_summary[];                                       \
    int mth_##id##_render(const alb_scene *s, const alb_profile *p, unsigned frame, alb_frame *out)
MTH_METHOD(zbuffer);
MTH_METHOD(scanline_zbuffer);
MTH_METHOD(watkins);
MTH_METHOD(watkins_nosplit);
MTH_METHOD(warnock);
MTH_METHOD(painter);
MTH_METHOD(raycast);

/* Clipping a convex polygon by the four planes of the view pyramid adds at
 * most one vertex per plane. */
#define MTH_MAX_VERTICES (ALB_SCENE_MAX_FACE_VERTICES + 4)

/* One method's run over one frame. */
typedef struct {
    const alb_scene *s;
    const alb_profile *p;
    alb_frame *out;
    ref_frame rf;            /* the front faces, in stream order */
    unsigned w, h;
    double depth_one;        /* 2^depth_bits: the depth store's unit */
    double colour_top;       /* 2^colour_bits - 1 */
} mth_ctx;

/* Set up a run: checks (aa_levels 0, frame exists), prepares the faces,
 * allocates *out and fills it with the background.  -1 on failure (nothing
 * to free). */
int mth_begin(mth_ctx *c, const alb_scene *s, const alb_profile *p, unsigned frame, alb_frame *out);
/* Finish a run; on failure (ok false) the frame is freed too.  Returns 0 if
 * ok, else -1, so that a method can end with `return mth_end(&c, ok);`. */
int mth_end(mth_ctx *c, bool ok);

/* Screen coordinates of pixel centres (docs/vp.md §2). */
static inline double mth_x(const mth_ctx *c, int col) { return ref_sample_x((unsigned)col, c->w); }
static inline double mth_y(const mth_ctx *c, int row) { return ref_sample_y((unsigned)row, c->h); }

/* 1/Z of face f's plane at screen point (x, y): linear on the screen, eq. (6).
 * The same arithmetic as the reference's cast. */
static inline double mth_q(const ref_face *f, double x, double y)
{
    return v3_dot(f->plane_n, v3(x, y, 1)) / f->plane_d;
}

/* The reference's depth rule: larger 1/Z is nearer; equal depths keep the
 * earlier face (lower index = earlier in the stream). */
static inline bool mth_nearer(double qa, unsigned ia, double qb, unsigned ib)
{
    return qa > qb || (qa == qb && ia < ib);
}

/* Depth store value of 1/Z = q: near/Z as a 0.depth_bits fraction, 0 when
 * behind or too far, saturated nearer than `near` (docs/vp.md §4). */
uint32_t mth_depth(const mth_ctx *c, double q);

/* Write pixel (col, row) as face fi (index into c->rf) seen at 1/Z = q:
 * colour by the reference's shading and fog, face id, depth, coverage. */
void mth_put(mth_ctx *c, int col, int row, unsigned fi, double q);

/* The visible part of a face: its polygon clipped to the view pyramid
 * |x| <= z, |y| <= z (which also removes everything behind the observer).
 * Observer-space vertices in v; false if nothing is left. */
bool mth_clip(const ref_face *f, vec3 v[MTH_MAX_VERTICES], unsigned *n);

/* A screen polygon in pixel units: X right from the left border, Y down from
 * the top border, so pixel (col, row) has its centre at (col + 0.5, row + 0.5). */
typedef struct {
    unsigned n;
    double x[MTH_MAX_VERTICES], y[MTH_MAX_VERTICES];
} mth_poly;

/* Project clipped observer-space vertices onto the pixel grid. */
void mth_project(const mth_ctx *c, const vec3 *v, unsigned n, mth_poly *out);
/* Clip and project face fi; false if no part of it is in view. */
bool mth_face_poly(const mth_ctx *c, unsigned fi, mth_poly *out);

/* A polygon edge as scan conversion steps it: the rows whose centres it
 * crosses, [row0, row1), and its x at the current row, stepped by dx. */
typedef struct {
    double x, dx;
    int row0, row1;
    unsigned face;
} mth_edge;

/* The edges of pg that cross at least one row centre, appended to out
 * (room for pg->n).  Returns how many.  Tie rule: an edge holds a row whose
 * centre is at or below its top end and above its bottom end (top-left). */
unsigned mth_edges(const mth_poly *pg, unsigned rows, unsigned face, mth_edge *out);

/* First column whose centre is at or right of x, clamped to [0, w]: with
 * spans [first(xl), first(xr)) a centre on a left edge is in, on a right
 * edge out (the top-left tie rule). */
static inline int mth_col(double x, unsigned w)
{
    double c = ceil(x - 0.5);
    return c < 0 ? 0 : c > w ? (int)w : (int)c;
}

/* Scan-convert one polygon by its own edge list and active edge list (even-
 * odd pairs), calling span(ctx, row, c0, c1) for the pixels [c0, c1). */
typedef void (*mth_span_fn)(void *ctx, int row, int c0, int c1);
void mth_fill(const mth_poly *pg, unsigned w, unsigned h, mth_span_fn span, void *ctx);

/* Insertion sort of edges by x: the active edge list is nearly sorted from
 * one row to the next, the case insertion sort is fast on. */
void mth_sort_edges(mth_edge **e, unsigned n);

#endif
