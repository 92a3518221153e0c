/* accuracy.c — VP against reference with the quantisation bounds of
 * docs/reference.md: a pixel is "clear" when its centre is farther than half
 * an intercept LSB (along the edge's U axis) from every exact edge line and
 * every emitted (quantised) edge, and the depths of the two nearest faces
 * there differ by more than their forms' rounding. */
#include "accuracy.h"
#include "../common/vec3.h"
#include "ref.h"
#include "albatros/words.h"
#include "albatros/gp.h"
#include "albatros/vp.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
    alb_ws_face *f;
    unsigned n;
    unsigned frac;
} emitted;

/* The FACE packets of frame `frame` of the stream. */
static int decode_frame(const uint32_t *w, size_t n, unsigned frame, emitted *em)
{
    alb_ws_reader r;
    alb_ws_event *ev = malloc(sizeof *ev);
    alb_diag d;
    alb_diag_init(&d, NULL);
    memset(em, 0, sizeof *em);
    int frames = -1, rc = ev ? 0 : -1;
    alb_ws_reader_init(&r, w, n, "");
    while (!rc && !r.ended && alb_ws_next(&r, ev, &d) == ALB_OK) {
        if (ev->kind == ALB_WS_EV_CONFIG)
            em->frac = ev->u.config.edge_frac_bits;
        frames += ev->kind == ALB_WS_EV_FRAME;
        if (ev->kind == ALB_WS_EV_FACE && frames == (int)frame) {
            alb_ws_face *nf = realloc(em->f, (em->n + 1) * sizeof *nf);
            if (!nf)
                rc = -1;
            else
                em->f = nf, em->f[em->n++] = ev->u.face;
        }
    }
    free(ev);
    return rc;
}

static double intercept(uint32_t q, unsigned frac) { return ldexp(q, -(int)frac) - 3; }

/* Distance along the U axis from (x, y) to an emitted edge's line. */
static double emitted_distance(const alb_ws_edge *e, unsigned frac, double x, double y)
{
    double a = intercept(e->x1, frac), b = intercept(e->x2, frac);
    if (e->u)
        return fabs(x - (a + (b - a) * (y + 1) / 2));
    return fabs(y - (a + (b - a) * (x + 1) / 2));
}

/* Distance along the U axis from (x, y) to an exact line n.(x, y, 1) = 0. */
static double exact_distance(vec3 n, double x, double y)
{
    double f = fabs(n.x * x + n.y * y + n.z);
    return fabs(n.x) > fabs(n.y) ? f / fabs(n.x) : f / fabs(n.y);
}

static const alb_ws_face *find_emitted(const emitted *em, uint32_t id)
{
    for (unsigned i = 0; i < em->n; i++)
        if (em->f[i].id == id)
            return &em->f[i];
    return NULL;
}

/* Rounding bound of a face's near/Z: half a mantissa unit on each of the
 * three terms, |x|, |y| <= 1. */
static double depth_bound(const alb_ws_face *f) { return f ? 1.5 * ldexp(1, f->depth.exp) : 0; }

static bool pixel_clear(const ref_frame *rf, const emitted *em, const alb_profile *p, double near,
                        double x, double y)
{
    double delta = ldexp(1, -(int)(em->frac + 1)) * (1 + 1e-9) + 1e-12;
    vec3 dir = {x, y, 1};
    double q[2] = {0, 0};
    const alb_ws_face *fq[2] = {NULL, NULL};
    for (unsigned i = 0; i < rf->n; i++) {
        const ref_face *f = &rf->faces[i];
        bool in = true;
        for (unsigned k = 0; k < f->n; k++) {
            if (!(fabs(f->edge[k].x) + fabs(f->edge[k].y) > 0))
                continue;
            if (exact_distance(f->edge[k], x, y) <= delta)
                return false;
            in &= v3_dot(f->edge[k], dir) >= 0;
        }
        double qi = in ? v3_dot(f->plane_n, dir) / f->plane_d : 0;
        if (qi > q[0]) {
            q[1] = q[0], fq[1] = fq[0];
            q[0] = qi, fq[0] = find_emitted(em, f->id);
        } else if (qi > q[1]) {
            q[1] = qi, fq[1] = find_emitted(em, f->id);
        }
    }
    for (unsigned i = 0; i < em->n; i++)
        for (unsigned k = 0; k < em->f[i].n_edges; k++)
            if (emitted_distance(&em->f[i].edge[k], em->frac, x, y) <= delta)
                return false;
    double store = ldexp(1, -(int)p->depth_bits);
    double tol = depth_bound(fq[0]) + depth_bound(fq[1]) + 2 * store;
    if (q[0] > 0 && near * q[0] >= 1 - tol)
        return false;   /* nearer than `near`: the depth store saturates */
    if (q[0] > 0 && near * q[0] <= tol)
        return false;   /* beyond the depth store's range */
    if (q[1] > 0 && near * (q[0] - q[1]) <= tol)
        return false;   /* a depth tie within rounding */
    return true;
}

int accuracy_measure(const alb_scene *s, const alb_profile *p, unsigned frame, const uint32_t *stream,
                     size_t nwords, const alb_frame *vp, const alb_frame *ref, accuracy *out)
{
    ref_frame rf;
    emitted em;
    if (ref_prepare(s, p, frame, &rf))
        return -1;
    if (decode_frame(stream, nwords, frame, &em)) {
        ref_frame_free(&rf);
        return -1;
    }
    memset(out, 0, sizeof *out);
    out->first_clear_diff = (size_t)-1;
    for (unsigned y = 0; y < p->height; y++)
        for (unsigned x = 0; x < p->width; x++) {
            size_t i = (size_t)y * p->width + x;
            bool differs = vp->face[i] != ref->face[i];
            out->pixels++;
            out->face_diff += differs;
            if (!pixel_clear(&rf, &em, p, s->near, ref_sample_x(x, p->width),
                             ref_sample_y(y, p->height)))
                continue;
            out->clear++;
            if (differs && out->clear_diff++ == 0)
                out->first_clear_diff = i;
        }
    free(em.f);
    ref_frame_free(&rf);
    return 0;
}

typedef struct {
    const alb_scene *s;
    const alb_profile *p;
    const alb_ws_buf *b;
    accuracy *acc;
    int rc;
} measure_ctx;

static int measure_frame(void *ctx, const alb_frame *f, const alb_vp_stats *st)
{
    (void)st;
    measure_ctx *m = ctx;
    alb_frame ref;
    accuracy a;
    if (ref_render(m->s, m->p, f->number, &ref))
        return m->rc = -1;
    int rc = accuracy_measure(m->s, m->p, f->number, m->b->w, m->b->n, f, &ref, &a);
    alb_frame_free(&ref);
    if (rc)
        return m->rc = -1;
    if (a.clear_diff && m->acc->clear_diff == 0)
        m->acc->first_clear_diff = a.first_clear_diff;
    m->acc->pixels += a.pixels;
    m->acc->face_diff += a.face_diff;
    m->acc->clear += a.clear;
    m->acc->clear_diff += a.clear_diff;
    return 0;
}

int accuracy_of_scene(const alb_scene *s, const alb_profile *p, accuracy *acc, alb_diag *d)
{
    alb_gp *gp = NULL;
    alb_vp *vp = NULL;
    alb_ws_buf b;
    alb_ws_buf_init(&b);
    measure_ctx m = {s, p, &b, acc, 0};
    alb_err e = alb_gp_create(&gp, s, p, d);
    if (!e)
        e = alb_gp_run(gp, &b, NULL, d);
    if (!e)
        e = alb_vp_create(&vp, p, d);
    if (!e)
        e = alb_vp_run_stream(vp, b.w, b.n, "generated", measure_frame, &m, d);
    if (e && m.rc)
        alb_diag_at(d, ALB_ERR_NOMEM, s->file, 0, 0, "out of memory");
    alb_vp_destroy(vp);
    alb_gp_destroy(gp);
    alb_ws_buf_free(&b);
    return e ? -1 : 0;
}

int accuracy_of_text(const char *text, const alb_profile *p, accuracy *acc, char *err, size_t len)
{
    alb_scene s;
    alb_diag d;
    alb_diag_init(&d, NULL);
    if (alb_scene_parse(text, strlen(text), "generated", &s, &d)) {
        snprintf(err, len, "%u:%u: %s", d.line, d.col, d.msg);
        return -1;
    }
    int rc = accuracy_of_scene(&s, p, acc, &d);
    if (rc)
        snprintf(err, len, "%s", d.msg);
    alb_scene_free(&s);
    return rc;
}
