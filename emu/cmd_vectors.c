/* cmd_vectors.c — `albatros vectors check|bless DIR [NAME...]`: the golden
 * vectors of test-vectors/ (docs/golden-vectors.md).  Each folder holds a
 * scene, its options, a README line and the expected outputs; check compares
 * exact bits and names the first difference; bless rewrites the expected
 * outputs on purpose.  digest prints one number per expected frame, by which
 * check --digests compares frames without reading EXR: a build without
 * OpenEXR (ALB_NO_EXTERNAL, make crosscheck's musl build) checks every
 * vector so (docs/golden-vectors.md, "Another C library"). */
#include "cli.h"
#include "albatros/file.h"
#include "commands.h"
#include "albatros/file.h"
#include "albatros/link.h"
#include "albatros/exr.h"
#include "albatros/preview.h"
#include "albatros/sim.h"
#include "albatros/vp.h"

#include <dirent.h>
#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

typedef struct {
    char dir[512];
    char name[256];
} vector;

/* The digests of expected frames (check --digests FILE), as `vectors
 * digest` printed them: "NAME FRAME DIGEST" per line. */
typedef struct {
    char name[256];
    unsigned frame;
    uint32_t digest;
} frame_digest;

typedef struct {
    frame_digest *d;
    size_t n;
    const char *file;
} digest_table;

/* Where the messages about the vector being checked go: stderr, or with
 * --junit a buffer that is copied to stderr and into the report. */
static FILE *vlog;

/* A small text file (options, KNOWN-FAILURE) into buf; -1 if it cannot be
 * read or does not fit (never silently cut short). */
static int read_text(const char *path, char *buf, size_t len)
{
    const char *why;
    FILE *f = alb_file_open_input(path, true, &why);
    if (!f)
        return -1;
    size_t n = fread(buf, 1, len - 1, f);
    bool more = n == len - 1 && fgetc(f) != EOF;
    buf[n] = 0;
    int bad = ferror(f) || more || memchr(buf, 0, n);
    fclose(f);
    if (more)
        fprintf(stderr, "%s: longer than %zu bytes\n", path, len - 1);
    return bad ? -1 : 0;
}

/* A text into path through alb_out: under its name only once complete. */
static int write_text(const char *path, const char *text)
{
    alb_out out;
    alb_diag d;
    alb_diag_init(&d, NULL);
    FILE *f = NULL;
    if (alb_out_open(&out, path, 0, &d) || !(f = alb_out_stdio(&out, &d))) {
        alb_diag_print(&d, vlog);
        return -1;
    }
    fputs(text, f);
    if (alb_out_commit(&out, &d)) {
        alb_diag_print(&d, vlog);
        return -1;
    }
    return 0;
}

static bool exists(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0;
}

/* The scene file of a vector: scene.scene or scene.obj. */
static int scene_path(const vector *v, char *out, size_t len)
{
    snprintf(out, len, "%s/scene.scene", v->dir);
    if (exists(out))
        return 0;
    snprintf(out, len, "%s/scene.obj", v->dir);
    return exists(out) ? 0 : -1;
}

static int no_own_options(void *ctx, const char *name, const char *value)
{
    (void)ctx, (void)name, (void)value;
    return -1;
}

/* Run the vector's GP; its stream goes to out, its profile to *prof.
 * Non-zero after a message. */
static int run_vector(const vector *v, alb_ws_buf *out, alb_profile *prof)
{
    char path[600], opts[4096] = "";
    run_opts o;
    run_opts_init(&o);
    snprintf(path, sizeof path, "%s/options", v->dir);
    if (exists(path) && read_text(path, opts, sizeof opts)) {
        fprintf(vlog, "%s: cannot read\n", path);
        return -1;
    }
    char *argv[64];
    int argc = cli_split_words(opts, argv, 64);
    const char *pos[1];
    int npos;
    static const char *const none[] = {NULL};
    if (argc < 0 || cli_parse("vectors", argc, argv, none, no_own_options, NULL, &o, pos, 0, &npos)) {
        fprintf(vlog, "%s: bad options file\n", path);
        return -1;
    }
    if (cli_check_profile(&o.prof))
        return -1;
    *prof = o.prof;
    if (scene_path(v, path, sizeof path)) {
        fprintf(vlog, "%s: no scene.scene or scene.obj\n", v->dir);
        return -1;
    }
    alb_scene scene;
    if (cli_load_scene(path, &o, &scene))
        return -1;
    alb_diag d;
    alb_diag_init(&d, vlog);
    alb_gp *gp = NULL;
    alb_err e = alb_gp_create(&gp, &scene, &o.prof, &d);
    if (!e)
        e = alb_gp_run(gp, out, NULL, &d);
    alb_gp_destroy(gp);
    alb_scene_free(&scene);
    if (e) {
        alb_diag_print(&d, vlog);
        return -1;
    }
    return 0;
}

/* Compare streams; on a difference print the first differing word with its
 * field names on both sides.  Returns 0 if equal. */
static int compare_streams(const char *name, const uint32_t *want, size_t nw, const uint32_t *got,
                           size_t ng)
{
    size_t n = nw < ng ? nw : ng;
    size_t i = 0;
    while (i < n && want[i] == got[i])
        i++;
    if (i == n && nw == ng)
        return 0;
    char dw[200], dg[200];
    alb_ws_describe_at(want, nw, i, dw, sizeof dw);
    alb_ws_describe_at(got, ng, i, dg, sizeof dg);
    fprintf(vlog, "FAIL %s: stream differs at word %zu (byte offset %zu)\n", name, i, i * 4);
    if (i < nw)
        fprintf(vlog, "  expected %08x  %s\n", want[i], dw);
    else
        fprintf(vlog, "  expected end of stream (%zu words)\n", nw);
    if (i < ng)
        fprintf(vlog, "  got      %08x  %s\n", got[i], dg);
    else
        fprintf(vlog, "  got      end of stream (%zu words)\n", ng);
    size_t diff = 0;
    for (size_t k = 0; k < n; k++)
        diff += want[k] != got[k];
    fprintf(vlog, "  %zu of %zu words differ%s\n", diff + (nw > ng ? nw - ng : ng - nw),
            nw > ng ? nw : ng, nw != ng ? " (lengths differ)" : "");
    return 1;
}

/* ---- frames ---- */

typedef struct {
    const digest_table *digests;   /* check: compare frames by these, not EXR */
    const vector *v;
    const alb_profile *prof;
    const char *scene;       /* the vector's scene file (EXR provenance) */
    bool bless;
    const char *diff_dir;
    unsigned frames;
    int failed;
    char *counters;          /* bless: expected.cycles being written */
    size_t clen, ccap;
    char **want;             /* check: the lines of expected.cycles */
    unsigned nwant;
    char *summary;           /* bless: expected.frames being written */
    size_t slen, scap;
    char **want_sum;         /* check: the lines of expected.frames */
    unsigned nwant_sum;
} frames_ctx;

/* A line for a text being built (expected.cycles, expected.frames); -1 if
 * out of memory. */
static int append_line(char **buf, size_t *len, size_t *cap, const char *line)
{
    size_t need = *len + strlen(line) + 2;
    if (need > *cap) {
        char *nb = realloc(*buf, 2 * need);
        if (!nb)
            return -1;
        *buf = nb;
        *cap = 2 * need;
    }
    *len += (size_t)sprintf(*buf + *len, "%s\n", line);
    return 0;
}

/* One line of expected.frames (docs/golden-vectors.md): the frame's number,
 * cycle count and CRC, as a testbench reads them with $fscanf("%d %d %h"). */
static void summary_line(char *out, size_t len, const alb_frame *f, const alb_sim_counters *c)
{
    snprintf(out, len, "%u %llu %08x", f->number, (unsigned long long)c->cycles,
             alb_link_frame_crc(f->rgb, (size_t)f->width * f->height));
}

/* One line of expected.cycles: the frame's counters as key=value. */
static void counters_line(char *out, size_t len, unsigned frame, const alb_sim_counters *c)
{
    int n = snprintf(out, len, "frame=%u", frame);
#define KV(field) n += snprintf(out + n, len - (size_t)n, " " #field "=%llu", \
                                (unsigned long long)c->field);
    ALB_SIM_COUNTER_FIELDS(KV)
#undef KV
}

/* The first key whose value differs between two counter lines. */
static void first_counter_diff(const char *want, const char *got, char *out, size_t len)
{
    const char *w = want, *g = got;
    while (*w && *g) {
        size_t wl = strcspn(w, " "), gl = strcspn(g, " ");
        if (wl != gl || strncmp(w, g, wl)) {
            snprintf(out, len, "expected %.*s, got %.*s", (int)wl, w, (int)gl, g);
            return;
        }
        w += wl + (w[wl] == ' ');
        g += gl + (g[gl] == ' ');
    }
    snprintf(out, len, "lines differ in length");
}

static void frame_path(const vector *v, unsigned k, char *out, size_t len)
{
    snprintf(out, len, "%s/expected.%04u.exr", v->dir, k);
}

/* check --digests: the frame against the digest of its expected EXR */
static int check_digest(frames_ctx *c, const alb_frame *f, unsigned k)
{
    const digest_table *t = c->digests;
    for (size_t i = 0; i < t->n; i++)
        if (t->d[i].frame == k && !strcmp(t->d[i].name, c->v->name)) {
            uint32_t got = alb_frame_digest(f);
            if (got == t->d[i].digest)
                return 0;
            fprintf(vlog, "FAIL %s: frame %u differs: digest %08x, expected %08x (%s; the "
                          "full build's check names the pixel)\n", c->v->name, f->number, got,
                    t->d[i].digest, t->file);
            return 1;
        }
    fprintf(vlog, "FAIL %s: %s has no digest for frame %u\n", c->v->name, t->file, k);
    return 1;
}

#ifdef ALB_NO_EXTERNAL
static int check_frame(frames_ctx *c, const alb_frame *f, const char *path)
{
    (void)path;
    return check_digest(c, f, c->frames - 1);
}
#else
static int check_frame(frames_ctx *c, const alb_frame *f, const char *path)
{
    if (c->digests)
        return check_digest(c, f, c->frames - 1);
    alb_frame want;
    alb_diag d;
    alb_diag_init(&d, NULL);
    if (alb_exr_read_frame(path, &want, &d)) {
        alb_diag_print(&d, vlog);
        return 1;
    }
    int rc = 0;
    size_t at = 0, count;
    const char *ch;
    uint64_t va, vb;
    if (want.width != f->width || want.height != f->height) {
        fprintf(vlog, "FAIL %s: frame %u is %ux%u, expected %ux%u\n", c->v->name, f->number,
                f->width, f->height, want.width, want.height);
        rc = 1;
    } else if (alb_frame_first_diff(&want, f, &at, &ch, &va, &vb, &count)) {
        char diff[700];
        snprintf(diff, sizeof diff, "%s/%s.%04u.png", c->diff_dir, c->v->name, f->number);
        mkdir(c->diff_dir, 0777);
        bool wrote = alb_preview_write_diff(diff, &want, f, NULL, NULL, &d) == ALB_OK;
        fprintf(vlog, "FAIL %s: frame %u differs at pixel (%zu, %zu): %s expected %llu, got %llu\n"
                        "  %zu pixels differ%s%s\n", c->v->name, f->number, at % f->width,
                at / f->width, ch, (unsigned long long)va, (unsigned long long)vb, count,
                wrote ? "; diff image " : "", wrote ? diff : "");
        rc = 1;
    }
    alb_frame_free(&want);
    return rc;
}
#endif

static void check_counters(frames_ctx *c, const alb_frame *f, const char *line)
{
    unsigned k = c->frames - 1;
    if (k >= c->nwant) {
        fprintf(vlog, "FAIL %s: expected.cycles has no line for frame %u\n", c->v->name, k);
        c->failed = 1;
    } else if (strcmp(c->want[k], line)) {
        char what[200];
        first_counter_diff(c->want[k], line, what, sizeof what);
        fprintf(vlog, "FAIL %s: frame %u counters differ: %s\n", c->v->name, f->number, what);
        c->failed = 1;
    }
}

static int frame_sink(void *ctx, const alb_frame *f, const alb_vp_stats *st, const alb_sim_counters *sc)
{
    (void)st;
    frames_ctx *c = ctx;
    char path[600], line[600];
    frame_path(c->v, c->frames++, path, sizeof path);
    counters_line(line, sizeof line, f->number, sc);
    char sum[100];
    summary_line(sum, sizeof sum, f, sc);
    if (c->bless) {
        if (append_line(&c->counters, &c->clen, &c->ccap, line) ||
            append_line(&c->summary, &c->slen, &c->scap, sum))
            return -1;
    } else {
        check_counters(c, f, line);
        unsigned k = c->frames - 1;
        if (c->want_sum && (k >= c->nwant_sum || strcmp(c->want_sum[k], sum))) {
            fprintf(vlog, "FAIL %s: expected.frames line %u: expected '%s', got '%s'\n",
                    c->v->name, k + 1, k < c->nwant_sum ? c->want_sum[k] : "(none)", sum);
            c->failed = 1;
        }
    }
    if (c->bless) {
#ifdef ALB_NO_EXTERNAL
        c->failed = 1;   /* refused before: cmd_vectors */
#else
        alb_diag d;
        alb_diag_init(&d, NULL);
        /* provenance without the folder: a vector blessed anywhere gives the
         * same bytes (docs/golden-vectors.md) */
        char software[32];
        snprintf(software, sizeof software, "albatros %s", ALBATROS_VERSION);
        alb_exr_options eo = {1, software, c->prof->name, "timed",
                              strrchr(c->scene, '/') ? strrchr(c->scene, '/') + 1 : c->scene};
        if (alb_exr_write(path, f, &eo, &d)) {
            alb_diag_print(&d, vlog);
            c->failed = 1;
        }
#endif
    } else if (!exists(path)) {
        fprintf(vlog, "FAIL %s: no %s (run 'make bless' to create it)\n", c->v->name, path);
        c->failed = 1;
    } else {
        c->failed |= check_frame(c, f, path);
    }
    return 0;
}

/* The lines of a text file, in a malloc'd array of pointers into *text. */
static char **read_lines(const char *path, char **text, unsigned *n)
{
    *n = 0;
    *text = NULL;
    FILE *f = fopen(path, "r");
    if (!f)
        return NULL;
    char *buf;
    size_t len;
    int rc = alb_file_read_all(f, &buf, &len);
    fclose(f);
    if (rc)
        return NULL;
    char **lines = malloc((len / 2 + 2) * sizeof *lines);
    if (!lines) {
        free(buf);
        return NULL;
    }
    for (char *p = buf; *p;) {
        lines[(*n)++] = p;
        char *nl = strchr(p, '\n');
        if (!nl)
            break;
        *nl = 0;
        p = nl + 1;
    }
    *text = buf;
    return lines;
}

/* Render the stream through the timed model (pixels, vp.cycles and the
 * counters, equal to the cycle model's by test); check or bless them. */
static int vector_frames(const vector *v, const alb_profile *prof, const alb_ws_buf *stream, bool bless,
                         const char *diff_dir, const digest_table *digests)
{
    char scene[600];
    if (scene_path(v, scene, sizeof scene))
        snprintf(scene, sizeof scene, "scene");
    frames_ctx c = {.digests = digests, .v = v, .prof = prof, .scene = scene, .bless = bless,
                    .diff_dir = diff_dir};
    char cpath[600], spath[600], *ctext = NULL, *stext = NULL;
    snprintf(cpath, sizeof cpath, "%s/expected.cycles", v->dir);
    snprintf(spath, sizeof spath, "%s/expected.frames", v->dir);
    if (!bless) {
        c.want = read_lines(cpath, &ctext, &c.nwant);
        c.want_sum = read_lines(spath, &stext, &c.nwant_sum);
        if (!c.want || !c.want_sum) {
            fprintf(vlog, "FAIL %s: no %s (run 'make bless' to create it)\n", v->name,
                    c.want ? spath : cpath);
            c.failed = 1;
        }
    }
    alb_diag d;
    alb_diag_init(&d, NULL);
    alb_sim_options opt = {.fid = ALB_FIDELITY_TIMED, .threads = 1};
    alb_err e = alb_sim_run(prof, stream->w, stream->n, v->name, &opt, frame_sink, &c, &d);
    free(c.want);
    free(ctext);
    free(c.want_sum);
    free(stext);
    if (e) {
        alb_diag_print(&d, vlog);
        free(c.counters);
        free(c.summary);
        return 1;
    }
    if (!bless && c.want && c.nwant != c.frames) {
        fprintf(vlog, "FAIL %s: expected.cycles has %u lines, the run %u frames\n", v->name,
                c.nwant, c.frames);
        c.failed = 1;
    }
    if (!bless && c.want_sum && c.nwant_sum != c.frames) {
        fprintf(vlog, "FAIL %s: expected.frames has %u lines, the run %u frames\n", v->name,
                c.nwant_sum, c.frames);
        c.failed = 1;
    }
    if (bless) {
        const char *paths[2] = {cpath, spath}, *texts[2] = {c.counters, c.summary};
        for (int i = 0; i < 2; i++)
            if (write_text(paths[i], texts[i] ? texts[i] : ""))
                c.failed = 1;
        free(c.counters);
        free(c.summary);
    }
    /* no expected frame may be left over from a longer run */
    char path[600];
    for (unsigned k = c.frames;; k++) {
        frame_path(v, k, path, sizeof path);
        if (!exists(path))
            break;
        if (bless) {
            remove(path);
        } else {
            fprintf(vlog, "FAIL %s: %s expected, but the run has %u frames\n", v->name, path,
                    c.frames);
            c.failed = 1;
        }
    }
    return c.failed;
}

/* 0 pass, 1 fail, 2 known failure. */
static int check_vector(const vector *v, const char *diff_dir, const digest_table *digests)
{
    alb_ws_buf got;
    alb_ws_buf_init(&got);
    alb_profile prof;
    char path[600], known[512] = "";
    snprintf(path, sizeof path, "%s/KNOWN-FAILURE", v->dir);
    bool is_known = exists(path) && read_text(path, known, sizeof known) == 0;
    int rc = run_vector(v, &got, &prof);
    if (!rc) {
        uint32_t *want;
        size_t nw;
        alb_diag d;
        alb_diag_init(&d, NULL);
        snprintf(path, sizeof path, "%s/expected.stream", v->dir);
        if (alb_ws_read_file(path, &want, &nw, &d)) {
            alb_diag_print(&d, vlog);
            fprintf(vlog, "  (run 'make bless' to create the expected outputs)\n");
            rc = 1;
        } else {
            rc = compare_streams(v->name, want, nw, got.w, got.n);
            free(want);
        }
        /* the frames are checked from the stream just made, so a GP
         * difference does not hide a VP one */
        rc |= vector_frames(v, &prof, &got, false, diff_dir, digests);
    } else {
        fprintf(vlog, "FAIL %s: could not run\n", v->name);
        rc = 1;
    }
    alb_ws_buf_free(&got);
    if (is_known) {
        if (rc) {
            printf("known failure %s: %s", v->name, known);
            return 2;
        }
        fprintf(vlog, "FAIL %s: marked KNOWN-FAILURE but passes; remove the marker\n", v->name);
        return 1;
    }
    if (!rc)
        printf("ok %s\n", v->name);
    return rc;
}

#ifndef ALB_NO_EXTERNAL
static int bless_vector(const vector *v)
{
    alb_ws_buf got;
    alb_ws_buf_init(&got);
    alb_profile prof;
    if (run_vector(v, &got, &prof) || vector_frames(v, &prof, &got, true, NULL, NULL)) {
        alb_ws_buf_free(&got);
        return 1;
    }
    char path[600];
    snprintf(path, sizeof path, "%s/expected.stream", v->dir);
    uint32_t *old = NULL;
    size_t nold = 0;
    alb_diag d;
    alb_diag_init(&d, NULL);
    bool had = alb_ws_read_file(path, &old, &nold, &d) == ALB_OK;
    bool same = had && nold == got.n && !memcmp(old, got.w, nold * 4);
    free(old);
    int rc = 0;
    if (!same && alb_ws_write_file(path, got.w, got.n, &d)) {
        alb_diag_print(&d, vlog);
        rc = 1;
    }
    /* the readable twin, so reviews of a re-bless show field-level diffs */
    snprintf(path, sizeof path, "%s/expected.hex", v->dir);
    alb_out hex;
    FILE *hf = NULL;
    alb_err he = alb_out_open(&hex, path, 0, &d);
    if (!he && !(hf = alb_out_stdio(&hex, &d)))
        he = ALB_ERR_IO;
    if (!he && (he = alb_ws_dump(hf, got.w, got.n, "expected.stream", &d)))
        alb_out_abort(&hex);
    else if (!he)
        he = alb_out_commit(&hex, &d);
    if (he) {
        alb_diag_print(&d, vlog);
        rc = 1;
    }
    printf("%s %s (%zu words)\n", same ? "unchanged" : had ? "REBLESSED" : "created", v->name, got.n);
    alb_ws_buf_free(&got);
    return rc;
}
#endif

static int cmp_names(const void *a, const void *b)
{
    return strcmp(((const vector *)a)->name, ((const vector *)b)->name);
}

/* The vectors of dir (every sub-folder with a README), sorted by name. */
static vector *list_vectors(const char *dir, size_t *count)
{
    DIR *dp = opendir(dir);
    if (!dp) {
        fprintf(stderr, "albatros vectors: %s: %s\n", dir, strerror(errno));
        return NULL;
    }
    vector *v = NULL;
    size_t n = 0;
    struct dirent *de;
    while ((de = readdir(dp))) {
        if (de->d_name[0] == '.')
            continue;
        vector one;
        /* every path below is the folder's and a short file name: a folder
         * name too long for them is refused, never cut short */
        if (snprintf(one.dir, sizeof one.dir, "%s/%s", dir, de->d_name) >= (int)sizeof one.dir ||
            snprintf(one.name, sizeof one.name, "%s", de->d_name) >= (int)sizeof one.name) {
            fprintf(stderr, "albatros vectors: %s/%s: path longer than %zu characters\n", dir,
                    de->d_name, sizeof one.dir - 1);
            continue;
        }
        char readme[600];
        snprintf(readme, sizeof readme, "%s/README", one.dir);
        if (!exists(readme))
            continue;
        vector *nv = realloc(v, (n + 1) * sizeof *nv);
        if (!nv)
            break;
        v = nv;
        v[n++] = one;
    }
    closedir(dp);
    if (v)
        qsort(v, n, sizeof *v, cmp_names);
    *count = n;
    return v;
}

typedef struct {
    const char *diff_dir;
    bool diff_dir_given, help;
    const char *junit, *digests;
} vectors_args;

static int vectors_opt(void *ctx, const char *name, const char *value)
{
    vectors_args *a = ctx;
    if (strcmp(name, "diff-dir") == 0) {
        a->diff_dir = value;
        a->diff_dir_given = true;
    } else if (strcmp(name, "junit") == 0) {
        a->junit = value;
    } else if (strcmp(name, "digests") == 0) {
        a->digests = value;
    } else {
        a->help = true;
    }
    return 0;
}

static void vectors_usage(FILE *f)
{
    fprintf(f, "usage: albatros vectors check [--diff-dir DIR] [--junit FILE] [--digests FILE]\n"
               "                              VECTORS [NAME...]\n"
               "       albatros vectors bless VECTORS [NAME...]\n"
               "       albatros vectors digest VECTORS [NAME...]\n\n"
               "check: run every golden vector in VECTORS (or the NAMEd ones) and compare its\n"
               "       word stream and frames bit for bit; the first difference is named\n"
               "       (word and field, pixel and channel), a diff image goes to DIR\n"
               "       (default ./vector-diffs); exit 1 on any.  --junit FILE: a JUnit XML\n"
               "       report, one test case per vector, a failure carrying the first\n"
               "       difference (what Jenkins and GitLab read).  --digests FILE: compare\n"
               "       the frames by the digests in FILE instead of the EXR files (a build\n"
               "       without OpenEXR can only do so).\n"
               "bless: regenerate the expected outputs (a deliberate act: say why in the\n"
               "       commit message).\n"
               "digest: print NAME FRAME DIGEST for each expected frame (alb_frame_digest of\n"
               "       its exact planes), for check --digests.\n");
}

/* ---- the JUnit report ---- */

/* What one vector's check said. */
typedef struct {
    const char *name;
    int rc;                  /* 0 pass, 1 fail, 2 known failure */
    char *text;              /* its messages */
} vector_result;

/* Text as XML character data or attribute value: the five specials
 * escaped, and characters XML 1.0 cannot hold at all as U+FFFD. */
static void xml_text(FILE *f, const char *s, size_t n)
{
    for (size_t i = 0; i < n; i++) {
        unsigned char c = (unsigned char)s[i];
        if (c == '&')
            fputs("&amp;", f);
        else if (c == '<')
            fputs("&lt;", f);
        else if (c == '>')
            fputs("&gt;", f);
        else if (c == '"')
            fputs("&quot;", f);
        else if (c == '\'')
            fputs("&apos;", f);
        else if (c < 0x20 && c != '\t' && c != '\n' && c != '\r')
            fputs("\xef\xbf\xbd", f);
        else
            fputc(c, f);
    }
}

/* The first FAIL line without its "FAIL name: ". */
static void first_failure(const vector_result *r, const char **s, size_t *n)
{
    const char *t = r->text ? r->text : "";
    const char *line = strstr(t, "FAIL ");
    if (!line)
        line = t;
    const char *colon = strstr(line, ": ");
    if (colon && line == strstr(t, "FAIL "))
        line = colon + 2;
    *s = line;
    *n = strcspn(line, "\n");
}

/* One <testcase> per vector, in the form Jenkins and GitLab read; no times
 * (they would make two runs' reports differ). */
static int write_junit(const char *path, const vector_result *r, size_t n)
{
    alb_out out;
    alb_diag d;
    alb_diag_init(&d, NULL);
    FILE *f = NULL;
    if (alb_out_open(&out, path, 0, &d) || !(f = alb_out_stdio(&out, &d))) {
        fprintf(stderr, "albatros vectors: --junit ");
        alb_diag_print(&d, stderr);
        return -1;
    }
    unsigned failures = 0, skipped = 0;
    for (size_t i = 0; i < n; i++)
        failures += r[i].rc == 1, skipped += r[i].rc == 2;
    fprintf(f, "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
               "<testsuites name=\"albatros vectors\" tests=\"%zu\" failures=\"%u\" "
               "errors=\"0\" skipped=\"%u\">\n"
               "  <testsuite name=\"vectors\" tests=\"%zu\" failures=\"%u\" errors=\"0\" "
               "skipped=\"%u\">\n", n, failures, skipped, n, failures, skipped);
    for (size_t i = 0; i < n; i++) {
        fputs("    <testcase classname=\"vectors\" name=\"", f);
        xml_text(f, r[i].name, strlen(r[i].name));
        if (r[i].rc == 0) {
            fputs("\"/>\n", f);
            continue;
        }
        const char *msg;
        size_t len;
        first_failure(&r[i], &msg, &len);
        fprintf(f, "\">\n      <%s message=\"", r[i].rc == 1 ? "failure" : "skipped");
        xml_text(f, msg, len);
        if (r[i].rc == 1) {
            fputs("\" type=\"mismatch\">", f);
            xml_text(f, r[i].text ? r[i].text : "", r[i].text ? strlen(r[i].text) : 0);
            fputs("</failure>\n", f);
        } else {
            fputs("\"/>\n", f);
        }
        fputs("    </testcase>\n", f);
    }
    fputs("  </testsuite>\n</testsuites>\n", f);
    if (alb_out_commit(&out, &d)) {
        fprintf(stderr, "albatros vectors: --junit ");
        alb_diag_print(&d, stderr);
        return -1;
    }
    return 0;
}

/* Check one vector with its messages in a buffer as well as on stderr. */
static int check_captured(const vector *v, const char *diff_dir, const digest_table *digests,
                          vector_result *r)
{
    size_t len = 0;
    r->name = v->name;
    r->text = NULL;
    vlog = open_memstream(&r->text, &len);
    if (!vlog) {
        vlog = stderr;
        return r->rc = check_vector(v, diff_dir, digests);
    }
    /* the known-failure line goes to stdout; keep it for the report too */
    r->rc = check_vector(v, diff_dir, digests);
    fclose(vlog);
    vlog = stderr;
    if (r->text)
        fputs(r->text, stderr);
    if (r->rc == 2) {
        char path[600], known[512] = "";
        snprintf(path, sizeof path, "%s/KNOWN-FAILURE", v->dir);
        read_text(path, known, sizeof known);
        free(r->text);
        size_t n = strlen(known) + 32;
        r->text = malloc(n);
        if (r->text)
            snprintf(r->text, n, "known failure: %s", known);
    }
    return r->rc;
}

/* Read a digest file; 0, or -1 after a message naming the line. */
static int load_digests(const char *path, digest_table *t)
{
    char *text;
    unsigned n;
    char **lines = read_lines(path, &text, &n);
    t->d = NULL;
    t->n = 0;
    t->file = path;
    if (!lines) {
        fprintf(stderr, "albatros vectors: --digests %s: cannot read: %s\n", path, strerror(errno));
        return -1;
    }
    t->d = malloc((n ? n : 1) * sizeof *t->d);
    int rc = t->d ? 0 : -1;
    for (unsigned i = 0; i < n && !rc; i++) {
        frame_digest *e = &t->d[t->n];
        char tail;
        if (!lines[i][0])
            continue;
        if (sscanf(lines[i], "%255s %u %8x %c", e->name, &e->frame, &e->digest, &tail) != 3) {
            fprintf(stderr, "%s:%u: expected NAME FRAME DIGEST (hexadecimal), as 'albatros vectors "
                            "digest' writes\n", path, i + 1);
            rc = -1;
        }
        t->n++;
    }
    free(lines);
    free(text);
    if (rc) {
        free(t->d);
        t->d = NULL;
    }
    return rc;
}

#ifndef ALB_NO_EXTERNAL
/* vectors digest: one line per expected frame of each vector */
static int vector_digests(const vector *v)
{
    char path[600];
    int rc = 0;
    for (unsigned k = 0;; k++) {
        frame_path(v, k, path, sizeof path);
        if (!exists(path))
            break;
        alb_frame f;
        alb_diag d;
        alb_diag_init(&d, NULL);
        if (alb_exr_read_frame(path, &f, &d)) {
            alb_diag_print(&d, stderr);
            rc = 1;
            continue;
        }
        printf("%s %u %08x\n", v->name, k, alb_frame_digest(&f));
        alb_frame_free(&f);
    }
    return rc;
}
#endif

enum { ACT_CHECK, ACT_BLESS, ACT_DIGEST };

/* Check, bless or digest the vectors of dir named in names[] (all if n == 0). */
static int vectors_run(int act, const char *dir, const char *const *names, int nnames,
                       const char *diff_dir, const char *junit, const digest_table *digests)
{
    size_t n;
    vector *v = list_vectors(dir, &n);
    if (!v) {
        printf("0 passed, 1 failed\n");
        return 1;
    }
    unsigned passed = 0, failed = 0, known = 0, selected = 0;
    vector_result *results = junit && act == ACT_CHECK ? calloc(n ? n : 1, sizeof *results) : NULL;
    if (junit && act == ACT_CHECK && !results) {
        fprintf(stderr, "albatros vectors: out of memory\n");
        free(v);
        return 1;
    }
    for (size_t i = 0; i < n; i++) {
        bool want = nnames == 0;
        for (int k = 0; k < nnames; k++)
            want |= strcmp(names[k], v[i].name) == 0;
        if (!want)
            continue;
#ifdef ALB_NO_EXTERNAL
        int rc = act != ACT_CHECK ? 1
                 : results        ? check_captured(&v[i], diff_dir, digests, &results[selected])
                                  : check_vector(&v[i], diff_dir, digests);
#else
        int rc = act == ACT_BLESS    ? bless_vector(&v[i])
                 : act == ACT_DIGEST ? vector_digests(&v[i])
                 : results           ? check_captured(&v[i], diff_dir, digests, &results[selected])
                                     : check_vector(&v[i], diff_dir, digests);
#endif
        selected++;
        if (rc == 0)
            passed++;
        else if (rc == 2)
            known++;
        else
            failed++;
    }
    for (int k = 0; k < nnames; k++) {
        bool found = false;
        for (size_t i = 0; i < n; i++)
            found |= strcmp(names[k], v[i].name) == 0;
        if (!found) {
            fprintf(stderr, "albatros vectors: no vector named '%s' in %s\n", names[k], dir);
            failed++;
        }
    }
    if (results && write_junit(junit, results, selected))
        failed++;
    for (size_t i = 0; results && i < selected; i++)
        free(results[i].text);
    free(results);
    free(v);
    if (act == ACT_DIGEST) {
        if (failed)
            fprintf(stderr, "albatros vectors digest: %u vectors failed\n", failed);
        return failed || selected == 0 ? 1 : 0;
    }
    if (known)
        printf("%u known failures\n", known);
    printf("%u passed, %u failed\n", passed, failed);
    return failed || selected == 0 ? 1 : 0;
}

int cmd_vectors(int argc, char **argv)
{
    static const char *const spec[] = {"diff-dir=", "junit=", "digests=", "help", NULL};
    vectors_args a = {"vector-diffs", false, false, NULL, NULL};
    vlog = stderr;
    const char **pos = malloc(((size_t)argc + 1) * sizeof *pos);
    int npos, rc = 2;
    if (!pos) {
        fprintf(stderr, "albatros vectors: out of memory\n");
        return 1;
    }
    int parsed = cli_parse("vectors", argc, argv, spec, vectors_opt, &a, NULL, pos, argc, &npos);
    if (parsed) {
        rc = parsed > 0 ? 0 : rc;
        goto done;
    }
    if (a.help) {
        vectors_usage(stdout);
        rc = 0;
        goto done;
    }
    int act = npos < 1                        ? -1
              : strcmp(pos[0], "check") == 0  ? ACT_CHECK
              : strcmp(pos[0], "bless") == 0  ? ACT_BLESS
              : strcmp(pos[0], "digest") == 0 ? ACT_DIGEST
                                              : -1;
    if (npos < 2 || act < 0) {
        if (npos >= 1 && act < 0)
            fprintf(stderr, "albatros vectors: unknown action '%s'\n\n", pos[0]);
        vectors_usage(stderr);
        goto done;
    }
    if (act != ACT_CHECK && a.diff_dir_given) {
        fprintf(stderr, "albatros vectors: --diff-dir is for check only (bless writes no diff "
                        "images)\n");
        goto done;
    }
    if (act != ACT_CHECK && a.junit) {
        fprintf(stderr, "albatros vectors: --junit reports a check (bless compares nothing)\n");
        goto done;
    }
    if (act != ACT_CHECK && a.digests) {
        fprintf(stderr, "albatros vectors: --digests is for check only\n");
        goto done;
    }
#ifdef ALB_NO_EXTERNAL
    if (act != ACT_CHECK || !a.digests) {
        fprintf(stderr, "albatros vectors: this albatros was built with ALB_NO_EXTERNAL, without "
                        "OpenEXR: it can only check, with --digests FILE from a full build's "
                        "'albatros vectors digest'\n");
        goto done;
    }
#endif
    digest_table dt = {NULL, 0, NULL};
    if (a.digests && load_digests(a.digests, &dt))
        goto done;
    rc = vectors_run(act, pos[1], pos + 2, npos - 2, a.diff_dir, a.junit,
                     a.digests ? &dt : NULL);
    free(dt.d);
done:
    free(pos);
    return rc;
}
