/* cost.c — how the VP's work grows: cells visited, samples written and host
 * time against resolution (the built-in scene) and against face count
 * (random scenes).  Run by `make bench`; figures go to docs/performance.md. */
#include "scenegen.h"
#include "albatros/gp.h"
#include "albatros/vp.h"

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
    alb_vp_stats st;
    unsigned frames;
} run_result;

static int keep(void *ctx, const alb_frame *f, const alb_vp_stats *st)
{
    (void)f;
    run_result *r = ctx;
    if (r->frames++ == 0)
        r->st = *st;
    return 0;
}

static uint64_t cells(const alb_vp_stats *st)
{
    uint64_t n = 0;
    for (unsigned l = 0; l < ALB_VP_MAX_LEVELS; l++)
        n += st->cells[l];
    return n;
}

/* GP + VP on the scene's frame 0 (repeated for a stable time); -1 on error. */
static int measure(const alb_scene *s, const alb_profile *p, run_result *r, double *ms)
{
    alb_diag d;
    alb_diag_init(&d, stderr);
    alb_gp *gp = NULL;
    alb_vp *vp = NULL;
    alb_ws_buf b;
    alb_ws_buf_init(&b);
    alb_gp_stats gst;
    int rc = -1;
    if (alb_gp_create(&gp, s, p, &d) || alb_vp_create(&vp, p, &d))
        goto out;
    alb_gp_stream_header(gp, &b);
    if (alb_gp_frame(gp, 0, &b, &gst, &d))
        goto out;
    alb_ws_put_end(&b);
    double t0 = now(), t;
    unsigned reps = 0;
    do {
        r->frames = 0;
        if (alb_vp_run_stream(vp, b.w, b.n, "bench", keep, r, &d)) {
            alb_diag_print(&d, stderr);
            goto out;
        }
        reps++;
        t = now() - t0;
    } while (t < 0.5 && reps < 50);
    *ms = 1000 * t / reps;
    rc = 0;
out:
    alb_vp_destroy(vp);
    alb_gp_destroy(gp);
    alb_ws_buf_free(&b);
    return rc;
}

static void set_resolution(alb_profile *p, unsigned res)
{
    unsigned lg = 0;
    while ((1u << lg) < res)
        lg++;
    p->width = p->height = res;
    p->edge_frac_bits = lg + 5;   /* six bits below the pixel, as the profiles */
}

int main(void)
{
    alb_profile p;
    alb_profile_lookup("a512", &p);
    alb_scene s;
    alb_diag d;
    alb_diag_init(&d, stderr);
    if (alb_scene_load_builtin(&s, &d)) {
        alb_diag_print(&d, stderr);
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
    alb_scene_free(&s);
    printf("\n## Face count (random scenes, 1024²)\n\n"
           "| faces | cells visited | cells / face | samples written | ms |\n"
           "|---|---|---|---|---|\n");
    set_resolution(&p, 1024);
    for (unsigned n = 10; n <= 10000; n *= 10) {
        scenegen_params gp = scenegen_defaults();
        gp.faces = n;
        gp.size = 0.3 / (n < 100 ? 1 : n < 1000 ? 3 : n < 10000 ? 10 : 30);
        char *text = scenegen_random(1, &gp);
        if (!text || alb_scene_parse(text, strlen(text), "random", &s, &d)) {
            alb_diag_print(&d, stderr);
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
        alb_scene_free(&s);
    }
    return 0;
}
