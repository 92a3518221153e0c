/* cost.c — how the VP's work grows: cells visited, samples written and host
 * time against resolution (the built-in scene) and against face count
 * (random scenes).  Run by `make bench`; figures go to docs/performance.md. */
#include "scenegen.h"
#include "../gp/gp.h"
#include "../vp/vp.h"

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
    vp_stats st;
    unsigned frames;
} run_result;

static int keep(void *ctx, const frame_t *f, const vp_stats *st)
{
    (void)f;
    run_result *r = ctx;
    if (r->frames++ == 0)
        r->st = *st;
    return 0;
}

static uint64_t cells(const vp_stats *st)
{
    uint64_t n = 0;
    for (unsigned l = 0; l < VP_MAX_LEVELS; l++)
        n += st->cells[l];
    return n;
}

/* GP + VP on the scene's frame 0 (repeated for a stable time); -1 on error. */
static int measure(const scene_t *s, const profile_t *p, run_result *r, double *ms)
{
    diag_t d;
    diag_init(&d, stderr);
    gp_t *gp = NULL;
    vp_t *vp = NULL;
    ws_buf b;
    ws_buf_init(&b);
    gp_stats gst;
    int rc = -1;
    if (gp_create(&gp, s, p, &d) || vp_create(&vp, p, &d))
        goto out;
    gp_stream_header(gp, &b);
    if (gp_frame(gp, 0, &b, &gst, &d))
        goto out;
    ws_put_end(&b);
    double t0 = now(), t;
    unsigned reps = 0;
    do {
        r->frames = 0;
        if (vp_run_stream(vp, b.w, b.n, "bench", keep, r, &d)) {
            diag_print(&d, stderr);
            goto out;
        }
        reps++;
        t = now() - t0;
    } while (t < 0.5 && reps < 50);
    *ms = 1000 * t / reps;
    rc = 0;
out:
    vp_destroy(vp);
    gp_destroy(gp);
    ws_buf_free(&b);
    return rc;
}

static void set_resolution(profile_t *p, unsigned res)
{
    unsigned lg = 0;
    while ((1u << lg) < res)
        lg++;
    p->width = p->height = res;
    p->edge_frac_bits = lg + 5;   /* six bits below the pixel, as the profiles */
}

int main(void)
{
    profile_t p;
    profile_lookup("a512", &p);
    scene_t s;
    diag_t d;
    diag_init(&d, stderr);
    if (scene_load_builtin(&s, &d)) {
        diag_print(&d, stderr);
        return 1;
    }
    printf("## Resolution (built-in scene, frame 0)\n\n"
           "| screen | cells visited | cells / side | samples written | samples / pixel | ms |\n"
           "|---|---|---|---|---|---|\n");
    for (unsigned res = 256; res <= 4096; res *= 2) {
        run_result r;
        double ms;
        set_resolution(&p, res);
        if (measure(&s, &p, &r, &ms))
            return 1;
        printf("| %u² | %llu | %.1f | %llu | %.2f | %.1f |\n", res,
               (unsigned long long)cells(&r.st), (double)cells(&r.st) / res,
               (unsigned long long)r.st.samples_written,
               (double)r.st.samples_written / ((double)res * res), ms);
    }
    scene_free(&s);
    printf("\n## Face count (random scenes, 1024²)\n\n"
           "| faces | cells visited | cells / face | samples written | ms |\n"
           "|---|---|---|---|---|\n");
    set_resolution(&p, 1024);
    for (unsigned n = 10; n <= 10000; n *= 10) {
        scenegen_params gp = scenegen_defaults();
        gp.faces = n;
        gp.size = 0.3 / (n < 100 ? 1 : n < 1000 ? 3 : n < 10000 ? 10 : 30);
        char *text = scenegen_random(1, &gp);
        if (!text || scene_parse(text, strlen(text), "random", &s, &d)) {
            diag_print(&d, stderr);
            free(text);
            return 1;
        }
        free(text);
        run_result r;
        double ms;
        if (measure(&s, &p, &r, &ms))
            return 1;
        printf("| %u | %llu | %.1f | %llu | %.1f |\n", n, (unsigned long long)cells(&r.st),
               (double)cells(&r.st) / n, (unsigned long long)r.st.samples_written, ms);
        scene_free(&s);
    }
    return 0;
}
