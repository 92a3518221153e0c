/* test_reference.c — the exact reference's camera against positions worked
 * out by hand from docs/scene-format.md ("Orientation"), and the GP's camera
 * against the reference on rotated observers and objects: the reference
 * computes its camera apart from the GP (tools/ref.c), so a mistake in
 * either shows. */
#include "t.h"
#include "../tools/accuracy.h"
#include "../tools/ref.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <zlib.h>

/* The observer-space vertices (screen-scaled: x/z, y/z on the screen) of the
 * first face the reference keeps in frame 0 of scene text; 0 on success. */
static int ref_vertices(const char *text, vec3 out[3])
{
    alb_scene s;
    alb_diag d;
    alb_diag_init(&d, NULL);
    if (alb_scene_parse(text, strlen(text), "camera", &s, &d)) {
        CHECK_MSG(0, "%u:%u: %s", d.line, d.col, d.msg);
        return -1;
    }
    alb_profile p;
    alb_profile_lookup("a256", &p);
    ref_frame rf;
    int rc = -1;
    if (!ref_prepare(&s, &p, 0, &rf)) {
        if (rf.n >= 1) {
            for (int k = 0; k < 3; k++)
                out[k] = rf.faces[0].v[k];
            rc = 0;
        }
        ref_frame_free(&rf);
    }
    alb_scene_free(&s);
    CHECK_MSG(rc == 0, "no face in view");
    return rc;
}

#define SCENE(observer, pose, v1, v2, v3)                                                        \
    "albatros-scene 1\nobserver " observer " fov 90\nobject t " pose "\n v " v1 "\n v " v2        \
    "\n v " v3 "\n f 1 2 3\nend\n"

TEST(reference_camera_by_hand)
{
    static const struct {
        const char *text;
        double p[3][3];          /* expected observer-space vertices */
    } cases[] = {
        /* yaw 90: forward +x, right -z, up +y; fov 90 gives sx = sy = 1:
         * (5, 1, -2) has right 2, up 1, forward 5 */
        {SCENE("yaw 90", "", "5 1 -2", "5 1 -3", "5 2 -2"), {{2, 1, 5}, {3, 1, 5}, {2, 2, 5}}},
        /* pitch 30: forward (0, 1/2, sqrt 3/2), up (0, sqrt 3/2, -1/2):
         * (0, 1, 2) has up sqrt 3/2 - 1, forward 1/2 + sqrt 3 */
        {SCENE("pitch 30", "", "0 1 2", "1 1 2", "0 2 2"),
         {{0, 0.86602540378443865 - 1, 0.5 + 1.7320508075688773},
          {1, 0.86602540378443865 - 1, 0.5 + 1.7320508075688773},
          {0, 2 * 0.86602540378443865 - 1, 1 + 1.7320508075688773}}},
        /* roll 90: up turns to +x, right to -y: (1, 2, 4) has right -2, up 1 */
        {SCENE("roll 90", "", "1 2 4", "2 2 4", "1 3 4"), {{-2, 1, 4}, {-2, 2, 4}, {-3, 1, 4}}},
        /* the eye moved and turned: at (0 0 -10) yaw 180 looks along -z, right
         * is -x; (1, 0, -20) is 10 ahead, 1 to the left */
        {SCENE("at 0 0 -10 yaw 180", "", "1 0 -20", "0 0 -20", "1 1 -20"),
         {{-1, 0, 10}, {0, 0, 10}, {-1, 1, 10}}},
        /* an object turned instead: yaw 90 maps its x axis to -z, its z axis
         * to +x; placed at (0 0 10), vertex (0 0 1) is at (1, 0, 10) */
        {SCENE("", "at 0 0 10 yaw 90", "0 0 1", "1 0 1", "0 1 1"),
         {{1, 0, 10}, {1, 0, 9}, {1, 1, 10}}},
        /* pitch 90 then yaw 90 on an object (Ry Rx): its z axis turns to +y,
         * its x axis to -z, its y axis to -x */
        {SCENE("", "at 0 0 10 yaw 90 pitch 90", "0 0 1", "1 0 1", "0 1 1"),
         {{0, 1, 10}, {0, 1, 9}, {-1, 1, 10}}},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        vec3 v[3];
        if (ref_vertices(cases[i].text, v))
            continue;
        for (int k = 0; k < 3; k++)
            CHECK_MSG(fabs(v[k].x - cases[i].p[k][0]) < 1e-12 &&
                          fabs(v[k].y - cases[i].p[k][1]) < 1e-12 &&
                          fabs(v[k].z - cases[i].p[k][2]) < 1e-12,
                      "case %zu vertex %d: (%.15g, %.15g, %.15g), expected (%g, %g, %g)", i, k,
                      v[k].x, v[k].y, v[k].z, cases[i].p[k][0], cases[i].p[k][1],
                      cases[i].p[k][2]);
    }
}

/* An OBJ look-at camera: eye (5, 0, 0) toward the origin, up y, in the OBJ's
 * right-handed frame; the importer negates z.  OBJ vertex (0, 0, 1) is scene
 * (0, 0, -1): from the eye (-5, 0, -1), forward 5, right (scene +z) -1. */
TEST(reference_look_at_by_hand)
{
    char path[600];
    snprintf(path, sizeof path, "%s/cam.obj", t_tmpdir());
    FILE *f = fopen(path, "w");
    CHECK(f != NULL);
    if (!f)
        return;
    fputs("v 0 0 1\nv 0 1 1\nv 0 0 2\nf 1 2 3\nf 1 3 2\n", f);
    fclose(f);
    alb_scene_camera cam = {{5, 0, 0}, {0, 0, 0}, {0, 1, 0}, 90, 256, 256};
    alb_scene s;
    alb_diag d;
    alb_diag_init(&d, NULL);
    if (alb_scene_load_obj(path, &cam, &s, &d)) {
        CHECK_MSG(0, "%s", d.msg);
        return;
    }
    alb_profile p;
    alb_profile_lookup("a256", &p);
    ref_frame rf;
    CHECK(ref_prepare(&s, &p, 0, &rf) == 0 && rf.n == 1);
    if (rf.n == 1) {
        /* the face kept is the one facing the eye; its vertices in order */
        const vec3 *v = rf.faces[0].v;
        static const double want[2][3] = {{-1, 0, 5}, {-1, 1, 5}};
        for (int k = 0; k < 2; k++)
            CHECK_MSG(fabs(v[k].x - want[k][0]) < 1e-12 && fabs(v[k].y - want[k][1]) < 1e-12 &&
                          fabs(v[k].z - want[k][2]) < 1e-12,
                      "vertex %d: (%.15g, %.15g, %.15g)", k, v[k].x, v[k].y, v[k].z);
    }
    ref_frame_free(&rf);
    alb_scene_free(&s);
}

/* The GP against the reference under rotated observers and objects: a
 * camera convention the GP got wrong (a sign, an order of rotations) would
 * move the faces and differ on clear pixels. */
TEST(gp_camera_agrees_with_reference)
{
    static const char *const observers[] = {
        "yaw 30", "pitch -20", "roll 45", "yaw 200 pitch 35 roll -70 at 1 -2 3",
        "yaw -95 pitch 80 roll 10 fov 40", "yaw 720.5 pitch 360 roll -359 aspect 2"};
    alb_profile p;
    alb_profile_lookup("a256", &p);
    char err[300];
    alb_profile_set(&p, "width=128", err, sizeof err);
    alb_profile_set(&p, "height=128", err, sizeof err);
    accuracy total;
    accuracy_init(&total);
    for (size_t i = 0; i < sizeof observers / sizeof observers[0]; i++) {
        char text[16384];
        int n = snprintf(text, sizeof text, "albatros-scene 1\nobserver %s\n", observers[i]);
        /* turned quads in the 26 directions around the eye, so that every
         * view sees several, both sides drawn */
        unsigned q = 0;
        for (int dx = -1; dx <= 1; dx++)
            for (int dy = -1; dy <= 1; dy++)
                for (int dz = -1; dz <= 1; dz++, q++) {
                    if (!dx && !dy && !dz)
                        continue;
                    n += snprintf(text + n, sizeof text - (size_t)n,
                                  "object q%u at %d %d %d yaw %u pitch %u roll %u\n"
                                  " v -3 -3 0\n v 3 -3 0\n v 3 3 0\n v -3 3 0\n"
                                  " f 1 2 3 4 colour %u 90 90\n f 4 3 2 1 colour 90 %u 90\nend\n",
                                  q, 7 * dx, 7 * dy, 7 * dz, q * 37 % 360, q * 53 % 360,
                                  q * 71 % 360, 9 * q, 9 * q);
                }
        accuracy a;
        accuracy_init(&a);
        CHECK_MSG(!accuracy_of_text(text, &p, &a, err, sizeof err), "%s: %s", observers[i], err);
        size_t judged = accuracy_judged(&a, ACC_JUDGED);
        CHECK_MSG(accuracy_errors(&a, ACC_JUDGED) == 0, "observer %s: %zu judged pixels differ",
                  observers[i], accuracy_errors(&a, ACC_JUDGED));
        /* most of the picture judged, a good part of it covered by faces */
        CHECK_MSG(judged > a.pixels * 9 / 10 && a.covered > a.pixels / 4,
                  "observer %s: %zu of %zu pixels judged, %zu covered", observers[i], judged,
                  a.pixels, a.covered);
        accuracy_add(&total, &a);
    }
    CHECK(total.pixels == 6 * 128 * 128);
}

/* alb_frame_digest (emu/frame_out.c, its own CRC table) against the byte
 * layout it documents, hashed here by zlib: a change of layout or table
 * shows, and so does a plane left out. */
TEST(frame_digest_is_the_documented_crc)
{
    alb_frame f;
    CHECK(alb_frame_alloc(&f, 3, 2, true) == 0);
    f.colour_bits = 8, f.depth_bits = 24, f.aa_levels = 0, f.number = 7;
    for (unsigned i = 0; i < 6; i++) {
        for (int ch = 0; ch < 3; ch++)
            f.rgb[3 * i + ch] = (uint16_t)(40 * i + ch);
        f.depth[i] = 0x10000 * i + 3, f.face[i] = i == 4 ? ALB_FRAME_NO_FACE : i;
        f.level[i] = (uint8_t)i, f.coverage[i] = (uint16_t)(i & 1), f.cycles[i] = 1000 * i;
    }
    uint8_t bytes[6 * 21 + 24], *p = bytes;
    for (unsigned i = 0; i < 6; i++) {
        uint64_t v[8] = {f.rgb[3 * i], f.rgb[3 * i + 1], f.rgb[3 * i + 2], f.depth[i], f.face[i],
                         f.level[i], f.coverage[i], f.cycles[i]};
        static const int size[8] = {2, 2, 2, 4, 4, 1, 2, 4};
        for (int k = 0; k < 8; k++)
            for (int b = 0; b < size[k]; b++)
                *p++ = (uint8_t)(v[k] >> 8 * b);
    }
    const uint32_t meta[6] = {3, 2, 8, 24, 0, 7};
    for (int k = 0; k < 6; k++)
        for (int b = 0; b < 4; b++)
            *p++ = (uint8_t)(meta[k] >> 8 * b);
    CHECK_EQ(alb_frame_digest(&f), (uint32_t)crc32(0, bytes, (uInt)(p - bytes)));
    uint32_t d0 = alb_frame_digest(&f);
    f.level[5] ^= 1;   /* any plane counts */
    CHECK(alb_frame_digest(&f) != d0);
    alb_frame_free(&f);
}
