/* bench.c — host speed of the three fidelities (docs/performance.md):
 * emulated cycles per second for cycle and timed, frames per second for
 * functional, on the built-in scene and a heavy random scene at 1024x1024.
 * Figures, not tests: run by `make bench`. */
#include "scenegen.h"
#include "albatros/sim.h"
#include "albatros/gp.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

typedef struct {
    uint64_t cycles;
    unsigned frames;
    bool hashing;             /* hash the frames (untimed runs only) */
    uint64_t hash;            /* FNV-1a over every frame's colour, depth and face */
    uint64_t shaded, textured, fogged, faces;
} totals;

static uint64_t fnv(uint64_t h, const void *p, size_t n)
{
    const unsigned char *b = p;
    for (size_t i = 0; i < n; i++)
        h = (h ^ b[i]) * 0x100000001b3ull;
    return h;
}

static int count(void *ctx, const alb_frame *f, const alb_vp_stats *vs, const alb_sim_counters *sc)
{
    totals *t = ctx;
    t->frames++;
    if (sc)
        t->cycles += sc->cycles;
    t->faces += vs->faces, t->shaded += vs->faces_shaded;
    t->textured += vs->faces_textured, t->fogged += vs->faces_fogged;
    if (!t->hashing)
        return 0;
    size_t np = (size_t)f->width * f->height;
    t->hash = fnv(t->hash, f->rgb, 3 * np * sizeof *f->rgb);
    t->hash = fnv(t->hash, f->depth, np * sizeof *f->depth);
    t->hash = fnv(t->hash, f->face, np * sizeof *f->face);
    return 0;
}

/* Seconds per run of the stream at fidelity fid (best of a few). */
static double time_run_threads(const alb_profile *p, const alb_ws_buf *b, alb_fidelity fid,
                               unsigned threads, totals *t)
{
    alb_diag d;
    alb_diag_init(&d, stderr);
    alb_sim_options o = {.fid = fid, .threads = threads};
    double best = 1e9;
    for (int rep = 0; rep < 3; rep++) {
        memset(t, 0, sizeof *t);
        double t0 = now();
        if (alb_sim_run(p, b->w, b->n, "bench", &o, count, t, &d)) {
            alb_diag_print(&d, stderr);
            exit(1);
        }
        double s = now() - t0;
        best = s < best ? s : best;
    }
    return best;
}

static double time_run(const alb_profile *p, const alb_ws_buf *b, alb_fidelity fid, totals *t)
{
    return time_run_threads(p, b, fid, 1, t);
}

/* The GP's stream of scene s, and the seconds it took. */
static double gp_stream(alb_scene *s, const alb_profile *p, alb_ws_buf *b)
{
    alb_diag d;
    alb_diag_init(&d, stderr);
    alb_gp *gp = NULL;
    alb_ws_buf_init(b);
    double t0 = now();
    if (alb_gp_create(&gp, s, p, &d) || alb_gp_run(gp, b, NULL, &d)) {
        alb_diag_print(&d, stderr);
        exit(1);
    }
    alb_gp_destroy(gp);
    return now() - t0;
}

static void bench_scene(const char *label, alb_scene *s, const alb_profile *p)
{
    alb_ws_buf b;
    double gp_s = gp_stream(s, p, &b);
    totals tf, tt, tc;
    double sf = time_run(p, &b, ALB_FIDELITY_FUNCTIONAL, &tf);
    double st = time_run(p, &b, ALB_FIDELITY_TIMED, &tt);
    double sc = time_run(p, &b, ALB_FIDELITY_CYCLE, &tc);
    /* the timing models' own cost: their time beyond the functional run,
     * which does the same pixel work */
    double ot = st - sf, oc = sc - sf;
    printf("| %s | %u | %llu | %.1f | %.1f | %.1f M/s | %.1f M/s | %.1fx | %.0f M/s | %.0f M/s |\n",
           label, tf.frames, (unsigned long long)tc.cycles, tf.frames / sf, tf.frames / (sf + gp_s),
           (double)tt.cycles / st / 1e6, (double)tc.cycles / sc / 1e6, sc / st,
           ot > 0 ? (double)tt.cycles / ot / 1e6 : 0.0, oc > 0 ? (double)tc.cycles / oc / 1e6 : 0.0);
    alb_ws_buf_free(&b);
}

/* The hash of every frame of the stream, functional. */
static uint64_t frames_hash(const alb_profile *p, const alb_ws_buf *b, unsigned threads)
{
    alb_diag d;
    alb_diag_init(&d, stderr);
    alb_sim_options o = {.fid = ALB_FIDELITY_FUNCTIONAL, .threads = threads};
    totals t = {.hashing = true, .hash = 0xcbf29ce484222325ull};
    if (alb_sim_run(p, b->w, b->n, "bench", &o, count, &t, &d)) {
        alb_diag_print(&d, stderr);
        exit(1);
    }
    return t.hash;
}

/* Only the units a scene uses against every unit on (all_units=1). */
static void bench_units(const char *label, alb_scene *s, const alb_profile *p)
{
    alb_ws_buf b;
    gp_stream(s, p, &b);
    alb_profile all = *p;
    all.all_units = 1;
    totals tu, ta;
    double su = time_run(p, &b, ALB_FIDELITY_FUNCTIONAL, &tu);
    double sa = time_run(&all, &b, ALB_FIDELITY_FUNCTIONAL, &ta);
    printf("| %s | %.1f%% / %.1f%% / %.1f%% | %.2f | %.2f | %.2fx | %s |\n", label,
           100.0 * (double)tu.shaded / (double)tu.faces,
           100.0 * (double)tu.textured / (double)tu.faces,
           100.0 * (double)tu.fogged / (double)tu.faces, 1e3 * su / tu.frames,
           1e3 * sa / ta.frames, sa / su, frames_hash(p, &b, 1) == frames_hash(&all, &b, 1) ? "identical" : "DIFFERENT");
    alb_ws_buf_free(&b);
}

/* The random scene of seed 7 with these parameters; -1 (said) on failure. */
static int random_scene(const scenegen_params *gp, alb_scene *s)
{
    alb_diag d;
    alb_diag_init(&d, stderr);
    char *text = scenegen_random(7, gp);
    alb_err e = text ? alb_scene_parse(text, strlen(text), "random", s, &d) : ALB_ERR_NOMEM;
    free(text);
    if (e)
        alb_diag_print(&d, stderr);
    return e ? -1 : 0;
}

/* The functional renderer on every core against one (vp/parallel.c). */
static void bench_threads(const char *label, alb_scene *s, const alb_profile *p)
{
    alb_ws_buf b;
    gp_stream(s, p, &b);
    unsigned n = alb_vp_cores();
    totals t1, tn;
    double s1 = time_run_threads(p, &b, ALB_FIDELITY_FUNCTIONAL, 1, &t1);
    double sn = time_run_threads(p, &b, ALB_FIDELITY_FUNCTIONAL, n, &tn);
    printf("| %s | %u | %.2f | %.2f | %.2fx | %s |\n", label, n, 1e3 * s1 / t1.frames,
           1e3 * sn / tn.frames, s1 / sn,
           frames_hash(p, &b, 1) == frames_hash(p, &b, n) ? "identical" : "DIFFERENT");
    alb_ws_buf_free(&b);
}

int main(void)
{
    alb_profile p;
    alb_profile_lookup("a1024", &p);
    printf("## Fidelities (profile a1024, one core)\n\n"
           "| scene | frames | cycles | functional fps (VP) | fps (GP + VP) | timed | cycle | "
           "timed / cycle | timing logic, timed | timing logic, cycle |\n"
           "|---|---|---|---|---|---|---|---|---|---|\n");
    alb_scene s;
    alb_diag d;
    alb_diag_init(&d, stderr);
    if (alb_scene_load_builtin(&s, &d)) {
        alb_diag_print(&d, stderr);
        return 1;
    }
    bench_scene("built-in", &s, &p);
    alb_scene builtin = s;
    scenegen_params gp = scenegen_defaults();
    gp.faces = 3000;
    gp.size = 0.05;
    if (random_scene(&gp, &s))
        return 1;
    bench_scene("random 3000 faces", &s, &p);
    printf("\n## Units a scene needs (functional, profile a1024)\n\n"
           "| scene | faces shaded / textured / fogged | ms/frame, its units | "
           "ms/frame, all_units=1 | speed-up | pixels |\n|---|---|---|---|---|---|\n");
    bench_units("built-in", &builtin, &p);
    bench_units("random 3000 faces", &s, &p);
    alb_scene_free(&s);
    gp.flat = true;
    if (random_scene(&gp, &s))
        return 1;
    bench_units("the same, flat", &s, &p);
    printf("\n## Threads (functional, profile a1024)\n\n"
           "| scene | threads | ms/frame, 1 thread | ms/frame, all | speed-up | pixels |\n"
           "|---|---|---|---|---|---|\n");
    bench_threads("built-in", &builtin, &p);
    bench_threads("random 3000 faces, flat", &s, &p);
    alb_profile aa = p;
    aa.aa_levels = 2;
    bench_threads("built-in, aa=2", &builtin, &aa);
    alb_scene_free(&builtin);
    alb_scene_free(&s);
    return 0;
}
