/* accuracy.c — VP against reference, each pixel in one class of
 * docs/reference.md: within half an intercept LSB (along the edge's U axis)
 * of an exact or an emitted (quantised) edge; its nearest face nearer than
 * near (the depth store saturates) or beyond near 2^depth_bits (it
 * underflows); the two nearest faces within their forms' rounding; or clear
 * of all of these. */
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

/* The class of the pixel centred at (x, y) (accuracy.h); *covered if the
 * reference has a face there. */
static accuracy_class pixel_class(const ref_frame *rf, const emitted *em, const alb_profile *p,
                                  double near, double x, double y, bool *covered)
{
    double delta = ldexp(1, -(int)(em->frac + 1)) * (1 + 1e-9) + 1e-12;
    vec3 dir = {x, y, 1};
    double q[2] = {0, 0};
    const alb_ws_face *fq[2] = {NULL, NULL};
    bool edge = false;
    for (unsigned i = 0; i < rf->n; i++) {
        const ref_face *f = &rf->faces[i];
        bool in = true;
        for (unsigned k = 0; k < f->n; k++) {
            if (!(fabs(f->edge[k].x) + fabs(f->edge[k].y) > 0))
                continue;
            edge |= exact_distance(f->edge[k], x, y) <= delta;
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
    *covered = q[0] > 0;
    for (unsigned i = 0; i < em->n && !edge; i++)
        for (unsigned k = 0; k < em->f[i].n_edges; k++)
            edge |= emitted_distance(&em->f[i].edge[k], em->frac, x, y) <= delta;
    if (edge)
        return ACC_EDGE;
    double store = ldexp(1, -(int)p->depth_bits);
    double tol = depth_bound(fq[0]) + depth_bound(fq[1]) + 2 * store;
    if (q[0] > 0 && near * q[0] >= 1 - tol)
        return ACC_NEAR;    /* nearer than `near`: the depth store saturates */
    if (q[0] > 0 && near * q[0] <= tol)
        return ACC_FAR;     /* beyond the depth store's range */
    if (q[1] > 0 && near * (q[0] - q[1]) <= tol)
        return ACC_TIE;     /* a depth tie within rounding */
    return ACC_CLEAR;
}

const char *accuracy_class_name(accuracy_class c)
{
    static const char *const names[ACC_NCLASSES] = {"clear", "edge-band", "near-clamp",
                                                    "underflow", "depth-tie"};
    return c < ACC_NCLASSES ? names[c] : "?";
}

size_t accuracy_judged(const accuracy *a, unsigned judged)
{
    size_t n = 0;
    for (unsigned c = 0; c < ACC_NCLASSES; c++)
        n += judged >> c & 1 ? a->in_class[c] : 0;
    return n;
}

size_t accuracy_errors(const accuracy *a, unsigned judged)
{
    size_t n = 0;
    for (unsigned c = 0; c < ACC_NCLASSES; c++)
        n += judged >> c & 1 ? a->diff_in_class[c] : 0;
    return n;
}

void accuracy_init(accuracy *a) { memset(a, 0, sizeof *a); }

void accuracy_add(accuracy *sum, const accuracy *a)
{
    sum->pixels += a->pixels;
    sum->covered += a->covered;
    sum->face_diff += a->face_diff;
    for (unsigned c = 0; c < ACC_NCLASSES; c++) {
        if (a->diff_in_class[c] && !sum->diff_in_class[c]) {
            sum->first_diff[c] = a->first_diff[c];
            sum->first_frame[c] = a->first_frame[c];
            sum->first_scene[c] = sum->scenes + a->first_scene[c];
        }
        sum->in_class[c] += a->in_class[c];
        sum->diff_in_class[c] += a->diff_in_class[c];
    }
    sum->scenes += a->scenes;
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
    accuracy_init(out);
    for (unsigned y = 0; y < p->height; y++)
        for (unsigned x = 0; x < p->width; x++) {
            size_t i = (size_t)y * p->width + x;
            bool differs = vp->face[i] != ref->face[i], covered;
            accuracy_class c = pixel_class(&rf, &em, p, s->near, ref_sample_x(x, p->width),
                                           ref_sample_y(y, p->height), &covered);
            out->pixels++;
            out->covered += covered;
            out->face_diff += differs;
            out->in_class[c]++;
            if (differs && out->diff_in_class[c]++ == 0) {
                out->first_diff[c] = i;
                out->first_frame[c] = frame;
            }
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
    a.scenes = 0;
    alb_frame_free(&ref);
    if (rc)
        return m->rc = -1;
    accuracy_add(m->acc, &a);
    return 0;
}

int accuracy_of_scene(const alb_scene *s, const alb_profile *p, accuracy *acc, alb_diag *d)
{
    alb_gp *gp = NULL;
    alb_vp *vp = NULL;
    alb_ws_buf b;
    alb_ws_buf_init(&b);
    accuracy one;
    accuracy_init(&one);
    measure_ctx m = {s, p, &b, &one, 0};
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
    one.scenes = 1;   /* its frames' first differences are of scene 0 of one */
    if (!e)
        accuracy_add(acc, &one);
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
