/* test_textbook.c — the worked 32x32 examples of the hidden-surface chapter of
 * Rogers, "Procedural Elements for Computer Graphics" (Russian translation,
 * /work/shared/seeds/000_23b6c5543dfa20bd.txt; "seed line N" below), rendered
 * by the GP and VP with profile t32 in screen space.
 *
 * The seed states the polygons, the conventions and a few results in prose,
 * but its 32x32 frame-buffer arrays did not survive (they were pictures).  So:
 *  - what the seed does print is transcribed in tests/data/textbook/ex4_22_*
 *    and ex4_23_* and checked as far as it can be (see those files);
 *  - the full frames tests/data/textbook/ex4_17_*, ex4_19_* are computed from
 *    the book's own conventions by exact.py there (exact rationals), and the
 *    test recomputes them independently here in integers (exact_frame).
 * Book conventions (seed lines 32, 62, 70, 148): pixel (x, y) counts from the
 * bottom-left, is decided at its centre (x + 1/2, y + 1/2), is covered when the
 * centre is inside a polygon or ON ITS BOUNDARY, larger z is nearer, and a
 * later polygon replaces an earlier one only if strictly nearer.
 *
 * The VP agrees everywhere except at a few pixels whose centre lies exactly
 * on a triangle edge (listed per example with the reason): the book counts
 * such a centre as covered, the VP applies its tie rule (docs/vp.md §2) to an
 * edge it holds exactly, or sees the edge moved by the rounding of its 3.10
 * intercepts (docs/number-formats.md §1) when the edge is not exactly
 * representable.  Exact depth ties go to the earlier polygon in both. */
#include "t.h"
#include "gp_helpers.h"

#include <math.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define W 32   /* the textbook's screen, profile t32 */

typedef struct {
    int x, y, z;
} ipt;

typedef struct {
    const ipt *v;
    unsigned n;
} poly;

/* Example 4.19 / 4.22 / 4.23 (seed line 58; line 174; line 331). */
static const ipt rect_v[] = {{10, 5, 10}, {10, 25, 10}, {25, 25, 10}, {25, 5, 10}};
static const ipt tri_v[] = {{15, 15, 15}, {25, 25, 5}, {30, 10, 5}};
static const poly zb_scene[] = {{rect_v, 4}, {tri_v, 3}};
static const poly zb_reversed[] = {{tri_v, 3}, {rect_v, 4}};
static const poly rect_scene[] = {{rect_v, 4}};

/* Example 4.17 (seed lines 661-663).  Polygon 2's last vertex is printed as
 * (27, 12, 20); line 665 puts polygon 2 in the plane z = 10 (with 20 it would
 * not even be planar), so it is (27, 12, 10) here. */
static const ipt wa1_v[] = {{10, 3, 20}, {20, 28, 20}, {22, 28, 20}, {22, 3, 20}};
static const ipt wa2_v[] = {{5, 12, 10}, {5, 20, 10}, {27, 20, 10}, {27, 12, 10}};
static const ipt wa3_v[] = {{15, 15, 25}, {25, 25, 5}, {30, 10, 5}};
static const poly wa_scene[] = {{wa1_v, 4}, {wa2_v, 4}, {wa3_v, 3}};

/* ---- the exact computation (integers; coordinates doubled so that pixel
 * centres (x + 1/2, y + 1/2) are the odd points (2x + 1, 2y + 1)) ---- */

typedef struct {
    long long a, b, c, d;   /* Newell's plane a x + b y + c z + d = 0 */
} plane;

static plane newell(const poly *p)
{
    plane q = {0, 0, 0, 0};
    for (unsigned i = 0; i < p->n; i++) {
        ipt u = p->v[i], w = p->v[(i + 1) % p->n];
        q.a += (long long)(u.y - w.y) * (u.z + w.z);
        q.b += (long long)(u.z - w.z) * (u.x + w.x);
        q.c += (long long)(u.x - w.x) * (u.y + w.y);
    }
    q.d = -(q.a * p->v[0].x + q.b * p->v[0].y + q.c * p->v[0].z);
    return q;
}

/* 2 inside, 1 on the boundary, 0 outside, at the doubled point (X, Y). */
static int where(const poly *p, long long X, long long Y)
{
    bool pos = false, neg = false, zero = false;
    for (unsigned i = 0; i < p->n; i++) {
        long long x1 = 2 * p->v[i].x, y1 = 2 * p->v[i].y;
        long long x2 = 2 * p->v[(i + 1) % p->n].x, y2 = 2 * p->v[(i + 1) % p->n].y;
        long long s = (x2 - x1) * (Y - y1) - (y2 - y1) * (X - x1);
        pos |= s > 0, neg |= s < 0, zero |= s == 0;
    }
    return pos && neg ? 0 : zero ? 1 : 2;
}

/* z = num / den (den > 0) of polygon p's plane at the doubled point. */
static void depth_at(const poly *p, long long X, long long Y, long long *num, long long *den)
{
    plane q = newell(p);
    *num = -(q.a * X + q.b * Y + 2 * q.d);
    *den = 2 * q.c;
    if (*den < 0)
        *num = -*num, *den = -*den;
}

typedef struct {
    int value;        /* the book's: 0 background, k for the k-th polygon */
    bool on_edge;     /* a covering polygon has the centre on its boundary */
    bool tie;         /* the two nearest covering polygons are equally near */
    unsigned admit;   /* bit v: value v if some on-boundary polygons are not
                         counted as covering (the other reading of a tie) */
    long long znum, zden;   /* depth of the winner (if value > 0) */
} exact_px;

/* The z-buffer of seed lines 29-34, skipping the polygons in `drop`. */
static int zbuffer_at(const poly *s, unsigned n, long long X, long long Y, unsigned drop,
                      long long *zn, long long *zd)
{
    int best = 0;
    long long bn = 0, bd = 1;
    for (unsigned i = 0; i < n; i++) {
        if (drop >> i & 1 || !where(&s[i], X, Y))
            continue;
        long long num, den;
        depth_at(&s[i], X, Y, &num, &den);
        if (!best || num * bd > bn * den)
            best = (int)i + 1, bn = num, bd = den;
    }
    *zn = bn, *zd = bd;
    return best;
}

static exact_px exact_pixel(const poly *s, unsigned n, int x, int y)
{
    long long X = 2 * x + 1, Y = 2 * y + 1;
    exact_px e;
    memset(&e, 0, sizeof e);
    e.value = zbuffer_at(s, n, X, Y, 0, &e.znum, &e.zden);
    unsigned edge = 0;
    long long top_n = 0, top_d = 1, next_n = 0, next_d = 1;
    int ncover = 0;
    for (unsigned i = 0; i < n; i++) {
        int k = where(&s[i], X, Y);
        if (!k)
            continue;
        if (k == 1)
            edge |= 1u << i;
        long long num, den;
        depth_at(&s[i], X, Y, &num, &den);
        if (!ncover++ || num * top_d > top_n * den) {
            next_n = top_n, next_d = top_d;
            top_n = num, top_d = den;
        } else if (ncover == 2 || num * next_d > next_n * den) {
            next_n = num, next_d = den;
        }
    }
    e.on_edge = edge != 0;
    e.tie = ncover > 1 && top_n * next_d == next_n * top_d;
    for (unsigned drop = 0; drop < 1u << n; drop++)
        if ((drop & ~edge) == 0) {
            long long zn, zd;
            e.admit |= 1u << zbuffer_at(s, n, X, Y, drop, &zn, &zd);
        }
    return e;
}

/* grid[row][x] with row 0 the top (y = 31), as the data files and frames. */
static void exact_frame(const poly *s, unsigned n, exact_px g[W][W])
{
    for (int row = 0; row < W; row++)
        for (int x = 0; x < W; x++)
            g[row][x] = exact_pixel(s, n, x, W - 1 - row);
}

/* ---- scenes, rendering, data files ---- */

static void append(char *buf, size_t len, size_t *k, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));
static void append(char *buf, size_t len, size_t *k, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    if (*k < len)
        *k += (size_t)vsnprintf(buf + *k, len - *k, fmt, ap);
    va_end(ap);
}

/* The scene text: `screenspace`, one object per polygon in the given order
 * (face id i is the book's polygon i + 1). */
static void scene_text(const poly *s, unsigned n, char *buf, size_t len)
{
    size_t k = 0;
    append(buf, len, &k, "albatros-scene 1\nscreenspace\n");
    for (unsigned i = 0; i < n; i++) {
        append(buf, len, &k, "object p%u\n", i + 1);
        for (unsigned j = 0; j < s[i].n; j++)
            append(buf, len, &k, " v %d %d %d\n", s[i].v[j].x, s[i].v[j].y, s[i].v[j].z);
        append(buf, len, &k, " f");
        for (unsigned j = 0; j < s[i].n; j++)
            append(buf, len, &k, " %u", j + 1);
        append(buf, len, &k, "\nend\n");
    }
}

typedef struct {
    int value[W][W];        /* face id + 1; 0 where no face */
    uint32_t depth[W][W];   /* depth store: near/Z in 0.24 */
} vp_grid;

/* Render the polygons with profile t32 and `sets`; 0 on success. */
static int render(const poly *s, unsigned n, const char *sets, vp_grid *g)
{
    char text[2048], err[600];
    alb_frame f;
    memset(&f, 0, sizeof f);
    scene_text(s, n, text, sizeof text);
    if (render_text(text, "t32", sets, &f, NULL, NULL, err, sizeof err)) {
        CHECK_MSG(0, "render (%s): %s", sets ? sets : "defaults", err);
        return -1;
    }
    CHECK_EQ(f.width, W);
    CHECK_EQ(f.height, W);
    CHECK_EQ(f.depth_bits, 24);
    for (int row = 0; row < W; row++)
        for (int x = 0; x < W; x++) {
            uint32_t id = f.face[row * W + x];
            g->value[row][x] = id == ALB_FRAME_NO_FACE ? 0 : (int)id + 1;
            g->depth[row][x] = f.depth[row * W + x];
        }
    alb_frame_free(&f);
    return 0;
}

/* The book's depth of a depth store value: screenspace makes near/Z = z/zmax. */
static double book_z(uint32_t d, int zmax) { return ldexp((double)d, -24) * zmax; }

static int scene_zmax(const poly *s, unsigned n)
{
    int m = 0;
    for (unsigned i = 0; i < n; i++)
        for (unsigned j = 0; j < s[i].n; j++)
            m = s[i].v[j].z > m ? s[i].v[j].z : m;
    return m;
}

/* The non-comment lines of a data file, at most max of them; -1 if unreadable. */
static int read_lines(const char *name, char lines[][256], int max)
{
    char path[256];
    snprintf(path, sizeof path, "tests/data/textbook/%s", name);
    FILE *fp = fopen(path, "r");
    if (!fp) {
        CHECK_MSG(0, "cannot open %s (run from the repository root)", path);
        return -1;
    }
    int n = 0;
    char buf[256];
    while (fgets(buf, sizeof buf, fp)) {
        buf[strcspn(buf, "\r\n")] = 0;
        if (buf[0] == '#' || buf[0] == 0)
            continue;
        if (n < max)
            memcpy(lines[n], buf, sizeof buf);
        n++;
    }
    fclose(fp);
    return n;
}

/* A 32x32 frame file: 32 lines of 32 digits. */
static int read_grid(const char *name, int g[W][W])
{
    char lines[W + 1][256];
    int n = read_lines(name, lines, W + 1);
    if (n < 0)
        return -1;
    CHECK_MSG(n == W, "%s: %d rows, expected %d", name, n, W);
    for (int row = 0; row < W && row < n; row++) {
        CHECK_MSG(strlen(lines[row]) == W, "%s: row %d is not %d digits", name, row, W);
        for (int x = 0; x < W; x++)
            g[row][x] = lines[row][x] - '0';
    }
    return n == W ? 0 : -1;
}

/* Integers of one line (whitespace-separated); their count. */
static int parse_ints(const char *line, int *v, int max)
{
    int n = 0;
    const char *p = line;
    char *end;
    for (long k = strtol(p, &end, 10); end != p; k = strtol(p, &end, 10)) {
        if (n < max)
            v[n] = (int)k;
        n++;
        p = end;
    }
    return n;
}

/* The distinct values of a sequence in order of appearance, runs collapsed. */
static int runs(const int *v, int n, int *out)
{
    int m = 0;
    for (int i = 0; i < n; i++)
        if (!m || out[m - 1] != v[i])
            out[m++] = v[i];
    return m;
}

static bool same_runs(const int *a, int na, const int *b, int nb)
{
    int ra[64], rb[64];
    int ma = runs(a, na, ra), mb = runs(b, nb, rb);
    return ma == mb && memcmp(ra, rb, (size_t)ma * sizeof *ra) == 0;
}

/* ---- comparison against the exact frame with the listed exceptions ---- */

typedef struct {
    int x, y;      /* book coordinates: y up from the bottom */
    int vp;        /* what the VP shows there */
    const char *why;
} exception;

typedef struct {
    int x, y;
} xy;

static bool listed(const exception *ex, unsigned nex, int x, int y, const exception **hit)
{
    for (unsigned i = 0; i < nex; i++)
        if (ex[i].x == x && ex[i].y == y) {
            *hit = &ex[i];
            return true;
        }
    return false;
}

/* Checks, for one example:
 *  - the data file equals the exact computation (two independent programs);
 *  - every bound mode gives the same frame as the default (bound=albatros);
 *  - the VP equals the book on every pixel but the listed ones;
 *  - each listed pixel has its centre on a polygon's boundary in the exact
 *    computation, the VP differs there from the book, shows the listed
 *    value, and that value is the other reading of the boundary (the value
 *    with the on-boundary polygon not counted as covering);
 *  - the exact computation's depth ties are exactly the listed ties, and the
 *    VP gives them to the earlier polygon like the book;
 *  - the VP's depth is the plane's depth within the depth store's precision. */
static void check_example(const char *file, const poly *s, unsigned n, const exception *ex,
                          unsigned nex, const xy *ties, unsigned nties, vp_grid *out)
{
    static exact_px e[W][W];
    int book[W][W];
    exact_frame(s, n, e);
    if (read_grid(file, book) == 0) {
        int diff = 0;
        for (int row = 0; row < W; row++)
            for (int x = 0; x < W; x++)
                if (book[row][x] != e[row][x].value && diff++ < 5)
                    CHECK_MSG(0, "%s: (%d,%d) file %d, exact %d", file, x, W - 1 - row,
                              book[row][x], e[row][x].value);
        CHECK_EQ(diff, 0);
    }

    vp_grid *g = out, *alt = malloc(sizeof *alt);
    if (!alt || render(s, n, NULL, g)) {
        free(alt);
        return;
    }
    static const char *const bounds[] = {"bound=none", "bound=box", "bound=bisector",
                                         "bound=albatros"};
    for (unsigned b = 0; b < sizeof bounds / sizeof bounds[0]; b++)
        if (!render(s, n, bounds[b], alt))
            CHECK_MSG(memcmp(alt->value, g->value, sizeof g->value) == 0 &&
                          memcmp(alt->depth, g->depth, sizeof g->depth) == 0,
                      "%s: %s changes the frame", file, bounds[b]);
    free(alt);

    int zmax = scene_zmax(s, n);
    unsigned seen = 0, nt = 0;
    double worst = 0;
    for (int row = 0; row < W; row++)
        for (int x = 0; x < W; x++) {
            int y = W - 1 - row, v = g->value[row][x];
            const exact_px *p = &e[row][x];
            const exception *hit;
            if (listed(ex, nex, x, y, &hit)) {
                seen++;
                CHECK_MSG(p->on_edge, "%s: listed (%d,%d) is not on a boundary", file, x, y);
                CHECK_MSG(v == hit->vp, "%s: (%d,%d) VP %d, listed %d (%s)", file, x, y, v,
                          hit->vp, hit->why);
                CHECK_MSG(v != p->value, "%s: listed (%d,%d) agrees with the book now (%d)",
                          file, x, y, v);
                CHECK_MSG(p->admit >> v & 1,
                          "%s: (%d,%d) VP %d is no reading of the boundary (book %d)", file, x,
                          y, v, p->value);
            } else {
                CHECK_MSG(v == p->value, "%s: (%d,%d) VP %d, book %d%s%s", file, x, y, v,
                          p->value, p->on_edge ? " (centre on an edge)" : "",
                          p->tie ? " (depth tie)" : "");
            }
            if (p->tie) {
                bool in = false;
                for (unsigned i = 0; i < nties; i++)
                    in |= ties[i].x == x && ties[i].y == y;
                CHECK_MSG(in, "%s: unlisted exact depth tie at (%d,%d)", file, x, y);
                nt++;
            }
            if (v && v == p->value) {
                double err = fabs(book_z(g->depth[row][x], zmax) -
                                  (double)p->znum / (double)p->zden);
                worst = err > worst ? err : worst;
            }
        }
    CHECK_EQ(seen, nex);
    CHECK_EQ(nt, nties);
    for (unsigned i = 0; i < nties; i++) {
        const exact_px *p = &e[W - 1 - ties[i].y][ties[i].x];
        CHECK_MSG(p->tie, "%s: listed tie (%d,%d) is no tie", file, ties[i].x, ties[i].y);
    }
    /* d = floor((z / zmax) 2^24) from 24-bit forms: a few units of 2^-24 */
    CHECK_MSG(worst < zmax * ldexp(1, -20), "%s: depth off by %g", file, worst);
}

/* ---- Example 4.19 (z-buffer) and its repetitions 4.22, 4.23 ---- */

/* Pixels whose centre lies exactly on a triangle edge, where the book (centre
 * on the boundary covers, seed line 70) and the VP differ. */
static const exception zb_exceptions[] = {
    /* edge P5P6, y = x: exact in 3.10; the triangle lies below it, so R = 1 and
     * the VP's tie rule (docs/vp.md §2) leaves samples on it outside; the
     * triangle is nearer than the rectangle there, so the book shows 2 */
    {15, 15, 1, "on P5P6 (y = x): VP tie rule R = 1 excludes; book includes, z 14.5 > 10"},
    {16, 16, 1, "on P5P6 (y = x): VP tie rule R = 1 excludes; book includes, z 13.5 > 10"},
    {17, 17, 1, "on P5P6 (y = x): VP tie rule R = 1 excludes; book includes, z 12.5 > 10"},
    {18, 18, 1, "on P5P6 (y = x): VP tie rule R = 1 excludes; book includes, z 11.5 > 10"},
    {19, 19, 1, "on P5P6 (y = x): VP tie rule R = 1 excludes; book includes, z 10.5 > 10"},
    /* edge P6P7, 3x + y = 100: its intercepts 13/12 and 5/12 (screen units)
     * round to 3.10 as 1.0830 and 0.4170, turning the edge about y = 0
     * (pixel y = 16): below it the edge moves left (by 0.0005 and 0.0015 px
     * at these two rows) and the centres (28.5, 14.5), (29.5, 11.5) fall
     * outside; above it the edge moves right and the on-edge centres of
     * (25,23), (26,20), (27,17) stay in, as in the book */
    {28, 14, 0, "on P6P7 (3x + y = 100, book x_R = 28.5 at line 70): rounded edge passes left"},
    {29, 11, 0, "on P6P7 (3x + y = 100, book x_R = 29.5 at line 70): rounded edge passes left"},
};

/* Exact depth ties: the centres on the intersection line 3x + y = 80 (seed
 * line 78) inside the triangle; z = 10 for both, the rectangle (drawn first)
 * keeps them — the book's strict ">" and the VP's "equal keeps the earlier". */
static const xy zb_ties[] = {{20, 18}, {21, 15}, {22, 12}};

TEST(textbook_zbuffer_rectangle_alone)
{
    /* Example 4.19's frame buffer after the rectangle (seed line 60); no pixel
     * centre lies on an edge of the rectangle: no exceptions. */
    static vp_grid g;
    check_example("ex4_19_rectangle.txt", rect_scene, 1, NULL, 0, NULL, 0, &g);

    /* Example 4.22 prints scan line 15 after the rectangle (seed lines 199,
     * 201): compare what survives of those lines, their runs */
    char lines[4][256];
    int fb[64], zb[64];
    if (read_lines("ex4_22_scanline_row15.txt", lines, 4) != 4) {
        CHECK_MSG(0, "ex4_22_scanline_row15.txt: expected 4 printed lines");
        return;
    }
    int nfb = parse_ints(lines[0], fb, 64), nzb = parse_ints(lines[1], zb, 64);
    CHECK_EQ(nfb, 25);   /* as printed: the line lost 7 of its 32 values */
    CHECK_EQ(nzb, 25);
    int row15[W], z15[W];
    for (int x = 0; x < W; x++) {
        row15[x] = g.value[W - 1 - 15][x];
        z15[x] = (int)lround(book_z(g.depth[W - 1 - 15][x], 10));
    }
    CHECK_MSG(same_runs(fb, nfb, row15, W), "row 15 after the rectangle: runs differ from line 199");
    CHECK_MSG(same_runs(zb, nzb, z15, W), "z-buffer row 15 after the rectangle: runs differ from line 201");
    /* the pixels themselves: centres 10.5 .. 24.5 lie in [10, 25] */
    for (int x = 0; x < W; x++)
        CHECK_EQ(row15[x], x >= 10 && x <= 24);
}

TEST(textbook_zbuffer_example)
{
    static vp_grid g;
    check_example("ex4_19_zbuffer.txt", zb_scene, 2, zb_exceptions,
                  sizeof zb_exceptions / sizeof zb_exceptions[0], zb_ties,
                  sizeof zb_ties / sizeof zb_ties[0], &g);

    /* the triangle's plane by Newell's method: 3x + y + 4z - 120 = 0 (line 64) */
    plane q = newell(&zb_scene[1]);
    long long k = q.b;   /* the common factor */
    CHECK(k != 0 && q.a == 3 * k && q.c == 4 * k && q.d == -120 * k);

    /* line 70: the crossings of edge P6P7 with scan lines 24 .. 10 at y + 1/2,
     * to one decimal; where a crossing is a pixel centre, that pixel is on the
     * boundary — exactly the P6P7 pixels the exact computation flags */
    static const int tenths[15] = {252, 255, 258, 262, 265, 268, 272, 275,
                                   278, 282, 285, 288, 292, 295, 298};
    for (int i = 0; i < 15; i++) {
        int y = 24 - i;
        double xr = (100 - (y + 0.5)) / 3;   /* 3x + y = 100 */
        CHECK_MSG(fabs(xr - tenths[i] / 10.0) < 0.05 + 1e-9, "row %d: x_R %.4f vs book %.1f", y,
                  xr, tenths[i] / 10.0);
        long long X2 = 2 * (100LL - y) - 1;          /* 2 x_R = (200 - 2y - 1) / 3 */
        bool centre = X2 % 3 == 0 && (X2 / 3) % 2 == 1;   /* x_R = x + 1/2 */
        CHECK_EQ(centre, tenths[i] % 10 == 5);
        if (centre) {
            int x = (int)(X2 / 3 - 1) / 2;
            CHECK_EQ(where(&zb_scene[1], 2 * x + 1, 2 * y + 1), 1);
        }
    }

    /* lines 72-74: pixel (20, 15) shows the triangle, z = 43/4 = 10.75 at its
     * centre, 11 in the 4-bit z-buffer */
    CHECK_EQ(g.value[W - 1 - 15][20], 2);
    double z = book_z(g.depth[W - 1 - 15][20], 15);
    CHECK_NEAR(z, 10.75, 1e-5);
    CHECK_EQ(lround(z), 11);

    /* Example 4.23, scan line 15 in prose (lines 337-394): all 32 pixels; the
     * VP differs only at the listed (15, 15) */
    char lines[4][256];
    if (read_lines("ex4_23_interval_row15.txt", lines, 1) == 1 && strlen(lines[0]) == W) {
        for (int x = 0; x < W; x++) {
            int want = lines[0][x] - '0', v = g.value[W - 1 - 15][x];
            CHECK_EQ(exact_pixel(zb_scene, 2, x, 15).value, want);
            if (x == 15)
                CHECK_MSG(v == 1 && want == 2, "(15,15): VP %d, book %d", v, want);
            else
                CHECK_MSG(v == want, "row 15 pixel %d: VP %d, book (line 337-394) %d", x, v,
                          want);
        }
    } else {
        CHECK_MSG(0, "ex4_23_interval_row15.txt: expected one line of %d digits", W);
    }

    /* Example 4.22, scan line 15 after the triangle (line 208): the damaged
     * print keeps the runs 0 1 2 1 2 0 */
    if (read_lines("ex4_22_scanline_row15.txt", lines, 4) == 4) {
        int fb[64], row15[W];
        int nfb = parse_ints(lines[2], fb, 64);
        CHECK_EQ(nfb, 31);   /* as printed */
        for (int x = 0; x < W; x++)
            row15[x] = g.value[W - 1 - 15][x];
        CHECK_MSG(same_runs(fb, nfb, row15, W), "row 15: runs differ from line 208");
    } else {
        CHECK_MSG(0, "ex4_22_scanline_row15.txt: expected 4 printed lines");
    }
}

TEST(textbook_zbuffer_ties_keep_the_earlier_face)
{
    /* The same polygons with the triangle first: the VP's depths at the three
     * tie pixels are exactly equal, so they now go to the triangle; nothing
     * else changes. */
    static vp_grid g, r;
    if (render(zb_scene, 2, NULL, &g) || render(zb_reversed, 2, NULL, &r))
        return;
    for (int row = 0; row < W; row++)
        for (int x = 0; x < W; x++) {
            int y = W - 1 - row, v = r.value[row][x];
            int swapped = v == 1 ? 2 : v == 2 ? 1 : 0;   /* back to the book's numbers */
            bool tie = false;
            for (unsigned i = 0; i < sizeof zb_ties / sizeof zb_ties[0]; i++)
                tie |= zb_ties[i].x == x && zb_ties[i].y == y;
            if (tie)
                CHECK_MSG(g.value[row][x] == 1 && swapped == 2, "tie (%d,%d): %d then %d", x, y,
                          g.value[row][x], swapped);
            else
                CHECK_MSG(swapped == g.value[row][x], "(%d,%d): order changes %d to %d", x, y,
                          g.value[row][x], swapped);
        }
}

/* ---- Example 4.17 (Warnock) ---- */

static const exception wa_exceptions[] = {
    /* the triangle's edge (15,15)-(25,25), y = x, as in Example 4.19 */
    {15, 15, 1, "on y = x: VP tie rule R = 1 excludes; book includes, z 24 > 20"},
    {16, 16, 1, "on y = x: VP tie rule R = 1 excludes; book includes, z 22 > 20"},
    {22, 22, 0, "on y = x: VP tie rule R = 1 excludes; book includes (only polygon there)"},
    {23, 23, 0, "on y = x: VP tie rule R = 1 excludes; book includes (only polygon there)"},
    {24, 24, 0, "on y = x: VP tie rule R = 1 excludes; book includes (only polygon there)"},
    /* the edge (25,25)-(30,10), 3x + y = 100: the same rounded intercepts */
    {28, 14, 0, "on 3x + y = 100: the rounded edge passes left of the centre"},
    {29, 11, 0, "on 3x + y = 100: the rounded edge passes left of the centre"},
};

/* Exact depth ties: the triangle (3x + y + 2z = 110) meets polygon 1 (z = 20)
 * on 3x + y = 70 and polygon 2 (z = 10) on 3x + y = 90; the earlier keeps them. */
static const xy wa_ties[] = {{17, 17}, {18, 14}, {23, 19}, {24, 16}, {25, 13}};

TEST(textbook_warnock_example)
{
    static vp_grid g;
    check_example("ex4_17_warnock.txt", wa_scene, 3, wa_exceptions,
                  sizeof wa_exceptions / sizeof wa_exceptions[0], wa_ties,
                  sizeof wa_ties / sizeof wa_ties[0], &g);
    /* the planes: polygon 1 at z = 20, polygon 2 at z = 10 (line 665) */
    plane p1 = newell(&wa_scene[0]), p2 = newell(&wa_scene[1]), p3 = newell(&wa_scene[2]);
    CHECK(p1.a == 0 && p1.b == 0 && p1.d == -20 * p1.c);
    CHECK(p2.a == 0 && p2.b == 0 && p2.d == -10 * p2.c);
    CHECK(p3.a == 3 * p3.b && p3.c == 2 * p3.b && p3.d == -110 * p3.b);
}
