/* test_gp.c — the GP against computations made here independently: culling
 * by the screen's corners (Fig. 1), intercepts by substitution, system (11)
 * by its own equations, and whole-pipeline output against ray casting. */
#include "t.h"
#include "../common/vec3.h"
#include "gp_helpers.h"
#include "../gp/gp_internal.h"
#include "../common/fix.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---- eq. (18) and Fig. 1 ---- */

TEST(culling_fig1_against_screen_corners)
{
    uint64_t s = 11;
    unsigned seen[3] = {0, 0, 0};
    for (int i = 0; i < 200000; i++) {
        gp_line l = {t_uniform(&s, -1, 1), t_uniform(&s, -1, 1), t_uniform(&s, -3, 3)};
        int pos = 0, neg = 0;
        for (int cx = -1; cx <= 1; cx += 2)
            for (int cy = -1; cy <= 1; cy += 2) {
                double f = l.a * cx + l.b * cy + l.c;
                pos += f > 0;
                neg += f < 0;
            }
        gp_line_class want = pos == 4 ? LINE_DROP_EDGE : neg == 4 ? LINE_DROP_FACE : LINE_CROSSES;
        gp_line_class got = gp_classify_line(l);
        seen[want]++;
        if (got != want) {
            CHECK_MSG(got == want, "line %g %g %g: class %d, corners say %d", l.a, l.b, l.c, got, want);
            return;
        }
    }
    CHECK(seen[0] > 1000 && seen[1] > 1000 && seen[2] > 1000);
    /* a line through a corner touches the screen: kept */
    CHECK_EQ(gp_classify_line((gp_line){1, 1, 2}), LINE_CROSSES);
    CHECK_EQ(gp_classify_line((gp_line){1, 1, 2.000001}), LINE_DROP_EDGE);
    CHECK_EQ(gp_classify_line((gp_line){1, 1, -2.000001}), LINE_DROP_FACE);
}

/* ---- the edge format (19) ---- */

static double intercept_value(uint32_t q, unsigned frac) { return ldexp(q, -(int)frac) - 3; }

TEST(edge_format_intercepts_lie_on_the_line)
{
    uint64_t s = 5;
    const unsigned frac = 14;
    double half_lsb = ldexp(0.5, -(int)frac);
    int checked = 0;
    for (int i = 0; i < 100000; i++) {
        gp_line l = {t_uniform(&s, -1, 1), t_uniform(&s, -1, 1), t_uniform(&s, -2, 2)};
        if (gp_classify_line(l) != LINE_CROSSES)
            continue;
        alb_ws_edge e = gp_edge_format(l, frac);
        CHECK_EQ(e.u, fabs(l.a) > fabs(l.b));
        double x1 = intercept_value(e.x1, frac), x2 = intercept_value(e.x2, frac);
        /* (X1, -1) and (X2, 1) on the line for a vertical edge; (-1, Y1) and
         * (1, Y2) for a horizontal one: substitute and compare. */
        double r1, r2;
        if (e.u) {
            CHECK_EQ(e.r, l.a < 0);
            r1 = (l.b * 1 - l.c) / l.a; /* x at y = -1 from A x - B + C = 0 */
            r2 = (-l.b - l.c) / l.a;    /* x at y = +1 from A x + B + C = 0 */
        } else {
            CHECK_EQ(e.r, l.b < 0);
            r1 = (l.a - l.c) / l.b;     /* y at x = -1 */
            r2 = (-l.a - l.c) / l.b;    /* y at x = +1 */
        }
        CHECK(fabs(r1) <= 3 && fabs(r2) <= 3);
        if (fabs(x1 - r1) > half_lsb || fabs(x2 - r2) > half_lsb) {
            CHECK_MSG(0, "line %g %g %g: intercepts %g %g, exact %g %g", l.a, l.b, l.c, x1, x2, r1, r2);
            return;
        }
        checked++;
    }
    CHECK(checked > 10000);
}

/* The VP's reading of an edge: is screen point (x, y) inside? (R = 0: the
 * face is on the side of larger x (vertical) or larger y (horizontal).) */
static bool edge_inside(const alb_ws_edge *e, unsigned frac, double x, double y)
{
    double a = intercept_value(e->x1, frac), b = intercept_value(e->x2, frac);
    if (e->u) {
        double xe = a + (b - a) * (y + 1) / 2;
        return e->r ? x <= xe : x >= xe;
    }
    double ye = a + (b - a) * (x + 1) / 2;
    return e->r ? y <= ye : y >= ye;
}

TEST(edge_format_keeps_the_inside)
{
    uint64_t s = 9;
    int checked = 0;
    for (int i = 0; i < 20000; i++) {
        gp_line l = {t_uniform(&s, -1, 1), t_uniform(&s, -1, 1), t_uniform(&s, -1.5, 1.5)};
        if (gp_classify_line(l) != LINE_CROSSES)
            continue;
        alb_ws_edge e = gp_edge_format(l, 16);
        double norm = hypot(l.a, l.b);
        for (int k = 0; k < 20; k++) {
            double x = t_uniform(&s, -1, 1), y = t_uniform(&s, -1, 1);
            double f = (l.a * x + l.b * y + l.c) / norm;
            if (fabs(f) < 1e-3)
                continue;   /* within quantisation of the line */
            CHECK_EQ(edge_inside(&e, 16, x, y), f > 0);
            checked++;
        }
    }
    CHECK(checked > 100000);
}

TEST(intercept_rounding_half_up_and_saturation)
{
    /* 3.F after the +3 shift: -3 -> 0, 0 -> 3 * 2^F, ties round up */
    CHECK_EQ(gp_quantise_intercept(-3, 10), 0);
    CHECK_EQ(gp_quantise_intercept(0, 10), 3 << 10);
    CHECK_EQ(gp_quantise_intercept(ldexp(1, -11), 10), (3 << 10) + 1);       /* half LSB up */
    CHECK_EQ(gp_quantise_intercept(-ldexp(1, -11), 10), 3 << 10);            /* -half LSB up */
    CHECK_EQ(gp_quantise_intercept(-5, 10), 0);                              /* saturates */
    CHECK_EQ(gp_quantise_intercept(9, 10), (8 << 10) - 1);
    CHECK_EQ(gp_quantise_intercept(NAN, 10), 0);
}

/* ---- block floating point ---- */

TEST(form_quantisation_bounds)
{
    uint64_t s = 3;
    for (int i = 0; i < 100000; i++) {
        double v[3];
        for (int k = 0; k < 3; k++)
            v[k] = ldexp(t_uniform(&s, -1, 1), (int)(t_rand(&s) % 80) - 40);
        int sat = 0;
        alb_ws_form f = gp_quantise_form(v[0], v[1], v[2], 24, &sat);
        CHECK(!sat);
        double m = fmax(fabs(v[0]), fmax(fabs(v[1]), fabs(v[2])));
        int32_t big = 0;
        for (int k = 0; k < 3; k++) {
            /* each mantissa within half an LSB of the value; none overflows */
            double err = fabs(ldexp(f.m[k], f.exp) - v[k]);
            if (err > ldexp(0.5, f.exp) * (1 + 1e-12)) {
                CHECK_MSG(0, "value %g: mantissa %d exp %d", v[k], f.m[k], f.exp);
                return;
            }
            if (abs(f.m[k]) > big)
                big = abs(f.m[k]);
        }
        CHECK(big <= (1 << 23) - 1);
        /* and the exponent is the smallest: the largest mantissa uses the top bit */
        CHECK(m == 0 || big >= (1 << 22));
    }
}

/* ---- system (11) ---- */

TEST(intensity_solution_reproduces_vertices_and_lies_in_plane)
{
    uint64_t s = 17;
    for (int i = 0; i < 5000; i++) {
        vec3 r[3];
        double val[3], out[4];
        for (int k = 0; k < 3; k++) {
            r[k] = v3(t_uniform(&s, -10, 10), t_uniform(&s, -10, 10), t_uniform(&s, -10, 10));
            val[k] = t_uniform(&s, 0, 1);
        }
        vec3 n = v3_cross(v3_sub(r[1], r[0]), v3_sub(r[2], r[1]));
        if (v3_len(n) < 1)
            continue;
        CHECK(gp_solve_linear(r, val, n, out) == 0);
        for (int k = 0; k < 3; k++)
            CHECK_NEAR(out[0] * r[k].x + out[1] * r[k].y + out[2] * r[k].z + out[3], val[k], 1e-9);
        /* eq. (10): the gradient is in the face plane */
        CHECK_NEAR(out[0] * n.x + out[1] * n.y + out[2] * n.z, 0, 1e-9 * v3_len(n));
    }
    /* collinear vertices: the determinant k.N vanishes */
    vec3 r[3] = {{0, 0, 0}, {1, 1, 1}, {2, 2, 2}};
    double val[3] = {0, 1, 2}, out[4];
    CHECK(gp_solve_linear(r, val, v3(1, -1, 0), out) != 0);
}

/* ---- bounding edges against the screen (§7), edge-on faces ---- */

/* A sliver pointing along +x before a turn by quarter * 90 degrees: its tip at
 * (tip, 0) and a blunt back, five points of a circle of radius 0.06 about
 * (back, 0), counter-clockwise from the tip.  The observer looks along +Z with
 * a 90-degree square view, so a vertex at Z = 1 is at screen (X, Y).  Every
 * turn of the back is under 90 degrees and only the tip's (above 170) makes
 * the sectors of its edges differ by 3 or 4: the tip alone gets a bounding
 * edge, vertical (x = tip) when the sliver lies along x, horizontal along y. */
#define SLIVER_N 6
static void sliver(double tip, double back, int quarter, double pt[SLIVER_N][2])
{
    static const double deg[SLIVER_N - 1] = {95, 140, 185, 230, 265};
    double c = cos(quarter * VEC3_PI / 2), s = sin(quarter * VEC3_PI / 2);
    double u[SLIVER_N][2] = {{tip, 0}};
    for (int k = 1; k < SLIVER_N; k++) {
        double a = deg[k - 1] * VEC3_PI / 180;
        u[k][0] = back + 0.06 * cos(a);
        u[k][1] = 0.06 * sin(a);
    }
    for (int k = 0; k < SLIVER_N; k++) {
        /* quarter turns: exact, so the tip stays exactly on an axis */
        double x = u[k][0], y = u[k][1];
        pt[k][0] = quarter % 2 ? -s * y : c * x;
        pt[k][1] = quarter % 2 ? s * x : c * y;
    }
}

static void polygon_scene(double (*pt)[2], unsigned n, char *buf, size_t len)
{
    size_t k = (size_t)snprintf(buf, len, "albatros-scene 1\nobserver fov 90 aspect 1\nobject s\n");
    for (unsigned i = 0; i < n && k < len; i++)
        k += (size_t)snprintf(buf + k, len - k, " v %.17g %.17g 1\n", pt[i][0], pt[i][1]);
    if (k < len)
        k += (size_t)snprintf(buf + k, len - k, " f");
    for (unsigned i = 0; i < n && k < len; i++)
        k += (size_t)snprintf(buf + k, len - k, " %u", i + 1);
    if (k < len)
        snprintf(buf + k, len - k, "\nend\n");
}

/* Eq. (18) decided by the screen's corners instead of |A| + |B| < |C|: the
 * face is on the left of the edge p -> q (counter-clockwise). */
static gp_line_class edge_by_corners(const double p[2], const double q[2])
{
    int in = 0, out = 0;
    for (int cx = -1; cx <= 1; cx += 2)
        for (int cy = -1; cy <= 1; cy += 2) {
            double f = (q[0] - p[0]) * (cy - p[1]) - (q[1] - p[1]) * (cx - p[0]);
            in += f > 0;
            out += f < 0;
        }
    return in == 4 ? LINE_DROP_EDGE : out == 4 ? LINE_DROP_FACE : LINE_CROSSES;
}

/* Where the VP puts edge e at the other coordinate of point p: its distance
 * from p along the edge's U axis. */
static double edge_miss(const alb_ws_edge *e, unsigned frac, const double p[2])
{
    double a = intercept_value(e->x1, frac), b = intercept_value(e->x2, frac);
    if (e->u)
        return fabs(a + (b - a) * (p[1] + 1) / 2 - p[0]);
    return fabs(a + (b - a) * (p[0] + 1) / 2 - p[1]);
}

TEST(bounding_edge_screen_test_by_border)
{
    static const struct {
        double tip, back;
        int quarter;
        bool face_dropped;     /* otherwise the tip's bounding edge is dropped */
        const char *why;
    } cases[] = {
        /* tip beyond a border, the sliver across the screen: the bounding
         * edge has the screen on its inside, so it goes */
        {2, -0.3, 0, false, "x = 2, R = 1 (face at smaller x): v >= 1 drops the edge"},
        {2, -0.3, 1, false, "y = 2, R = 1: v >= 1 drops the edge"},
        {2, -0.3, 2, false, "x = -2, R = 0: v <= -1 drops the edge"},
        {2, -0.3, 3, false, "y = -2, R = 0: v <= -1 drops the edge"},
        /* the sliver wholly beyond a border, its tip toward the screen: every
         * edge line of its own meets the screen or has it inside, and only
         * the bounding edge at the tip has the screen outside */
        {-1.2, -3.5, 0, true, "x = -1.2, R = 1: v <= -1 drops the face"},
        {-1.2, -3.5, 1, true, "y = -1.2, R = 1: v <= -1 drops the face"},
        {-1.2, -3.5, 2, true, "x = 1.2, R = 0: v >= 1 drops the face"},
        {-1.2, -3.5, 3, true, "y = 1.2, R = 0: v >= 1 drops the face"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        double pt[SLIVER_N][2];
        char text[1024];
        sliver(cases[i].tip, cases[i].back, cases[i].quarter, pt);
        polygon_scene(pt, SLIVER_N, text, sizeof text);
        unsigned cross = 0, inside = 0, outside = 0, kept[SLIVER_N];
        for (unsigned k = 0; k < SLIVER_N; k++) {
            gp_line_class c = edge_by_corners(pt[k], pt[(k + 1) % SLIVER_N]);
            if (c == LINE_CROSSES)
                kept[cross++] = k;
            inside += c == LINE_DROP_EDGE;
            outside += c == LINE_DROP_FACE;
        }
        CHECK_MSG(outside == 0 && cross >= 2, "case %zu: the sliver is not as designed", i);
        gp_run_result r;
        if (gp_run_text(text, "bound=albatros", &r)) {
            CHECK_MSG(0, "case %zu: %s", i, r.err);
            continue;
        }
        CHECK_EQ(r.st.faces_in, 1);
        CHECK_EQ(r.st.edges_offscreen, inside);
        CHECK_EQ(r.st.bound_added, 0);
        if (cases[i].face_dropped) {
            CHECK_MSG(r.st.faces_offscreen == 1 && r.st.faces_out == 0 && r.st.bound_culled == 0,
                      "case %zu (%s): offscreen %u out %u culled %u", i, cases[i].why,
                      r.st.faces_offscreen, r.st.faces_out, r.st.bound_culled);
            CHECK_EQ(r.nfaces, 0);
        } else {
            CHECK_MSG(r.st.faces_offscreen == 0 && r.st.faces_out == 1 && r.st.bound_culled == 1,
                      "case %zu (%s): offscreen %u out %u culled %u", i, cases[i].why,
                      r.st.faces_offscreen, r.st.faces_out, r.st.bound_culled);
            CHECK_EQ(r.st.edges_out, cross);
            if (r.nfaces == 1 && r.faces[0].n_edges == cross)
                /* the face's own edges in vertex order, each through both
                 * of its vertices, and nothing else */
                for (unsigned j = 0; j < cross; j++) {
                    const alb_ws_edge *e = &r.faces[0].edge[j];
                    unsigned k = kept[j];
                    double miss = fmax(edge_miss(e, r.cfg.edge_frac_bits, pt[k]),
                                       edge_miss(e, r.cfg.edge_frac_bits, pt[(k + 1) % SLIVER_N]));
                    CHECK_MSG(miss < 1e-3, "case %zu: edge %u misses vertex by %g", i, j, miss);
                }
            else
                CHECK_MSG(0, "case %zu: %u faces, expected 1 with %u edges", i, r.nfaces, cross);
        }
        gp_run_free(&r);
    }
}

TEST(bounding_edge_on_the_screen_is_sent)
{
    /* tip at (0.5, 0): the vertical x = 0.5 with the face at smaller x */
    double pt[SLIVER_N][2];
    char text[1024];
    sliver(0.5, -0.3, 0, pt);
    polygon_scene(pt, SLIVER_N, text, sizeof text);
    gp_run_result r;
    if (gp_run_text(text, "bound=albatros", &r)) {
        CHECK_MSG(0, "%s", r.err);
        return;
    }
    CHECK(r.st.bound_added == 1 && r.st.bound_culled == 0 && r.st.edges_out == SLIVER_N + 1);
    if (r.nfaces == 1 && r.faces[0].n_edges == SLIVER_N + 1) {
        const alb_ws_edge *b = &r.faces[0].edge[SLIVER_N];
        unsigned frac = r.cfg.edge_frac_bits;
        CHECK(b->u == 1 && b->r == 1 && b->x1 == b->x2);
        CHECK_NEAR(intercept_value(b->x1, frac), 0.5, ldexp(0.5, -(int)frac));
    } else {
        CHECK_MSG(0, "%u faces", r.nfaces);
    }
    gp_run_free(&r);
}

TEST(edge_on_face_is_dropped)
{
    /* the plane y = 0 holds the observer: the face, either way round,
     * projects onto the line y = 0 of the screen; the triangle in z = 3,
     * counter-clockwise on the screen, is drawn */
    static const char text[] =
        "albatros-scene 1\nobserver fov 90 aspect 1\nobject s\n"
        " v -1 0 2\n v 1 0 2\n v 0 0 4\n f 1 2 3\n f 3 2 1\n"
        " v -1 -1 3\n v 1 -1 3\n v 0 1 3\n f 4 5 6\nend\n";
    gp_run_result r;
    if (gp_run_text(text, NULL, &r)) {
        CHECK_MSG(0, "%s", r.err);
        return;
    }
    CHECK_EQ(r.st.faces_in, 3);
    CHECK_EQ(r.st.faces_edge_on, 2);    /* both sides of the plane through the eye */
    CHECK_EQ(r.st.faces_backfacing, 0);
    CHECK_EQ(r.st.faces_out, 1);
    CHECK(r.nfaces == 1 && r.faces[0].id == 2);
    gp_run_free(&r);
}

/* ---- scene values the stream holds as they are (docs/word-format.md) ---- */

typedef struct {
    alb_err e;
    unsigned line, col;
    char msg[600];
    alb_ws_config cfg;
    alb_ws_frame frame;
} stream_check;

/* Parse (the scene format takes any positive near), then create and run the
 * GP; on success decode the CONFIG and first FRAME back. */
static void gp_on_text(const char *body, stream_check *out)
{
    char text[1024];
    snprintf(text, sizeof text, "albatros-scene 1\n%sobject t\n v 0 0 5\n v 1 0 5\n v 0 1 5\n"
                                " f 1 2 3\nend\n", body);
    memset(out, 0, sizeof *out);
    alb_scene s;
    alb_diag d;
    alb_diag_init(&d, NULL);
    alb_profile p;
    alb_profile_lookup("a256", &p);
    if ((out->e = alb_scene_parse(text, strlen(text), "x.scene", &s, &d))) {
        snprintf(out->msg, sizeof out->msg, "parse: %s", d.msg);
        return;
    }
    alb_gp *gp = NULL;
    alb_ws_buf b;
    alb_ws_buf_init(&b);
    out->e = alb_gp_create(&gp, &s, &p, &d);
    if (!out->e)
        out->e = alb_gp_run(gp, &b, NULL, &d);
    out->line = d.line, out->col = d.col;
    snprintf(out->msg, sizeof out->msg, "%s", d.msg);
    alb_ws_reader rd;
    alb_ws_reader_init(&rd, b.w, b.n, "x.stream");
    alb_ws_event ev;
    while (!out->e && !rd.ended && !(out->e = alb_ws_next(&rd, &ev, &d))) {
        if (ev.kind == ALB_WS_EV_CONFIG)
            out->cfg = ev.u.config;
        if (ev.kind == ALB_WS_EV_FRAME)
            out->frame = ev.u.frame;
    }
    if (out->e && !out->line)
        snprintf(out->msg, sizeof out->msg, "decoding: %s", d.msg);
    alb_gp_destroy(gp);
    alb_ws_buf_free(&b);
    alb_scene_free(&s);
}

TEST(gp_refuses_values_the_stream_cannot_hold)
{
    static const struct {
        const char *body;
        unsigned line, col;
        const char *msg;     /* NULL: accepted */
    } cases[] = {
        /* near: binary32's normal range, FLT_MIN .. FLT_MAX */
        {"near 1e40\n", 2, 6, "near 1e+40 is outside 1.1754943508222875e-38 .. "
                              "3.4028234663852886e+38: the word stream stores near as IEEE-754 "
                              "binary32"},
        /* the decimal just below FLT_MIN: the message has the digits to show it */
        {"near 1.17549435e-38\n", 2, 6, "near 1.17549435e-38 is outside 1.1754943508222875e-38"},
        {"near 1e-50\n", 2, 6, "near 1e-50 is outside"},
        {"near 3.5e38\n", 2, 6, "near 3.5e+38 is outside"},
        {"near 1.1e-38\n", 2, 6, "near 1.1e-38 is outside"},
        {"near 3.4e38\n", 0, 0, NULL},
        {"near 1.2e-38\n", 0, 0, NULL},
        /* fog: Z/near in 24.8 below 2^32 (Z/near <= 2^24 - 1/512), far's
         * word beyond near's; checked whichever of near and fog comes first */
        {"fog 1 2 3 0 2e6\n", 2, 13, "fog far 2e+06 is 2e+07 times near (0.1): the word stream's "
                                     "24.8 fog distance holds at most 1.67772e+07"},
        {"fog 1 2 3 0 4294967296\nnear 256\n", 2, 13, "fog far 4.29497e+09 is 1.67772e+07 times"},
        {"near 256\nfog 1 2 3 0 4294967295\n", 0, 0, NULL},
        /* 1 and 1.0001 at near 0.1: 2560 and round(2560.256) = 2560 */
        {"fog 1 2 3 1 1.0001\n", 2, 13, "fog near 1 and far 1.0001 are one value in the word "
                                         "stream's 24.8 fog distance (steps of near/256"},
        {"fog 1 2 3 1 1.0003\n", 0, 0, NULL},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        stream_check c;
        gp_on_text(cases[i].body, &c);
        if (!cases[i].msg) {
            CHECK_MSG(c.e == ALB_OK, "case %zu: %s", i, c.msg);
            continue;
        }
        CHECK_MSG(c.e != ALB_OK, "case %zu: accepted", i);
        CHECK_MSG(c.line == cases[i].line && c.col == cases[i].col, "case %zu: at %u:%u (%s)", i,
                  c.line, c.col, c.msg);
        CHECK_STR_CONTAINS(c.msg, cases[i].msg);
    }
    /* what was accepted is stored as the decoder reads it back */
    stream_check c;
    gp_on_text("near 3.4e38\n", &c);
    CHECK(c.e == ALB_OK && c.cfg.near == 3.4e38f);
    gp_on_text("near 256\nfog 1 2 3 0 4294967295\n", &c);
    CHECK(c.e == ALB_OK && c.frame.fog && c.frame.fog_near == 0 && c.frame.fog_far == 0xFFFFFFFFu);
    gp_on_text("fog 1 2 3 1 1.0003\n", &c);   /* 2560 and round(2560.768) */
    CHECK(c.e == ALB_OK && c.frame.fog_near == 2560 && c.frame.fog_far == 2561);
}

/* The paper's rule gives a convex polygon at most two bounding edges; a
 * face the parser's convexity tolerance accepts — here a triangle whose
 * vertical side has a vertex pushed in by 1e-11 of the screen, a turn of sine
 * -5e-11 — steps back a sector at the dent, and the table then generates at
 * the three corners (sectors 1 -> 4 -> 7 -> 6 -> 1: differences 3, 3, 7, 3).
 * The GP keeps the first two (docs/gp.md, "Bounding edges"). */
TEST(bounding_edges_at_most_two_per_face)
{
    static const char text[] =
        "albatros-scene 1\nobserver fov 90\nobject t\n v 2.5 3 5\n v -3 1 5\n v 2.5 -1.001 5\n"
        " v 2.49999999995 1 5\n f 1 2 3 4\nend\n";
    gp_run_result r;
    if (gp_run_text(text, "bound=albatros", &r)) {
        CHECK_MSG(0, "%s", r.err);
        return;
    }
    CHECK(r.nfaces == 1 && r.st.bound_added == 2 && r.st.bound_excess == 1);
    if (r.nfaces == 1) {
        /* own edges first, then the bounding edges of the first two corners
         * in vertex order: A = (0.5, 0.6) and B = (-0.6, 0.2), both under
         * sector differences of 3 */
        CHECK_EQ(r.faces[0].n_edges, 4 + 2);
        const alb_ws_edge *ba = &r.faces[0].edge[4], *bb = &r.faces[0].edge[5];
        unsigned frac = r.cfg.edge_frac_bits;
        CHECK(ba->x1 == ba->x2 && bb->x1 == bb->x2);
        CHECK_NEAR(intercept_value(ba->x1, frac), ba->u ? 0.5 : 0.6, ldexp(1, -(int)frac));
        CHECK_NEAR(intercept_value(bb->x1, frac), bb->u ? -0.6 : 0.2, ldexp(1, -(int)frac));
    }
    gp_run_free(&r);
    /* and never more than two on dented polygons, the dented side along
     * each of the eight sector borders (multiples of 45 degrees) or not */
    uint64_t seed = 5;
    unsigned faces = 0, excess = 0;
    for (int i = 0; i < 400; i++) {
        char buf[2048];
        double rot = (i % 8) * VEC3_PI / 4 + (i % 16 < 8 ? 0 : t_uniform(&seed, -0.3, 0.3));
        double dent = t_uniform(&seed, 1e-12, 1e-10), at = t_uniform(&seed, 0.2, 0.8);
        int n = snprintf(buf, sizeof buf, "albatros-scene 1\nobserver fov 90\nobject t\n");
        /* a triangle (0.5,0.6) (-0.6,0.2) (0.5,-0.2) turned by rot, with a
         * point of its third side pushed in by `dent` */
        const double tri[4][2] = {{0.5, 0.6}, {-0.6, 0.2}, {0.5, -0.2}, {0.5, -0.2 + 0.8 * at}};
        for (int k = 0; k < 4; k++) {
            double x = tri[k][0] - (k == 3 ? dent : 0), y = tri[k][1];
            double xr = x * cr_cos(rot) - y * cr_sin(rot), yr = x * cr_sin(rot) + y * cr_cos(rot);
            n += snprintf(buf + n, sizeof buf - (size_t)n, " v %.17g %.17g 5\n", 5 * xr, 5 * yr);
        }
        snprintf(buf + n, sizeof buf - (size_t)n, " f 1 2 3 4\nend\n");
        if (gp_run_text(buf, "bound=albatros", &r)) {
            CHECK_MSG(0, "%s", r.err);
            return;
        }
        CHECK_MSG(r.st.bound_added + r.st.bound_culled <= 2 * r.st.faces_out,
                  "rotation %g: %u bounding edges on %u faces", rot,
                  r.st.bound_added + r.st.bound_culled, r.st.faces_out);
        faces += r.st.faces_out;
        excess += r.st.bound_excess;
        gp_run_free(&r);
    }
    CHECK_MSG(faces == 400 && excess > 0, "%u faces, %u excess", faces, excess);
}
