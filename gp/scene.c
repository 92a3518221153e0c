/* scene.c — the text scene format of docs/scene-format.md: a line-oriented
 * parser whose every error names file:line:column and what was expected, and
 * the degenerate-face checks shared with the OBJ importer. */
#include "albatros/scene.h"
#include "../common/vec3.h"
#include "albatros/file.h"
#include "gp_internal.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_TOKENS 96

typedef struct {
    const char *s;
    unsigned len, col;
} token;

#define NO_QUOTE 0u   /* parser.open_quote: every quote was closed */

typedef struct {
    alb_scene *s;
    alb_diag *d;
    const char *file;
    unsigned line;
    token tok[MAX_TOKENS];
    unsigned ntok;
    unsigned open_quote;          /* column of a '"' the line did not close */
    alb_scene_object *obj;        /* inside object ... end */
    uint8_t colour[3];
    int texture;
    alb_scene_frame init;         /* state before the first frame line */
    alb_scene_frame *cur;         /* state being modified */
    bool in_frames;
    unsigned cap_frames;          /* of s->frames */
    /* object names -> index + 1, open addressing, at most half full: a
     * lookup by name costs the same in a scene of a million objects */
    unsigned *names;
    size_t cap_names;
} parser;

/* ---- allocation helpers ---- */

static int grow(void **p, unsigned *cap, unsigned need, size_t elem)
{
    if (need <= *cap)
        return 0;
    unsigned n = *cap ? *cap : 8;
    while (n < need) {
        if (n > (1u << 30))
            return -1;
        n *= 2;
    }
    void *q = realloc(*p, (size_t)n * elem);
    if (!q)
        return -1;
    *p = q;
    *cap = n;
    return 0;
}

void alb_scene_init(alb_scene *s, const char *name)
{
    memset(s, 0, sizeof *s);
    snprintf(s->file, sizeof s->file, "%s", name ? name : "<scene>");
    s->near = 0.1;
    s->background[0] = 90, s->background[1] = 140, s->background[2] = 210;
}

alb_scene_object *alb_scene_add_object(alb_scene *s, const char *name)
{
    if (grow((void **)&s->obj, &s->cap_obj, s->nobj + 1, sizeof *s->obj))
        return NULL;
    alb_scene_object *o = &s->obj[s->nobj++];
    memset(o, 0, sizeof *o);
    snprintf(o->name, sizeof o->name, "%s", name);
    return o;
}

int alb_scene_add_vertex(alb_scene_object *o, const alb_scene_vertex *v)
{
    if (grow((void **)&o->v, &o->cap_v, o->nv + 1, sizeof *o->v))
        return -1;
    o->v[o->nv++] = *v;
    return 0;
}

alb_scene_face *alb_scene_add_face(alb_scene *s, alb_scene_object *o, const unsigned *vidx, unsigned n)
{
    if (grow((void **)&o->f, &o->cap_f, o->nf + 1, sizeof *o->f) ||
        grow((void **)&o->idx, &o->cap_idx, o->nidx + n, sizeof *o->idx))
        return NULL;
    alb_scene_face *f = &o->f[o->nf++];
    memset(f, 0, sizeof *f);
    f->first = o->nidx;
    f->count = n;
    memcpy(o->idx + o->nidx, vidx, n * sizeof *vidx);
    o->nidx += n;
    f->rgb[0] = f->rgb[1] = f->rgb[2] = 200;
    f->intensity = 1.0;
    f->texture = -1;
    f->fog = true;
    f->id = s->nfaces++;
    return f;
}

const alb_scene_pose *alb_scene_pose_at(const alb_scene *s, unsigned f, unsigned oi)
{
    static const alb_scene_pose origin;
    const alb_scene_object *o = &s->obj[oi];
    if (!o->npose)
        return &origin;
    unsigned lo = 0, hi = o->npose;   /* the last change at or before f */
    while (hi - lo > 1) {
        unsigned mid = lo + (hi - lo) / 2;
        if (o->pose_from[mid] <= f)
            lo = mid;
        else
            hi = mid;
    }
    return &o->pose[lo];
}

int alb_scene_set_pose(alb_scene *s, unsigned oi, unsigned f, const alb_scene_pose *p)
{
    alb_scene_object *o = &s->obj[oi];
    if (o->npose && o->pose_from[o->npose - 1] > f)
        return -1;
    if (o->npose && o->pose_from[o->npose - 1] == f) {
        o->pose[o->npose - 1] = *p;
        return 0;
    }
    unsigned cap = o->cap_pose;
    if (grow((void **)&o->pose, &cap, o->npose + 1, sizeof *o->pose) ||
        grow((void **)&o->pose_from, &o->cap_pose, o->npose + 1, sizeof *o->pose_from))
        return -1;
    o->pose[o->npose] = *p;
    o->pose_from[o->npose++] = f;
    return 0;
}

int alb_scene_note_file(alb_scene *s, const char *path)
{
    char **f = realloc(s->files, (s->nfiles + 1) * sizeof *f);
    if (!f)
        return -1;
    s->files = f;
    if (!(f[s->nfiles] = malloc(strlen(path) + 1)))
        return -1;
    strcpy(f[s->nfiles++], path);
    return 0;
}

void alb_scene_free(alb_scene *s)
{
    for (unsigned i = 0; i < s->nfiles; i++)
        free(s->files[i]);
    free(s->files);
    for (unsigned i = 0; i < s->nobj; i++) {
        free(s->obj[i].v);
        free(s->obj[i].idx);
        free(s->obj[i].f);
        free(s->obj[i].pose);
        free(s->obj[i].pose_from);
    }
    for (unsigned i = 0; i < s->ntex; i++)
        free(s->tex[i].texels);
    free(s->obj);
    free(s->tex);
    free(s->frames);
    char file[sizeof s->file];
    memcpy(file, s->file, sizeof file);
    alb_scene_init(s, file);
}

/* ---- geometry checks ---- */

vec3 alb_scene_face_newell(const alb_scene_object *o, const alb_scene_face *f)
{
    vec3 n = {0, 0, 0};
    for (unsigned k = 0; k < f->count; k++) {
        vec3 a = alb_scene_face_vertex(o, f, k), b = alb_scene_face_vertex(o, f, (k + 1) % f->count);
        n.x += (a.y - b.y) * (a.z + b.z);
        n.y += (a.z - b.z) * (a.x + b.x);
        n.z += (a.x - b.x) * (a.y + b.y);
    }
    return n;
}

/* Tolerances of docs/scene-format.md §"Degenerate faces", relative to the
 * face's longest edge L. */
#define TOL_AREA   1e-12   /* |Newell| / L^2 below this: collinear */
#define TOL_PLANE  1e-6    /* distance from the plane / L above this: non-planar */
#define TOL_TURN   1e-9    /* sine of a turn this far negative: a reflex vertex */

/* The number by which the face's k-th vertex is written: 1-based in its
 * object, as on an `f` line (the index itself for OBJ's positive indices). */
static unsigned vertex_number(const alb_scene_object *o, const alb_scene_face *f, unsigned k)
{
    return o->idx[f->first + k] + 1;
}

/* Where an error about the face's k-th vertex is reported: the column of
 * its number on the `f` line, or the face's own column if unknown. */
static unsigned vertex_col(const alb_scene_face *f, const unsigned *cols, unsigned k)
{
    return cols ? cols[k] : f->col;
}

/* Distance of the face's vertex k from the plane through the others: the
 * Newell normal of the polygon without k, through the others' centroid.
 * Negative if the others have no plane (they lie on one line). */
static double distance_from_others(const alb_scene_object *o, const alb_scene_face *f, unsigned k)
{
    unsigned n = f->count;
    vec3 nn = {0, 0, 0}, c = {0, 0, 0};
    for (unsigned j = 0; j < n; j++) {
        if (j == k)
            continue;
        unsigned next = (j + 1) % n == k ? (j + 2) % n : (j + 1) % n;
        vec3 a = alb_scene_face_vertex(o, f, j), b = alb_scene_face_vertex(o, f, next);
        nn.x += (a.y - b.y) * (a.z + b.z);
        nn.y += (a.z - b.z) * (a.x + b.x);
        nn.z += (a.x - b.x) * (a.y + b.y);
        c = v3_add(c, a);
    }
    double nl = v3_len(nn);
    if (!(nl > 0))
        return -1;
    c = v3_scale(c, 1.0 / (n - 1));
    return fabs(v3_dot(v3_scale(nn, 1 / nl), v3_sub(alb_scene_face_vertex(o, f, k), c)));
}

/* A face that is not planar: name the vertex farthest from the plane of the
 * others.  Where one vertex was moved off a planar face, its distance is how
 * far it moved, while each other vertex is measured against a plane the moved
 * one has tilted (a plane through the centroid of all of them would put every
 * vertex of a quad at the same distance, and name the first). */
static alb_err not_planar(const alb_scene *s, const alb_scene_object *o, const alb_scene_face *f,
                          const unsigned *cols, double tol, alb_diag *d)
{
    unsigned worst = 0;
    double dist = -1;
    for (unsigned k = 0; k < f->count; k++) {
        double dk = distance_from_others(o, f, k);
        if (dk > dist)
            dist = dk, worst = k;
    }
    return alb_diag_at(d, ALB_ERR_GEOMETRY, s->file, f->line, vertex_col(f, cols, worst),
                   "face %u of object '%s' is not planar: vertex %u is %.3g from the plane of "
                   "the others (tolerance %.3g)", f->id, o->name, vertex_number(o, f, worst),
                   dist, tol);
}

alb_err alb_scene_check_face(const alb_scene *s, const alb_scene_object *o, const alb_scene_face *f,
                         const unsigned *cols, alb_diag *d)
{
    const char *file = s->file;
    unsigned n = f->count;
    if (n < 3)
        return alb_diag_at(d, ALB_ERR_GEOMETRY, file, f->line, f->col,
                       "face %u of object '%s' has %u vertices: expected at least 3 vertex "
                       "numbers", f->id, o->name, n);
    if (n > ALB_SCENE_MAX_FACE_VERTICES)
        return alb_diag_at(d, ALB_ERR_LIMIT, file, f->line, f->col,
                       "face %u of object '%s' has more than %d vertices (%u)", f->id, o->name,
                       ALB_SCENE_MAX_FACE_VERTICES, n);
    double L = 0;
    for (unsigned k = 0; k < n; k++) {
        unsigned k2 = (k + 1) % n;
        vec3 a = alb_scene_face_vertex(o, f, k), b = alb_scene_face_vertex(o, f, k2);
        unsigned va = vertex_number(o, f, k), vb = vertex_number(o, f, k2);
        if (!isfinite(a.x) || !isfinite(a.y) || !isfinite(a.z))
            return alb_diag_at(d, ALB_ERR_GEOMETRY, file, f->line, vertex_col(f, cols, k),
                           "face %u of object '%s': vertex %u is not finite", f->id, o->name, va);
        /* the second of the two is the one to delete, unless the pair is the
         * closing edge: then the last number written */
        unsigned col = vertex_col(f, cols, k2 ? k2 : k);
        double len = v3_len(v3_sub(b, a));
        if (len == 0 && va == vb)
            return alb_diag_at(d, ALB_ERR_GEOMETRY, file, f->line, col,
                           "face %u of object '%s': vertex %u is given twice in a row "
                           "(zero-length edge)", f->id, o->name, va);
        if (len == 0)
            return alb_diag_at(d, ALB_ERR_GEOMETRY, file, f->line, col,
                           "face %u of object '%s': vertices %u and %u coincide (zero-length edge)",
                           f->id, o->name, va, vb);
        if (len > L)
            L = len;
    }
    if (!isfinite(L))
        return alb_diag_at(d, ALB_ERR_GEOMETRY, file, f->line, f->col,
                       "face %u of object '%s': coordinates too large (edge length overflows)",
                       f->id, o->name);
    vec3 nn = alb_scene_face_newell(o, f);
    double nl = v3_len(nn);
    if (!(nl > TOL_AREA * L * L)) {
        /* no area because a vertex is used twice (not in a row: that is a
         * zero-length edge), folding the face onto itself: say so, not
         * "collinear" (f 1 2 1 3) */
        for (unsigned k = 0; k < n; k++)
            for (unsigned j = k + 2; j < n; j++)
                if (o->idx[f->first + k] == o->idx[f->first + j] && !(k == 0 && j == n - 1))
                    return alb_diag_at(d, ALB_ERR_GEOMETRY, file, f->line, vertex_col(f, cols, j),
                                   "face %u of object '%s' has zero area: vertex %u is used "
                                   "twice (as its vertex %u and %u), folding it onto itself",
                                   f->id, o->name, vertex_number(o, f, k), k + 1, j + 1);
        return alb_diag_at(d, ALB_ERR_GEOMETRY, file, f->line, f->col,
                       "face %u of object '%s' has zero area (collinear vertices)", f->id, o->name);
    }
    /* Planar: every vertex within TOL_PLANE L of the plane of the Newell
     * normal through the centroid. */
    vec3 u = v3_scale(nn, 1 / nl);
    vec3 c = {0, 0, 0};
    for (unsigned k = 0; k < n; k++)
        c = v3_add(c, alb_scene_face_vertex(o, f, k));
    c = v3_scale(c, 1.0 / n);
    for (unsigned k = 0; k < n; k++)
        if (fabs(v3_dot(u, v3_sub(alb_scene_face_vertex(o, f, k), c))) > TOL_PLANE * L)
            return not_planar(s, o, f, cols, TOL_PLANE * L, d);
    /* Convex and simple: no turn about the Newell normal below -TOL_TURN (its
     * sine), and one revolution in all; in the plane's frame (a, b), a x b =
     * u, so that a left turn about u is a left turn there (gp/polygon.c). */
    vec3 axis = fabs(u.x) <= fabs(u.y) && fabs(u.x) <= fabs(u.z) ? v3(1, 0, 0)
                : fabs(u.y) <= fabs(u.z) ? v3(0, 1, 0) : v3(0, 0, 1);
    vec3 pa = v3_cross(axis, u);
    pa = v3_scale(pa, 1 / v3_len(pa));
    vec3 pb = v3_cross(u, pa);
    double ex[ALB_SCENE_MAX_FACE_VERTICES], ey[ALB_SCENE_MAX_FACE_VERTICES];
    for (unsigned k = 0; k < n; k++) {
        vec3 e = v3_sub(alb_scene_face_vertex(o, f, (k + 1) % n), alb_scene_face_vertex(o, f, k));
        ex[k] = v3_dot(e, pa);
        ey[k] = v3_dot(e, pb);
    }
    unsigned k;
    switch (gp_polygon_turns(ex, ey, n, TOL_TURN, &k)) {
    case GP_TURNS_CONVEX:
        break;
    case GP_TURNS_REFLEX:
        return alb_diag_at(d, ALB_ERR_GEOMETRY, file, f->line, vertex_col(f, cols, k),
                       "face %u of object '%s' is not convex at vertex %u", f->id, o->name,
                       vertex_number(o, f, k));
    case GP_TURNS_NOT_SIMPLE:
        return alb_diag_at(d, ALB_ERR_GEOMETRY, file, f->line, f->col,
                       "face %u of object '%s' is not a simple convex polygon (it winds %.2f times)",
                       f->id, o->name, (double)(int)k);
    }
    return ALB_OK;
}

/* ---- tokens ---- */

static void tokenize(parser *p, const char *line, size_t len)
{
    p->ntok = 0;
    p->open_quote = NO_QUOTE;
    size_t i = 0;
    while (i < len) {
        while (i < len && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r'))
            i++;
        if (i >= len || line[i] == '#')
            break;
        size_t start = i;
        if (line[i] == '"') {
            start = ++i;
            while (i < len && line[i] != '"')
                i++;
            if (i >= len && !p->open_quote)
                p->open_quote = (unsigned)start;   /* the quote's own column */
        } else {
            while (i < len && line[i] != ' ' && line[i] != '\t' && line[i] != '\r' && line[i] != '#')
                i++;
        }
        if (p->ntok < MAX_TOKENS)
            p->tok[p->ntok] = (token){line + start, (unsigned)(i - start), (unsigned)start + 1};
        p->ntok++;
        if (i < len && line[i] == '"')
            i++;
    }
}

static bool tok_is(const token *t, const char *w)
{
    return strlen(w) == t->len && memcmp(t->s, w, t->len) == 0;
}

static alb_err __attribute__((format(printf, 3, 4)))
perr(parser *p, unsigned col, const char *fmt, ...)
{
    char msg[400];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    return alb_diag_at(p->d, ALB_ERR_PARSE, p->file, p->line, col, "%s", msg);
}

/* A word as a message quotes it: at most 40 characters, and those that
 * would not print (a form feed, a vertical tab) as \x0c. */
static void quote_word(char *out, size_t cap, const char *s, unsigned len)
{
    size_t n = 0;
    for (unsigned i = 0; i < len && i < 40 && n + 5 < cap; i++) {
        unsigned char c = (unsigned char)s[i];
        if (c >= 0x20 && c < 0x7F)
            out[n++] = (char)c;
        else
            n += (size_t)snprintf(out + n, cap - n, "\\x%02x", c);
    }
    out[n] = 0;
}

static alb_err err_found(parser *p, const token *t, const char *expected)
{
    char got[200];
    quote_word(got, sizeof got, t->s, t->len);
    return alb_diag_at(p->d, ALB_ERR_PARSE, p->file, p->line, t->col, "expected %s, found '%s'",
                   expected, got);
}

static alb_err err_tok(parser *p, unsigned i, const char *expected)
{
    if (i >= p->ntok) {
        unsigned col = p->ntok ? p->tok[p->ntok - 1].col + p->tok[p->ntok - 1].len : 1;
        return perr(p, col, "expected %s at end of line", expected);
    }
    return err_found(p, &p->tok[i], expected);
}

bool alb_scene_decimal_syntax(const char *s, size_t len)
{
    const char *e = s + len;
    bool digits = false;
    if (s < e && (*s == '+' || *s == '-'))
        s++;
    for (; s < e && *s >= '0' && *s <= '9'; s++)
        digits = true;
    if (s < e && *s == '.')
        for (s++; s < e && *s >= '0' && *s <= '9'; s++)
            digits = true;
    if (!digits)
        return false;
    if (s < e && (*s == 'e' || *s == 'E')) {
        s++;
        if (s < e && (*s == '+' || *s == '-'))
            s++;
        if (!(s < e && *s >= '0' && *s <= '9'))
            return false;
        while (s < e && *s >= '0' && *s <= '9')
            s++;
    }
    return s == e;
}

const char *alb_scene_byte_hint(const char *text, size_t len, size_t at)
{
    if (at == 0 && len >= 3 && memcmp(text, "\xef\xbb\xbf", 3) == 0)
        return " (this is a UTF-8 byte-order mark: save the file without one)";
    return "";
}

/* A number is copied to the stack for strtod; no coordinate, angle or colour
 * needs more characters than this (a double round-trips in 24). */
#define NUM_MAX_CHARS 63

/* The number spelled by token t (a whole token, or part of one). */
static alb_err num_token(parser *p, const token *t, double *out)
{
    char buf[NUM_MAX_CHARS + 1];
    if (t->len > NUM_MAX_CHARS) {
        if (!alb_scene_decimal_syntax(t->s, t->len))
            return err_found(p, t, "a number");
        return perr(p, t->col, "number '%.40s...' is too long: %u characters, at most %d",
                    t->s, t->len, NUM_MAX_CHARS);
    }
    memcpy(buf, t->s, t->len);
    buf[t->len] = 0;
    char *end;
    errno = 0;
    double v = strtod(buf, &end);
    bool whole = end != buf && *end == 0;
    /* strtod also reads "nan", "inf" and "infinity" (named as what they
     * are) and hexadecimal (not a scene number at all). */
    if (whole && (isnan(v) || (isinf(v) && errno != ERANGE)))
        return perr(p, t->col, "number '%s' is not finite or out of range", buf);
    if (!whole || !alb_scene_decimal_syntax(buf, t->len))
        return err_found(p, t, "a number");
    if (isinf(v))
        return perr(p, t->col, "number '%s' is not finite or out of range", buf);
    *out = v;   /* an underflow to 0 or a denormal is a faithful rounding */
    return ALB_OK;
}

static alb_err num(parser *p, unsigned i, double *out)
{
    if (i >= p->ntok)
        return err_tok(p, i, "a number");
    return num_token(p, &p->tok[i], out);
}

/* An aspect ratio: a number, or W/H as two numbers (`aspect 4/3`). */
static alb_err aspect_ratio(parser *p, unsigned i, double *out)
{
    if (i >= p->ntok)
        return err_tok(p, i, "a number or W/H");
    const token *t = &p->tok[i];
    const char *slash = memchr(t->s, '/', t->len);
    if (!slash)
        return num_token(p, t, out);
    unsigned wlen = (unsigned)(slash - t->s);
    token w = {t->s, wlen, t->col}, h = {slash + 1, t->len - wlen - 1, t->col + wlen + 1};
    double wv, hv;
    alb_err e;
    if (!w.len || !h.len)
        return perr(p, w.len ? h.col : w.col, "expected W/H with a number on each side of '/', "
                                             "found '%.*s'", (int)t->len, t->s);
    if ((e = num_token(p, &w, &wv)) || (e = num_token(p, &h, &hv)))
        return e;
    if (!(hv > 0))
        return perr(p, h.col, "aspect W/H needs H > 0");
    *out = wv / hv;
    return ALB_OK;
}

static alb_err nums(parser *p, unsigned i, double *out, unsigned n)
{
    for (unsigned k = 0; k < n; k++) {
        alb_err e = num(p, i + k, &out[k]);
        if (e)
            return e;
    }
    return ALB_OK;
}

static alb_err byte3(parser *p, unsigned i, uint8_t out[3])
{
    for (unsigned k = 0; k < 3; k++) {
        double v;
        alb_err e = num(p, i + k, &v);
        if (e)
            return e;
        if (v < 0 || v > 255 || v != floor(v))
            return alb_diag_at(p->d, ALB_ERR_PARSE, p->file, p->line, p->tok[i + k].col,
                           "colour component must be an integer 0..255, found %g", v);
        out[k] = (uint8_t)v;
    }
    return ALB_OK;
}

static alb_err name_tok(parser *p, unsigned i, char *out)
{
    if (i >= p->ntok)
        return err_tok(p, i, "a name");
    if (p->tok[i].len >= ALB_SCENE_NAME_MAX)
        return alb_diag_at(p->d, ALB_ERR_PARSE, p->file, p->line, p->tok[i].col,
                       "name longer than %d characters", ALB_SCENE_NAME_MAX - 1);
    memcpy(out, p->tok[i].s, p->tok[i].len);
    out[p->tok[i].len] = 0;
    return ALB_OK;
}

/* "at X Y Z", "yaw D", "pitch D", "roll D" from token i on. */
static alb_err pose_options(parser *p, unsigned i, alb_scene_pose *pose, unsigned *next,
                            const char *others)
{
    while (i < p->ntok) {
        double v[3];
        alb_err e;
        if (tok_is(&p->tok[i], "at")) {
            if ((e = nums(p, i + 1, v, 3)))
                return e;
            pose->pos = v3(v[0], v[1], v[2]);
            i += 4;
        } else if (tok_is(&p->tok[i], "yaw") || tok_is(&p->tok[i], "pitch") ||
                   tok_is(&p->tok[i], "roll")) {
            if ((e = num(p, i + 1, v)))
                return e;
            double *slot = tok_is(&p->tok[i], "yaw") ? &pose->yaw
                         : tok_is(&p->tok[i], "pitch") ? &pose->pitch : &pose->roll;
            *slot = v[0];
            i += 2;
        } else {
            break;
        }
    }
    *next = i;
    if (!others && i < p->ntok)
        return err_tok(p, i, "at, yaw, pitch or roll");
    return ALB_OK;
}

/* Give back what doubling reserved beyond a finished object's size: most
 * objects of big generated scenes are one small face. */
static void shrink_object(alb_scene_object *o)
{
    void *q;
    if (o->nv < o->cap_v && (q = realloc(o->v, o->nv * sizeof *o->v)))
        o->v = q, o->cap_v = o->nv;
    if (o->nf < o->cap_f && (q = realloc(o->f, o->nf * sizeof *o->f)))
        o->f = q, o->cap_f = o->nf;
    if (o->nidx < o->cap_idx && (q = realloc(o->idx, o->nidx * sizeof *o->idx)))
        o->idx = q, o->cap_idx = o->nidx;
}

static size_t name_hash(const char *s, size_t n)
{
    uint64_t h = 0xcbf29ce484222325ull;   /* FNV-1a */
    for (size_t i = 0; i < n; i++)
        h = (h ^ (unsigned char)s[i]) * 0x100000001b3ull;
    return (size_t)h;
}

static alb_scene_object *find_object(const parser *p, const token *t)
{
    if (!p->cap_names)
        return NULL;
    size_t mask = p->cap_names - 1;
    for (size_t i = name_hash(t->s, t->len) & mask; p->names[i]; i = (i + 1) & mask)
        if (tok_is(t, p->s->obj[p->names[i] - 1].name))
            return &p->s->obj[p->names[i] - 1];
    return NULL;
}

/* Enter object k into the name index; -1 if out of memory. */
static int index_object(parser *p, unsigned k)
{
    if (2 * ((size_t)k + 1) > p->cap_names) {
        size_t cap = p->cap_names ? 2 * p->cap_names : 64;
        unsigned *n = calloc(cap, sizeof *n);
        if (!n)
            return -1;
        free(p->names);
        p->names = n;
        p->cap_names = cap;
        for (unsigned j = 0; j < k; j++)
            index_object(p, j);   /* fits: cap > 2 k */
    }
    const char *name = p->s->obj[k].name;
    size_t mask = p->cap_names - 1, i = name_hash(name, strlen(name)) & mask;
    while (p->names[i])
        i = (i + 1) & mask;
    p->names[i] = k + 1;
    return 0;
}

static int find_texture(alb_scene *s, const token *t)
{
    for (unsigned i = 0; i < s->ntex; i++)
        if (tok_is(t, s->tex[i].name))
            return (int)i;
    return -1;
}

/* ---- statements ---- */

static alb_err st_observer(parser *p)
{
    alb_scene_observer *o = &p->cur->obs;
    unsigned i = 1;
    while (i < p->ntok) {
        unsigned next;
        alb_err e = pose_options(p, i, &o->pose, &next, "fov aspect");
        if (e)
            return e;
        i = next;
        if (i >= p->ntok)
            break;
        double v;
        if (tok_is(&p->tok[i], "fov")) {
            if ((e = num(p, i + 1, &v)))
                return e;
            if (!(v >= ALB_SCENE_MIN_FOV && v < 180))
                return perr(p, p->tok[i + 1].col, "field of view %g must be in [%g, 180) "
                            "degrees: a narrower view magnifies beyond what the GP's doubles "
                            "hold", v, ALB_SCENE_MIN_FOV);
            o->fov_y = v;
        } else if (tok_is(&p->tok[i], "aspect")) {
            if ((e = aspect_ratio(p, i + 1, &v)))
                return e;
            if (!(v >= ALB_SCENE_MIN_ASPECT && v < 100))
                return perr(p, p->tok[i + 1].col, "aspect %g must be in [%g, 100)", v,
                            ALB_SCENE_MIN_ASPECT);
            o->aspect = v;
        } else {
            return err_tok(p, i, "at, yaw, pitch, roll, fov or aspect");
        }
        i += 2;
    }
    return ALB_OK;
}

static alb_err st_light(parser *p)
{
    double v[3];
    alb_err e = nums(p, 1, v, 3);
    if (e)
        return e;
    p->cur->light.dir = v3(v[0], v[1], v[2]);
    if (p->ntok > 4) {
        if (!tok_is(&p->tok[4], "ambient"))
            return err_tok(p, 4, "'ambient'");
        if ((e = num(p, 5, &p->cur->light.ambient)))
            return e;
        if (p->ntok > 6)
            return err_tok(p, 6, "end of line");
    }
    return ALB_OK;
}

static alb_err st_texture(parser *p)
{
    alb_scene *s = p->s;
    char name[ALB_SCENE_NAME_MAX];
    alb_err e = name_tok(p, 1, name);
    if (e)
        return e;
    if (find_texture(s, &p->tok[1]) >= 0)
        return perr(p, p->tok[1].col, "texture '%s' defined twice", name);
    if (s->ntex >= 255)
        return perr(p, p->tok[0].col, "more than 255 textures");
    if (grow((void **)&s->tex, &s->cap_tex, s->ntex + 1, sizeof *s->tex))
        return ALB_ERR_NOMEM;
    alb_scene_texture t = {.line = p->line};
    snprintf(t.name, sizeof t.name, "%s", name);
    if (p->ntok > 2 && tok_is(&p->tok[2], "checker")) {
        double lg, sq = 8;
        uint8_t a[3], b[3];
        if ((e = num(p, 3, &lg)) || (e = byte3(p, 4, a)) || (e = byte3(p, 7, b)))
            return e;
        if (lg < 1 || lg > 10 || lg != floor(lg))
            return perr(p, p->tok[3].col, "texture size must be 2^1 .. 2^10 (give log2)");
        if (p->ntok > 10) {
            if ((e = num(p, 10, &sq)))
                return e;
            if (sq < 1 || sq > ldexp(1, (int)lg) || sq != floor(sq))
                return perr(p, p->tok[10].col, "squares must be an integer in 1..size");
        }
        if (p->ntok > 11)
            return err_tok(p, 11, "end of line");
        if (alb_scene_texture_checker(&t, (unsigned)lg, a, b, (unsigned)sq))
            return ALB_ERR_NOMEM;
    } else if (p->ntok > 2 && tok_is(&p->tok[2], "file")) {
        if (p->ntok < 4)
            return err_tok(p, 3, "a file name");
        if (p->ntok > 4)
            return err_tok(p, 4, "end of line");
        /* relative to the scene file's folder, from its whole name (not
         * the one kept for messages, which may be cut short) */
        const char *slash = strrchr(p->file, '/');
        int dirlen = slash ? (int)(slash - p->file + 1) : 0;
        if (p->tok[3].s[0] == '/')
            dirlen = 0;
        char *path = alb_strprintf("%.*s%.*s", dirlen, p->file, (int)p->tok[3].len, p->tok[3].s);
        if (!path)
            return ALB_ERR_NOMEM;
        alb_diag inner;
        alb_diag_init(&inner, NULL);
        e = alb_scene_texture_png(&t, path, &inner);
        if (!e && alb_scene_note_file(s, path))
            e = ALB_ERR_NOMEM;
        free(path);
        if (e == ALB_ERR_NOMEM)
            return e;
        if (e)
            return alb_diag_at(p->d, e, p->file, p->line, p->tok[3].col, "texture '%s': %s",
                           name, inner.msg);
    } else {
        return err_tok(p, 2, "'checker' or 'file'");
    }
    s->tex[s->ntex++] = t;
    return ALB_OK;
}

static alb_err st_object(parser *p)
{
    if (p->in_frames)
        return perr(p, p->tok[0].col, "objects must be declared before the first 'frame'");
    if (p->obj)
        return perr(p, p->tok[0].col, "'object' inside object '%s' (missing 'end'?)", p->obj->name);
    char name[ALB_SCENE_NAME_MAX];
    alb_err e = name_tok(p, 1, name);
    if (e)
        return e;
    if (find_object(p, &p->tok[1]))
        return perr(p, p->tok[1].col, "object '%s' defined twice", name);
    alb_scene_object *o = alb_scene_add_object(p->s, name);
    if (!o || index_object(p, p->s->nobj - 1))
        return ALB_ERR_NOMEM;
    o->line = p->line;
    unsigned i = 2;
    if (i < p->ntok && tok_is(&p->tok[i], "moving")) {
        o->moving = true;
        i++;
    }
    alb_scene_pose pose = {{0, 0, 0}, 0, 0, 0};
    unsigned next;
    if ((e = pose_options(p, i, &pose, &next, NULL)))
        return e;
    /* the initial pose, from frame 0 until a 'pose' changes it */
    if (alb_scene_set_pose(p->s, p->s->nobj - 1, 0, &pose))
        return ALB_ERR_NOMEM;
    p->obj = o;
    p->colour[0] = p->colour[1] = p->colour[2] = 200;
    p->texture = -1;
    return ALB_OK;
}

static alb_err st_vertex(parser *p)
{
    alb_scene_vertex v = {0};
    double x[3];
    alb_err e = nums(p, 1, x, 3);
    if (e)
        return e;
    v.p = v3(x[0], x[1], x[2]);
    unsigned i = 4;
    while (i < p->ntok) {
        if (tok_is(&p->tok[i], "i")) {
            if ((e = num(p, i + 1, &v.i)))
                return e;
            v.has |= ALB_SV_INTENSITY;
            i += 2;
        } else if (tok_is(&p->tok[i], "n")) {
            if ((e = nums(p, i + 1, x, 3)))
                return e;
            v.n = v3(x[0], x[1], x[2]);
            double l = v3_len(v.n);
            if (!(l > 0))
                return perr(p, p->tok[i].col, "vertex normal has zero length");
            v.n = v3_scale(v.n, 1 / l);
            v.has |= ALB_SV_NORMAL;
            i += 4;
        } else if (tok_is(&p->tok[i], "t")) {
            if ((e = nums(p, i + 1, x, 2)))
                return e;
            v.u = x[0], v.v = x[1];
            v.has |= ALB_SV_UV;
            i += 3;
        } else {
            return err_tok(p, i, "i, n or t");
        }
    }
    if (alb_scene_add_vertex(p->obj, &v))
        return ALB_ERR_NOMEM;
    return ALB_OK;
}

static alb_err face_options(parser *p, unsigned i, alb_scene_face *f)
{
    alb_err e;
    while (i < p->ntok) {
        if (tok_is(&p->tok[i], "colour") || tok_is(&p->tok[i], "color")) {
            if ((e = byte3(p, i + 1, f->rgb)))
                return e;
            i += 4;
        } else if (tok_is(&p->tok[i], "texture")) {
            if (i + 1 >= p->ntok)
                return err_tok(p, i + 1, "a texture name");
            f->texture = find_texture(p->s, &p->tok[i + 1]);
            if (f->texture < 0)
                return err_tok(p, i + 1, "the name of a texture defined above");
            i += 2;
        } else if (tok_is(&p->tok[i], "axes")) {
            if ((e = nums(p, i + 1, f->axes, 8)))
                return e;
            f->texmap = ALB_TEXMAP_AXES;
            i += 9;
        } else if (tok_is(&p->tok[i], "intensity")) {
            if ((e = num(p, i + 1, &f->intensity)))
                return e;
            i += 2;
        } else if (tok_is(&p->tok[i], "nofog")) {
            f->fog = false;
            i++;
        } else {
            return err_tok(p, i, "a vertex number, colour, texture, axes, intensity or nofog");
        }
    }
    return ALB_OK;
}

static alb_err st_face(parser *p)
{
    alb_scene_object *o = p->obj;
    unsigned vidx[ALB_SCENE_MAX_FACE_VERTICES], cols[ALB_SCENE_MAX_FACE_VERTICES];
    unsigned n = 0, i = 1;
    for (; i < p->ntok; i++) {
        const token *t = &p->tok[i];
        if (t->s[0] < '0' || t->s[0] > '9')
            break;
        double v;
        alb_err e = num(p, i, &v);
        if (e)
            return e;
        if (v < 1 || v > o->nv || v != floor(v))
            return alb_diag_at(p->d, ALB_ERR_PARSE, p->file, p->line, t->col,
                           "vertex number %g: object '%s' has vertices 1..%u so far", v,
                           o->name, o->nv);
        if (n == ALB_SCENE_MAX_FACE_VERTICES)
            return alb_diag_at(p->d, ALB_ERR_LIMIT, p->file, p->line, t->col,
                           "face has more than %d vertices", ALB_SCENE_MAX_FACE_VERTICES);
        cols[n] = t->col;
        vidx[n++] = (unsigned)v - 1;
    }
    if (n < 3)
        return err_tok(p, i, n ? "at least 3 vertex numbers" : "vertex numbers");
    alb_scene_face *f = alb_scene_add_face(p->s, o, vidx, n);
    if (!f)
        return ALB_ERR_NOMEM;
    f->line = p->line;
    f->col = p->tok[0].col;
    memcpy(f->rgb, p->colour, 3);
    f->texture = p->texture;
    alb_err e = face_options(p, i, f);
    if (e)
        return e;
    /* Shading: vertex intensities if every vertex has one; a moving object
     * is lit through its normals; otherwise flat. */
    bool all_i = true, all_uv = true;
    for (unsigned k = 0; k < n; k++) {
        all_i &= (o->v[vidx[k]].has & ALB_SV_INTENSITY) != 0;
        all_uv &= (o->v[vidx[k]].has & ALB_SV_UV) != 0;
    }
    f->shade = o->moving ? ALB_SHADE_LIT : all_i ? ALB_SHADE_VERTEX : ALB_SHADE_FLAT;
    if (f->texture >= 0 && f->texmap != ALB_TEXMAP_AXES) {
        if (!all_uv)
            return alb_diag_at(p->d, ALB_ERR_PARSE, p->file, p->line, p->tok[0].col,
                           "face has texture '%s' but no mapping: give 't U V' on each of its "
                           "vertices or 'axes' on the face", p->s->tex[f->texture].name);
        f->texmap = ALB_TEXMAP_UV;
    }
    if (f->texture < 0)
        f->texmap = ALB_TEXMAP_NONE;
    return alb_scene_check_face(p->s, o, f, cols, p->d);
}

static alb_err st_pose(parser *p)
{
    if (!p->in_frames)
        return perr(p, p->tok[0].col, "'pose' belongs inside a frame (after a 'frame' line)");
    if (p->ntok < 2)
        return err_tok(p, 1, "an object name");
    alb_scene_object *o = find_object(p, &p->tok[1]);
    if (!o)
        return err_tok(p, 1, "the name of an object defined above");
    /* a change from this frame on: what it does not set stays as it was */
    unsigned next, oi = (unsigned)(o - p->s->obj), frame = p->s->nframes - 1;
    alb_scene_pose pose = *alb_scene_pose_at(p->s, frame, oi);
    alb_err e = pose_options(p, 2, &pose, &next, NULL);
    if (!e && alb_scene_set_pose(p->s, oi, frame, &pose))
        e = ALB_ERR_NOMEM;
    return e;
}

static alb_err st_frame(parser *p)
{
    alb_scene *s = p->s;
    if (p->ntok > 1)
        return err_tok(p, 1, "end of line");
    /* doubling: a scene of 100,000 frames is read in linear time */
    if (grow((void **)&s->frames, &p->cap_frames, s->nframes + 1, sizeof *s->frames))
        return ALB_ERR_NOMEM;
    s->frames[s->nframes] = s->nframes ? s->frames[s->nframes - 1] : p->init;
    p->cur = &s->frames[s->nframes++];
    p->in_frames = true;
    return ALB_OK;
}

static alb_err statement(parser *p)
{
    const token *k = &p->tok[0];
    alb_scene *s = p->s;
    alb_err e;
    double v[3];
    if (p->obj) {
        if (tok_is(k, "v"))
            return st_vertex(p);
        if (tok_is(k, "f"))
            return st_face(p);
        if (tok_is(k, "colour") || tok_is(k, "color")) {
            if ((e = byte3(p, 1, p->colour)))
                return e;
            return p->ntok > 4 ? err_tok(p, 4, "end of line") : ALB_OK;
        }
        if (tok_is(k, "texture")) {
            if (p->ntok != 2)
                return err_tok(p, p->ntok < 2 ? 1 : 2, p->ntok < 2 ? "a texture name" : "end of line");
            if (tok_is(&p->tok[1], "none")) {
                p->texture = -1;
                return ALB_OK;
            }
            p->texture = find_texture(s, &p->tok[1]);
            return p->texture < 0 ? err_tok(p, 1, "the name of a texture defined above") : ALB_OK;
        }
        if (tok_is(k, "end")) {
            if (p->obj->nf == 0)
                return perr(p, k->col, "object '%s' has no faces", p->obj->name);
            shrink_object(p->obj);
            p->obj = NULL;
            return p->ntok > 1 ? err_tok(p, 1, "end of line") : ALB_OK;
        }
        if (tok_is(k, "object"))   /* says what is missing */
            return st_object(p);
        return err_tok(p, 0, "v, f, colour, texture or end (inside an object)");
    }
    if (tok_is(k, "observer"))
        return st_observer(p);
    if (tok_is(k, "light"))
        return st_light(p);
    if (tok_is(k, "frame"))
        return st_frame(p);
    if (tok_is(k, "pose"))
        return st_pose(p);
    if (tok_is(k, "object"))   /* says why it cannot come after a frame */
        return st_object(p);
    if (p->in_frames) {
        static const char *const global[] = {"texture", "screenspace", "near", "background",
                                             "fog"};
        for (size_t g = 0; g < sizeof global / sizeof global[0]; g++)
            if (tok_is(k, global[g]))
                return perr(p, k->col, "'%s' is a global statement: it must come before the "
                                       "first 'frame'", global[g]);
        return err_tok(p, 0, "observer, light, pose or frame (inside frames)");
    }
    if (tok_is(k, "texture"))
        return st_texture(p);
    if (tok_is(k, "screenspace")) {
        if (s->nobj)
            return perr(p, k->col, "'screenspace' must come before the first object");
        s->screenspace = true;
        if (!s->near_line)
            s->near = 1;   /* near/Z = depth / largest depth */
        return p->ntok > 1 ? err_tok(p, 1, "end of line") : ALB_OK;
    }
    if (tok_is(k, "near")) {
        if ((e = num(p, 1, &s->near)))
            return e;
        if (!(s->near > 0))
            return perr(p, p->tok[1].col, "near must be positive");
        /* whether the stream can hold it is the GP's check (alb_gp_create): the
         * reference methods take any positive near */
        s->near_line = p->line;
        s->near_col = p->tok[1].col;
        return p->ntok > 2 ? err_tok(p, 2, "end of line") : ALB_OK;
    }
    if (tok_is(k, "background")) {
        if ((e = byte3(p, 1, s->background)))
            return e;
        return p->ntok > 4 ? err_tok(p, 4, "end of line") : ALB_OK;
    }
    if (tok_is(k, "fog")) {
        if ((e = byte3(p, 1, s->fog_rgb)) || (e = nums(p, 4, v, 2)))
            return e;
        if (!(v[0] >= 0 && v[1] > v[0]))
            return perr(p, p->tok[5].col, "fog needs 0 <= near < far");
        s->fog = true;
        s->fog_near = v[0];
        s->fog_far = v[1];
        s->fog_line = p->line;   /* for the GP's check of the stream's fog words */
        s->fog_col = p->tok[5].col;
        return p->ntok > 6 ? err_tok(p, 6, "end of line") : ALB_OK;
    }
    return err_tok(p, 0, "a statement (object, texture, observer, light, near, background, "
                         "fog, frame)");
}

void alb_scene_default_frame(alb_scene_frame *f)
{
    memset(f, 0, sizeof *f);
    f->obs.fov_y = 60;
    f->light = (alb_scene_light){{0.3, 0.8, -0.5}, 0.3};
}

alb_err alb_scene_finish(alb_scene *s, alb_diag *d)
{
    (void)d;
    if (s->nframes == 0) {
        s->frames = calloc(1, sizeof *s->frames);
        if (!s->frames)
            return ALB_ERR_NOMEM;
        s->nframes = 1;
        alb_scene_default_frame(&s->frames[0]);
    }
    static const alb_scene_pose origin;
    for (unsigned i = 0; i < s->nobj; i++)
        if (!s->obj[i].npose && alb_scene_set_pose(s, i, 0, &origin))
            return ALB_ERR_NOMEM;
    return ALB_OK;
}

/* The line text[pos, end) holds only ASCII and no carriage return but the
 * one before its LF.  A bare CR is most likely a file with classic Mac (CR
 * only) line ends, which would otherwise read as one long line. */
static alb_err check_bytes(parser *p, const char *text, size_t len, size_t pos, size_t end)
{
    for (size_t i = pos; i < end; i++) {
        unsigned char c = (unsigned char)text[i];
        unsigned col = (unsigned)(i - pos) + 1;
        if (c == '\r' && i + 1 < end)
            return perr(p, col, "line ends with a bare carriage return (CR): use LF or CRLF "
                                "line ends");
        if (c == 0 || c >= 0x80)
            return perr(p, col, "byte 0x%02x: scene files are ASCII text%s", c,
                        alb_scene_byte_hint(text, len, i));
    }
    return ALB_OK;
}

alb_err alb_scene_parse(const char *text, size_t len, const char *name, alb_scene *s, alb_diag *d)
{
    parser p;
    memset(&p, 0, sizeof p);
    alb_scene_init(s, name);
    p.s = s;
    p.d = d;
    p.file = name ? name : s->file;
    p.texture = -1;
    alb_scene_default_frame(&p.init);
    p.cur = &p.init;
    alb_err e = ALB_OK;
    bool header = false;
    size_t pos = 0;
    while (pos < len && !e) {
        size_t end = pos;
        while (end < len && text[end] != '\n')
            end++;
        p.line++;
        if ((e = check_bytes(&p, text, len, pos, end)))
            break;
        tokenize(&p, text + pos, end - pos);
        pos = end + 1;
        if (p.ntok == 0)
            continue;
        if (p.open_quote) {
            e = alb_diag_at(d, ALB_ERR_PARSE, p.file, p.line, p.open_quote,
                        "unterminated quote: the '\"' here is not closed on its line");
            break;
        }
        if (p.ntok > MAX_TOKENS) {
            /* a face is the one statement that long: its own limit says more */
            if (tok_is(&p.tok[0], "f") && p.obj)
                e = alb_diag_at(d, ALB_ERR_LIMIT, p.file, p.line, p.tok[0].col,
                            "face has more than %d vertices (%u words on the line); split it "
                            "(docs/limits.md)", ALB_SCENE_MAX_FACE_VERTICES, p.ntok - 1);
            else
                e = alb_diag_at(d, ALB_ERR_PARSE, p.file, p.line, p.tok[MAX_TOKENS - 1].col,
                            "more than %d words on one line", MAX_TOKENS);
            break;
        }
        if (!header) {
            if (!tok_is(&p.tok[0], "albatros-scene") || p.ntok != 2 || !tok_is(&p.tok[1], "1")) {
                e = alb_diag_at(d, ALB_ERR_PARSE, p.file, p.line, 1,
                            "expected the header line 'albatros-scene 1'");
                break;
            }
            header = true;
            continue;
        }
        e = statement(&p);
    }
    if (!e && !header)
        e = alb_diag_at(d, ALB_ERR_PARSE, p.file, p.line ? p.line : 1, 1,
                    "empty scene: expected the header line 'albatros-scene 1'");
    if (!e && p.obj)
        e = alb_diag_at(d, ALB_ERR_PARSE, p.file, p.line, 1,
                    "object '%s' (line %u) has no 'end'", p.obj->name, p.obj->line);
    if (!e && s->nobj == 0)
        e = alb_diag_at(d, ALB_ERR_PARSE, p.file, p.line, 1, "scene has no objects");
    if (!e && s->nframes == 0) {
        /* one frame: the initial state itself */
        s->frames = malloc(sizeof *s->frames);
        if (!s->frames)
            e = ALB_ERR_NOMEM;
        else
            s->frames[s->nframes++] = p.init;
    }
    free(p.names);
    if (!e)
        e = alb_scene_finish(s, d);
    if (e == ALB_ERR_NOMEM)
        alb_diag_at(d, e, p.file, p.line, 0, "out of memory");
    if (e)
        alb_scene_free(s);
    return e;
}

alb_err alb_scene_load(const char *path, alb_scene *s, alb_diag *d)
{
    const char *why;
    FILE *f = alb_file_open_input(path, false, &why);
    if (!f)
        return alb_diag_at(d, ALB_ERR_IO, path, 0, 0, "cannot open scene: %s", why);
    char *buf;
    size_t len;
    /* a NUL ends the reading: the parser refuses it where it stands */
    int rc = alb_file_read_text(f, &buf, &len);
    int err = errno;
    fclose(f);
    if (rc == -2)
        return alb_diag_at(d, ALB_ERR_NOMEM, path, 0, 0, "scene too large for memory");
    if (rc)
        return alb_diag_at(d, ALB_ERR_IO, path, 0, 0, "read error: %s", strerror(err));
    alb_err e = alb_scene_parse(buf, len, path, s, d);
    free(buf);
    return e;
}

alb_err alb_scene_resolve_screenspace(alb_scene *s, unsigned width, unsigned height, alb_diag *d)
{
    if (!s->screenspace)
        return ALB_OK;
    double dmax = 0;
    for (unsigned i = 0; i < s->nobj; i++)
        for (unsigned k = 0; k < s->obj[i].nv; k++) {
            double z = s->obj[i].v[k].p.z;
            if (!(z > 0))
                return alb_diag_at(d, ALB_ERR_GEOMETRY, s->file, s->obj[i].line, 0,
                               "screen-space object '%s': vertex %u has depth %g; depths must be "
                               "positive", s->obj[i].name, k + 1, z);
            dmax = fmax(dmax, z);
        }
    /* (xs, ys, q) with q = depth / dmax in (0, 1] is the image of the point
     * (xs / q, ys / q, 1 / q): its projection is (xs, ys) and its 1/Z is q, and
     * the map takes planes to planes, so each face stays planar and convex
     * with 1/Z linear on the screen, as the textbook's depth is. */
    for (unsigned i = 0; i < s->nobj; i++) {
        alb_scene_object *o = &s->obj[i];
        for (unsigned k = 0; k < o->nv; k++) {
            vec3 *p = &o->v[k].p;
            double xs = -1 + 2 * p->x / width, ys = -1 + 2 * p->y / height, q = p->z / dmax;
            *p = v3(xs / q, ys / q, 1 / q);
        }
        for (unsigned j = 0; j < o->nf; j++) {
            alb_scene_face *f = &o->f[j];
            double area = 0;
            for (unsigned k = 0; k < f->count; k++) {
                vec3 a = alb_scene_face_vertex(o, f, k), b = alb_scene_face_vertex(o, f, (k + 1) % f->count);
                area += a.x / a.z * (b.y / b.z) - b.x / b.z * (a.y / a.z);
            }
            if (area < 0)   /* clockwise on the screen: turn it round */
                for (unsigned a = 0, b = f->count - 1; a < b; a++, b--) {
                    unsigned t = o->idx[f->first + a];
                    o->idx[f->first + a] = o->idx[f->first + b];
                    o->idx[f->first + b] = t;
                }
        }
    }
    if (!s->near_line)
        s->near = 1;
    for (unsigned f = 0; f < s->nframes; f++) {
        s->frames[f].obs.pose = (alb_scene_pose){{0, 0, 0}, 0, 0, 0};
        s->frames[f].obs.fov_y = 90;
        s->frames[f].obs.aspect = 1;
    }
    for (unsigned i = 0; i < s->nobj; i++) {   /* one pose, at the origin, in every frame */
        s->obj[i].npose = 1;
        s->obj[i].pose[0] = (alb_scene_pose){{0, 0, 0}, 0, 0, 0};
    }
    s->screenspace = false;
    return ALB_OK;
}
