/* ref.c — the exact reference renderer (see ref.h).  Written apart from the
 * GP: it casts the ray through each sample into the observer-space faces and
 * evaluates the scene's fields at the hit point by barycentric coordinates,
 * where the GP solves system (11) and the VP divides linear forms. */
#include "ref.h"
#include "../common/vec3.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The camera, computed here from the scene's own values and not with the
 * GP's matrices (m3_orientation, m3_look_at) or its correctly rounded maths:
 * each elementary rotation is applied to vectors as docs/scene-format.md
 * words it ("yaw turns forward (+z) toward +x, pitch turns forward toward +y,
 * roll turns up (+y) toward +x", applied roll first, as the product
 * Ry Rx Rz), in long double with the C library's sinl and cosl; a look-at
 * camera by Gram-Schmidt on up against the view direction.  A mistake in
 * the GP's camera therefore shows as a difference (docs/reference.md). */
typedef long double ldbl;
typedef struct {
    ldbl v[3];
} lvec;

static lvec lv(ldbl x, ldbl y, ldbl z) { return (lvec){{x, y, z}}; }
static ldbl lv_dot(lvec a, lvec b) { return a.v[0] * b.v[0] + a.v[1] * b.v[1] + a.v[2] * b.v[2]; }

static lvec lv_unit(lvec a)
{
    ldbl l = sqrtl(lv_dot(a, a));
    return lv(a.v[0] / l, a.v[1] / l, a.v[2] / l);
}

/* Turn v by deg degrees in the plane of axes `from` and `to`, `from` toward
 * `to`: from -> cos from + sin to, to -> cos to - sin from. */
static lvec turn_plane(lvec v, int from, int to, double deg)
{
    ldbl a = (ldbl)deg * 3.14159265358979323846264338327950288L / 180;
    ldbl c = cosl(a), s = sinl(a), f = v.v[from], t = v.v[to];
    v.v[from] = c * f - s * t;
    v.v[to] = s * f + c * t;
    return v;
}

enum { AX_X, AX_Y, AX_Z };

/* A body vector of a pose in the parent frame: roll, then pitch, then yaw. */
static lvec pose_apply(const alb_scene_pose *p, lvec v)
{
    v = turn_plane(v, AX_Y, AX_X, p->roll);
    v = turn_plane(v, AX_Z, AX_Y, p->pitch);
    return turn_plane(v, AX_Z, AX_X, p->yaw);
}

/* The observer's right, up and forward axes in the world. */
static void observer_axes(const alb_scene_observer *ob, lvec axes[3])
{
    if (ob->look_at) {
        lvec f = lv_unit(lv((ldbl)ob->at.x - ob->pose.pos.x, (ldbl)ob->at.y - ob->pose.pos.y,
                            (ldbl)ob->at.z - ob->pose.pos.z));
        lvec u = lv(ob->up.x, ob->up.y, ob->up.z);
        ldbl k = lv_dot(u, f);
        u = lv_unit(lv(u.v[0] - k * f.v[0], u.v[1] - k * f.v[1], u.v[2] - k * f.v[2]));
        /* right = up x forward in this left-handed frame (x = y x z) */
        axes[0] = lv(u.v[1] * f.v[2] - u.v[2] * f.v[1], u.v[2] * f.v[0] - u.v[0] * f.v[2],
                     u.v[0] * f.v[1] - u.v[1] * f.v[0]);
        axes[1] = u;
        axes[2] = f;
        return;
    }
    for (int a = 0; a < 3; a++)
        axes[a] = pose_apply(&ob->pose, lv(a == 0, a == 1, a == 2));
}

/* Observer space P = (sx X, sy Y, Z), (X, Y, Z) the eye's right, up and
 * forward components of (Q R + pos - E): P = m R + t, and R = inv (P - t). */
static void object_to_observer(const alb_scene_frame *fr, const alb_scene_pose *pose, double aspect, mat3 *m, vec3 *t,
                               mat3 *inv, mat3 *q_out)
{
    const alb_scene_observer *ob = &fr->obs;
    ldbl a = ob->aspect > 0 ? ob->aspect : aspect;
    ldbl half = (ldbl)ob->fov_y * 3.14159265358979323846264338327950288L / 360;
    ldbl scale[3] = {cosl(half) / sinl(half) / a, cosl(half) / sinl(half), 1};
    lvec eye[3], body[3];
    observer_axes(ob, eye);
    for (int j = 0; j < 3; j++)
        body[j] = pose_apply(pose, lv(j == 0, j == 1, j == 2));   /* Q's columns */
    lvec off = lv((ldbl)pose->pos.x - ob->pose.pos.x, (ldbl)pose->pos.y - ob->pose.pos.y,
                  (ldbl)pose->pos.z - ob->pose.pos.z);
    double tv[3];
    for (int i = 0; i < 3; i++) {
        for (int j = 0; j < 3; j++) {
            m->m[i][j] = (double)(scale[i] * lv_dot(eye[i], body[j]));
            /* the axes are orthonormal: the inverse is the transpose, over
             * the scale */
            inv->m[j][i] = (double)(lv_dot(eye[i], body[j]) / scale[i]);
            q_out->m[i][j] = (double)body[j].v[i];
        }
        tv[i] = (double)(scale[i] * lv_dot(eye[i], off));
    }
    *t = v3(tv[0], tv[1], tv[2]);
}

static void prepare_face(ref_face *rf, const vec3 *p, unsigned n)
{
    rf->n = n;
    bool all_front = true;
    for (unsigned k = 0; k < n; k++) {
        rf->v[k] = p[k];
        rf->edge[k] = v3_cross(p[k], p[(k + 1) % n]);
        all_front &= p[k].z > 0;
    }
    vec3 nn = {0, 0, 0};
    for (unsigned k = 0; k < n; k++) {
        const vec3 *a = &p[k], *b = &p[(k + 1) % n];
        nn.x += (a->y - b->y) * (a->z + b->z);
        nn.y += (a->z - b->z) * (a->x + b->x);
        nn.z += (a->x - b->x) * (a->y + b->y);
    }
    rf->plane_n = nn;
    rf->plane_d = v3_dot(nn, p[0]);
    rf->bbox[0] = rf->bbox[1] = -1;
    rf->bbox[2] = rf->bbox[3] = 1;
    if (all_front) {
        double x0 = INFINITY, y0 = INFINITY, x1 = -INFINITY, y1 = -INFINITY;
        for (unsigned k = 0; k < n; k++) {
            double x = p[k].x / p[k].z, y = p[k].y / p[k].z;
            x0 = fmin(x0, x), x1 = fmax(x1, x), y0 = fmin(y0, y), y1 = fmax(y1, y);
        }
        rf->bbox[0] = fmax(x0, -1), rf->bbox[1] = fmax(y0, -1);
        rf->bbox[2] = fmin(x1, 1), rf->bbox[3] = fmin(y1, 1);
    }
}

int ref_prepare(const alb_scene *s, const alb_profile *prof, unsigned frame, ref_frame *rf)
{
    const alb_scene_frame *fr = &s->frames[frame];
    rf->n = 0;
    rf->faces = malloc((s->nfaces ? s->nfaces : 1) * sizeof *rf->faces);
    if (!rf->faces)
        return -1;
    for (unsigned oi = 0; oi < s->nobj; oi++) {
        const alb_scene_object *o = &s->obj[oi];
        mat3 m, inv, q;
        vec3 t;
        object_to_observer(fr, alb_scene_pose_at(s, frame, oi), (double)prof->width / prof->height,
                           &m, &t, &inv, &q);
        mat3 qt = m3_transpose(&q);
        for (unsigned j = 0; j < o->nf; j++) {
            const alb_scene_face *f = &o->f[j];
            vec3 p[ALB_SCENE_MAX_FACE_VERTICES], c = {0, 0, 0};
            bool any_front = false;
            for (unsigned k = 0; k < f->count; k++) {
                p[k] = v3_add(m3_apply(&m, alb_scene_face_vertex(o, f, k)), t);
                any_front |= p[k].z > 0;
                c = v3_add(c, p[k]);
            }
            double side = 0;
            for (unsigned k = 0; k < f->count; k++)
                side += v3_dot(v3_cross(p[k], p[(k + 1) % f->count]), c);
            /* only fronts are visible: a back face's half-planes are empty */
            if (!any_front || !(side > 0))
                continue;
            ref_face *r = &rf->faces[rf->n++];
            r->id = f->id;
            r->obj = o;
            r->face = f;
            r->to_object = inv;
            r->t = t;
            r->light_obj = m3_apply(&qt, fr->light.dir);
            r->ambient = fr->light.ambient;
            prepare_face(r, p, f->count);
        }
    }
    return 0;
}

void ref_frame_free(ref_frame *rf)
{
    free(rf->faces);
    rf->faces = NULL;
    rf->n = 0;
}

/* The vertex triple (0, a, b) spanning the largest triangle: the one the
 * scene format's fields are defined by (docs/scene-format.md). */
static void field_triple(const alb_scene_object *o, const alb_scene_face *f, unsigned tri[3])
{
    double best = -1;
    vec3 p0 = alb_scene_face_vertex(o, f, 0);
    tri[0] = 0, tri[1] = 1, tri[2] = 2;
    for (unsigned a = 1; a + 1 < f->count; a++)
        for (unsigned b = a + 1; b < f->count; b++) {
            vec3 k = v3_cross(v3_sub(alb_scene_face_vertex(o, f, a), p0),
                              v3_sub(alb_scene_face_vertex(o, f, b), p0));
            if (v3_dot(k, k) > best) {
                best = v3_dot(k, k);
                tri[1] = a, tri[2] = b;
            }
        }
}

/* Barycentric weights of object point q in the triple: q = v0 + s e1 + t e2. */
static void barycentric(const alb_scene_object *o, const alb_scene_face *f, const unsigned tri[3], vec3 q,
                        double *s, double *t)
{
    vec3 v0 = alb_scene_face_vertex(o, f, tri[0]);
    vec3 e1 = v3_sub(alb_scene_face_vertex(o, f, tri[1]), v0);
    vec3 e2 = v3_sub(alb_scene_face_vertex(o, f, tri[2]), v0), w = v3_sub(q, v0);
    double a = v3_dot(e1, e1), b = v3_dot(e1, e2), c = v3_dot(e2, e2);
    double p = v3_dot(w, e1), r = v3_dot(w, e2), det = a * c - b * b;
    *s = (p * c - r * b) / det;
    *t = (a * r - b * p) / det;
}

static double lerp3(double a, double b, double c, double s, double t)
{
    return a + s * (b - a) + t * (c - a);
}

/* Colour (0..255 per channel, before fog) of face r at observer point P. */
void ref_shade_point(const alb_scene *sc, const ref_face *r, vec3 P, double out[3])
{
    const alb_scene_object *o = r->obj;
    const alb_scene_face *f = r->face;
    vec3 q = m3_apply(&r->to_object, v3_sub(P, r->t));
    unsigned tri[3];
    field_triple(o, f, tri);
    double s, t;
    barycentric(o, f, tri, q, &s, &t);
    const alb_scene_vertex *v[3];
    for (int k = 0; k < 3; k++)
        v[k] = &o->v[o->idx[f->first + tri[k]]];
    double inten = f->intensity;
    if (f->shade == ALB_SHADE_VERTEX) {
        inten = lerp3(v[0]->i, v[1]->i, v[2]->i, s, t);
    } else if (f->shade == ALB_SHADE_LIT) {
        /* -Newell is the front normal (docs/gp.md) */
        vec3 fn = v3_scale(alb_scene_face_newell(o, f), -1 / v3_len(alb_scene_face_newell(o, f)));
        vec3 nv[3];
        for (int k = 0; k < 3; k++)
            nv[k] = (v[k]->has & ALB_SV_NORMAL) ? v[k]->n : fn;
        vec3 n = v3(lerp3(nv[0].x, nv[1].x, nv[2].x, s, t), lerp3(nv[0].y, nv[1].y, nv[2].y, s, t),
                    lerp3(nv[0].z, nv[1].z, nv[2].z, s, t));
        inten = r->ambient + v3_dot(r->light_obj, n);
    }
    inten = fmin(fmax(inten, 0), 1);
    double texel[3] = {255, 255, 255};
    if (f->texmap != ALB_TEXMAP_NONE) {
        double u, w;
        if (f->texmap == ALB_TEXMAP_AXES) {
            u = f->axes[0] * q.x + f->axes[1] * q.y + f->axes[2] * q.z + f->axes[3];
            w = f->axes[4] * q.x + f->axes[5] * q.y + f->axes[6] * q.z + f->axes[7];
        } else {
            u = lerp3(v[0]->u, v[1]->u, v[2]->u, s, t);
            w = lerp3(v[0]->v, v[1]->v, v[2]->v, s, t);
        }
        const alb_scene_texture *tx = &sc->tex[f->texture];
        unsigned size = 1u << tx->log2size;
        unsigned iu = (unsigned)((u - floor(u)) * size) & (size - 1);
        unsigned iv = (unsigned)((w - floor(w)) * size) & (size - 1);
        uint32_t c = tx->texels[(size_t)iv * size + iu];
        for (int ch = 0; ch < 3; ch++)
            texel[ch] = c >> (16 - 8 * ch) & 0xFF;
    }
    for (int ch = 0; ch < 3; ch++)
        out[ch] = f->rgb[ch] * texel[ch] / 255 * inten;
}

typedef struct {
    int face;          /* index into ref_frame, -1 none */
    double q;          /* 1/Z */
} hit;

static hit cast(const ref_frame *rf, double x, double y)
{
    hit h = {-1, 0};
    vec3 dir = {x, y, 1};
    for (unsigned i = 0; i < rf->n; i++) {
        const ref_face *f = &rf->faces[i];
        if (x < f->bbox[0] || x > f->bbox[2] || y < f->bbox[1] || y > f->bbox[3])
            continue;
        bool in = true;
        for (unsigned k = 0; k < f->n && in; k++)
            in = v3_dot(f->edge[k], dir) >= 0;
        if (!in)
            continue;
        double q = v3_dot(f->plane_n, dir) / f->plane_d;
        if (q > h.q) {   /* nearer; equal depths keep the earlier face */
            h.face = (int)i;
            h.q = q;
        }
    }
    return h;
}

static double fogged(const alb_scene *s, const ref_face *f, double c, double fogc, double z)
{
    if (!s->fog || !f->face->fog)
        return c;
    double vis = fmin(fmax((s->fog_far - z) / (s->fog_far - s->fog_near), 0), 1);
    return fogc + (c - fogc) * vis;
}

void ref_fog_point(const alb_scene *s, const ref_face *f, double z, double rgb[3])
{
    for (int ch = 0; ch < 3; ch++)
        rgb[ch] = fogged(s, f, rgb[ch], s->fog_rgb[ch], z);
}

int ref_render(const alb_scene *s, const alb_profile *p, unsigned frame, alb_frame *out)
{
    ref_frame rf;
    if (ref_prepare(s, p, frame, &rf))
        return -1;
    if (alb_frame_alloc(out, p->width, p->height, false)) {
        ref_frame_free(&rf);
        return -1;
    }
    out->colour_bits = p->colour_bits;
    out->depth_bits = p->depth_bits;
    out->aa_levels = p->aa_levels;
    out->near = (float)s->near;
    out->number = frame;
    unsigned n = 1u << p->aa_levels, sw = p->width * n, shh = p->height * n;
    double top = ldexp(1, (int)p->colour_bits) - 1, dmax = ldexp(1, (int)p->depth_bits) - 1;
    for (unsigned y = 0; y < p->height; y++)
        for (unsigned x = 0; x < p->width; x++) {
            double sum[3] = {0, 0, 0}, best_q = 0;
            int best = -1;
            unsigned covered = 0;
            for (unsigned sy = 0; sy < n; sy++)
                for (unsigned sx = 0; sx < n; sx++) {
                    double xs = ref_sample_x(x * n + sx, sw), ys = ref_sample_y(y * n + sy, shh);
                    hit h = cast(&rf, xs, ys);
                    double c[3];
                    for (int ch = 0; ch < 3; ch++)
                        c[ch] = s->background[ch];
                    if (h.face >= 0) {
                        const ref_face *f = &rf.faces[h.face];
                        covered++;
                        ref_shade_point(s, f, v3_scale(v3(xs, ys, 1), 1 / h.q), c);
                        ref_fog_point(s, f, 1 / h.q, c);
                        if (h.q > best_q) {
                            best_q = h.q;
                            best = h.face;
                        }
                    }
                    for (int ch = 0; ch < 3; ch++)
                        sum[ch] += c[ch];
                }
            size_t i = (size_t)y * p->width + x;
            for (int ch = 0; ch < 3; ch++)
                out->rgb[3 * i + ch] = (uint16_t)floor(sum[ch] / (n * n) / 255 * top + 0.5);
            out->face[i] = best >= 0 ? rf.faces[best].id : ALB_FRAME_NO_FACE;
            out->depth[i] = best >= 0 ? (uint32_t)fmin(floor(s->near * best_q * (dmax + 1)), dmax) : 0;
            out->level[i] = ALB_FRAME_NO_LEVEL;
            out->coverage[i] = (uint16_t)covered;
        }
    ref_frame_free(&rf);
    return 0;
}
