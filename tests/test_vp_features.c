/* test_vp_features.c — anti-aliasing, image textures, fog and colours of the
 * VP, each against a computation made here. */
#include "t.h"
#include "gp_helpers.h"
#include "../tools/ref.h"
#include "../tools/scenegen.h"
#include "../vp/units.h"

#include <math.h>
#include <png.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Coverage with 4 x 4 samples: each pixel counts the sample centres inside
 * the exact triangle (no centre lies on its edges). */
TEST(antialiasing_coverage_and_colour_mean)
{
    const double tri[3][2] = {{3.01, 2.02}, {29.03, 9.07}, {11.05, 28.09}};   /* pixels, y up */
    char text[512];
    snprintf(text, sizeof text,
             "albatros-scene 1\nscreenspace\nbackground 0 0 0\nobject t\n v %g %g 1\n v %g %g 1\n"
             " v %g %g 1\n f 1 2 3 colour 255 255 255\nend\n",
             tri[0][0], tri[0][1], tri[1][0], tri[1][1], tri[2][0], tri[2][1]);
    alb_frame fr;
    char err[300];
    if (render_text(text, "t32", "aa=2 bound=none", &fr, NULL, NULL, err, sizeof err)) {
        CHECK_MSG(0, "%s", err);
        return;
    }
    /* t32 with aa=2: F = 10, so an edge moves by up to 2^-11 screen units,
     * 1/128 pixel, along its U axis; pixels with a sample that close to an
     * edge are left out */
    const double bound = 1.0 / 128 + 1e-9;
    unsigned bad_cov = 0, bad_col = 0, partial = 0, skipped = 0;
    for (unsigned y = 0; y < 32; y++)
        for (unsigned x = 0; x < 32; x++) {
            unsigned k = 0;
            bool near = false;
            for (unsigned sy = 0; sy < 4; sy++)
                for (unsigned sx = 0; sx < 4; sx++) {
                    /* sample centre in pixel units, y up from the bottom */
                    double px = x + (sx + 0.5) / 4, py = 32 - (y + (sy + 0.5) / 4);
                    bool in = true;
                    for (int e = 0; e < 3; e++) {
                        const double *a = tri[e], *b = tri[(e + 1) % 3];
                        double dx = b[0] - a[0], dy = b[1] - a[1];
                        double f = dx * (py - a[1]) - dy * (px - a[0]);
                        in &= f > 0;
                        near |= fabs(f) / fmax(fabs(dx), fabs(dy)) <= bound;
                    }
                    k += in;
                }
            size_t i = (size_t)y * 32 + x;
            if (near) {
                skipped++;
                continue;
            }
            bad_cov += fr.coverage[i] != k;
            partial += k > 0 && k < 16;
            /* colour: mean of 16 samples of 255 or 0, rounded half up */
            unsigned want = (unsigned)floor(255.0 * k / 16 + 0.5);
            bad_col += fr.rgb[3 * i] != want;
        }
    CHECK_EQ(bad_cov, 0);
    CHECK_EQ(bad_col, 0);
    CHECK(partial > 40);
    CHECK_MSG(skipped < partial / 2, "%u pixels skipped, %u partly covered", skipped, partial);
    alb_frame_free(&fr);
}

static int write_png(const char *path, const uint8_t *rgb, unsigned w, unsigned h)
{
    png_image img;
    memset(&img, 0, sizeof img);
    img.version = PNG_IMAGE_VERSION;
    img.width = w;
    img.height = h;
    img.format = PNG_FORMAT_RGB;
    return png_image_write_to_file(&img, path, 0, rgb, 0, NULL) ? 0 : -1;
}

/* A 4 x 4 PNG mapped onto a screen-filling quad: each texel covers an 8 x 8
 * block of pixels, exactly its colour (base white, intensity 1, no fog);
 * PNG row 0 is the top, v = 0 the bottom. */
TEST(image_texture_from_png)
{
    uint8_t rgb[4 * 4 * 3];
    for (unsigned i = 0; i < 16; i++) {
        rgb[3 * i] = (uint8_t)(i * 16);
        rgb[3 * i + 1] = (uint8_t)(255 - i * 16);
        rgb[3 * i + 2] = (uint8_t)(i * 7 + 3);
    }
    char path[600], text[1024];
    snprintf(path, sizeof path, "%s/tex.png", t_tmpdir());
    CHECK(write_png(path, rgb, 4, 4) == 0);
    /* u = x / 32, v = y / 32 in pixel units (y up): one period over the screen */
    snprintf(text, sizeof text,
             "albatros-scene 1\nscreenspace\ntexture t file %s\nobject q\n v 0 0 1 t 0 0\n"
             " v 32 0 1 t 1 0\n v 32 32 1 t 1 1\n v 0 32 1 t 0 1\n"
             " f 1 2 3 4 colour 255 255 255 texture t\nend\n", path);
    alb_frame fr;
    char err[300];
    if (render_text(text, "t32", NULL, &fr, NULL, NULL, err, sizeof err)) {
        CHECK_MSG(0, "%s", err);
        return;
    }
    unsigned bad = 0;
    for (unsigned y = 0; y < 32; y++)
        for (unsigned x = 0; x < 32; x++) {
            unsigned tx = x / 8, ty = y / 8;   /* frame row 0 = top = PNG row 0 */
            const uint8_t *t = &rgb[3 * (ty * 4 + tx)];
            const uint16_t *c = &fr.rgb[3 * ((size_t)y * 32 + x)];
            bad += c[0] != t[0] || c[1] != t[1] || c[2] != t[2];
        }
    CHECK_EQ(bad, 0);
    alb_frame_free(&fr);
}

/* Colour and fog against the exact reference: the built-in scene (lit,
 * vertex-shaded, textured, fogged) agrees within a few frame-store units
 * wherever both draw the same face. */
TEST(colours_agree_with_reference)
{
    char *copy = builtin_scene_copy();
    alb_frame vp;
    char err[300];
    alb_profile p;
    if (render_text(copy, "a256", NULL, &vp, NULL, &p, err, sizeof err)) {
        CHECK_MSG(0, "%s", err);
        free(copy);
        return;
    }
    alb_scene s;
    alb_diag d;
    alb_diag_init(&d, NULL);
    alb_frame ref;
    CHECK(alb_scene_parse(copy, strlen(copy), "builtin", &s, &d) == ALB_OK);
    CHECK(ref_render(&s, &p, 0, &ref) == 0);
    size_t same = 0, close = 0, n = (size_t)p.width * p.height;
    double sq = 0;
    for (size_t i = 0; i < n; i++) {
        if (vp.face[i] != ref.face[i])
            continue;
        same++;
        unsigned worst = 0;
        for (int ch = 0; ch < 3; ch++) {
            int dlt = (int)vp.rgb[3 * i + ch] - (int)ref.rgb[3 * i + ch];
            worst = (unsigned)abs(dlt) > worst ? (unsigned)abs(dlt) : worst;
            sq += dlt * dlt;
        }
        close += worst <= 2;
    }
    /* texel boundaries decide some pixels differently (nearest texel of a
     * coordinate within the divider's error of the boundary) */
    CHECK_MSG(close >= same * 995 / 1000, "%zu of %zu pixels within 2 units", close, same);
    double psnr = 10 * log10(255.0 * 255.0 / (sq / (3.0 * (double)same)));
    CHECK_MSG(psnr > 40, "PSNR %.2f dB", psnr);
    alb_frame_free(&vp);
    alb_frame_free(&ref);
    alb_scene_free(&s);
    free(copy);
}

/* Render text both ways — only the units each face uses, and every unit for
 * every sample (all_units=1) — and require the same frame and statistics. */
static void same_with_all_units(const char *what, const char *text, const char *sets,
                                alb_vp_stats *st)
{
    alb_frame a, b;
    alb_vp_stats sb;
    char err[300], all_sets[200];
    snprintf(all_sets, sizeof all_sets, "%s all_units=1", sets);
    if (render_text(text, "a256", sets, &a, st, NULL, err, sizeof err) ||
        render_text(text, "a256", all_sets, &b, &sb, NULL, err, sizeof err)) {
        CHECK_MSG(0, "%s: %s", what, err);
        return;
    }
    size_t diff = alb_frame_count_differences(&a, &b);
    CHECK_MSG(diff == 0, "%s: %zu pixels differ with all_units=1", what, diff);
    CHECK_MSG(memcmp(st, &sb, sizeof sb) == 0, "%s: statistics differ with all_units=1", what);
    CHECK_MSG(st->samples_written > 1000, "%s: only %llu samples written", what,
              (unsigned long long)st->samples_written);
    alb_frame_free(&a);
    alb_frame_free(&b);
}

/* The output stage's shading loops specialised per set of units (vp/shade.c,
 * vp_shade_run) against the all-units path, over every combination: the
 * built-in scene has shaded, textured and flat faces, all fogged; without
 * its fog line none is; a random scene gives Gouraud faces, and --flat
 * faces with no unit at all. */
TEST(units_a_scene_needs_change_no_pixel)
{
    char *text = builtin_scene_copy();
    alb_vp_stats st;
    same_with_all_units("built-in", text, "", &st);
    CHECK(st.faces_fogged == st.faces && st.faces_textured > 0 && st.faces_shaded > 0 &&
          st.faces_shaded < st.faces);
    same_with_all_units("built-in, aa=1", text, "aa=1", &st);
    char *fog = strstr(text, "\nfog ");
    CHECK(fog != NULL);
    if (fog)
        fog[1] = '#';   /* comment the fog out */
    same_with_all_units("built-in without fog", text, "", &st);
    CHECK(st.faces_fogged == 0 && st.faces_textured > 0);
    free(text);
    for (int flat = 0; flat < 2; flat++) {
        scenegen_params p = scenegen_defaults();
        p.faces = 200;
        p.flat = flat;
        text = scenegen_random(11, &p);
        same_with_all_units(flat ? "random, flat" : "random", text, "", &st);
        CHECK(st.faces_shaded == (flat ? 0 : st.faces) && st.faces_textured == 0);
        /* in fog: flat faces use the fog unit alone */
        const char *body = strchr(text, '\n');
        char *fogged = body ? malloc(strlen(text) + 32) : NULL;
        CHECK(fogged != NULL);
        if (fogged) {
            snprintf(fogged, strlen(text) + 32, "albatros-scene 1\nfog 250 240 230 0.5 4%s", body);
            same_with_all_units(flat ? "random, flat, fog" : "random, fog", fogged, "", &st);
            CHECK(st.faces_fogged == st.faces && st.faces_shaded == (flat ? 0 : st.faces));
            free(fogged);
        }
        free(text);
    }
}

/* The output stage's Gouraud stretches (vp/shade.c: the run cut where the
 * depth form's bit length changes, the reciprocal's shifts then constant;
 * AVX2 four samples a step where the host has it, else plain C) against
 * vp_shade_sample, the every-unit path, sample by sample: random depth and
 * intensity forms whose runs cross powers of two upward and downward, ratio
 * exponents either way (floors, saturation at 1, negative intensities),
 * every colour width and several reciprocal and intensity widths.  And the
 * AVX2 form's division by 65025 as a multiply and shift: exact below the
 * largest x it meets when (M 65025 - 2^S) x_max < 2^S. */
TEST(gouraud_stretches_equal_the_units)
{
    const uint64_t m = 2164359683u, e = m * 65025u - ((uint64_t)1 << 47);
    const uint64_t x_max = (uint64_t)255 * 255 * 65535 + 32512;
    CHECK(m < ((uint64_t)1 << 32) && m * 65025u >= (uint64_t)1 << 47 && e * x_max < (uint64_t)1 << 47);
    uint64_t seed = 99;
    unsigned samples = 0, stretches = 0, clamped = 0, zeros = 0, between = 0, bad = 0;
    for (unsigned trial = 0; trial < 3000 && bad < 5; trial++) {
        alb_profile p;
        alb_profile_lookup("t32", &p);
        p.width = p.height = 256;
        p.recip_bits = 8 + (unsigned)(t_rand(&seed) % 9);
        p.shade_frac_bits = 8 + (unsigned)(t_rand(&seed) % 9);
        p.colour_bits = 4 + (unsigned)(t_rand(&seed) % 13);
        /* every form the host runs: plain C, AVX2, AVX-512 */
        const unsigned forms = 1 + vp_shade_isa_host();
        alb_vp *vp[3] = {NULL, NULL, NULL};
        alb_diag d;
        alb_diag_init(&d, NULL);
        bool made = true;
        for (unsigned k = 0; k < forms; k++) {
            made &= alb_vp_create(&vp[k], &p, &d) == ALB_OK;
            if (vp[k])
                vp[k]->shade_isa = k;
        }
        if (!made) {
            CHECK_MSG(0, "alb_vp_create: %s", d.msg);
            for (unsigned k = 0; k < forms; k++)
                alb_vp_destroy(vp[k]);
            return;
        }
        if (trial == 0)
            printf("# Gouraud stretch forms: %u\n", forms);
        vp_face_setup fs;
        memset(&fs, 0, sizeof fs);
        fs.flags = ALB_WS_FACE_SHADE;
        fs.units = vp_face_units(&fs);
        for (int c = 0; c < 3; c++)
            fs.rgb[c] = (uint8_t)t_rand(&seed);
        /* N_z from just above a power of two, stepping toward the next one
         * up or the previous one down (never to 0), or flat */
        const unsigned n = 1 + (unsigned)(t_rand(&seed) % 90), nb = 4 + (unsigned)(t_rand(&seed) % 34);
        const int64_t dir = (int64_t)(t_rand(&seed) % 3) - 1;
        const int64_t span = (int64_t)1 << (nb - 1), base = span + (int64_t)(t_rand(&seed) % (uint64_t)span);
        fs.depth.step_c = dir * (1 + (int64_t)(t_rand(&seed) % (uint64_t)(span / n + 1)));
        fs.depth.origin = base;
        fs.depth.exp = (int)(t_rand(&seed) % 40) - 20;
        /* N_s of either sign, fitting the product's 63 bits */
        const unsigned sb = 1 + (unsigned)(t_rand(&seed) % (60 - p.recip_bits - 8));
        fs.shade.origin = (int64_t)(t_rand(&seed) >> (64 - sb)) - ((int64_t)1 << (sb - 1)) / 4;
        fs.shade.step_c = (int64_t)(t_rand(&seed) % 2001) - 1000;
        fs.shade.exp = (int)(t_rand(&seed) % 60) - 30;
        if (trial & 1) {
            /* intensities inside (0, 1) mostly: N_s a fraction of N_z */
            const int64_t t = (int64_t)(t_rand(&seed) % 1300);
            fs.shade.exp = fs.depth.exp;
            fs.shade.origin = base / 1024 * t;
            fs.shade.step_c = fs.depth.step_c / 1024 * t + (int64_t)(t_rand(&seed) % 21) - 10;
        }
        int64_t last = base + (int64_t)(n - 1) * fs.depth.step_c;
        if (last <= 0)
            fs.depth.step_c = 0;
        unsigned fb = 0;
        for (unsigned i = 0; i + 1 < n; i++)
            fb += fix_bitlen((uint64_t)(base + (int64_t)i * fs.depth.step_c)) !=
                  fix_bitlen((uint64_t)(base + (int64_t)(i + 1) * fs.depth.step_c));
        stretches += 1 + fb;
        uint16_t got[3][3 * 90 + 8], want[3 * 90];
        for (unsigned k = 0; k < forms; k++) {
            for (unsigned i = 0; i < sizeof got[k] / sizeof *got[k]; i++)
                got[k][i] = 0xBEEF;   /* nothing past the run may change */
            vp_shade_run(vp[k], &fs, 0, 0, n, got[k]);
            for (unsigned i = 3 * n; i < sizeof got[k] / sizeof *got[k]; i++)
                if (got[k][i] != 0xBEEF && bad++ < 5)
                    CHECK_MSG(0, "trial %u: %u samples, a write past the run at %u", trial, n, i);
        }
        for (unsigned i = 0; i < n; i++) {
            vp_shade_sample(vp[0], &fs, units_form_at(&fs.depth, i, 0), i, 0, want + 3 * i);
            samples++;
            clamped += want[3 * i] == vp_scale_colour8(vp[0], fs.rgb[0]) && fs.rgb[0];
            zeros += want[3 * i] == 0 && fs.rgb[0] > 16;
            between += want[3 * i] > 0 && want[3 * i] < vp_scale_colour8(vp[0], fs.rgb[0]);
        }
        for (unsigned k = 0; k < forms; k++)
            if (memcmp(got[k], want, 3 * n * sizeof *want) && bad++ < 5)
                CHECK_MSG(0, "trial %u (%s): %u samples from N_z %lld step %lld, N_s %lld step %lld, "
                          "exps %d %d, recip %u, frac %u, colour %u: a sample differs", trial,
                          k == 2 ? "AVX-512" : k ? "AVX2" : "plain C", n, (long long)base,
                          (long long)fs.depth.step_c, (long long)fs.shade.origin,
                          (long long)fs.shade.step_c, fs.depth.exp, fs.shade.exp, p.recip_bits,
                          p.shade_frac_bits, p.colour_bits);
        for (unsigned k = 0; k < forms; k++)
            alb_vp_destroy(vp[k]);
    }
    CHECK_EQ(bad, 0);
    /* not vacuous: runs across powers of two, intensities saturated and 0 */
    printf("# %u samples, %u stretches, %u at full intensity, %u at none, %u between\n", samples,
           stretches, clamped, zeros, between);
    CHECK_MSG(samples > 100000 && stretches > 4000 && clamped > 1000 && zeros > 1000 &&
                  between > samples / 3,
              "%u samples, %u stretches, %u at full intensity, %u at none, %u between", samples,
              stretches, clamped, zeros, between);
}
