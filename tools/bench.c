/* bench.c — host speed of the three fidelities (docs/performance.md):
 * emulated cycles per second for cycle and timed, frames per second for
 * functional, on the built-in scene and a heavy random scene at 1024x1024.
 * Figures, not tests: run by `make bench`. */
#include "scenegen.h"
#include "../emu/sim.h"
#include "../gp/gp.h"

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
} totals;

static int count(void *ctx, const frame_t *f, const vp_stats *vs, const sim_counters *sc)
{
    (void)f, (void)vs;
    totals *t = ctx;
    t->frames++;
    if (sc)
        t->cycles += sc->cycles;
    return 0;
}

/* Seconds per run of the stream at fidelity fid (best of a few). */
static double time_run(const profile_t *p, const ws_buf *b, fidelity fid, totals *t)
{
    diag_t d;
    diag_init(&d, stderr);
    sim_options o = {fid, NULL, 0, 0};
    double best = 1e9;
    for (int rep = 0; rep < 3; rep++) {
        memset(t, 0, sizeof *t);
        double t0 = now();
        if (sim_run(p, b->w, b->n, "bench", &o, count, t, &d)) {
            diag_print(&d, stderr);
            exit(1);
        }
        double s = now() - t0;
        best = s < best ? s : best;
    }
    return best;
}

static void bench_scene(const char *label, scene_t *s, const profile_t *p)
{
    diag_t d;
    diag_init(&d, stderr);
    gp_t *gp = NULL;
    ws_buf b;
    ws_buf_init(&b);
    double t0 = now();
    if (gp_create(&gp, s, p, &d) || gp_run(gp, &b, NULL, &d)) {
        diag_print(&d, stderr);
        exit(1);
    }
    double gp_s = now() - t0;
    gp_destroy(gp);
    totals tf, tt, tc;
    double sf = time_run(p, &b, FIDELITY_FUNCTIONAL, &tf);
    double st = time_run(p, &b, FIDELITY_TIMED, &tt);
    double sc = time_run(p, &b, FIDELITY_CYCLE, &tc);
    /* the timing models' own cost: their time beyond the functional run,
     * which does the same pixel work */
    double ot = st - sf, oc = sc - sf;
    printf("| %s | %u | %llu | %.1f | %.1f | %.1f M/s | %.1f M/s | %.1fx | %.0f M/s | %.0f M/s |\n",
           label, tf.frames, (unsigned long long)tc.cycles, tf.frames / sf, tf.frames / (sf + gp_s),
           (double)tt.cycles / st / 1e6, (double)tc.cycles / sc / 1e6, sc / st,
           ot > 0 ? (double)tt.cycles / ot / 1e6 : 0.0, oc > 0 ? (double)tc.cycles / oc / 1e6 : 0.0);
    ws_buf_free(&b);
}

int main(void)
{
    profile_t p;
    profile_lookup("a1024", &p);
    printf("## Fidelities (profile a1024, one core)\n\n"
           "| scene | frames | cycles | functional fps (VP) | fps (GP + VP) | timed | cycle | "
           "timed / cycle | timing logic, timed | timing logic, cycle |\n"
           "|---|---|---|---|---|---|---|---|---|---|\n");
    scene_t s;
    diag_t d;
    diag_init(&d, stderr);
    if (scene_load_builtin(&s, &d)) {
        diag_print(&d, stderr);
        return 1;
    }
    bench_scene("built-in", &s, &p);
    scene_free(&s);
    scenegen_params gp = scenegen_defaults();
    gp.faces = 3000;
    gp.size = 0.05;
    char *text = scenegen_random(7, &gp);
    if (!text || scene_parse(text, strlen(text), "heavy", &s, &d)) {
        diag_print(&d, stderr);
        return 1;
    }
    free(text);
    bench_scene("random 3000 faces", &s, &p);
    scene_free(&s);
    return 0;
}
