/* test_timing.c — the clocked model: hand-computed cycle counts of tiny
 * streams (docs/microarchitecture.md), cycle == timed on every counter and
 * functional == cycle on every pixel over random scenes and odd parameter
 * sets, monotonicity, and the VCD trace read back by a parser. */
#include "t.h"
#include "gp_helpers.h"
#include "albatros/sim.h"
#include "albatros/vcd.h"
#include "../tools/scenegen.h"

#include <dirent.h>
#include <stdlib.h>
#include <string.h>

#define MAX_FRAMES 8

typedef struct {
    unsigned n;
    alb_sim_counters c[MAX_FRAMES];
    alb_vp_stats s[MAX_FRAMES];
    alb_frame f[MAX_FRAMES];
} run_log;

static int log_frame(void *ctx, const alb_frame *f, const alb_vp_stats *vs, const alb_sim_counters *sc)
{
    run_log *l = ctx;
    if (l->n == MAX_FRAMES)
        return 0;
    l->s[l->n] = *vs;
    if (sc)
        l->c[l->n] = *sc;
    if (alb_frame_copy(&l->f[l->n], f))
        return -1;
    l->n++;
    return 0;
}

static void log_free(run_log *l)
{
    for (unsigned i = 0; i < l->n; i++)
        alb_frame_free(&l->f[i]);
    l->n = 0;
}

static alb_err run_threads(const alb_profile *p, const alb_ws_buf *b, alb_fidelity fid, unsigned threads,
                           run_log *l, alb_vcd *v)
{
    alb_diag d;
    alb_diag_init(&d, NULL);
    alb_sim_options o = {.fid = fid, .vcd = v, .vcd_to = UINT64_MAX, .threads = threads};
    memset(l, 0, sizeof *l);
    alb_err e = alb_sim_run(p, b->w, b->n, "test", &o, log_frame, l, &d);
    if (e)
        fprintf(stderr, "sim_run: %s\n", d.msg);
    return e;
}

/* A clocked run with counters_only: each frame's counters and statistics,
 * and how many frames came with a plane (there must be none). */
typedef struct {
    unsigned n, with_planes;
    alb_sim_counters c[MAX_FRAMES];
    alb_vp_stats s[MAX_FRAMES];
} counters_log;

static int log_counters(void *ctx, const alb_frame *f, const alb_vp_stats *vs,
                        const alb_sim_counters *sc)
{
    counters_log *l = ctx;
    l->with_planes += f->rgb || f->depth || f->face || f->level || f->coverage || f->cycles;
    if (l->n < MAX_FRAMES) {
        l->c[l->n] = *sc;
        l->s[l->n] = *vs;
    }
    l->n++;
    return 0;
}

static alb_err run_counters(const alb_profile *p, const alb_ws_buf *b, alb_fidelity fid,
                            counters_log *l)
{
    alb_diag d;
    alb_diag_init(&d, NULL);
    alb_sim_options o = {.fid = fid, .counters_only = true};
    memset(l, 0, sizeof *l);
    return alb_sim_run(p, b->w, b->n, "test", &o, log_counters, l, &d);
}

static alb_err run(const alb_profile *p, const alb_ws_buf *b, alb_fidelity fid, run_log *l, alb_vcd *v)
{
    return run_threads(p, b, fid, 1, l, v);
}

static alb_profile t32_fast_gp(void)
{
    alb_profile p;
    alb_profile_lookup("t32", &p);
    p.gp_face_cycles = 10;
    p.gp_edge_cycles = 0;
    p.gp_frame_cycles = 0;
    return p;
}

/* A stream of one frame with the given faces (screen-covering faces with
 * the given edges). */
static void one_frame(alb_ws_buf *b, const alb_profile *p, const alb_ws_face *faces, unsigned n)
{
    alb_ws_buf_init(b);
    alb_ws_config cfg = {p->edge_frac_bits, p->coef_bits, 1.0f};
    alb_ws_put_config(b, &cfg);
    alb_ws_frame fr = {0, 0x101010, false, 0, 0, 0};
    alb_ws_put_frame(b, &fr);
    for (unsigned i = 0; i < n; i++)
        alb_ws_put_face(b, &faces[i]);
    alb_ws_put_frame_end(b, n);
    alb_ws_put_end(b);
}

/* A face at depth 1/2 everywhere (near/Z = 0.5), no edges: the whole screen. */
static alb_ws_face whole_screen(uint32_t id)
{
    alb_ws_face f;
    memset(&f, 0, sizeof f);
    f.id = id;
    f.rgb = 0xFF8040;
    f.depth = (alb_ws_form){-1, {0, 0, 1}};
    return f;
}

TEST(timing_worked_example_whole_screen_face)
{
    /* docs/microarchitecture.md, "Worked example": 295 cycles */
    alb_profile p = t32_fast_gp();
    alb_ws_face f = whole_screen(0);
    alb_ws_buf b;
    one_frame(&b, &p, &f, 1);
    run_log l;
    for (int fid = ALB_FIDELITY_TIMED; fid <= ALB_FIDELITY_CYCLE; fid++) {
        CHECK(run(&p, &b, (alb_fidelity)fid, &l, NULL) == ALB_OK);
        CHECK_EQ(l.n, 1);
        CHECK_EQ(l.c[0].cycles, 295);
        CHECK_EQ(l.c[0].engine_busy, 1);
        CHECK_EQ(l.c[0].fill_busy, 256);
        CHECK_EQ(l.c[0].gp_busy, 10 + 17);   /* compute + the words up to FRAME_END and END */
        CHECK_EQ(l.c[0].parser_busy, 16);
        /* every sample written: the whole screen has the face */
        CHECK_EQ(l.n ? l.f[0].face[32 * 32 - 1] : 99, 0);
        log_free(&l);
    }
    alb_ws_buf_free(&b);
}

TEST(timing_face_rejected_at_top_level)
{
    /* one vertical edge at x = 2, face to its right: the screen is outside.
     * GP: words 0-7 in cycles 0-7, computes 8-17, the face's 9 words in
     * 18-26, FRAME_END 27, END 28.  Parser: each word a cycle later, starving
     * in cycle 0 and 9-18; the face loaded in 27, FRAME_END taken in 28.
     * Engine: one 1-cycle step in 28, rejected.  Retires in 28: 29 cycles. */
    alb_profile p = t32_fast_gp();
    alb_ws_face f = whole_screen(0);
    f.n_edges = 1;
    f.edge[0] = (alb_ws_edge){1, 0, 5u << p.edge_frac_bits, 5u << p.edge_frac_bits};
    alb_ws_buf b;
    one_frame(&b, &p, &f, 1);
    run_log l;
    for (int fid = ALB_FIDELITY_TIMED; fid <= ALB_FIDELITY_CYCLE; fid++) {
        CHECK(run(&p, &b, (alb_fidelity)fid, &l, NULL) == ALB_OK);
        CHECK_EQ(l.c[0].cycles, 29);
        CHECK_EQ(l.c[0].engine_busy, 1);
        CHECK_EQ(l.c[0].fill_busy, 0);
        CHECK_EQ(l.c[0].gp_busy, 19 + 10);
        CHECK_EQ(l.c[0].parser_busy, 18);
        CHECK_EQ(l.c[0].parser_starve, 11);
        CHECK_EQ(l.f[0].face[0], ALB_FRAME_NO_FACE);
        log_free(&l);
    }
    alb_ws_buf_free(&b);
}

TEST(timing_full_fifo_stalls_the_gp)
{
    /* Two screen-covering faces, one face slot, a 2-word FIFO, no GP compute.
     * The second face's words wait for the slot (blocked in 16), so the FIFO
     * fills and the GP stalls in cycle 17.  Face 1 is loaded in 23, starts in
     * 24, its cell waits for the fill unit (busy 17-272) and is filled in
     * 273-528, written by 540: 541 cycles. */
    alb_profile p = t32_fast_gp();
    p.gp_face_cycles = 0;
    p.face_slots = 1;
    p.fifo_depth = 2;
    alb_ws_face f[2] = {whole_screen(0), whole_screen(1)};
    alb_ws_buf b;
    one_frame(&b, &p, f, 2);
    run_log l;
    for (int fid = ALB_FIDELITY_TIMED; fid <= ALB_FIDELITY_CYCLE; fid++) {
        CHECK(run(&p, &b, (alb_fidelity)fid, &l, NULL) == ALB_OK);
        CHECK_EQ(l.c[0].cycles, 541);
        CHECK_EQ(l.c[0].gp_stall, 1);
        /* blocked in 16 for the slot, then 25-540 holding END for retirement */
        CHECK_EQ(l.c[0].parser_blocked, 1 + 516);
        CHECK_EQ(l.c[0].fifo_peak, 2);
        CHECK_EQ(l.c[0].fill_busy, 512);
        /* the equal depths keep face 0 */
        CHECK_EQ(l.f[0].face[100], 0);
        log_free(&l);
    }
    alb_ws_buf_free(&b);
}

/* The stream of a scene text for profile p. */
static bool counters_equal(const alb_sim_counters *a, const alb_sim_counters *b)
{
#define EQ(field) if (a->field != b->field) return false;
    ALB_SIM_COUNTER_FIELDS(EQ)
#undef EQ
    return true;
}

static bool frames_equal(const alb_frame *a, const alb_frame *b, bool cycles)
{
    size_t n = (size_t)a->width * a->height;
    return !memcmp(a->rgb, b->rgb, 3 * n * sizeof *a->rgb) &&
           !memcmp(a->depth, b->depth, n * sizeof *a->depth) &&
           !memcmp(a->face, b->face, n * sizeof *a->face) &&
           !memcmp(a->level, b->level, n) &&
           (!cycles || !memcmp(a->cycles, b->cycles, n * sizeof *a->cycles));
}

/* The functional renderer on several threads (vp/parallel.c) against one:
 * every plane of every frame and every statistic the same. */
static void check_threads(const alb_profile *p, const alb_ws_buf *b, const run_log *lf,
                          const char *what)
{
    static const unsigned counts[] = {2, 3, 5, 8};
    for (unsigned k = 0; k < sizeof counts / sizeof counts[0]; k++) {
        run_log lm;
        if (run_threads(p, b, ALB_FIDELITY_FUNCTIONAL, counts[k], &lm, NULL)) {
            CHECK_MSG(0, "%s: the run on %u threads failed", what, counts[k]);
            continue;
        }
        CHECK_MSG(lm.n == lf->n, "%s: %u frames on %u threads, %u on one", what, lm.n,
                  counts[k], lf->n);
        for (unsigned i = 0; i < lm.n && i < lf->n; i++) {
            CHECK_MSG(alb_frame_count_differences(&lm.f[i], &lf->f[i]) == 0,
                      "%s frame %u: %zu pixels differ on %u threads", what, i,
                      alb_frame_count_differences(&lm.f[i], &lf->f[i]), counts[k]);
            CHECK_MSG(!memcmp(&lm.s[i], &lf->s[i], sizeof lm.s[i]),
                      "%s frame %u: statistics differ on %u threads", what, i, counts[k]);
        }
        log_free(&lm);
    }
}

/* cycle == timed (counters, frames, per-pixel cycles); functional == both
 * on pixels, on any number of threads. */
static void check_fidelities(const alb_profile *p, const alb_ws_buf *b, const char *what)
{
    run_log lf, lt, lc;
    if (run(p, b, ALB_FIDELITY_FUNCTIONAL, &lf, NULL) || run(p, b, ALB_FIDELITY_TIMED, &lt, NULL) ||
        run(p, b, ALB_FIDELITY_CYCLE, &lc, NULL)) {
        CHECK_MSG(0, "%s: a run failed", what);
        return;
    }
    CHECK(lt.n == lc.n && lf.n == lc.n && lc.n > 0);
    for (unsigned i = 0; i < lc.n && i < lt.n && i < lf.n; i++) {
        CHECK_MSG(counters_equal(&lt.c[i], &lc.c[i]),
                  "%s frame %u: timed %llu cycles, cycle %llu (or a counter differs)", what, i,
                  (unsigned long long)lt.c[i].cycles, (unsigned long long)lc.c[i].cycles);
        CHECK_MSG(frames_equal(&lt.f[i], &lc.f[i], true), "%s frame %u: timed/cycle frames", what, i);
        CHECK_MSG(frames_equal(&lf.f[i], &lc.f[i], false), "%s frame %u: functional/cycle", what, i);
        /* the frame's nearest surface: the largest depth of its depth plane */
        uint64_t nearest = 0;
        for (size_t k = 0; k < (size_t)lf.f[i].width * lf.f[i].height; k++)
            nearest = lf.f[i].depth[k] > nearest ? lf.f[i].depth[k] : nearest;
        CHECK_MSG(lf.s[i].depth_nearest == nearest, "%s frame %u: depth_nearest %llu, the "
                  "frame's largest depth %llu", what, i,
                  (unsigned long long)lf.s[i].depth_nearest, (unsigned long long)nearest);
        /* the functional engine walks faces its own way (vp_draw_face), the
         * clocked models step by step: every statistic must agree */
        CHECK_MSG(!memcmp(&lf.s[i], &lt.s[i], sizeof lf.s[i]) &&
                      !memcmp(&lc.s[i], &lt.s[i], sizeof lc.s[i]),
                  "%s frame %u: statistics differ between the fidelities", what, i);
    }
    /* no frame asked for: the depth tests alone, the same counters and
     * statistics, frames without planes */
    for (int fid = ALB_FIDELITY_TIMED; fid <= ALB_FIDELITY_CYCLE; fid++) {
        counters_log lo;
        if (run_counters(p, b, (alb_fidelity)fid, &lo)) {
            CHECK_MSG(0, "%s: the %s run without frames failed", what,
                      alb_fidelity_name((alb_fidelity)fid));
            continue;
        }
        CHECK_MSG(lo.n == lt.n && lo.with_planes == 0, "%s, %s without frames: %u frames, %u "
                  "with planes", what, alb_fidelity_name((alb_fidelity)fid), lo.n, lo.with_planes);
        for (unsigned i = 0; i < lo.n && i < lt.n; i++)
            CHECK_MSG(counters_equal(&lo.c[i], &lt.c[i]) &&
                          !memcmp(&lo.s[i], &lt.s[i], sizeof lo.s[i]),
                      "%s frame %u: %s without frames: a counter or statistic differs", what, i,
                      alb_fidelity_name((alb_fidelity)fid));
    }
    /* the plain forms (simd=0: the fill's plain C, the engine's baseline
     * lanes) give the same frames, statistics and counters */
    alb_profile plain = *p;
    plain.simd = 0;
    run_log lfp, ltp;
    if (run(&plain, b, ALB_FIDELITY_FUNCTIONAL, &lfp, NULL) ||
        run(&plain, b, ALB_FIDELITY_TIMED, &ltp, NULL)) {
        CHECK_MSG(0, "%s: a run with simd=0 failed", what);
    } else {
        CHECK(lfp.n == lf.n && ltp.n == lt.n);
        for (unsigned i = 0; i < lfp.n && i < lf.n && i < ltp.n && i < lt.n; i++) {
            CHECK_MSG(frames_equal(&lfp.f[i], &lf.f[i], false) &&
                          !memcmp(&lfp.s[i], &lf.s[i], sizeof lf.s[i]),
                      "%s frame %u: functional with simd=0 differs", what, i);
            CHECK_MSG(frames_equal(&ltp.f[i], &lt.f[i], true) &&
                          !memcmp(&ltp.s[i], &lt.s[i], sizeof lt.s[i]) &&
                          counters_equal(&ltp.c[i], &lt.c[i]),
                      "%s frame %u: timed with simd=0 differs", what, i);
        }
        log_free(&lfp);
        log_free(&ltp);
    }
    /* and the timed model without frames (its store without tags,
     * vp_create_counters) in the plain forms: the same counters */
    counters_log lop;
    if (run_counters(&plain, b, ALB_FIDELITY_TIMED, &lop)) {
        CHECK_MSG(0, "%s: the timed run without frames with simd=0 failed", what);
    } else {
        CHECK(lop.n == lt.n && lop.with_planes == 0);
        for (unsigned i = 0; i < lop.n && i < lt.n; i++)
            CHECK_MSG(counters_equal(&lop.c[i], &lt.c[i]) && !memcmp(&lop.s[i], &lt.s[i], sizeof lt.s[i]),
                      "%s frame %u: timed without frames with simd=0 differs", what, i);
    }
    check_threads(p, b, &lf, what);
    log_free(&lf);
    log_free(&lt);
    log_free(&lc);
}

TEST(timing_cycle_equals_timed_on_random_scenes)
{
    /* small screens and odd parameters, so stalls of every kind happen */
    static const char *const sets[] = {
        "",
        "fifo_depth=3 face_slots=1 fill_queue=1",
        "edge_units=1 fill_rate=1 divider_latency=0 shade_latency=0",
        "fifo_depth=64 face_slots=4 fill_queue=8 fill_rate=16 gp_face_cycles=200",
        "aa=1 fill_rate=3 edge_units=3 gp_edge_cycles=40",
    };
    scenegen_params gp = scenegen_defaults();
    for (uint64_t seed = 1; seed <= 200; seed++) {
        alb_profile p;
        small_profile(&p, sets[seed % 5]);
        gp.faces = 2 + (unsigned)(seed % 23);
        alb_ws_buf b;
        char *text = random_frames_stream(seed, &gp, 0, &p, &b);
        if (!text) {
            CHECK_MSG(0, "seed %llu: no stream", (unsigned long long)seed);
            return;
        }
        char what[64];
        snprintf(what, sizeof what, "seed %llu", (unsigned long long)seed);
        check_fidelities(&p, &b, what);
        alb_ws_buf_free(&b);
        free(text);
    }
}

TEST(timing_cycle_equals_timed_on_builtin_scene)
{
    size_t len;
    const char *text = alb_scene_builtin_text(&len);
    char *copy = malloc(len + 1);
    memcpy(copy, text, len);
    copy[len] = 0;
    alb_profile p;
    alb_profile_lookup("a256", &p);
    alb_ws_buf b;
    CHECK(stream_of(copy, &p, &b) == 0);
    check_fidelities(&p, &b, "builtin");
    alb_ws_buf_free(&b);
    free(copy);
}

/* Monotonicity (docs/microarchitecture.md, "Monotonicity"): adding a face
 * at the end of a frame never shortens that frame, nor delays any earlier
 * event, so the last frame never retires earlier either — in every
 * configuration, here the odd ones of the fidelity test.  Each scene has two
 * frames, so the face added to frame 0 is inserted mid-stream; frame 1's own
 * cycle count may fall (it overlaps frame 0's drain) and is not checked. */
TEST(timing_more_faces_never_fewer_cycles)
{
    static const char *const sets[] = {
        "",
        "fifo_depth=3 face_slots=1 fill_queue=1",
        "edge_units=1 fill_rate=1 divider_latency=0 shade_latency=0",
        "fifo_depth=64 face_slots=4 fill_queue=8 fill_rate=16 gp_face_cycles=200",
        "aa=1 fill_rate=3 edge_units=3 gp_edge_cycles=40",
    };
    scenegen_params gp = scenegen_defaults();
    for (uint64_t seed = 1; seed <= 40; seed++) {
        alb_profile p;
        alb_profile_lookup("t32", &p);
        profile_set_all(&p, sets[seed % 5]);
        uint64_t prev = 0, prev_end = 0;
        for (unsigned n = 1; n <= 12; n++) {
            gp.faces = n;
            /* the same first n-1 polygons, one more at the end; two frames */
            char *text = scenegen_random(seed, &gp), *more = NULL;
            if (text && (more = realloc(text, strlen(text) + 16)) != NULL)
                strcat(text = more, "\nframe\nframe\n");
            alb_ws_buf b;
            run_log l;
            if (!more || stream_of(text, &p, &b) || run(&p, &b, ALB_FIDELITY_TIMED, &l, NULL)) {
                CHECK_MSG(0, "seed %llu n %u", (unsigned long long)seed, n);
                free(text);
                return;
            }
            CHECK_EQ(l.n, 2);
            CHECK_MSG(l.c[0].cycles >= prev, "seed %llu: %u faces %llu cycles < %llu",
                      (unsigned long long)seed, n, (unsigned long long)l.c[0].cycles,
                      (unsigned long long)prev);
            CHECK_MSG(l.c[1].retire >= prev_end, "seed %llu: %u faces end in %llu < %llu",
                      (unsigned long long)seed, n, (unsigned long long)l.c[1].retire,
                      (unsigned long long)prev_end);
            prev = l.c[0].cycles;
            prev_end = l.c[1].retire;
            log_free(&l);
            alb_ws_buf_free(&b);
            free(text);
        }
    }
}

/* ---- the VCD trace, read back ---- */

typedef struct {
    char id[8];
    char name[96];            /* scope.signal, e.g. "fifo.push" */
    unsigned width;
    uint64_t value;
    long long since;          /* time of its last change */
    uint64_t sum;             /* value summed over the cycles seen */
    uint64_t high;            /* cycles with a non-zero value */
    long long first, last;    /* first and last cycle with a non-zero value, -1 none */
} vcd_var_decl;

typedef struct {
    vcd_var_decl vars[64];
    unsigned nvars;
} vcd_summary;

/* A signal's value held from its last change to time `now`, in cycles. */
static void vcd_hold(vcd_var_decl *v, long long now, long long period_ps)
{
    long long cycles = (now - v->since) / period_ps;
    if (v->value && cycles > 0) {
        v->sum += v->value * (uint64_t)cycles;
        v->high += (uint64_t)cycles;
        if (v->first < 0)
            v->first = v->since / period_ps;
        v->last = v->since / period_ps + cycles - 1;
    }
    v->since = now;
}

static const vcd_var_decl *vcd_signal(const vcd_summary *s, const char *name)
{
    for (unsigned i = 0; i < s->nvars; i++)
        if (!strcmp(s->vars[i].name, name))
            return &s->vars[i];
    CHECK_MSG(0, "the trace has no signal %s", name);
    return NULL;
}

/* Check the trace's structure and sum every signal over its cycles (a
 * value is held from its change at a rising edge to the next change or the
 * final timestamp); -1 (with a failed check) if it is malformed. */
static int vcd_parse(const char *path, long long period_ps, vcd_summary *s)
{
    memset(s, 0, sizeof *s);
    FILE *f = fopen(path, "r");
    if (!f) {
        CHECK_MSG(0, "no trace %s", path);
        return -1;
    }
    char scopes[8][32];
    unsigned depth = 0;
    char tok[256];
    bool timescale = false, enddef = false;
    /* header */
    while (!enddef && fscanf(f, "%255s", tok) == 1) {
        if (!strcmp(tok, "$timescale")) {
            CHECK(fscanf(f, "%255s", tok) == 1 && !strcmp(tok, "1ps"));
            timescale = true;
        } else if (!strcmp(tok, "$scope")) {
            CHECK(fscanf(f, "%255s", tok) == 1 && !strcmp(tok, "module"));
            CHECK(fscanf(f, "%255s", tok) == 1 && depth < 8);
            if (depth < 8)
                snprintf(scopes[depth++], sizeof scopes[0], "%.31s", tok);
        } else if (!strcmp(tok, "$upscope")) {
            CHECK(depth > 0);
            depth -= depth > 0;
        } else if (!strcmp(tok, "$var") && s->nvars < 64) {
            vcd_var_decl *v = &s->vars[s->nvars++];
            char name[64];
            CHECK(fscanf(f, "%255s %u %7s %63s", tok, &v->width, v->id, name) == 4);
            CHECK(!strcmp(tok, "wire") && v->width >= 1 && v->width <= 64);
            /* below the top scope "albatros": unit.signal */
            snprintf(v->name, sizeof v->name, "%.31s%s%.63s", depth > 1 ? scopes[depth - 1] : "",
                     depth > 1 ? "." : "", name);
            v->first = v->last = -1;
        } else if (!strcmp(tok, "$enddefinitions")) {
            enddef = true;
        } else if (!strcmp(tok, "$date")) {
            CHECK_MSG(0, "a $date makes traces differ between runs");
        }
    }
    /* every trace has the clock, whichever units it keeps */
    bool clk = false;
    for (unsigned i = 0; i < s->nvars; i++)
        clk |= !strcmp(s->vars[i].name, "clk") && s->vars[i].width == 1;
    CHECK(timescale && enddef && depth == 0 && clk);
    /* body: timestamps increasing, changes of declared variables */
    long long now = -1;
    bool ok = true;
    while (ok && fscanf(f, "%255s", tok) == 1) {
        if (tok[0] == '#') {
            long long t = atoll(tok + 1);
            ok = t > now || (now == 0 && t == 0);
            if (now >= 0 && t > now && t % period_ps != 0 && t % period_ps != period_ps / 2)
                ok = false;   /* only clock edges */
            now = t;
            continue;
        }
        if (tok[0] == '$')
            continue;   /* $dumpvars, $end */
        char val[80] = "", id[8] = "";
        if (tok[0] == 'b') {
            snprintf(val, sizeof val, "%.79s", tok + 1);
            ok = fscanf(f, "%7s", id) == 1;
        } else {
            val[0] = tok[0];
            snprintf(id, sizeof id, "%.7s", tok + 1);
        }
        int found = -1;
        for (unsigned i = 0; i < s->nvars; i++)
            if (!strcmp(s->vars[i].id, id))
                found = (int)i;
        ok = ok && found >= 0 && strlen(val) <= s->vars[found].width &&
             strspn(val, "01") == strlen(val);
        if (ok) {
            vcd_var_decl *v = &s->vars[found];
            vcd_hold(v, now, period_ps);
            v->value = strtoull(val, NULL, 2);
        }
    }
    fclose(f);
    CHECK_MSG(ok, "malformed trace near time %lld token '%s'", now, tok);
    for (unsigned i = 0; ok && i < s->nvars; i++)
        vcd_hold(&s->vars[i], now, period_ps);
    return ok ? 0 : -1;
}

/* A whole run traced: its frames in l, its trace summed in s. */
static int run_traced(const alb_profile *p, const alb_ws_buf *b, const char *path, run_log *l,
                      vcd_summary *s)
{
    alb_diag d;
    alb_diag_init(&d, NULL);
    alb_vcd *v = alb_vcd_open(path, &d);
    CHECK(v != NULL);
    if (!v)
        return -1;
    alb_err e = run(p, b, ALB_FIDELITY_CYCLE, l, v);
    CHECK(e == ALB_OK);
    CHECK(alb_vcd_close(v) == 0);
    /* every profile here runs at 10 MHz: 100000 ps a cycle */
    return e || vcd_parse(path, 1000000000ll / p->clock_khz, s) ? -1 : 0;
}

TEST(timing_vcd_trace_is_valid)
{
    alb_profile p = t32_fast_gp();
    p.fifo_depth = 2;
    p.face_slots = 1;
    p.gp_face_cycles = 0;
    alb_ws_face f[2] = {whole_screen(0), whole_screen(1)};
    alb_ws_buf b;
    one_frame(&b, &p, f, 2);
    char path[600];
    snprintf(path, sizeof path, "%s/t.vcd", t_tmpdir());
    run_log l;
    vcd_summary s;
    if (run_traced(&p, &b, path, &l, &s) == 0) {
        /* fifo.push was high in exactly as many cycles as the stream has
         * words (24) */
        const vcd_var_decl *push = vcd_signal(&s, "fifo.push");
        CHECK_EQ(push ? push->high : 0, 24);
        /* the second face ties with the first everywhere and loses: both
         * faces' samples pass the pipeline, only the first's are written */
        const vcd_var_decl *out = vcd_signal(&s, "pipe.samples"),
                           *wr = vcd_signal(&s, "pipe.written");
        CHECK_EQ(l.n, 1);
        CHECK_EQ(l.s[0].samples_written, 1024);
        CHECK_EQ(out ? out->sum : 0, l.s[0].samples_covered);
        CHECK_EQ(out ? out->sum : 0, 2048);
        CHECK_EQ(wr ? wr->sum : 0, l.s[0].samples_written);
    }
    log_free(&l);
    /* a second run gives the same bytes */
    char path2[600];
    snprintf(path2, sizeof path2, "%s/t2.vcd", t_tmpdir());
    alb_diag d;
    alb_diag_init(&d, NULL);
    alb_vcd *v = alb_vcd_open(path2, &d);
    CHECK(run(&p, &b, ALB_FIDELITY_CYCLE, &l, v) == ALB_OK);
    CHECK(alb_vcd_close(v) == 0);
    log_free(&l);
    char cmd[1300];
    snprintf(cmd, sizeof cmd, "cmp -s '%s' '%s'", path, path2);
    CHECK(system(cmd) == 0);
    alb_ws_buf_free(&b);
}

/* --vcd-units: the names are the scopes of a full trace; a list parses to
 * their bits, an unknown or empty name is pointed at. */
TEST(timing_vcd_unit_names)
{
    unsigned mask = 0, n = 0;
    const char *bad = NULL;
    size_t badlen = 99;
    while (alb_sim_trace_unit_name(n))
        n++;
    CHECK_EQ(n, 6);
    CHECK_EQ(ALB_SIM_TRACE_ALL, (1u << n) - 1);
    for (unsigned i = 0; i < n; i++) {
        CHECK(alb_sim_trace_units_parse(alb_sim_trace_unit_name(i), &mask, &bad, &badlen) == 0);
        CHECK_EQ(mask, 1u << i);
    }
    CHECK(alb_sim_trace_units_parse("all", &mask, &bad, &badlen) == 0);
    CHECK_EQ(mask, ALB_SIM_TRACE_ALL);
    CHECK(alb_sim_trace_units_parse("pipe,fifo,pipe", &mask, &bad, &badlen) == 0);
    CHECK_EQ(mask, 1u << 1 | 1u << 5);
    const char *list = "fifo,engines,pipe";
    CHECK(alb_sim_trace_units_parse(list, &mask, &bad, &badlen) == -1);
    CHECK(bad == list + 5 && badlen == 7);
    CHECK(alb_sim_trace_units_parse("fifo,", &mask, &bad, &badlen) == -1 && badlen == 0);
    CHECK(alb_sim_trace_units_parse("", &mask, &bad, &badlen) == -1 && badlen == 0);
    CHECK(alb_sim_trace_units_parse("FIFO", &mask, &bad, &badlen) == -1);
}

/* A trace that keeps only the fifo's scope: the clock and the open frame,
 * the fifo's signals with the same values as in the full trace, nothing
 * of the other units, and the same bytes twice. */
TEST(timing_vcd_units_keep_only_their_scopes)
{
    alb_profile p = t32_fast_gp();
    p.fifo_depth = 3;
    alb_ws_face f[3] = {whole_screen(0), whole_screen(1), whole_screen(2)};
    alb_ws_buf b;
    one_frame(&b, &p, f, 3);
    char full[600], part[600], part2[600];
    snprintf(full, sizeof full, "%s/full.vcd", t_tmpdir());
    snprintf(part, sizeof part, "%s/fifo.vcd", t_tmpdir());
    snprintf(part2, sizeof part2, "%s/fifo2.vcd", t_tmpdir());
    run_log l;
    vcd_summary sf, sp;
    bool have_full = run_traced(&p, &b, full, &l, &sf) == 0;
    log_free(&l);
    for (int k = 0; k < 2; k++) {
        alb_diag d;
        alb_diag_init(&d, NULL);
        alb_vcd *v = alb_vcd_open(k ? part2 : part, &d);
        CHECK(v != NULL && alb_vcd_keep_scope(v, "fifo") == 0);
        CHECK(run(&p, &b, ALB_FIDELITY_CYCLE, &l, v) == ALB_OK);
        CHECK(alb_vcd_close(v) == 0);
        log_free(&l);
    }
    if (have_full && vcd_parse(part, 1000000000ll / p.clock_khz, &sp) == 0) {
        CHECK_EQ(sp.nvars, 7);   /* clk, frame_open, the fifo's five */
        unsigned fifo = 0;
        for (unsigned i = 0; i < sp.nvars; i++) {
            const vcd_var_decl *a = &sp.vars[i], *w = vcd_signal(&sf, a->name);
            fifo += !strncmp(a->name, "fifo.", 5);
            CHECK_MSG(!strchr(a->name, '.') || !strncmp(a->name, "fifo.", 5),
                      "%s in a trace of the fifo", a->name);
            /* the same identifier and the same values, cycle for cycle */
            if (w)
                CHECK_MSG(!strcmp(a->id, w->id) && a->width == w->width && a->sum == w->sum &&
                          a->high == w->high && a->first == w->first && a->last == w->last,
                          "%s differs from the full trace", a->name);
        }
        CHECK_EQ(fifo, 5);
        const vcd_var_decl *push = vcd_signal(&sp, "fifo.push");
        CHECK_EQ(push ? push->high : 0, 31);   /* the stream's words */
    }
    char cmd[1300];
    snprintf(cmd, sizeof cmd, "cmp -s '%s' '%s'", part, part2);
    CHECK(system(cmd) == 0);
    alb_ws_buf_free(&b);
}

TEST(timing_vcd_pixel_writes_of_the_worked_example)
{
    /* docs/microarchitecture.md, "Worked example": samples issued 4 a cycle
     * in cycles 27-282 and written L - 1 = 12 cycles later, 39-294 */
    alb_profile p = t32_fast_gp();
    alb_ws_face f = whole_screen(0);
    alb_ws_buf b;
    one_frame(&b, &p, &f, 1);
    char path[600];
    snprintf(path, sizeof path, "%s/w.vcd", t_tmpdir());
    run_log l;
    vcd_summary s;
    if (run_traced(&p, &b, path, &l, &s) == 0) {
        const vcd_var_decl *issued = vcd_signal(&s, "fill.issued"),
                           *busy = vcd_signal(&s, "fill.busy"),
                           *strobe = vcd_signal(&s, "pipe.write"),
                           *wr = vcd_signal(&s, "pipe.written");
        if (issued && busy && strobe && wr) {
            CHECK_EQ(issued->sum, 1024);
            CHECK_EQ(busy->first, 27);
            CHECK_EQ(busy->last, 282);
            CHECK_EQ(strobe->high, 256);
            CHECK_EQ(strobe->first, 39);
            CHECK_EQ(strobe->last, 294);
            CHECK_EQ(wr->sum, l.s[0].samples_written);
            CHECK_EQ(wr->sum, 1024);
            CHECK_EQ(l.c[0].retire, 294);
        }
    }
    log_free(&l);
    alb_ws_buf_free(&b);
}


/* Over whole traces of random scenes (several frames, odd fill rates and
 * latencies, stalls): the samples written by the pipeline's last stage sum
 * to the frames' samples_written, and the samples through it to
 * samples_covered; with one sample a clock, write strobes count the writes. */
TEST(timing_vcd_pixel_writes_match_the_counters)
{
    static const char *const sets[] = {
        "",
        "fill_rate=1 divider_latency=0 shade_latency=0",
        "fill_rate=3 fill_queue=1 face_slots=1 fifo_depth=3",
        "aa=1 fill_rate=16 divider_latency=30",
    };
    scenegen_params gp = scenegen_defaults();
    for (uint64_t seed = 1; seed <= 8; seed++) {
        alb_profile p;
        alb_profile_lookup("t32", &p);
        profile_set_all(&p, sets[seed % 4]);
        gp.faces = 5 + (unsigned)(seed % 11);
        /* 1 to 3 frames of the same faces (each `frame` copies the last) */
        unsigned frames = 1 + (unsigned)(seed % 3);
        alb_ws_buf b;
        char *text = random_frames_stream(seed, &gp, frames, &p, &b);
        if (!text) {
            CHECK_MSG(0, "seed %llu: no stream", (unsigned long long)seed);
            return;
        }
        char path[600];
        snprintf(path, sizeof path, "%s/r.vcd", t_tmpdir());
        run_log l;
        vcd_summary s;
        if (run_traced(&p, &b, path, &l, &s) == 0) {
            uint64_t written = 0, covered = 0;
            for (unsigned i = 0; i < l.n; i++) {
                written += l.s[i].samples_written;
                covered += l.s[i].samples_covered;
            }
            const vcd_var_decl *out = vcd_signal(&s, "pipe.samples"),
                               *strobe = vcd_signal(&s, "pipe.write"),
                               *wr = vcd_signal(&s, "pipe.written");
            CHECK(written > 0 && l.n == frames);
            CHECK_MSG(wr && wr->sum == written, "seed %llu: %llu samples written in the trace, "
                      "%llu counted", (unsigned long long)seed,
                      (unsigned long long)(wr ? wr->sum : 0), (unsigned long long)written);
            CHECK_MSG(out && out->sum == covered, "seed %llu: samples through the pipeline",
                      (unsigned long long)seed);
            if (p.fill_rate == 1)
                CHECK_MSG(strobe && strobe->high == written, "seed %llu: write strobes",
                          (unsigned long long)seed);
            /* engine.state shows what the engine did in each cycle: 1 in its
             * busy cycles, 2 in its stalled ones (single-cycle steps too) */
            uint64_t busy = 0, stall = 0;
            for (unsigned i = 0; i < l.n; i++)
                busy += l.c[i].engine_busy, stall += l.c[i].engine_stall;
            const vcd_var_decl *eng = vcd_signal(&s, "engine.state");
            CHECK_MSG(eng && eng->high == busy + stall && eng->sum == busy + 2 * stall,
                      "seed %llu: engine.state high %llu sum %llu, counters busy %llu stall %llu",
                      (unsigned long long)seed, (unsigned long long)(eng ? eng->high : 0),
                      (unsigned long long)(eng ? eng->sum : 0), (unsigned long long)busy,
                      (unsigned long long)stall);
        }
        log_free(&l);
        alb_ws_buf_free(&b);
        free(text);
    }
}

/* cycle == timed == functional on every golden vector's stream, with the
 * vector's own profile (its options file: --profile and --set only). */
static void vector_fidelities(const char *name, const alb_profile *p, const alb_ws_buf *b,
                              void *ctx)
{
    (void)ctx;
    check_fidelities(p, b, name);
}

TEST(timing_fidelities_agree_on_every_vector)
{
    CHECK(for_each_vector(vector_fidelities, NULL) >= 12);
}

/* The timed model fed a stream in pieces of any size (the simulated board's
 * alb_sim_feed) gives each frame, at its FRAME_END, the pixels, statistics and
 * cycle count of the whole run. */
TEST(timing_feed_in_pieces_equals_the_whole_run)
{
    static const char *const sets[] = {
        "",
        "fifo_depth=3 face_slots=1 fill_queue=1",
        "aa=1 fill_rate=3 edge_units=3 gp_edge_cycles=40",
    };
    scenegen_params gp = scenegen_defaults();
    uint64_t rnd = 12345;
    for (uint64_t seed = 1; seed <= 30; seed++) {
        alb_profile p;
        alb_profile_lookup("t32", &p);
        profile_set_all(&p, sets[seed % 3]);
        gp.faces = 3 + (unsigned)(seed % 9);
        unsigned frames = 1 + (unsigned)(seed % 3);
        alb_ws_buf b;
        char *text = random_frames_stream(seed, &gp, frames - 1, &p, &b);
        if (!text) {
            CHECK_MSG(0, "seed %llu: no stream", (unsigned long long)seed);
            return;
        }
        run_log whole, pieces;
        CHECK(run_threads(&p, &b, ALB_FIDELITY_TIMED, 1, &whole, NULL) == ALB_OK);
        memset(&pieces, 0, sizeof pieces);
        alb_diag d;
        alb_diag_init(&d, NULL);
        alb_sim_feed *f = NULL;
        CHECK(alb_sim_feed_open(&f, &p, "pieces", log_frame, &pieces, &d) == ALB_OK);
        size_t n = 0;
        while (f && n < b.n) {
            rnd = rnd * 6364136223846793005ull + 1442695040888963407ull;
            size_t k = 1 + (size_t)(rnd >> 33) % 50;
            n = n + k < b.n ? n + k : b.n;
            if (alb_sim_feed_words(f, b.w, n, &d)) {
                CHECK_MSG(0, "seed %llu: %s", (unsigned long long)seed, d.msg);
                break;
            }
        }
        alb_sim_feed_close(f);
        CHECK_EQ(pieces.n, whole.n);
        for (unsigned i = 0; i < whole.n && i < pieces.n; i++) {
            CHECK_MSG(alb_frame_count_differences(&whole.f[i], &pieces.f[i]) == 0 &&
                      whole.c[i].cycles == pieces.c[i].cycles &&
                      whole.s[i].faces == pieces.s[i].faces,
                      "seed %llu frame %u: cycles %llu against %llu", (unsigned long long)seed, i,
                      (unsigned long long)pieces.c[i].cycles, (unsigned long long)whole.c[i].cycles);
        }
        log_free(&whole);
        log_free(&pieces);
        alb_ws_buf_free(&b);
        free(text);
    }
}
