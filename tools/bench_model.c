/* bench_model.c — the step-and-compare API against `render --fidelity
 * cycle` (docs/performance.md, "The model through the API"): emulated
 * cycles per second on the built-in scene with every event off, with frame
 * events, and with every event on (read as they come, as a scoreboard
 * would), beside alb_sim_run, the command's path.  Figures, not tests: run
 * by `make bench`. */
#include "albatros/albatros.h"

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

static int no_sink(void *ctx, const alb_frame *f, const alb_vp_stats *s, const alb_sim_counters *c)
{
    (void)f, (void)s;
    *(uint64_t *)ctx = c->retire + 1;
    return 0;
}

/* Best of three: seconds of alb_sim_run at cycle fidelity; *cycles run. */
static double run_sim(const alb_profile *p, const uint32_t *w, size_t n, uint64_t *cycles)
{
    double best = 1e9;
    for (int rep = 0; rep < 3; rep++) {
        alb_sim_options o = {.fid = ALB_FIDELITY_CYCLE, .threads = 1};
        alb_diag d;
        alb_diag_init(&d, stderr);
        double t0 = now();
        if (alb_sim_run(p, w, n, "bench", &o, no_sink, cycles, &d))
            exit(1);
        double s = now() - t0;
        best = s < best ? s : best;
    }
    return best;
}

/* Best of three through alb_model with these events, read every 4096
 * cycles; *events counted. */
static double run_model(const alb_profile *p, const uint32_t *w, size_t n, uint32_t mask,
                        uint64_t *events)
{
    double best = 1e9;
    for (int rep = 0; rep < 3; rep++) {
        alb_model_config c;
        alb_model_config_default(&c);
        c.events = mask;
        alb_model *m;
        alb_diag d;
        if (alb_model_create(&m, p, &c, &d))
            exit(1);
        uint64_t k = 0, sum = 0;
        double t0 = now();
        alb_model_push(m, w, n);
        while (!alb_model_done(m)) {
            if (alb_model_step(m, 4096))
                exit(1);
            const alb_event *ev;
            size_t got = alb_model_events(m, &ev);
            for (size_t i = 0; i < got; i++)
                sum += ev[i].cycle ^ ev[i].kind;   /* touch them, as a scoreboard would */
            k += got;
            alb_model_consume(m, got);
        }
        double s = now() - t0;
        alb_model_destroy(m);
        best = s < best ? s : best;
        *events = k + (sum == 1);   /* keep sum alive */
    }
    return best;
}

static void bench(const char *profile)
{
    alb_profile p;
    alb_profile_lookup(profile, &p);
    uint32_t *w;
    size_t n;
    alb_diag d;
    if (alb_gp_compile_file(NULL, profile, NULL, &w, &n, &d)) {
        alb_diag_print(&d, stderr);
        exit(1);
    }
    uint64_t cycles = 0, e0, e1, e2;
    double s_run = run_sim(&p, w, n, &cycles);
    double s_off = run_model(&p, w, n, 0, &e0);
    double s_frame = run_model(&p, w, n, ALB_EV_FRAME, &e1);
    double s_all = run_model(&p, w, n, ALB_EV_ALL, &e2);
    printf("| %s | %.2f | %.2f (%.2fx) | %.2f (%.2fx) | %.2f (%.2fx), %.1f M events |\n", profile,
           cycles / s_run / 1e6, cycles / s_off / 1e6, s_run / s_off, cycles / s_frame / 1e6,
           s_run / s_frame, cycles / s_all / 1e6, s_run / s_all, e2 / 1e6);
    free(w);
}

/* One run of one configuration (for callgrind's instruction counts):
 * bench-model --one PROFILE sim|off|frame|all */
static int one(const char *profile, const char *mode)
{
    alb_profile p;
    uint32_t *w;
    size_t n;
    alb_diag d;
    if (alb_profile_lookup(profile, &p) || alb_gp_compile_file(NULL, profile, NULL, &w, &n, &d))
        return 2;
    uint64_t x = 0;
    if (!strcmp(mode, "sim")) {
        alb_sim_options o = {.fid = ALB_FIDELITY_CYCLE, .threads = 1};
        if (alb_sim_run(&p, w, n, "bench", &o, no_sink, &x, &d))
            return 1;
    } else {
        uint32_t mask = !strcmp(mode, "off") ? 0 : !strcmp(mode, "frame") ? ALB_EV_FRAME : ALB_EV_ALL;
        alb_model_config c;
        alb_model_config_default(&c);
        c.events = mask;
        alb_model *m;
        if (alb_model_create(&m, &p, &c, &d))
            return 1;
        alb_model_push(m, w, n);
        while (!alb_model_done(m)) {
            if (alb_model_step(m, 4096))
                return 1;
            const alb_event *ev;
            size_t k = alb_model_events(m, &ev);
            for (size_t i = 0; i < k; i++)
                x += ev[i].cycle ^ ev[i].kind;
            alb_model_consume(m, k);
        }
        alb_model_destroy(m);
    }
    free(w);
    printf("%llu\n", (unsigned long long)x);
    return 0;
}

int main(int argc, char **argv)
{
    if (argc == 4 && !strcmp(argv[1], "--one"))
        return one(argv[2], argv[3]);
    printf("## The model through the API (built-in scene, cycle fidelity, one core)\n\n"
           "M emulated cycles per second; in brackets, the speed against alb_sim_run "
           "(render --fidelity cycle)\n\n"
           "| profile | alb_sim_run | alb_model, events off | frame events | every event |\n"
           "|---|---|---|---|---|\n");
    bench("t32");
    bench("a256");
    bench("a1024");
    return 0;
}
