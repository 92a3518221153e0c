/* test_model.c — alb_model, the step-and-compare API (docs/cosim.md): the
 * worked example's events cycle by cycle (docs/microarchitecture.md, worked
 * by hand), write events that rebuild every frame, an external producer
 * equal to the GP stage, stepping in any sizes, the three fidelities on the
 * golden vectors, masks, and errors. */
#include "t.h"
#include "gp_helpers.h"
#include "refpacket.h"
#include "albatros/albatros.h"
#include "../tools/scenegen.h"

#include <stdlib.h>
#include <string.h>

/* The frame CRC of docs/cosim.md: R, G, B of every pixel, 16-bit LE. */
static uint32_t frame_crc(const alb_frame *f)
{
    uint32_t crc = 0;
    for (size_t i = 0; i < 3 * (size_t)f->width * f->height; i++) {
        uint8_t b[2] = {(uint8_t)f->rgb[i], (uint8_t)(f->rgb[i] >> 8)};
        crc = ref_crc32_more(crc, b, 2);
    }
    return crc;
}

/* Every event of a run, in order. */
typedef struct {
    alb_event *e;
    size_t n, cap;
} ev_log;

static void log_take(ev_log *l, alb_model *m)
{
    const alb_event *ev;
    size_t k = alb_model_events(m, &ev);
    if (!k)
        return;
    if (l->n + k > l->cap) {
        size_t cap = l->cap ? l->cap : 1024;
        while (cap < l->n + k)
            cap *= 2;
        alb_event *ne = realloc(l->e, cap * sizeof *ne);
        if (!ne)
            return;
        l->e = ne;
        l->cap = cap;
    }
    memcpy(l->e + l->n, ev, k * sizeof *ev);
    l->n += k;
    alb_model_consume(m, k);
}

static size_t count_kind(const ev_log *l, uint32_t kind)
{
    size_t n = 0;
    for (size_t i = 0; i < l->n; i++)
        n += l->e[i].kind == kind;
    return n;
}

static alb_model *model(const alb_profile *p, alb_fidelity fid, alb_producer prod, uint32_t ev)
{
    alb_model_config c;
    alb_model_config_default(&c);
    c.fidelity = fid;
    c.producer = prod;
    c.events = ev;
    alb_model *m = NULL;
    alb_diag d;
    if (alb_model_create(&m, p, &c, &d)) {
        fprintf(stderr, "alb_model_create: %s\n", d.msg);
        return NULL;
    }
    return m;
}

/* A whole stream through a model with the GP producer, stepping `chunk`
 * clocks at a time, every event logged. */
static int run_all(alb_model *m, const alb_ws_buf *b, uint64_t chunk, ev_log *l)
{
    if (alb_model_push(m, b->w, b->n) != b->n)
        return -1;
    for (uint64_t guard = 0; !alb_model_done(m) && guard < 100000000; guard += chunk) {
        if (alb_model_step(m, chunk))
            return -1;
        log_take(l, m);
    }
    log_take(l, m);
    return alb_model_done(m) ? 0 : -1;
}

/* The worked example of docs/microarchitecture.md: t32, the GP at 10 cycles
 * a face and none per edge or frame, one face covering the screen. */
static void worked_example(alb_profile *p, alb_ws_buf *b)
{
    alb_profile_lookup("t32", p);
    p->gp_face_cycles = 10;
    p->gp_edge_cycles = 0;
    p->gp_frame_cycles = 0;
    alb_ws_buf_init(b);
    alb_ws_config cfg = {p->edge_frac_bits, p->coef_bits, 1.0f};
    alb_ws_put_config(b, &cfg);
    alb_ws_frame fr = {7, 0x101010, false, 0, 0, 0};
    alb_ws_put_frame(b, &fr);
    alb_ws_face f;
    memset(&f, 0, sizeof f);
    f.id = 42;
    f.rgb = 0xFF8040;
    f.depth = (alb_ws_form){-1, {0, 0, 1}};
    alb_ws_put_face(b, &f);
    alb_ws_put_frame_end(b, 1);
    alb_ws_put_end(b);
}

TEST(model_worked_example_event_by_event)
{
    alb_profile p;
    alb_ws_buf b;
    worked_example(&p, &b);
    alb_model *m = model(&p, ALB_FIDELITY_CYCLE, ALB_PRODUCER_GP, ALB_EV_ALL);
    ev_log l = {0};
    CHECK(m && run_all(m, &b, 1, &l) == 0);
    /* 17 words: CONFIG 3, FRAME 5, FACE 7, FRAME_END, END */
    CHECK_EQ(b.n, 17);
    CHECK_EQ(count_kind(&l, ALB_EV_PUSH), 17);
    CHECK_EQ(count_kind(&l, ALB_EV_POP), 17);
    for (size_t i = 0; i < l.n; i++) {
        const alb_event *e = &l.e[i];
        switch (e->kind) {
        case ALB_EV_PUSH:
            /* words 0-7 in cycles 0-7, the face's 7 words after 10 cycles
             * of compute in 18-24, FRAME_END in 25, END in 26 */
            CHECK_EQ(e->cycle, e->index < 8 ? e->index : e->index + 10);
            CHECK_EQ(e->word, b.w[e->index]);
            break;
        case ALB_EV_POP:
            if (e->index < 16)   /* each one cycle after its push */
                CHECK_EQ(e->cycle, (e->index < 8 ? e->index : e->index + 10) + 1);
            else                 /* END waits for the frame to retire (294) */
                CHECK_EQ(e->cycle, 295);
            break;
        case ALB_EV_LOAD:
            CHECK_EQ(e->cycle, 25);
            CHECK_EQ(e->face, 42);
            CHECK_EQ(e->slot, 0);
            CHECK_EQ(e->edges, 0);
            break;
        case ALB_EV_START:
        case ALB_EV_END:
            CHECK_EQ(e->cycle, 26);
            CHECK_EQ(e->face, 42);
            break;
        case ALB_EV_CELL:   /* one step: the top cell, no edges, filled */
            CHECK_EQ(e->cycle, 26);
            CHECK_EQ(e->result, 3);
            CHECK_EQ(e->level, 0);
            CHECK_EQ(e->wl, 5);
            CHECK_EQ(e->hl, 5);
            CHECK_EQ(e->edges, 0);
            break;
        case ALB_EV_FILL:
            CHECK_EQ(e->cycle, 27);
            CHECK_EQ(e->x + e->y, 0);
            break;
        case ALB_EV_WRITE: {
            /* 1024 samples, 4 a cycle from 27, written 12 cycles later,
             * in raster order within the cell */
            static unsigned k;
            unsigned idx = e->y * 32 + e->x;
            if (idx == 0)
                k = 0;
            CHECK_EQ(idx, k);
            CHECK_EQ(e->cycle, 27 + k / 4 + 12);
            k++;
            CHECK_EQ(e->face, 42);
            CHECK_EQ(e->depth, 1u << 23);   /* near/Z = 1/2 in 0.24 */
            CHECK_EQ(e->rgb[0], 255);
            CHECK_EQ(e->rgb[1], 128);
            CHECK_EQ(e->rgb[2], 64);
            break;
        }
        case ALB_EV_FRAME: {
            CHECK_EQ(e->cycle, 294);
            CHECK_EQ(e->cycles, 295);
            CHECK_EQ(e->number, 7);
            /* every pixel (255, 128, 64): the CRC from the bytes alone */
            uint8_t px[6] = {255, 0, 128, 0, 64, 0};
            uint32_t crc = 0;
            for (int px_i = 0; px_i < 1024; px_i++)
                crc = ref_crc32_more(crc, px, 6);
            CHECK_EQ(e->crc, crc);
            break;
        }
        default:
            CHECK_MSG(0, "unexpected event kind %u", e->kind);
        }
    }
    CHECK_EQ(count_kind(&l, ALB_EV_WRITE), 1024);
    CHECK_EQ(count_kind(&l, ALB_EV_FRAME), 1);
    CHECK_EQ(alb_model_frames(m), 1);
    const alb_sim_counters *c = alb_model_counters(m, 0);
    CHECK(c && c->cycles == 295 && c->retire == 294);
    /* in the documented order within each cycle, cycles never go back */
    for (size_t i = 1; i < l.n; i++)
        CHECK_MSG(l.e[i].cycle > l.e[i - 1].cycle ||
                  (l.e[i].cycle == l.e[i - 1].cycle && l.e[i].kind >= l.e[i - 1].kind),
                  "event %zu (kind %u, cycle %llu) after kind %u, cycle %llu", i, l.e[i].kind,
                  (unsigned long long)l.e[i].cycle, l.e[i - 1].kind,
                  (unsigned long long)l.e[i - 1].cycle);
    free(l.e);
    alb_model_destroy(m);
    alb_ws_buf_free(&b);
}

/* Replay the write events of each frame into an empty store: every pixel
 * written holds its last write, every other none (aa = 0: a pixel is a
 * sample); the counts agree with the statistics and counters. */
TEST(model_write_events_rebuild_every_frame)
{
    static const char *const sets[] = {
        "", "fill_rate=1 edge_units=1 divider_latency=0 shade_latency=0",
        "fill_rate=3 fill_queue=1 face_slots=1 fifo_depth=2", "edge_units=3 fill_rate=8",
    };
    scenegen_params gp = scenegen_defaults();
    for (uint64_t seed = 1; seed <= 12; seed++) {
        alb_profile p;
        alb_profile_lookup("t32", &p);
        profile_set_all(&p, sets[seed % 4]);
        gp.faces = 4 + (unsigned)(seed % 13);
        alb_ws_buf b;
        char *text = random_frames_stream(seed, &gp, (unsigned)(seed % 3), &p, &b);
        if (!text) {
            CHECK_MSG(0, "seed %llu: no stream", (unsigned long long)seed);
            return;
        }
        alb_model *m = model(&p, ALB_FIDELITY_CYCLE, ALB_PRODUCER_GP, ALB_EV_ALL);
        CHECK(m && alb_model_push(m, b.w, b.n) == b.n);
        const size_t np = 32 * 32;
        alb_event *last = calloc(np, sizeof *last);
        unsigned frames = 0;
        uint64_t writes = 0, cells = 0, fills = 0, handed = 0;
        while (m && last && !alb_model_done(m)) {
            alb_stop why;
            CHECK(alb_model_run(m, ALB_EV_FRAME, 1u << 30, &why) == ALB_OK);
            const alb_event *ev;
            size_t k = alb_model_events(m, &ev);
            for (size_t i = 0; i < k; i++) {
                const alb_event *e = &ev[i];
                if (e->kind == ALB_EV_WRITE) {
                    CHECK(e->x < 32 && e->y < 32);
                    if (e->x < 32 && e->y < 32) {
                        /* a sample is written only nearer than before */
                        alb_event *prev = &last[e->y * 32 + e->x];
                        CHECK(prev->kind == 0 || e->depth > prev->depth);
                        *prev = *e;
                    }
                    writes++;
                }
                cells += e->kind == ALB_EV_CELL;
                handed += e->kind == ALB_EV_CELL && (e->result == 3 || e->result == 4);
                fills += e->kind == ALB_EV_FILL;
                if (e->kind != ALB_EV_FRAME)
                    continue;
                const alb_frame *f = alb_model_frame(m);
                const alb_vp_stats *st = alb_model_frame_stats(m);
                const alb_sim_counters *c = alb_model_counters(m, frames);
                CHECK(f && st && c);
                if (!f || !st || !c)
                    break;
                size_t bad = 0;
                for (size_t px = 0; px < np; px++) {
                    const alb_event *w = &last[px];
                    if (w->kind ? f->depth[px] != w->depth || f->face[px] != w->face ||
                                      f->level[px] != w->level || f->rgb[3 * px] != w->rgb[0] ||
                                      f->rgb[3 * px + 1] != w->rgb[1] ||
                                      f->rgb[3 * px + 2] != w->rgb[2]
                                : f->face[px] != ALB_FRAME_NO_FACE || f->depth[px] != 0)
                        bad++;
                }
                CHECK_MSG(!bad, "seed %llu frame %u: %zu pixels differ from the writes",
                          (unsigned long long)seed, frames, bad);
                CHECK_EQ(writes, st->samples_written);
                uint64_t visited = 0;
                for (unsigned lv = 0; lv < ALB_VP_MAX_LEVELS; lv++)
                    visited += st->cells[lv];
                CHECK_EQ(cells, visited);
                CHECK_EQ(fills, handed);
                CHECK_EQ(e->cycle, c->retire);
                CHECK_EQ(e->cycles, c->cycles);
                CHECK_EQ(e->crc, frame_crc(f));
                CHECK_EQ(e->index, frames);
                memset(last, 0, np * sizeof *last);
                writes = cells = fills = handed = 0;
                frames++;
            }
            alb_model_consume(m, k);
            if (why == ALB_STOP_CYCLES)
                break;
        }
        CHECK(frames >= 1);
        free(last);
        alb_model_destroy(m);
        alb_ws_buf_free(&b);
        free(text);
    }
}

static bool events_equal(const ev_log *a, const ev_log *b, uint32_t kinds)
{
    size_t i = 0, j = 0;
    for (;;) {
        while (i < a->n && !(a->e[i].kind & kinds))
            i++;
        while (j < b->n && !(b->e[j].kind & kinds))
            j++;
        if (i == a->n || j == b->n)
            return i == a->n && j == b->n;
        if (memcmp(&a->e[i], &b->e[j], sizeof a->e[i]))
            return false;
        i++, j++;
    }
}

/* A testbench as the FIFO's producer, pushing whenever the FIFO takes a
 * word, is the GP stage with no compute time: the same events, pushes
 * included; a FIFO of two words pushes back. */
TEST(model_external_producer_equals_an_instant_gp)
{
    alb_profile p;
    alb_profile_lookup("t32", &p);
    profile_set_all(&p, "fifo_depth=2 gp_face_cycles=0 gp_edge_cycles=0 gp_frame_cycles=0");
    scenegen_params gp = scenegen_defaults();
    gp.faces = 9;
    char *text = scenegen_random(77, &gp);
    alb_ws_buf b;
    CHECK(text && stream_of(text, &p, &b) == 0);
    alb_model *g = model(&p, ALB_FIDELITY_CYCLE, ALB_PRODUCER_GP, ALB_EV_ALL);
    alb_model *x = model(&p, ALB_FIDELITY_CYCLE, ALB_PRODUCER_EXTERNAL, ALB_EV_ALL);
    ev_log lg = {0}, lx = {0};
    CHECK(g && run_all(g, &b, 7, &lg) == 0);
    size_t next = 0, refused = 0;
    while (x && !alb_model_done(x) && alb_model_cycle(x) < 10000000) {
        if (next < b.n) {
            size_t k = alb_model_push(x, &b.w[next], b.n - next);
            CHECK(k <= 1);
            next += k;
            refused += !k;
            /* at most one word a cycle */
            if (k && next < b.n)
                CHECK_EQ(alb_model_push(x, &b.w[next], 1), 0);
        }
        CHECK(alb_model_step(x, 1) == ALB_OK);
        log_take(&lx, x);
    }
    CHECK_EQ(next, b.n);
    CHECK(refused > 0);
    CHECK(events_equal(&lg, &lx, ALB_EV_ALL));
    free(lg.e);
    free(lx.e);
    alb_model_destroy(g);
    alb_model_destroy(x);
    alb_ws_buf_free(&b);
    free(text);
}

/* One clock at a time, a thousand at a time, or to each next write: the
 * same events. */
TEST(model_step_sizes_give_the_same_events)
{
    char *text = builtin_scene_copy();
    alb_profile p;
    alb_profile_lookup("t32", &p);
    alb_ws_buf b;
    CHECK(text && stream_of(text, &p, &b) == 0);
    ev_log l1 = {0}, l2 = {0}, l3 = {0};
    alb_model *m1 = model(&p, ALB_FIDELITY_CYCLE, ALB_PRODUCER_GP, ALB_EV_ALL);
    alb_model *m2 = model(&p, ALB_FIDELITY_CYCLE, ALB_PRODUCER_GP, ALB_EV_ALL);
    alb_model *m3 = model(&p, ALB_FIDELITY_CYCLE, ALB_PRODUCER_GP, ALB_EV_ALL);
    CHECK(m1 && run_all(m1, &b, 1, &l1) == 0);
    CHECK(m2 && run_all(m2, &b, 1000, &l2) == 0);
    CHECK(m3 && alb_model_push(m3, b.w, b.n) == b.n);
    unsigned stops = 0;
    for (alb_stop why = ALB_STOP_EVENT; m3 && why != ALB_STOP_DONE;) {
        CHECK(alb_model_run(m3, ALB_EV_WRITE, 1u << 30, &why) == ALB_OK);
        if (why == ALB_STOP_EVENT) {
            /* it stopped right after a cycle with a write */
            const alb_event *ev;
            size_t k = alb_model_events(m3, &ev);
            CHECK(k && ev[k - 1].kind == ALB_EV_WRITE &&
                  ev[k - 1].cycle + 1 == alb_model_cycle(m3));
            stops++;
        }
        log_take(&l3, m3);
        if (why == ALB_STOP_CYCLES)
            break;
    }
    CHECK(l1.n > 10000);
    CHECK(stops > 100);
    CHECK(events_equal(&l1, &l2, ALB_EV_ALL));
    CHECK(events_equal(&l1, &l3, ALB_EV_ALL));
    free(l1.e), free(l2.e), free(l3.e);
    alb_model_destroy(m1), alb_model_destroy(m2), alb_model_destroy(m3);
    alb_ws_buf_free(&b);
    free(text);
}

static void vector_fidelities(const char *name, const alb_profile *p, const alb_ws_buf *b,
                              void *ctx)
{
    (void)ctx;
    /* the expected cycle counts and retirements, by frame */
    uint64_t cycles[64], retire[64];
    unsigned nexp = 0;
    char path[600];
    snprintf(path, sizeof path, "test-vectors/%s/expected.cycles", name);
    FILE *f = fopen(path, "r");
    char line[1024];
    while (f && nexp < 64 && fgets(line, sizeof line, f)) {
        unsigned long long c, r;
        const char *pc = strstr(line, " cycles="), *pr = strstr(line, " retire=");
        if (pc && pr && sscanf(pc, " cycles=%llu", &c) == 1 && sscanf(pr, " retire=%llu", &r) == 1) {
            cycles[nexp] = c;
            retire[nexp++] = r;
        }
    }
    if (f)
        fclose(f);
    ev_log l[3] = {{0}};
    static const alb_fidelity fids[3] = {ALB_FIDELITY_CYCLE, ALB_FIDELITY_TIMED,
                                         ALB_FIDELITY_FUNCTIONAL};
    for (int k = 0; k < 3; k++) {
        alb_model *m = model(p, fids[k], ALB_PRODUCER_GP, ALB_EV_FRAME);
        CHECK_MSG(m && run_all(m, b, 1u << 20, &l[k]) == 0, "%s: %s", name,
                  m ? alb_model_error(m) : "no model");
        alb_model_destroy(m);
    }
    CHECK_MSG(l[0].n == nexp && nexp > 0, "%s: %zu frames, %u expected", name, l[0].n, nexp);
    for (size_t i = 0; i < l[0].n && i < nexp; i++) {
        CHECK_EQ(l[0].e[i].cycles, cycles[i]);
        CHECK_EQ(l[0].e[i].cycle, retire[i]);
    }
    CHECK(events_equal(&l[0], &l[1], ALB_EV_FRAME));
    CHECK_EQ(l[2].n, l[0].n);
    for (size_t i = 0; i < l[2].n && i < l[0].n; i++) {
        CHECK_EQ(l[2].e[i].crc, l[0].e[i].crc);
        CHECK_EQ(l[2].e[i].number, l[0].e[i].number);
    }
    for (int k = 0; k < 3; k++)
        free(l[k].e);
}

/* Every golden vector through the API: the cycle model's frame events are
 * the vector's expected counters (expected.cycles), the timed fidelity's
 * the same, the functional one's CRCs the same. */
TEST(model_fidelities_on_every_vector)
{
    CHECK(for_each_vector(vector_fidelities, NULL) >= 12);
}

TEST(model_masks_record_only_what_is_asked)
{
    alb_profile p;
    alb_ws_buf b;
    worked_example(&p, &b);
    ev_log none = {0}, pops = {0};
    alb_model *m = model(&p, ALB_FIDELITY_CYCLE, ALB_PRODUCER_GP, 0);
    CHECK(m && run_all(m, &b, 50, &none) == 0);
    CHECK_EQ(none.n, 0);
    CHECK_EQ(alb_model_frames(m), 1);   /* the frame still retires */
    alb_model_destroy(m);
    m = model(&p, ALB_FIDELITY_CYCLE, ALB_PRODUCER_GP, ALB_EV_POP);
    CHECK(m && run_all(m, &b, 50, &pops) == 0);
    CHECK_EQ(pops.n, 17);
    CHECK_EQ(count_kind(&pops, ALB_EV_POP), 17);
    alb_model_destroy(m);
    free(pops.e);
    alb_ws_buf_free(&b);
}

TEST(model_errors_are_located)
{
    alb_profile p;
    alb_ws_buf b;
    worked_example(&p, &b);
    for (int fid = ALB_FIDELITY_FUNCTIONAL; fid <= ALB_FIDELITY_CYCLE; fid++) {
        /* a word after END */
        alb_model *m = model(&p, (alb_fidelity)fid, ALB_PRODUCER_GP, ALB_EV_ALL);
        uint32_t extra[18];
        memcpy(extra, b.w, 17 * sizeof *extra);
        extra[17] = 0xFF000000;
        size_t k = m ? alb_model_push(m, extra, 18) : 0;
        if (fid != ALB_FIDELITY_CYCLE)   /* the cycle model takes words as they come */
            CHECK(k <= 18);
        for (int i = 0; m && i < 400 && !alb_model_error(m)[0]; i++)
            alb_model_step(m, 1);
        CHECK_STR_CONTAINS(m ? alb_model_error(m) : NULL, "after END");
        CHECK_STR_CONTAINS(m ? alb_model_error(m) : NULL, "offset 68");
        alb_model_destroy(m);
        /* an unknown opcode where the FRAME belongs (word 3) */
        m = model(&p, (alb_fidelity)fid, ALB_PRODUCER_GP, ALB_EV_ALL);
        uint32_t bad[17];
        memcpy(bad, b.w, sizeof bad);
        bad[3] = 0x12345678;
        if (m)
            alb_model_push(m, bad, 17);
        alb_err e = ALB_OK;
        for (int i = 0; m && i < 100 && !e; i++)
            e = alb_model_step(m, 1);
        if (fid != ALB_FIDELITY_CYCLE)
            e = m && alb_model_error(m)[0] ? ALB_ERR_STREAM : ALB_OK;
        CHECK_EQ(e, ALB_ERR_STREAM);
        CHECK_STR_CONTAINS(m ? alb_model_error(m) : NULL, "offset 12");
        CHECK_STR_CONTAINS(m ? alb_model_error(m) : NULL, "not a packet opcode");
        /* once failed, it stays failed */
        if (m && fid == ALB_FIDELITY_CYCLE)
            CHECK_EQ(alb_model_step(m, 1), ALB_ERR_STREAM);
        alb_model_destroy(m);
    }
    alb_model *m = NULL;
    alb_diag d;
    CHECK_EQ(alb_model_open(&m, "no-such-profile", NULL, NULL, &d), ALB_ERR_CONFIG);
    CHECK(m == NULL);
    const char *const bad_set[] = {"edge_units=0", NULL};
    CHECK_EQ(alb_model_open(&m, "t32", bad_set, NULL, &d), ALB_ERR_CONFIG);
    CHECK_STR_CONTAINS(d.msg, "edge_units");
    const char *const good_set[] = {"edge_units=3", "fill_rate=1", NULL};
    CHECK_EQ(alb_model_open(&m, "t32", good_set, NULL, &d), ALB_OK);
    alb_model_destroy(m);
    alb_ws_buf_free(&b);
}

/* A heavy frame (whole-screen faces) and then `empty` empty frames, taken
 * while it drains as far as the FRAME registers allow (frame_queue). */
static void frames_behind_a_heavy_one(alb_profile *p, alb_ws_buf *b, unsigned empty)
{
    alb_profile_lookup("t32", p);
    alb_ws_buf_init(b);
    alb_ws_config cfg = {p->edge_frac_bits, p->coef_bits, 1.0f};
    alb_ws_put_config(b, &cfg);
    for (unsigned k = 0; k <= empty; k++) {
        alb_ws_frame fr = {k, 0x101010, false, 0, 0, 0};
        alb_ws_put_frame(b, &fr);
        unsigned faces = k ? 0 : 3;
        for (unsigned i = 0; i < faces; i++) {
            alb_ws_face f;
            memset(&f, 0, sizeof f);
            f.id = i;
            f.rgb = 0x808080;
            f.depth = (alb_ws_form){-1, {0, 0, 1}};
            alb_ws_put_face(b, &f);
        }
        alb_ws_put_frame_end(b, faces);
    }
    alb_ws_put_end(b);
}

static bool counters_same(const alb_sim_counters *a, const alb_sim_counters *b)
{
#define SAME(field) if (a->field != b->field) return false;
    ALB_SIM_COUNTER_FIELDS(SAME)
#undef SAME
    return true;
}

/* The FRAME registers (docs/microarchitecture.md, "VP input parser"): with
 * one set a FRAME waits for the frame before it to retire, so each empty
 * frame after the heavy one takes its 6 words' pops (5 of FRAME, 1 of
 * FRAME_END) from the retirement before it; with 16, the next 15 are taken
 * while the heavy frame drains and retire one a cycle after it.  Timed and
 * cycle agree on every counter at every queue size. */
TEST(model_frame_registers_hold_frame_queue_frames)
{
    static const unsigned queues[] = {1, 2, 3, 16};
    for (size_t qi = 0; qi < sizeof queues / sizeof *queues; qi++) {
        alb_profile p;
        alb_ws_buf b;
        frames_behind_a_heavy_one(&p, &b, 24);
        p.frame_queue = queues[qi];
        ev_log lc = {0}, lt = {0};
        alb_model *c = model(&p, ALB_FIDELITY_CYCLE, ALB_PRODUCER_GP, ALB_EV_FRAME);
        alb_model *t = model(&p, ALB_FIDELITY_TIMED, ALB_PRODUCER_GP, ALB_EV_FRAME);
        CHECK(c && run_all(c, &b, 1000, &lc) == 0);
        CHECK(t && run_all(t, &b, 1000, &lt) == 0);
        CHECK_EQ(lc.n, 25);
        CHECK(events_equal(&lc, &lt, ALB_EV_FRAME));
        for (unsigned k = 0; k < lc.n; k++) {
            const alb_sim_counters *cc = alb_model_counters(c, k), *ct = alb_model_counters(t, k);
            CHECK_MSG(cc && ct && counters_same(cc, ct), "frame_queue=%u frame %u: counters",
                      queues[qi], k);
        }
        uint64_t r0 = lc.n ? lc.e[0].cycle : 0;
        for (unsigned k = 1; k < lc.n; k++) {
            uint64_t want = queues[qi] == 1 ? r0 + 6 * k : queues[qi] == 16 && k <= 15 ? r0 + k : 0;
            if (want)
                CHECK_MSG(lc.e[k].cycle == want, "frame_queue=%u: frame %u retired in %llu, "
                          "expected %llu", queues[qi], k, (unsigned long long)lc.e[k].cycle,
                          (unsigned long long)want);
        }
        if (queues[qi] == 1)   /* FRAME 1 waited, in frame 0's cycles: blocked */
            CHECK(alb_model_counters(c, 0) && alb_model_counters(c, 0)->parser_blocked > 0);
        free(lc.e), free(lt.e);
        alb_model_destroy(c), alb_model_destroy(t);
        alb_ws_buf_free(&b);
    }
}
