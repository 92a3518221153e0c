/* model.c — alb_model, the golden model a testbench drives (docs/cosim.md):
 * one object over the three fidelities.  The cycle fidelity is the clocked
 * machine of sim_cycle.c, stepped on demand; the timed fidelity is the
 * incremental timed model (sim_timed.c) fed as words come; the functional
 * one is the VP taking whole packets.  The latter two report frames only. */
#include "sim_internal.h"
#include "albatros/albatros.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

struct alb_model {
    alb_model_config cfg;
    alb_profile prof;
    alb_diag d;
    char error[800];
    alb_err err;
    sim_cycle *cyc;                /* cycle fidelity */
    alb_sim_feed *feed;            /* timed */
    alb_vp *vp;                    /* functional */
    alb_ws_reader rd;
    alb_ws_event *ev;
    /* the words so far (timed, functional), and whether END was among them */
    uint32_t *w;
    size_t n, cap;
    bool ended;
    /* frame events and the last frame (timed, functional) */
    item_queue evq;                /* alb_event */
    alb_frame frame;
    alb_vp_stats stats;
    unsigned frames;
};

const char *alb_version(void) { return ALB_VERSION_STRING; }

void alb_model_config_default(alb_model_config *c)
{
    memset(c, 0, sizeof *c);
    c->fidelity = ALB_FIDELITY_CYCLE;
    c->producer = ALB_PRODUCER_GP;
    c->events = ALB_EV_FRAME;
    c->threads = 1;
}

static alb_err fail(alb_model *m, alb_err e)
{
    m->err = e;
    alb_diag_format(&m->d, m->error, sizeof m->error);
    return e;
}

/* ---- frames of the timed and functional fidelities ---- */

/* A frame done: keep it, and its event if frames are recorded. */
static int frame_done(void *ctx, const alb_frame *f, const alb_vp_stats *st,
                      const alb_sim_counters *c)
{
    alb_model *m = ctx;
    if (!m->frame.rgb || m->frame.width != f->width || m->frame.height != f->height ||
        !m->frame.cycles != !f->cycles) {
        alb_frame_free(&m->frame);
        if (alb_frame_copy(&m->frame, f))
            return -1;
    } else {
        size_t np = (size_t)f->width * f->height;
        uint32_t *cycles = m->frame.cycles;
        uint16_t *rgb = m->frame.rgb, *cov = m->frame.coverage;
        uint32_t *depth = m->frame.depth, *face = m->frame.face;
        uint8_t *level = m->frame.level;
        m->frame = *f;
        m->frame.rgb = memcpy(rgb, f->rgb, 3 * np * sizeof *rgb);
        m->frame.coverage = memcpy(cov, f->coverage, np * sizeof *cov);
        m->frame.depth = memcpy(depth, f->depth, np * sizeof *depth);
        m->frame.face = memcpy(face, f->face, np * sizeof *face);
        m->frame.level = memcpy(level, f->level, np);
        m->frame.cycles = cycles ? memcpy(cycles, f->cycles, np * sizeof *cycles) : NULL;
    }
    m->stats = *st;
    if (m->cfg.events & ALB_EV_FRAME) {
        alb_event *e = queue_push(&m->evq);
        if (!e)
            return -1;
        e->kind = ALB_EV_FRAME;
        e->index = m->frames;
        e->number = f->number;
        e->cycle = c ? c->retire : 0;
        e->cycles = c ? c->cycles : 0;
        e->crc = alb_link_frame_crc(f->rgb, (size_t)f->width * f->height);
    }
    m->frames++;
    return 0;
}

static int frame_counted(void *ctx, const alb_frame *f, const alb_vp_stats *st,
                         const alb_sim_counters *c)
{
    (void)f, (void)st, (void)c;
    ((alb_model *)ctx)->frames++;
    return 0;
}

/* ---- creation ---- */

alb_err alb_model_create(alb_model **out, const alb_profile *p, const alb_model_config *c,
                         alb_diag *d)
{
    *out = NULL;
    alb_model *m = calloc(1, sizeof *m);
    alb_diag local;
    if (!d)
        d = &local;
    alb_diag_init(d, NULL);
    if (!m)
        return alb_diag_at(d, ALB_ERR_NOMEM, "", 0, 0, "out of memory for a model");
    if (c)
        m->cfg = *c;
    else
        alb_model_config_default(&m->cfg);
    if (!m->cfg.name)
        m->cfg.name = "<stream>";
    m->evq = ITEM_QUEUE(alb_event);
    m->prof = *p;
    alb_diag_init(&m->d, NULL);
    char msg[256];
    alb_err e = ALB_OK;
    if (alb_profile_check(p, msg, sizeof msg))
        e = alb_diag_at(&m->d, ALB_ERR_CONFIG, "", 0, 0, "%s", msg);
    else if (m->cfg.fidelity == ALB_FIDELITY_CYCLE) {
        /* the machine keeps its last frame and makes its own events */
        sim_cycle_config sc = {.producer = m->cfg.producer, .events = m->cfg.events,
                               .sink = frame_counted, .ctx = m, .name = m->cfg.name};
        e = sim_cycle_open(&m->cyc, &m->prof, &sc, &m->d);
    } else if (m->cfg.fidelity == ALB_FIDELITY_TIMED) {
        e = alb_sim_feed_open(&m->feed, &m->prof, m->cfg.name, frame_done, m, &m->d);
    } else {
        e = alb_vp_create(&m->vp, &m->prof, &m->d);
        if (!e && m->cfg.threads > 1 && alb_vp_set_threads(m->vp, m->cfg.threads))
            e = alb_diag_at(&m->d, ALB_ERR_NOMEM, "", 0, 0, "out of memory for threads");
        m->ev = malloc(sizeof *m->ev);
        if (!e && !m->ev)
            e = alb_diag_at(&m->d, ALB_ERR_NOMEM, "", 0, 0, "out of memory");
        alb_ws_reader_init(&m->rd, NULL, 0, m->cfg.name);
        m->rd.max_faces = p->frame_faces;
    }
    if (e) {
        *d = m->d;
        alb_model_destroy(m);
        return e;
    }
    *out = m;
    return ALB_OK;
}

alb_err alb_model_open(alb_model **out, const char *profile, const char *const *overrides,
                       const alb_model_config *c, alb_diag *d)
{
    alb_diag local;
    if (!d)
        d = &local;
    alb_diag_init(d, NULL);
    *out = NULL;
    alb_profile p;
    alb_err e = alb_profile_open(&p, profile, overrides, d);
    return e ? e : alb_model_create(out, &p, c, d);
}

void alb_model_destroy(alb_model *m)
{
    if (!m)
        return;
    sim_cycle_close(m->cyc);
    alb_sim_feed_close(m->feed);
    alb_vp_destroy(m->vp);
    alb_frame_free(&m->frame);
    free(m->ev);
    free(m->w);
    queue_free(&m->evq);
    free(m);
}

/* ---- words ---- */

/* The functional VP on the whole packets of w[0, n) not taken yet. */
static alb_err functional_feed(alb_model *m)
{
    while (!m->rd.ended && m->rd.pos < m->n) {
        alb_ws_reader r = m->rd;
        r.w = m->w;
        r.n = m->n;
        alb_diag dd;
        alb_diag_init(&dd, NULL);
        alb_err e = alb_ws_next(&r, m->ev, &dd);
        if (e) {
            if (dd.offset == (long long)m->n * 4)
                return ALB_OK;   /* a packet still arriving */
            m->d = dd;
            return e;
        }
        m->rd = r;
        alb_ws_event *ev = m->ev;
        switch (ev->kind) {
        case ALB_WS_EV_CONFIG:
            e = alb_vp_config(m->vp, &ev->u.config, &m->d);
            if (!e && !m->frame.rgb && (alb_vp_frame_alloc(m->vp, &m->frame, false)))
                e = alb_diag_at(&m->d, ALB_ERR_NOMEM, m->cfg.name, 0, 0, "out of memory");
            break;
        case ALB_WS_EV_TEXTURE:
            e = alb_vp_texture(m->vp, &ev->u.texture, &m->d);
            break;
        case ALB_WS_EV_FRAME:
            alb_vp_frame_begin(m->vp, &ev->u.frame);
            break;
        case ALB_WS_EV_FACE:
            e = alb_vp_face(m->vp, &ev->u.face, &m->d);
            break;
        case ALB_WS_EV_FRAME_END: {
            alb_frame *f = &m->frame;
            alb_vp_frame_end(m->vp, f);
            if (frame_done(m, f, alb_vp_stats_get(m->vp), NULL))
                e = alb_diag_at(&m->d, ALB_ERR_NOMEM, m->cfg.name, 0, 0, "out of memory");
            break;
        }
        case ALB_WS_EV_END:
            break;
        }
        if (e) {
            if (m->d.offset < 0 && !m->d.line) {
                char msg[sizeof m->d.msg];
                memcpy(msg, m->d.msg, sizeof msg);
                alb_diag_off(&m->d, e, m->cfg.name, (long long)ev->first * 4, "word %zu: %s",
                             ev->first, msg);
            }
            return e;
        }
    }
    return ALB_OK;
}

static size_t keep_words(alb_model *m, const uint32_t *w, size_t n)
{
    if (m->ended) {
        alb_diag_off(&m->d, ALB_ERR_STREAM, m->cfg.name, (long long)m->n * 4,
                     "word %zu: a word after END", m->n);
        fail(m, ALB_ERR_STREAM);
        return 0;
    }
    if (m->n + n > m->cap) {
        size_t cap = m->cap ? m->cap : 4096;
        while (cap < m->n + n)
            cap *= 2;
        uint32_t *nw = realloc(m->w, cap * sizeof *nw);
        if (!nw) {
            alb_diag_at(&m->d, ALB_ERR_NOMEM, m->cfg.name, 0, 0, "out of memory for the stream");
            fail(m, ALB_ERR_NOMEM);
            return 0;
        }
        m->w = nw;
        m->cap = cap;
    }
    memcpy(m->w + m->n, w, n * sizeof *w);
    m->n += n;
    return n;
}

size_t alb_model_push(alb_model *m, const uint32_t *w, size_t n)
{
    if (m->err || !n)
        return 0;
    if (m->cyc) {
        size_t k = sim_cycle_push(m->cyc, w, n);
        alb_err e = sim_cycle_status(m->cyc);
        if (e)
            fail(m, e);   /* refused for an error, not for back-pressure */
        return k;
    }
    size_t k = keep_words(m, w, n);
    if (!k)
        return 0;
    alb_err e;
    if (m->feed) {
        e = alb_sim_feed_words(m->feed, m->w, m->n, &m->d);
        size_t taken = sim_feed_taken(m->feed, &m->ended);
        if (!e && m->ended && taken < m->n)
            e = alb_diag_off(&m->d, ALB_ERR_STREAM, m->cfg.name, (long long)taken * 4,
                             "word %zu: %zu words after END", taken, m->n - taken);
    } else {
        e = functional_feed(m);
        m->ended = m->rd.ended;
    }
    if (e)
        fail(m, e);
    return k;
}

/* ---- the clock ---- */

alb_err alb_model_step(alb_model *m, uint64_t cycles)
{
    alb_stop why;
    return alb_model_run(m, 0, cycles, &why);
}

alb_err alb_model_run(alb_model *m, uint32_t until, uint64_t max_cycles, alb_stop *why)
{
    alb_stop w = ALB_STOP_CYCLES;
    if (m->err) {
        if (why)
            *why = w;
        return m->err;
    }
    if (m->cyc) {
        uint64_t ran;
        alb_err e = sim_cycle_step(m->cyc, max_cycles, until, &ran);
        if (e) {
            if (why)
                *why = w;
            return fail(m, e);
        }
        if (ran && (sim_cycle_happened(m->cyc) & until))
            w = ALB_STOP_EVENT;
        else if (sim_cycle_done(m->cyc))
            w = ALB_STOP_DONE;
    } else if (alb_model_done(m)) {
        w = ALB_STOP_DONE;
    }
    if (why)
        *why = w;
    return ALB_OK;
}

/* ---- events and state ---- */

size_t alb_model_events(const alb_model *m, const alb_event **ev)
{
    if (m->cyc)
        return sim_cycle_events(m->cyc, ev);
    *ev = queue_front(&m->evq);
    return m->evq.n;
}

void alb_model_consume(alb_model *m, size_t n)
{
    if (m->cyc) {
        sim_cycle_consume(m->cyc, n);
        return;
    }
    queue_drop(&m->evq, n);
}

int alb_model_event(alb_model *m, alb_event *out)
{
    const alb_event *ev;
    if (!alb_model_events(m, &ev))
        return 0;
    *out = ev[0];
    alb_model_consume(m, 1);
    return 1;
}

uint64_t alb_model_cycle(const alb_model *m)
{
    if (m->cyc)
        return sim_cycle_now(m->cyc);
    return m->feed ? sim_feed_next_cycle(m->feed) : 0;
}

bool alb_model_done(const alb_model *m)
{
    return m->cyc ? sim_cycle_done(m->cyc) : m->ended;
}

uint64_t alb_model_fifo_level(const alb_model *m)
{
    return m->cyc ? sim_cycle_fifo_level(m->cyc) : 0;
}

unsigned alb_model_frames(const alb_model *m) { return m->frames; }

const alb_frame *alb_model_frame(const alb_model *m)
{
    if (m->cyc)
        return sim_cycle_frame(m->cyc, NULL, NULL);
    return m->frames ? &m->frame : NULL;
}

const alb_vp_stats *alb_model_frame_stats(const alb_model *m)
{
    const alb_vp_stats *st = NULL;
    if (m->cyc)
        return sim_cycle_frame(m->cyc, &st, NULL) ? st : NULL;
    return m->frames ? &m->stats : NULL;
}

const alb_sim_counters *alb_model_counters(const alb_model *m, unsigned k)
{
    if (m->cyc)
        return sim_cycle_counters(m->cyc, k);
    return m->feed ? sim_feed_counters(m->feed, k) : NULL;
}

const char *alb_model_error(const alb_model *m) { return m->error; }
