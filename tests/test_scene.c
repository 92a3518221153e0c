/* test_scene.c — the scene format: what parses, and for what does not, the
 * exact line, column and message (docs/scene-format.md). */
#include "t.h"
#include "albatros/scene.h"

#include <malloc.h>
#include <png.h>
#include <stdio.h>
#include <stdlib.h>
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
    alb_scene s;
    alb_diag d;
    alb_diag_init(&d, NULL);
    alb_err e = alb_scene_parse(text, strlen(text), "x.scene", &s, &d);
    CHECK_MSG(e == ALB_OK, "%u:%u: %s", d.line, d.col, d.msg);
    if (e)
        return;
    CHECK_EQ(s.nobj, 1);
    CHECK_EQ(s.nframes, 2);
    CHECK_EQ(s.nfaces, 2);
    CHECK(s.near == 0.25 && s.fog && s.fog_far == 50);
    const alb_scene_object *o = &s.obj[0];
    CHECK(o->moving && o->nv == 3 && o->nf == 2);
    CHECK(o->f[0].shade == ALB_SHADE_LIT && o->f[0].texmap == ALB_TEXMAP_UV && o->f[0].rgb[1] == 20);
    CHECK(o->f[1].texmap == ALB_TEXMAP_AXES && !o->f[1].fog && o->f[1].rgb[0] == 9);
    CHECK_NEAR(o->v[1].n.z, -1, 1e-12);   /* normals are normalised */
    /* frame 1 inherits frame 0's pose and changes the observer */
    CHECK(alb_scene_pose_at(&s, 0, 0)->pos.x == 1 && alb_scene_pose_at(&s, 1, 0)->pos.x == 1);
    CHECK(s.frames[0].obs.pose.pos.x == 1 && s.frames[1].obs.pose.pos.x == 0);
    CHECK(s.frames[0].obs.fov_y == 45 && s.frames[1].light.dir.x == 1);
    alb_scene_free(&s);
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
        /* bad faces: at the column of the vertex number at fault, or of the
         * `f` for the face as a whole */
        {HDR "object t\n v 0 0 5\n v 1 0 5\n v 2 0 5\n f 1 2 3\nend\n", 6, 2,
         "face 0 of object 't' has zero area (collinear vertices)"},
        /* vertex 4 lifted by 1 out of the plane z = 5 of the other three */
        {HDR "object t\n v 0 0 5\n v 1 0 5\n v 1 1 5\n v 0 1 6\n f 1 2 3 4\nend\n", 7, 10,
         "is not planar: vertex 4 is 1 from the plane of the others (tolerance 1.41e-06)"},
        /* a pentagon, vertex 4 lifted by 0.3: the plane through the centroid
         * would put vertex 1 first beyond the tolerance */
        {HDR "object t\n v 0 0 5\n v 2 0 5\n v 3 1.5 5\n v 1.5 3 5.3\n v 0 2 5\n"
             " f 1 2 3 4 5\nend\n", 8, 10, "is not planar: vertex 4 is 0.3 from the plane of the "
                                          "others"},
        {HDR "object t\n v 0 0 5\n v 2 0 5\n v 1 0.2 5\n v 1 2 5\n f 1 2 3 4\nend\n", 7, 8,
         "face 0 of object 't' is not convex at vertex 3"},
        /* the closing edge: the last number written is the one at fault */
        {HDR "object t\n v 0 0 5\n v 1 0 5\n v 1 1 5\n v 0 0 5\n f 1 2 3 4\nend\n", 7, 10,
         "vertices 4 and 1 coincide (zero-length edge)"},
        {HDR "object t\n v 0 0 5\n v 1 0 5\n v 0 1 5\n f 1 1 3\nend\n", 6, 6,
         "vertex 1 is given twice in a row"},
        /* vertices named by the numbers written on the f line, not positions */
        {HDR "object t\n v 0 0 5\n v 1 0 5\n v 0 1 5\n v 1 0 5\n f 1 2 4 3\nend\n", 7, 8,
         "vertices 2 and 4 coincide"},
        {HDR "object t\n v 0 0 5\n v 2 0 5\n v 1 0.2 5\n v 1 2 5\n f 4 1 2 3\nend\n", 7, 10,
         "not convex at vertex 3"},
        /* a pentagram: every turn 144 degrees, two revolutions */
        {HDR "object t\n v 0 1 5\n v -0.951 0.309 5\n v -0.588 -0.809 5\n v 0.588 -0.809 5\n"
             " v 0.951 0.309 5\n f 1 3 5 2 4\nend\n", 8, 2,
         "is not a simple convex polygon (it winds 2.00 times)"},
        /* aspect: a number or W/H */
        {HDR "observer aspect 4/0\n" TRI, 2, 19, "aspect W/H needs H > 0"},
        {HDR "observer aspect 4/\n" TRI, 2, 19, "expected W/H with a number on each side of '/', "
                                               "found '4/'"},
        {HDR "observer aspect /3\n" TRI, 2, 17, "expected W/H with a number"},
        {HDR "observer aspect x/3\n" TRI, 2, 17, "expected a number, found 'x'"},
        {HDR "observer aspect 4/3x\n" TRI, 2, 19, "expected a number, found '3x'"},
        {HDR "observer aspect 400/3\n" TRI, 2, 17, "aspect 133.333 must be in [1e-06, 100)"},
        {HDR "object t\n v 0 0 5\n v 1 0 5\n v 0 1 5\n f 1 2 3\n", 6, 1, "has no 'end'"},
        {HDR "object t\nend\n", 3, 1, "has no faces"},
        {HDR TRI "object t\n", 8, 8, "defined twice"},
        {HDR TRI "frame\nobject u\n", 9, 1, "objects must be declared before the first 'frame'"},
        {HDR TRI "frame\nnear 1\n", 9, 1, "'near' is a global statement: it must come before"},
        {HDR TRI "frame\nend\n", 9, 1, "expected observer, light, pose or frame"},
        {HDR "object t\n v 0 0 5\nobject u\n", 4, 1, "'object' inside object 't' (missing 'end'?)"},
        {HDR TRI "pose t at 1 2 3\n", 8, 1, "belongs inside a frame"},
        {HDR TRI "frame\n pose q at 1 2 3\n", 9, 7, "the name of an object"},
        {HDR "object t\n v 0 0 5 t 0 0\n v 1 0 5\n v 0 1 5\n f 1 2 3 texture nope\nend\n", 6, 18,
         "texture defined above"},
        {HDR "texture c checker 4 0 0 0 1 1 1\nobject t\n v 0 0 5\n v 1 0 5\n v 0 1 5\n"
             " f 1 2 3 texture c\nend\n", 7, 2, "no mapping"},
        {HDR "texture c checker 11 0 0 0 1 1 1\n" TRI, 2, 19, "2^1 .. 2^10"},
        {HDR "texture c file /nonexistent/x.png\n" TRI, 2, 16,
         "texture 'c': cannot open '/nonexistent/x.png': No such file or directory"},
        {HDR "observer fov 180\n" TRI, 2, 14, "[1e-06, 180)"},
        /* the scene format takes any positive near; whether the word stream
         * can hold it is the GP's check (test_gp.c) */
        {HDR "near 1e40\n" TRI, 0, 0, NULL},
        {HDR "near 1e-50\n" TRI, 0, 0, NULL},
        {HDR "object t\n v 0 0 5 n 0 0 0\nend\n", 3, 10, "zero length"},
        {HDR "near 1\xff\n" TRI, 2, 7, "byte 0xff"},
        {"\xef\xbb\xbf" HDR TRI, 1, 1, "byte 0xef: scene files are ASCII text (this is a UTF-8 "
                                    "byte-order mark"},
        /* classic Mac line ends would read as one line */
        {"albatros-scene 1\robject t\r", 1, 17, "bare carriage return (CR)"},
        {HDR "near 1\r\r\n" TRI, 2, 7, "bare carriage return"},
        /* numbers are decimal: strtod's other syntaxes are not numbers, or not finite */
        {HDR "near 0x10\n" TRI, 2, 6, "expected a number, found '0x10'"},
        {HDR "near 0x1p99999\n" TRI, 2, 6, "expected a number, found '0x1p99999'"},
        {HDR "near 1e\n" TRI, 2, 6, "expected a number, found '1e'"},
        {HDR "near infinity\n" TRI, 2, 6, "number 'infinity' is not finite"},
        {HDR "near NAN(1)\n" TRI, 2, 6, "number 'NAN(1)' is not finite"},
        {HDR "near 1111111111111111111111111111111111111111111111111111111111111111\n" TRI, 2, 6,
         "is too long: 64 characters, at most 63"},
        {HDR "near 1111111111111111111111111111111111111111111111111111111111111111x\n" TRI, 2, 6,
         "expected a number, found '1111"},
        /* messages that say what is wrong (issue 16, item 10) */
        {HDR "object t\n v 0 0 5\n v 1 0 5\n v 0 1 5\n f 1 2 1 3\nend\n", 6, 8,
         "vertex 1 is used twice (as its vertex 1 and 3), folding it onto itself"},
        {HDR "observer fov 1e-300\n" TRI, 2, 14, "field of view 1e-300 must be in [1e-06, 180)"},
        {HDR "observer aspect 1e-300\n" TRI, 2, 17, "aspect 1e-300 must be in [1e-06, 100)"},
        {HDR "near 1\f\n" TRI, 2, 6, "expected a number, found '1\\x0c'"},
        {HDR "near \v 1\n" TRI, 2, 6, "expected a number, found '\\x0b'"},
        {HDR "texture t file \"a b.png\n" TRI, 2, 16, "unterminated quote"},
        {HDR TRI, 0, 0, NULL},   /* valid */
        {"albatros-scene 1\r\nnear +.5e-1\r\nbackground 1. 2 3\r\n" TRI, 0, 0, NULL},
        /* 63 characters, the longest number taken */
        {HDR "near 0.0000000000000000000000000000000000000000000000000000000000001\n" TRI, 0, 0,
         NULL},
        {HDR TRI "near 1\r", 0, 0, NULL},   /* cut after the CR of a CRLF */
        /* an underflow is a rounding to 0 (or a denormal), as in an OBJ file */
        {HDR "object t\n v 1e-400 0 5\n v 1 0 5\n v 0 1 5\n f 1 2 3\nend\n", 0, 0, NULL},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        alb_scene s;
        alb_diag d;
        alb_diag_init(&d, NULL);
        alb_err e = alb_scene_parse(cases[i].text, strlen(cases[i].text), "x.scene", &s, &d);
        if (!cases[i].msg) {
            CHECK_MSG(e == ALB_OK, "case %zu: %s", i, d.msg);
            if (!e)
                alb_scene_free(&s);
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

TEST(scene_aspect_takes_a_ratio)
{
    static const struct {
        const char *text;
        double aspect;
    } cases[] = {
        {HDR "observer aspect 4/3\n" TRI, 4.0 / 3},
        {HDR "observer aspect 16/9 fov 50\n" TRI, 16.0 / 9},
        {HDR "observer aspect 1.5e0/.5\n" TRI, 3},
        {HDR "observer aspect 1.25\n" TRI, 1.25},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        alb_scene s;
        alb_diag d;
        alb_diag_init(&d, NULL);
        if (alb_scene_parse(cases[i].text, strlen(cases[i].text), "x.scene", &s, &d)) {
            CHECK_MSG(0, "case %zu: %u:%u: %s", i, d.line, d.col, d.msg);
            continue;
        }
        CHECK(s.frames[0].obs.aspect == cases[i].aspect);
        alb_scene_free(&s);
    }
}

/* Screen space: near/Z = near * depth / (largest depth), near 1 unless the
 * scene says, before or after `screenspace` (docs/scene-format.md). */
TEST(screenspace_keeps_a_written_near)
{
    static const struct {
        const char *head;
        double near;
    } cases[] = {
        {"screenspace\n", 1},
        {"screenspace\nnear 0.5\n", 0.5},
        {"near 0.25\nscreenspace\n", 0.25},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        char text[256];
        snprintf(text, sizeof text, HDR "%sobject t\n v 0 0 2\n v 32 0 4\n v 0 32 4\n f 1 2 3\nend\n",
                 cases[i].head);
        alb_scene s;
        alb_diag d;
        alb_diag_init(&d, NULL);
        if (alb_scene_parse(text, strlen(text), "x.scene", &s, &d) ||
            alb_scene_resolve_screenspace(&s, 32, 32, &d)) {
            CHECK_MSG(0, "case %zu: %s", i, d.msg);
            continue;
        }
        CHECK(s.near == cases[i].near);
        /* the vertex at the largest depth at Z = 1, the one at half of it at 2 */
        CHECK(s.obj[0].v[1].p.z == 1 && s.obj[0].v[0].p.z == 2);
        alb_scene_free(&s);
    }
}

static const char *tmp_path(const char *name)
{
    static char path[4][600];
    static unsigned next;
    char *p = path[next++ % 4];
    snprintf(p, sizeof path[0], "%s/%s", t_tmpdir(), name);
    return p;
}

/* The first `len` bytes of a valid 4x4 PNG in `name`; the whole file if len
 * is SIZE_MAX.  Returns its full size, 0 on failure. */
static size_t write_png_prefix(const char *name, size_t len)
{
    uint8_t rgb[4 * 4 * 3] = {0};
    png_image img;
    memset(&img, 0, sizeof img);
    img.version = PNG_IMAGE_VERSION;
    img.width = img.height = 4;
    img.format = PNG_FORMAT_RGB;
    static uint8_t buf[4096];
    png_alloc_size_t size = sizeof buf;
    if (!png_image_write_to_memory(&img, buf, &size, 0, rgb, 0, NULL))
        return 0;
    FILE *f = fopen(tmp_path(name), "wb");
    if (!f)
        return 0;
    fwrite(buf, 1, len < size ? len : size, f);
    fclose(f);
    return size;
}

/* libpng's own message for a file that ends early is "Read Error". */
TEST(texture_png_errors_say_why)
{
    size_t size = write_png_prefix("ok.png", SIZE_MAX);
    CHECK(size > 60);
    write_png_prefix("empty.png", 0);
    write_png_prefix("sig.png", 4);
    write_png_prefix("header.png", 20);
    write_png_prefix("data.png", size - 20);
    static const struct {
        const char *file, *msg;
    } cases[] = {
        {"ok.png", NULL},
        {"missing.png", "cannot open '"},
        {"empty.png", "is empty (0 bytes)"},
        {"sig.png", "is truncated: the file ends after 4 bytes, inside the PNG signature"},
        {"header.png", "is truncated: the file ends after 20 bytes"},
        {"data.png", "is truncated"},
        {".", "is a directory"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        alb_scene_texture t = {0};
        alb_diag d;
        alb_diag_init(&d, NULL);
        const char *path = tmp_path(cases[i].file);
        alb_err e = alb_scene_texture_png(&t, path, &d);
        if (!cases[i].msg) {
            CHECK_MSG(e == ALB_OK && t.log2size == 2, "%s: %s", cases[i].file, d.msg);
            free(t.texels);
            continue;
        }
        CHECK_MSG(e != ALB_OK, "%s accepted", cases[i].file);
        CHECK_STR_CONTAINS(d.msg, cases[i].msg);
        CHECK_MSG(strstr(d.msg, path) != NULL, "%s: the path is not named", d.msg);
        CHECK(t.texels == NULL);
    }
}

/* A texture with alpha: opaque texels as they are, transparent ones black
 * (composited onto black, never onto whatever memory held — that varied
 * from run to run). */
TEST(texture_png_alpha_composited_onto_black)
{
    uint8_t rgba[4 * 4 * 4];
    for (int i = 0; i < 16; i++) {
        bool opaque = i % 2 == 0;
        rgba[4 * i] = 200, rgba[4 * i + 1] = 100, rgba[4 * i + 2] = 50;
        rgba[4 * i + 3] = opaque ? 255 : 0;
    }
    png_image img;
    memset(&img, 0, sizeof img);
    img.version = PNG_IMAGE_VERSION;
    img.width = img.height = 4;
    img.format = PNG_FORMAT_RGBA;
    const char *path = tmp_path("alpha.png");
    CHECK(png_image_write_to_file(&img, path, 0, rgba, 0, NULL));
    /* fresh memory filled with a pattern, as a reused heap would hold */
    mallopt(M_PERTURB, 0x5a);
    for (int run = 0; run < 2; run++) {
        alb_scene_texture t = {0};
        alb_diag d;
        alb_diag_init(&d, NULL);
        if (alb_scene_texture_png(&t, path, &d) != ALB_OK) {
            CHECK_MSG(0, "%s", d.msg);
            return;
        }
        for (int y = 0; y < 4; y++)
            for (int x = 0; x < 4; x++) {
                /* texel row 0 is the image's bottom row */
                bool opaque = ((3 - y) * 4 + x) % 2 == 0;
                uint32_t want = opaque ? 0xC86432u : 0;
                CHECK_MSG(t.texels[y * 4 + x] == want, "texel (%d, %d) = %06x, expected %06x", x,
                          y, t.texels[y * 4 + x], want);
            }
        free(t.texels);
    }
    mallopt(M_PERTURB, 0);
}

TEST(builtin_scene_parses)
{
    alb_scene s;
    alb_diag d;
    alb_diag_init(&d, NULL);
    alb_err e = alb_scene_load_builtin(&s, &d);
    CHECK_MSG(e == ALB_OK, "%u:%u: %s", d.line, d.col, d.msg);
    if (e)
        return;
    CHECK(s.nobj >= 8 && s.nframes >= 2 && s.ntex == 2 && s.fog);
    bool moving = false, vertex_shaded = false, textured = false;
    for (unsigned i = 0; i < s.nobj; i++)
        for (unsigned j = 0; j < s.obj[i].nf; j++) {
            moving |= s.obj[i].f[j].shade == ALB_SHADE_LIT;
            vertex_shaded |= s.obj[i].f[j].shade == ALB_SHADE_VERTEX;
            textured |= s.obj[i].f[j].texmap != ALB_TEXMAP_NONE;
        }
    CHECK(moving && vertex_shaded && textured);
    alb_scene_free(&s);
}

/* A face longer than the format takes is named for that limit, not for the
 * words on its line (issue 16, item 10). */
TEST(scene_long_face_names_the_vertex_limit)
{
    char *text = NULL;
    size_t size = 0;
    FILE *f = open_memstream(&text, &size);
    fprintf(f, "albatros-scene 1\nobject t\n");
    for (int k = 0; k < 1000; k++)
        fprintf(f, " v %.17g %.17g 5\n", cos(k * 6.283185307179586 / 1000), sin(k * 6.283185307179586 / 1000));
    fprintf(f, " f");
    for (int k = 1; k <= 1000; k++)
        fprintf(f, " %d", k);
    fprintf(f, "\nend\n");
    fclose(f);
    alb_scene s;
    alb_diag d;
    alb_diag_init(&d, NULL);
    CHECK(alb_scene_parse(text, size, "x.scene", &s, &d) == ALB_ERR_LIMIT);
    CHECK_EQ(d.line, 1003);
    CHECK_STR_CONTAINS(d.msg, "face has more than 32 vertices (1000 words on the line)");
    free(text);
}

/* Poses are kept per change: 1000 objects over 20000 frames in which one
 * object moves each frame hold 1000 + 20000 poses, not 20 million, and each
 * frame still sees every object where its last change put it. */
TEST(scene_poses_per_change_not_per_frame)
{
    char *text = NULL;
    size_t size = 0;
    FILE *f = open_memstream(&text, &size);
    fprintf(f, "albatros-scene 1\n");
    for (int o = 0; o < 1000; o++)
        fprintf(f, "object o%d at %d 0 50\n v 0 0 0\n v 1 0 0\n v 0 1 0\n f 1 2 3\nend\n", o, o);
    for (int k = 0; k < 20000; k++)
        fprintf(f, "frame\n pose o%d yaw %d\n", k % 1000, k);
    fclose(f);
    alb_scene s;
    alb_diag d;
    alb_diag_init(&d, NULL);
    CHECK(alb_scene_parse(text, size, "x.scene", &s, &d) == ALB_OK);
    free(text);
    unsigned long poses = 0;
    for (unsigned o = 0; o < s.nobj; o++)
        poses += s.obj[o].npose;
    /* object 0's first change is in frame 0, where it replaces the initial pose */
    CHECK_EQ(poses, 1000 + 20000 - 1);
    CHECK_EQ(s.nframes, 20000);
    /* object 7 moves in frames 7, 1007, ...: yaw 7 from frame 7 to 1006 */
    CHECK(alb_scene_pose_at(&s, 6, 7)->yaw == 0 && alb_scene_pose_at(&s, 7, 7)->yaw == 7);
    CHECK(alb_scene_pose_at(&s, 1006, 7)->yaw == 7 && alb_scene_pose_at(&s, 1007, 7)->yaw == 1007);
    CHECK(alb_scene_pose_at(&s, 19999, 999)->yaw == 19999 && alb_scene_pose_at(&s, 0, 999)->pos.x == 999);
    alb_scene_free(&s);
}
