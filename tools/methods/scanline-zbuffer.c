/* scanline-zbuffer.c — the scan-line z-buffer (seed 000 §4.2; seed 002):
 * the z-buffer with a depth buffer one scan line high.  Polygons are sorted
 * into groups by their top row (the y-group sort), enter the active polygon
 * list there and leave it after their bottom row; each row the active edges
 * of every active polygon are paired into spans, and each pixel of a span
 * passes the line's fixed-point near/Z test (0.depth_bits, as the VP's).
 * Shading happens once per visible pixel, when the line is complete.
 * Known failures: those of the z-buffer (depth precision far away: ties keep
 * the earlier face), plus the drift of the edges' x stepped row by row. */
#include "common.h"

#include <limits.h>
#include <stdlib.h>

typedef struct {
    unsigned fi;             /* face index in the ref_frame */
    int row0, row1;          /* rows it covers, [row0, row1) */
    unsigned first, n;       /* its edges in the edge table */
} sl_poly;

typedef struct {
    mth_ctx c;
    sl_poly *poly;
    unsigned npoly;
    mth_edge *edge;          /* the edge table, polygon by polygon */
    unsigned *apl;           /* active polygon list */
    unsigned napl;
    uint32_t *line_depth;    /* the one-line z-buffer */
    unsigned *line_face;     /* UINT_MAX: background */
} sl_run;

static int by_top_row(const void *a, const void *b)
{
    const sl_poly *p = a, *q = b;
    if (p->row0 != q->row0)
        return p->row0 < q->row0 ? -1 : 1;
    return p->fi < q->fi ? -1 : p->fi > q->fi;
}

/* The polygon table: every face's edges, polygons in groups by top row. */
static void build_tables(sl_run *r)
{
    unsigned ne = 0;
    for (unsigned fi = 0; fi < r->c.rf.n; fi++) {
        mth_poly pg;
        if (!mth_face_poly(&r->c, fi, &pg))
            continue;
        unsigned n = mth_edges(&pg, r->c.h, fi, r->edge + ne);
        if (n == 0)
            continue;
        sl_poly *p = &r->poly[r->npoly++];
        p->fi = fi, p->first = ne, p->n = n;
        p->row0 = INT_MAX, p->row1 = 0;
        for (unsigned k = ne; k < ne + n; k++) {
            p->row0 = r->edge[k].row0 < p->row0 ? r->edge[k].row0 : p->row0;
            p->row1 = r->edge[k].row1 > p->row1 ? r->edge[k].row1 : p->row1;
        }
        ne += n;
    }
    qsort(r->poly, r->npoly, sizeof *r->poly, by_top_row);
}

/* One active polygon on one row: its spans through the line's depth test;
 * then its active edges step to the next row. */
static void poly_row(sl_run *r, const sl_poly *p, int row)
{
    mth_edge *ael[MTH_MAX_VERTICES];
    unsigned na = 0;
    for (unsigned k = p->first; k < p->first + p->n; k++)
        if (r->edge[k].row0 <= row && row < r->edge[k].row1)
            ael[na++] = &r->edge[k];
    mth_sort_edges(ael, na);
    const ref_face *f = &r->c.rf.faces[p->fi];
    double y = mth_y(&r->c, row);
    for (unsigned k = 0; k + 1 < na; k += 2) {
        int c0 = mth_col(ael[k]->x, r->c.w), c1 = mth_col(ael[k + 1]->x, r->c.w);
        for (int col = c0; col < c1; col++) {
            uint32_t d = mth_depth(&r->c, mth_q(f, mth_x(&r->c, col), y));
            if (d > r->line_depth[col]) {   /* strictly nearer: ties keep the earlier */
                r->line_depth[col] = d;
                r->line_face[col] = p->fi;
            }
        }
    }
    for (unsigned k = 0; k < na; k++)
        ael[k]->x += ael[k]->dx;
}

static void scan_rows(sl_run *r)
{
    unsigned next = 0;
    for (int row = 0; row < (int)r->c.h; row++) {
        while (next < r->npoly && r->poly[next].row0 <= row)
            r->apl[r->napl++] = next++;   /* the row's y-group enters */
        for (unsigned col = 0; col < r->c.w; col++)
            r->line_depth[col] = 0, r->line_face[col] = UINT_MAX;
        unsigned kept = 0;
        for (unsigned k = 0; k < r->napl; k++) {
            const sl_poly *p = &r->poly[r->apl[k]];
            poly_row(r, p, row);
            if (p->row1 > row + 1)
                r->apl[kept++] = r->apl[k];   /* still active below */
        }
        r->napl = kept;
        for (unsigned col = 0; col < r->c.w; col++)
            if (r->line_face[col] != UINT_MAX) {
                const ref_face *f = &r->c.rf.faces[r->line_face[col]];
                mth_put(&r->c, (int)col, row, r->line_face[col],
                        mth_q(f, mth_x(&r->c, (int)col), mth_y(&r->c, row)));
            }
    }
}

int mth_scanline_zbuffer_render(const alb_scene *s, const alb_profile *p, unsigned frame,
                                alb_frame *out)
{
    sl_run r = {0};
    if (mth_begin(&r.c, s, p, frame, out))
        return -1;
    size_t nf = r.c.rf.n ? r.c.rf.n : 1;
    r.poly = malloc(nf * sizeof *r.poly);
    r.edge = malloc(nf * MTH_MAX_VERTICES * sizeof *r.edge);
    r.apl = malloc(nf * sizeof *r.apl);
    r.line_depth = malloc(r.c.w * sizeof *r.line_depth);
    r.line_face = malloc(r.c.w * sizeof *r.line_face);
    bool ok = r.poly && r.edge && r.apl && r.line_depth && r.line_face;
    if (ok) {
        build_tables(&r);
        scan_rows(&r);
    }
    free(r.poly);
    free(r.edge);
    free(r.apl);
    free(r.line_depth);
    free(r.line_face);
    return mth_end(&r.c, ok);
}

const char mth_scanline_zbuffer_summary[] =
    "scan-line z-buffer: y-group sorted polygons, active edge pairs, one line of fixed-point "
    "depth (fails: depth precision far away)";
