/* sweep.c — where each method breaks, and what accuracy costs: every classic
 * method and several Albatros configurations over the stress families,
 * measured against the exact reference (pixels whose face differs, colour
 * PSNR, host time), as CSV; tables and charts from the CSVs (gnuplot). */
#include "sweep.h"
#include "methods.h"
#include "ref.h"
#include "scenegen.h"
#include "stress.h"
#include "albatros/sim.h"
#include "albatros/gp.h"

#include "albatros/file.h"

#include <errno.h>
#include <spawn.h>
#include <sys/wait.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

/* ---- families and configurations ---- */

static const struct {
    const char *family;
    double severity[SWEEP_SEVERITIES];
    const char *unit;        /* what the severity measures (tools/stress.h): the x axis */
} families[] = {
    {"sliver", {10, 1, 0.1, 0.01}, "tip angle, degrees"},
    {"crossing-z0", {0, 0.3, 0.7, 0.95}, "fraction of the face behind Z = 0"},
    {"far", {10, 1e3, 1e4, 1e6}, "distance of the front face (gap 1)"},
    {"texture-far", {10, 1e4, 1e8, 1e12}, "distance from the texture origin, periods"},
    {"interpenetrating", {45, 5, 0.5, 0.01}, "angle between the planes, degrees"},
    {"cyclic", {0.05, 0.1, 0.2, 0.4}, "bar width / distance between crossings"},
    {"degenerate", {0.1, 1e-3, 1e-6, 1e-9}, "triangle height / base"},
    {"tjunction", {2, 8, 32, 64}, "rows of T-junctions"},
    {"deep", {1, 8, 32, 64}, "depth complexity at the centre"},
    {"coords", {0, 10, 25, 40}, "log10 of the coordinate scale"},
};
#define NFAMILIES (sizeof families / sizeof families[0])

unsigned sweep_family_count(void) { return NFAMILIES; }
const char *sweep_family(unsigned i) { return i < NFAMILIES ? families[i].family : NULL; }
const double *sweep_severities(unsigned i) { return i < NFAMILIES ? families[i].severity : NULL; }

/* An Albatros configuration: the VP with profile changes.  Two narrower
 * edge formats, two narrower depth stores and two anti-aliasing levels, so
 * that each chart shows where a width starts to matter, not only that it
 * does (docs/stability.md). */
static const struct {
    const char *name;
    const char *sets;        /* alb_profile_set assignments, space separated */
    int edge_delta;          /* added to edge_frac_bits */
} vp_configs[] = {
    {"vp", "", 0},
    {"vp-bound-none", "bound=none", 0},
    {"vp-bound-box", "bound=box", 0},
    {"vp-bound-bisector", "bound=bisector", 0},
    {"vp-edge-2", "", -2},
    {"vp-edge-4", "", -4},
    {"vp-depth20", "depth_bits=20", 0},
    {"vp-depth16", "depth_bits=16", 0},
    {"vp-aa1", "aa=1", 0},
    {"vp-aa2", "aa=2", 0},
};
#define NVP (sizeof vp_configs / sizeof vp_configs[0])

static int config_profile(unsigned k, const alb_profile *base, alb_profile *q)
{
    char buf[128], err[200];
    *q = *base;
    snprintf(buf, sizeof buf, "%s", vp_configs[k].sets);
    for (char *tok = strtok(buf, " "); tok; tok = strtok(NULL, " "))
        if (alb_profile_set(q, tok, err, sizeof err))
            return -1;
    q->edge_frac_bits = (unsigned)((int)q->edge_frac_bits + vp_configs[k].edge_delta);
    return alb_profile_check(q, err, sizeof err);
}

static double now_ms(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return 1e3 * (double)t.tv_sec + 1e-6 * (double)t.tv_nsec;
}

/* ---- rendering ---- */

static int keep_first(void *ctx, const alb_frame *f, const alb_vp_stats *vs, const alb_sim_counters *sc)
{
    (void)vs, (void)sc;
    alb_frame *out = ctx;
    return out->face ? 0 : alb_frame_copy(out, f);
}

/* Frame 0 through GP and VP at a fidelity; -1 if the GP refuses the scene. */
static int vp_render(const alb_scene *s, const alb_profile *p, alb_fidelity fid, alb_frame *out)
{
    alb_diag d;
    alb_diag_init(&d, NULL);
    alb_gp *gp = NULL;
    alb_ws_buf b;
    alb_ws_buf_init(&b);
    memset(out, 0, sizeof *out);
    alb_sim_options o = {.fid = fid, .threads = 1};
    int rc = alb_gp_create(&gp, s, p, &d) || alb_gp_run(gp, &b, NULL, &d) ||
             alb_sim_run(p, b.w, b.n, "sweep", &o, keep_first, out, &d) || !out->face;
    alb_gp_destroy(gp);
    alb_ws_buf_free(&b);
    if (rc && out->face)
        alb_frame_free(out);
    return rc ? -1 : 0;
}

typedef struct {
    double face_pct, psnr, ms;
    unsigned runs, failed;
} point;

/* Configuration k (methods first, then vp_configs) on one scene; the host
 * time is the best of `reps` runs. */
static void measure(unsigned k, const alb_scene *s, const alb_profile *base, alb_fidelity fid, unsigned reps,
                    point *pt)
{
    unsigned nm;
    const method *m = methods_all(&nm);
    alb_profile q = *base;
    if (k >= nm && config_profile(k - nm, base, &q)) {
        pt->failed++;
        return;
    }
    alb_frame ref, got;
    if (ref_render(s, &q, 0, &ref)) {
        pt->failed++;
        return;
    }
    double ms = INFINITY;
    int rc = 0;
    for (unsigned r = 0; r < reps && !rc; r++) {
        if (r)
            alb_frame_free(&got);
        double t0 = now_ms();
        rc = k < nm ? m[k].render(s, &q, 0, &got) : vp_render(s, &q, fid, &got);
        ms = fmin(ms, now_ms() - t0);
    }
    if (rc) {
        pt->failed++;
    } else {
        alb_frame_diff df;
        alb_frame_compare(&ref, &got, &df);
        pt->face_pct += 100.0 * (double)df.face_diff / (double)df.pixels;
        pt->psnr += isinf(df.psnr) ? 99 : df.psnr;
        pt->ms += ms;
        pt->runs++;
        alb_frame_free(&got);
    }
    alb_frame_free(&ref);
}

static unsigned config_count(void)
{
    unsigned nm;
    methods_all(&nm);
    return nm + (unsigned)NVP;
}

static const char *config_name(unsigned k)
{
    unsigned nm;
    const method *m = methods_all(&nm);
    return k < nm ? m[k].name : vp_configs[k - nm].name;
}

static void write_point(FILE *out, const char *family, unsigned step, double sev, const char *config,
                        const point *pt)
{
    if (pt->runs)
        fprintf(out, "%s,%u,%g,%s,%.4f,%.2f,%.3f,%u\n", family, step, sev, config,
                pt->face_pct / pt->runs, pt->psnr / pt->runs, pt->ms / pt->runs, pt->failed);
    else
        fprintf(out, "%s,%u,%g,%s,,,,%u\n", family, step, sev, config, pt->failed);
}

#define CSV_HEADER "family,step,severity,config,face_diff_pct,psnr_db,ms_per_frame,failed\n"

int sweep_family_run(const char *family, const alb_profile *p, unsigned seeds, FILE *out,
                     const sweep_progress *progress)
{
    double t0 = now_ms();
    unsigned f = 0;
    while (f < NFAMILIES && strcmp(families[f].family, family))
        f++;
    if (f == NFAMILIES)
        return -1;
    fputs(CSV_HEADER, out);
    unsigned nc = config_count();
    for (unsigned j = 0; j < SWEEP_SEVERITIES; j++) {
        double sev = families[f].severity[j];
        for (unsigned k = 0; k < nc; k++) {
            point pt = {0, 0, 0, 0, 0};
            for (uint64_t seed = 1; seed <= seeds; seed++) {
                char *text = stress_scene(family, sev, seed);
                alb_scene s;
                alb_diag d;
                alb_diag_init(&d, NULL);
                if (text && !alb_scene_parse(text, strlen(text), family, &s, &d)) {
                    measure(k, &s, p, ALB_FIDELITY_FUNCTIONAL, 1, &pt);
                    alb_scene_free(&s);
                } else {
                    pt.failed++;
                }
                free(text);
            }
            write_point(out, family, j + 1, sev, config_name(k), &pt);
            if (progress->f && progress->live)
                fprintf(progress->f, "\r%s: severity %u/%u, configuration %u/%u   ", family,
                        j + 1, SWEEP_SEVERITIES, k + 1, nc);
        }
        if (progress->f && !progress->live)
            fprintf(progress->f, "stability %s: severity %u/%u (%g) done, %.1f s\n", family, j + 1,
                    SWEEP_SEVERITIES, sev, (now_ms() - t0) / 1e3);
        fflush(out);
    }
    if (progress->f && progress->live)
        fputc('\n', progress->f);
    return ferror(out) ? -1 : 0;
}

/* ---- speed against accuracy ---- */

/* The exact reference as one more point of the chart: its error is 0 by
 * definition, its time the best of `reps` renders. */
static void time_reference(const alb_scene *s, const alb_profile *p, unsigned reps, point *pt)
{
    double ms = INFINITY;
    for (unsigned r = 0; r < reps; r++) {
        alb_frame ref;
        double t0 = now_ms();
        if (ref_render(s, p, 0, &ref)) {
            pt->failed++;
            return;
        }
        ms = fmin(ms, now_ms() - t0);
        alb_frame_free(&ref);
    }
    pt->ms += ms;
    pt->runs++;
}

static void speed_progress(const sweep_progress *progress, unsigned k, unsigned nc,
                           const char *name, const char *fid)
{
    if (progress->f && progress->live)
        fprintf(progress->f, "\rspeed: configuration %u/%u   ", k + 1, nc);
    else if (progress->f)
        fprintf(progress->f, "speed: configuration %u/%u (%s%s%s) done\n", k + 1, nc, name,
                *fid ? " " : "", fid);
}

int sweep_speed_run(const alb_profile *p, FILE *out, const sweep_progress *progress)
{
    /* the scenes: 8 random ones and every family at its second severity
     * (docs/stability.md) */
    enum { NRANDOM = 8 };
    char *texts[NRANDOM + NFAMILIES];
    unsigned nt = 0;
    scenegen_params gp = scenegen_defaults();
    gp.faces = 40;
    for (unsigned i = 0; i < NRANDOM; i++)
        texts[nt++] = scenegen_random(100 + i, &gp);
    for (unsigned f = 0; f < NFAMILIES; f++)
        texts[nt++] = stress_scene(families[f].family, families[f].severity[1], 1);
    unsigned nm, nc = config_count();
    methods_all(&nm);
    fputs("config,fidelity,scenes,face_diff_pct,ms_per_frame,failed\n", out);
    for (unsigned k = 0; k < nc; k++) {
        unsigned nfid = k == nm ? 3 : 1;   /* the default VP at every fidelity */
        for (unsigned fi = 0; fi < nfid; fi++) {
            alb_fidelity fid = fi == 0 ? ALB_FIDELITY_FUNCTIONAL : fi == 1 ? ALB_FIDELITY_TIMED : ALB_FIDELITY_CYCLE;
            point pt = {0, 0, 0, 0, 0};
            for (unsigned i = 0; i < nt; i++) {
                alb_scene s;
                alb_diag d;
                alb_diag_init(&d, NULL);
                if (texts[i] && !alb_scene_parse(texts[i], strlen(texts[i]), "speed", &s, &d)) {
                    measure(k, &s, p, fid, 3, &pt);
                    alb_scene_free(&s);
                } else {
                    pt.failed++;
                }
            }
            fprintf(out, "%s,%s,%u,%.4f,%.3f,%u\n", config_name(k),
                    k < nm ? "-" : alb_fidelity_name(fid), pt.runs,
                    pt.runs ? pt.face_pct / pt.runs : 0.0, pt.runs ? pt.ms / pt.runs : 0.0,
                    pt.failed);
            speed_progress(progress, k, nc + 1, config_name(k),
                           k < nm ? "" : alb_fidelity_name(fid));
        }
    }
    point pt = {0, 0, 0, 0, 0};   /* last, the exact reference itself */
    for (unsigned i = 0; i < nt; i++) {
        alb_scene s;
        alb_diag d;
        alb_diag_init(&d, NULL);
        if (texts[i] && !alb_scene_parse(texts[i], strlen(texts[i]), "speed", &s, &d)) {
            time_reference(&s, p, 3, &pt);
            alb_scene_free(&s);
        } else {
            pt.failed++;
        }
    }
    fprintf(out, "reference,-,%u,0.0000,%.3f,%u\n", pt.runs, pt.runs ? pt.ms / pt.runs : 0.0,
            pt.failed);
    speed_progress(progress, nc, nc + 1, "reference", "");
    if (progress->f && progress->live)
        fputc('\n', progress->f);
    for (unsigned i = 0; i < nt; i++)
        free(texts[i]);
    return ferror(out) ? -1 : 0;
}

/* ---- reports ---- */

typedef struct {
    char family[32], config[40];
    unsigned step, failed;   /* failed: seeds that could not render (write_point) */
    double severity, face, psnr, ms;
    bool have;
} row;

static int read_rows(const char *path, row **rows, size_t *n)
{
    FILE *f = fopen(path, "r");
    if (!f)
        return -1;
    char line[512];
    size_t cap = *n + 64;
    row *r = realloc(*rows, cap * sizeof *r);
    if (!r) {
        fclose(f);
        return -1;
    }
    *rows = r;
    if (!fgets(line, sizeof line, f)) {   /* header */
        fclose(f);
        return 0;
    }
    while (fgets(line, sizeof line, f)) {
        if (*n == cap) {
            cap *= 2;
            row *nr = realloc(*rows, cap * sizeof *nr);
            if (!nr)
                break;
            *rows = nr;
        }
        row *x = &(*rows)[*n];
        memset(x, 0, sizeof *x);
        char face[32] = "", psnr[32] = "", ms[32] = "";
        int k = sscanf(line, "%31[^,],%u,%lf,%39[^,],%31[^,],%31[^,],%31[^,]", x->family, &x->step,
                       &x->severity, x->config, face, psnr, ms);
        if (k < 4)
            continue;
        x->have = k == 7;
        x->face = atof(face), x->psnr = atof(psnr), x->ms = atof(ms);
        x->failed = (unsigned)strtoul(strrchr(line, ',') + 1, NULL, 10);
        (*n)++;
    }
    fclose(f);
    return 0;
}

/* The first severity at which a configuration differs from the reference on
 * more than 1% of the pixels (or cannot render): where it breaks. */
static void breaks_table(FILE *md, const row *r, size_t n, unsigned fam)
{
    unsigned nc = config_count();
    fprintf(md, "\n| configuration | breaks at (>1%% of pixels wrong) |\n|---|---|\n");
    for (unsigned k = 0; k < nc; k++) {
        const char *name = config_name(k);
        const row *hit = NULL;
        for (size_t i = 0; i < n && !hit; i++)
            if (!strcmp(r[i].family, families[fam].family) && !strcmp(r[i].config, name) &&
                (!r[i].have || r[i].face > 1.0))
                hit = &r[i];
        if (hit)
            fprintf(md, "| %s | severity %g%s |\n", name, hit->severity,
                    hit->have ? "" : " (refused)");
        else
            fprintf(md, "| %s | holds everywhere |\n", name);
    }
}

static void family_table(FILE *md, const row *r, size_t n, unsigned fam)
{
    unsigned nc = config_count();
    fprintf(md, "\n### %s\n\nPixels whose face differs from the exact reference, %%:\n\n"
                "| severity |", families[fam].family);
    for (unsigned k = 0; k < nc; k++)
        fprintf(md, " %s |", config_name(k));
    fprintf(md, "\n|---|");
    for (unsigned k = 0; k < nc; k++)
        fprintf(md, "---|");
    for (unsigned j = 0; j < SWEEP_SEVERITIES; j++) {
        fprintf(md, "\n| %g |", families[fam].severity[j]);
        for (unsigned k = 0; k < nc; k++) {
            const row *x = NULL;
            for (size_t i = 0; i < n && !x; i++)
                if (!strcmp(r[i].family, families[fam].family) && r[i].step == j + 1 &&
                    !strcmp(r[i].config, config_name(k)))
                    x = &r[i];
            if (!x)
                fprintf(md, " – |");
            else if (!x->have)
                fprintf(md, " refused |");
            else
                fprintf(md, " %.2f |", x->face);
        }
    }
    fputc('\n', md);
    breaks_table(md, r, n, fam);
}

/* ---- report files: each under its name only once complete (file.h) ---- */

typedef struct {
    alb_out out;
    FILE *f;
    char *path;
} report_file;

static FILE *report_open(report_file *r, const char *dir, const char *name)
{
    alb_diag d;
    alb_diag_init(&d, NULL);
    r->f = NULL;
    if (!(r->path = alb_strprintf("%s/%s", dir, name))) {
        fprintf(stderr, "albatros stability: out of memory\n");
        return NULL;
    }
    if (alb_out_open(&r->out, r->path, 0, &d) || !(r->f = alb_out_stdio(&r->out, &d))) {
        fprintf(stderr, "albatros stability: ");
        alb_diag_print(&d, stderr);
        free(r->path);
        r->path = NULL;
    }
    return r->f;
}

/* Put the file in place (ok) or drop it; -1 if it is not in place. */
static int report_close(report_file *r, bool ok)
{
    alb_diag d;
    alb_diag_init(&d, NULL);
    int rc = 0;
    if (!ok) {
        alb_out_abort(&r->out);
        rc = -1;
    } else if (alb_out_commit(&r->out, &d)) {
        fprintf(stderr, "albatros stability: ");
        alb_diag_print(&d, stderr);
        rc = -1;
    }
    free(r->path);
    return rc;
}

/* path as a gnuplot single-quoted string: a quote doubled */
static void gp_quoted(FILE *g, const char *path)
{
    fputc('\'', g);
    for (const char *p = path; *p; p++) {
        if (*p == '\'')
            fputc('\'', g);
        fputc(*p, g);
    }
    fputc('\'', g);
}

/* gnuplot on a script (no shell: any file name will do); 0 if it ran and
 * succeeded. */
static int run_gnuplot(const char *script_path)
{
    pid_t pid;
    char name[] = "gnuplot", *script = alb_strprintf("%s", script_path);
    char *argv[] = {name, script, NULL};
    extern char **environ;
    int rc = script ? posix_spawnp(&pid, "gnuplot", NULL, NULL, argv, environ) : -1;
    free(script);
    if (rc != 0)
        return -1;
    int status;
    while (waitpid(pid, &status, 0) < 0)
        if (errno != EINTR)
            return -1;
    return WIFEXITED(status) && WEXITSTATUS(status) == 0 ? 0 : -1;
}

/* A chart: gnuplot runs the script at script_name, which draws into the
 * PNG's temporary file (its path given to write_script), put in place only
 * if gnuplot succeeded — a failed run keeps the last good chart. */
static int draw_chart(const char *dir, const char *script_name, const char *png_name,
                      void (*write_script)(FILE *g, const char *png_path, const void *ctx),
                      const void *ctx)
{
    report_file png, gp;
    if (!report_open(&png, dir, png_name))
        return -1;
    char *tmp = alb_out_temp_path(&png.out);
    if (!tmp || !report_open(&gp, dir, script_name)) {
        free(tmp);
        report_close(&png, false);
        return -1;
    }
    /* the script names the chart by its final name; gnuplot is run on a
     * copy that writes the temporary */
    write_script(gp.f, png.path, ctx);
    int rc = report_close(&gp, true);
    char *run = rc ? NULL : alb_strprintf("%s/.%s.run", dir, script_name);
    FILE *rf = run ? fopen(run, "w") : NULL;
    if (rf) {
        fputs("set output ", rf);
        gp_quoted(rf, tmp);
        fputc('\n', rf);
        write_script(rf, NULL, ctx);
        rc = fclose(rf) ? -1 : run_gnuplot(run);
        remove(run);   /* ours: made just above */
    } else {
        rc = -1;
    }
    free(run);
    free(tmp);
    return report_close(&png, rc == 0) || rc ? -1 : 0;
}

/* Per family, a gnuplot data file: step, then one column per configuration
 * (NaN where it refused), so each configuration is a connected line. */
static int family_data(const char *dir, unsigned fam, const row *r, size_t n)
{
    char name[64];
    snprintf(name, sizeof name, "stability-%s.dat", families[fam].family);
    report_file rf;
    FILE *f = report_open(&rf, dir, name);
    if (!f)
        return -1;
    unsigned nc = config_count();
    for (unsigned j = 0; j < SWEEP_SEVERITIES; j++) {
        fprintf(f, "%u", j + 1);
        for (unsigned k = 0; k < nc; k++) {
            double v = NAN;
            for (size_t i = 0; i < n; i++)
                if (!strcmp(r[i].family, families[fam].family) && r[i].step == j + 1 &&
                    !strcmp(r[i].config, config_name(k)) && r[i].have)
                    v = r[i].face;
            fprintf(f, isnan(v) ? " NaN" : " %.4f", v);
        }
        fputc('\n', f);
    }
    return report_close(&rf, true);
}

static bool family_present(unsigned fam, const row *r, size_t n)
{
    for (size_t i = 0; i < n; i++)
        if (!strcmp(r[i].family, families[fam].family) && r[i].have)
            return true;
    return false;
}

/* The largest value of a family's panel (0: nothing differs anywhere). */
static double family_max(unsigned fam, const row *r, size_t n)
{
    double m = 0;
    for (size_t i = 0; i < n; i++)
        if (!strcmp(r[i].family, families[fam].family) && r[i].have && r[i].face > m)
            m = r[i].face;
    return m;
}

/* Seventeen series told apart by colour alone (no two share one), and by
 * the line: the classic methods solid with filled points, the Albatros
 * configurations dashed with open ones. */
static const char *const method_colours[] = {"#1f77b4", "#ff7f0e", "#2ca02c", "#d62728",
                                             "#9467bd", "#8c564b", "#e377c2", "#4d4d4d"};
static const char *const vp_colours[] = {"#17becf", "#bcbd22", "#000000", "#e6ab02",
                                         "#a6761d", "#1b9e77", "#d95f02", "#7570b3",
                                         "#e7298a", "#66a61e", "#999999", "#0000cd"};

static void series_styles(FILE *g)
{
    unsigned nm, nc = config_count();
    methods_all(&nm);
    static const int filled[] = {5, 7, 9, 11, 13, 15}, open[] = {4, 6, 8, 10, 12, 14, 1, 2, 3};
    for (unsigned k = 0; k < nc; k++) {
        bool m = k < nm;
        unsigned i = m ? k : k - nm;
        const char *colour = m ? method_colours[i % 8] : vp_colours[i % 12];
        int pt = m ? filled[i % 6] : open[i % 9];
        fprintf(g, "set linetype %u lc rgb '%s' lw 1.6 dt %d pt %d ps 1.1\n", k + 1, colour,
                m ? 1 : 2, pt);
    }
}

typedef struct {
    const char *dir;
    const row *r;
    size_t n;
} chart_ctx;

static void stability_script(FILE *g, const char *png, const void *ctx)
{
    const chart_ctx *c = ctx;
    unsigned nc = config_count(), drawn = 0;
    char none[400] = "";
    for (unsigned f = 0; f < NFAMILIES; f++) {
        if (!family_present(f, c->r, c->n))
            continue;
        if (family_max(f, c->r, c->n) > 0)
            drawn++;
        else   /* a flat panel says nothing: named in the title instead */
            snprintf(none + strlen(none), sizeof none - strlen(none), "%s%s", none[0] ? ", " : "",
                     families[f].family);
    }
    unsigned rows = (drawn + 1 + 1) / 2;   /* the panels and the legend's */
    fprintf(g, "# stability chart, written by albatros stability --report\n"
               "set terminal pngcairo size 1600,%u font ',10' noenhanced\n", 330 * rows + 60);
    if (png) {
        fputs("set output ", g);
        gp_quoted(g, png);
        fputc('\n', g);
    }
    fprintf(g, "set multiplot layout %u,2 title \"Pixels whose face differs from the exact "
               "reference, %%, against each family's severity (more severe to the right)%s%s\"\n"
               "set grid\nset datafile missing 'NaN'\nunset key\nset ylabel 'pixels wrong, %%'\n",
            rows, none[0] ? "\\nno configuration differs anywhere on: " : "", none);
    series_styles(g);
    for (unsigned f = 0; f < NFAMILIES; f++) {
        double m = family_max(f, c->r, c->n);
        if (!family_present(f, c->r, c->n) || !(m > 0))
            continue;
        /* each panel's own range: small differences are not a flat line */
        fprintf(g, "set title '%s'\nset xlabel 'severity: %s'\nset yrange [0:%g]\nset xtics (",
                families[f].family, families[f].unit, m * 1.15 > 0.05 ? m * 1.15 : 0.05);
        for (unsigned j = 0; j < SWEEP_SEVERITIES; j++)
            fprintf(g, "%s'%g' %u", j ? ", " : "", families[f].severity[j], j + 1);
        fprintf(g, ")\nplot ");
        for (unsigned k = 0; k < nc; k++) {
            char *dat = alb_strprintf("%s/stability-%s.dat", c->dir, families[f].family);
            fprintf(g, "%s", k ? ", \\\n     " : "");
            gp_quoted(g, dat ? dat : "");
            fprintf(g, " using 1:%u with linespoints ls %u notitle", k + 2, k + 1);
            free(dat);
        }
        fputc('\n', g);
    }
    /* one legend, in a panel of its own, each series as it is drawn */
    fprintf(g, "set title 'series'\nunset xlabel\nunset ylabel\nunset border\nunset tics\n"
               "unset grid\nset xrange [0:1]\nset yrange [0:1]\n"
               "set key center center vertical maxrows 9 width 2 font ',11' samplen 4\nplot ");
    for (unsigned k = 0; k < nc; k++)
        fprintf(g, "%sNaN with linespoints ls %u title '%s'", k ? ", \\\n     " : "", k + 1,
                config_name(k));
    fprintf(g, "\nunset multiplot\n");
}

static int stability_chart(const char *dir, const row *r, size_t n)
{
    for (unsigned f = 0; f < NFAMILIES; f++)
        if (family_present(f, r, n) && family_data(dir, f, r, n))
            return -1;
    chart_ctx c = {dir, r, n};
    return draw_chart(dir, "stability.gp", "stability.png", stability_script, &c);
}

typedef struct sp {
    char config[40], fid[16];
    double face, ms;
    bool pareto;
} speed_point;

typedef struct {
    const char *dir;
    const speed_point *pts;
    unsigned n;
} speed_ctx;

/* Each point numbered on the chart, its name in the key by the number: long
 * labels beside clustered points piled up. */
static void speed_script(FILE *g, const char *png, const void *ctx)
{
    const speed_ctx *c = ctx;
    char *dat = alb_strprintf("%s/speed-points.dat", c->dir);
    fprintf(g, "# speed against accuracy, written by albatros stability --report\n"
               "set terminal pngcairo size 1400,800 font ',10' noenhanced\n");
    if (png) {
        fputs("set output ", g);
        gp_quoted(g, png);
        fputc('\n', g);
    }
    fprintf(g, "set title 'Speed against accuracy: each point a method, or an Albatros "
               "configuration at a fidelity (numbered as in the key)'\n"
               "set xlabel 'host time per frame, ms (log scale)'\nset logscale x\n"
               "set ylabel 'pixels whose face differs from the exact reference, %% (log scale; "
               "0 drawn at 0.001)'\nset logscale y\nset grid\n"
               "set key outside right top vertical font ',9' spacing 1.1 title 'points'\n"
               "set rmargin 38\nplot ");
    gp_quoted(g, dat ? dat : "");
    fprintf(g, " index 0 using 1:2 with points pt 7 ps 1.3 lc rgb '#1f77b4' notitle, \\\n"
               "     '' index 0 using 1:2:5 with labels left offset char 0.7,0.6 font ',9' "
               "notitle, \\\n"
               "     '' index 1 using 1:2 with lines lw 2 lc rgb '#d62728' title 'Pareto front "
               "(nothing faster and more accurate)'");
    for (unsigned i = 0; i < c->n; i++)
        fprintf(g, ", \\\n     keyentry with points pt 7 ps 0 lc rgb '#ffffff' title '%u  %s%s%s'",
                i + 1, c->pts[i].config, strcmp(c->pts[i].fid, "-") ? ", " : "",
                strcmp(c->pts[i].fid, "-") ? c->pts[i].fid : "");
    fputc('\n', g);
    free(dat);
}

/* Two points a label's width apart or less on the log-log chart: within 3%
 * in time and 10% in error. */
static bool same_spot(const speed_point *a, const speed_point *b)
{
    return fabs(log(a->ms / b->ms)) < 0.03 &&
           fabs(log(fmax(a->face, 0.001) / fmax(b->face, 0.001))) < 0.1;
}

/* speed.md and speed.png from speed.csv; 1 if written, 0 if the directory
 * has no speed sweep, -1 on error. */
static int speed_report(const char *dir)
{
    char *path = alb_strprintf("%s/speed.csv", dir);
    const char *why;
    FILE *f = path ? alb_file_open_input(path, true, &why) : NULL;
    free(path);
    if (!f)
        return 0;   /* no speed sweep in this directory: nothing written */
    speed_point pts[64];
    unsigned n = 0;
    char line[256];
    if (!fgets(line, sizeof line, f)) {
        fclose(f);
        return -1;
    }
    while (n < 64 && fgets(line, sizeof line, f)) {
        unsigned scenes;
        if (sscanf(line, "%39[^,],%15[^,],%u,%lf,%lf", pts[n].config, pts[n].fid, &scenes,
                   &pts[n].face, &pts[n].ms) == 5 && scenes)
            n++;
    }
    fclose(f);
    /* the Pareto front: no other point both faster and more accurate */
    for (unsigned i = 0; i < n; i++) {
        pts[i].pareto = true;
        for (unsigned j = 0; j < n; j++)
            if (j != i && pts[j].ms <= pts[i].ms && pts[j].face <= pts[i].face &&
                (pts[j].ms < pts[i].ms || pts[j].face < pts[i].face))
                pts[i].pareto = false;
    }
    report_file md, dat;
    if (!report_open(&md, dir, "speed.md"))
        return -1;
    if (!report_open(&dat, dir, "speed-points.dat")) {
        report_close(&md, false);
        return -1;
    }
    fprintf(md.f, "| configuration | fidelity | ms per frame | pixels wrong, %% | Pareto front |\n"
                  "|---|---|---|---|---|\n");
    for (unsigned i = 0; i < n; i++)
        fprintf(md.f, "| %s | %s | %.2f | %.3f | %s |\n", pts[i].config, pts[i].fid, pts[i].ms,
                pts[i].face, pts[i].pareto ? "yes" : "");
    /* block 0: the points (errors of 0 drawn at 0.001 on the logarithmic
     * axis), each labelled with its number, those that fall on one spot
     * with one label listing them all */
    for (unsigned i = 0; i < n; i++) {
        char label[128] = "";
        bool first = true;
        for (unsigned j = 0; j < i && first; j++)
            first = !same_spot(&pts[i], &pts[j]);
        for (unsigned j = i; j < n && first; j++)
            if (same_spot(&pts[i], &pts[j]))
                snprintf(label + strlen(label), sizeof label - strlen(label), "%s%u",
                         label[0] ? "," : "", j + 1);
        fprintf(dat.f, "%g %g %d \"%s%s%s\" \"%s\"\n", pts[i].ms, fmax(pts[i].face, 0.001),
                pts[i].pareto, pts[i].config, strcmp(pts[i].fid, "-") ? " " : "",
                strcmp(pts[i].fid, "-") ? pts[i].fid : "", label);
    }
    /* block 1: the Pareto front in order of time */
    fprintf(dat.f, "\n\n");
    for (double last = -1;;) {
        int next = -1;
        for (unsigned i = 0; i < n; i++)
            if (pts[i].pareto && pts[i].ms > last && (next < 0 || pts[i].ms < pts[next].ms))
                next = (int)i;
        if (next < 0)
            break;
        fprintf(dat.f, "%g %g\n", pts[next].ms, fmax(pts[next].face, 0.001));
        last = pts[next].ms;
    }
    if (report_close(&md, true) | report_close(&dat, true))
        return -1;
    speed_ctx c = {dir, pts, n};
    return draw_chart(dir, "speed.gp", "speed.png", speed_script, &c) ? -1 : 1;
}

int sweep_report(const char *dir, bool *with_speed)
{
    *with_speed = false;
    row *rows = NULL;
    size_t n = 0;
    report_file merged;
    if (!report_open(&merged, dir, "stability.csv"))
        return -1;
    fputs(CSV_HEADER, merged.f);
    unsigned found = 0;
    for (unsigned f = 0; f < NFAMILIES; f++) {
        char *path = alb_strprintf("%s/stability-%s.csv", dir, families[f].family);
        size_t before = n;
        int rc = path ? read_rows(path, &rows, &n) : -1;
        free(path);
        if (rc)
            continue;
        found++;
        for (size_t i = before; i < n; i++) {
            const row *x = &rows[i];
            if (x->have)
                fprintf(merged.f, "%s,%u,%g,%s,%.4f,%.2f,%.3f,%u\n", x->family, x->step,
                        x->severity, x->config, x->face, x->psnr, x->ms, x->failed);
            else
                fprintf(merged.f, "%s,%u,%g,%s,,,,%u\n", x->family, x->step, x->severity,
                        x->config, x->failed);
        }
    }
    if (!found) {
        report_close(&merged, false);
        fprintf(stderr, "albatros stability: no stability-FAMILY.csv in %s (run the jobs first)\n",
                dir);
        free(rows);
        return -1;
    }
    report_file md;
    if (report_close(&merged, true) || !report_open(&md, dir, "stability.md")) {
        free(rows);
        return -1;
    }
    fprintf(md.f, "# Stability: the methods where they fail\n\nEvery classic method and Albatros "
                  "configuration on each stress family (tools/stress.c), against the exact "
                  "reference; written by `albatros stability --report` from the CSVs beside it.\n");
    for (unsigned f = 0; f < NFAMILIES; f++)
        if (family_present(f, rows, n))
            family_table(md.f, rows, n, f);
    if (report_close(&md, true)) {
        free(rows);
        return -1;
    }
    int chart = stability_chart(dir, rows, n);
    free(rows);
    if (chart) {
        fprintf(stderr, "albatros stability: gnuplot failed (is gnuplot installed? "
                        "apt-get install gnuplot-nox)\n");
        return -1;
    }
    int speed = speed_report(dir);
    *with_speed = speed == 1;
    return speed < 0 ? -1 : 0;
}
