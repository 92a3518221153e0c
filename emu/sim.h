/* sim.h — the clocked model of GP output stage, FIFO and VP at three
 * fidelities (docs/microarchitecture.md): cycle (every unit ticked per
 * clock), timed (event times without idle clocks) and functional (pixels). */
#ifndef ALBATROS_SIM_H
#define ALBATROS_SIM_H

#include "../common/diag.h"
#include "../common/profile.h"
#include "../vp/vp.h"
#include "../vp/vp.h"

#include <stddef.h>
#include <stdint.h>

typedef enum { FIDELITY_FUNCTIONAL, FIDELITY_TIMED, FIDELITY_CYCLE } fidelity;

const char *fidelity_name(fidelity f);
int fidelity_parse(const char *s, fidelity *f);

/* Per-frame counters of docs/microarchitecture.md ("Counters"). */
typedef struct {
    uint64_t cycles;          /* the frame's cycle count */
    uint64_t retire;          /* the cycle it retired in */
    uint64_t gp_busy, gp_stall;
    uint64_t parser_busy, parser_starve, parser_blocked;
    uint64_t engine_busy, engine_stall;
    uint64_t fill_busy;
    uint64_t fifo_sum;        /* occupancy summed over the frame's cycles */
    uint64_t fifo_peak;
} sim_counters;

#define SIM_COUNTER_FIELDS(X) \
    X(cycles) X(retire) X(gp_busy) X(gp_stall) X(parser_busy) X(parser_starve) \
    X(parser_blocked) X(engine_busy) X(engine_stall) X(fill_busy) X(fifo_sum) X(fifo_peak)

struct vcd;

/* The units a VCD trace can be limited to, by their scope names
 * (docs/microarchitecture.md, "Traces"): bit i of a mask is unit i.  A
 * trace keeps the units whose scopes its writer keeps (vcd_keep_scope). */
const char *sim_trace_unit_name(unsigned i);   /* NULL past the last */
#define SIM_TRACE_ALL 0x3fu                     /* every unit */
/* A comma-separated list of unit names, or "all", into *mask; -1 on an
 * unknown or empty name, its start and length in *bad and *badlen. */
int sim_trace_units_parse(const char *list, unsigned *mask, const char **bad, size_t *badlen);

typedef struct {
    fidelity fid;
    struct vcd *vcd;          /* cycle fidelity only; NULL = no trace */
    uint64_t vcd_from, vcd_to;/* cycle window of the trace */
    unsigned threads;         /* functional fidelity: threads (0 or 1: one; vp/parallel.c) */
} sim_options;

/* sc is NULL in functional fidelity; f->cycles is filled in the others. */
typedef int (*sim_sink)(void *ctx, const frame_t *f, const vp_stats *vs, const sim_counters *sc);

alb_err sim_run(const profile_t *p, const uint32_t *w, size_t n, const char *name,
                const sim_options *opt, sim_sink sink, void *ctx, diag_t *d);

/* The timed model fed a word stream as it arrives (the simulated board):
 * sim_feed_words takes the whole packets of w[0, n) not taken yet — w is the
 * same stream, grown since the last call — and leaves a packet cut short at
 * n for the next call; on_frame gets each frame at its FRAME_END, with its
 * pixels, statistics and cycle count (its other counters may still grow with
 * later words).  Errors as sim_run's, located in the whole stream. */
typedef struct sim_feed sim_feed;
alb_err sim_feed_open(sim_feed **f, const profile_t *p, const char *name, sim_sink on_frame,
                      void *ctx, diag_t *d);
alb_err sim_feed_words(sim_feed *f, const uint32_t *w, size_t n, diag_t *d);
/* The first word of the frame being received, or, between frames, of the
 * next packet: where a RESUME takes the stream up again. */
size_t sim_feed_frame_start(const sim_feed *f);
void sim_feed_close(sim_feed *f);

/* The counters as a JSON object / a readable summary (with fps against
 * the profile's clock and the 50 Hz budget). */
void sim_counters_json(FILE *f, const sim_counters *c, const profile_t *p);
void sim_counters_text(FILE *f, const sim_counters *c, const profile_t *p);

#endif
