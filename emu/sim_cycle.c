/* sim_cycle.c — the cycle fidelity: GP output stage, FIFO, VP input parser,
 * subdivision engine, fill unit and depth/shade pipeline as explicit state,
 * each ticked once per clock by a clock that belongs to none of them
 * (docs/microarchitecture.md).  A unit reads only what the others held at the
 * start of the cycle (their registers) and writes its own next state. */
#include "sim_internal.h"
#include "vcd.h"

#include <signal.h>
#include <stdlib.h>
#include <string.h>

/* ---- the stream, decoded up front into packets ---- */

typedef struct {
    ws_event *ev;
    size_t n;
    const ws_frame **frame;   /* the FRAME packet of each frame */
    unsigned nframes;
} packets;

static alb_err decode_all(const uint32_t *w, size_t n, const char *name, uint32_t max_faces,
                          packets *ps, diag_t *d)
{
    ws_reader r;
    size_t cap = 64;
    ps->n = 0;
    ps->ev = malloc(cap * sizeof *ps->ev);
    ws_reader_init(&r, w, n, name);
    r.max_faces = max_faces;
    while (ps->ev && !r.ended) {
        if (ps->n == cap) {
            ws_event *ne = realloc(ps->ev, 2 * cap * sizeof *ne);
            if (!ne)
                break;
            ps->ev = ne;
            cap *= 2;
        }
        alb_err e = ws_next(&r, &ps->ev[ps->n], d);
        if (e)
            return e;
        ps->n++;
    }
    if (!ps->ev || !r.ended)
        return diag_at(d, ALB_ERR_NOMEM, name, 0, 0, "out of memory decoding the stream");
    ps->frame = malloc((ps->n + 1) * sizeof *ps->frame);
    if (!ps->frame)
        return diag_at(d, ALB_ERR_NOMEM, name, 0, 0, "out of memory decoding the stream");
    for (size_t i = 0; i < ps->n; i++)
        if (ps->ev[i].kind == WS_EV_FRAME)
            ps->frame[ps->nframes++] = &ps->ev[i].u.frame;
    return ALB_OK;
}

/* ---- units ---- */

typedef struct {                 /* GP output stage */
    size_t pkt, word;            /* next packet, next word of it */
    bool have;                   /* computing or pushing packet pkt */
    uint64_t compute_left;
    uint8_t state;               /* for the trace: 0 idle 1 compute 2 push 3 stall */
} gp_unit;

typedef struct {                 /* the GP -> VP FIFO (words are indices) */
    uint64_t count;
    bool push, pop;              /* this cycle, for the trace */
} fifo_unit;

typedef struct {
    vp_loaded_face face;
    int64_t loaded_at;           /* cycle its last word was popped; -1 empty */
    unsigned frame;              /* frame it belongs to */
} slot;

typedef struct {                 /* VP input parser */
    size_t pkt, word;            /* next word to take */
    uint8_t state;               /* trace: 0 idle 1 pop 2 starve 3 blocked */
} parser_unit;

typedef struct {                 /* subdivision engine */
    bool busy, stalled;
    size_t slot;                 /* slot of the face in work */
    vp_walk walk;
    vp_step step;
    uint64_t left;               /* cycles left in the step */
    /* the trace: what the engine did this cycle — 0 idle, 1 worked on a
     * step, 2 stalled handing one over — and that step's face and cell */
    uint8_t did;
    uint32_t did_face;
    vp_step did_step;
} engine_unit;

/* A queued cell carries its face's shading set-up: the face's slot is freed
 * when the engine is done with it, possibly before its cells are filled. */
typedef struct {
    vp_cell cell;
    vp_face_setup fs;
} queued_cell;

typedef struct {                 /* fill unit (and the queue before it) */
    queued_cell *q;
    unsigned head, count;
    uint64_t left;               /* cycles left on the current cell */
    uint32_t samples, next;      /* the current cell's samples; the next, raster order */
    uint32_t issue_at, issued;   /* this cycle: first sample issued, how many */
    int64_t last_write;          /* cycle the last issued sample is written */
} fill_unit;

/* The depth/shade pipeline as the trace shows it, kept only when tracing it
 * (the pixels themselves come from vp_fill when the fill unit takes a cell):
 * which samples of the cell in fill win the depth test, and for each of the
 * L stages the samples in it and how many of them won. */
typedef struct {
    uint32_t *won;               /* per sample of the cell in fill: 1 if written */
    size_t cap;
    uint16_t (*stage)[2];        /* by cycle mod L: samples issued, of which won */
    unsigned out, written;       /* the last stage this cycle */
} pipe_trace;

typedef struct {
    const profile_t *p;
    vp_t *vp;
    packets ps;
    gp_unit gp;
    fifo_unit fifo;
    parser_unit parser;
    engine_unit engine;
    fill_unit fill;
    pipe_trace pipe;
    bool pipe_traced;            /* the trace has the pipe scope: keep pipe_trace */
    slot *slots;
    uint64_t faces_loaded, faces_started;   /* FIFO order of slots */
    /* frames: frame_open (= frames retired) is the one whose faces may run;
     * later frames' packets may be taken while it drains */
    unsigned frames_taken;       /* FRAME packets taken */
    unsigned ends_taken;         /* FRAME_END packets taken */
    unsigned frame_open;
    int64_t prev_retire;
    bool ended;
    sim_bins bins;
    cycle_map map;
    frame_t frame;
    unsigned latency;
    sim_sink sink;
    void *ctx;
    alb_err err;
    diag_t *d;
} machine;

static const ws_event *cur_packet(const machine *m, size_t pkt) { return &m->ps.ev[pkt]; }

/* Everything earlier has retired: no face in the engine, slots, queue or
 * pipeline, and no frame waiting to retire (state at the start of cycle t). */
static bool drained(const machine *m, int64_t t)
{
    return !m->engine.busy && m->faces_started == m->faces_loaded && m->fill.count == 0 &&
           m->fill.left == 0 && m->fill.last_write < t && m->frames_taken == m->frame_open &&
           m->ends_taken == m->frame_open;
}

/* ---- the parser ---- */

static bool has_room(const machine *m, const ws_event *ev, int64_t t)
{
    switch (ev->kind) {
    case WS_EV_FACE:
        return m->slots[m->faces_loaded % m->p->face_slots].loaded_at < 0;
    case WS_EV_TEXTURE:
    case WS_EV_END:
        return drained(m, t);
    default:
        return true;
    }
}

static void packet_taken(machine *m, const ws_event *ev, int64_t t)
{
    switch (ev->kind) {
    case WS_EV_CONFIG:
        if (!m->err && !(m->err = vp_config(m->vp, &ev->u.config, m->d)))
            m->frame.near = ev->u.config.near;
        break;
    case WS_EV_TEXTURE:
        if (!m->err)
            m->err = vp_texture(m->vp, &ev->u.texture, m->d);
        break;
    case WS_EV_FRAME:
        /* the next frame's registers; it begins now if every earlier frame
         * has retired, else when its predecessor retires */
        if (m->frames_taken++ == m->frame_open)
            vp_frame_begin(m->vp, &ev->u.frame);
        break;
    case WS_EV_FACE: {
        slot *s = &m->slots[m->faces_loaded % m->p->face_slots];
        if (!m->err)
            m->err = vp_load_face(m->vp, &ev->u.face, &s->face, m->d);
        s->loaded_at = t;
        s->frame = m->frames_taken - 1;
        m->faces_loaded++;
        break;
    }
    case WS_EV_FRAME_END:
        m->ends_taken++;
        break;
    case WS_EV_END:
        m->ended = true;
        break;
    }
}

static void parser_tick(machine *m, int64_t t, uint64_t fifo_start)
{
    parser_unit *pa = &m->parser;
    if (pa->pkt >= m->ps.n) {
        pa->state = 0;
        return;
    }
    const ws_event *ev = cur_packet(m, pa->pkt);
    if (!has_room(m, ev, t)) {
        bins_add(&m->bins, CNT(parser_blocked), t, t + 1);
        pa->state = 3;
        return;
    }
    if (fifo_start == 0) {
        bins_add(&m->bins, CNT(parser_starve), t, t + 1);
        pa->state = 2;
        return;
    }
    m->fifo.count--;
    m->fifo.pop = true;
    pa->state = 1;
    bins_add(&m->bins, CNT(parser_busy), t, t + 1);
    if (++pa->word == ev->count) {
        packet_taken(m, ev, t);
        pa->pkt++;
        pa->word = 0;
    }
}

/* ---- the GP output stage ---- */

static void gp_tick(machine *m, int64_t t, uint64_t fifo_start)
{
    gp_unit *g = &m->gp;
    if (!g->have) {
        if (g->pkt >= m->ps.n) {
            g->state = 0;
            return;
        }
        g->have = true;
        g->word = 0;
        g->compute_left = gp_packet_cycles(m->p, cur_packet(m, g->pkt));
    }
    if (g->compute_left) {
        g->compute_left--;
        g->state = 1;
        bins_add(&m->bins, CNT(gp_busy), t, t + 1);
        return;
    }
    if (fifo_start >= m->p->fifo_depth) {
        g->state = 3;
        bins_add(&m->bins, CNT(gp_stall), t, t + 1);
        return;
    }
    g->state = 2;
    m->fifo.count++;
    m->fifo.push = true;
    bins_add(&m->bins, CNT(gp_busy), t, t + 1);
    if (++g->word == cur_packet(m, g->pkt)->count) {
        g->have = false;
        g->pkt++;
    }
}

/* ---- the engine ---- */

static bool step_fills(const vp_step *s)
{
    return s->kind == VP_STEP_FILL || s->kind == VP_STEP_SAMPLE_IN;
}

/* After a step's hand-over (or a step without one): the next step, or the
 * end of the face in cycle t. */
static void engine_next(machine *m, int64_t t)
{
    engine_unit *e = &m->engine;
    slot *s = &m->slots[e->slot];
    e->stalled = false;
    if (vp_walk_next(m->vp, &e->walk, &e->step)) {
        e->left = step_cycles(e->step.edges, m->p->edge_units);
        cycle_map_charge(&m->map, m->vp, &e->step.cell, e->left);
        return;
    }
    e->busy = false;
    s->loaded_at = -1;          /* the slot is free from the next cycle */
    m->faces_started++;
    (void)t;
}

static bool enqueue(machine *m, uint64_t queue_start)
{
    fill_unit *f = &m->fill;
    if (queue_start >= m->p->fill_queue)
        return false;
    queued_cell *qc = &f->q[(f->head + f->count) % m->p->fill_queue];
    qc->cell = m->engine.step.cell;
    qc->fs = m->slots[m->engine.slot].face.fs;
    f->count++;
    return true;
}

static void engine_tick(machine *m, int64_t t, uint64_t queue_start)
{
    engine_unit *e = &m->engine;
    e->did = 0;
    if (!e->busy) {
        slot *s = &m->slots[m->faces_started % m->p->face_slots];
        if (m->faces_started == m->faces_loaded || s->loaded_at < 0 || s->loaded_at >= t ||
            s->frame != m->frame_open || t <= m->prev_retire)
            return;
        e->busy = true;
        e->slot = m->faces_started % m->p->face_slots;
        vp_count_face(m->vp, &s->face);
        vp_walk_begin(&e->walk, m->vp, &s->face);
        engine_next(m, t);   /* the first step starts this cycle */
    }
    e->did = e->stalled ? 2 : 1;
    e->did_step = e->step;
    e->did_face = m->slots[e->slot].face.fs.id;
    if (e->stalled) {
        bins_add(&m->bins, CNT(engine_stall), t, t + 1);
        if (enqueue(m, queue_start))
            engine_next(m, t);
        return;
    }
    bins_add(&m->bins, CNT(engine_busy), t, t + 1);
    if (--e->left)
        return;
    if (step_fills(&e->step) && !enqueue(m, queue_start)) {
        e->stalled = true;
        return;
    }
    engine_next(m, t);
}

/* ---- the fill unit and pipeline ---- */

/* vp_fill, noting which of the cell's samples it wrote: a sample is written
 * only if strictly nearer (docs/vp.md §4), so exactly those whose depth changed. */
static void fill_traced(machine *m, const queued_cell *qc)
{
    pipe_trace *pt = &m->pipe;
    const vp_cell *k = &qc->cell;
    const uint32_t cw = 1u << k->wl, n = vp_cell_samples(k);
    if (n > pt->cap) {
        uint32_t *nw = realloc(pt->won, (size_t)n * sizeof *nw);
        if (!nw) {
            m->err = diag_at(m->d, ALB_ERR_NOMEM, "", 0, 0, "out of memory for the trace");
            return;
        }
        pt->won = nw;
        pt->cap = n;
    }
    const uint32_t *depth = m->vp->s_depth;
    const size_t sw = m->vp->sw;
    for (uint32_t i = 0; i < n; i++)
        pt->won[i] = depth[(size_t)(k->r0 + i / cw) * sw + k->c0 + i % cw];
    vp_fill(m->vp, &qc->fs, k);
    for (uint32_t i = 0; i < n; i++)
        pt->won[i] = depth[(size_t)(k->r0 + i / cw) * sw + k->c0 + i % cw] != pt->won[i];
}

static void fill_tick(machine *m, int64_t t, uint64_t queue_start)
{
    fill_unit *f = &m->fill;
    if (!f->left) {
        if (!queue_start)
            return;
        queued_cell *qc = &f->q[f->head];
        f->head = (f->head + 1) % m->p->fill_queue;
        f->count--;
        f->left = fill_cycles(vp_cell_samples(&qc->cell), m->p->fill_rate);
        f->samples = vp_cell_samples(&qc->cell);
        f->next = 0;
        cycle_map_charge(&m->map, m->vp, &qc->cell, f->left);
        if (m->pipe_traced)
            fill_traced(m, qc);
        else
            vp_fill(m->vp, &qc->fs, &qc->cell);
    }
    bins_add(&m->bins, CNT(fill_busy), t, t + 1);
    f->left--;
    /* fill_rate samples a cycle; the cell's last cycle issues the rest */
    f->issue_at = f->next;
    f->issued = f->samples - f->next < m->p->fill_rate ? f->samples - f->next : m->p->fill_rate;
    f->next += f->issued;
    f->last_write = t + (int64_t)m->latency - 1;
}

/* ---- frames ---- */

static void retire_check(machine *m, int64_t t)
{
    if (m->ends_taken <= m->frame_open || m->engine.busy || m->fill.count || m->fill.left ||
        m->fill.last_write > t || t <= m->prev_retire)
        return;
    /* faces of the open frame still waiting in slots? */
    if (m->faces_started != m->faces_loaded &&
        m->slots[m->faces_started % m->p->face_slots].frame == m->frame_open)
        return;
    if (bins_retire(&m->bins, t)) {
        m->err = diag_at(m->d, ALB_ERR_NOMEM, "", 0, 0, "out of memory");
        return;
    }
    vp_frame_end(m->vp, &m->frame);
    cycle_map_resolve(&m->map, m->vp, &m->frame);
    if (m->sink && m->sink(m->ctx, &m->frame, vp_stats_get(m->vp),
                           &m->bins.bin[m->bins.nretired - 1]))
        m->err = ALB_ERR_IO;
    m->prev_retire = t;
    m->frame_open++;
    if (m->frames_taken > m->frame_open)
        vp_frame_begin(m->vp, m->ps.frame[m->frame_open]);
}

/* ---- trace ---- */

/* Identifiers by signal, the same whichever units are traced, so a
 * signal keeps its code in every trace. */
enum { SIG_CLK, SIG_FIFO_LEVEL, SIG_FIFO_PUSH, SIG_FIFO_POP, SIG_FIFO_FULL, SIG_FIFO_EMPTY,
       SIG_GP_STATE, SIG_PARSER_STATE, SIG_SLOTS, SIG_ENGINE_STATE, SIG_FACE, SIG_LEVEL,
       SIG_CELL_X, SIG_CELL_Y, SIG_RESULT, SIG_ACTIVE, SIG_FILL_BUSY, SIG_QUEUE, SIG_FRAME,
       SIG_FILL_ISSUED, SIG_PIPE_SAMPLES, SIG_PIPE_WRITE, SIG_PIPE_WRITTEN, SIG_COUNT };

static void trace_gp(const machine *m, vcd_t *v)
{
    vcd_set(v, SIG_GP_STATE, m->gp.state);
}

static void trace_fifo(const machine *m, vcd_t *v)
{
    vcd_set(v, SIG_FIFO_LEVEL, m->fifo.count);
    vcd_set(v, SIG_FIFO_PUSH, m->fifo.push);
    vcd_set(v, SIG_FIFO_POP, m->fifo.pop);
    vcd_set(v, SIG_FIFO_FULL, m->fifo.count >= m->p->fifo_depth);
    vcd_set(v, SIG_FIFO_EMPTY, m->fifo.count == 0);
}

static void trace_parser(const machine *m, vcd_t *v)
{
    vcd_set(v, SIG_PARSER_STATE, m->parser.state);
    vcd_set(v, SIG_SLOTS, m->faces_loaded - m->faces_started);
}

static void trace_engine(const machine *m, vcd_t *v)
{
    const engine_unit *e = &m->engine;
    /* what happened during the cycle, like the strobes: a face of a single
     * one-cycle step still shows */
    vcd_set(v, SIG_ENGINE_STATE, e->did);
    if (e->did) {
        vcd_set(v, SIG_FACE, e->did_face);
        vcd_set(v, SIG_LEVEL, e->did_step.cell.level);
        vcd_set(v, SIG_CELL_X, e->did_step.cell.c0);
        vcd_set(v, SIG_CELL_Y, e->did_step.cell.r0);
        vcd_set(v, SIG_RESULT, (uint64_t)e->did_step.kind + 1);
        vcd_set(v, SIG_ACTIVE, e->did_step.edges);
    } else {
        vcd_set(v, SIG_RESULT, 0);
    }
}

static void trace_fill(const machine *m, vcd_t *v)
{
    /* not fill.left, which is 0 after a cell's last cycle */
    vcd_set(v, SIG_FILL_BUSY, m->fill.issued > 0);
    vcd_set(v, SIG_QUEUE, m->fill.count);
    vcd_set(v, SIG_FILL_ISSUED, m->fill.issued);
}

static void trace_pipe(const machine *m, vcd_t *v)
{
    vcd_set(v, SIG_PIPE_SAMPLES, m->pipe.out);
    vcd_set(v, SIG_PIPE_WRITE, m->pipe.written > 0);
    vcd_set(v, SIG_PIPE_WRITTEN, m->pipe.written);
}

/* The units below the top scope, in trace order (--vcd-units picks
 * some; docs/microarchitecture.md, "Traces"): each a $scope of its signals
 * and the function that records them.  A unit left out is neither declared
 * nor recorded: a trace of a few units costs little more than their values. */
typedef struct {
    unsigned id;
    const char *name;
    unsigned width;
} trace_signal;

enum { UNIT_GP, UNIT_FIFO, UNIT_PARSER, UNIT_ENGINE, UNIT_FILL, UNIT_PIPE, TRACE_UNITS };
_Static_assert(SIM_TRACE_ALL == (1u << TRACE_UNITS) - 1, "SIM_TRACE_ALL: one bit a unit");

static const struct {
    const char *scope;
    void (*record)(const machine *m, vcd_t *v);
    trace_signal sig[8];         /* up to the first without a name */
} trace_units[TRACE_UNITS] = {
    [UNIT_GP] = {"gp", trace_gp, {{SIG_GP_STATE, "state", 2}}},
    [UNIT_FIFO] = {"fifo", trace_fifo, {{SIG_FIFO_LEVEL, "level", 21}, {SIG_FIFO_PUSH, "push", 1},
                                        {SIG_FIFO_POP, "pop", 1}, {SIG_FIFO_FULL, "full", 1},
                                        {SIG_FIFO_EMPTY, "empty", 1}}},
    [UNIT_PARSER] = {"parser", trace_parser, {{SIG_PARSER_STATE, "state", 2},
                                              {SIG_SLOTS, "slots_loaded", 7}}},
    [UNIT_ENGINE] = {"engine", trace_engine, {{SIG_ENGINE_STATE, "state", 2},
                                              {SIG_FACE, "face", 32}, {SIG_LEVEL, "level", 5},
                                              {SIG_CELL_X, "cell_x", 16},
                                              {SIG_CELL_Y, "cell_y", 16},
                                              {SIG_RESULT, "result", 3},
                                              {SIG_ACTIVE, "active_edges", 7}}},
    [UNIT_FILL] = {"fill", trace_fill, {{SIG_FILL_BUSY, "busy", 1}, {SIG_QUEUE, "queue", 11},
                                        {SIG_FILL_ISSUED, "issued", 9}}},
    [UNIT_PIPE] = {"pipe", trace_pipe, {{SIG_PIPE_SAMPLES, "samples", 9},
                                        {SIG_PIPE_WRITE, "write", 1},
                                        {SIG_PIPE_WRITTEN, "written", 9}}},
};

const char *sim_trace_unit_name(unsigned i)
{
    return i < TRACE_UNITS ? trace_units[i].scope : NULL;
}

int sim_trace_units_parse(const char *list, unsigned *mask, const char **bad, size_t *badlen)
{
    *mask = 0;
    for (const char *p = list;; p++) {
        size_t n = strcspn(p, ",");
        unsigned bit = 0;
        if (n == 3 && !strncmp(p, "all", 3))
            bit = SIM_TRACE_ALL;
        for (unsigned u = 0; u < TRACE_UNITS && !bit; u++)
            if (strlen(trace_units[u].scope) == n && !strncmp(p, trace_units[u].scope, n))
                bit = 1u << u;
        if (!bit) {
            *bad = p;
            *badlen = n;
            return -1;
        }
        *mask |= bit;
        p += n;
        if (!*p)
            return 0;
    }
}

/* Every signal: the clock and the open frame at the top, each unit in its
 * scope.  The writer drops the scopes it was not asked to keep
 * (vcd_keep_scope); the units it kept, a mask, are the ones recorded. */
static unsigned trace_declare(vcd_t *v)
{
    unsigned units = 0;
    vcd_scope(v, "albatros");
    vcd_var(v, SIG_CLK, "clk", 1);
    vcd_var(v, SIG_FRAME, "frame_open", 24);
    for (unsigned u = 0; u < TRACE_UNITS; u++) {
        vcd_scope(v, trace_units[u].scope);
        for (const trace_signal *sg = trace_units[u].sig; sg->name; sg++)
            vcd_var(v, sg->id, sg->name, sg->width);
        vcd_upscope(v);
        if (vcd_declared(v, trace_units[u].sig[0].id))
            units |= 1u << u;
    }
    vcd_upscope(v);
    return units;
}

/* The pipeline's stages this cycle (every cycle while tracing it, in or out of
 * the window): the samples issued now enter the first stage; the last stage
 * holds those issued L - 1 cycles ago, written at the end of this cycle. */
static void pipe_record(machine *m, int64_t t)
{
    pipe_trace *pt = &m->pipe;
    const fill_unit *f = &m->fill;
    unsigned won = 0;
    if (!m->err)   /* else fill_traced may have had no memory for the cell */
        for (uint32_t i = f->issue_at; i < f->issue_at + f->issued; i++)
            won += pt->won[i];
    uint16_t *first = pt->stage[t % m->latency];
    first[0] = (uint16_t)f->issued;
    first[1] = (uint16_t)won;
    const uint16_t *last = pt->stage[(t + 1) % m->latency];
    pt->out = last[0];
    pt->written = last[1];
}

static void trace_cycle(const machine *m, vcd_t *v, int64_t t, unsigned units)
{
    vcd_time(v, (uint64_t)t, 0);
    vcd_set(v, SIG_CLK, 1);
    vcd_set(v, SIG_FRAME, m->frame_open);
    for (unsigned u = 0; u < TRACE_UNITS; u++)
        if (units >> u & 1)
            trace_units[u].record(m, v);
    vcd_time(v, (uint64_t)t, 1);
    vcd_set(v, SIG_CLK, 0);
}

/* ---- the clock ---- */

static volatile sig_atomic_t interrupted;
static void on_interrupt(int sig) { interrupted = sig; }

/* sigaction, not signal(): in strict ISO/POSIX mode glibc's signal() has
 * System V semantics — the handler is reset on delivery — so a second Ctrl-C
 * (shells and timeout(1) signal the process group as well as the process)
 * would kill the run before its trace is complete. */
static void catch_signal(int sig, void (*fn)(int), struct sigaction *old)
{
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = fn;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = SA_RESTART;
    sigaction(sig, &sa, old);
}

static void tick(machine *m, int64_t t)
{
    uint64_t fifo_start = m->fifo.count, queue_start = m->fill.count;
    m->fifo.push = m->fifo.pop = false;
    m->fill.issued = 0;
    bins_at(&m->bins, t)->fifo_sum += fifo_start;
    parser_tick(m, t, fifo_start);
    gp_tick(m, t, fifo_start);
    engine_tick(m, t, queue_start);
    fill_tick(m, t, queue_start);
    if (m->fifo.push) {
        sim_counters *c = bins_at(&m->bins, t);
        if (m->fifo.count > c->fifo_peak)
            c->fifo_peak = m->fifo.count;
    }
    retire_check(m, t);
}

static alb_err machine_init(machine *m, const profile_t *p, bool pipe_traced, diag_t *d)
{
    memset(m, 0, sizeof *m);
    m->p = p;
    m->d = d;
    m->prev_retire = -1;
    m->fill.last_write = -1;
    m->latency = 1 + p->divider_latency + p->shade_latency;
    alb_err e = vp_create(&m->vp, p, d);
    if (e)
        return e;
    m->slots = calloc(p->face_slots, sizeof *m->slots);
    m->fill.q = calloc(p->fill_queue, sizeof *m->fill.q);
    m->pipe_traced = pipe_traced;
    if (pipe_traced)
        m->pipe.stage = calloc(m->latency, sizeof *m->pipe.stage);
    if (!m->slots || !m->fill.q || (pipe_traced && !m->pipe.stage) || bins_init(&m->bins) ||
        cycle_map_init(&m->map, m->vp) || vp_frame_alloc(m->vp, &m->frame, true))
        return diag_at(d, ALB_ERR_NOMEM, "", 0, 0, "out of memory for the cycle model");
    for (unsigned i = 0; i < p->face_slots; i++)
        m->slots[i].loaded_at = -1;
    return ALB_OK;
}

static void machine_free(machine *m)
{
    vp_destroy(m->vp);
    free(m->slots);
    free(m->fill.q);
    free(m->pipe.won);
    free(m->pipe.stage);
    free(m->ps.ev);
    free(m->ps.frame);
    bins_free(&m->bins);
    cycle_map_free(&m->map);
    frame_free(&m->frame);
}

alb_err sim_run_cycle(const profile_t *p, const uint32_t *w, size_t n, const char *name,
                      const sim_options *opt, sim_sink sink, void *ctx, diag_t *d)
{
    /* caught from the start: a Ctrl-C while the machine is set up (large
     * screens take a while) still ends with a complete trace */
    interrupted = 0;
    struct sigaction old_int, old_term;
    catch_signal(SIGINT, on_interrupt, &old_int);
    catch_signal(SIGTERM, on_interrupt, &old_term);
    machine m;
    vcd_t *v = opt->vcd;
    unsigned units = 0;
    if (v) {
        units = trace_declare(v);
        vcd_begin(v, 1000000000ull / p->clock_khz);
    }
    /* the pipeline's record (which samples win) only for the pipe's signals */
    alb_err e = machine_init(&m, p, units >> UNIT_PIPE & 1, d);
    if (!e)
        e = decode_all(w, n, name, p->frame_faces, &m.ps, d);
    m.sink = sink;
    m.ctx = ctx;
    int64_t t = 0;
    while (!e && !m.err) {
        tick(&m, t);
        if (v) {
            if (m.pipe_traced)
                pipe_record(&m, t);
            if ((uint64_t)t >= opt->vcd_from && (uint64_t)t <= opt->vcd_to)
                trace_cycle(&m, v, t, units);
        }
        t++;
        if (m.ended && drained(&m, t))
            break;
        if ((t == 1 || !(t & 4095)) && interrupted) {
            e = diag_at(d, ALB_ERR_INTERRUPTED, name, 0, 0, "interrupted at cycle %lld; the trace "
                        "is complete up to it", (long long)t);
            break;
        }
    }
    /* once interrupted, the process is on its way out: a second signal must
     * not cut the trace short */
    if (interrupted) {
        catch_signal(SIGINT, SIG_IGN, NULL);
        catch_signal(SIGTERM, SIG_IGN, NULL);
    } else {
        sigaction(SIGINT, &old_int, NULL);
        sigaction(SIGTERM, &old_term, NULL);
    }
    if (v)
        vcd_end(v, (uint64_t)t);
    if (!e)
        e = m.err;
    machine_free(&m);
    return e;
}
