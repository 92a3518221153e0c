/* test_pipeline.c — whole GP runs on small scenes, the emitted words read
 * back and compared with ray casting and direct evaluation in double. */
#include "t.h"
#include "../common/vec3.h"
#include "gp_helpers.h"
#include "../common/fix.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

static double ival(uint32_t q, unsigned frac) { return ldexp(q, -(int)frac) - 3; }

/* The VP's reading of a face's edges at screen point (x, y), in double. */
static bool face_covers(const alb_ws_face *f, unsigned frac, double x, double y)
{
    for (unsigned i = 0; i < f->n_edges; i++) {
        const alb_ws_edge *e = &f->edge[i];
        double a = ival(e->x1, frac), b = ival(e->x2, frac);
        if (e->u) {
            double xe = a + (b - a) * (y + 1) / 2;
            if (e->r ? x > xe : x < xe)
                return false;
        } else {
            double ye = a + (b - a) * (x + 1) / 2;
            if (e->r ? y > ye : y < ye)
                return false;
        }
    }
    return true;
}

/* fov 90 and aspect 1 make screen coordinates x = X/Z, y = Y/Z exactly. */
#define OBSERVER_AT_ORIGIN "observer fov 90 aspect 1\n"

/* Ground quad y = -1, x in [-5, 5], z in [-10, 10]: half behind the observer. */
static const char ground_crossing_z0[] =
    "albatros-scene 1\n" OBSERVER_AT_ORIGIN
    "object ground\n v -5 -1 -10\n v 5 -1 -10\n v 5 -1 10\n v -5 -1 10\n f 1 2 3 4\nend\n";

static bool ground_hit(double x, double y)
{
    if (y >= 0)
        return false;
    double t = -1 / y;   /* ray (x, y, 1) t meets y = -1 */
    return fabs(x * t) <= 5 && t <= 10;
}

TEST(face_crossing_z0_is_its_visible_part)
{
    gp_run_result r;
    if (gp_run_text(ground_crossing_z0, "bound=none", &r)) {
        CHECK_MSG(0, "%s", r.err);
        return;
    }
    CHECK_EQ(r.nfaces, 1);
    CHECK_EQ(r.st.edges_behind, 1);   /* the edge at z = -10 */
    uint64_t s = 1;
    int agree = 0, total = 0;
    for (int i = 0; i < 20000 && r.nfaces == 1; i++) {
        double x = t_uniform(&s, -1, 1), y = t_uniform(&s, -1, 1);
        bool want = ground_hit(x, y);
        /* skip samples within 1e-3 of the boundary */
        if (want != ground_hit(x + 1e-3, y) || want != ground_hit(x - 1e-3, y) ||
            want != ground_hit(x, y + 1e-3) || want != ground_hit(x, y - 1e-3))
            continue;
        total++;
        agree += face_covers(&r.faces[0], r.cfg.edge_frac_bits, x, y) == want;
    }
    CHECK_EQ(agree, total);
    CHECK(total > 15000);
    gp_run_free(&r);
}

TEST(face_wholly_behind_is_dropped)
{
    gp_run_result r;
    const char *text = "albatros-scene 1\n" OBSERVER_AT_ORIGIN
                       "object g\n v -5 -1 -10\n v 5 -1 -10\n v 5 -1 -2\n v -5 -1 -2\n f 1 2 3 4\nend\n";
    if (gp_run_text(text, NULL, &r)) {
        CHECK_MSG(0, "%s", r.err);
        return;
    }
    CHECK_EQ(r.nfaces, 0);
    CHECK_EQ(r.st.faces_behind, 1);
    gp_run_free(&r);
}

TEST(culling_drops_face_or_edges_as_fig1)
{
    gp_run_result r;
    /* a triangle wholly right of the screen: some edge has the screen outside */
    const char *right = "albatros-scene 1\n" OBSERVER_AT_ORIGIN
                        "object t\n v 20 0 10\n v 30 0 10\n v 25 5 10\n f 1 2 3\nend\n";
    if (gp_run_text(right, NULL, &r)) {
        CHECK_MSG(0, "%s", r.err);
        return;
    }
    CHECK_EQ(r.nfaces, 0);
    CHECK_EQ(r.st.faces_offscreen, 1);
    gp_run_free(&r);
    /* a quad far larger than the view: every edge has the screen inside */
    const char *huge = "albatros-scene 1\n" OBSERVER_AT_ORIGIN
                       "object q\n v -100 -100 10\n v 100 -100 10\n v 100 100 10\n v -100 100 10\n"
                       " f 1 2 3 4\nend\n";
    if (gp_run_text(huge, NULL, &r)) {
        CHECK_MSG(0, "%s", r.err);
        return;
    }
    CHECK_EQ(r.nfaces, 1);
    CHECK_EQ(r.st.edges_offscreen, 4);
    CHECK_EQ(r.nfaces ? r.faces[0].n_edges : 99, 0);
    gp_run_free(&r);
}

/* A triangle facing the observer (counter-clockwise on the screen). */
static const char *tri_scene(char *buf, size_t len, const char *extra_v, const char *face_opts)
{
    (void)extra_v;
    snprintf(buf, len,
             "albatros-scene 1\n" OBSERVER_AT_ORIGIN "near 0.5\n"
             "light 0.3 0.5 -0.8 ambient 0.2\n"
             "object t\n"
             " v -2 -1 5 i 0.2 n -0.3 0.1 -1 t 0 0\n"
             " v 3 -1 9 i 0.9 n 0.4 0.2 -1 t 1 0\n"
             " v 0 2 7 i 0.5 n 0 0.6 -1 t 0 1\n"
             " f 1 2 3 %s\nend\n", face_opts);
    return buf;
}

TEST(backface_culling_by_winding)
{
    gp_run_result r;
    char buf[1024];
    /* 1 2 3 as above is counter-clockwise on the screen: front */
    if (gp_run_text(tri_scene(buf, sizeof buf, "", ""), NULL, &r)) {
        CHECK_MSG(0, "%s", r.err);
        return;
    }
    CHECK_EQ(r.nfaces, 1);
    gp_run_free(&r);
    const char *rev = "albatros-scene 1\n" OBSERVER_AT_ORIGIN
                      "object t\n v -2 -1 5\n v 3 -1 9\n v 0 2 7\n f 3 2 1\nend\n";
    CHECK(gp_run_text(rev, NULL, &r) == 0);
    CHECK_EQ(r.nfaces, 0);
    CHECK_EQ(r.st.faces_backfacing, 1);
    gp_run_free(&r);
    CHECK(gp_run_text(rev, "backface=0", &r) == 0);
    CHECK_EQ(r.nfaces, 1);
    gp_run_free(&r);
}

/* Depth (6) and the ratio (7) at the projected vertices equal near/Z and the
 * vertex intensities. */
TEST(depth_and_intensity_forms_reproduce_vertices)
{
    gp_run_result r;
    char buf[1024];
    if (gp_run_text(tri_scene(buf, sizeof buf, "", ""), "bound=none", &r) || r.nfaces != 1) {
        CHECK_MSG(0, "run failed: %s", r.err);
        return;
    }
    const alb_ws_face *f = &r.faces[0];
    CHECK(f->flags & ALB_WS_FACE_SHADE);
    const double v[3][4] = {{-2, -1, 5, 0.2}, {3, -1, 9, 0.9}, {0, 2, 7, 0.5}};
    for (int k = 0; k < 3; k++) {
        double x = v[k][0] / v[k][2], y = v[k][1] / v[k][2];
        double depth = alb_ws_form_eval(&f->depth, x, y);
        CHECK_NEAR(depth, 0.5 / v[k][2], 1e-6);
        CHECK_NEAR(alb_ws_form_eval(&f->shade, x, y) / depth, v[k][3], 1e-5);
    }
    gp_run_free(&r);
}

/* Lighting (8): I = ambient + L.N with N interpolated from vertex normals. */
TEST(lit_object_intensity_at_vertices)
{
    const char *text = "albatros-scene 1\n" OBSERVER_AT_ORIGIN "near 0.5\n"
                       "light 0.3 0.5 -0.8 ambient 0.2\n"
                       "object t moving\n"
                       " v -2 -1 5 n -0.3 0.1 -1\n v 3 -1 9 n 0.4 0.2 -1\n v 0 2 7 n 0 0.6 -1\n"
                       " f 1 2 3\nend\n";
    gp_run_result r;
    if (gp_run_text(text, "bound=none", &r) || r.nfaces != 1) {
        CHECK_MSG(0, "run failed: %s", r.err);
        return;
    }
    const double v[3][3] = {{-2, -1, 5}, {3, -1, 9}, {0, 2, 7}};
    const double n[3][3] = {{-0.3, 0.1, -1}, {0.4, 0.2, -1}, {0, 0.6, -1}};
    for (int k = 0; k < 3; k++) {
        double len = sqrt(n[k][0] * n[k][0] + n[k][1] * n[k][1] + n[k][2] * n[k][2]);
        double want = 0.2 + (0.3 * n[k][0] + 0.5 * n[k][1] - 0.8 * n[k][2]) / len;
        double x = v[k][0] / v[k][2], y = v[k][1] / v[k][2];
        const alb_ws_face *f = &r.faces[0];
        CHECK_NEAR(alb_ws_form_eval(&f->shade, x, y) / alb_ws_form_eval(&f->depth, x, y), want, 1e-5);
    }
    gp_run_free(&r);
}

/* The observer transform with rotation, field of view, aspect and an object
 * pose: the depth form at each vertex's screen position is near/Z, computed
 * here from the scene's conventions. */
TEST(observer_transform_places_vertices)
{
    const char *text = "albatros-scene 1\nnear 0.25\n"
                       "observer at 1 2 -3 yaw 20 pitch -10 roll 5 fov 50 aspect 1.5\n"
                       "object t at 2 1 6 yaw -30 pitch 15\n"
                       " v -2 -1 0 i 0.1\n v 2 -1 1 i 0.6\n v 0 2 0.5 i 1\n f 1 2 3\nend\n";
    gp_run_result r;
    if (gp_run_text(text, "bound=none backface=0", &r) || r.nfaces != 1) {
        CHECK_MSG(0, "run failed: %s", r.err);
        return;
    }
    const double obj[3][4] = {{-2, -1, 0, 0.1}, {2, -1, 1, 0.6}, {0, 2, 0.5, 1}};
    mat3 q = m3_orientation(-30, 15, 0), o = m3_orientation(20, -10, 5);
    mat3 ot = m3_transpose(&o);
    double sy = 1 / tan(25 * VEC3_PI / 180), sx = sy / 1.5;
    for (int k = 0; k < 3; k++) {
        vec3 w = v3_add(m3_apply(&q, v3(obj[k][0], obj[k][1], obj[k][2])), v3(2, 1, 6));
        vec3 e = m3_apply(&ot, v3_sub(w, v3(1, 2, -3)));
        double x = sx * e.x / e.z, y = sy * e.y / e.z;
        const alb_ws_face *f = &r.faces[0];
        double depth = alb_ws_form_eval(&f->depth, x, y);
        CHECK_NEAR(depth, 0.25 / e.z, 1e-6 * 0.25 / e.z + 1e-9);
        CHECK_NEAR(alb_ws_form_eval(&f->shade, x, y) / depth, obj[k][3], 1e-5);
    }
    gp_run_free(&r);
}

TEST(orientation_conventions)
{
    mat3 m = m3_orientation(90, 0, 0);
    vec3 f = m3_apply(&m, v3(0, 0, 1));   /* yaw 90: forward turns to +x */
    CHECK_NEAR(f.x, 1, 1e-12);
    CHECK_NEAR(f.z, 0, 1e-12);
    m = m3_orientation(0, 90, 0);         /* pitch 90: forward turns up */
    f = m3_apply(&m, v3(0, 0, 1));
    CHECK_NEAR(f.y, 1, 1e-12);
    m = m3_orientation(0, 0, 90);         /* roll 90: up turns to +x */
    f = m3_apply(&m, v3(0, 1, 0));
    CHECK_NEAR(f.x, 1, 1e-12);
}

/* §2: the integer parts of D_u, D_v dropped keep texture precise however far
 * the observer is from the texture origin.  Here the face is 10^6 periods from
 * it; the fraction of u at screen points must match the exact value. */
TEST(texture_far_from_origin_keeps_precision)
{
    const char *text = "albatros-scene 1\n"
                       "observer at 1000000.25 0.5 0 fov 90 aspect 1\n"
                       "texture c checker 3 0 0 0 255 255 255\n"
                       "object far\n"
                       " v 999995 -5 10\n v 1000005 -5 10\n v 1000005 5 10\n v 999995 5 10\n"
                       " f 1 2 3 4 texture c axes 1 0 0 0 0 1 0 0\nend\n";
    gp_run_result r;
    if (gp_run_text(text, "bound=none", &r) || r.nfaces != 1) {
        CHECK_MSG(0, "run failed: %s", r.err);
        return;
    }
    const alb_ws_face *f = &r.faces[0];
    CHECK(f->flags & ALB_WS_FACE_TEXTURE);
    uint64_t s = 4;
    double worst = 0;
    for (int i = 0; i < 2000; i++) {
        double x = t_uniform(&s, -0.45, 0.45), y = t_uniform(&s, -0.45, 0.45);
        /* ray (x, y, 1) from the observer meets z = 10 at X = 1000000.25 + 10x */
        double u_exact = 0.25 + 10 * x, v_exact = 0.5 + 10 * y;
        double depth = alb_ws_form_eval(&f->depth, x, y);
        double u = alb_ws_form_eval(&f->tex_u, x, y) / depth, v = alb_ws_form_eval(&f->tex_v, x, y) / depth;
        double du = fabs(remainder(u - u_exact, 1)), dv = fabs(remainder(v - v_exact, 1));
        worst = fmax(worst, fmax(du, dv));
    }
    CHECK_MSG(worst < 1e-4, "texture error %g periods", worst);
    /* the forms stay small: the observer is within a period of the origin */
    CHECK(fabs(ldexp(f->tex_u.m[2], f->tex_u.exp)) < 0.2);
    gp_run_free(&r);
}

/* Bounding edges: a sliver triangle gets the Albatros edges; none without. */
TEST(sliver_gets_bounding_edges)
{
    const char *text = "albatros-scene 1\n" OBSERVER_AT_ORIGIN
                       "object s\n v -0.4 -1 5\n v 0.4 -1 5\n v 0 3 5\n f 1 2 3\nend\n";
    gp_run_result r;
    CHECK(gp_run_text(text, "bound=albatros", &r) == 0);
    /* Edge sectors (Fig. 2): the base runs along +x with A = 0, and Sgn 0 = 0
     * puts it in sector 4; the right side is in 7, the left in 2.  The tip
     * (7 -> 2) and the lower-right vertex (4 -> 7) have sector differences
     * of 3, so the rule fires on both, though the base angle is 84 degrees. */
    CHECK_EQ(r.st.bound_added, 2);
    unsigned with = r.nfaces ? r.faces[0].n_edges : 0;
    CHECK_EQ(with, 5);
    if (with == 5) {
        /* the tip's edge: horizontal (both edges steep), at y = 0.6, the
         * face below it; the corner's: vertical (the first edge is
         * horizontal) at x = 0.08, the face to its left */
        const alb_ws_edge *tip = &r.faces[0].edge[4], *corner = &r.faces[0].edge[3];
        CHECK(tip->u == 0 && tip->r == 1 && tip->x1 == tip->x2);
        CHECK_NEAR(ival(tip->x1, r.cfg.edge_frac_bits), 3.0 / 5, ldexp(1, -14));
        CHECK(corner->u == 1 && corner->r == 1 && corner->x1 == corner->x2);
        CHECK_NEAR(ival(corner->x1, r.cfg.edge_frac_bits), 0.4 / 5, ldexp(1, -14));
    }
    gp_run_free(&r);
    CHECK(gp_run_text(text, "bound=none", &r) == 0);
    CHECK_EQ(r.nfaces ? r.faces[0].n_edges : 0, 3);
    gp_run_free(&r);
    CHECK(gp_run_text(text, "bound=box", &r) == 0);
    CHECK_EQ(r.nfaces ? r.faces[0].n_edges : 0, 7);
    gp_run_free(&r);
    CHECK(gp_run_text(text, "bound=bisector", &r) == 0);
    CHECK_EQ(r.nfaces ? r.faces[0].n_edges : 0, 6);
    /* bounding edges never cut the face: points inside the exact triangle are
     * inside every emitted edge */
    uint64_t s = 2;
    int bad = 0;
    for (int i = 0; i < 5000 && r.nfaces; i++) {
        double y = t_uniform(&s, -0.19, 0.59), half = 0.08 * (0.6 - y) / 0.8;
        double x = t_uniform(&s, -half * 0.98, half * 0.98);
        bad += !face_covers(&r.faces[0], r.cfg.edge_frac_bits, x, y);
    }
    CHECK_EQ(bad, 0);
    gp_run_free(&r);
}

/* Shared edges of a mesh quantise to identical intercepts with opposite R,
 * so the VP's tie rule can give each sample on them to exactly one face. */
TEST(shared_edges_identical_with_opposite_r)
{
    char text[4096];
    int n = snprintf(text, sizeof text, "albatros-scene 1\nobserver at 0 3 -6 pitch -20 fov 60\n"
                                        "object grid\n");
    for (int j = 0; j <= 4; j++)
        for (int i = 0; i <= 4; i++)
            n += snprintf(text + n, sizeof text - (size_t)n, " v %d 0 %d\n", i - 2, j);
    for (int j = 0; j < 4; j++)
        for (int i = 0; i < 4; i++) {
            int a = j * 5 + i + 1;
            n += snprintf(text + n, sizeof text - (size_t)n, " f %d %d %d %d\n", a, a + 1, a + 6, a + 5);
        }
    snprintf(text + n, sizeof text - (size_t)n, "end\n");
    gp_run_result r;
    if (gp_run_text(text, "bound=none", &r)) {
        CHECK_MSG(0, "%s", r.err);
        return;
    }
    CHECK_EQ(r.nfaces, 16);
    /* face (i, j) has vertices a, a+1, a+6, a+5; its edge k joins its
     * vertices k and k+1 (no edge is dropped in this view) */
    int vid[16][4];
    for (int f = 0; f < 16; f++) {
        int a = (f / 4) * 5 + f % 4;
        vid[f][0] = a, vid[f][1] = a + 1, vid[f][2] = a + 6, vid[f][3] = a + 5;
    }
    unsigned shared = 0, identical = 0;
    for (unsigned a = 0; a < r.nfaces && r.nfaces == 16; a++)
        for (unsigned b = a + 1; b < 16; b++)
            for (int i = 0; i < 4; i++)
                for (int j = 0; j < 4; j++) {
                    if (vid[a][i] != vid[b][(j + 1) % 4] || vid[a][(i + 1) % 4] != vid[b][j])
                        continue;
                    shared++;
                    CHECK(r.faces[a].n_edges == 4 && r.faces[b].n_edges == 4);
                    const alb_ws_edge *e = &r.faces[a].edge[i], *g = &r.faces[b].edge[j];
                    identical += e->u == g->u && e->x1 == g->x1 && e->x2 == g->x2 && e->r != g->r;
                }
    CHECK_EQ(shared, 24);
    CHECK_EQ(identical, 24);
    gp_run_free(&r);
}
