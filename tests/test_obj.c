/* test_obj.c — Wavefront OBJ import: materials, splitting of faces the GP
 * cannot take as they are, located errors, and the command-line camera. */
#include "t.h"
#include "../common/vec3.h"
#include "gp_helpers.h"
#include "albatros/scene.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

static const char *write_file(const char *name, const char *text)
{
    static char path[600];
    snprintf(path, sizeof path, "%s/%s", t_tmpdir(), name);
    FILE *f = fopen(path, "w");
    if (f) {
        fputs(text, f);
        fclose(f);
    }
    return path;
}

static alb_scene_camera default_camera(void)
{
    alb_scene_camera c = {{0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 60, 256, 256};
    return c;
}

TEST(obj_cube_with_materials_and_negative_indices)
{
    write_file("m.mtl", "newmtl red\nKd 1 0 0\nnewmtl half\nKd 0.5 0.5 0.5\n");
    const char *path = write_file("cube.obj",
        "mtllib m.mtl\r\n"
        "v -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\n"
        "v -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1\n"
        "usemtl red\nf 5 6 7 8\nf -7 -8 -5 -6\n"    /* -7.. = 2 1 4 3 */
        "usemtl half\nf 6 2 3 7\n");
    alb_scene s;
    alb_diag d;
    alb_diag_init(&d, NULL);
    alb_scene_camera cam = default_camera();
    alb_err e = alb_scene_load_obj(path, &cam, &s, &d);
    CHECK_MSG(e == ALB_OK, "%s:%u:%u %s", d.file, d.line, d.col, d.msg);
    if (e)
        return;
    CHECK_EQ(s.nobj, 1);
    CHECK_EQ(s.obj[0].nf, 3);
    CHECK(s.obj[0].f[0].rgb[0] == 255 && s.obj[0].f[0].rgb[1] == 0);
    CHECK_EQ(s.obj[0].f[2].rgb[0], 128);      /* 0.5 * 255 rounded half up */
    CHECK_EQ(s.obj[0].idx[s.obj[0].f[1].first], 1);   /* -7 of 8 is vertex 2 (0-based 1) */
    CHECK_EQ(s.obj[0].f[1].line, 12);
    /* z negated: the scene is the OBJ seen in a left-handed frame */
    CHECK_NEAR(s.obj[0].v[4].p.z, -1, 0);
    alb_scene_free(&s);
}

TEST(obj_front_faces_seen_from_the_camera)
{
    /* a cube seen from OBJ (3, 2.5, 4): exactly its +x, +y, +z faces are front */
    const char *path = write_file("c.obj",
        "v -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\n"
        "v -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1\n"
        "f 5 6 7 8\nf 2 1 4 3\nf 6 2 3 7\nf 1 5 8 4\nf 8 7 3 4\nf 1 2 6 5\n");
    char text[200];
    snprintf(text, sizeof text, "%s", path);
    alb_scene s;
    alb_diag d;
    alb_diag_init(&d, NULL);
    alb_scene_camera cam = {{3, 2.5, 4}, {0, 0, 0}, {0, 1, 0}, 45, 256, 256};
    if (alb_scene_load_obj(text, &cam, &s, &d)) {
        CHECK_MSG(0, "%s", d.msg);
        return;
    }
    alb_profile p;
    alb_profile_lookup("a256", &p);
    alb_gp *gp = NULL;
    alb_ws_buf b;
    alb_ws_buf_init(&b);
    alb_gp_stats st;
    CHECK(alb_gp_create(&gp, &s, &p, &d) == ALB_OK && alb_gp_run(gp, &b, &st, &d) == ALB_OK);
    CHECK_EQ(st.faces_out, 3);
    CHECK_EQ(st.faces_backfacing, 3);
    /* and the emitted ones are faces 0 (+z), 2 (+x), 4 (+y) */
    alb_ws_reader r;
    alb_ws_reader_init(&r, b.w, b.n, "c");
    static alb_ws_event ev;
    unsigned ids = 0;
    while (!r.ended && alb_ws_next(&r, &ev, &d) == ALB_OK)
        if (ev.kind == ALB_WS_EV_FACE)
            ids |= 1u << ev.u.face.id;
    CHECK_EQ(ids, 1u << 0 | 1u << 2 | 1u << 4);
    alb_ws_buf_free(&b);
    alb_gp_destroy(gp);
    alb_scene_free(&s);
}

TEST(obj_nonconvex_polygon_is_split)
{
    /* an L-shaped planar hexagon, area 3 */
    const char *path = write_file("l.obj", "v 0 0 0\nv 2 0 0\nv 2 1 0\nv 1 1 0\nv 1 2 0\nv 0 2 0\n"
                                           "f 1 2 3 4 5 6\nv 5 5 5\nf 1 2 1\n");
    alb_scene s;
    alb_diag d;
    alb_diag_init(&d, NULL);
    alb_scene_camera cam = default_camera();
    alb_err e = alb_scene_load_obj(path, &cam, &s, &d);
    CHECK_MSG(e == ALB_OK, "%s", d.msg);
    if (e)
        return;
    const alb_scene_object *o = &s.obj[0];
    CHECK_EQ(o->nf, 4);
    double area = 0;
    for (unsigned i = 0; i < o->nf; i++) {
        CHECK_EQ(o->f[i].count, 3);
        CHECK_EQ(o->f[i].id, 0);   /* the triangles share the hexagon's: OBJ face 0 */
        area += v3_len(alb_scene_face_newell(o, &o->f[i])) / 2;
        alb_diag chk;
        alb_diag_init(&chk, NULL);
        CHECK(alb_scene_check_face(&s, o, &o->f[i], NULL, &chk) == ALB_OK);
    }
    CHECK_NEAR(area, 3, 1e-12);
    CHECK_EQ(d.warnings, 1);   /* the degenerate "f 1 2 1" skipped with a warning */
    alb_scene_free(&s);
}

TEST(obj_errors_are_located)
{
    static const struct {
        const char *text;
        unsigned line, col;
        const char *msg;
    } cases[] = {
        {"v 1 2.5x 3\n", 1, 5, "2.5x"},
        {"v 1 nan 3\n", 1, 5, "nan"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n", 4, 7, "4"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 0\n", 4, 7, "0"},
        /* quoted as written, beyond what an unsigned holds */
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 99999999999999999999 3\n", 4, 5,
         "vertex index 99999999999999999999 is out of range: 3 defined so far"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2/-00000000000000000000000009 3\n", 4, 7,
         "texture vertex index -00000000000000000000000009 is out of range: 0 defined"},
        {"v 0x1 0 0\n", 1, 3, "expected a number, found '0x1'"},
        {"\xef\xbb\xbfv 0 0 0\n", 1, 1, "byte 0xef: expected ASCII text (this is a UTF-8 "
                                     "byte-order mark"},
        {"v 0 0 0 \xef\xbb\xbf\n", 1, 9, "byte 0xef: expected ASCII text"},
        {"v 1 2 3.5e\n", 1, 7, "expected a number, found '3.5e'"},
        {"v 1e999 0 0\n", 1, 3, "number '1e999' is out of range"},
        {"v 0 0 0\nv 1 0 0\nf 1 2\n", 3, 0, "3"},
        {"v 0 0 0\nv 2 0 0\nv 2 1 0\nv 1 1 0.5\nv 1 2 0\nv 0 2 0\n"
         "f 1 2 3 4 5 6\n", 7, 0, "non-convex and non-planar"},
        {"v 0 0 0\nv 1 1 0\nv 1 0 0\nv 0 1 0\nf 1 2 3 4\n", 5, 0, "self-intersecting"},
        {"# nothing\n", 1, 0, "no faces"},
        /* classic Mac line ends: named, not "expected a number, found 'v'" */
        {"v 0 0 0\rv 1 0 0\rv 0 1 0\rf 1 2 3\r", 1, 8, "bare carriage return (CR)"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        const char *path = write_file("bad.obj", cases[i].text);
        alb_scene s;
        alb_diag d;
        alb_diag_init(&d, NULL);
        alb_scene_camera cam = default_camera();
        alb_err e = alb_scene_load_obj(path, &cam, &s, &d);
        CHECK_MSG(e != ALB_OK, "case %zu accepted", i);
        if (e == ALB_OK) {
            alb_scene_free(&s);
            continue;
        }
        CHECK_MSG(d.line == cases[i].line && (cases[i].col == 0 || d.col == cases[i].col),
                  "case %zu: at %u:%u, expected %u:%u: %s", i, d.line, d.col, cases[i].line,
                  cases[i].col, d.msg);
        CHECK_STR_CONTAINS(d.msg, cases[i].msg);
    }
}

/* an underflow is a rounding, as in a scene: 1e-400 reads as 0 */
TEST(obj_underflow_reads_as_zero)
{
    const char *path = write_file("u.obj", "v 1e-400 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    alb_scene s;
    alb_diag d;
    alb_diag_init(&d, NULL);
    alb_scene_camera cam = default_camera();
    alb_err e = alb_scene_load_obj(path, &cam, &s, &d);
    CHECK_MSG(e == ALB_OK, "%s", d.msg);
    if (e)
        return;
    CHECK_EQ(s.nobj, 1);
    CHECK(s.obj[0].nv == 3 && s.obj[0].v[0].p.x == 0);
    alb_scene_free(&s);
}

TEST(obj_camera_orientation)
{
    const char *path = write_file("t.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    alb_scene s;
    alb_diag d;
    alb_diag_init(&d, NULL);
    /* OBJ eye (5, 0, 0) looking at the origin: forward is OBJ -x = scene -x */
    alb_scene_camera cam = {{5, 0, 0}, {0, 0, 0}, {0, 1, 0}, 60, 512, 256};
    if (alb_scene_load_obj(path, &cam, &s, &d)) {
        CHECK_MSG(0, "%s", d.msg);
        return;
    }
    const alb_scene_observer *o = &s.frames[0].obs;
    CHECK(o->look_at);
    mat3 m = m3_look_at(o->pose.pos, o->at, o->up);
    vec3 f = m3_apply(&m, v3(0, 0, 1)), up = m3_apply(&m, v3(0, 1, 0));
    vec3 right = m3_apply(&m, v3(1, 0, 0));
    CHECK_NEAR(f.x, -1, 1e-12);
    CHECK_NEAR(up.y, 1, 1e-12);
    /* looking along scene -x with y up, the right hand is scene +z: OBJ -z,
     * as forward x up = (-1,0,0) x (0,1,0) in the OBJ's right-handed frame */
    CHECK_NEAR(right.z, 1, 1e-12);
    CHECK_NEAR(o->aspect, 2, 0);
    alb_scene_free(&s);
    /* the default OBJ eye (0, 0, 5) is scene (0, 0, -5) looking along +z */
    cam = default_camera();
    if (alb_scene_load_obj(path, &cam, &s, &d)) {
        CHECK_MSG(0, "%s", d.msg);
        return;
    }
    o = &s.frames[0].obs;
    m = m3_look_at(o->pose.pos, o->at, o->up);
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            CHECK(m.m[i][j] == (i == j));   /* exactly the identity: no angle */
    CHECK_NEAR(o->pose.pos.z, -5, 0);
    alb_scene_free(&s);
    /* bad cameras are errors naming the option */
    cam = default_camera();
    cam.at = cam.eye;
    CHECK(alb_scene_load_obj(path, &cam, &s, &d) == ALB_ERR_CONFIG);
    CHECK_STR_CONTAINS(d.msg, "--eye and --at");
    cam = default_camera();
    cam.up = v3(0, 0, 1);
    CHECK(alb_scene_load_obj(path, &cam, &s, &d) == ALB_ERR_CONFIG);
    /* as the user gave it, not with z negated as the importer works */
    CHECK_STR_CONTAINS(d.msg, "--up (0,0,1) is parallel");
    /* the command line checks the view before any file is read */
    CHECK(alb_scene_camera_check(&cam, &d) == ALB_ERR_CONFIG);
    CHECK_STR_CONTAINS(d.msg, "--up (0,0,1) is parallel");
    cam = default_camera();
    cam.width = 0;   /* the size is the profile's to check */
    CHECK(alb_scene_camera_check(&cam, &d) == ALB_OK);
}

/* The camera's lengths neither overflow nor underflow on the way: an eye
 * at 1e308 is not "the same point as at", a denormal up is not zero; what
 * does overflow says so (issue 16, item 10). */
TEST(obj_camera_check_takes_extreme_values)
{
    alb_diag d;
    alb_diag_init(&d, NULL);
    alb_scene_camera c = default_camera();
    c.eye = v3(1e308, 0, 0);
    CHECK_MSG(alb_scene_camera_check(&c, &d) == ALB_OK, "%s", d.msg);
    c = default_camera();
    c.up = v3(1e-320, 0, 0);
    CHECK_MSG(alb_scene_camera_check(&c, &d) == ALB_OK, "%s", d.msg);
    c = default_camera();
    c.eye = v3(1e308, 0, 0);
    c.at = v3(-1e308, 0, 0);
    CHECK(alb_scene_camera_check(&c, &d) == ALB_ERR_CONFIG);
    CHECK_STR_CONTAINS(d.msg, "too far apart");
    c = default_camera();
    c.at = c.eye;
    CHECK(alb_scene_camera_check(&c, &d) == ALB_ERR_CONFIG);
    CHECK_STR_CONTAINS(d.msg, "must be different points");
    c = default_camera();
    c.up = v3(0, 0, 0);
    CHECK(alb_scene_camera_check(&c, &d) == ALB_ERR_CONFIG);
    CHECK_STR_CONTAINS(d.msg, "non-zero");
    c = default_camera();
    c.fov_y = 1e-300;
    CHECK(alb_scene_camera_check(&c, &d) == ALB_ERR_CONFIG);
    CHECK_STR_CONTAINS(d.msg, "[1e-06, 180)");
}

/* face.id is the OBJ's face order (docs/vp.md §7): a skipped degenerate face
 * keeps its number (no later id shifts) and the triangles a polygon is split
 * into share their polygon's, in the scene, the stream and the frame. */
TEST(obj_face_ids_follow_the_file)
{
    const char *path = write_file("ids.obj",
        "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nv 0 0 0\nv 1.2 -1 0\nv 2.2 -1 0\nv 1.7 1 0\n"
        "v -2.4 -1 0\nv -1.4 -1 0\nv -1.4 1 0\nv -1.9 0 0\nv -2.4 1 0\n"
        "f 1 2 5\n"            /* 0: a triangle */
        "f 1 5 3\n"            /* 1: collinear, skipped */
        "f 6 7 8\n"            /* 2: a triangle */
        "f 9 10 11 12 13\n"    /* 3: a pentagon, reflex at 12: split */
        "f 5 2 3\n");          /* 4: a triangle */
    alb_scene s;
    alb_diag d;
    alb_diag_init(&d, NULL);
    alb_scene_camera cam = default_camera();
    if (alb_scene_load_obj(path, &cam, &s, &d)) {
        CHECK_MSG(0, "%s", d.msg);
        return;
    }
    const alb_scene_object *o = &s.obj[0];
    CHECK_EQ(d.warnings, 1);   /* the collinear face, skipped */
    CHECK_EQ(o->nf, 6);        /* 3 triangles and the pentagon's 3 */
    unsigned count[5] = {0};
    for (unsigned i = 0; i < o->nf; i++)
        if (o->f[i].id < 5)
            count[o->f[i].id]++;
    CHECK(count[0] == 1 && count[1] == 0 && count[2] == 1 && count[3] == 3 && count[4] == 1);
    /* the frame shows the file's numbers, each where its face is */
    alb_profile p;
    alb_profile_lookup("a256", &p);
    alb_gp *gp = NULL;
    alb_vp *vp = NULL;
    alb_ws_buf b;
    alb_ws_buf_init(&b);
    alb_frame fr;
    CHECK(alb_gp_create(&gp, &s, &p, &d) == ALB_OK && alb_gp_run(gp, &b, NULL, &d) == ALB_OK &&
          alb_vp_create(&vp, &p, &d) == ALB_OK && alb_vp_frame_alloc(vp, &fr, false) == 0);
    alb_ws_reader r;
    alb_ws_reader_init(&r, b.w, b.n, "ids");
    static alb_ws_event ev;
    unsigned seen = 0;
    while (!r.ended && alb_ws_next(&r, &ev, &d) == ALB_OK) {
        if (ev.kind == ALB_WS_EV_CONFIG)
            alb_vp_config(vp, &ev.u.config, &d);
        else if (ev.kind == ALB_WS_EV_FRAME)
            alb_vp_frame_begin(vp, &ev.u.frame);
        else if (ev.kind == ALB_WS_EV_FACE) {
            seen |= 1u << ev.u.face.id;
            alb_vp_face(vp, &ev.u.face, &d);
        } else if (ev.kind == ALB_WS_EV_FRAME_END)
            alb_vp_frame_end(vp, &fr);
    }
    CHECK_EQ(seen, 1u << 0 | 1u << 2 | 1u << 3 | 1u << 4);
    /* screen positions of the faces' insides: the eye at OBJ (0, 0, 5),
     * fov 60, looks at the origin; x = X / (5 tan 30) */
    static const struct { double x, y; unsigned id; } at[] = {
        {0, -0.6, 0}, {1.7, -0.5, 2}, {-2.2, -0.8, 3}, {-1.5, 0.6, 3}, {-2.3, 0.6, 3},
        {0.6, 0, 4}};
    for (size_t i = 0; i < sizeof at / sizeof at[0]; i++) {
        double sx = at[i].x / (5 * 0.57735026918962576), sy = at[i].y / (5 * 0.57735026918962576);
        unsigned px = (unsigned)((sx + 1) / 2 * 256), py = (unsigned)((1 - sy) / 2 * 256);
        CHECK_MSG(fr.face[(size_t)py * 256 + px] == at[i].id, "at (%g, %g): face %u, expected %u",
                  at[i].x, at[i].y, fr.face[(size_t)py * 256 + px], at[i].id);
    }
    alb_frame_free(&fr);
    alb_vp_destroy(vp);
    alb_ws_buf_free(&b);
    alb_gp_destroy(gp);
    alb_scene_free(&s);
}
