/* sim_timed.c — the timed fidelity: the rules of docs/microarchitecture.md
 * as recurrences over event times, computed in stream order.  Each word's
 * push and pop, each engine step and each fill gets its cycle from the events
 * it waits for (all earlier in stream order), so idle and predictable
 * stretches cost nothing.  Equal to the cycle fidelity by test. */
#include "sim_internal.h"

#include <stdlib.h>
#include <string.h>

typedef struct {
    const alb_profile *p;
    alb_vp *vp;
    sim_bins bins;
    cycle_map map;
    alb_frame frame;
    /* words: the pop times of the last fifo_depth + 1 words, by index */
    int64_t *pop_ring;
    unsigned word_slot;       /* words % (fifo_depth + 1): the next word's in pop_ring */
    unsigned popped_slot;     /* popped % (fifo_depth + 1) */
    uint64_t words;           /* words pushed so far */
    uint64_t popped;          /* words counted as popped for the FIFO peak */
    int64_t last_push, last_pop;
    /* units */
    int64_t *slot_free;       /* face slot k % face_slots free from this cycle */
    uint64_t faces;
    int64_t engine_free;      /* first cycle the engine can start a face */
    int64_t *take_ring;       /* fill_queue last cells: cycle the fill unit took them */
    /* the walk's steps and hand-overs, the engine's next cycle (now) and the
     * fill queue (vp_timer_hand_over) */
    vp_timer timer;
    int64_t drain;            /* last cycle of any face's activity so far */
    int64_t frame_last;       /* last activity of the current frame's faces */
    int64_t frame_start;      /* first cycle a face of the current frame may start */
    int64_t prev_retire;
    bool first_face_of_frame;
    unsigned latency;         /* 1 + divider + shade */
    /* retired frames whose counters may still grow: words of later frames
     * pushed or popped before their retirement are met later in the stream */
    struct pending {
        alb_frame frame;
        alb_vp_stats st;
        unsigned bin;
    } *pending;
    unsigned npending, cap_pending;
    alb_frame spare;            /* a flushed frame's planes, reused (no copies) */
    /* frames wanted: else only what timing and the statistics need — the
     * walk and the fills (depth and tag), no output stage, no per-pixel
     * cycles — and the sink gets frames without planes */
    bool frames;
} timed;

static int64_t max64(int64_t a, int64_t b) { return a > b ? a : b; }

/* When the parser can take a word of this packet (room in the VP). */
static int64_t room(timed *t, const alb_ws_event *ev)
{
    switch (ev->kind) {
    case ALB_WS_EV_FACE:
        return t->slot_free[t->faces % t->p->face_slots];
    case ALB_WS_EV_TEXTURE:
    case ALB_WS_EV_END:
        return t->drain + 1;   /* wait until every earlier face retired */
    case ALB_WS_EV_FRAME: {
        /* frame k (every earlier one retired in the model's order) needs a
         * free register set: frame k - frame_queue retired before the cycle */
        unsigned k = t->bins.nretired, q = t->p->frame_queue;
        return k >= q ? t->bins.retire[k - q] + 1 : 0;
    }
    default:
        return 0;
    }
}

/* GP push and parser pop of one word; `compute` is the GP's time before it
 * (the packet's first word) or -1. */
static void word_times(timed *t, int64_t compute, int64_t ready)
{
    const unsigned depth = t->p->fifo_depth;
    uint64_t i = t->words;
    /* the ring's slots without divisions: word i - depth is in the slot
     * after word i's (the ring holds depth + 1) */
    const unsigned slot = t->word_slot, next = slot == depth ? 0 : slot + 1;
    int64_t want = t->last_push + 1;   /* GP free after its previous push */
    /* the FIFO held fewer than depth words at the start of the push cycle:
     * the word depth places back has been popped before it */
    int64_t push = want + (compute >= 0 ? compute : 0);
    if (i >= depth)
        push = max64(push, t->pop_ring[next] + 1);
    /* the parser wants it from the cycle after its previous pop */
    int64_t asked = t->last_pop + 1;
    int64_t pop = max64(max64(asked, push + 1), ready);
    /* it starves until the word is in the FIFO, then waits for room */
    int64_t arrived = push + 1 < pop ? push + 1 : pop;
    const int64_t waited = arrived > asked ? arrived : asked;
    if (compute >= 0) {
        bins_add(&t->bins, CNT(gp_busy), want, want + compute);
        want += compute;
    }
    bins_add(&t->bins, CNT(gp_stall), want, push);
    bins_add(&t->bins, CNT(gp_busy), push, push + 1);
    bins_add(&t->bins, CNT(parser_starve), asked, waited);
    bins_add(&t->bins, CNT(parser_blocked), waited, pop);
    bins_add(&t->bins, CNT(parser_busy), pop, pop + 1);
    /* occupancy: the word is in the FIFO at the start of push+1 .. pop */
    bins_add(&t->bins, CNT(fifo_sum), push + 1, pop + 1);
    while (t->popped < i && t->pop_ring[t->popped_slot] <= push) {
        t->popped++;
        t->popped_slot = t->popped_slot == depth ? 0 : t->popped_slot + 1;
    }
    alb_sim_counters *at = bins_at(&t->bins, push);
    uint64_t level = i + 1 - t->popped;
    if (level > at->fifo_peak)
        at->fifo_peak = level;
    t->pop_ring[slot] = pop;
    t->word_slot = next;
    t->last_push = push;
    t->last_pop = pop;
    t->words++;
}

/* Each step's cycles on the per-pixel cycle map (frames wanted). */
static void charge(vp_timer *tm, const vp_cell *k, uint64_t cycles)
{
    timed *t = tm->ctx;
    cycle_map_charge(&t->map, t->vp, k, cycles);
}

/* The engine and fill unit on one loaded face: its walk, timed. */
static alb_err run_face(timed *t, vp_loaded_face *lf, int64_t loaded, alb_diag *d)
{
    const alb_profile *p = t->p;
    vp_timer *tm = &t->timer;
    const int64_t start =
        max64(max64(loaded + 1, t->engine_free), t->first_face_of_frame ? t->frame_start : 0);
    t->first_face_of_frame = false;
    alb_err e = vp_begin_face(t->vp, lf, d);
    if (e)
        return e;
    tm->now = start;
    tm->pending = 0;
    tm->engine = tm->stall = tm->fill = 0;
    const uint64_t cells = tm->cells;
    vp_draw_face_timed(t->vp, lf, tm);
    /* the steps after the last hand-over */
    tm->engine += tm->pending;
    tm->now += (int64_t)tm->pending;
    /* every cycle of the face follows the last retirement (its first is at
     * least the frame's start): the face's sums go to the open bin at once */
    bins_add(&t->bins, CNT(engine_busy), start, start + (int64_t)tm->engine);
    bins_add(&t->bins, CNT(engine_stall), start, start + (int64_t)tm->stall);
    bins_add(&t->bins, CNT(fill_busy), start, start + (int64_t)tm->fill);
    /* a cell's last sample is written latency - 1 cycles after its last
     * fill cycle; fill_free only grows, so the face's last cell is latest */
    if (tm->cells != cells)
        t->frame_last = max64(t->frame_last, tm->fill_free - 1 + (int64_t)t->latency - 1);
    /* the face is finished in its last step's cycle; its slot is free next */
    t->engine_free = tm->now;
    t->frame_last = max64(t->frame_last, tm->now - 1);
    t->slot_free[t->faces % p->face_slots] = tm->now;
    t->faces++;
    t->drain = max64(t->drain, t->frame_last);
    return ALB_OK;
}

/* Hand retired frames to the sink once no later word can add to their
 * counters: every later push and pop comes after the GP's and the parser's
 * last ones, so a frame retired before both is final (all: at the end). */
static alb_err flush_frames(timed *t, bool all, alb_sim_sink sink, void *ctx)
{
    int64_t safe = t->last_push < t->last_pop ? t->last_push : t->last_pop;
    unsigned done = 0;
    alb_err e = ALB_OK;
    while (done < t->npending) {
        struct pending *pf = &t->pending[done];
        if (!all && t->bins.retire[pf->bin] >= safe)
            break;
        if (!e && sink && sink(ctx, &pf->frame, &pf->st, &t->bins.bin[pf->bin]))
            e = ALB_ERR_IO;
        if (!t->spare.rgb)
            t->spare = pf->frame;
        else
            alb_frame_free(&pf->frame);
        done++;
    }
    if (done && done < t->npending)
        memmove(t->pending, t->pending + done, (t->npending - done) * sizeof *t->pending);
    t->npending -= done;
    return e;
}

static alb_err frame_end(timed *t, int64_t popped, alb_diag *d)
{
    int64_t r = max64(max64(popped, t->frame_last), t->prev_retire + 1);
    if (bins_retire(&t->bins, r))
        return alb_diag_at(d, ALB_ERR_NOMEM, "", 0, 0, "out of memory");
    if (t->frames) {
        alb_vp_frame_end(t->vp, &t->frame);
        cycle_map_resolve(&t->map, t->vp, &t->frame);
    } else {
        t->frame.number = t->vp->frame.number;
        vp_store_name_tie(t->vp);   /* st.tie_kept, before the counters are taken */
    }
    t->prev_retire = r;
    t->drain = max64(t->drain, r);
    if (t->npending == t->cap_pending) {
        unsigned cap = t->cap_pending ? 2 * t->cap_pending : 4;
        struct pending *np = realloc(t->pending, cap * sizeof *np);
        if (!np)
            return alb_diag_at(d, ALB_ERR_NOMEM, "", 0, 0, "out of memory");
        t->pending = np;
        t->cap_pending = cap;
    }
    /* the finished planes move to the pending list; drawing goes on in a
     * spare set */
    struct pending *pf = &t->pending[t->npending];
    pf->frame = t->frame;
    if (!t->frames) {
        /* the same frame without planes goes on */
    } else if (t->spare.rgb) {
        t->frame = t->spare;
        memset(&t->spare, 0, sizeof t->spare);
    } else if (alb_vp_frame_alloc(t->vp, &t->frame, true)) {
        return alb_diag_at(d, ALB_ERR_NOMEM, "", 0, 0, "out of memory");
    }
    t->frame.near = pf->frame.near;
    pf->st = *alb_vp_stats_get(t->vp);
    pf->bin = t->bins.nretired - 1;
    t->npending++;
    return ALB_OK;
}

static alb_err timed_init(timed *t, const alb_profile *p, bool frames, alb_diag *d)
{
    memset(t, 0, sizeof *t);
    t->p = p;
    t->latency = 1 + p->divider_latency + p->shade_latency;
    t->last_push = t->last_pop = -1;
    t->prev_retire = -1;
    t->drain = -1;
    t->frame_last = -1;
    t->frames = frames;
    sim_frame_without_planes(p, &t->frame);
    /* counters alone: the VP without tag plane, reciprocal ROM nor output
     * stage (the same statistics) */
    alb_err e = frames ? alb_vp_create(&t->vp, p, d) : vp_create_counters(&t->vp, p, d);
    if (e)
        return e;
    t->pop_ring = calloc(p->fifo_depth + 1, sizeof *t->pop_ring);
    t->slot_free = calloc(p->face_slots, sizeof *t->slot_free);
    t->take_ring = calloc(p->fill_queue, sizeof *t->take_ring);
    vp_timer_init(&t->timer, p, t->take_ring);
    t->timer.charge = frames ? charge : NULL;
    t->timer.ctx = t;
    if (!t->pop_ring || !t->slot_free || !t->take_ring || bins_init(&t->bins) ||
        (frames && (cycle_map_init(&t->map, t->vp) || alb_vp_frame_alloc(t->vp, &t->frame, true))))
        return alb_diag_at(d, ALB_ERR_NOMEM, "", 0, 0, "out of memory for the timed model");
    return ALB_OK;
}

static void timed_free(timed *t)
{
    for (unsigned i = 0; i < t->npending; i++)
        alb_frame_free(&t->pending[i].frame);
    free(t->pending);
    alb_frame_free(&t->spare);
    alb_vp_destroy(t->vp);
    free(t->pop_ring);
    free(t->slot_free);
    free(t->take_ring);
    bins_free(&t->bins);
    cycle_map_free(&t->map);
    alb_frame_free(&t->frame);
}

/* The GP's compute time before a packet (gp_header_cycles of its header). */
static uint64_t gp_packet_cycles(const alb_profile *p, const alb_ws_event *ev)
{
    if (ev->kind == ALB_WS_EV_FACE)
        return p->gp_face_cycles + (uint64_t)p->gp_edge_cycles * ev->u.face.n_edges;
    return ev->kind == ALB_WS_EV_FRAME ? p->gp_frame_cycles : 0;
}

/* One packet of the stream through the model. */
static alb_err timed_event(timed *t, const alb_ws_event *ev, vp_loaded_face *lf, alb_diag *d)
{
    const alb_profile *p = t->p;
    int64_t ready = room(t, ev);
    for (size_t k = 0; k < ev->count; k++)
        word_times(t, k == 0 ? (int64_t)gp_packet_cycles(p, ev) : -1, ready);
    alb_err e = ALB_OK;
    switch (ev->kind) {
    case ALB_WS_EV_CONFIG:
        if (!(e = alb_vp_config(t->vp, &ev->u.config, d)))
            t->frame.near = ev->u.config.near;
        break;
    case ALB_WS_EV_TEXTURE:
        e = alb_vp_texture(t->vp, &ev->u.texture, d);
        break;
    case ALB_WS_EV_FRAME:
        alb_vp_frame_begin(t->vp, &ev->u.frame);
        t->frame_start = t->prev_retire + 1;
        t->frame_last = -1;
        t->first_face_of_frame = true;
        break;
    case ALB_WS_EV_FACE:
        if (!(e = vp_load_face(t->vp, &ev->u.face, lf, d)))
            e = run_face(t, lf, t->last_pop, d);
        break;
    case ALB_WS_EV_FRAME_END:
        e = frame_end(t, t->last_pop, d);
        break;
    case ALB_WS_EV_END:
        break;
    }
    return e;
}

alb_err sim_run_timed(const alb_profile *p, const uint32_t *w, size_t n, const char *name,
                      bool frames, alb_sim_sink sink, void *ctx, alb_diag *d)
{
    timed t;
    alb_err e = timed_init(&t, p, frames, d);
    alb_ws_reader r;
    alb_ws_event *ev = malloc(sizeof *ev);
    vp_loaded_face *lf = malloc(sizeof *lf);
    if (!e && (!ev || !lf))
        e = alb_diag_at(d, ALB_ERR_NOMEM, name, 0, 0, "out of memory");
    alb_ws_reader_init(&r, w, n, name);
    r.max_faces = p->frame_faces;
    while (!e && !r.ended) {
        if ((e = alb_ws_next(&r, ev, d)))
            break;
        e = timed_event(&t, ev, lf, d);
        if (!e)
            e = flush_frames(&t, r.ended, sink, ctx);
    }
    free(ev);
    free(lf);
    timed_free(&t);
    return e;
}

/* ---- the same model fed a stream as it arrives (the simulated board) ---- */

struct alb_sim_feed {
    timed t;
    alb_ws_reader r;              /* after the last whole packet */
    alb_ws_event *ev;
    vp_loaded_face *lf;
    alb_sim_sink on_frame;
    void *ctx;
    size_t frame_start;
    bool ok;                  /* timed_init succeeded */
};

alb_err alb_sim_feed_open(alb_sim_feed **out, const alb_profile *p, const char *name, alb_sim_sink on_frame,
                      void *ctx, alb_diag *d)
{
    alb_sim_feed *f = calloc(1, sizeof *f);
    *out = NULL;
    if (!f)
        return alb_diag_at(d, ALB_ERR_NOMEM, name, 0, 0, "out of memory");
    alb_err e = timed_init(&f->t, p, true, d);
    f->ok = true;
    f->ev = malloc(sizeof *f->ev);
    f->lf = malloc(sizeof *f->lf);
    if (!e && (!f->ev || !f->lf))
        e = alb_diag_at(d, ALB_ERR_NOMEM, name, 0, 0, "out of memory");
    if (e) {
        alb_sim_feed_close(f);
        return e;
    }
    alb_ws_reader_init(&f->r, NULL, 0, name);
    f->r.max_faces = p->frame_faces;
    f->on_frame = on_frame;
    f->ctx = ctx;
    *out = f;
    return ALB_OK;
}

alb_err alb_sim_feed_words(alb_sim_feed *f, const uint32_t *w, size_t n, alb_diag *d)
{
    while (!f->r.ended && f->r.pos < n) {
        alb_ws_reader r = f->r;
        r.w = w;
        r.n = n;
        alb_diag dd;
        alb_diag_init(&dd, NULL);
        alb_err e = alb_ws_next(&r, f->ev, &dd);
        if (e) {
            if (dd.offset == (long long)n * 4)
                return ALB_OK;   /* a packet still arriving */
            *d = dd;
            return e;
        }
        f->r = r;
        e = timed_event(&f->t, f->ev, f->lf, d);
        if (e)
            return e;
        if (f->ev->kind == ALB_WS_EV_FRAME)
            f->frame_start = f->ev->first;
        else if (!r.in_frame)
            f->frame_start = r.pos;
        if (f->ev->kind == ALB_WS_EV_FRAME_END && f->on_frame) {
            /* its pixels and cycle count are final now; its other counters
             * may still grow with later words (flush_frames) */
            const struct pending *pf = &f->t.pending[f->t.npending - 1];
            if (f->on_frame(f->ctx, &pf->frame, &pf->st, &f->t.bins.bin[pf->bin]))
                return alb_diag_at(d, ALB_ERR_IO, f->r.name, 0, 0, "the frame's sink failed");
        }
        if ((e = flush_frames(&f->t, f->r.ended, NULL, NULL)))
            return e;
    }
    return ALB_OK;
}

size_t alb_sim_feed_frame_start(const alb_sim_feed *f) { return f->frame_start; }

const alb_sim_counters *sim_feed_counters(const alb_sim_feed *f, unsigned k)
{
    return k < f->t.bins.nretired ? &f->t.bins.bin[k] : NULL;
}

uint64_t sim_feed_next_cycle(const alb_sim_feed *f) { return (uint64_t)(f->t.prev_retire + 1); }

size_t sim_feed_taken(const alb_sim_feed *f, bool *ended)
{
    *ended = f->r.ended;
    return f->r.pos;
}

void alb_sim_feed_close(alb_sim_feed *f)
{
    if (!f)
        return;
    if (f->ok)
        timed_free(&f->t);
    free(f->ev);
    free(f->lf);
    free(f);
}
