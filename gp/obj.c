/* obj.c — Wavefront OBJ import: the polygons become one scene object of valid
 * convex planar faces (split or rejected where needed), MTL Kd colours become
 * face colours, and an eye/at/up camera becomes the single frame's observer. */
#include "albatros/scene.h"
#include "../common/vec3.h"
#include "albatros/file.h"
#include "gp_internal.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

#define GREY 200                /* colour of faces without a (known) material */
#define OBJ_MAX_POLY 1024       /* ear clipping is cubic in the worst case */
/* The tolerances of alb_scene_check_face (scene.c), so that "planar" and
 * "collinear" here mean exactly what the checker means. */
#define TOL_AREA  1e-12
#define TOL_PLANE 1e-6
#define TOL_TURN  1e-9
/* An ear this thin (relative to its longest edge squared) is treated as zero
 * area: the margin over TOL_AREA keeps every ear we emit clear of the check. */
#define TOL_EAR   1e-10
#define TOL_UP    1e-6          /* sin(angle) below which --up is along the view */
/* Unknown keywords and undefined materials named in a warning each; the
 * rest are counted in one warning at the end (a generated file may hold
 * thousands, docs/scene-format.md). */
#define OBJ_WARN_NAMED 10

/* ---- small helpers ---- */

/* Room for `need` elements in p; returns the (moved) block, NULL if no memory
 * (p is then still valid and still owned by the caller). */
static void *grow(void *p, unsigned *cap, unsigned need, size_t elem)
{
    if (need <= *cap)
        return p;
    unsigned n = *cap ? *cap : 8;
    while (n < need) {
        if (n > (1u << 30))
            return NULL;
        n *= 2;
    }
    void *q = realloc(p, (size_t)n * elem);
    if (q)
        *cap = n;
    return q;
}

/* The OBJ file may be anything that can be read (a pipe, say); a material
 * library it names must be a regular file: a FIFO would block, /dev/zero
 * never end.  Both are text, so a NUL stops the reading (the parser
 * reports it). */
static alb_err read_file(const char *path, bool regular_only, char **out, size_t *len,
                         alb_diag *d)
{
    const char *why;
    FILE *f = alb_file_open_input(path, regular_only, &why);
    if (!f)
        return alb_diag_at(d, ALB_ERR_IO, path, 0, 0, "cannot open: %s", why);
    int rc = alb_file_read_text(f, out, len);
    int err = errno;
    fclose(f);
    if (rc == -2)
        return alb_diag_at(d, ALB_ERR_NOMEM, path, 0, 0, "file too large for memory");
    if (rc)
        return alb_diag_at(d, ALB_ERR_IO, path, 0, 0, "read error: %s", strerror(err));
    return ALB_OK;
}

/* ---- line reader and tokens (shared by OBJ and MTL) ---- */

typedef struct {
    const char *s;
    unsigned len, col;       /* col: 1-based */
} otok;

typedef struct {
    const char *file;
    alb_diag *d;
    const char *text;
    size_t len, next;        /* next: offset of the next line */
    unsigned line;
    const char *ln;          /* the current line, its length, scan position */
    size_t lnlen, pos;
    unsigned end_col;        /* column just after the last token read */
} reader;

static reader reader_make(const char *text, size_t len, const char *file, alb_diag *d)
{
    reader r;
    memset(&r, 0, sizeof r);
    r.text = text;
    r.len = len;
    r.file = file;
    r.d = d;
    return r;
}

static alb_err __attribute__((format(printf, 3, 4)))
rerr(reader *r, unsigned col, const char *fmt, ...)
{
    char msg[400];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    return alb_diag_at(r->d, ALB_ERR_PARSE, r->file, r->line, col, "%s", msg);
}

/* Advance to the next line; *got = false at the end.  Both formats are
 * ASCII: a NUL or a high byte means a binary or mis-encoded file. */
static alb_err next_line(reader *r, bool *got)
{
    *got = r->next < r->len;
    if (!*got)
        return ALB_OK;
    size_t end = r->next;
    while (end < r->len && r->text[end] != '\n')
        end++;
    r->line++;
    r->ln = r->text + r->next;
    r->lnlen = end - r->next;
    r->pos = 0;
    r->end_col = 1;
    r->next = end + 1;
    for (size_t i = 0; i < r->lnlen; i++) {
        unsigned char c = (unsigned char)r->ln[i];
        /* a CR not before the LF: classic Mac line ends, which would read
         * as one long line ("expected a number, found 'v'") */
        if (c == '\r' && i + 1 < r->lnlen)
            return rerr(r, (unsigned)i + 1, "line ends with a bare carriage return (CR): use LF "
                        "or CRLF line ends");
        if (c == 0 || c >= 0x80)
            return rerr(r, (unsigned)i + 1, "byte 0x%02x: expected ASCII text%s", c,
                        alb_scene_byte_hint(r->text, r->len, (size_t)(r->ln - r->text) + i));
    }
    return ALB_OK;
}

static bool is_space(char c)
{
    return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v';
}

/* The next whitespace-separated word; false at the end of the line or at a
 * '#' comment. */
static bool next_tok(reader *r, otok *t)
{
    while (r->pos < r->lnlen && is_space(r->ln[r->pos]))
        r->pos++;
    if (r->pos >= r->lnlen || r->ln[r->pos] == '#')
        return false;
    size_t start = r->pos;
    while (r->pos < r->lnlen && !is_space(r->ln[r->pos]) && r->ln[r->pos] != '#')
        r->pos++;
    *t = (otok){r->ln + start, (unsigned)(r->pos - start), (unsigned)start + 1};
    r->end_col = t->col + t->len;
    return true;
}

/* The rest of the line as one word: material and file names may hold spaces. */
static bool rest_tok(reader *r, otok *t)
{
    otok first, last;
    if (!next_tok(r, &first))
        return false;
    last = first;
    while (next_tok(r, &last))
        ;
    *t = (otok){first.s, last.col + last.len - first.col, first.col};
    return true;
}

static bool tok_is(const otok *t, const char *w)
{
    return strlen(w) == t->len && memcmp(t->s, w, t->len) == 0;
}

static int clip_len(unsigned len) { return len > 40 ? 40 : (int)len; }

/* t == NULL: the line ended where something was expected. */
static alb_err expected(reader *r, const otok *t, const char *what)
{
    if (!t)
        return rerr(r, r->end_col, "expected %s at end of line", what);
    return rerr(r, t->col, "expected %s, found '%.*s'", what, clip_len(t->len), t->s);
}

static alb_err expect_end(reader *r)
{
    otok t;
    return next_tok(r, &t) ? expected(r, &t, "end of line") : ALB_OK;
}

static alb_err parse_num(reader *r, const otok *t, double *out)
{
    char buf[128];
    if (t->len >= sizeof buf)
        return expected(r, t, "a number (at most 127 characters)");
    memcpy(buf, t->s, t->len);
    buf[t->len] = 0;
    char *end;
    errno = 0;
    double v = strtod(buf, &end);
    bool whole = end != buf && *end == 0;
    if (whole && (isnan(v) || (isinf(v) && errno != ERANGE)))
        return rerr(r, t->col, "number '%s' is NaN or infinite; expected a finite number", buf);
    /* plain decimal only: strtod would also take hexadecimal */
    if (!whole || !alb_scene_decimal_syntax(buf, t->len))
        return expected(r, t, "a number");
    if (isinf(v))
        return rerr(r, t->col, "number '%s' is out of range", buf);
    *out = v;   /* an underflow to 0 or a denormal is a faithful rounding */
    return ALB_OK;
}

static alb_err next_num(reader *r, double *out)
{
    otok t;
    if (!next_tok(r, &t))
        return expected(r, NULL, "a number");
    return parse_num(r, &t, out);
}

/* ---- the importer ---- */

typedef struct {
    char *name;
    uint8_t rgb[3];
} material;

/* Names to their index + 1 (0: empty), open addressing, at most half full:
 * looking up a material or keyword costs the same in a file of a hundred
 * thousand of them (it was a linear search: quadratic in all). */
typedef struct {
    unsigned *slot;
    size_t cap;
} name_index;

static size_t name_hash(const char *s, size_t len)
{
    uint64_t h = 1469598103934665603u;   /* FNV-1a */
    for (size_t i = 0; i < len; i++)
        h = (h ^ (unsigned char)s[i]) * 1099511628211u;
    return (size_t)h;
}

/* The slot of name in the index (holding its index + 1, or 0 if absent);
 * names[i] is the name of index i. */
static unsigned *index_slot(const name_index *x, char *const *names, size_t stride,
                            const char *name, size_t len)
{
    size_t mask = x->cap - 1;
    for (size_t i = name_hash(name, len) & mask;; i = (i + 1) & mask) {
        unsigned k = x->slot[i];
        const char *nm = k ? *(char *const *)(const void *)((const char *)names + (k - 1) * stride) : NULL;
        if (!k || (strlen(nm) == len && !memcmp(nm, name, len)))
            return &x->slot[i];
    }
}

/* Index `count` (already in names) under its name; -1 if out of memory. */
static int index_add(name_index *x, char *const *names, size_t stride, unsigned count)
{
    if (2 * (size_t)count >= x->cap) {
        name_index big = {calloc(x->cap ? 2 * x->cap : 64, sizeof *big.slot), x->cap ? 2 * x->cap : 64};
        if (!big.slot)
            return -1;
        for (unsigned k = 0; k < count; k++) {
            const char *nm = *(char *const *)(const void *)((const char *)names + k * stride);
            *index_slot(&big, names, stride, nm, strlen(nm)) = k + 1;
        }
        free(x->slot);
        *x = big;
    }
    const char *nm = *(char *const *)(const void *)((const char *)names + count * stride);
    *index_slot(x, names, stride, nm, strlen(nm)) = count + 1;
    return 0;
}

static unsigned index_find(const name_index *x, char *const *names, size_t stride,
                           const char *name, size_t len)
{
    return x->cap ? *index_slot(x, names, stride, name, len) : 0;
}

typedef struct {
    alb_scene *s;
    alb_scene_object *o;
    alb_diag *d;
    const char *path;        /* the OBJ file: diagnostics, mtllib directory */
    unsigned line, col;      /* the statement being imported */
    unsigned nvt, nvn;       /* counted only, to check face indices */
    material *mat;           /* a later definition of a name wins */
    unsigned nmat, cap_mat;
    name_index mat_index;    /* name -> its latest definition */
    int cur_mat;             /* -1: none */
    unsigned undefined, undefined_more, undefined_line;   /* usemtl of unknown names */
    char **kw;               /* unknown keywords seen */
    unsigned nkw, cap_kw;
    name_index kw_index;
    unsigned kw_more, kw_more_line;   /* statements of keywords not named */
    bool warned_vcolour, warned_kd;
    unsigned *poly;          /* vertex indices of the face being read */
    unsigned cap_poly;
    unsigned ndegenerate, first_degenerate;
    unsigned fnum;           /* the 'f' statement being imported, from 0: the id of
                                every face made of it (docs/vp.md §7) */
    alb_diag chk;              /* why the last alb_scene_check_face failed */
} importer;

static void importer_free(importer *im)
{
    for (unsigned i = 0; i < im->nmat; i++)
        free(im->mat[i].name);
    for (unsigned i = 0; i < im->nkw; i++)
        free(im->kw[i]);
    free(im->mat);
    free(im->kw);
    free(im->mat_index.slot);
    free(im->kw_index.slot);
    free(im->poly);
}

static char *dup_n(const char *s, size_t len)
{
    char *p = malloc(len + 1);
    if (p) {
        memcpy(p, s, len);
        p[len] = 0;
    }
    return p;
}

static alb_err __attribute__((format(printf, 2, 3))) gerr(importer *im, const char *fmt, ...)
{
    char msg[400];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    return alb_diag_at(im->d, ALB_ERR_GEOMETRY, im->path, im->line, im->col, "%s", msg);
}

/* ---- materials ---- */

static int find_material(const importer *im, const char *name, unsigned len)
{
    if (!im->nmat)
        return -1;
    return (int)index_find(&im->mat_index, &im->mat[0].name, sizeof im->mat[0], name, len) - 1;
}

/* Returns the new index, -1 if out of memory. */
static int add_material(importer *im, const char *name, unsigned len)
{
    material *m = grow(im->mat, &im->cap_mat, im->nmat + 1, sizeof *m);
    if (!m)
        return -1;
    im->mat = m;
    char *nm = dup_n(name, len);
    if (!nm)
        return -1;
    im->mat[im->nmat] = (material){nm, {GREY, GREY, GREY}};
    /* a later definition of the name replaces the earlier in the index */
    if (index_add(&im->mat_index, &im->mat[0].name, sizeof im->mat[0], im->nmat))
        return -1;
    return (int)im->nmat++;
}

static uint8_t kd_byte(double c)
{
    c = c < 0 ? 0 : c > 1 ? 1 : c;
    return (uint8_t)floor(c * 255 + 0.5);
}

/* "Kd r [g b]" (one value means grey, as the MTL spec says). */
static alb_err mtl_kd(importer *im, reader *r, int cur, unsigned col)
{
    otok t;
    if (cur < 0)
        return rerr(r, col, "'Kd' before any 'newmtl'");
    if (!next_tok(r, &t))
        return expected(r, NULL, "a red value 0..1");
    if (tok_is(&t, "spectral") || tok_is(&t, "xyz")) {
        if (!im->warned_kd)
            alb_diag_warn(im->d, r->file, r->line, "'Kd %.*s' is not supported; such materials "
                      "keep the default colour", clip_len(t.len), t.s);
        im->warned_kd = true;
        return ALB_OK;
    }
    double c[3];
    alb_err e = parse_num(r, &t, &c[0]);
    if (e)
        return e;
    c[1] = c[2] = c[0];
    if (next_tok(r, &t) && ((e = parse_num(r, &t, &c[1])) || (e = next_num(r, &c[2]))))
        return e;
    for (unsigned k = 0; k < 3; k++)
        im->mat[cur].rgb[k] = kd_byte(c[k]);
    return expect_end(r);
}

/* Only newmtl and Kd matter; the many other MTL statements are ignored. */
static alb_err mtl_parse(importer *im, const char *text, size_t len, const char *file)
{
    reader r = reader_make(text, len, file, im->d);
    int cur = -1;
    for (;;) {
        bool got;
        otok k;
        alb_err e = next_line(&r, &got);
        if (e || !got)
            return e;
        if (!next_tok(&r, &k))
            continue;
        if (tok_is(&k, "newmtl")) {
            if (!rest_tok(&r, &k))
                return expected(&r, NULL, "a material name");
            if ((cur = add_material(im, k.s, k.len)) < 0)
                return ALB_ERR_NOMEM;
        } else if (tok_is(&k, "Kd") && (e = mtl_kd(im, &r, cur, k.col))) {
            return e;
        }
    }
}

/* `name` relative to the OBJ file's directory unless absolute. */
static char *sibling_path(const char *base, const char *name, size_t len)
{
    const char *slash = strrchr(base, '/');
    size_t dir = slash && name[0] != '/' ? (size_t)(slash - base + 1) : 0;
    char *p = malloc(dir + len + 1);
    if (!p)
        return NULL;
    memcpy(p, base, dir);
    memcpy(p + dir, name, len);
    p[dir + len] = 0;
    return p;
}

/* Load one material library; a missing one is a warning only when `warn`
 * (the caller may try another reading of the name first). */
static alb_err load_mtl(importer *im, const otok *name, bool warn, bool *opened)
{
    char *path = sibling_path(im->path, name->s, name->len), *text = NULL;
    if (!path)
        return ALB_ERR_NOMEM;
    size_t len;
    alb_diag io;
    alb_diag_init(&io, NULL);
    alb_err e = read_file(path, true, &text, &len, &io);
    *opened = e != ALB_ERR_IO;
    if (!e && alb_scene_note_file(im->s, path))
        e = ALB_ERR_NOMEM;
    if (e == ALB_ERR_IO) {
        if (warn)
            alb_diag_warn(im->d, im->path, im->line, "material library '%s': %s; faces using its "
                      "materials get the default colour", path, io.msg);
        e = ALB_OK;
    } else if (!e) {
        e = mtl_parse(im, text, len, path);
    }
    free(text);
    free(path);
    return e;
}

/* "mtllib a.mtl b.mtl": several names, but exporters also write one name
 * with spaces, so the whole rest of the line is tried first. */
static alb_err st_mtllib(importer *im, reader *r)
{
    otok all, t;
    bool opened;
    if (!rest_tok(r, &all))
        return expected(r, NULL, "a material library file name");
    bool several = memchr(all.s, ' ', all.len) || memchr(all.s, '\t', all.len);
    alb_err e = load_mtl(im, &all, !several, &opened);
    if (e || opened || !several)
        return e;
    r->pos = all.col - 1;
    while (next_tok(r, &t))
        if ((e = load_mtl(im, &t, true, &opened)))
            return e;
    return ALB_OK;
}

static alb_err st_usemtl(importer *im, reader *r)
{
    otok t;
    if (!rest_tok(r, &t))
        return expected(r, NULL, "a material name");
    int m = find_material(im, t.s, t.len);
    if (m < 0) {
        /* Remembered as a grey material so that it is reported only once;
         * past the first few, counted for one warning at the end. */
        if (im->undefined++ < OBJ_WARN_NAMED)
            alb_diag_warn(im->d, im->path, r->line, "material '%.*s' is not defined in any "
                      "material library; its faces get the default colour", clip_len(t.len), t.s);
        else if (!im->undefined_more++)
            im->undefined_line = r->line;
        if ((m = add_material(im, t.s, t.len)) < 0)
            return ALB_ERR_NOMEM;
    }
    im->cur_mat = m;
    return ALB_OK;
}

/* ---- vertices ---- */

/* "v x y z [w]"; also the common "v x y z r g b" vertex-colour extension,
 * whose colours are ignored. */
static alb_err st_v(importer *im, reader *r)
{
    alb_scene_vertex v;
    memset(&v, 0, sizeof v);
    double x[3], extra[3];
    unsigned n = 0;
    otok t[3], more;
    alb_err e;
    for (unsigned k = 0; k < 3; k++)
        if ((e = next_num(r, &x[k])))
            return e;
    for (; n < 3 && next_tok(r, &t[n]); n++)
        if ((e = parse_num(r, &t[n], &extra[n])))
            return e;
    if (next_tok(r, &more) || n == 2)
        return rerr(r, t[0].col, "expected 'v x y z', 'v x y z w' or 'v x y z r g b'");
    if (n == 1 && extra[0] == 0)
        return rerr(r, t[0].col, "vertex weight w is 0 (a point at infinity)");
    if (n == 3 && !im->warned_vcolour) {
        alb_diag_warn(im->d, im->path, r->line, "vertex colours are ignored");
        im->warned_vcolour = true;
    }
    v.p = v3(x[0], x[1], -x[2]);   /* see alb_scene_load_obj: OBJ is right-handed */
    return alb_scene_add_vertex(im->o, &v) ? ALB_ERR_NOMEM : ALB_OK;
}

/* vt / vn: between `min` and `max` numbers, checked and counted. */
static alb_err st_counted(reader *r, unsigned min, unsigned max, unsigned *count)
{
    double x;
    otok t;
    alb_err e;
    for (unsigned k = 0; k < min; k++)
        if ((e = next_num(r, &x)))
            return e;
    for (unsigned k = min; k < max && next_tok(r, &t); k++)
        if ((e = parse_num(r, &t, &x)))
            return e;
    if ((e = expect_end(r)))
        return e;
    if (*count == UINT_MAX)
        return rerr(r, 1, "too many elements");
    ++*count;
    return ALB_OK;
}

/* ---- faces: indices ---- */

/* One OBJ index: 1..count, or -1..-count counting back from the latest. */
static alb_err parse_index(reader *r, const char *p, size_t len, unsigned col, unsigned count,
                           const char *what, unsigned *out)
{
    bool neg = len && p[0] == '-';
    unsigned long long v = 0;
    if (len == neg)
        return rerr(r, col, "expected a %s index", what);
    for (size_t i = neg; i < len; i++) {
        if (p[i] < '0' || p[i] > '9')
            return rerr(r, col, "expected a %s index (an integer), found '%.*s'", what,
                        clip_len((unsigned)len), p);
        if (v <= UINT_MAX)      /* larger is out of range anyway */
            v = v * 10 + (unsigned)(p[i] - '0');
    }
    if (v == 0)
        return rerr(r, col, "%s index 0 is invalid: OBJ indices start at 1 (or at -1 for the "
                    "latest)", what);
    if (v > count)   /* quoted as written: v stops growing past UINT_MAX */
        return rerr(r, col, "%s index %.*s is out of range: %u defined so far", what,
                    clip_len((unsigned)len), p, count);
    *out = neg ? count - (unsigned)v : (unsigned)v - 1;
    return ALB_OK;
}

/* "v", "v/vt", "v/vt/vn" or "v//vn"; vt and vn are checked, then dropped. */
static alb_err face_ref(importer *im, reader *r, const otok *t, unsigned *out)
{
    const char *s = t->s, *end = s + t->len;
    unsigned slashes = 0;
    for (const char *q = s; q < end; q++)
        slashes += *q == '/';
    if (slashes > 2)
        return rerr(r, t->col, "expected v, v/vt, v/vt/vn or v//vn, found '%.*s'",
                    clip_len(t->len), t->s);
    const char *sl1 = memchr(s, '/', t->len);
    alb_err e = parse_index(r, s, (size_t)((sl1 ? sl1 : end) - s), t->col, im->o->nv, "vertex",
                            out);
    if (e || !sl1)
        return e;
    const char *q = sl1 + 1, *sl2 = memchr(q, '/', (size_t)(end - q));
    unsigned ignored;
    if ((!sl2 || sl2 > q) &&
        (e = parse_index(r, q, (size_t)((sl2 ? sl2 : end) - q), t->col + (unsigned)(q - s),
                         im->nvt, "texture vertex", &ignored)))
        return e;
    if (!sl2)
        return ALB_OK;
    q = sl2 + 1;
    return parse_index(r, q, (size_t)(end - q), t->col + (unsigned)(q - s), im->nvn, "normal",
                       &ignored);
}

/* ---- faces: geometry ---- */

/* Append a face and check it; one that fails is taken back out again.  Its
 * id is its 'f' statement's number, not its place among the faces made: the
 * triangles of a split polygon share their polygon's, and a skipped face
 * moves no later one, so face.id is the OBJ's face order.  *ok says which. */
static alb_err emit_face(importer *im, const unsigned *vi, unsigned n, bool *ok)
{
    alb_scene *s = im->s;
    alb_scene_object *o = im->o;
    alb_scene_face *f = alb_scene_add_face(s, o, vi, n);
    if (!f)
        return ALB_ERR_NOMEM;
    f->id = im->fnum;
    f->line = im->line;
    f->col = im->col;
    if (im->cur_mat >= 0)
        memcpy(f->rgb, im->mat[im->cur_mat].rgb, 3);
    f->shade = ALB_SHADE_FLAT;
    f->intensity = 1.0;
    f->texture = -1;
    f->texmap = ALB_TEXMAP_NONE;
    *ok = alb_scene_check_face(s, o, f, NULL, &im->chk) == ALB_OK;
    if (!*ok) {
        o->nf--;
        o->nidx -= n;
        s->nfaces--;
    }
    return ALB_OK;
}

typedef struct {
    vec3 p;
    double x, y;             /* in the polygon's best-fit plane */
    unsigned vi;             /* object vertex index */
    unsigned prev, next;     /* ring links while clipping ears */
} pvert;

typedef struct {
    pvert *v;
    unsigned n;
    double L;                /* longest edge */
    vec3 u;                  /* unit Newell normal */
} polygon;

/* Drop vertices at the same place as their predecessor: they add nothing. */
static unsigned drop_repeats(pvert *v, unsigned n)
{
    unsigned m = 0;
    for (unsigned k = 0; k < n; k++)
        if (m == 0 || v3_len(v3_sub(v[k].p, v[m - 1].p)) > 0)
            v[m++] = v[k];
    while (m > 1 && v3_len(v3_sub(v[m - 1].p, v[0].p)) == 0)
        m--;
    return m;
}

static double longest_edge(const pvert *v, unsigned n)
{
    double L = 0;
    for (unsigned k = 0; k < n; k++) {
        double len = v3_len(v3_sub(v[(k + 1) % n].p, v[k].p));
        L = len > L ? len : L;
    }
    return L;
}

/* All vertices on one line (the test alb_scene_check_face makes for triangles). */
static bool collinear(const polygon *pg)
{
    unsigned far = 0;
    for (unsigned k = 1; k < pg->n; k++)
        if (v3_len(v3_sub(pg->v[k].p, pg->v[0].p)) > v3_len(v3_sub(pg->v[far].p, pg->v[0].p)))
            far = k;
    vec3 dir = v3_sub(pg->v[far].p, pg->v[0].p);
    for (unsigned k = 1; k < pg->n; k++)
        if (v3_len(v3_cross(v3_sub(pg->v[k].p, pg->v[0].p), dir)) > TOL_AREA * pg->L * pg->L)
            return false;
    return true;
}

static vec3 centroid(const polygon *pg)
{
    vec3 c = {0, 0, 0};
    for (unsigned k = 0; k < pg->n; k++)
        c = v3_add(c, pg->v[k].p);
    return v3_scale(c, 1.0 / pg->n);
}

/* Newell normal, unnormalised (as alb_scene_face_newell). */
static vec3 newell(const polygon *pg)
{
    vec3 n = {0, 0, 0};
    for (unsigned k = 0; k < pg->n; k++) {
        vec3 a = pg->v[k].p, b = pg->v[(k + 1) % pg->n].p;
        n.x += (a.y - b.y) * (a.z + b.z);
        n.y += (a.z - b.z) * (a.x + b.x);
        n.z += (a.x - b.x) * (a.y + b.y);
    }
    return n;
}

static bool planar(const polygon *pg)
{
    vec3 c = centroid(pg);
    for (unsigned k = 0; k < pg->n; k++)
        if (fabs(v3_dot(pg->u, v3_sub(pg->v[k].p, c))) > TOL_PLANE * pg->L)
            return false;
    return true;
}

/* 2-D coordinates in the plane through the centroid normal to u, with axes
 * e1 x e2 = u so that the polygon keeps its winding (positive area). */
static void project(polygon *pg)
{
    vec3 u = pg->u, a = fabs(u.x) <= fabs(u.y) && fabs(u.x) <= fabs(u.z) ? v3(1, 0, 0)
                      : fabs(u.y) <= fabs(u.z) ? v3(0, 1, 0) : v3(0, 0, 1);
    vec3 e1 = v3_cross(a, u);
    e1 = v3_scale(e1, 1 / v3_len(e1));
    vec3 e2 = v3_cross(u, e1), c = centroid(pg);
    for (unsigned k = 0; k < pg->n; k++) {
        vec3 d = v3_sub(pg->v[k].p, c);
        pg->v[k].x = v3_dot(d, e1);
        pg->v[k].y = v3_dot(d, e2);
    }
}

/* Twice the signed area of abc in the plane: > 0 turning left. */
static double orient(const pvert *a, const pvert *b, const pvert *c)
{
    return (b->x - a->x) * (c->y - a->y) - (b->y - a->y) * (c->x - a->x);
}

/* Convex in the plane: no right turn, one revolution in all (the rule of
 * alb_scene_check_face, gp/polygon.c). */
static bool convex2d(const polygon *pg)
{
    double ex[OBJ_MAX_POLY], ey[OBJ_MAX_POLY];
    unsigned k;
    for (k = 0; k < pg->n; k++) {
        const pvert *a = &pg->v[k], *b = &pg->v[(k + 1) % pg->n];
        ex[k] = b->x - a->x;
        ey[k] = b->y - a->y;
    }
    return gp_polygon_turns(ex, ey, pg->n, TOL_TURN, &k) == GP_TURNS_CONVEX;
}

/* p, known to be on the line ab, lies on the segment ab. */
static bool in_box(const pvert *a, const pvert *b, const pvert *p)
{
    return p->x >= fmin(a->x, b->x) && p->x <= fmax(a->x, b->x) &&
           p->y >= fmin(a->y, b->y) && p->y <= fmax(a->y, b->y);
}

static bool opposite(double s, double t, double eps)
{
    return (s > eps && t < -eps) || (s < -eps && t > eps);
}

/* Segments ab and cd cross or touch. */
static bool segments_meet(const pvert *a, const pvert *b, const pvert *c, const pvert *d,
                          double eps)
{
    double o1 = orient(a, b, c), o2 = orient(a, b, d), o3 = orient(c, d, a), o4 = orient(c, d, b);
    if (opposite(o1, o2, eps) && opposite(o3, o4, eps))
        return true;
    return (fabs(o1) <= eps && in_box(a, b, c)) || (fabs(o2) <= eps && in_box(a, b, d)) ||
           (fabs(o3) <= eps && in_box(c, d, a)) || (fabs(o4) <= eps && in_box(c, d, b));
}

/* Simple in the plane: no two edges meet except neighbours at their shared
 * vertex, and no edge doubles back along its neighbour. */
static bool simple2d(const polygon *pg)
{
    unsigned n = pg->n;
    double eps = TOL_AREA * pg->L * pg->L;
    for (unsigned i = 0; i < n; i++) {
        const pvert *a = &pg->v[i], *b = &pg->v[(i + 1) % n], *c = &pg->v[(i + 2) % n];
        double dot = (b->x - a->x) * (c->x - b->x) + (b->y - a->y) * (c->y - b->y);
        if (fabs(orient(a, b, c)) <= eps && dot < 0)
            return false;
        for (unsigned j = i + 2; j < n; j++) {
            if (i == 0 && j == n - 1)
                continue;
            if (segments_meet(a, b, &pg->v[j], &pg->v[(j + 1) % n], eps))
                return false;
        }
    }
    return true;
}

static double ear_eps(const pvert *a, const pvert *b, const pvert *c)
{
    double l1 = cr_hypot(b->x - a->x, b->y - a->y), l2 = cr_hypot(c->x - b->x, c->y - b->y),
           l3 = cr_hypot(a->x - c->x, a->y - c->y);
    double L = fmax(l1, fmax(l2, l3));
    return TOL_EAR * L * L;
}

/* Vertex b is an ear: a left turn, and no other remaining vertex in or on
 * the triangle (prev, b, next). */
static bool is_ear(const polygon *pg, unsigned b)
{
    const pvert *v = pg->v, *pa = &v[v[b].prev], *pb = &v[b], *pc = &v[v[b].next];
    if (!(orient(pa, pb, pc) > ear_eps(pa, pb, pc)))
        return false;
    double eps = TOL_AREA * pg->L * pg->L;
    for (unsigned k = pc->next; k != v[b].prev; k = v[k].next) {
        const pvert *p = &v[k];
        if (orient(pa, pb, p) >= -eps && orient(pb, pc, p) >= -eps && orient(pc, pa, p) >= -eps)
            return false;
    }
    return true;
}

/* Vertex b is on a straight run (zero-area ear): removing it changes no area. */
static bool is_straight(const polygon *pg, unsigned b)
{
    const pvert *v = pg->v, *pa = &v[v[b].prev], *pb = &v[b], *pc = &v[v[b].next];
    double dot = (pb->x - pa->x) * (pc->x - pb->x) + (pb->y - pa->y) * (pc->y - pb->y);
    return fabs(orient(pa, pb, pc)) <= ear_eps(pa, pb, pc) && dot > 0;
}

/* A vertex of the m remaining ones, from `start`, that is an ear (or, if
 * `straight`, on a straight run); UINT_MAX if none. */
static unsigned find_vertex(const polygon *pg, unsigned start, unsigned m, bool straight)
{
    unsigned b = start;
    for (unsigned k = 0; k < m; k++, b = pg->v[b].next)
        if (straight ? is_straight(pg, b) : is_ear(pg, b))
            return b;
    return UINT_MAX;
}

static alb_err emit_triangle(importer *im, const polygon *pg, unsigned b)
{
    const pvert *v = pg->v;
    unsigned vi[3] = {v[v[b].prev].vi, v[b].vi, v[v[b].next].vi};
    bool ok;
    alb_err e = emit_face(im, vi, 3, &ok);
    if (!e && !ok)
        e = gerr(im, "a triangle split from this face fails the face check (%s)", im->chk.msg);
    return e;
}

/* Ear clipping in the plane; every ear keeps the polygon's winding. */
static alb_err ear_clip(importer *im, polygon *pg)
{
    pvert *v = pg->v;
    unsigned m = pg->n, b = 0;
    for (unsigned k = 0; k < m; k++) {
        v[k].prev = (k + m - 1) % m;
        v[k].next = (k + 1) % m;
    }
    for (; m > 3; m--) {
        unsigned ear = find_vertex(pg, b, m, false);
        unsigned cut = ear != UINT_MAX ? ear : find_vertex(pg, b, m, true);
        if (cut == UINT_MAX)
            return gerr(im, "cannot split this face into triangles (it is too close to "
                        "self-intersecting); triangulate it in your modeller");
        alb_err e = ear == cut ? emit_triangle(im, pg, cut) : ALB_OK;
        if (e)
            return e;
        v[v[cut].prev].next = v[cut].next;
        v[v[cut].next].prev = v[cut].prev;
        b = v[cut].next;
    }
    /* The last three: a zero-area remainder covers nothing and is dropped. */
    const pvert *pa = &v[v[b].prev], *pc = &v[v[b].next];
    return orient(pa, &v[b], pc) > ear_eps(pa, &v[b], pc) ? emit_triangle(im, pg, b) : ALB_OK;
}

static void note_degenerate(importer *im)
{
    if (im->ndegenerate++ == 0)
        im->first_degenerate = im->line;
}

/* The polygon (already cleaned of repeats) is not a valid face as written:
 * skip it if it has no area, split it if that is unambiguous, else reject. */
static alb_err split_polygon(importer *im, polygon *pg, unsigned n_orig)
{
    bool ok;
    alb_err e;
    pg->L = longest_edge(pg->v, pg->n);
    if (!isfinite(pg->L))
        return gerr(im, "face coordinates are too large (an edge length overflows)");
    if (pg->n < 3 || collinear(pg)) {
        note_degenerate(im);
        return ALB_OK;
    }
    if (pg->n < n_orig && pg->n <= ALB_SCENE_MAX_FACE_VERTICES) {
        unsigned vi[ALB_SCENE_MAX_FACE_VERTICES];
        for (unsigned k = 0; k < pg->n; k++)
            vi[k] = pg->v[k].vi;
        if ((e = emit_face(im, vi, pg->n, &ok)) || ok)
            return e;
    }
    if (pg->n == 3) {            /* a triangle fails only by having no area */
        note_degenerate(im);
        return ALB_OK;
    }
    vec3 nn = newell(pg);
    double nl = v3_len(nn);
    if (!(nl > TOL_AREA * pg->L * pg->L))
        return gerr(im, "face is self-intersecting (its signed area is zero but its vertices "
                    "are not on one line); fix it in your modeller");
    pg->u = v3_scale(nn, 1 / nl);
    project(pg);
    if (!planar(pg) && !convex2d(pg))
        return gerr(im, "face is non-convex and non-planar; triangulate it in your modeller");
    if (!simple2d(pg))
        return gerr(im, "face is self-intersecting (its edges cross or touch); fix it in your "
                    "modeller");
    return ear_clip(im, pg);
}

/* The face of im->poly[0..n): as written if alb_scene_check_face takes it,
 * otherwise cleaned up and possibly split into triangles. */
static alb_err add_polygon(importer *im, unsigned n)
{
    bool ok;
    alb_err e;
    if (n <= ALB_SCENE_MAX_FACE_VERTICES && ((e = emit_face(im, im->poly, n, &ok)) || ok))
        return e;
    pvert *v = malloc(n * sizeof *v);
    if (!v)
        return ALB_ERR_NOMEM;
    for (unsigned k = 0; k < n; k++) {
        v[k].p = im->o->v[im->poly[k]].p;
        v[k].vi = im->poly[k];
    }
    polygon pg = {v, drop_repeats(v, n), 0, {0, 0, 0}};
    e = split_polygon(im, &pg, n);
    free(v);
    return e;
}

static alb_err st_f(importer *im, reader *r, unsigned col)
{
    unsigned n = 0;
    otok t;
    alb_err e;
    while (next_tok(r, &t)) {
        if (n == OBJ_MAX_POLY)
            return rerr(r, t.col, "face has more than %d vertices", OBJ_MAX_POLY);
        unsigned *p = grow(im->poly, &im->cap_poly, n + 1, sizeof *p);
        if (!p)
            return ALB_ERR_NOMEM;
        im->poly = p;
        if ((e = face_ref(im, r, &t, &im->poly[n])))
            return e;
        n++;
    }
    if (n < 3)
        return rerr(r, r->end_col, "a face needs at least 3 vertices, found %u", n);
    im->col = col;
    e = add_polygon(im, n);
    im->fnum++;
    return e;
}

/* ---- statements ---- */

/* An unknown keyword: a warning the first time, for the first few; the
 * statements of the others are counted for one warning at the end. */
static alb_err warn_keyword(importer *im, reader *r, const otok *k)
{
    unsigned seen = im->nkw ? index_find(&im->kw_index, im->kw, sizeof *im->kw, k->s, k->len) : 0;
    if (seen) {
        if (seen > OBJ_WARN_NAMED)
            im->kw_more++;
        return ALB_OK;
    }
    char **kw = grow(im->kw, &im->cap_kw, im->nkw + 1, sizeof *kw);
    if (!kw)
        return ALB_ERR_NOMEM;
    im->kw = kw;
    if (!(im->kw[im->nkw] = dup_n(k->s, k->len)) ||
        index_add(&im->kw_index, im->kw, sizeof *im->kw, im->nkw))
        return ALB_ERR_NOMEM;
    if (++im->nkw <= OBJ_WARN_NAMED)
        alb_diag_warn(im->d, im->path, r->line, "'%.*s' statements are not supported and are "
                  "ignored", clip_len(k->len), k->s);
    else if (!im->kw_more++)
        im->kw_more_line = r->line;
    return ALB_OK;
}

/* What was counted rather than named. */
static void warn_counted(importer *im)
{
    if (im->kw_more)
        alb_diag_warn(im->d, im->path, 0, "%u more statements of %u other unsupported keywords "
                  "were ignored, the first on line %u (only the first %d keywords are named)",
                  im->kw_more, im->nkw - OBJ_WARN_NAMED, im->kw_more_line, OBJ_WARN_NAMED);
    if (im->undefined_more)
        alb_diag_warn(im->d, im->path, 0, "%u more materials are not defined in any material "
                  "library, the first on line %u; their faces get the default colour",
                  im->undefined_more, im->undefined_line);
}

static alb_err statement(importer *im, reader *r, const otok *k)
{
    if (tok_is(k, "v"))
        return st_v(im, r);
    if (tok_is(k, "vt"))
        return st_counted(r, 1, 3, &im->nvt);
    if (tok_is(k, "vn"))
        return st_counted(r, 3, 3, &im->nvn);
    if (tok_is(k, "f"))
        return st_f(im, r, k->col);
    if (tok_is(k, "usemtl"))
        return st_usemtl(im, r);
    if (tok_is(k, "mtllib"))
        return st_mtllib(im, r);
    /* The whole file is one scene object, and shading is flat. */
    if (tok_is(k, "o") || tok_is(k, "g") || tok_is(k, "s"))
        return ALB_OK;
    return warn_keyword(im, r, k);
}

static alb_err obj_parse(importer *im, const char *text, size_t len)
{
    reader r = reader_make(text, len, im->path, im->d);
    alb_err e;
    for (;;) {
        bool got;
        otok k;
        if ((e = next_line(&r, &got)) || !got)
            break;
        im->line = r.line;
        im->col = 0;
        if (next_tok(&r, &k) && (e = statement(im, &r, &k)))
            break;
    }
    im->line = r.line;
    return e;
}

/* The object is named after the file: basename without its extension. */
static void object_name(const char *path, char out[ALB_SCENE_NAME_MAX])
{
    const char *base = strrchr(path, '/');
    base = base ? base + 1 : path;
    const char *dot = strrchr(base, '.');
    size_t len = dot && dot > base ? (size_t)(dot - base) : strlen(base);
    if (len == 0)
        snprintf(out, ALB_SCENE_NAME_MAX, "obj");
    else
        snprintf(out, ALB_SCENE_NAME_MAX, "%.*s",
                 (int)(len < ALB_SCENE_NAME_MAX ? len : ALB_SCENE_NAME_MAX - 1), base);
}

static alb_err import(importer *im, const char *text, size_t len)
{
    char name[ALB_SCENE_NAME_MAX];
    object_name(im->path, name);
    if (!(im->o = alb_scene_add_object(im->s, name)))
        return ALB_ERR_NOMEM;
    im->o->line = 1;
    alb_err e = obj_parse(im, text, len);
    if (e)
        return e;
    warn_counted(im);
    if (im->ndegenerate)
        alb_diag_warn(im->d, im->path, 0, "skipped %u degenerate face%s (no area), the first on "
                  "line %u", im->ndegenerate, im->ndegenerate == 1 ? "" : "s",
                  im->first_degenerate);
    if (im->o->nf == 0)
        return alb_diag_at(im->d, ALB_ERR_PARSE, im->path, im->line, 0,
                       "no faces to draw (no 'f' statements, or only degenerate ones)");
    return ALB_OK;
}

/* ---- camera ---- */

static bool finite3(vec3 v)
{
    return isfinite(v.x) && isfinite(v.y) && isfinite(v.z);
}

/* v's length, with v scaled by its largest component first, so that
 * neither 1e308 (whose square overflows) nor a denormal (whose square is
 * 0) is mistaken: inf only if the length itself overflows. */
static double length_of(vec3 v, vec3 *unit)
{
    double m = fmax(fabs(v.x), fmax(fabs(v.y), fabs(v.z)));
    if (!(m > 0) || !isfinite(m))
        return m;
    vec3 s = v3(v.x / m, v.y / m, v.z / m);   /* not * (1 / m): 1 / a denormal overflows */
    double l = v3_len(s);
    *unit = v3_scale(s, 1 / l);
    return m * l;
}

alb_err alb_scene_camera_check(const alb_scene_camera *c, alb_diag *d)
{
    if (!finite3(c->eye) || !finite3(c->at) || !finite3(c->up))
        return alb_diag_at(d, ALB_ERR_CONFIG, "", 0, 0, "--eye, --at and --up must be finite");
    vec3 f = v3_sub(c->at, c->eye), fu = {0, 0, 0}, uu = {0, 0, 0};
    double fl = length_of(f, &fu), ul = length_of(c->up, &uu);
    if (!isfinite(fl))
        return alb_diag_at(d, ALB_ERR_CONFIG, "", 0, 0, "--eye and --at are too far apart: their "
                       "difference overflows a double");
    if (!(fl > 0))
        return alb_diag_at(d, ALB_ERR_CONFIG, "", 0, 0, "--eye and --at must be different points "
                       "(the camera looks from --eye toward --at)");
    if (!(ul > 0))
        return alb_diag_at(d, ALB_ERR_CONFIG, "", 0, 0, "--up must be a non-zero vector");
    if (!(v3_len(v3_cross(fu, uu)) > TOL_UP))
        return alb_diag_at(d, ALB_ERR_CONFIG, "", 0, 0, "--up (%g,%g,%g) is parallel to the view "
                       "direction from --eye to --at; choose an up vector across it",
                       c->up.x, c->up.y, c->up.z);
    if (!(c->fov_y >= ALB_SCENE_MIN_FOV && c->fov_y < 180))
        return alb_diag_at(d, ALB_ERR_CONFIG, "", 0, 0, "--fov %g: the vertical field of view must "
                       "be in [%g, 180) degrees", c->fov_y, ALB_SCENE_MIN_FOV);
    return ALB_OK;
}

static alb_err camera_size_check(const alb_scene_camera *c, alb_diag *d)
{
    if (!c->width || !c->height)
        return alb_diag_at(d, ALB_ERR_CONFIG, "", 0, 0, "--size %ux%u: width and height must be "
                       "positive", c->width, c->height);
    if (!((double)c->width / c->height < 100))   /* the scene format's aspect limit */
        return alb_diag_at(d, ALB_ERR_CONFIG, "", 0, 0, "--size %ux%u: aspect ratio width/height "
                       "must be below 100", c->width, c->height);
    return ALB_OK;
}

/* A look-at observer: the GP builds its orientation from the vectors
 * (m3_look_at), with no round trip through angles, so no transcendental
 * function of the C library touches the camera (docs/number-formats.md §0). */
static void camera_observer(const alb_scene_camera *c, alb_scene_observer *obs)
{
    obs->pose = (alb_scene_pose){c->eye, 0, 0, 0};
    obs->look_at = true;
    obs->at = c->at;
    obs->up = c->up;
    obs->fov_y = c->fov_y;
    obs->aspect = (double)c->width / c->height;
}

/* ---- entry point ---- */

/* OBJ is right-handed (z toward the viewer of its front view) and its faces
 * run counter-clockwise seen from their front; the scene frame is
 * left-handed (z away from the observer) with the same rule for fronts
 * (docs/gp.md).  Negating z maps one onto the other: the model is not
 * mirrored and the file's vertex order keeps its front as the front.  Kept
 * as they are, the coordinates would show the model mirrored and the GP
 * would take every front for a back.  The camera is given in the file's
 * coordinates, as the user's modeller shows them, and converted alike. */
alb_err alb_scene_load_obj(const char *path, const alb_scene_camera *cam_obj, alb_scene *s, alb_diag *d)
{
    alb_scene_init(s, path);
    char *text;
    size_t len;
    /* checked as the user gave it, so that the messages quote what was typed
     * (negating z changes no length and no angle) */
    alb_err e = alb_scene_camera_check(cam_obj, d);
    if (e || (e = camera_size_check(cam_obj, d)) || (e = read_file(path, false, &text, &len, d)))
        return e;
    alb_scene_camera c = *cam_obj, *cam = &c;
    c.eye.z = -c.eye.z;
    c.at.z = -c.at.z;
    c.up.z = -c.up.z;
    importer im;
    memset(&im, 0, sizeof im);
    im.s = s;
    im.d = d;
    im.path = path;
    im.cur_mat = -1;
    alb_diag_init(&im.chk, NULL);
    e = import(&im, text, len);
    free(text);
    importer_free(&im);
    if (!e && !(e = alb_scene_finish(s, d)))
        camera_observer(cam, &s->frames[0].obs);
    if (e == ALB_ERR_NOMEM)
        alb_diag_at(d, e, path, im.line, 0, "out of memory");
    if (e)
        alb_scene_free(s);
    return e;
}
