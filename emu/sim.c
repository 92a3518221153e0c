/* sim.c — the fidelity switch, and what the cycle and timed models share:
 * counter bins per frame, the per-pixel cycle map, counter output. */
#include "sim_internal.h"
#include "../common/fix.h"

#include <stdlib.h>
#include <string.h>

const char *alb_fidelity_name(alb_fidelity f)
{
    return f == ALB_FIDELITY_CYCLE ? "cycle" : f == ALB_FIDELITY_TIMED ? "timed" : "functional";
}

int alb_fidelity_parse(const char *s, alb_fidelity *f)
{
    for (int i = ALB_FIDELITY_FUNCTIONAL; i <= ALB_FIDELITY_CYCLE; i++)
        if (strcmp(s, alb_fidelity_name((alb_fidelity)i)) == 0) {
            *f = (alb_fidelity)i;
            return 0;
        }
    return -1;
}

/* ---- queues ---- */

void *queue_push(item_queue *q)
{
    if (q->head + q->n == q->cap) {
        if (q->head) {   /* reuse what the reader took */
            memmove(q->a, queue_front(q), q->n * q->size);
            q->head = 0;
        } else {
            size_t cap = q->cap ? 2 * q->cap : 256;
            void *na = realloc(q->a, cap * q->size);
            if (!na)
                return NULL;
            q->a = na;
            q->cap = cap;
        }
    }
    void *item = (char *)q->a + (q->head + q->n++) * q->size;
    return memset(item, 0, q->size);
}

void queue_drop(item_queue *q, size_t k)
{
    if (k > q->n)
        k = q->n;
    q->head += k;
    q->n -= k;
    if (!q->n)
        q->head = 0;
}

void queue_free(item_queue *q)
{
    free(q->a);
    q->a = NULL;
    q->head = q->n = q->cap = 0;
}

/* ---- bins ---- */

int bins_init(sim_bins *b)
{
    memset(b, 0, sizeof *b);
    b->cap = 16;
    b->bin = calloc(b->cap + 1, sizeof *b->bin);
    b->retire = calloc(b->cap, sizeof *b->retire);
    return b->bin && b->retire ? 0 : -1;
}

void bins_free(sim_bins *b)
{
    free(b->bin);
    free(b->retire);
    memset(b, 0, sizeof *b);
}

/* The bin of cycle t: the first frame retiring at or after t. */
static unsigned bin_index(const sim_bins *b, int64_t t)
{
    unsigned lo = 0, hi = b->nretired;
    while (lo < hi) {
        unsigned mid = (lo + hi) / 2;
        if (b->retire[mid] >= t)
            hi = mid;
        else
            lo = mid + 1;
    }
    return lo;
}

alb_sim_counters *bins_at(sim_bins *b, int64_t t)
{
    if (!b->nretired || t > b->retire[b->nretired - 1])
        return &b->bin[b->nretired];   /* the open bin, the usual case */
    return &b->bin[bin_index(b, t)];
}

void bins_add_split(sim_bins *b, size_t offset, int64_t a, int64_t e)
{
    for (unsigned i = bin_index(b, a); a < e; i++) {
        int64_t end = i < b->nretired && b->retire[i] + 1 < e ? b->retire[i] + 1 : e;
        *(uint64_t *)((char *)&b->bin[i] + offset) += (uint64_t)(end - a);
        a = end;
    }
}

int bins_retire(sim_bins *b, int64_t r)
{
    if (b->nretired == b->cap) {
        unsigned cap = b->cap * 2;
        alb_sim_counters *nb = realloc(b->bin, (cap + 1) * sizeof *nb);
        if (!nb)
            return -1;
        b->bin = nb;
        int64_t *nr = realloc(b->retire, cap * sizeof *nr);
        if (!nr)
            return -1;
        b->retire = nr;
        memset(b->bin + b->cap + 1, 0, (cap - b->cap) * sizeof *nb);
        b->cap = cap;
    }
    alb_sim_counters *c = &b->bin[b->nretired];
    int64_t prev = b->nretired ? b->retire[b->nretired - 1] : -1;
    c->retire = (uint64_t)r;
    c->cycles = (uint64_t)(r - prev);
    b->retire[b->nretired++] = r;
    return 0;
}

/* ---- the per-pixel cycle map ---- */

/* Cells of level l are (S_W >> l) x (S_H >> l), one sample at least. */
static unsigned lvl_wl(const alb_vp *vp, unsigned l) { return vp->lw > l ? vp->lw - l : 0; }
static unsigned lvl_hl(const alb_vp *vp, unsigned l) { return vp->lh > l ? vp->lh - l : 0; }

/* Cells of at most 2^FINE_LOG2 samples are charged to their samples. */
#define FINE_LOG2 4

int cycle_map_init(cycle_map *m, const alb_vp *vp)
{
    memset(m, 0, sizeof *m);
    m->levels = vp->p + 1;
    while (m->fine_from < m->levels &&
           lvl_wl(vp, m->fine_from) + lvl_hl(vp, m->fine_from) > FINE_LOG2)
        m->fine_from++;
    m->fine = vp_plane_alloc((size_t)vp->sw * vp->sh, sizeof *m->fine, true);   /* huge pages, as the store */
    if (!m->fine)
        return -1;
    for (unsigned l = 0; l < m->fine_from; l++) {
        size_t n = (size_t)1 << ((vp->lw - lvl_wl(vp, l)) + (vp->lh - lvl_hl(vp, l)));
        m->lvl[l] = calloc(n, sizeof *m->lvl[l]);
        if (!m->lvl[l]) {
            cycle_map_free(m);
            return -1;
        }
    }
    return 0;
}

void cycle_map_free(cycle_map *m)
{
    for (unsigned l = 0; l < ALB_VP_MAX_LEVELS; l++)
        free(m->lvl[l]);
    free(m->fine);
    memset(m, 0, sizeof *m);
}

void cycle_map_charge(cycle_map *m, const alb_vp *vp, const vp_cell *k, uint64_t cycles)
{
    const unsigned s = k->wl + k->hl;
    if (s > FINE_LOG2) {
        size_t per_row = (size_t)1 << (vp->lw - k->wl);
        m->lvl[k->level][(size_t)(k->r0 >> k->hl) * per_row + (k->c0 >> k->wl)] += cycles;
        return;
    }
    /* cycles * 65536 / 2^s, exact */
    const uint32_t share = (uint32_t)(cycles << (16 - s));
    uint32_t *row = m->fine + (size_t)k->r0 * vp->sw + k->c0;
    for (uint32_t r = 0; r < 1u << k->hl; r++, row += vp->sw)
        for (uint32_t c = 0; c < 1u << k->wl; c++)
            row[c] += share;
}

void cycle_map_resolve(cycle_map *m, const alb_vp *vp, alb_frame *out)
{
    /* Each sample's share is the sum over the cells containing it of
     * cycles * 65536 / (samples of the cell), truncated per cell: the large
     * cells pushed down their levels, each adding its share to its parent's
     * total, the small ones' already in the sample plane. */
    unsigned aa = vp->prof.aa_levels;
    for (unsigned l = 0; l < m->fine_from; l++) {
        unsigned wl = lvl_wl(vp, l), hl = lvl_hl(vp, l);
        unsigned dx = l && lvl_wl(vp, l - 1) > wl, dy = l && lvl_hl(vp, l - 1) > hl;
        size_t per_row = (size_t)1 << (vp->lw - wl), rows = (size_t)1 << (vp->lh - hl);
        size_t parent_row = per_row >> dx;
        for (size_t cy = 0; cy < rows; cy++)
            for (size_t cx = 0; cx < per_row; cx++) {
                uint64_t *cell = &m->lvl[l][cy * per_row + cx];
                uint64_t inherited = l ? m->lvl[l - 1][(cy >> dy) * parent_row + (cx >> dx)] : 0;
                *cell = inherited + ((*cell << 16) >> (wl + hl));
            }
    }
    /* every sample: its large cells' total and its own; pixels sum their
     * samples (the plane is 32 bits: all mod 2^32) */
    const uint64_t *coarse = m->fine_from ? m->lvl[m->fine_from - 1] : NULL;
    const unsigned cwl = m->fine_from ? lvl_wl(vp, m->fine_from - 1) : 0;
    const unsigned chl = m->fine_from ? lvl_hl(vp, m->fine_from - 1) : 0;
    const size_t coarse_row = (size_t)1 << (vp->lw - cwl);
    memset(out->cycles, 0, (size_t)out->width * out->height * sizeof *out->cycles);
    for (size_t r = 0; r < (size_t)1 << vp->lh; r++) {
        uint32_t *fine = m->fine + (r << vp->lw), *px = out->cycles + (r >> aa) * out->width;
        const uint64_t *above = coarse ? coarse + (r >> chl) * coarse_row : NULL;
        for (size_t c = 0; c < (size_t)1 << vp->lw; c++) {
            px[c >> aa] += fine[c] + (above ? (uint32_t)above[c >> cwl] : 0);
            fine[c] = 0;
        }
    }
    for (unsigned l = 0; l < m->fine_from; l++) {
        size_t n = (size_t)1 << ((vp->lw - lvl_wl(vp, l)) + (vp->lh - lvl_hl(vp, l)));
        memset(m->lvl[l], 0, n * sizeof *m->lvl[l]);
    }
}

void sim_frame_without_planes(const alb_profile *p, alb_frame *f)
{
    memset(f, 0, sizeof *f);
    f->width = p->width;
    f->height = p->height;
    f->colour_bits = p->colour_bits;
    f->depth_bits = p->depth_bits;
    f->aa_levels = p->aa_levels;
}

uint64_t gp_header_cycles(const alb_profile *p, uint32_t header)
{
    if (header >> 24 == ALB_WS_OP_FACE)
        return p->gp_face_cycles + (uint64_t)p->gp_edge_cycles * (header >> 16 & 0xFF);
    if (header >> 24 == ALB_WS_OP_FRAME)
        return p->gp_frame_cycles;
    return 0;
}

/* ---- entry and output ---- */

typedef struct {
    alb_sim_sink sink;
    void *ctx;
} functional_ctx;

static int functional_sink(void *ctx, const alb_frame *f, const alb_vp_stats *st)
{
    functional_ctx *c = ctx;
    return c->sink ? c->sink(c->ctx, f, st, NULL) : 0;
}

alb_err alb_sim_run(const alb_profile *p, const uint32_t *w, size_t n, const char *name,
                const alb_sim_options *opt, alb_sim_sink sink, void *ctx, alb_diag *d)
{
    if (opt->fid == ALB_FIDELITY_TIMED)
        return sim_run_timed(p, w, n, name, !opt->counters_only, sink, ctx, d);
    if (opt->fid == ALB_FIDELITY_CYCLE)
        return sim_run_cycle(p, w, n, name, opt, sink, ctx, d);
    alb_vp *vp = NULL;
    alb_err e = alb_vp_create(&vp, p, d);
    functional_ctx fc = {sink, ctx};
    if (!e && opt->threads > 1 && alb_vp_set_threads(vp, opt->threads))
        e = alb_diag_at(d, ALB_ERR_NOMEM, name, 0, 0, "out of memory for %u threads", opt->threads);
    if (!e)
        e = alb_vp_run_stream(vp, w, n, name, functional_sink, &fc, d);
    alb_vp_destroy(vp);
    return e;
}

static double fps(const alb_sim_counters *c, const alb_profile *p)
{
    return c->cycles ? 1000.0 * p->clock_khz / (double)c->cycles : 0;
}

void alb_sim_counters_json(alb_json *j, const alb_sim_counters *c, const alb_profile *p)
{
    alb_json_begin_object(j);
#define J(field) alb_json_kv_uint(j, #field, c->field);
    ALB_SIM_COUNTER_FIELDS(J)
#undef J
    alb_json_kv_fixed(j, "fifo_mean", c->cycles ? (double)c->fifo_sum / (double)c->cycles : 0.0, 3);
    alb_json_kv_fixed(j, "fps", fps(c, p), 3);
    alb_json_kv_bool(j, "realtime_50hz", c->cycles * 50 <= (uint64_t)p->clock_khz * 1000);
    alb_json_end_object(j);
}

void alb_sim_counters_text(FILE *f, const alb_sim_counters *c, const alb_profile *p)
{
    double cyc = (double)(c->cycles ? c->cycles : 1);
    fprintf(f, "  %llu cycles = %.3f ms at %.3f MHz: %.1f fps, %s the 50 Hz budget\n",
            (unsigned long long)c->cycles, (double)c->cycles / p->clock_khz,
            p->clock_khz / 1000.0, fps(c, p),
            c->cycles * 50 <= (uint64_t)p->clock_khz * 1000 ? "within" : "OVER");
    fprintf(f, "  GP busy %.1f%% stall %.1f%% | parser busy %.1f%% starve %.1f%% blocked %.1f%% | "
               "engine busy %.1f%% stall %.1f%% | fill busy %.1f%% | FIFO peak %llu mean %.1f\n",
            100 * (double)c->gp_busy / cyc, 100 * (double)c->gp_stall / cyc,
            100 * (double)c->parser_busy / cyc, 100 * (double)c->parser_starve / cyc,
            100 * (double)c->parser_blocked / cyc, 100 * (double)c->engine_busy / cyc,
            100 * (double)c->engine_stall / cyc, 100 * (double)c->fill_busy / cyc,
            (unsigned long long)c->fifo_peak, (double)c->fifo_sum / cyc);
}
