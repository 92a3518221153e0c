/* raycast.c — ray casting (seed 003, "光线投射算法"; seed 004, the point-in-
 * polygon test by counting crossings): for each pixel the ray from the
 * observer through its centre is intersected with every face's plane and the
 * hit point tested against the polygon by the crossing number, in the plane
 * of the two largest components of the face normal; the nearest hit wins.
 * Unlike the reference (double, edge planes through the observer) it is
 * single precision (float) throughout: plane from Newell's sums of float
 * vertices, hit distance t = d / (N.ray), crossing test on the hit point.
 * Known failures: float precision — far or huge coordinates (Newell's
 * products overflow near 1e19, underflow near 1e-19: the face vanishes),
 * depth differences below 2^-24 relative (near-coplanar faces far away tie
 * and the earlier wins), slivers and nearly edge-on faces (the hit point's
 * rounding moves it across the polygon's edges). */
#include "common.h"

#include <float.h>
#include <stdlib.h>

typedef struct {
    float pu[ALB_SCENE_MAX_FACE_VERTICES], pv[ALB_SCENE_MAX_FACE_VERTICES];   /* kept axes */
    unsigned n;
    int u, v;                /* which two of x, y, z are kept */
    float nx, ny, nz, d;     /* plane N.P = d, observer space */
} rc_face;

static float axis(const float p[3], int k) { return p[k]; }

static void prepare(const ref_face *rf, rc_face *f)
{
    float p[ALB_SCENE_MAX_FACE_VERTICES][3];
    f->n = rf->n;
    for (unsigned k = 0; k < f->n; k++)
        p[k][0] = (float)rf->v[k].x, p[k][1] = (float)rf->v[k].y, p[k][2] = (float)rf->v[k].z;
    f->nx = f->ny = f->nz = 0;
    for (unsigned k = 0; k < f->n; k++) {   /* Newell's sums, in float */
        const float *a = p[k], *b = p[(k + 1) % f->n];
        f->nx += (a[1] - b[1]) * (a[2] + b[2]);
        f->ny += (a[2] - b[2]) * (a[0] + b[0]);
        f->nz += (a[0] - b[0]) * (a[1] + b[1]);
    }
    f->d = 0;   /* N.P averaged over the vertices: they are not exactly coplanar in float */
    for (unsigned k = 0; k < f->n; k++)
        f->d += (f->nx * p[k][0] + f->ny * p[k][1] + f->nz * p[k][2]) / (float)f->n;
    /* drop the axis the normal is largest along: the projection that keeps
     * the polygon largest */
    float ax = fabsf(f->nx), ay = fabsf(f->ny), az = fabsf(f->nz);
    int drop = ax >= ay && ax >= az ? 0 : ay >= az ? 1 : 2;
    f->u = drop == 0 ? 1 : 0, f->v = drop == 2 ? 1 : 2;
    for (unsigned k = 0; k < f->n; k++)
        f->pu[k] = axis(p[k], f->u), f->pv[k] = axis(p[k], f->v);
}

/* The crossing number of a ray from (u, v) along +u: odd is inside.  Half-
 * open in v so that a vertex on the ray is counted once. */
static bool inside(const rc_face *f, float u, float v)
{
    bool in = false;
    for (unsigned i = 0, j = f->n - 1; i < f->n; j = i++) {
        if ((f->pv[i] > v) != (f->pv[j] > v)) {
            float cu = f->pu[i] + (f->pu[j] - f->pu[i]) * (v - f->pv[i]) / (f->pv[j] - f->pv[i]);
            if (u < cu)
                in = !in;
        }
    }
    return in;
}

/* The nearest face hit by the ray through (x, y, 1), -1 if none; *t_out its
 * distance along the ray (= Z). */
static long cast(const mth_ctx *c, const rc_face *face, double x, double y, float *t_out)
{
    float dir[3] = {(float)x, (float)y, 1}, best_t = FLT_MAX;
    long best = -1;
    for (unsigned fi = 0; fi < c->rf.n; fi++) {
        const ref_face *rf = &c->rf.faces[fi];
        const rc_face *f = &face[fi];
        if (x < rf->bbox[0] || x > rf->bbox[2] || y < rf->bbox[1] || y > rf->bbox[3])
            continue;
        float den = f->nx * dir[0] + f->ny * dir[1] + f->nz * dir[2];
        float t = f->d / den;
        if (!(t > 0) || !(t < best_t))   /* behind, parallel, or not nearer: earlier wins ties */
            continue;
        float p[3] = {t * dir[0], t * dir[1], t};
        if (inside(f, axis(p, f->u), axis(p, f->v)))
            best = (long)fi, best_t = t;
    }
    *t_out = best_t;
    return best;
}

int mth_raycast_render(const alb_scene *s, const alb_profile *p, unsigned frame, alb_frame *out)
{
    mth_ctx c;
    if (mth_begin(&c, s, p, frame, out))
        return -1;
    rc_face *face = malloc((c.rf.n ? c.rf.n : 1) * sizeof *face);
    if (!face)
        return mth_end(&c, false);
    for (unsigned fi = 0; fi < c.rf.n; fi++)
        prepare(&c.rf.faces[fi], &face[fi]);
    for (int row = 0; row < (int)c.h; row++)
        for (int col = 0; col < (int)c.w; col++) {
            float t;
            long fi = cast(&c, face, mth_x(&c, col), mth_y(&c, row), &t);
            if (fi >= 0)
                mth_put(&c, col, row, (unsigned)fi, 1 / (double)t);
        }
    free(face);
    return mth_end(&c, true);
}

const char mth_raycast_summary[] =
    "ray casting in float: nearest ray-plane hit inside the polygon by crossing number (fails: "
    "float precision)";
