/* sim_cycle.c — the cycle fidelity: GP output stage, FIFO, VP input parser,
 * subdivision engine, fill unit and depth/shade pipeline as explicit state,
 * each ticked once per clock by a clock that belongs to none of them
 * (docs/microarchitecture.md).  A unit reads only what the others held at the
 * start of the cycle (their registers) and writes its own next state.
 *
 * The machine takes its words as they come (sim_cycle_push) and runs as many
 * clocks as it is asked (sim_cycle_step), so a testbench can drive it beside
 * an RTL and compare the events of every cycle (docs/cosim.md); sim_run_cycle
 * gives it a whole stream and runs it to the end. */
#include "sim_internal.h"
#include "albatros/vcd.h"
#include "albatros/link.h"

#include <signal.h>
#include <stdlib.h>
#include <string.h>

/* ---- units ---- */

typedef struct {                 /* GP output stage */
    size_t next;                 /* index of the next word to push */
    size_t pkt_end;              /* end of the packet in hand */
    bool have;                   /* computing or pushing a packet */
    uint64_t compute_left;
    uint8_t state;               /* for the trace: 0 idle 1 compute 2 push 3 stall */
} gp_unit;

typedef struct {                 /* the GP -> VP FIFO: words [popped, pushed) */
    uint64_t count;
    size_t pushed;
    bool push, pop;              /* this cycle, for the trace */
} fifo_unit;

typedef struct {
    vp_loaded_face face;
    int64_t loaded_at;           /* cycle its last word was popped; -1 empty */
    unsigned frame;              /* frame it belongs to */
} slot;

typedef struct {                 /* VP input parser */
    size_t pos;                  /* index of the next word to take */
    size_t pkt_start, pkt_end;   /* the packet it is in (pkt_end = pkt_start: none yet) */
    alb_ws_event_kind kind;          /* that packet's kind, from its header word */
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

/* A queued cell names its face by its tag, the face's index in the frame's
 * face list (vp_begin_face), which holds the face's set-up for the frame:
 * the face's slot is freed when the engine is done with it, possibly before
 * its cells are filled. */
typedef struct {
    vp_cell cell;
    uint32_t face;               /* the face's tag */
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

/* A sample on its way through the pipeline to its write (write events). */
typedef struct {
    int64_t at;                  /* the cycle at whose end it is written */
    uint32_t x, y, depth, face;
    uint16_t rgb[3];
    uint8_t level;
} pending_write;

struct sim_cycle {
    alb_profile prof;
    const alb_profile *p;          /* &prof */
    alb_producer producer;
    alb_vp *vp;
    /* the stream as received: words [0, n) */
    uint32_t *w;
    size_t n, cap;
    size_t recv_pkt;             /* where the next packet starts among them */
    bool recv_end;               /* the packet recv_pkt ends is END */
    bool end_received;           /* the END packet's last word is among them */
    bool ext_push;               /* an external producer's word for the next cycle */
    alb_ws_reader rd;                /* the parser's grammar state, packet by packet */
    alb_ws_event *ev;
    const char *name;
    gp_unit gp;
    fifo_unit fifo;
    parser_unit parser;
    engine_unit engine;
    fill_unit fill;
    pipe_trace pipe;
    bool pipe_traced;            /* the trace has the pipe scope: keep pipe_trace */
    slot *slots;
    uint64_t faces_loaded, faces_started;   /* FIFO order of slots */
    unsigned slot_in, slot_out;  /* their slots: faces_loaded, faces_started mod face_slots */
    /* frames: frame_open (= frames retired) is the one whose faces may run;
     * later frames' packets may be taken while it drains */
    unsigned frames_taken;       /* FRAME packets taken */
    unsigned ends_taken;         /* FRAME_END packets taken */
    unsigned frame_open;
    alb_ws_frame *frames;            /* FRAME packets taken and not begun: [frame_open + 1, frames_taken) */
    unsigned frames_cap;
    int64_t prev_retire;
    bool ended;
    sim_bins bins;
    alb_sim_counters *cnt;       /* this cycle's bin: the frame retiring next */
    cycle_map map;
    bool pixels;                 /* frames wanted: else no output stage, no frame */
    sim_durations dur;           /* steps' and fills' cycles */
    alb_frame frame;
    alb_vp_stats last_stats;         /* of the last frame retired */
    unsigned latency;
    alb_sim_sink sink;
    void *ctx;
    /* events (docs/cosim.md): kinds recorded, the queue, writes in flight */
    uint32_t record;
    uint32_t happened;           /* kinds that happened in the last cycle */
    item_queue evq;              /* alb_event */
    item_queue wq;               /* pending_write, in write order */
    /* the trace */
    alb_vcd *vcd;
    uint64_t vcd_from, vcd_to;
    unsigned units;              /* units traced */
    int64_t t;                   /* the next cycle to run */
    alb_err err;
    alb_diag *d, dd;
};

/* i + 1 modulo n: the round-robin pointers of the slots and the fill queue
 * (no division a cycle). */
static inline unsigned ring_next(unsigned i, unsigned n) { return i + 1 == n ? 0 : i + 1; }

/* ---- events ---- */

static alb_event *event_new(sim_cycle *m, uint32_t kind, int64_t t)
{
    alb_event *e = queue_push(&m->evq);
    if (!e) {
        m->err = alb_diag_at(m->d, ALB_ERR_NOMEM, m->name, 0, 0, "out of memory for events");
        return NULL;
    }
    e->cycle = (uint64_t)t;
    e->kind = kind;
    return e;
}

/* An event of `kind` in cycle t: noted always (sim_cycle_happened), queued
 * only if recorded.  NULL when not recorded. */
static inline alb_event *event(sim_cycle *m, uint32_t kind, int64_t t)
{
    m->happened |= kind;
    return m->record & kind ? event_new(m, kind, t) : NULL;
}

static void event_word(sim_cycle *m, uint32_t kind, int64_t t, size_t index)
{
    alb_event *e = event(m, kind, t);
    if (e) {
        e->index = index;
        e->word = m->w[index];
    }
}

static void event_face(sim_cycle *m, uint32_t kind, int64_t t, const slot *s, size_t slot_index)
{
    alb_event *e = event(m, kind, t);
    if (e) {
        e->face = s->face.fs.id;
        e->slot = (uint32_t)slot_index;
        e->edges = s->face.n;
    }
}

static void event_cell(sim_cycle *m, uint32_t kind, int64_t t, uint32_t face, const vp_cell *k,
                       const vp_step *st)
{
    alb_event *e = event(m, kind, t);
    if (e) {
        e->face = face;
        e->x = k->c0;
        e->y = k->r0;
        e->wl = k->wl;
        e->hl = k->hl;
        e->level = k->level;
        if (st) {
            e->result = (uint8_t)(st->kind + 1);
            e->edges = st->edges;
        }
    }
}

/* ---- the stream ---- */

/* Everything earlier has retired: no face in the engine, slots, queue or
 * pipeline, and no frame waiting to retire (state at the start of cycle t). */
static bool drained(const sim_cycle *m, int64_t t)
{
    return !m->engine.busy && m->faces_started == m->faces_loaded && m->fill.count == 0 &&
           m->fill.left == 0 && m->fill.last_write < t && m->frames_taken == m->frame_open &&
           m->ends_taken == m->frame_open;
}

static alb_ws_event_kind kind_of(uint32_t header)
{
    switch (header >> 24) {
    case ALB_WS_OP_CONFIG: return ALB_WS_EV_CONFIG;
    case ALB_WS_OP_TEXTURE: return ALB_WS_EV_TEXTURE;
    case ALB_WS_OP_FRAME: return ALB_WS_EV_FRAME;
    case ALB_WS_OP_FACE: return ALB_WS_EV_FACE;
    case ALB_WS_OP_FRAME_END: return ALB_WS_EV_FRAME_END;
    default: return ALB_WS_EV_END;   /* END, or a header the decoder will refuse */
    }
}

/* The packet at word i ends at: its length from its header (an unknown
 * opcode counts as one word, which the parser's decoder then refuses). */
static size_t packet_end(const sim_cycle *m, size_t i)
{
    size_t len = alb_ws_packet_words(m->w[i]);
    return i + (len ? len : 1);
}

/* ---- the parser ---- */

static bool has_room(const sim_cycle *m, alb_ws_event_kind kind, int64_t t)
{
    switch (kind) {
    case ALB_WS_EV_FACE:
        return m->slots[m->slot_in].loaded_at < 0;
    case ALB_WS_EV_TEXTURE:
    case ALB_WS_EV_END:
        return drained(m, t);
    case ALB_WS_EV_FRAME:   /* a register set free: the open frame's and the waiting ones */
        return m->frames_taken - m->frame_open < m->p->frame_queue;
    default:
        return true;
    }
}

static void begin_frame(sim_cycle *m, const alb_ws_frame *f)
{
    alb_vp_frame_begin(m->vp, f);
}

/* A FRAME taken while an earlier frame drains: its registers wait. */
static void frame_wait(sim_cycle *m, const alb_ws_frame *f)
{
    unsigned k = m->frames_taken - m->frame_open - 2;   /* frames_taken counts it */
    if (k >= m->frames_cap) {
        unsigned cap = m->frames_cap ? 2 * m->frames_cap : 4;
        alb_ws_frame *nf = realloc(m->frames, cap * sizeof *nf);
        if (!nf) {
            m->err = alb_diag_at(m->d, ALB_ERR_NOMEM, m->name, 0, 0, "out of memory");
            return;
        }
        m->frames = nf;
        m->frames_cap = cap;
    }
    m->frames[k] = *f;
}

/* The parser took the last word of its packet in cycle t: decode it (the
 * words are all here) and hand it to the VP. */
static void packet_taken(sim_cycle *m, int64_t t)
{
    parser_unit *pa = &m->parser;
    alb_ws_event *ev = m->ev;
    m->rd.w = m->w;
    m->rd.n = pa->pkt_end;
    if (m->err || (m->err = alb_ws_next(&m->rd, ev, m->d)))
        return;
    switch (ev->kind) {
    case ALB_WS_EV_CONFIG:
        if (!(m->err = alb_vp_config(m->vp, &ev->u.config, m->d)))
            m->frame.near = ev->u.config.near;
        break;
    case ALB_WS_EV_TEXTURE:
        m->err = alb_vp_texture(m->vp, &ev->u.texture, m->d);
        break;
    case ALB_WS_EV_FRAME:
        /* the next frame's registers; it begins now if every earlier frame
         * has retired, else when its predecessor retires */
        if (m->frames_taken++ == m->frame_open)
            begin_frame(m, &ev->u.frame);
        else
            frame_wait(m, &ev->u.frame);
        break;
    case ALB_WS_EV_FACE: {
        size_t k = m->slot_in;
        slot *s = &m->slots[k];
        m->err = vp_load_face(m->vp, &ev->u.face, &s->face, m->d);
        s->loaded_at = t;
        s->frame = m->frames_taken - 1;
        m->faces_loaded++;
        m->slot_in = ring_next(m->slot_in, m->p->face_slots);
        event_face(m, ALB_EV_LOAD, t, s, k);
        break;
    }
    case ALB_WS_EV_FRAME_END:
        m->ends_taken++;
        break;
    case ALB_WS_EV_END:
        m->ended = true;
        break;
    }
    if (m->err && m->d->offset < 0 && !m->d->line) {
        /* a packet the decoder accepted but this VP cannot take: say where */
        char msg[sizeof m->d->msg];
        memcpy(msg, m->d->msg, sizeof msg);
        alb_diag_off(m->d, m->err, m->name, (long long)ev->first * 4, "word %zu: %s", ev->first, msg);
    }
}

static void parser_tick(sim_cycle *m, int64_t t, uint64_t fifo_start)
{
    parser_unit *pa = &m->parser;
    if (m->ended) {
        pa->state = 0;
        return;
    }
    /* the parser sees a word only once it is in the FIFO: before, it starves
     * whatever that word will need */
    if (fifo_start == 0) {
        m->cnt->parser_starve++;
        pa->state = 2;
        return;
    }
    if (pa->pos == pa->pkt_end) {   /* a header: its kind says where the packet goes */
        pa->pkt_start = pa->pos;
        pa->pkt_end = packet_end(m, pa->pos);
        pa->kind = kind_of(m->w[pa->pos]);
    }
    if (!has_room(m, pa->kind, t)) {
        m->cnt->parser_blocked++;
        pa->state = 3;
        return;
    }
    m->fifo.count--;
    m->fifo.pop = true;
    pa->state = 1;
    m->cnt->parser_busy++;
    event_word(m, ALB_EV_POP, t, pa->pos);
    if (++pa->pos == pa->pkt_end)
        packet_taken(m, t);
}

/* ---- the GP output stage, or the testbench in its place ---- */

static void push_word(sim_cycle *m, int64_t t)
{
    m->fifo.count++;
    m->fifo.push = true;
    m->cnt->gp_busy++;
    event_word(m, ALB_EV_PUSH, t, m->fifo.pushed++);
}

static void gp_tick(sim_cycle *m, int64_t t, uint64_t fifo_start)
{
    gp_unit *g = &m->gp;
    if (m->producer == ALB_PRODUCER_EXTERNAL) {
        g->state = m->ext_push ? 2 : 0;
        if (m->ext_push)
            push_word(m, t);
        m->ext_push = false;
        return;
    }
    if (!g->have) {
        if (m->fifo.pushed >= m->n) {   /* no packet given to it (yet) */
            g->state = 0;
            return;
        }
        g->have = true;
        g->pkt_end = packet_end(m, m->fifo.pushed);
        g->compute_left = gp_header_cycles(m->p, m->w[m->fifo.pushed]);
    }
    if (g->compute_left) {
        g->compute_left--;
        g->state = 1;
        m->cnt->gp_busy++;
        return;
    }
    if (m->fifo.pushed >= m->n) {       /* the packet's next word not given yet */
        g->state = 0;
        return;
    }
    if (fifo_start >= m->p->fifo_depth) {
        g->state = 3;
        m->cnt->gp_stall++;
        return;
    }
    g->state = 2;
    push_word(m, t);
    if (m->fifo.pushed == g->pkt_end)
        g->have = false;
}

/* ---- the engine ---- */

static bool step_fills(const vp_step *s)
{
    return s->kind == VP_STEP_FILL || s->kind == VP_STEP_SAMPLE_IN;
}

/* After a step's hand-over (or a step without one): the next step, or the
 * end of the face in cycle t. */
static void engine_next(sim_cycle *m, int64_t t)
{
    engine_unit *e = &m->engine;
    slot *s = &m->slots[e->slot];
    e->stalled = false;
    if (vp_walk_next(m->vp, &e->walk, &e->step)) {
        e->left = m->dur.step[e->step.edges];
        if (m->pixels)
            cycle_map_charge(&m->map, m->vp, &e->step.cell, e->left);
        return;
    }
    e->busy = false;
    event_face(m, ALB_EV_END, t, s, e->slot);
    s->loaded_at = -1;          /* the slot is free from the next cycle */
    m->faces_started++;
    m->slot_out = ring_next(m->slot_out, m->p->face_slots);
}

static bool enqueue(sim_cycle *m, uint64_t queue_start)
{
    fill_unit *f = &m->fill;
    if (queue_start >= m->p->fill_queue)
        return false;
    unsigned tail = f->head + f->count;
    queued_cell *qc = &f->q[tail >= m->p->fill_queue ? tail - m->p->fill_queue : tail];
    qc->cell = m->engine.step.cell;
    qc->face = m->slots[m->engine.slot].face.fs.tag;
    f->count++;
    return true;
}

static void engine_tick(sim_cycle *m, int64_t t, uint64_t queue_start)
{
    engine_unit *e = &m->engine;
    e->did = 0;
    if (!e->busy) {
        slot *s = &m->slots[m->slot_out];
        if (m->faces_started == m->faces_loaded || s->loaded_at < 0 || s->loaded_at >= t ||
            s->frame != m->frame_open || t <= m->prev_retire)
            return;
        e->busy = true;
        e->slot = m->slot_out;
        if ((m->err = vp_begin_face(m->vp, &s->face, m->d)))
            return;
        vp_walk_begin(&e->walk, m->vp, &s->face);
        event_face(m, ALB_EV_START, t, s, e->slot);
        engine_next(m, t);   /* the first step starts this cycle */
    }
    e->did = e->stalled ? 2 : 1;
    if (m->vcd) {   /* the trace's engine.*: the step as it stands in this cycle */
        e->did_step = e->step;
        e->did_face = m->slots[e->slot].face.fs.id;
    }
    if (e->stalled) {
        m->cnt->engine_stall++;
        if (enqueue(m, queue_start))
            engine_next(m, t);
        return;
    }
    m->cnt->engine_busy++;
    if (--e->left)
        return;
    event_cell(m, ALB_EV_CELL, t, m->slots[e->slot].face.fs.id, &e->step.cell, &e->step);
    if (step_fills(&e->step) && !enqueue(m, queue_start)) {
        e->stalled = true;
        return;
    }
    engine_next(m, t);
}

/* ---- the fill unit and pipeline ---- */

static pending_write *write_new(sim_cycle *m)
{
    pending_write *pw = queue_push(&m->wq);
    if (!pw)
        m->err = alb_diag_at(m->d, ALB_ERR_NOMEM, m->name, 0, 0, "out of memory for events");
    return pw;
}

/* vp_fill of the cell the fill unit takes in cycle t, noting which of its
 * samples it wrote — a sample is written only if strictly nearer (docs/vp.md
 * §4), so exactly those whose depth changed — for the trace's pipe.written,
 * and the values each write carries when write events are recorded: sample
 * i is issued in t + i / fill_rate and written L - 1 cycles later. */
static void fill_noted(sim_cycle *m, const queued_cell *qc, int64_t t)
{
    const vp_face_setup *fs = vp_frame_face(m->vp, qc->face);
    pipe_trace *pt = &m->pipe;
    const vp_cell *k = &qc->cell;
    const uint32_t cw = 1u << k->wl, n = vp_cell_samples(k);
    if (n > pt->cap) {
        uint32_t *nw = realloc(pt->won, (size_t)n * sizeof *nw);
        if (!nw) {
            m->err = alb_diag_at(m->d, ALB_ERR_NOMEM, m->name, 0, 0, "out of memory for the trace");
            return;
        }
        pt->won = nw;
        pt->cap = n;
    }
    const alb_vp *vp = m->vp;
    const uint32_t *depth = vp->s_depth;
    const size_t sw = vp->sw;
    vp_touch_tiles(m->vp, k);   /* the depths before: the store's, not a stale frame's */
    for (uint32_t i = 0; i < n; i++)
        pt->won[i] = depth[(size_t)(k->r0 + i / cw) * sw + k->c0 + i % cw];
    vp_fill(m->vp, fs, k);
    const bool writes = m->record & ALB_EV_WRITE;
    for (uint32_t i = 0; i < n; i++) {
        size_t idx = (size_t)(k->r0 + i / cw) * sw + k->c0 + i % cw;
        pt->won[i] = depth[idx] != pt->won[i];
        if (!writes || !pt->won[i])
            continue;
        pending_write *pw = write_new(m);
        if (!pw)
            return;
        pw->at = t + (int64_t)(i / m->p->fill_rate) + (int64_t)m->latency - 1;
        pw->x = k->c0 + i % cw;
        pw->y = k->r0 + i / cw;
        /* what the last stage writes: the face's depth, id, level and the
         * colour the output stage gives the sample */
        pw->depth = depth[idx];
        pw->face = fs->id;
        pw->level = k->level;
        vp_sample_colour(vp, fs, pw->x, pw->y, pw->rgb);
    }
}

static void fill_tick(sim_cycle *m, int64_t t, uint64_t queue_start)
{
    fill_unit *f = &m->fill;
    if (!f->left) {
        if (!queue_start)
            return;
        queued_cell *qc = &f->q[f->head];
        f->head = ring_next(f->head, m->p->fill_queue);
        f->count--;
        f->left = m->dur.fill[qc->cell.wl + qc->cell.hl];
        f->samples = vp_cell_samples(&qc->cell);
        f->next = 0;
        if (m->pixels)
            cycle_map_charge(&m->map, m->vp, &qc->cell, f->left);
        const vp_face_setup *fs = vp_frame_face(m->vp, qc->face);
        event_cell(m, ALB_EV_FILL, t, fs->id, &qc->cell, NULL);
        if (m->pipe_traced || (m->record & ALB_EV_WRITE))
            fill_noted(m, qc, t);
        else
            vp_fill(m->vp, fs, &qc->cell);
    }
    m->cnt->fill_busy++;
    f->left--;
    /* fill_rate samples a cycle; the cell's last cycle issues the rest */
    f->issue_at = f->next;
    f->issued = f->samples - f->next < m->p->fill_rate ? f->samples - f->next : m->p->fill_rate;
    f->next += f->issued;
    f->last_write = t + (int64_t)m->latency - 1;
}

/* The pipeline's last stage in cycle t: the writes due at its end. */
static void writes_due(sim_cycle *m, int64_t t)
{
    while (m->wq.n && ((const pending_write *)queue_front(&m->wq))->at == t) {
        const pending_write *pw = queue_front(&m->wq);
        alb_event *e = event(m, ALB_EV_WRITE, t);
        if (!e)
            return;
        e->x = pw->x;
        e->y = pw->y;
        e->depth = pw->depth;
        e->face = pw->face;
        e->level = pw->level;
        memcpy(e->rgb, pw->rgb, sizeof e->rgb);
        queue_drop(&m->wq, 1);
    }
}

/* ---- frames ---- */

static void retire_check(sim_cycle *m, int64_t t)
{
    if (m->ends_taken <= m->frame_open || m->engine.busy || m->fill.count || m->fill.left ||
        m->fill.last_write > t || t <= m->prev_retire)
        return;
    /* faces of the open frame still waiting in slots? */
    if (m->faces_started != m->faces_loaded &&
        m->slots[m->slot_out].frame == m->frame_open)
        return;
    if (bins_retire(&m->bins, t)) {
        m->err = alb_diag_at(m->d, ALB_ERR_NOMEM, m->name, 0, 0, "out of memory");
        return;
    }
    if (m->pixels) {
        alb_vp_frame_end(m->vp, &m->frame);
        cycle_map_resolve(&m->map, m->vp, &m->frame);
    } else {
        m->frame.number = m->vp->frame.number;
        m->frame.near = m->vp->cfg.near;
    }
    m->last_stats = *alb_vp_stats_get(m->vp);
    const alb_sim_counters *c = &m->bins.bin[m->bins.nretired - 1];
    alb_event *e = event(m, ALB_EV_FRAME, t);
    if (e) {
        e->index = m->frame_open;
        e->number = m->frame.number;
        e->cycles = c->cycles;
        e->crc = alb_link_frame_crc(m->frame.rgb, (size_t)m->frame.width * m->frame.height);
    }
    if (m->sink && m->sink(m->ctx, &m->frame, &m->last_stats, c))
        m->err = ALB_ERR_IO;   /* the sink says why */
    m->prev_retire = t;
    m->frame_open++;
    if (m->frames_taken > m->frame_open) {
        begin_frame(m, &m->frames[0]);
        memmove(m->frames, m->frames + 1, (m->frames_taken - m->frame_open - 1) * sizeof *m->frames);
    }
}
/* ---- trace ---- */

/* Identifiers by signal, the same whichever units are traced, so a
 * signal keeps its code in every trace. */
enum { SIG_CLK, SIG_FIFO_LEVEL, SIG_FIFO_PUSH, SIG_FIFO_POP, SIG_FIFO_FULL, SIG_FIFO_EMPTY,
       SIG_GP_STATE, SIG_PARSER_STATE, SIG_SLOTS, SIG_ENGINE_STATE, SIG_FACE, SIG_LEVEL,
       SIG_CELL_X, SIG_CELL_Y, SIG_RESULT, SIG_ACTIVE, SIG_FILL_BUSY, SIG_QUEUE, SIG_FRAME,
       SIG_FILL_ISSUED, SIG_PIPE_SAMPLES, SIG_PIPE_WRITE, SIG_PIPE_WRITTEN, SIG_COUNT };

static void trace_gp(const sim_cycle *m, alb_vcd *v)
{
    alb_vcd_set(v, SIG_GP_STATE, m->gp.state);
}

static void trace_fifo(const sim_cycle *m, alb_vcd *v)
{
    alb_vcd_set(v, SIG_FIFO_LEVEL, m->fifo.count);
    alb_vcd_set(v, SIG_FIFO_PUSH, m->fifo.push);
    alb_vcd_set(v, SIG_FIFO_POP, m->fifo.pop);
    alb_vcd_set(v, SIG_FIFO_FULL, m->fifo.count >= m->p->fifo_depth);
    alb_vcd_set(v, SIG_FIFO_EMPTY, m->fifo.count == 0);
}

static void trace_parser(const sim_cycle *m, alb_vcd *v)
{
    alb_vcd_set(v, SIG_PARSER_STATE, m->parser.state);
    alb_vcd_set(v, SIG_SLOTS, m->faces_loaded - m->faces_started);
}

static void trace_engine(const sim_cycle *m, alb_vcd *v)
{
    const engine_unit *e = &m->engine;
    /* what happened during the cycle, like the strobes: a face of a single
     * one-cycle step still shows */
    alb_vcd_set(v, SIG_ENGINE_STATE, e->did);
    if (e->did) {
        alb_vcd_set(v, SIG_FACE, e->did_face);
        alb_vcd_set(v, SIG_LEVEL, e->did_step.cell.level);
        alb_vcd_set(v, SIG_CELL_X, e->did_step.cell.c0);
        alb_vcd_set(v, SIG_CELL_Y, e->did_step.cell.r0);
        alb_vcd_set(v, SIG_RESULT, (uint64_t)e->did_step.kind + 1);
        alb_vcd_set(v, SIG_ACTIVE, e->did_step.edges);
    } else {
        alb_vcd_set(v, SIG_RESULT, 0);
    }
}

static void trace_fill(const sim_cycle *m, alb_vcd *v)
{
    /* not fill.left, which is 0 after a cell's last cycle */
    alb_vcd_set(v, SIG_FILL_BUSY, m->fill.issued > 0);
    alb_vcd_set(v, SIG_QUEUE, m->fill.count);
    alb_vcd_set(v, SIG_FILL_ISSUED, m->fill.issued);
}

static void trace_pipe(const sim_cycle *m, alb_vcd *v)
{
    alb_vcd_set(v, SIG_PIPE_SAMPLES, m->pipe.out);
    alb_vcd_set(v, SIG_PIPE_WRITE, m->pipe.written > 0);
    alb_vcd_set(v, SIG_PIPE_WRITTEN, m->pipe.written);
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
_Static_assert(ALB_SIM_TRACE_ALL == (1u << TRACE_UNITS) - 1, "SIM_TRACE_ALL: one bit a unit");

static const struct {
    const char *scope;
    void (*record)(const sim_cycle *m, alb_vcd *v);
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

const char *alb_sim_trace_unit_name(unsigned i)
{
    return i < TRACE_UNITS ? trace_units[i].scope : NULL;
}

int alb_sim_trace_units_parse(const char *list, unsigned *mask, const char **bad, size_t *badlen)
{
    *mask = 0;
    for (const char *p = list;; p++) {
        size_t n = strcspn(p, ",");
        unsigned bit = 0;
        if (n == 3 && !strncmp(p, "all", 3))
            bit = ALB_SIM_TRACE_ALL;
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
 * (alb_vcd_keep_scope); the units it kept, a mask, are the ones recorded. */
static unsigned trace_declare(alb_vcd *v)
{
    unsigned units = 0;
    alb_vcd_scope(v, "albatros");
    alb_vcd_var(v, SIG_CLK, "clk", 1);
    alb_vcd_var(v, SIG_FRAME, "frame_open", 24);
    for (unsigned u = 0; u < TRACE_UNITS; u++) {
        alb_vcd_scope(v, trace_units[u].scope);
        for (const trace_signal *sg = trace_units[u].sig; sg->name; sg++)
            alb_vcd_var(v, sg->id, sg->name, sg->width);
        alb_vcd_upscope(v);
        if (alb_vcd_declared(v, trace_units[u].sig[0].id))
            units |= 1u << u;
    }
    alb_vcd_upscope(v);
    return units;
}

/* The pipeline's stages this cycle (every cycle while tracing it, in or out of
 * the window): the samples issued now enter the first stage; the last stage
 * holds those issued L - 1 cycles ago, written at the end of this cycle. */
static void pipe_record(sim_cycle *m, int64_t t)
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

static void trace_cycle(const sim_cycle *m, alb_vcd *v, int64_t t, unsigned units)
{
    alb_vcd_time(v, (uint64_t)t, 0);
    alb_vcd_set(v, SIG_CLK, 1);
    alb_vcd_set(v, SIG_FRAME, m->frame_open);
    for (unsigned u = 0; u < TRACE_UNITS; u++)
        if (units >> u & 1)
            trace_units[u].record(m, v);
    alb_vcd_time(v, (uint64_t)t, 1);
    alb_vcd_set(v, SIG_CLK, 0);
}

/* ---- the clock ---- */

static void tick(sim_cycle *m, int64_t t)
{
    uint64_t fifo_start = m->fifo.count, queue_start = m->fill.count;
    m->fifo.push = m->fifo.pop = false;
    m->fill.issued = 0;
    /* the counters of the frame this cycle belongs to (the open one) */
    m->cnt = bins_at(&m->bins, t);
    m->cnt->fifo_sum += fifo_start;
    gp_tick(m, t, fifo_start);
    parser_tick(m, t, fifo_start);
    engine_tick(m, t, queue_start);
    fill_tick(m, t, queue_start);
    if (m->wq.n)
        writes_due(m, t);
    if (m->fifo.push) {
        alb_sim_counters *c = m->cnt;
        if (m->fifo.count > c->fifo_peak)
            c->fifo_peak = m->fifo.count;
    }
    retire_check(m, t);
}

alb_err sim_cycle_open(sim_cycle **out, const alb_profile *p, const sim_cycle_config *cfg,
                       alb_diag *d)
{
    *out = NULL;
    sim_cycle *m = calloc(1, sizeof *m);
    if (!m)
        return alb_diag_at(d, ALB_ERR_NOMEM, "", 0, 0, "out of memory for the cycle model");
    m->prof = *p;
    m->p = &m->prof;
    m->d = d ? d : &m->dd;
    if (!d)
        alb_diag_init(&m->dd, NULL);
    m->name = cfg && cfg->name ? cfg->name : "<stream>";
    m->producer = cfg ? cfg->producer : ALB_PRODUCER_GP;
    m->record = cfg ? cfg->events & ALB_EV_ALL : 0;
    m->sink = cfg ? cfg->sink : NULL;
    m->ctx = cfg ? cfg->ctx : NULL;
    m->prev_retire = -1;
    m->fill.last_write = -1;
    m->latency = 1 + p->divider_latency + p->shade_latency;
    sim_durations_init(&m->dur, p);
    m->evq = ITEM_QUEUE(alb_event);
    m->wq = ITEM_QUEUE(pending_write);
    alb_ws_reader_init(&m->rd, NULL, 0, m->name);
    m->rd.max_faces = p->frame_faces;
    alb_err e = alb_vp_create(&m->vp, p, m->d);
    if (e) {
        free(m);
        return e;
    }
    if (cfg && cfg->vcd) {
        m->vcd = cfg->vcd;
        m->vcd_from = cfg->vcd_from;
        m->vcd_to = cfg->vcd_to;
        m->units = trace_declare(m->vcd);
        alb_vcd_window(m->vcd, m->vcd_from, m->vcd_to);
        alb_vcd_begin(m->vcd, 1000000000ull / p->clock_khz);
    }
    /* the pipeline's record (which samples win) only for the pipe's signals */
    m->pipe_traced = m->units >> UNIT_PIPE & 1;
    /* a FRAME event carries the resolved frame's CRC */
    m->pixels = !(cfg && cfg->counters_only) || (m->record & ALB_EV_FRAME);
    sim_frame_without_planes(p, &m->frame);
    m->slots = calloc(p->face_slots, sizeof *m->slots);
    m->fill.q = calloc(p->fill_queue, sizeof *m->fill.q);
    m->ev = malloc(sizeof *m->ev);
    if (m->pipe_traced)
        m->pipe.stage = calloc(m->latency, sizeof *m->pipe.stage);
    if (!m->slots || !m->fill.q || !m->ev || (m->pipe_traced && !m->pipe.stage) ||
        bins_init(&m->bins) ||
        (m->pixels && (cycle_map_init(&m->map, m->vp) || alb_vp_frame_alloc(m->vp, &m->frame, true)))) {
        sim_cycle_close(m);
        return alb_diag_at(d, ALB_ERR_NOMEM, "", 0, 0, "out of memory for the cycle model");
    }
    for (unsigned i = 0; i < p->face_slots; i++)
        m->slots[i].loaded_at = -1;
    *out = m;
    return ALB_OK;
}

void sim_cycle_close(sim_cycle *m)
{
    if (!m)
        return;
    alb_vp_destroy(m->vp);
    free(m->w);
    free(m->slots);
    free(m->fill.q);
    free(m->pipe.won);
    free(m->pipe.stage);
    free(m->ev);
    free(m->frames);
    queue_free(&m->evq);
    queue_free(&m->wq);
    bins_free(&m->bins);
    cycle_map_free(&m->map);
    alb_frame_free(&m->frame);
    free(m);
}

/* Words into the stream as received; refused after the END packet. */
static size_t receive(sim_cycle *m, const uint32_t *w, size_t n)
{
    size_t i = 0;
    for (; i < n; i++) {
        if (m->end_received) {
            m->err = alb_diag_off(m->d, ALB_ERR_STREAM, m->name, (long long)m->n * 4,
                              "word %zu: a word after END", m->n);
            break;
        }
        if (m->n == m->cap) {
            size_t cap = m->cap ? 2 * m->cap : 4096;
            uint32_t *nw = realloc(m->w, cap * sizeof *nw);
            if (!nw) {
                m->err = alb_diag_at(m->d, ALB_ERR_NOMEM, m->name, 0, 0, "out of memory for the stream");
                break;
            }
            m->w = nw;
            m->cap = cap;
        }
        m->w[m->n] = w[i];
        if (m->n == m->recv_pkt) {
            m->recv_pkt = packet_end(m, m->n);
            m->recv_end = w[i] >> 24 == ALB_WS_OP_END;
        }
        if (++m->n == m->recv_pkt && m->recv_end)
            m->end_received = true;
    }
    return i;
}

size_t sim_cycle_push(sim_cycle *m, const uint32_t *w, size_t n)
{
    if (m->err || !n)
        return 0;
    if (m->producer == ALB_PRODUCER_GP)
        return receive(m, w, n);
    /* the testbench is the producer: one word into the FIFO in the next
     * cycle, if the FIFO holds fewer than fifo_depth words at its start */
    if (m->ext_push || m->fifo.count >= m->p->fifo_depth || !receive(m, w, 1))
        return 0;
    m->ext_push = true;
    return 1;
}

bool sim_cycle_done(const sim_cycle *m) { return m->ended && drained(m, m->t); }

static void trace_one(sim_cycle *m, int64_t t)
{
    if (m->pipe_traced)
        pipe_record(m, t);
    /* from the first cycle: the writer keeps the values before the window
     * (it dumps them all at its start) and writes nothing after it */
    if ((uint64_t)t <= m->vcd_to)
        trace_cycle(m, m->vcd, t, m->units);
}

alb_err sim_cycle_step(sim_cycle *m, uint64_t cycles, uint32_t until, uint64_t *ran)
{
    uint64_t i = 0;
    while (i < cycles && !m->err && !sim_cycle_done(m)) {
        m->happened = 0;
        tick(m, m->t);
        if (m->vcd)
            trace_one(m, m->t);
        m->t++;
        i++;
        if (m->happened & until)
            break;
    }
    if (ran)
        *ran = i;
    return m->err;
}

uint64_t sim_cycle_now(const sim_cycle *m) { return (uint64_t)m->t; }

size_t sim_cycle_events(const sim_cycle *m, const alb_event **ev)
{
    *ev = queue_front(&m->evq);
    return m->evq.n;
}

void sim_cycle_consume(sim_cycle *m, size_t k)
{
    queue_drop(&m->evq, k);
}

const alb_frame *sim_cycle_frame(const sim_cycle *m, const alb_vp_stats **st, const alb_sim_counters **c)
{
    if (!m->bins.nretired)
        return NULL;
    if (st)
        *st = &m->last_stats;
    if (c)
        *c = &m->bins.bin[m->bins.nretired - 1];
    return &m->frame;
}

const alb_sim_counters *sim_cycle_counters(const sim_cycle *m, unsigned k)
{
    return k < m->bins.nretired ? &m->bins.bin[k] : NULL;
}

uint64_t sim_cycle_fifo_level(const sim_cycle *m) { return m->fifo.count; }

const alb_diag *sim_cycle_diag(const sim_cycle *m) { return m->d; }

alb_err sim_cycle_status(const sim_cycle *m) { return m->err; }

uint32_t sim_cycle_happened(const sim_cycle *m) { return m->happened; }

/* ---- a whole stream ---- */

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

/* The whole stream, decoded once before the first clock: a malformed one
 * is refused with the decoder's message before any cycle runs. */
static alb_err check_stream(const uint32_t *w, size_t n, const char *name, uint32_t max_faces,
                            alb_diag *d)
{
    alb_ws_reader r;
    alb_ws_event *ev = malloc(sizeof *ev);
    if (!ev)
        return alb_diag_at(d, ALB_ERR_NOMEM, name, 0, 0, "out of memory decoding the stream");
    alb_ws_reader_init(&r, w, n, name);
    r.max_faces = max_faces;
    alb_err e = ALB_OK;
    while (!e && !r.ended)
        e = alb_ws_next(&r, ev, d);
    free(ev);
    return e;
}

alb_err sim_run_cycle(const alb_profile *p, const uint32_t *w, size_t n, const char *name,
                      const alb_sim_options *opt, alb_sim_sink sink, void *ctx, alb_diag *d)
{
    /* caught from the start: a Ctrl-C while the machine is set up (large
     * screens take a while) still ends with a complete trace */
    interrupted = 0;
    struct sigaction old_int, old_term;
    catch_signal(SIGINT, on_interrupt, &old_int);
    catch_signal(SIGTERM, on_interrupt, &old_term);
    sim_cycle_config cfg = {.producer = ALB_PRODUCER_GP, .events = opt->events,
                            .sink = sink, .ctx = ctx, .name = name, .vcd = opt->vcd,
                            .vcd_from = opt->vcd_from, .vcd_to = opt->vcd_to,
                            .counters_only = opt->counters_only};
    sim_cycle *m = NULL;
    alb_err e = sim_cycle_open(&m, p, &cfg, d);
    if (!e)
        e = check_stream(w, n, name, p->frame_faces, d);
    if (!e && sim_cycle_push(m, w, n) != n)
        e = m->err;
    while (!e && !sim_cycle_done(m)) {
        e = sim_cycle_step(m, 4096, 0, NULL);
        if (!e && m->evq.n && opt->on_events) {
            if (opt->on_events(opt->events_ctx, queue_front(&m->evq), m->evq.n))
                e = ALB_ERR_IO;
            sim_cycle_consume(m, m->evq.n);
        }
        if (!e && interrupted)
            e = alb_diag_at(d, ALB_ERR_INTERRUPTED, name, 0, 0, "interrupted at cycle %lld; the trace "
                        "is complete up to it", (long long)m->t);
    }
    if (!e && m->evq.n && opt->on_events &&
        opt->on_events(opt->events_ctx, queue_front(&m->evq), m->evq.n))
        e = ALB_ERR_IO;
    /* once interrupted, the process is on its way out: a second signal must
     * not cut the trace short */
    if (interrupted) {
        catch_signal(SIGINT, SIG_IGN, NULL);
        catch_signal(SIGTERM, SIG_IGN, NULL);
    } else {
        sigaction(SIGINT, &old_int, NULL);
        sigaction(SIGTERM, &old_term, NULL);
    }
    if (m && m->vcd)
        alb_vcd_end(m->vcd, (uint64_t)m->t);
    sim_cycle_close(m);
    return e;
}

/* ---- events as text (docs/cosim.md) ---- */

static const char *const event_names[] = {"push", "pop", "load", "start", "cell",
                                          "end",  "fill", "write", "frame"};

size_t alb_event_size(void) { return sizeof(alb_event); }

const char *alb_sim_event_name(uint32_t kind)
{
    for (unsigned i = 0; i < sizeof event_names / sizeof *event_names; i++)
        if (kind == 1u << i)
            return event_names[i];
    return NULL;
}

int alb_sim_events_parse(const char *list, uint32_t *mask, const char **bad, size_t *badlen)
{
    *mask = 0;
    for (const char *p = list;; p++) {
        size_t n = strcspn(p, ",");
        uint32_t bit = 0;
        if (n == 3 && !strncmp(p, "all", 3))
            bit = ALB_EV_ALL;
        for (unsigned i = 0; i < sizeof event_names / sizeof *event_names && !bit; i++)
            if (strlen(event_names[i]) == n && !strncmp(p, event_names[i], n))
                bit = 1u << i;
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

int alb_sim_event_format(const alb_event *e, char *buf, size_t len)
{
    unsigned long long t = (unsigned long long)e->cycle;
    const char *k = alb_sim_event_name(e->kind);
    switch (e->kind) {
    case ALB_EV_PUSH:
    case ALB_EV_POP:
        return snprintf(buf, len, "%llu %s %llu 0x%08x\n", t, k, (unsigned long long)e->index,
                        e->word);
    case ALB_EV_LOAD:
        return snprintf(buf, len, "%llu %s %u %u %u\n", t, k, e->face, e->slot, e->edges);
    case ALB_EV_START:
    case ALB_EV_END:
        return snprintf(buf, len, "%llu %s %u %u\n", t, k, e->face, e->slot);
    case ALB_EV_CELL:
        return snprintf(buf, len, "%llu %s %u %u %u %u %u %u %u %u\n", t, k, e->face, e->x, e->y,
                        e->wl, e->hl, e->level, e->result, e->edges);
    case ALB_EV_FILL:
        return snprintf(buf, len, "%llu %s %u %u %u %u %u %u\n", t, k, e->face, e->x, e->y, e->wl,
                        e->hl, e->level);
    case ALB_EV_WRITE:
        return snprintf(buf, len, "%llu %s %u %u %u %u %u %u %u %u\n", t, k, e->x, e->y, e->depth,
                        e->rgb[0], e->rgb[1], e->rgb[2], e->face, e->level);
    case ALB_EV_FRAME:
        return snprintf(buf, len, "%llu %s %u %llu 0x%08x\n", t, k, e->number,
                        (unsigned long long)e->cycles, e->crc);
    }
    return snprintf(buf, len, "%llu unknown %u\n", t, e->kind);
}
