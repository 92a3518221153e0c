/* cmd_compare.c — `albatros compare A.exr B.exr`: how two frames differ —
 * pixels with a different face, colour error (max, mean, PSNR) — with a diff
 * image.  Exit status as cmp(1): 0 identical, 1 different, 2 trouble. */
#include "cli.h"
#include "commands.h"
#include "albatros/dump.h"
#include "albatros/exr.h"
#include "albatros/preview.h"
#include "albatros/json.h"
#include "../tools/accuracy.h"
#include "../tools/scenegen.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

typedef struct {
    const char *diff;
    bool json, help, exact;
} compare_args;

static int compare_opt(void *ctx, const char *name, const char *value)
{
    compare_args *a = ctx;
    if (strcmp(name, "diff") == 0)
        a->diff = value;
    else if (strcmp(name, "json") == 0)
        a->json = true;
    else if (strcmp(name, "exact") == 0)
        a->exact = true;
    else if (strcmp(name, "help") == 0)
        a->help = true;
    return 0;
}

/* The frames of files a and b: OpenEXR, or frame-store dumps of an RTL
 * bench (docs/cosim.md), which take their size and formats from the other
 * file when it is an EXR, else from the profile.  0, or 2 after saying why. */
static int load_pair(const char *const path[2], const alb_profile *p, alb_frame f[2])
{
    alb_diag d;
    alb_diag_init(&d, NULL);
    bool exr[2] = {alb_dump_is_exr(path[0]), alb_dump_is_exr(path[1])};
    for (int i = 0; i < 2; i++)
        if (exr[i] && alb_exr_read_frame(path[i], &f[i], &d))
            goto fail;
    for (int i = 0; i < 2; i++) {
        if (exr[i])
            continue;
        alb_frame shape;
        if (exr[1 - i]) {
            shape = f[1 - i];
        } else {
            memset(&shape, 0, sizeof shape);
            shape.width = p->width, shape.height = p->height;
            shape.colour_bits = p->colour_bits, shape.depth_bits = p->depth_bits;
            shape.aa_levels = p->aa_levels, shape.near = 1;
        }
        if (alb_dump_read(path[i], &shape, &f[i], &d))
            goto fail;
    }
    return 0;
fail:
    alb_diag_print(&d, stderr);
    alb_frame_free(&f[0]);
    alb_frame_free(&f[1]);
    return 2;
}

/* Compare the frames in files a and b (diff: the diff image, or NULL);
 * prints one line (or JSON object) prefixed with `label`, naming the first
 * pixel and channel that differ.  0 identical, 1 different, 2 trouble. */
static int compare_files(const char *pa, const char *pb, const char *diff, alb_json *json,
                         const char *label, const alb_profile *p, bool exact)
{
    alb_frame f[2];
    alb_diag d;
    alb_diag_init(&d, NULL);
    memset(f, 0, sizeof f);
    const char *path[2] = {pa, pb};
    if (load_pair(path, p, f))
        return 2;
    int rc = 2;
    if (f[0].width != f[1].width || f[0].height != f[1].height ||
        f[0].colour_bits != f[1].colour_bits) {
        fprintf(stderr, "albatros compare: %s is %ux%u (%u-bit colour), %s is %ux%u (%u-bit)\n",
                pa, f[0].width, f[0].height, f[0].colour_bits, pb, f[1].width, f[1].height,
                f[1].colour_bits);
        goto done;
    }
    alb_frame_diff r;
    alb_frame_compare(&f[0], &f[1], &r);
    size_t at = 0, ndiff = 0;
    const char *ch = "";
    uint64_t va = 0, vb = 0;
    /* every plane counts with --exact, and for a dump (an RTL's frame store
     * is held against the model's); else what is seen: face, colour,
     * coverage (a reference has no depth store or levels) */
    exact |= !alb_dump_is_exr(pa) || !alb_dump_is_exr(pb);
    if (!exact)
        for (size_t i = 0; i < (size_t)f[0].width * f[0].height; i++) {
            f[1].depth[i] = f[0].depth[i];
            f[1].level[i] = f[0].level[i];
        }
    if (f[0].cycles && f[1].cycles && !exact)
        memcpy(f[1].cycles, f[0].cycles, (size_t)f[0].width * f[0].height * sizeof *f[1].cycles);
    bool differ = alb_frame_first_diff(&f[0], &f[1], &at, &ch, &va, &vb, &ndiff);
    unsigned x = (unsigned)(at % f[0].width), y = (unsigned)(at / f[0].width);
    if (diff && alb_preview_write_diff(diff, &f[0], &f[1], NULL, NULL, &d)) {
        alb_diag_print(&d, stderr);
        goto done;
    }
    if (json) {
        alb_json_begin_object(json);
        alb_json_kv_uint(json, "pixels", r.pixels);
        alb_json_kv_uint(json, "face_diff", r.face_diff);
        alb_json_kv_uint(json, "colour_diff", r.colour_diff);
        alb_json_kv_uint(json, "coverage_diff", r.coverage_diff);
        alb_json_kv_uint(json, "max_error", r.max_error);
        alb_json_kv_fixed(json, "mean_error", r.mean_error, 6);
        /* identical frames: infinite, written as 999 dB */
        alb_json_kv_fixed(json, "psnr", isinf(r.psnr) ? 999.0 : r.psnr, 3);
        alb_json_kv_uint(json, "pixels_diff", ndiff);
        if (differ) {
            alb_json_key(json, "first_diff");
            alb_json_begin_object(json);
            alb_json_kv_uint(json, "x", x);
            alb_json_kv_uint(json, "y", y);
            alb_json_kv_string(json, "channel", ch);
            alb_json_kv_uint(json, "a", va);
            alb_json_kv_uint(json, "b", vb);
            alb_json_end_object(json);
        }
        alb_json_end_object(json);
    } else {
        printf("%s%zu pixels: %zu with a different face (%.4f%%), %zu with a different colour; "
               "colour error max %u, mean %.4f, PSNR %.2f dB\n",
               label, r.pixels, r.face_diff, 100.0 * (double)r.face_diff / (double)r.pixels,
               r.colour_diff, r.max_error, r.mean_error, r.psnr);
        if (differ)
            printf("%s%zu pixels differ; the first at pixel (%u, %u): %s %llu in %s, %llu in %s\n",
                   label, ndiff, x, y, ch, (unsigned long long)va, pa, (unsigned long long)vb, pb);
    }
    rc = differ ? 1 : 0;
done:
    alb_frame_free(&f[0]);
    alb_frame_free(&f[1]);
    return rc;
}

static bool exists(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0;
}

/* How many numbered frames "f.0000.exr", "f.0001.exr", ... stand for the
 * name f.exr, which render gives a run of several frames; 0 if none. */
static unsigned numbered_frames(const char *path)
{
    for (unsigned n = 0;; n++) {
        char *p = cli_frame_path(path, n, 2);
        bool there = p && exists(p);
        free(p);
        if (!there)
            return n;
    }
}

int cmd_compare(int argc, char **argv)
{
    static const char *const spec[] = {"diff=", "json", "exact", "help", NULL};
    compare_args a = {0};
    run_opts o;
    run_opts_init(&o);
    const char *pos[2];
    int npos;
    int parsed = cli_parse("compare", argc, argv, spec, compare_opt, &a, &o, pos, 2, &npos);
    if (parsed)
        return CLI_PARSE_EXIT(parsed);
    if (a.help || npos != 2) {
        printf("usage: albatros compare A B [--diff DIFF.png] [--json] [--exact]\n"
               "                        [--profile P --set K=V --size WxH]\n\n"
               "Compare two frames: pixels whose face differs, colour error in frame-store\n"
               "units (max, mean, PSNR), the first pixel and channel that differ, and a\n"
               "diff image (red: face differs, yellow: colour only, grey: equal).  Exit 0\n"
               "if identical, 1 if they differ, 2 on error.  What counts: face, colour and\n"
               "coverage; with --exact, and whenever A or B is a dump, every plane (depth\n"
               "store, level, per-pixel cycles too).\n\n"
               "A and B are OpenEXR frames or frame-store dumps of an RTL bench (128 bits\n"
               "a pixel, $writememh text or raw: docs/cosim.md); a dump takes its size and\n"
               "formats from the other file if that is an EXR, else from --profile,\n"
               "--set and --size.\n\n"
               "A name render numbered (f.exr for f.0000.exr, f.0001.exr, ...) compares\n"
               "every frame of the two runs, one line each (diff images numbered alike).\n");
        return a.help ? 0 : 2;
    }
    cli_input(pos[0]);
    cli_input(pos[1]);
    if (a.diff && cli_check_format("compare", "--diff", a.diff, "png"))
        return 2;
    alb_json j;
    alb_json_init(&j, stdout);
    /* two files, or two runs of numbered frames */
    if (exists(pos[0]) || exists(pos[1])) {
        if (a.diff && cli_output("compare", "--diff", a.diff))
            return 2;   /* compare's "trouble" */
        int rc = compare_files(pos[0], pos[1], a.diff, a.json ? &j : NULL, "", &o.prof, a.exact);
        if (a.json && rc != 2)
            alb_json_end_line(&j);
        return rc;
    }
    unsigned n[2] = {numbered_frames(pos[0]), numbered_frames(pos[1])};
    if (!n[0] || !n[1]) {
        const char *missing = n[0] ? pos[1] : pos[0];
        char *first = cli_frame_path(missing, 0, 2);
        fprintf(stderr, "albatros compare: cannot open %s (nor %s, the first of a numbered run)\n",
                missing, first ? first : "");
        free(first);
        return 2;
    }
    if (n[0] != n[1]) {
        fprintf(stderr, "albatros compare: %s has %u numbered frames, %s has %u\n", pos[0], n[0],
                pos[1], n[1]);
        return 2;
    }
    int rc = 0;
    for (unsigned k = 0; k < n[0]; k++)
        for (int i = 0; i < 2; i++) {
            char *p = cli_frame_path(pos[i], k, n[0]);
            cli_input(p);
            free(p);
        }
    for (unsigned k = 0; k < n[0] && a.diff; k++) {
        char *pd = cli_frame_path(a.diff, k, n[0]);
        int bad = !pd || cli_output("compare", "--diff", pd);
        free(pd);
        if (bad)
            return 2;
    }
    if (a.json) {
        alb_json_begin_object(&j);
        alb_json_key(&j, "frames");
        alb_json_begin_array(&j);
    }
    for (unsigned k = 0; k < n[0] && rc != 2; k++) {
        char *pa = cli_frame_path(pos[0], k, n[0]), *pb = cli_frame_path(pos[1], k, n[0]);
        char *pd = a.diff ? cli_frame_path(a.diff, k, n[0]) : NULL, label[32];
        snprintf(label, sizeof label, "frame %u: ", k);
        int one = !pa || !pb || (a.diff && !pd)
                      ? 2 : compare_files(pa, pb, pd, a.json ? &j : NULL, label, &o.prof, a.exact);
        free(pa);
        free(pb);
        free(pd);
        rc = one == 2 ? 2 : rc | one;
    }
    if (a.json) {
        alb_json_end_array(&j);
        alb_json_end_object(&j);
        alb_json_end_line(&j);
    }
    return rc;
}

/* ---- albatros accuracy ---- */

typedef struct {
    unsigned random, faces;
    unsigned long long seed;
    unsigned judged;          /* mask of the classes judged (tools/accuracy.h) */
    double min_judged;        /* percent of the pixels that must be judged */
    bool json, help;
} accuracy_args;

/* --exclude near-clamp,underflow: the classes whose differences the user
 * excuses (the others are excused always) */
static int parse_exclude(accuracy_args *a, const char *value)
{
    for (const char *p = value; *p;) {
        size_t len = strcspn(p, ",");
        bool ok = false;
        for (unsigned c = ACC_NEAR; c <= ACC_FAR; c++)
            if (len == strlen(accuracy_class_name(c)) && !strncmp(p, accuracy_class_name(c), len)) {
                a->judged &= ~(1u << c);
                ok = true;
            }
        if (!ok) {
            fprintf(stderr, "albatros accuracy: --exclude %s: '%.*s' is not near-clamp or "
                            "underflow (edge bands and depth ties are always excluded)\n",
                    value, (int)len, p);
            return -1;
        }
        p += len + (p[len] == ',');
    }
    return 0;
}

static int accuracy_opt(void *ctx, const char *name, const char *value)
{
    accuracy_args *a = ctx;
    char *end;
    if (strcmp(name, "random") == 0 || strcmp(name, "faces") == 0 || strcmp(name, "seed") == 0) {
        unsigned long long v = strtoull(value, &end, 10);
        if (end == value || *end || v > 100000000ull) {
            fprintf(stderr, "albatros accuracy: --%s %s: expected a count\n", name, value);
            return -1;
        }
        if (name[0] == 'r')
            a->random = (unsigned)v;
        else if (name[0] == 'f')
            a->faces = (unsigned)v;
        else
            a->seed = v;
    } else if (strcmp(name, "exclude") == 0) {
        return parse_exclude(a, value);
    } else if (strcmp(name, "min-judged") == 0) {
        double v = strtod(value, &end);
        if (end == value || *end || !(v >= 0 && v <= 100)) {
            fprintf(stderr, "albatros accuracy: --min-judged %s: expected a percentage 0..100\n",
                    value);
            return -1;
        }
        a->min_judged = v;
    } else if (strcmp(name, "json") == 0) {
        a->json = true;
    } else if (strcmp(name, "help") == 0) {
        a->help = true;
    }
    return 0;
}

/* A scene file loaded as render and reference load it: .scene or .obj (with
 * the camera options), screen-space scenes resolved for the profile. */
static int accuracy_scene_file(const char *path, const run_opts *o, accuracy *acc)
{
    alb_scene s;
    if (cli_load_scene(path, o, &s))
        return -1;
    alb_diag d;
    alb_diag_init(&d, NULL);
    int rc = accuracy_of_scene(&s, &o->prof, acc, &d);
    if (rc)
        alb_diag_print(&d, stderr);
    alb_scene_free(&s);
    return rc;
}

static const char *const class_words[ACC_NCLASSES] = {
    [ACC_CLEAR] = "clear of every bound",
    [ACC_EDGE] = "in an edge band (half an intercept LSB)",
    [ACC_NEAR] = "nearer than near (the depth store saturates)",
    [ACC_FAR] = "beyond near x 2^depth_bits (the store underflows)",
    [ACC_TIE] = "in a depth tie (within the depth forms' rounding)",
};

static double pct(size_t a, size_t b) { return b ? 100.0 * (double)a / (double)b : 0; }

/* Which input scene k of the run was: a file, or a seed of --random. */
static void scene_label(char *out, size_t len, unsigned k, const char *const *pos, int npos,
                        const accuracy_args *a)
{
    if (k < (unsigned)npos)
        snprintf(out, len, "%s", pos[k]);
    else
        snprintf(out, len, "random seed %llu", a->seed + (k - (unsigned)npos));
}

static void accuracy_report(const accuracy *acc, const accuracy_args *a, const alb_profile *p,
                            const char *const *pos, int npos)
{
    size_t judged = accuracy_judged(acc, a->judged), errors = accuracy_errors(acc, a->judged);
    if (a->json) {
        alb_json j;
        alb_json_init(&j, stdout);
        alb_json_begin_object(&j);
        alb_json_kv_uint(&j, "pixels", acc->pixels);
        alb_json_kv_uint(&j, "covered", acc->covered);
        alb_json_kv_uint(&j, "face_diff", acc->face_diff);
        alb_json_kv_uint(&j, "judged", judged);
        alb_json_kv_uint(&j, "errors", errors);
        alb_json_key(&j, "classes");
        alb_json_begin_object(&j);
        for (unsigned c = 0; c < ACC_NCLASSES; c++) {
            alb_json_key(&j, accuracy_class_name(c));
            alb_json_begin_object(&j);
            alb_json_kv_uint(&j, "pixels", acc->in_class[c]);
            alb_json_kv_uint(&j, "differ", acc->diff_in_class[c]);
            alb_json_kv_bool(&j, "judged", a->judged >> c & 1);
            alb_json_end_object(&j);
        }
        alb_json_end_object(&j);
        alb_json_end_object(&j);
        alb_json_end_line(&j);
        return;
    }
    printf("%zu pixels, %zu with a face: %zu with a different face (%.4f%%)\n", acc->pixels,
           acc->covered, acc->face_diff, pct(acc->face_diff, acc->pixels));
    for (unsigned c = 0; c < ACC_NCLASSES; c++) {
        printf("  %-10s %10zu pixels (%6.2f%%) %8zu differ  %-8s  %s", accuracy_class_name(c),
               acc->in_class[c], pct(acc->in_class[c], acc->pixels), acc->diff_in_class[c],
               a->judged >> c & 1 ? "judged" : "excluded", class_words[c]);
        if (a->judged >> c & 1 && acc->diff_in_class[c]) {
            size_t i = acc->first_diff[c];
            char label[300];
            scene_label(label, sizeof label, acc->first_scene[c], pos, npos, a);
            printf("; the first at pixel (%zu, %zu) of frame %u of %s", i % p->width,
                   i / p->width, acc->first_frame[c], label);
        }
        putchar('\n');
    }
    printf("judged %zu of %zu pixels (%.2f%%): %zu errors\n", judged, acc->pixels,
           pct(judged, acc->pixels), errors);
}

int cmd_accuracy(int argc, char **argv)
{
    static const char *const spec[] = {"random=", "faces=", "seed=", "exclude=", "min-judged=",
                                       "json", "help", NULL};
    accuracy_args a = {0, 12, 1, ACC_JUDGED, 90, false, false};
    run_opts o;
    run_opts_init(&o);
    const char *pos[64];
    int npos;
    int parsed = cli_parse("accuracy", argc, argv, spec, accuracy_opt, &a, &o, pos, 64, &npos);
    if (parsed)
        return CLI_PARSE_EXIT(parsed);
    if (a.help || (npos == 0 && a.random == 0)) {
        printf("usage: albatros accuracy [SCENE...] [--random N [--faces F] [--seed S]]\n"
               "                         [--exclude near-clamp,underflow] [--min-judged PCT]\n"
               "                         [--json] [--profile NAME] [--set KEY=VALUE]\n\n"
               "Render each scene (or N seeded random scenes of F faces) with the VP and the\n"
               "exact reference, and sort every pixel into one class (docs/reference.md):\n"
               "  clear       outside every bound below: the VP must give the reference's face\n"
               "  edge-band   within half an intercept LSB of an exact or an emitted edge\n"
               "  near-clamp  its nearest face is nearer than near: the depth store saturates\n"
               "              and faces there tie (the first drawn wins)\n"
               "  underflow   its nearest face is beyond near x 2^depth_bits: not drawn\n"
               "  depth-tie   its two nearest faces are within their depth rounding\n"
               "Edge bands and depth ties are the quantisation the format allows and are\n"
               "excluded.  Near clamp and underflow are limits of the depth store: a pixel\n"
               "drawn wrong there is wrong, and counts as an error unless --exclude names\n"
               "its class.  Exit 1 if any judged pixel differs, or if fewer than PCT percent\n"
               "of the pixels are judged (--min-judged, default 90): a measurement that\n"
               "cannot judge most of the picture does not pass.  A SCENE is read as render\n"
               "reads it: a .scene file, or a .obj file with the camera options of render.\n");
        return a.help ? 0 : 2;
    }
    if (cli_check_profile(&o.prof))
        return 2;
    if (o.prof.aa_levels) {
        fprintf(stderr, "albatros accuracy: compares single samples; use aa=0\n");
        return 2;
    }
    accuracy acc;
    accuracy_init(&acc);
    for (int i = 0; i < npos; i++)
        if (accuracy_scene_file(pos[i], &o, &acc))
            return 2;
    scenegen_params gp = scenegen_defaults();
    gp.faces = a.faces;
    for (unsigned i = 0; i < a.random; i++) {
        char *text = scenegen_random(a.seed + i, &gp), err[400];
        if (!text || accuracy_of_text(text, &o.prof, &acc, err, sizeof err)) {
            fprintf(stderr, "albatros accuracy: random seed %llu: %s\n", a.seed + i,
                    text ? err : "out of memory");
            free(text);
            return 2;
        }
        free(text);
        if (cli_isatty_stderr() && (i + 1) % 10 == 0)
            fprintf(stderr, "\r%u/%u scenes", i + 1, a.random);
    }
    if (cli_isatty_stderr() && a.random >= 10)
        fputc('\n', stderr);
    accuracy_report(&acc, &a, &o.prof, pos, npos);
    size_t judged = accuracy_judged(&acc, a.judged);
    int rc = accuracy_errors(&acc, a.judged) ? 1 : 0;
    if (pct(judged, acc.pixels) < a.min_judged) {
        fprintf(stderr, "albatros accuracy: FAIL: only %.2f%% of the pixels could be judged "
                        "(--min-judged %g): the result says little about the rest\n",
                pct(judged, acc.pixels), a.min_judged);
        rc = 1;
    }
    for (unsigned c = ACC_NEAR; c <= ACC_FAR; c++)
        if (!(a.judged >> c & 1) && acc.diff_in_class[c])
            fprintf(stderr, "albatros accuracy: warning: %zu differing pixels %s were excluded "
                            "(--exclude %s)\n", acc.diff_in_class[c], class_words[c],
                    accuracy_class_name(c));
    return rc;
}
