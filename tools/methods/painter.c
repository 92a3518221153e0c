/* painter.c — the painter's algorithm with Newell's depth sort (seed 003,
 * "painter's algorithm" steps 1-3 a-d; seed 004, "Алгоритъм на художника"):
 * faces sorted farthest first by their farthest point; the head P is drawn
 * once no Q that overlaps it in depth must come before it.  P may precede Q
 * if (a) their screen bounding boxes are disjoint, (b) P lies wholly on the
 * far side of Q's plane, (c) Q lies wholly on the observer's side of P's
 * plane, or (d) their projections do not overlap or, where they do, P is
 * the farther at a point of the overlap.  Otherwise Q moves to the head and
 * is marked.  Faces are painted whole, later over earlier, with no depth
 * test; all tests use the part of each face inside the view pyramid.
 * Known failures, by design (no splitting, as the seeds leave it): cyclic
 * overlap (A over B over C over A) has no order — a marked face is never
 * moved again, so the loop ends and one overlap is painted wrong; and
 * interpenetrating faces are ordered by one point of their overlap, so the
 * part beyond the line of intersection is wrong. */
#include "common.h"
#include "../../common/vec3.h"

#include <stdlib.h>

typedef struct {
    vec3 v[MTH_MAX_VERTICES];   /* the visible part, observer space */
    unsigned n;
    mth_poly pg;                /* and on the pixel grid */
    double zmin, zmax;
    double box[4];              /* pixel bounding box x0 y0 x1 y1 */
} pt_face;

typedef struct {
    mth_ctx c;
    pt_face *face;              /* per ref face; n == 0: not in view */
    unsigned *order;            /* the depth-priority list */
    unsigned norder;
    uint8_t *marked;
} pt_run;

/* Every vertex of a on the side of face b's plane given by sign (+1: the
 * observer's side, -1: the far side), or on the plane. */
static bool all_on_side(const pt_face *a, const ref_face *b, double sign)
{
    double observer_side = b->plane_d > 0 ? -1 : 1;   /* N.0 - d at the observer */
    for (unsigned k = 0; k < a->n; k++) {
        double s = (v3_dot(b->plane_n, a->v[k]) - b->plane_d) * observer_side * sign;
        double tol = 1e-9 * (fabs(b->plane_d) + v3_len(b->plane_n) * v3_len(a->v[k]));
        if (s < -tol)
            return false;
    }
    return true;
}

/* Clip the convex polygon (x, y)[n] by the line through a, b, keeping the
 * side of positive cross product times orient; returns the new count. */
static unsigned clip_by_edge(const double *x, const double *y, unsigned n, double *ox, double *oy,
                             double ax, double ay, double bx, double by, double orient)
{
    unsigned m = 0;
    for (unsigned k = 0; k < n; k++) {
        unsigned j = (k + 1) % n;
        double dk = orient * ((bx - ax) * (y[k] - ay) - (by - ay) * (x[k] - ax));
        double dj = orient * ((bx - ax) * (y[j] - ay) - (by - ay) * (x[j] - ax));
        if (dk >= 0)
            ox[m] = x[k], oy[m++] = y[k];
        if ((dk >= 0) != (dj >= 0)) {
            double t = dk / (dk - dj);
            ox[m] = x[k] + t * (x[j] - x[k]), oy[m++] = y[k] + t * (y[j] - y[k]);
        }
    }
    return m;
}

static double area2(const double *x, const double *y, unsigned n)
{
    double a = 0;
    for (unsigned k = 0; k < n; k++)
        a += x[k] * y[(k + 1) % n] - x[(k + 1) % n] * y[k];
    return a;
}

/* Test (d): do the projections of a and b overlap (with area), and if so,
 * a point inside both (pixel units). */
static bool overlap_point(const pt_face *a, const pt_face *b, double *px, double *py)
{
    enum { CAP = 2 * MTH_MAX_VERTICES + 2 };
    double x[CAP], y[CAP], tx[CAP], ty[CAP];
    unsigned n = a->pg.n;
    for (unsigned k = 0; k < n; k++)
        x[k] = a->pg.x[k], y[k] = a->pg.y[k];
    double orient = area2(b->pg.x, b->pg.y, b->pg.n) > 0 ? 1 : -1;
    for (unsigned e = 0; e < b->pg.n && n > 0; e++) {
        unsigned f = (e + 1) % b->pg.n;
        n = clip_by_edge(x, y, n, tx, ty, b->pg.x[e], b->pg.y[e], b->pg.x[f], b->pg.y[f], orient);
        for (unsigned k = 0; k < n; k++)
            x[k] = tx[k], y[k] = ty[k];
    }
    if (n < 3 || fabs(area2(x, y, n)) < 1e-9)
        return false;   /* touching along an edge or at a point: no overlap */
    *px = *py = 0;
    for (unsigned k = 0; k < n; k++)
        *px += x[k] / n, *py += y[k] / n;   /* inside: the overlap is convex */
    return true;
}

/* May face p be painted before face q? */
static bool order_ok(const pt_run *r, unsigned p, unsigned q)
{
    const pt_face *a = &r->face[p], *b = &r->face[q];
    if (b->zmax <= a->zmin)
        return true;   /* no overlap in depth: q is wholly nearer */
    if (a->box[0] >= b->box[2] || b->box[0] >= a->box[2] || a->box[1] >= b->box[3] ||
        b->box[1] >= a->box[3])
        return true;   /* (a) */
    if (all_on_side(a, &r->c.rf.faces[q], -1) || all_on_side(b, &r->c.rf.faces[p], +1))
        return true;   /* (b), (c) */
    double px, py;
    if (!overlap_point(a, b, &px, &py))
        return true;   /* (d) */
    double x = px * 2 / r->c.w - 1, y = 1 - py * 2 / r->c.h;
    return mth_nearer(mth_q(&r->c.rf.faces[q], x, y), q, mth_q(&r->c.rf.faces[p], x, y), p);
}

typedef struct {
    mth_ctx *c;
    unsigned fi;
} pt_paint;

static void paint_span(void *ctx, int row, int c0, int c1)
{
    pt_paint *pp = ctx;
    const ref_face *f = &pp->c->rf.faces[pp->fi];
    for (int col = c0; col < c1; col++)
        mth_put(pp->c, col, row, pp->fi, mth_q(f, mth_x(pp->c, col), mth_y(pp->c, row)));
}

/* Newell's loop: settle the head of the list, paint it, go on. */
static void paint_in_order(pt_run *r)
{
    for (unsigned h = 0; h < r->norder; h++) {
        for (unsigned j = h + 1; j < r->norder; j++) {
            unsigned q = r->order[j];
            if (order_ok(r, r->order[h], q) || r->marked[q])
                continue;   /* a marked face must not move again: a cycle, left wrong */
            r->marked[q] = 1;
            for (unsigned k = j; k > h; k--)
                r->order[k] = r->order[k - 1];
            r->order[h] = q;
            j = h;   /* test the new head against the rest */
        }
        pt_paint pp = {&r->c, r->order[h]};
        mth_fill(&r->face[r->order[h]].pg, r->c.w, r->c.h, paint_span, &pp);
    }
}

static void prepare_face(pt_run *r, unsigned fi)
{
    pt_face *f = &r->face[fi];
    f->n = 0;
    if (!mth_clip(&r->c.rf.faces[fi], f->v, &f->n)) {
        f->n = 0;
        return;
    }
    mth_project(&r->c, f->v, f->n, &f->pg);
    f->zmin = f->zmax = f->v[0].z;
    f->box[0] = f->box[2] = f->pg.x[0], f->box[1] = f->box[3] = f->pg.y[0];
    for (unsigned k = 1; k < f->n; k++) {
        f->zmin = fmin(f->zmin, f->v[k].z), f->zmax = fmax(f->zmax, f->v[k].z);
        f->box[0] = fmin(f->box[0], f->pg.x[k]), f->box[2] = fmax(f->box[2], f->pg.x[k]);
        f->box[1] = fmin(f->box[1], f->pg.y[k]), f->box[3] = fmax(f->box[3], f->pg.y[k]);
    }
    r->order[r->norder++] = fi;
}

typedef struct {
    double zmax;
    unsigned fi;
} pt_key;

/* Farthest far point first; equal: the later face first, so that the
 * earlier is painted last and wins, as equal depths do in the reference. */
static int far_first(const void *pa, const void *pb)
{
    const pt_key *a = pa, *b = pb;
    if (a->zmax != b->zmax)
        return a->zmax > b->zmax ? -1 : 1;
    return a->fi > b->fi ? -1 : a->fi < b->fi;
}

static bool sort_far_first(pt_run *r)
{
    pt_key *key = malloc((r->norder ? r->norder : 1) * sizeof *key);
    if (!key)
        return false;
    for (unsigned k = 0; k < r->norder; k++)
        key[k] = (pt_key){r->face[r->order[k]].zmax, r->order[k]};
    qsort(key, r->norder, sizeof *key, far_first);
    for (unsigned k = 0; k < r->norder; k++)
        r->order[k] = key[k].fi;
    free(key);
    return true;
}

int mth_painter_render(const alb_scene *s, const alb_profile *p, unsigned frame, alb_frame *out)
{
    pt_run r = {0};
    if (mth_begin(&r.c, s, p, frame, out))
        return -1;
    size_t nf = r.c.rf.n ? r.c.rf.n : 1;
    r.face = malloc(nf * sizeof *r.face);
    r.order = malloc(nf * sizeof *r.order);
    r.marked = calloc(nf, 1);
    bool ok = r.face && r.order && r.marked;
    if (ok) {
        for (unsigned fi = 0; fi < r.c.rf.n; fi++)
            prepare_face(&r, fi);
        ok = sort_far_first(&r);
        if (ok)
            paint_in_order(&r);
    }
    free(r.face);
    free(r.order);
    free(r.marked);
    return mth_end(&r.c, ok);
}

const char mth_painter_summary[] =
    "painter's algorithm: Newell depth sort with tests (a)-(d), no splitting (fails: cyclic "
    "overlap, interpenetration)";
