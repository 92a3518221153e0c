/* watkins.c — Watkins' span scan-line algorithm (seed 000 §4.3, figs.
 * 4.59-4.63; seed 004, "scan-line method"): one active edge list of all
 * polygons sorted by x; each crossing toggles its polygon's in/out flag, and
 * the row is cut into spans between neighbouring crossings.  An empty span
 * is background, a span with one polygon is that polygon, and in a span with
 * several the depths (1/Z, exact in double) are compared at its two ends —
 * here its first and last pixel centres, which a span that only touches
 * another at a crossing never shares.  1/Z is linear along the row, so a
 * polygon nearest at both ends is nearest throughout; if the nearest differs
 * (eq. 4.9: the sign of a depth difference changes), the polygons penetrate
 * inside the span: it is split at the crossing of the depths, the left part
 * drawn and the right part taken up again (fig. 4.63).
 * "watkins-nosplit" is the basic algorithm of fig. 4.61, for polygons that
 * do not penetrate: depth compared once, at the span's middle sample (fig.
 * 4.59 b), the winner takes the span.
 * Known failures: penetrating polygons without the split (one of them wins
 * the whole span across the line of intersection); with the split, only the
 * edges' x stepped row by row (drift) and sub-pixel roots. */
#include "common.h"

#include <stdlib.h>

typedef struct {
    mth_ctx c;
    bool split;              /* fig. 4.63 (penetration) or fig. 4.61 */
    mth_edge *edge;          /* the edge table, sorted by top row */
    unsigned nedge, next;
    mth_edge **ael;          /* active edge list, sorted by x */
    unsigned nael;
    uint8_t *inside;         /* per face: the in/out flag of this row */
    unsigned *act;           /* the polygons in the current span */
    unsigned nact;
} wk_run;

static int by_row0(const void *a, const void *b)
{
    const mth_edge *p = a, *q = b;
    return (p->row0 > q->row0) - (p->row0 < q->row0);
}

static void build_edges(wk_run *r)
{
    for (unsigned fi = 0; fi < r->c.rf.n; fi++) {
        mth_poly pg;
        if (mth_face_poly(&r->c, fi, &pg))
            r->nedge += mth_edges(&pg, r->c.h, fi, r->edge + r->nedge);
    }
    qsort(r->edge, r->nedge, sizeof *r->edge, by_row0);
}

/* The polygon of act[] nearest at column col of the row. */
static unsigned nearest_at(const wk_run *r, int col, int row)
{
    double x = mth_x(&r->c, col), y = mth_y(&r->c, row);
    unsigned best = r->act[0];
    double bq = mth_q(&r->c.rf.faces[best], x, y);
    for (unsigned k = 1; k < r->nact; k++) {
        double q = mth_q(&r->c.rf.faces[r->act[k]], x, y);
        if (mth_nearer(q, r->act[k], bq, best))
            best = r->act[k], bq = q;
    }
    return best;
}

static bool beats(const wk_run *r, unsigned a, unsigned b, int col, int row)
{
    double x = mth_x(&r->c, col), y = mth_y(&r->c, row);
    return mth_nearer(mth_q(&r->c.rf.faces[a], x, y), a, mth_q(&r->c.rf.faces[b], x, y), b);
}

/* The first column in (c0, c1) where s is nearer than l, given that it is at
 * c1 - 1 and not at c0: from the root of the (linear) depth difference, then
 * settled by the depth test itself so that rounding cannot misplace it. */
static int overtake_col(const wk_run *r, unsigned l, unsigned s, int c0, int c1, int row)
{
    const ref_face *fl = &r->c.rf.faces[l], *fs = &r->c.rf.faces[s];
    double y = mth_y(&r->c, row), xa = mth_x(&r->c, c0), xb = mth_x(&r->c, c1 - 1);
    double ga = mth_q(fl, xa, y) - mth_q(fs, xa, y), gb = mth_q(fl, xb, y) - mth_q(fs, xb, y);
    double t = ga / (ga - gb);   /* 0..1 along the span's samples */
    int col = c0 + (int)ceil(t * (c1 - 1 - c0));
    col = col <= c0 ? c0 + 1 : col >= c1 ? c1 - 1 : col;
    while (col > c0 + 1 && beats(r, s, l, col - 1, row))
        col--;
    while (col < c1 - 1 && !beats(r, s, l, col, row))
        col++;
    return col;
}

static void draw(wk_run *r, unsigned fi, int c0, int c1, int row)
{
    const ref_face *f = &r->c.rf.faces[fi];
    for (int col = c0; col < c1; col++)
        mth_put(&r->c, col, row, fi, mth_q(f, mth_x(&r->c, col), mth_y(&r->c, row)));
}

/* The span of pixels [c0, c1) covered by the polygons act[]. */
static void resolve_span(wk_run *r, int c0, int c1, int row)
{
    if (!r->split) {
        draw(r, nearest_at(r, (c0 + c1 - 1) / 2, row), c0, c1, row);
        return;
    }
    while (c0 < c1) {   /* each pass draws a sub-span: the stack of fig. 4.63 */
        unsigned l = nearest_at(r, c0, row);
        int end = c1;
        for (unsigned k = 0; k < r->nact; k++) {
            unsigned s = r->act[k];
            if (s != l && beats(r, s, l, c1 - 1, row)) {   /* eq. (4.9) */
                int col = overtake_col(r, l, s, c0, c1, row);
                end = col < end ? col : end;
            }
        }
        draw(r, l, c0, end, row);
        c0 = end;
    }
}

static void toggle(wk_run *r, unsigned fi)
{
    r->inside[fi] ^= 1;
    if (r->inside[fi]) {
        r->act[r->nact++] = fi;
        return;
    }
    for (unsigned k = 0; k < r->nact; k++)
        if (r->act[k] == fi) {
            r->act[k] = r->act[--r->nact];
            return;
        }
}

/* One row: the active edge list updated and sorted, then its spans. */
static void scan_row(wk_run *r, int row)
{
    unsigned kept = 0;
    for (unsigned k = 0; k < r->nael; k++)
        if (r->ael[k]->row1 > row)
            r->ael[kept++] = r->ael[k];
    r->nael = kept;
    while (r->next < r->nedge && r->edge[r->next].row0 <= row)
        r->ael[r->nael++] = &r->edge[r->next++];
    mth_sort_edges(r->ael, r->nael);
    for (unsigned k = 0; k < r->nael; k++) {
        toggle(r, r->ael[k]->face);
        if (r->nact > 0 && k + 1 < r->nael) {
            int c0 = mth_col(r->ael[k]->x, r->c.w), c1 = mth_col(r->ael[k + 1]->x, r->c.w);
            if (c0 < c1)
                resolve_span(r, c0, c1, row);
        }
    }
    for (unsigned k = 0; k < r->nael; k++)
        r->ael[k]->x += r->ael[k]->dx;
}

static int watkins_run(const alb_scene *s, const alb_profile *p, unsigned frame, alb_frame *out,
                       bool split)
{
    wk_run r = {0};
    if (mth_begin(&r.c, s, p, frame, out))
        return -1;
    r.split = split;
    size_t nf = r.c.rf.n ? r.c.rf.n : 1;
    r.edge = malloc(nf * MTH_MAX_VERTICES * sizeof *r.edge);
    r.ael = malloc(nf * MTH_MAX_VERTICES * sizeof *r.ael);
    r.inside = calloc(nf, 1);
    r.act = malloc(nf * sizeof *r.act);
    bool ok = r.edge && r.ael && r.inside && r.act;
    if (ok) {
        build_edges(&r);
        for (int row = 0; row < (int)r.c.h; row++)
            scan_row(&r, row);
    }
    free(r.edge);
    free(r.ael);
    free(r.inside);
    free(r.act);
    return mth_end(&r.c, ok);
}

int mth_watkins_render(const alb_scene *s, const alb_profile *p, unsigned frame, alb_frame *out)
{
    return watkins_run(s, p, frame, out, true);
}

int mth_watkins_nosplit_render(const alb_scene *s, const alb_profile *p, unsigned frame,
                               alb_frame *out)
{
    return watkins_run(s, p, frame, out, false);
}

const char mth_watkins_summary[] =
    "Watkins span scan-line: spans between edge crossings, depth at span ends, split at "
    "penetrations (fig. 4.63)";

const char mth_watkins_nosplit_summary[] =
    "Watkins span scan-line for non-penetrating polygons (fig. 4.61): one depth test per span "
    "(fails: penetration)";
