/* test_scene.c — the scene format: what parses, and for what does not, the
 * exact line, column and message (docs/scene-format.md). */
#include "t.h"
#include "../gp/scene.h"

#include <string.h>

#define HDR "albatros-scene 1\n"
#define TRI "object t\n v 0 0 5\n v 1 0 5\n v 0 1 5\n f 1 2 3\nend\n"

TEST(scene_parses_everything)
{
    const char *text = HDR
        "# comment\n"
        "near 0.25\nbackground 1 2 3\nfog 10 20 30 5 50\n"
        "texture c checker 4 0 0 0 255 255 255 4\n"
        "light 0 1 0 ambient 0.5\n"
        "observer at 1 2 3 yaw 10 pitch 20 roll 30 fov 45 aspect 1.25\n"
        "object a moving at 4 5 6 yaw 7\n"
        " colour 10 20 30\n"
        " v 0 0 5 n 0 0 -1 t 0 0 i 0.5\n v 1 0 5 n 0 0 -2 t 1 0 i 0.5\n v 0 1 5 n 0 0 -1 t 0 1 i 0.5\n"
        " f 1 2 3 texture c\n"
        " f 1 2 3 colour 9 9 9 axes 1 0 0 0 0 1 0 0 texture c nofog intensity 0.5\n"
        "end\n"
        "frame\n pose a at 1 1 1\nframe\n observer at 0 0 0\n light 1 0 0\n";
    scene_t s;
    diag_t d;
    diag_init(&d, NULL);
    alb_err e = scene_parse(text, strlen(text), "x.scene", &s, &d);
    CHECK_MSG(e == ALB_OK, "%u:%u: %s", d.line, d.col, d.msg);
    if (e)
        return;
    CHECK_EQ(s.nobj, 1);
    CHECK_EQ(s.nframes, 2);
    CHECK_EQ(s.nfaces, 2);
    CHECK(s.near == 0.25 && s.fog && s.fog_far == 50);
    const scene_object *o = &s.obj[0];
    CHECK(o->moving && o->nv == 3 && o->nf == 2);
    CHECK(o->f[0].shade == SHADE_LIT && o->f[0].texmap == TEXMAP_UV && o->f[0].rgb[1] == 20);
    CHECK(o->f[1].texmap == TEXMAP_AXES && !o->f[1].fog && o->f[1].rgb[0] == 9);
    CHECK_NEAR(o->v[1].n.z, -1, 1e-12);   /* normals are normalised */
    /* frame 1 inherits frame 0's pose and changes the observer */
    CHECK(s.frames[0].poses[0].pos.x == 1 && s.frames[1].poses[0].pos.x == 1);
    CHECK(s.frames[0].obs.pose.pos.x == 1 && s.frames[1].obs.pose.pos.x == 0);
    CHECK(s.frames[0].obs.fov_y == 45 && s.frames[1].light.dir.x == 1);
    scene_free(&s);
}

TEST(scene_errors_name_line_column_and_expectation)
{
    static const struct {
        const char *text;
        unsigned line, col;
        const char *msg;
    } cases[] = {
        {"", 1, 1, "expected the header line"},
        {"albatros-scene 2\n", 1, 1, "expected the header line"},
        {HDR "near -1\n" TRI, 2, 6, "near must be positive"},
        {HDR "near abc\n" TRI, 2, 6, "expected a number, found 'abc'"},
        {HDR "near nan\n" TRI, 2, 6, "not finite"},
        {HDR "near 1e999\n" TRI, 2, 6, "not finite or out of range"},
        {HDR "background 1 2 256\n" TRI, 2, 16, "integer 0..255"},
        {HDR "bogus 1\n" TRI, 2, 1, "expected a statement"},
        {HDR "object t\n v 0 0\nend\n", 3, 7, "expected a number at end of line"},
        {HDR "object t\n v 0 0 5\n v 1 0 5\n v 0 1 5\n f 1 2 4\nend\n", 6, 8, "vertices 1..3"},
        {HDR "object t\n v 0 0 5\n v 1 0 5\n f 1 2\nend\n", 5, 7, "at least 3 vertex numbers"},
        {HDR "object t\n v 0 0 5\n v 1 0 5\n v 2 0 5\n f 1 2 3\nend\n", 6, 0, "zero area"},
        {HDR "object t\n v 0 0 5\n v 1 0 5\n v 1 1 5\n v 0 1 6\n f 1 2 3 4\nend\n", 7, 0,
         "not planar"},
        {HDR "object t\n v 0 0 5\n v 2 0 5\n v 1 0.2 5\n v 1 2 5\n f 1 2 3 4\nend\n", 7, 0,
         "not convex at vertex 3"},
        {HDR "object t\n v 0 0 5\n v 1 0 5\n v 1 1 5\n v 0 0 5\n f 1 2 3 4\nend\n", 7, 0,
         "coincide"},
        {HDR "object t\n v 0 0 5\n v 1 0 5\n v 0 1 5\n f 1 1 3\nend\n", 6, 0, "coincide"},
        {HDR "object t\n v 0 0 5\n v 1 0 5\n v 0 1 5\n f 1 2 3\n", 6, 1, "has no 'end'"},
        {HDR "object t\nend\n", 3, 1, "has no faces"},
        {HDR TRI "object t\n", 8, 8, "defined twice"},
        {HDR TRI "frame\nobject u\n", 9, 1, "expected observer, light, pose or frame"},
        {HDR TRI "pose t at 1 2 3\n", 8, 1, "belongs inside a frame"},
        {HDR TRI "frame\n pose q at 1 2 3\n", 9, 7, "the name of an object"},
        {HDR "object t\n v 0 0 5 t 0 0\n v 1 0 5\n v 0 1 5\n f 1 2 3 texture nope\nend\n", 6, 18,
         "texture defined above"},
        {HDR "texture c checker 4 0 0 0 1 1 1\nobject t\n v 0 0 5\n v 1 0 5\n v 0 1 5\n"
             " f 1 2 3 texture c\nend\n", 7, 2, "no mapping"},
        {HDR "texture c checker 11 0 0 0 1 1 1\n" TRI, 2, 19, "2^1 .. 2^10"},
        {HDR "texture c file /nonexistent/x.png\n" TRI, 2, 16, "texture 'c'"},
        {HDR "observer fov 180\n" TRI, 2, 14, "(0, 180)"},
        {HDR "object t\n v 0 0 5 n 0 0 0\nend\n", 3, 10, "zero length"},
        {HDR "near 1\xff\n" TRI, 2, 7, "byte 0xff"},
        {HDR TRI, 0, 0, NULL},   /* valid */
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        scene_t s;
        diag_t d;
        diag_init(&d, NULL);
        alb_err e = scene_parse(cases[i].text, strlen(cases[i].text), "x.scene", &s, &d);
        if (!cases[i].msg) {
            CHECK_MSG(e == ALB_OK, "case %zu: %s", i, d.msg);
            if (!e)
                scene_free(&s);
            continue;
        }
        CHECK_MSG(e != ALB_OK, "case %zu: accepted", i);
        CHECK_MSG(d.line == cases[i].line && d.col == cases[i].col,
                  "case %zu: at %u:%u, expected %u:%u (%s)", i, d.line, d.col, cases[i].line,
                  cases[i].col, d.msg);
        CHECK_STR_CONTAINS(d.msg, cases[i].msg);
        CHECK(strcmp(d.file, "x.scene") == 0);
    }
}

TEST(builtin_scene_parses)
{
    scene_t s;
    diag_t d;
    diag_init(&d, NULL);
    alb_err e = scene_load_builtin(&s, &d);
    CHECK_MSG(e == ALB_OK, "%u:%u: %s", d.line, d.col, d.msg);
    if (e)
        return;
    CHECK(s.nobj >= 8 && s.nframes >= 2 && s.ntex == 2 && s.fog);
    bool moving = false, vertex_shaded = false, textured = false;
    for (unsigned i = 0; i < s.nobj; i++)
        for (unsigned j = 0; j < s.obj[i].nf; j++) {
            moving |= s.obj[i].f[j].shade == SHADE_LIT;
            vertex_shaded |= s.obj[i].f[j].shade == SHADE_VERTEX;
            textured |= s.obj[i].f[j].texmap != TEXMAP_NONE;
        }
    CHECK(moving && vertex_shaded && textured);
    scene_free(&s);
}
