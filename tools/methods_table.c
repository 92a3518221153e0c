/* methods_table.c — the classic methods and the VP side by side on the stress
 * families (docs/methods.md): pixels whose face differs from the exact
 * reference, mean over four seeds, and host milliseconds per frame.  Figures,
 * not tests (tests/test_methods.c holds the claims).
 * Usage: methods-table [PROFILE]   (default a256) */
#include "methods.h"
#include "ref.h"
#include "scenegen.h"
#include "stress.h"
#include "../emu/sim.h"
#include "../gp/gp.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define SEEDS 4
#define NROWS (sizeof rows / sizeof rows[0])

static double now_ms(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return 1e3 * (double)t.tv_sec + 1e-6 * (double)t.tv_nsec;
}

typedef struct {
    double diff, ms;
    bool failed;
} column;

static int keep_frame(void *ctx, const frame_t *f, const vp_stats *vs, const sim_counters *sc)
{
    (void)vs, (void)sc;
    frame_t *out = ctx;
    if (out->face)
        return 0;   /* frame 0 only */
    return frame_copy(out, f);
}

/* The VP's frame 0 through the GP and the functional model; -1 if the GP
 * refuses the scene (e.g. coordinates beyond its formats). */
static int vp_render(const scene_t *s, const profile_t *p, frame_t *out)
{
    diag_t d;
    diag_init(&d, NULL);
    gp_t *gp = NULL;
    ws_buf b;
    ws_buf_init(&b);
    memset(out, 0, sizeof *out);
    sim_options o = {FIDELITY_FUNCTIONAL, NULL, 0, 0};
    int rc = gp_create(&gp, s, p, &d) || gp_run(gp, &b, NULL, &d) ||
             sim_run(p, b.w, b.n, "methods-table", &o, keep_frame, out, &d) || !out->face;
    gp_destroy(gp);
    ws_buf_free(&b);
    if (rc && out->face)
        frame_free(out);
    return rc ? -1 : 0;
}

static void measure(column *col, unsigned k, const frame_t *ref, const frame_t *got, double ms)
{
    frame_diff df;
    frame_compare(ref, got, &df);
    col[k].diff += (double)df.face_diff / SEEDS;
    col[k].ms += ms / SEEDS;
}

static int scene_row(const char *text, const profile_t *p, column *col)
{
    scene_t s;
    diag_t d;
    diag_init(&d, NULL);
    frame_t ref, got;
    if (!text || scene_parse(text, strlen(text), "stress", &s, &d))
        return -1;
    if (ref_render(&s, p, 0, &ref)) {
        scene_free(&s);
        return -1;
    }
    unsigned n;
    const method *m = methods_all(&n);
    for (unsigned k = 0; k <= n; k++) {
        double t0 = now_ms();
        int rc = k < n ? m[k].render(&s, p, 0, &got) : vp_render(&s, p, &got);
        if (rc) {
            col[k].failed = true;
            continue;
        }
        measure(col, k, &ref, &got, now_ms() - t0);
        frame_free(&got);
    }
    frame_free(&ref);
    scene_free(&s);
    return 0;
}

static void print_row(const char *label, double sev, const column *col, unsigned ncol, bool ms)
{
    printf("| %s | %g |", label, sev);
    for (unsigned k = 0; k < ncol; k++) {
        if (col[k].failed)
            printf(" refused |");
        else
            printf(ms ? " %.1f |" : " %.0f |", ms ? col[k].ms : col[k].diff);
    }
    printf("\n");
}

static const struct {
    const char *family;
    double severity[4];
} rows[] = {
    {"sliver", {10, 1, 0.1, 0.01}},         {"crossing-z0", {0, 0.3, 0.7, 0.95}},
    {"far", {10, 1e3, 1e4, 1e6}},            {"texture-far", {10, 1e4, 1e8, 1e12}},
    {"interpenetrating", {45, 5, 0.5, 0.01}}, {"cyclic", {0.05, 0.1, 0.2, 0.4}},
    {"degenerate", {0.1, 1e-3, 1e-6, 1e-9}}, {"tjunction", {2, 8, 32, 64}},
    {"deep", {1, 8, 32, 64}},                {"coords", {-40, 0, 20, 40}},
};

static void header(const char *what, unsigned n, const method *m)
{
    printf("\n%s\n\n| family | severity |", what);
    for (unsigned k = 0; k < n; k++)
        printf(" %s |", m[k].name);
    printf(" VP |\n|---|---|");
    for (unsigned k = 0; k <= n; k++)
        printf("---|");
    printf("\n");
}

/* Every family row and severity through every method and the VP; the
 * columns of row r, severity j are col + (4 r + j) ncol. */
static int run_all(const profile_t *p, column *col, unsigned ncol)
{
    for (size_t r = 0; r < NROWS; r++)
        for (int j = 0; j < 4; j++)
            for (uint64_t seed = 1; seed <= SEEDS; seed++) {
                char *text = stress_scene(rows[r].family, rows[r].severity[j], seed);
                int rc = scene_row(text, p, col + (4 * r + (size_t)j) * ncol);
                free(text);
                if (rc) {
                    fprintf(stderr, "methods-table: %s %g does not render\n", rows[r].family,
                            rows[r].severity[j]);
                    return -1;
                }
            }
    return 0;
}

int main(int argc, char **argv)
{
    profile_t p;
    if (profile_lookup(argc > 1 ? argv[1] : "a256", &p)) {
        fprintf(stderr, "methods-table: unknown profile\n");
        return 2;
    }
    unsigned n;
    const method *m = methods_all(&n);
    column *col = calloc(NROWS * 4 * (n + 1), sizeof *col);
    if (!col || run_all(&p, col, n + 1)) {
        free(col);
        return 1;
    }
    printf("Profile %s, %u x %u.\n", p.name, p.width, p.height);
    for (int ms = 0; ms < 2; ms++) {
        header(ms ? "Host milliseconds per frame (one core; the VP column is GP + functional VP)"
                  : "Pixels whose face differs from the reference (mean of 4 seeds)", n, m);
        for (size_t r = 0; r < NROWS; r++)
            for (int j = 0; j < 4; j++)
                print_row(rows[r].family, rows[r].severity[j], col + (4 * r + (size_t)j) * (n + 1),
                          n + 1, ms);
    }
    free(col);
    return 0;
}
