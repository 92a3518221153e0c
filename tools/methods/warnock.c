/* warnock.c — Warnock's recursive subdivision (seed 000 §4.4, figs. 4.32-4.43;
 * seed 003, "area subdivision"): a window is classified against each face of
 * its parent's list as disjoint (bounding box or one edge's half-plane
 * holding no corner), surrounding (every corner inside every edge),
 * contained (its bounding box inside the window) or intersecting.  Nothing
 * left: background.  One face left that does not surround: its part of the
 * window is filled (the seed's rules 2-3).
 * A surrounding face whose plane is nearer than every other face's plane at
 * the four corners hides them all (rule 5 with the depth test at the
 * corners; 1/Z is linear, so nearer at the corners is nearer throughout).
 * Otherwise the window is split in four, down to single pixels, where the
 * nearest face at the pixel centre wins.  Windows are tested on the hull of
 * their pixel centres, the only points that are sampled.  vp.level records
 * the level of the window that decided each pixel, as the VP's does.
 * Known failures: none in the image at pixel centres (it decides exactly what
 * a ray would); its cost is the weakness: every edge is followed down to
 * pixel windows, with a face list per window on the stack, and interpene-
 * trating or cyclic faces are only resolved pixel by pixel. */
#include "common.h"

#include <stdlib.h>

/* The seed's four relations of a face to a window (fig. 4.35). */
enum { WN_OUT, WN_SURROUND, WN_INTERSECT, WN_CONTAINED };

typedef struct {
    mth_ctx c;
    unsigned nf;
    double (*bbox)[4];       /* screen x0 y0 x1 y1 of each face's visible part */
    unsigned *list;          /* one face list per level: nf entries each */
    uint8_t *cls;            /* the class of each entry */
} wn_run;

typedef struct {
    int c0, r0, c1, r1;      /* pixels [c0, c1) x [r0, r1) */
    unsigned level;
    double x0, y0, x1, y1;   /* hull of the pixel centres, screen units */
} window;

static int classify(const wn_run *r, unsigned fi, const window *w)
{
    const double *b = r->bbox[fi];
    if (b[0] > w->x1 || b[2] < w->x0 || b[1] > w->y1 || b[3] < w->y0)
        return WN_OUT;   /* the bounding-box test (fig. 4.36) */
    const ref_face *f = &r->c.rf.faces[fi];
    const double xs[4] = {w->x0, w->x1, w->x1, w->x0}, ys[4] = {w->y0, w->y0, w->y1, w->y1};
    bool surround = true;
    for (unsigned k = 0; k < f->n; k++) {
        unsigned in = 0;
        for (int j = 0; j < 4; j++)
            in += v3_dot(f->edge[k], v3(xs[j], ys[j], 1)) >= 0;
        if (in == 0)
            return WN_OUT;   /* the window lies outside this edge (the substitution test) */
        surround &= in == 4;
    }
    if (surround)
        return WN_SURROUND;
    bool inside = b[0] >= w->x0 && b[2] <= w->x1 && b[1] >= w->y0 && b[3] <= w->y1;
    return inside ? WN_CONTAINED : WN_INTERSECT;   /* fig. 4.36 b */
}

static void fill(wn_run *r, const window *w, unsigned fi, bool test_edges)
{
    const ref_face *f = &r->c.rf.faces[fi];
    for (int row = w->r0; row < w->r1; row++)
        for (int col = w->c0; col < w->c1; col++) {
            double x = mth_x(&r->c, col), y = mth_y(&r->c, row);
            bool in = true;
            for (unsigned k = 0; test_edges && k < f->n && in; k++)
                in = v3_dot(f->edge[k], v3(x, y, 1)) >= 0;
            if (!in)
                continue;
            mth_put(&r->c, col, row, fi, mth_q(f, x, y));
            r->c.out->level[(size_t)row * r->c.w + (size_t)col] = (uint8_t)w->level;
        }
}

/* Of the surrounding faces, the one nearest at the window's centre, if it is
 * nearer than every other face of the list at all four corners; else -1. */
static long hiding_face(const wn_run *r, const window *w, const unsigned *list,
                        const uint8_t *cls, unsigned n)
{
    double xm = (w->x0 + w->x1) / 2, ym = (w->y0 + w->y1) / 2, best_q = 0;
    long s = -1;
    for (unsigned k = 0; k < n; k++) {
        double q = mth_q(&r->c.rf.faces[list[k]], xm, ym);
        if (cls[k] == WN_SURROUND && (s < 0 || mth_nearer(q, list[k], best_q, (unsigned)s)))
            s = list[k], best_q = q;
    }
    if (s < 0)
        return -1;
    const ref_face *fs = &r->c.rf.faces[s];
    const double xs[4] = {w->x0, w->x1, w->x1, w->x0}, ys[4] = {w->y0, w->y0, w->y1, w->y1};
    for (unsigned k = 0; k < n; k++)
        for (int j = 0; j < 4 && list[k] != (unsigned)s; j++)
            if (!mth_nearer(mth_q(fs, xs[j], ys[j]), (unsigned)s,
                            mth_q(&r->c.rf.faces[list[k]], xs[j], ys[j]), list[k]))
                return -1;
    return s;
}

static void subdivide(wn_run *r, const window *w, unsigned n);

static void window_set(const wn_run *r, window *w, int c0, int r0, int c1, int r1, unsigned level)
{
    w->c0 = c0, w->r0 = r0, w->c1 = c1, w->r1 = r1, w->level = level;
    w->x0 = mth_x(&r->c, c0), w->x1 = mth_x(&r->c, c1 - 1);
    w->y1 = mth_y(&r->c, r0), w->y0 = mth_y(&r->c, r1 - 1);
}

/* Decide window w; the faces that may touch it are the first n entries of
 * the list of its parent's level (all faces at level 0). */
static void visit(wn_run *r, const window *w, const unsigned *parent, unsigned n)
{
    unsigned *list = r->list + (size_t)(w->level + 1) * r->nf;
    uint8_t *cls = r->cls + (size_t)(w->level + 1) * r->nf;
    unsigned m = 0;
    for (unsigned k = 0; k < n; k++) {
        int cl = classify(r, parent[k], w);
        if (cl != WN_OUT)
            list[m] = parent[k], cls[m++] = (uint8_t)cl;
    }
    if (m == 0)
        return;   /* empty window: the background is already there */
    if (m == 1 && cls[0] != WN_SURROUND) {
        fill(r, w, list[0], true);   /* one face alone: its part of the window */
        return;
    }
    long s = hiding_face(r, w, list, cls, m);
    if (s >= 0)
        fill(r, w, (unsigned)s, false);
    else if (w->c1 - w->c0 > 1 || w->r1 - w->r0 > 1)
        subdivide(r, w, m);
    /* a pixel window has only surrounding or disjoint faces: hiding_face
     * found the nearest at its centre, or there is none */
}

/* Quarters (halves once a side is one pixel) in the seed's order: lower
 * left, lower right, upper left, upper right (fig. 4.32). */
static void subdivide(wn_run *r, const window *w, unsigned n)
{
    int cm = w->c1 - w->c0 > 1 ? (w->c0 + w->c1) / 2 : w->c1;
    int rm = w->r1 - w->r0 > 1 ? (w->r0 + w->r1) / 2 : w->r1;
    const int cs[3] = {w->c0, cm, w->c1};
    const unsigned *list = r->list + (size_t)(w->level + 1) * r->nf;
    for (int qr = 0; qr < 2; qr++)
        for (int qc = 0; qc < 2; qc++) {
            int r0 = qr == 0 ? rm : w->r0, r1 = qr == 0 ? w->r1 : rm;
            if (cs[qc] >= cs[qc + 1] || r0 >= r1)
                continue;
            window sub;
            window_set(r, &sub, cs[qc], r0, cs[qc + 1], r1, w->level + 1);
            visit(r, &sub, list, n);
        }
}

static bool prepare(wn_run *r, unsigned levels)
{
    size_t nf = r->nf ? r->nf : 1;
    r->bbox = malloc(nf * sizeof *r->bbox);
    r->list = malloc((levels + 2) * nf * sizeof *r->list);
    r->cls = malloc((levels + 2) * nf);
    if (!r->bbox || !r->list || !r->cls)
        return false;
    for (unsigned fi = 0; fi < r->nf; fi++) {
        mth_poly pg;
        double *b = r->bbox[fi];
        r->list[fi] = fi;   /* level 0's parent list: every face */
        b[0] = b[1] = 2, b[2] = b[3] = -2;   /* empty: no visible part */
        if (!mth_face_poly(&r->c, fi, &pg))
            continue;
        for (unsigned k = 0; k < pg.n; k++) {
            double x = pg.x[k] * 2 / r->c.w - 1, y = 1 - pg.y[k] * 2 / r->c.h;
            b[0] = fmin(b[0], x), b[2] = fmax(b[2], x), b[1] = fmin(b[1], y), b[3] = fmax(b[3], y);
        }
        /* a margin for the projection's rounding: the edge tests decide */
        b[0] -= 1e-9, b[1] -= 1e-9, b[2] += 1e-9, b[3] += 1e-9;
    }
    return true;
}

int mth_warnock_render(const alb_scene *s, const alb_profile *p, unsigned frame, alb_frame *out)
{
    wn_run r = {0};
    if (mth_begin(&r.c, s, p, frame, out))
        return -1;
    r.nf = r.c.rf.n;
    unsigned levels = 0;
    while ((1u << levels) < r.c.w || (1u << levels) < r.c.h)
        levels++;
    bool ok = prepare(&r, levels);
    if (ok) {
        window w;
        window_set(&r, &w, 0, 0, (int)r.c.w, (int)r.c.h, 0);
        visit(&r, &w, r.list, r.nf);
    }
    free(r.bbox);
    free(r.list);
    free(r.cls);
    return mth_end(&r.c, ok);
}

const char mth_warnock_summary[] =
    "Warnock subdivision: windows split until empty, one face, or hidden by a surrounding face; "
    "pixels decided at centres";
