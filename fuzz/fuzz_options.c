/* fuzz_options.c — the profile and option parsers (common/profile.c,
 * emu/cli.c): the options-file tokenizer on the whole input, then records
 * separated by NUL or newline, each "NAME=VALUE" given to run_opts_apply
 * (profile, set, eye, at, up, fov, size) or, for any other name, the whole
 * record to alb_profile_set; then alb_profile_check.  A profile it accepts must
 * survive alb_profile_describe -> alb_profile_set unchanged, and must run: the GP on
 * a cube imported with the fuzzed camera, and on small screens the VP at all
 * three fidelities on the GP's stream. */
#include "fuzz.h"
#include "../emu/cli.h"
#include "albatros/sim.h"
#include "albatros/gp.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Screens up to this many samples (pixels x 4^aa) also run the VP. */
#define VP_SAMPLES_MAX (1u << 14)
/* ... and the cycle model, when the GP's clocks per face stay below this. */
#define CYCLE_GP_MAX 20000u

static const char cube_obj[] =
    "v -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\nv -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1\n"
    "f 5 6 7 8\nf 2 1 4 3\nf 6 2 3 7\nf 1 5 8 4\nf 8 7 3 4\nf 1 2 6 5\n";

static const char *cube_path(void)
{
    static char path[512];
    if (!path[0] && fuzz_write("cube.obj", cube_obj, sizeof cube_obj - 1, path, sizeof path))
        path[0] = 0;
    return path[0] ? path : NULL;
}

static void apply_records(char *text, size_t size, run_opts *o)
{
    char err[400];
    for (size_t pos = 0; pos < size;) {
        char *rec = text + pos;
        size_t len = 0;
        while (pos + len < size && rec[len] && rec[len] != '\n')
            len++;
        rec[len] = 0;   /* text has a NUL after its last byte */
        pos += len + 1;
        char *eq = strchr(rec, '=');
        int taken = 0;
        if (eq) {
            *eq = 0;
            taken = run_opts_apply(o, rec, eq + 1, err, sizeof err);
            *eq = '=';
        }
        if (!taken && *rec)
            alb_profile_set(&o->prof, rec, err, sizeof err);
    }
}

/* alb_profile_describe's lines, given back to alb_profile_set on another profile,
 * rebuild this one. */
static void check_describe(const alb_profile *p)
{
    char want[2048], got[2048], err[400];
    alb_profile q;
    if (alb_profile_lookup(p->cull_backfaces ? "t32" : "a1024", &q))
        abort();
    q.cull_backfaces = !p->cull_backfaces;
    q.bound = p->bound == ALB_BOUND_NONE ? ALB_BOUND_BOX : ALB_BOUND_NONE;
    memcpy(q.name, p->name, sizeof q.name);
    alb_profile_describe(p, want, sizeof want);
    memcpy(got, want, sizeof got);
    char *line = strchr(got, '\n');   /* past "profile=NAME" */
    while (line && *++line) {
        char *end = strchr(line, '\n');
        if (end)
            *end = 0;
        if (alb_profile_set(&q, line, err, sizeof err)) {
            fprintf(stderr, "fuzz_options: profile_set rejects profile_describe's '%s': %s\n",
                    line, err);
            abort();
        }
        line = end;
    }
    alb_profile_describe(&q, got, sizeof got);
    if (strcmp(got, want)) {
        fprintf(stderr, "fuzz_options: profile_describe -> profile_set changed the profile:\n"
                        "%s---\n%s", want, got);
        abort();
    }
}

static unsigned frame_sum(const alb_frame *f)
{
    unsigned sum = 0;
    for (size_t i = 0; i < (size_t)f->width * f->height; i++)
        sum += f->rgb[3 * i] + f->depth[i] + f->face[i] + f->level[i] + f->coverage[i] +
               (f->cycles ? f->cycles[i] : 0);
    return sum;
}

static int sink(void *ctx, const alb_frame *f, const alb_vp_stats *vs, const alb_sim_counters *sc)
{
    *(unsigned *)ctx += frame_sum(f) + (unsigned)vs->faces + (unsigned)(sc ? sc->cycles : 0);
    return 0;
}

static void run_vp(const alb_profile *p, const alb_ws_buf *b)
{
    uint64_t samples = ((uint64_t)p->width * p->height) << (2 * p->aa_levels);
    if (samples > VP_SAMPLES_MAX)
        return;
    bool cycle = p->gp_face_cycles + 64ull * p->gp_edge_cycles + p->gp_frame_cycles +
                 p->divider_latency + p->shade_latency <= CYCLE_GP_MAX;
    unsigned sum = 0;
    for (int fid = ALB_FIDELITY_FUNCTIONAL; fid <= (cycle ? ALB_FIDELITY_CYCLE : ALB_FIDELITY_TIMED); fid++) {
        alb_sim_options opt = {.fid = (alb_fidelity)fid, .vcd_to = UINT64_MAX, .threads = 1};
        alb_diag d;
        alb_diag_init(&d, NULL);
        alb_sim_run(p, b->w, b->n, "<gp>", &opt, sink, &sum, &d);
    }
    volatile unsigned keep = sum;
    (void)keep;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    const char *cube = cube_path();
    char *text = malloc(size + 1), *copy = malloc(size + 1);
    if (!cube || !text || !copy) {
        free(text);
        free(copy);
        return 0;
    }
    memcpy(text, data, size);
    text[size] = 0;
    memcpy(copy, text, size + 1);
    char *argv[64];
    cli_split_words(copy, argv, 64);
    free(copy);

    run_opts o;
    run_opts_init(&o);
    apply_records(text, size, &o);
    free(text);
    char msg[300];
    if (alb_profile_check(&o.prof, msg, sizeof msg))
        return 0;
    check_describe(&o.prof);

    alb_scene_camera cam = o.cam;   /* as cli_load_scene gives it to the importer */
    cam.width = o.prof.width;
    cam.height = o.prof.height;
    alb_diag d;
    alb_diag_init(&d, NULL);
    alb_scene s;
    if (alb_scene_load_obj(cube, &cam, &s, &d) != ALB_OK)
        return 0;
    alb_ws_buf b;
    if (fuzz_run_gp(&s, &o.prof, &b) == 0) {
        run_vp(&o.prof, &b);
        alb_ws_buf_free(&b);
    }
    alb_scene_free(&s);
    return 0;
}
