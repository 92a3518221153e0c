/* zbuffer.c — Catmull's z-buffer (seed 000 §4.1, seed 002 §3.2, seed 004):
 * each face in stream order is scan-converted at pixel centres and a pixel
 * is written only if the face is strictly nearer than what the depth buffer
 * holds.  The buffer is the frame's own depth store: near/Z in fixed point,
 * 0.depth_bits of the profile, exactly the VP's (docs/vp.md §4).
 * Known failures: depth precision — two surfaces closer than one step of
 * near/Z (a step is Z^2 / (near 2^depth_bits) in Z: it grows with the square
 * of the distance) tie and the earlier face wins, so far geometry z-fights;
 * beyond near 2^depth_bits nothing is drawn; nearer than near saturates. */
#include "common.h"

typedef struct {
    mth_ctx *c;
    unsigned fi;
} zb_run;

static void zb_span(void *ctx, int row, int c0, int c1)
{
    zb_run *r = ctx;
    const ref_face *f = &r->c->rf.faces[r->fi];
    double y = mth_y(r->c, row);
    for (int col = c0; col < c1; col++) {
        /* 1/Z, not Z, is what is linear on the screen (eq. 6) and so what a
         * scan converter interpolates; it is also the VP's stored depth */
        double q = mth_q(f, mth_x(r->c, col), y);
        uint32_t d = mth_depth(r->c, q);
        size_t i = (size_t)row * r->c->w + (size_t)col;
        if (d > r->c->out->depth[i])
            mth_put(r->c, col, row, r->fi, q);
    }
}

int mth_zbuffer_render(const alb_scene *s, const alb_profile *p, unsigned frame, alb_frame *out)
{
    mth_ctx c;
    if (mth_begin(&c, s, p, frame, out))
        return -1;
    for (unsigned fi = 0; fi < c.rf.n; fi++) {
        mth_poly pg;
        if (!mth_face_poly(&c, fi, &pg))
            continue;
        zb_run r = {&c, fi};
        mth_fill(&pg, c.w, c.h, zb_span, &r);
    }
    return mth_end(&c, true);
}

const char mth_zbuffer_summary[] =
    "z-buffer: faces in stream order, per-pixel fixed-point near/Z test (fails: depth precision "
    "far away)";
