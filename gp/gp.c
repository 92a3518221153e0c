/* gp.c — the geometry processor.  Offline: each face's plane and the linear
 * fields of intensity, normals and texture (eqs. 9-11).  Per frame: the
 * observer transform of vertices and coefficients (eqs. 2-3), the depth form
 * (6), the numerators of (7), lighting (8), edges (16-17), culling (18), the
 * VP edge format (19) and bounding edges (20).  docs/gp.md walks through it. */
#include "gp_internal.h"
#include "../common/vec3.h"
#include "../common/fix.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
    vec3 n;              /* plane N.R = d, object space */
    double d;
    double shade[4];     /* static intensity field: M (3), D */
    double interp[4][3]; /* lit: rows A, B, C, D of the interpolation matrix */
    double tex[2][4];    /* u and v fields: M (3), D */
} face_db;

struct alb_gp {
    const alb_scene *scene;
    alb_profile prof;
    face_db **db;        /* per object, per face */
    vec3 *rn;            /* observer-space vertices of the current object */
    unsigned max_nv;
};

/* ---- offline database preparation ---- */

/* The vertex triple (0, a, b) spanning the largest triangle: the best-
 * conditioned system (11), whose determinant is k.N (§2). */
static void best_triple(const alb_scene_object *o, const alb_scene_face *f, unsigned tri[3])
{
    double best = -1;
    vec3 p0 = alb_scene_face_vertex(o, f, 0);
    tri[0] = 0, tri[1] = 1, tri[2] = 2;
    for (unsigned a = 1; a + 1 < f->count; a++)
        for (unsigned b = a + 1; b < f->count; b++) {
            vec3 k = v3_cross(v3_sub(alb_scene_face_vertex(o, f, a), p0),
                              v3_sub(alb_scene_face_vertex(o, f, b), p0));
            double area = v3_dot(k, k);
            if (area > best) {
                best = area;
                tri[1] = a, tri[2] = b;
            }
        }
}

/* One linear field over the face from values at the triple: system (11),
 * solved about the first vertex for precision far from the origin. */
static int solve_field(const alb_scene_object *o, const alb_scene_face *f, const unsigned tri[3],
                       vec3 n, const double val[3], double out[4])
{
    vec3 origin = alb_scene_face_vertex(o, f, tri[0]);
    vec3 r[3];
    for (int k = 0; k < 3; k++)
        r[k] = v3_sub(alb_scene_face_vertex(o, f, tri[k]), origin);
    if (gp_solve_linear(r, val, n, out))
        return -1;
    /* I = M.(R - origin) + D'  =>  D = D' - M.origin */
    out[3] -= out[0] * origin.x + out[1] * origin.y + out[2] * origin.z;
    return 0;
}

static alb_err prepare_face(const alb_scene *s, const alb_scene_object *o, const alb_scene_face *f,
                            face_db *db, alb_diag *d)
{
    vec3 n = alb_scene_face_newell(o, f);
    db->n = v3_scale(n, 1 / v3_len(n));
    db->d = v3_dot(db->n, alb_scene_face_vertex(o, f, 0));
    unsigned tri[3];
    best_triple(o, f, tri);
    double val[3];
    switch (f->shade) {
    case ALB_SHADE_FLAT:
        db->shade[0] = db->shade[1] = db->shade[2] = 0;
        db->shade[3] = f->intensity;
        break;
    case ALB_SHADE_VERTEX:
        for (int k = 0; k < 3; k++)
            val[k] = o->v[o->idx[f->first + tri[k]]].i;
        if (solve_field(o, f, tri, db->n, val, db->shade))
            goto singular;
        break;
    case ALB_SHADE_LIT: {
        /* The front normal is -Newell: with x right, y up, z forward a face
         * counter-clockwise on the screen has its Newell normal pointing away
         * from the observer.  Vertices without a normal take the face's. */
        vec3 front = v3_scale(db->n, -1);
        for (int c = 0; c < 3; c++) {
            double col[4];
            for (int k = 0; k < 3; k++) {
                const alb_scene_vertex *v = &o->v[o->idx[f->first + tri[k]]];
                vec3 nv = (v->has & ALB_SV_NORMAL) ? v->n : front;
                val[k] = c == 0 ? nv.x : c == 1 ? nv.y : nv.z;
            }
            if (solve_field(o, f, tri, db->n, val, col))
                goto singular;
            for (int row = 0; row < 4; row++)
                db->interp[row][c] = col[row];
        }
        break;
    }
    }
    if (f->texmap == ALB_TEXMAP_AXES) {
        memcpy(db->tex[0], f->axes, 4 * sizeof(double));
        memcpy(db->tex[1], f->axes + 4, 4 * sizeof(double));
    } else if (f->texmap == ALB_TEXMAP_UV) {
        for (int t = 0; t < 2; t++) {
            for (int k = 0; k < 3; k++) {
                const alb_scene_vertex *v = &o->v[o->idx[f->first + tri[k]]];
                val[k] = t ? v->v : v->u;
            }
            if (solve_field(o, f, tri, db->n, val, db->tex[t]))
                goto singular;
        }
    }
    return ALB_OK;
singular:
    return alb_diag_at(d, ALB_ERR_GEOMETRY, s->file, f->line, 0,
                   "face %u: system (11) is singular (vertices nearly collinear)", f->id);
}

/* ---- scene values the stream stores as they are ---- */

/* FRAME's fog distances: Z/near in unsigned 24.8, rounded half up
 * (docs/word-format.md §3); false if the word would exceed 2^32 - 1. */
#define FOG_WORD_MAX 4294967295.0

static bool fog_word(double dist, double near, uint32_t *word)
{
    double v = floor(dist / near * 256 + 0.5);
    if (!(v >= 0 && v <= FOG_WORD_MAX))
        return false;
    *word = (uint32_t)v;
    return true;
}

/* CONFIG's near is IEEE-754 binary32 (docs/word-format.md §1), taken in its
 * normal range so the stream holds the scene's value to binary32 precision;
 * fog needs both words in range and far's beyond near's, as the decoder does.
 * The scene format itself takes any positive near (the reference methods run
 * the stress family `coords` from 10^-60 to 10^60): this is where a scene the
 * stream cannot carry is refused, at the line and column that set the value,
 * rather than written into a stream the decoder rejects. */
static alb_err check_stream_values(const alb_scene *s, alb_diag *d)
{
    if (!(s->near >= FLT_MIN && s->near <= FLT_MAX))
        return alb_diag_at(d, ALB_ERR_LIMIT, s->file, s->near_line, s->near_col,
                       "near %.17g is outside %.17g .. %.17g: the word stream stores near as "
                       "IEEE-754 binary32, normal numbers only", s->near, (double)FLT_MIN,
                       (double)FLT_MAX);
    uint32_t wn, wf;
    if (s->fog && !(fog_word(s->fog_far, s->near, &wf) && fog_word(s->fog_near, s->near, &wn)))
        return alb_diag_at(d, ALB_ERR_LIMIT, s->file, s->fog_line, s->fog_col,
                       "fog far %g is %g times near (%g): the word stream's 24.8 fog distance "
                       "holds at most %g; raise near or lower the fog distances", s->fog_far,
                       s->fog_far / s->near, s->near, FOG_WORD_MAX / 256);
    if (s->fog && wf <= wn)
        return alb_diag_at(d, ALB_ERR_LIMIT, s->file, s->fog_line, s->fog_col,
                       "fog near %g and far %g are one value in the word stream's 24.8 fog "
                       "distance (steps of near/256 = %g): move them further apart", s->fog_near,
                       s->fog_far, s->near / 256);
    return ALB_OK;
}

alb_err alb_gp_create(alb_gp **out, const alb_scene *scene, const alb_profile *prof, alb_diag *d)
{
    char msg[256];
    if (alb_profile_check(prof, msg, sizeof msg))
        return alb_diag_at(d, ALB_ERR_CONFIG, "", 0, 0, "%s", msg);
    alb_err e = check_stream_values(scene, d);
    if (e)
        return e;
    alb_gp *gp = calloc(1, sizeof *gp);
    if (!gp)
        return ALB_ERR_NOMEM;
    gp->scene = scene;
    gp->prof = *prof;
    gp->db = calloc(scene->nobj ? scene->nobj : 1, sizeof *gp->db);
    if (!gp->db)
        goto nomem;
    for (unsigned i = 0; i < scene->nobj; i++) {
        const alb_scene_object *o = &scene->obj[i];
        if (o->nv > gp->max_nv)
            gp->max_nv = o->nv;
        gp->db[i] = calloc(o->nf ? o->nf : 1, sizeof **gp->db);
        if (!gp->db[i])
            goto nomem;
        for (unsigned j = 0; j < o->nf; j++) {
            e = prepare_face(scene, o, &o->f[j], &gp->db[i][j], d);
            if (e) {
                alb_gp_destroy(gp);
                return e;
            }
        }
    }
    gp->rn = malloc((gp->max_nv ? gp->max_nv : 1) * sizeof *gp->rn);
    if (!gp->rn)
        goto nomem;
    *out = gp;
    return ALB_OK;
nomem:
    alb_gp_destroy(gp);
    return alb_diag_at(d, ALB_ERR_NOMEM, "", 0, 0, "out of memory preparing the GP database");
}

void alb_gp_destroy(alb_gp *gp)
{
    if (!gp)
        return;
    if (gp->db)
        for (unsigned i = 0; i < gp->scene->nobj; i++)
            free(gp->db[i]);
    free(gp->db);
    free(gp->rn);
    free(gp);
}

unsigned alb_gp_frame_count(const alb_gp *gp) { return gp->scene->nframes; }

/* ---- per frame ---- */

/* The observer transform of one object (eq. 2): R_n = T (R + R_sm), with T
 * the observer rotation, the object's own rotation and the scaling that makes
 * the field of view the square screen [-1,1]^2 (§5), and T_k = (T^-1)^T. */
typedef struct {
    mat3 t, tk;
    vec3 r_sm;
    vec3 light;          /* light direction in object space (eq. 8) */
    double ambient;
} xform;

/* The frame's part of every object's T: S V^T, computed once a frame. */
static mat3 observer_part(const alb_gp *gp, const alb_scene_observer *ob)
{
    double aspect = ob->aspect > 0 ? ob->aspect : (double)gp->prof.width / gp->prof.height;
    double sy = 1 / cr_tan(ob->fov_y * VEC3_PI / 360), sx = sy / aspect;
    mat3 o = ob->look_at ? m3_look_at(ob->pose.pos, ob->at, ob->up)
                         : m3_orientation(ob->pose.yaw, ob->pose.pitch, ob->pose.roll);
    mat3 v = m3_transpose(&o);
    mat3 s = {{{sx, 0, 0}, {0, sy, 0}, {0, 0, 1}}};
    return m3_mul(&s, &v);
}

static int object_xform(const alb_scene *s, const alb_scene_frame *fr, unsigned frame,
                        const mat3 *sv, unsigned oi, xform *x)
{
    const alb_scene_pose *pose = alb_scene_pose_at(s, frame, oi);
    mat3 q = m3_orientation(pose->yaw, pose->pitch, pose->roll);
    x->t = m3_mul(sv, &q);
    if (!m3_inverse_transpose(&x->t, &x->tk))
        return -1;
    mat3 qt = m3_transpose(&q);
    x->r_sm = m3_apply(&qt, v3_sub(pose->pos, fr->obs.pose.pos));
    x->light = m3_apply(&qt, fr->light.dir);
    x->ambient = fr->light.ambient;
    return 0;
}

/* eq. (3): a linear field (M, D) in observer coordinates. */
static void field_to_observer(const xform *x, const double f[4], vec3 *m_n, double *d_n)
{
    vec3 m = v3(f[0], f[1], f[2]);
    *m_n = m3_apply(&x->tk, m);
    *d_n = f[3] - v3_dot(m, x->r_sm);
}

/* eq. (7): numerator coefficients A_n + D_n Az, ... scaled like the depth form. */
static alb_ws_form numerator_form(const alb_gp *gp, vec3 m_n, double d_n, vec3 z, int *sat)
{
    double near = gp->scene->near;
    return gp_quantise_form(near * (m_n.x + d_n * z.x), near * (m_n.y + d_n * z.y),
                            near * (m_n.z + d_n * z.z), gp->prof.coef_bits, sat);
}

typedef enum { EMIT_OK, EMIT_DROP_FACE } emit_result;

/* Append a screen line as an edge, unless eq. (18) drops it or the face. */
static emit_result add_line(const alb_gp *gp, alb_ws_face *wf, gp_line l, alb_gp_stats *st, bool bounding)
{
    switch (gp_classify_line(l)) {
    case LINE_DROP_FACE:
        return EMIT_DROP_FACE;
    case LINE_DROP_EDGE:
        if (bounding)
            st->bound_culled++;
        else
            st->edges_offscreen++;
        return EMIT_OK;
    case LINE_CROSSES:
        break;
    }
    wf->edge[wf->n_edges++] = gp_edge_format(l, gp->prof.edge_frac_bits);
    if (bounding)
        st->bound_added++;
    return EMIT_OK;
}

/* An axis-parallel bounding edge at screen coordinate v, with its screen test
 * of §7: it crosses the screen iff |v| < 1; otherwise R and the sign of v say
 * whether the screen is inside (drop the edge) or outside (drop the face). */
static emit_result add_bound(const alb_gp *gp, alb_ws_face *wf, unsigned u, unsigned r, double v,
                             alb_gp_stats *st)
{
    if (fabs(v) < 1) {
        wf->edge[wf->n_edges++] = gp_bound_format(u, r, v, gp->prof.edge_frac_bits);
        st->bound_added++;
        return EMIT_OK;
    }
    /* R = 0: inside is coordinate >= v; R = 1: coordinate <= v. */
    if ((r == 0 && v >= 1) || (r == 1 && v <= -1))
        return EMIT_DROP_FACE;
    st->bound_culled++;
    return EMIT_OK;
}

/* The paper's rule (§7, code 20): at most two per face, because the sector
 * differences around a convex polygon add up to 8 and each generating vertex
 * takes 3 or 4.  A face that is not strictly convex on the screen — a vertex
 * turning back within the scene parser's tolerance, or a straight vertex
 * whose two edges rounding puts on either side of a sector border — steps
 * back a sector (a difference of 7) and can then generate at three or more.
 * The GP keeps the rule as a guarantee: the first two generating vertices in
 * vertex order get bounding edges, later ones none (bound_excess counts
 * them).  Bounding edges only bound, so this changes no covered sample. */
#define BOUND_PER_FACE 2

static emit_result bound_albatros(const alb_gp *gp, alb_ws_face *wf, const vec3 *p,
                                  const gp_line *lines, unsigned n, alb_gp_stats *st)
{
    unsigned generated = 0;
    for (unsigned k = 0; k < n; k++) {
        const gp_line *e1 = &lines[(k + n - 1) % n], *e2 = &lines[k];
        /* the vertex between edge k-1 and edge k must have a screen image */
        if (p[k].z <= 0 || (e1->a == 0 && e1->b == 0) || (e2->a == 0 && e2->b == 0))
            continue;
        unsigned code = gp_edge_code3(*e1) << 3 | gp_edge_code3(*e2);
        unsigned rom = gp_bound_rom[code];
        if (!(rom & BOUND_ROM_GEN))
            continue;
        if (generated == BOUND_PER_FACE) {
            st->bound_excess++;
            continue;
        }
        generated++;
        unsigned u = (rom & BOUND_ROM_U) != 0, r = rom & BOUND_ROM_R;
        double v = u ? p[k].x / p[k].z : p[k].y / p[k].z;
        if (add_bound(gp, wf, u, r, v, st) == EMIT_DROP_FACE)
            return EMIT_DROP_FACE;
    }
    return EMIT_OK;
}

static emit_result bound_box(const alb_gp *gp, alb_ws_face *wf, const vec3 *p, unsigned n, alb_gp_stats *st)
{
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    for (unsigned k = 0; k < n; k++) {
        if (p[k].z <= 0)
            return EMIT_OK;   /* unbounded on the screen: no box */
        double s[2] = {p[k].x / p[k].z, p[k].y / p[k].z};
        for (int a = 0; a < 2; a++) {
            lo[a] = fmin(lo[a], s[a]);
            hi[a] = fmax(hi[a], s[a]);
        }
    }
    /* x >= xmin, x <= xmax (vertical, U = 1); y >= ymin, y <= ymax (U = 0) */
    const struct { unsigned u, r; double v; } box[4] = {
        {1, 0, lo[0]}, {1, 1, hi[0]}, {0, 0, lo[1]}, {0, 1, hi[1]}};
    for (int i = 0; i < 4; i++)
        if (add_bound(gp, wf, box[i].u, box[i].r, box[i].v, st) == EMIT_DROP_FACE)
            return EMIT_DROP_FACE;
    return EMIT_OK;
}

static emit_result bound_bisector(const alb_gp *gp, alb_ws_face *wf, const vec3 *p, unsigned n,
                                  alb_gp_stats *st)
{
    for (unsigned k = 0; k < n; k++)
        if (p[k].z <= 0)
            return EMIT_OK;
    for (unsigned k = 0; k < n; k++) {
        const vec3 *a = &p[(k + n - 1) % n], *b = &p[k], *c = &p[(k + 1) % n];
        double bx = b->x / b->z, by = b->y / b->z;
        double d1x = bx - a->x / a->z, d1y = by - a->y / a->z;
        double d2x = c->x / c->z - bx, d2y = c->y / c->z - by;
        double l1 = cr_hypot(d1x, d1y), l2 = cr_hypot(d2x, d2y);
        if (!(l1 > 0 && l2 > 0))
            continue;
        /* interior bisector -d1/|d1| + d2/|d2|; the edge is perpendicular to it */
        double nx = -d1x / l1 + d2x / l2, ny = -d1y / l1 + d2y / l2;
        if (!(cr_hypot(nx, ny) > 1e-9))
            continue;   /* a straight vertex needs no bounding edge */
        gp_line l = {nx, ny, -(nx * bx + ny * by)};
        if (add_line(gp, wf, l, st, true) == EMIT_DROP_FACE)
            return EMIT_DROP_FACE;
    }
    return EMIT_OK;
}

/* Build the FACE packet of one face; false if the face is dropped. */
static bool build_face(alb_gp *gp, const alb_scene_object *o, const alb_scene_face *f, const face_db *db,
                       const xform *x, alb_ws_face *wf, alb_gp_stats *st)
{
    const alb_scene *s = gp->scene;
    unsigned n = f->count;
    vec3 p[ALB_SCENE_MAX_FACE_VERTICES];
    bool any_front = false;
    for (unsigned k = 0; k < n; k++) {
        p[k] = gp->rn[o->idx[f->first + k]];
        any_front |= p[k].z > 0;
    }
    /* §4: a face wholly behind the observer projects reversed; with its edges
     * dropped below nothing would bound it, so it goes here. */
    if (!any_front) {
        st->faces_behind++;
        return false;
    }
    /* The sign of the edge functions over the face (§4): positive for a face
     * whose front the observer sees, whatever its vertices' Z. */
    vec3 c = {0, 0, 0};
    for (unsigned k = 0; k < n; k++)
        c = v3_add(c, p[k]);
    double side = 0;
    for (unsigned k = 0; k < n; k++)
        side += v3_dot(v3_cross(p[k], p[(k + 1) % n]), c);
    /* Plane in observer space and the depth form (6). */
    vec3 n_n = m3_apply(&x->tk, db->n);
    double d_n = db->d + v3_dot(db->n, x->r_sm);
    if (d_n == 0 || side == 0) {
        st->faces_edge_on++;
        return false;
    }
    if (side < 0 && gp->prof.cull_backfaces) {
        st->faces_backfacing++;
        return false;
    }
    vec3 z = v3_scale(n_n, 1 / d_n);   /* Az, Bz, Cz */
    int sat = 0, sat_shade = 0, sat_tex = 0;
    wf->n_edges = 0;
    wf->id = f->id;
    wf->rgb = (uint32_t)f->rgb[0] << 16 | (uint32_t)f->rgb[1] << 8 | f->rgb[2];
    wf->flags = 0;
    wf->texture = 0;
    wf->depth = gp_quantise_form(s->near * z.x, s->near * z.y, s->near * z.z,
                                 gp->prof.coef_bits, &sat);
    /* Edges (16-17) with culling (18). */
    gp_line lines[ALB_SCENE_MAX_FACE_VERTICES];
    for (unsigned k = 0; k < n; k++) {
        const vec3 *r1 = &p[k], *r2 = &p[(k + 1) % n];
        vec3 abc = v3_cross(*r1, *r2);
        lines[k] = (gp_line){abc.x, abc.y, abc.z};
        if (r1->z <= 0 && r2->z <= 0) {
            st->edges_behind++;   /* §4: both ends behind the observer */
            continue;
        }
        if (abc.x == 0 && abc.y == 0 && abc.z == 0) {
            st->edges_degenerate++;
            continue;
        }
        if (add_line(gp, wf, lines[k], st, false) == EMIT_DROP_FACE) {
            st->faces_offscreen++;
            return false;
        }
    }
    emit_result br = EMIT_OK;
    switch (gp->prof.bound) {
    case ALB_BOUND_NONE: break;
    case ALB_BOUND_ALBATROS: br = bound_albatros(gp, wf, p, lines, n, st); break;
    case ALB_BOUND_BOX: br = bound_box(gp, wf, p, n, st); break;
    case ALB_BOUND_BISECTOR: br = bound_bisector(gp, wf, p, n, st); break;
    }
    if (br == EMIT_DROP_FACE) {
        st->faces_offscreen++;
        return false;
    }
    /* Intensity (7): static fields, or lit through the interpolation matrix
     * (8) in object space, then transformed like any field (3). */
    bool shaded = !(f->shade == ALB_SHADE_FLAT && f->intensity == 1.0);
    if (shaded) {
        double field[4];
        if (f->shade == ALB_SHADE_LIT) {
            const vec3 *l = &x->light;
            for (int row = 0; row < 4; row++)
                field[row] = db->interp[row][0] * l->x + db->interp[row][1] * l->y +
                             db->interp[row][2] * l->z;
            field[3] += x->ambient;
        } else {
            memcpy(field, db->shade, sizeof field);
        }
        vec3 m_n;
        double dd;
        field_to_observer(x, field, &m_n, &dd);
        wf->shade = numerator_form(gp, m_n, dd, z, &sat_shade);
        wf->flags |= ALB_WS_FACE_SHADE;
    }
    if (f->texmap != ALB_TEXMAP_NONE) {
        for (int t = 0; t < 2; t++) {
            vec3 m_n;
            double dd;
            field_to_observer(x, db->tex[t], &m_n, &dd);
            /* §2: drop the integer part of D_u, D_v — a whole number of
             * texture periods — so the VP keeps its precision near the
             * observer however far the texture origin is. */
            dd -= floor(dd);
            *(t ? &wf->tex_v : &wf->tex_u) = numerator_form(gp, m_n, dd, z, &sat_tex);
        }
        wf->flags |= ALB_WS_FACE_TEXTURE;
        wf->texture = (uint8_t)f->texture;
    }
    if (s->fog && f->fog)
        wf->flags |= ALB_WS_FACE_FOG;
    /* the first face whose forms were clamped, and which of them: the
     * warning names it (a huge intensity is not an edge-on face) */
    if ((sat || sat_shade || sat_tex) && !st->saturated_line) {
        st->saturated_line = f->line;
        st->saturated_form = sat ? "depth" : sat_shade ? "intensity" : "texture";
    }
    st->coef_saturated += (sat || sat_shade || sat_tex) ? 1u : 0u;
    st->edges_out += wf->n_edges;
    return true;
}

static uint32_t rgb_word(const uint8_t c[3])
{
    return (uint32_t)c[0] << 16 | (uint32_t)c[1] << 8 | c[2];
}

void alb_gp_stream_header(alb_gp *gp, alb_ws_buf *out)
{
    alb_ws_config cfg = {gp->prof.edge_frac_bits, gp->prof.coef_bits, (float)gp->scene->near};
    alb_ws_put_config(out, &cfg);
    for (unsigned i = 0; i < gp->scene->ntex; i++) {
        const alb_scene_texture *t = &gp->scene->tex[i];
        alb_ws_texture wt = {(uint8_t)i, (uint8_t)t->log2size, t->texels};
        alb_ws_put_texture(out, &wt);
    }
}

alb_err alb_gp_frame(alb_gp *gp, unsigned frame, alb_ws_buf *out, alb_gp_stats *st, alb_diag *d)
{
    const alb_scene *s = gp->scene;
    const alb_scene_frame *fr = &s->frames[frame];
    memset(st, 0, sizeof *st);
    size_t start = out->n;
    alb_ws_frame wf = {frame & 0xFFFFFF, rgb_word(s->background), s->fog, rgb_word(s->fog_rgb), 0, 0};
    /* in range, far beyond near: alb_gp_create checked (check_stream_values) */
    if (s->fog) {
        fog_word(s->fog_near, s->near, &wf.fog_near);
        fog_word(s->fog_far, s->near, &wf.fog_far);
    }
    alb_ws_put_frame(out, &wf);
    alb_ws_face *face = malloc(sizeof *face);
    if (!face)
        return alb_diag_at(d, ALB_ERR_NOMEM, s->file, 0, 0, "out of memory");
    mat3 sv = observer_part(gp, &fr->obs);
    for (unsigned oi = 0; oi < s->nobj; oi++) {
        const alb_scene_object *o = &s->obj[oi];
        xform x;
        if (object_xform(s, fr, frame, &sv, oi, &x)) {
            free(face);
            return alb_diag_at(d, ALB_ERR_GEOMETRY, s->file, o->line, 0,
                           "frame %u: object '%s' has a singular observer transform", frame,
                           o->name);
        }
        for (unsigned k = 0; k < o->nv; k++)
            gp->rn[k] = m3_apply(&x.t, v3_add(o->v[k].p, x.r_sm));
        for (unsigned j = 0; j < o->nf; j++) {
            st->faces_in++;
            if (build_face(gp, o, &o->f[j], &gp->db[oi][j], &x, face, st)) {
                if (st->faces_out == gp->prof.frame_faces) {
                    free(face);
                    return alb_diag_at(d, ALB_ERR_LIMIT, s->file, o->f[j].line, 0,
                                   "frame %u has more than %u faces (frame_faces=%u; "
                                   "docs/limits.md)", frame, gp->prof.frame_faces,
                                   gp->prof.frame_faces);
                }
                alb_ws_put_face(out, face);
                st->faces_out++;
            }
        }
    }
    free(face);
    alb_ws_put_frame_end(out, st->faces_out);
    st->saturated_frame = frame;
    if (out->oom)
        return alb_diag_at(d, ALB_ERR_NOMEM, s->file, 0, 0, "out of memory for the word stream");
    st->words = out->n - start;
    return ALB_OK;
}

void alb_gp_stats_add(alb_gp_stats *sum, const alb_gp_stats *s)
{
#define ADD(f) sum->f += s->f
    ADD(faces_in); ADD(faces_out); ADD(faces_behind); ADD(faces_backfacing);
    ADD(faces_edge_on); ADD(faces_offscreen); ADD(edges_out); ADD(edges_behind);
    ADD(edges_degenerate); ADD(edges_offscreen); ADD(bound_added); ADD(bound_culled);
    ADD(bound_excess);
    ADD(coef_saturated); ADD(words);
#undef ADD
    if (!sum->saturated_line && s->saturated_line) {
        sum->saturated_line = s->saturated_line;
        sum->saturated_form = s->saturated_form;
        sum->saturated_frame = s->saturated_frame;
    }
}

alb_err alb_gp_run(alb_gp *gp, alb_ws_buf *out, alb_gp_stats *total, alb_diag *d)
{
    alb_gp_stats sum, st;
    memset(&sum, 0, sizeof sum);
    size_t start = out->n;
    alb_gp_stream_header(gp, out);
    for (unsigned f = 0; f < gp->scene->nframes; f++) {
        alb_err e = alb_gp_frame(gp, f, out, &st, d);
        if (e)
            return e;
        alb_gp_stats_add(&sum, &st);
    }
    alb_ws_put_end(out);
    if (out->oom)
        return alb_diag_at(d, ALB_ERR_NOMEM, gp->scene->file, 0, 0, "out of memory for the word stream");
    sum.words = out->n - start;
    if (total)
        *total = sum;
    return ALB_OK;
}

alb_err alb_gp_compile_file(const char *scene, const char *profile, const char *const *sets,
                            uint32_t **w, size_t *n, alb_diag *d)
{
    alb_diag local;
    if (!d)
        d = &local;
    alb_diag_init(d, NULL);
    *w = NULL;
    *n = 0;
    alb_profile p;
    alb_err e = alb_profile_open(&p, profile, sets, d);
    if (e)
        return e;
    alb_scene s;
    e = scene ? alb_scene_load(scene, &s, d) : alb_scene_load_builtin(&s, d);
    if (e)
        return e;
    if ((e = alb_scene_resolve_screenspace(&s, p.width, p.height, d))) {
        alb_scene_free(&s);
        return e;
    }
    alb_gp *gp = NULL;
    alb_ws_buf b;
    alb_ws_buf_init(&b);
    e = alb_gp_create(&gp, &s, &p, d);
    if (!e)
        e = alb_gp_run(gp, &b, NULL, d);
    alb_gp_destroy(gp);
    alb_scene_free(&s);
    if (e) {
        alb_ws_buf_free(&b);
        return e;
    }
    *w = b.w;
    *n = b.n;
    return ALB_OK;
}
