/* sim_internal.h — what the cycle and timed models share: the per-frame
 * counter bins, the per-pixel cycle map, and the functional VP calls. */
#ifndef ALBATROS_SIM_INTERNAL_H
#define ALBATROS_SIM_INTERNAL_H

#include "albatros/sim.h"
/* The one reach past vp/vp.h: the clocked models drive the VP's own units
 * (edge store, subdivision walk, fill) one step at a time, so they use the
 * unit-level interface the functional renderer is built from. */
#include "../vp/vp_internal.h"

#include <stddef.h>

/* Counters per frame: a cycle belongs to the first frame retiring at or
 * after it; cycles after the last retirement go to a tail bin. */
typedef struct {
    alb_sim_counters *bin;        /* bin[f] for frame f; bin[nretired] is open */
    int64_t *retire;          /* retirement cycle of frames 0 .. nretired-1 */
    unsigned nretired, cap;
} sim_bins;

int bins_init(sim_bins *b);
void bins_free(sim_bins *b);
/* Add the cycles [a, b) to the counter at `offset` of the bins they fall in:
 * at once into the open bin when they all follow the last retirement (the
 * usual case), else split over the bins (bins_add_split). */
void bins_add_split(sim_bins *b, size_t offset, int64_t a, int64_t e);
static inline void bins_add(sim_bins *b, size_t offset, int64_t a, int64_t e)
{
    if (a >= e)
        return;
    if (b->nretired && a <= b->retire[b->nretired - 1]) {
        bins_add_split(b, offset, a, e);
        return;
    }
    *(uint64_t *)((char *)&b->bin[b->nretired] + offset) += (uint64_t)(e - a);
}
alb_sim_counters *bins_at(sim_bins *b, int64_t t);
/* Close the open frame at cycle r; -1 if out of memory. */
int bins_retire(sim_bins *b, int64_t r);
#define CNT(field) offsetof(alb_sim_counters, field)

/* A first-in first-out queue of fixed-size items in one array (events,
 * writes in flight): items [head, head + n) are queued. */
typedef struct {
    void *a;
    size_t head, n, cap, size;
} item_queue;
#define ITEM_QUEUE(type) ((item_queue){NULL, 0, 0, 0, sizeof(type)})
/* Room for one more at the tail, zeroed; NULL if out of memory. */
void *queue_push(item_queue *q);
/* The oldest item (n > 0), and the queue without its k oldest. */
static inline void *queue_front(const item_queue *q) { return (char *)q->a + q->head * q->size; }
void queue_drop(item_queue *q, size_t k);
void queue_free(item_queue *q);

/* Per-pixel time (docs/microarchitecture.md): each charge of a cell spread
 * over its samples.  A cell of at most 16 samples gives each exactly
 * cycles * 2^(16 - log2 samples), added to the samples at once (mod 2^32,
 * the width of the frame's plane); larger cells are charged per level and
 * pushed down at the end of the frame, truncated per cell. */
typedef struct {
    uint64_t *lvl[ALB_VP_MAX_LEVELS];   /* levels below fine_from: cycles per cell */
    uint32_t *fine;                     /* per sample: the small cells' shares */
    unsigned levels, fine_from;
} cycle_map;

int cycle_map_init(cycle_map *m, const alb_vp *vp);
void cycle_map_free(cycle_map *m);
void cycle_map_charge(cycle_map *m, const alb_vp *vp, const vp_cell *k, uint64_t cycles);
/* Write the frame's per-pixel cycles into out->cycles and clear the map. */
void cycle_map_resolve(cycle_map *m, const alb_vp *vp, alb_frame *out);

/* A frame's description without its planes (timing without frames). */
void sim_frame_without_planes(const alb_profile *p, alb_frame *f);

/* Cycles of an engine step and of a fill (docs/microarchitecture.md). */
static inline uint64_t step_cycles(unsigned edges, unsigned units)
{
    return edges ? (edges + units - 1) / units : 1;
}
static inline uint64_t fill_cycles(uint32_t samples, unsigned rate)
{
    return (samples + rate - 1) / rate;
}
/* The same durations as tables, so that no step or cell costs a division: a
 * step's cycles by the edges it evaluates, a fill's by the log2 of its
 * samples (a cell's samples are a power of two). */
typedef struct {
    uint8_t step[ALB_WS_MAX_EDGES + 1];
    uint64_t fill[2 * (ALB_VP_MAX_LEVELS - 1) + 1];
} sim_durations;
static inline void sim_durations_init(sim_durations *d, const alb_profile *p)
{
    for (unsigned e = 0; e <= ALB_WS_MAX_EDGES; e++)
        d->step[e] = (uint8_t)step_cycles(e, p->edge_units);
    for (unsigned s = 0; s < sizeof d->fill / sizeof *d->fill; s++)
        d->fill[s] = ((1ull << s) + p->fill_rate - 1) / p->fill_rate;
}
/* The GP's compute time before a packet, from its header word. */
uint64_t gp_header_cycles(const alb_profile *p, uint32_t header);

/* The cycle model as a machine a testbench drives (docs/cosim.md): words
 * in as they come, clocks as asked, events out; alb_model (model.c) is its
 * public face. */

typedef struct {
    alb_producer producer;
    uint32_t events;          /* kinds to record (SIM_EV_*) */
    alb_sim_sink sink;            /* each frame as it retires; may be NULL */
    void *ctx;
    const char *name;         /* the stream's name in messages */
    struct alb_vcd *vcd;          /* a trace, or NULL */
    uint64_t vcd_from, vcd_to;
    bool counters_only;           /* no frame wanted (alb_sim_options.counters_only):
                                     frames without planes, unless FRAME events (their
                                     CRC) are recorded */
} sim_cycle_config;

typedef struct sim_cycle sim_cycle;
/* d: where errors are described for the machine's life (NULL: its own). */
alb_err sim_cycle_open(sim_cycle **m, const alb_profile *p, const sim_cycle_config *cfg, alb_diag *d);
void sim_cycle_close(sim_cycle *m);
/* Words offered; returns how many were taken.  GP producer: all (they wait
 * for the GP stage).  External: at most one, pushed in the next cycle, and
 * none if the FIFO will be full at its start or a word is already waiting. */
size_t sim_cycle_push(sim_cycle *m, const uint32_t *w, size_t n);
/* Run up to `cycles` clocks, stopping after one in which an event of a kind
 * in `until` was recorded, or when the run is done; *ran the clocks run. */
alb_err sim_cycle_step(sim_cycle *m, uint64_t cycles, uint32_t until, uint64_t *ran);
/* END taken and everything retired: no clock will change anything. */
bool sim_cycle_done(const sim_cycle *m);
uint64_t sim_cycle_now(const sim_cycle *m);   /* the next cycle's number */
uint64_t sim_cycle_fifo_level(const sim_cycle *m);
/* The recorded events not consumed yet, oldest first; consume k of them. */
size_t sim_cycle_events(const sim_cycle *m, const alb_event **ev);
void sim_cycle_consume(sim_cycle *m, size_t k);
/* The last retired frame (NULL before the first), its statistics and counters. */
const alb_frame *sim_cycle_frame(const sim_cycle *m, const alb_vp_stats **st, const alb_sim_counters **c);
/* The counters of retired frame k (from 0), NULL if not retired. */
const alb_sim_counters *sim_cycle_counters(const sim_cycle *m, unsigned k);
const alb_diag *sim_cycle_diag(const sim_cycle *m);
/* ALB_OK, or the error that stopped the machine (described in its diag). */
alb_err sim_cycle_status(const sim_cycle *m);
/* The kinds of the events recorded in the last cycle run. */
uint32_t sim_cycle_happened(const sim_cycle *m);

/* The timed model fed as words arrive: retired frame k's counters (NULL if
 * not retired), and the cycle after the last retirement. */
const alb_sim_counters *sim_feed_counters(const alb_sim_feed *f, unsigned k);
uint64_t sim_feed_next_cycle(const alb_sim_feed *f);
/* Words taken (whole packets), and whether the last was END. */
size_t sim_feed_taken(const alb_sim_feed *f, bool *ended);

/* frames: the sink wants pixels; without, only the statistics and counters
 * are made (alb_sim_options.counters_only). */
alb_err sim_run_timed(const alb_profile *p, const uint32_t *w, size_t n, const char *name,
                      bool frames, alb_sim_sink sink, void *ctx, alb_diag *d);
alb_err sim_run_cycle(const alb_profile *p, const uint32_t *w, size_t n, const char *name,
                      const alb_sim_options *opt, alb_sim_sink sink, void *ctx, alb_diag *d);

#endif
