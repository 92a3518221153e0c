/* sim_internal.h — what the cycle and timed models share: the per-frame
 * counter bins, the per-pixel cycle map, and the functional VP calls. */
#ifndef ALBATROS_SIM_INTERNAL_H
#define ALBATROS_SIM_INTERNAL_H

#include "sim.h"
/* The one reach past vp/vp.h: the clocked models drive the VP's own units
 * (edge store, subdivision walk, fill) one step at a time, so they use the
 * unit-level interface the functional renderer is built from. */
#include "../vp/vp_internal.h"

#include <stddef.h>

/* Counters per frame: a cycle belongs to the first frame retiring at or
 * after it; cycles after the last retirement go to a tail bin. */
typedef struct {
    sim_counters *bin;        /* bin[f] for frame f; bin[nretired] is open */
    int64_t *retire;          /* retirement cycle of frames 0 .. nretired-1 */
    unsigned nretired, cap;
} sim_bins;

int bins_init(sim_bins *b);
void bins_free(sim_bins *b);
/* Add the cycles [a, b) to the counter at `offset` of the bins they fall in. */
void bins_add(sim_bins *b, size_t offset, int64_t a, int64_t e);
sim_counters *bins_at(sim_bins *b, int64_t t);
/* Close the open frame at cycle r; -1 if out of memory. */
int bins_retire(sim_bins *b, int64_t r);
#define CNT(field) offsetof(sim_counters, field)

/* Per-pixel time (docs/microarchitecture.md): charges per cell, per level,
 * spread over the samples at the end of the frame. */
typedef struct {
    uint64_t *lvl[VP_MAX_LEVELS];
    unsigned levels;
} cycle_map;

int cycle_map_init(cycle_map *m, const vp_t *vp);
void cycle_map_free(cycle_map *m);
void cycle_map_charge(cycle_map *m, const vp_t *vp, const vp_cell *k, uint64_t cycles);
/* Write the frame's per-pixel cycles into out->cycles and clear the map. */
void cycle_map_resolve(cycle_map *m, const vp_t *vp, frame_t *out);

/* Cycles of an engine step and of a fill (docs/microarchitecture.md). */
static inline uint64_t step_cycles(unsigned edges, unsigned units)
{
    return edges ? (edges + units - 1) / units : 1;
}
static inline uint64_t fill_cycles(uint32_t samples, unsigned rate)
{
    return (samples + rate - 1) / rate;
}
/* The GP's compute time before a packet, from its header word. */
uint64_t gp_header_cycles(const profile_t *p, uint32_t header);

alb_err sim_run_timed(const profile_t *p, const uint32_t *w, size_t n, const char *name,
                      sim_sink sink, void *ctx, diag_t *d);
alb_err sim_run_cycle(const profile_t *p, const uint32_t *w, size_t n, const char *name,
                      const sim_options *opt, sim_sink sink, void *ctx, diag_t *d);

#endif
