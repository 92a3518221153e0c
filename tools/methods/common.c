/* common.c — the shared part of the classic methods (see common.h): frame
 * set-up, clipping to the view pyramid, scan conversion, depth store values
 * and shading through the reference. */
#include "common.h"
#include "../../common/vec3.h"

#include <stdlib.h>
#include <string.h>

int mth_begin(mth_ctx *c, const alb_scene *s, const alb_profile *p, unsigned frame, alb_frame *out)
{
    memset(c, 0, sizeof *c);
    if (p->aa_levels != 0 || frame >= s->nframes)
        return -1;   /* the methods sample pixel centres only */
    if (ref_prepare(s, p, frame, &c->rf))
        return -1;
    if (alb_frame_alloc(out, p->width, p->height, false)) {
        ref_frame_free(&c->rf);
        return -1;
    }
    c->s = s, c->p = p, c->out = out;
    c->w = p->width, c->h = p->height;
    c->depth_one = ldexp(1, (int)p->depth_bits);
    c->colour_top = ldexp(1, (int)p->colour_bits) - 1;
    out->colour_bits = p->colour_bits;
    out->depth_bits = p->depth_bits;
    out->aa_levels = 0;
    out->near = (float)s->near;
    out->number = frame;
    size_t n = (size_t)c->w * c->h;
    for (size_t i = 0; i < n; i++) {
        /* the reference's rounding of the background into the frame store */
        for (int ch = 0; ch < 3; ch++)
            out->rgb[3 * i + ch] = (uint16_t)floor(s->background[ch] / 255.0 * c->colour_top + 0.5);
        out->face[i] = ALB_FRAME_NO_FACE;
        out->level[i] = ALB_FRAME_NO_LEVEL;
    }
    return 0;
}

int mth_end(mth_ctx *c, bool ok)
{
    ref_frame_free(&c->rf);
    if (!ok && c->out)
        alb_frame_free(c->out);
    return ok ? 0 : -1;
}

uint32_t mth_depth(const mth_ctx *c, double q)
{
    if (!(q > 0))
        return 0;
    double dmax = c->depth_one - 1;
    return (uint32_t)fmin(floor(c->s->near * q * c->depth_one), dmax);
}

void mth_put(mth_ctx *c, int col, int row, unsigned fi, double q)
{
    const ref_face *f = &c->rf.faces[fi];
    size_t i = (size_t)row * c->w + (size_t)col;
    double x = mth_x(c, col), y = mth_y(c, row), rgb[3];
    ref_shade_point(c->s, f, v3_scale(v3(x, y, 1), 1 / q), rgb);
    ref_fog_point(c->s, f, 1 / q, rgb);
    for (int ch = 0; ch < 3; ch++)
        c->out->rgb[3 * i + ch] = (uint16_t)floor(rgb[ch] / 255 * c->colour_top + 0.5);
    c->out->face[i] = f->id;
    c->out->depth[i] = mth_depth(c, q);
    c->out->level[i] = ALB_FRAME_NO_LEVEL;
    c->out->coverage[i] = 1;
}

/* Sutherland-Hodgman against the plane through the observer with normal
 * (a, 0, 1) or (0, a, 1), a = +-1: keeps z + a x >= 0 (or z + a y >= 0). */
static unsigned clip_plane(const vec3 *in, unsigned n, vec3 *out, int axis, double a)
{
    unsigned m = 0;
    for (unsigned k = 0; k < n; k++) {
        const vec3 *p = &in[k], *q = &in[(k + 1) % n];
        double dp = p->z + a * (axis == 0 ? p->x : p->y);
        double dq = q->z + a * (axis == 0 ? q->x : q->y);
        if (dp >= 0)
            out[m++] = *p;
        if ((dp >= 0) != (dq >= 0)) {
            double t = dp / (dp - dq);
            out[m++] = v3_add(*p, v3_scale(v3_sub(*q, *p), t));
        }
    }
    return m;
}

bool mth_clip(const ref_face *f, vec3 v[MTH_MAX_VERTICES], unsigned *n)
{
    vec3 tmp[MTH_MAX_VERTICES];
    unsigned m = f->n;
    memcpy(v, f->v, m * sizeof *v);
    /* The four planes meet only at the observer; between them z >= |x|, |y|,
     * so the part behind the observer goes with them (ALBATROS.md §4). */
    m = clip_plane(v, m, tmp, 0, 1);
    m = clip_plane(tmp, m, v, 0, -1);
    m = clip_plane(v, m, tmp, 1, 1);
    m = clip_plane(tmp, m, v, 1, -1);
    for (unsigned k = 0; k < m; k++)
        if (!(v[k].z > 0))
            return false;   /* only the observer itself: the face is edge-on */
    *n = m;
    return m >= 3;
}

void mth_project(const mth_ctx *c, const vec3 *v, unsigned n, mth_poly *out)
{
    out->n = n;
    for (unsigned k = 0; k < n; k++) {
        out->x[k] = (v[k].x / v[k].z + 1) * 0.5 * c->w;   /* eq. (4) */
        out->y[k] = (1 - v[k].y / v[k].z) * 0.5 * c->h;
    }
}

bool mth_face_poly(const mth_ctx *c, unsigned fi, mth_poly *out)
{
    vec3 v[MTH_MAX_VERTICES];
    unsigned n;
    if (!mth_clip(&c->rf.faces[fi], v, &n))
        return false;
    mth_project(c, v, n, out);
    return true;
}

unsigned mth_edges(const mth_poly *pg, unsigned rows, unsigned face, mth_edge *out)
{
    unsigned m = 0;
    for (unsigned k = 0; k < pg->n; k++) {
        unsigned a = k, b = (k + 1) % pg->n;
        if (pg->y[a] == pg->y[b])
            continue;   /* horizontal: crosses no row centre's line */
        if (pg->y[a] > pg->y[b])
            a = b, b = k;
        double r0 = ceil(pg->y[a] - 0.5), r1 = ceil(pg->y[b] - 0.5);
        r0 = fmax(r0, 0), r1 = fmin(r1, rows);
        if (r0 >= r1)
            continue;
        mth_edge *e = &out[m++];
        e->dx = (pg->x[b] - pg->x[a]) / (pg->y[b] - pg->y[a]);
        e->x = pg->x[a] + (r0 + 0.5 - pg->y[a]) * e->dx;
        e->row0 = (int)r0, e->row1 = (int)r1;
        e->face = face;
    }
    return m;
}

void mth_sort_edges(mth_edge **e, unsigned n)
{
    for (unsigned i = 1; i < n; i++)
        for (unsigned j = i; j > 0 && e[j - 1]->x > e[j]->x; j--) {
            mth_edge *t = e[j];
            e[j] = e[j - 1];
            e[j - 1] = t;
        }
}

void mth_fill(const mth_poly *pg, unsigned w, unsigned h, mth_span_fn span, void *ctx)
{
    mth_edge edge[MTH_MAX_VERTICES], *ael[MTH_MAX_VERTICES];
    unsigned ne = mth_edges(pg, h, 0, edge);
    int top = (int)h, bottom = 0;
    for (unsigned k = 0; k < ne; k++) {
        top = edge[k].row0 < top ? edge[k].row0 : top;
        bottom = edge[k].row1 > bottom ? edge[k].row1 : bottom;
    }
    for (int row = top; row < bottom; row++) {
        unsigned na = 0;
        for (unsigned k = 0; k < ne; k++)
            if (edge[k].row0 <= row && row < edge[k].row1)
                ael[na++] = &edge[k];
        mth_sort_edges(ael, na);
        for (unsigned k = 0; k + 1 < na; k += 2) {
            int c0 = mth_col(ael[k]->x, w), c1 = mth_col(ael[k + 1]->x, w);
            if (c0 < c1)
                span(ctx, row, c0, c1);
        }
        for (unsigned k = 0; k < na; k++)
            ael[k]->x += ael[k]->dx;   /* the next row: one step along the edge */
    }
}
