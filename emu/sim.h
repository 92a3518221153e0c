/* sim.h — the clocked model of GP output stage, FIFO and VP at three
 * fidelities (docs/microarchitecture.md): cycle (every unit ticked per
 * clock), timed (event times without idle clocks) and functional (pixels). */
#ifndef ALBATROS_SIM_H
#define ALBATROS_SIM_H

#include "../common/diag.h"
#include "../common/profile.h"
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

/* ---- events of the cycle model (docs/cosim.md) ---- */

/* Kinds, one bit each, in the order a cycle reports them. */
enum {
    SIM_EV_PUSH = 1u << 0,    /* the producer pushed a word into the FIFO */
    SIM_EV_POP = 1u << 1,     /* the parser popped a word */
    SIM_EV_LOAD = 1u << 2,    /* a FACE's last word popped: the face is in a slot */
    SIM_EV_START = 1u << 3,   /* the engine took a face */
    SIM_EV_CELL = 1u << 4,    /* a step decided a cell (its last cycle) */
    SIM_EV_END = 1u << 5,     /* the engine finished a face; its slot is free next cycle */
    SIM_EV_FILL = 1u << 6,    /* the fill unit took a cell */
    SIM_EV_WRITE = 1u << 7,   /* a sample written at the end of the cycle */
    SIM_EV_FRAME = 1u << 8,   /* a frame retired */
    SIM_EV_ALL = 0x1ffu
};

/* One event; the fields a kind does not use are 0 (docs/cosim.md, "Events"). */
typedef struct {
    uint64_t cycle;
    uint32_t kind;            /* one SIM_EV_* bit */
    uint32_t face;            /* face id: LOAD START END CELL FILL WRITE */
    uint64_t index;           /* PUSH POP: the word's index; FRAME: the frame's, from 0 */
    uint32_t word;            /* PUSH POP: the word */
    uint32_t slot;            /* LOAD START END: the edge-store slot */
    uint32_t edges;           /* LOAD: the face's edges; CELL: active edges evaluated */
    uint32_t x, y;            /* CELL FILL: the top-left sample; WRITE: the sample */
    uint8_t wl, hl;           /* CELL FILL: log2 width and height in samples */
    uint8_t level;            /* CELL FILL WRITE: subdivision level */
    uint8_t result;           /* CELL: 1 out, 2 split, 3 fill, 4 sample in, 5 sample out */
    uint32_t depth;           /* WRITE: depth store value */
    uint16_t rgb[3];          /* WRITE: frame store colour */
    uint32_t number;          /* FRAME: the FRAME packet's number */
    uint64_t cycles;          /* FRAME: the frame's cycle count */
    uint32_t crc;             /* FRAME: CRC-32 of the resolved frame (docs/usb-protocol.md) */
} sim_event;

/* The kind's name ("push", ...), NULL for anything else; a comma-separated
 * list of names, or "all", into a mask (-1 naming the bad one); one event as
 * the text line of docs/cosim.md (snprintf's return). */
const char *sim_event_name(uint32_t kind);
int sim_events_parse(const char *list, uint32_t *mask, const char **bad, size_t *badlen);
int sim_event_format(const sim_event *e, char *buf, size_t len);

/* Events handed over in batches by sim_run (cycle fidelity): nonzero stops the run. */
typedef int (*sim_events_fn)(void *ctx, const sim_event *ev, size_t n);

typedef struct {
    fidelity fid;
    struct vcd *vcd;          /* cycle fidelity only; NULL = no trace */
    uint64_t vcd_from, vcd_to;/* cycle window of the trace */
    unsigned threads;         /* functional fidelity: threads (0 or 1: one; vp/parallel.c) */
    uint32_t events;          /* cycle fidelity: the kinds to hand to on_events */
    sim_events_fn on_events;
    void *events_ctx;
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

/* The cycle model as a machine a testbench drives (docs/cosim.md): words
 * in as they come, clocks as asked, events out. */
typedef enum {
    SIM_PRODUCER_GP,          /* the model's GP output stage pushes the words given,
                                 with the profile's GP timing */
    SIM_PRODUCER_EXTERNAL     /* the caller is the FIFO's producer: a word a cycle at most */
} sim_producer;

typedef struct {
    sim_producer producer;
    uint32_t events;          /* kinds to record (SIM_EV_*) */
    sim_sink sink;            /* each frame as it retires; may be NULL */
    void *ctx;
    const char *name;         /* the stream's name in messages */
    struct vcd *vcd;          /* a trace, or NULL */
    uint64_t vcd_from, vcd_to;
} sim_cycle_config;

typedef struct sim_cycle sim_cycle;
/* d: where errors are described for the machine's life (NULL: its own). */
alb_err sim_cycle_open(sim_cycle **m, const profile_t *p, const sim_cycle_config *cfg, diag_t *d);
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
size_t sim_cycle_events(const sim_cycle *m, const sim_event **ev);
void sim_cycle_consume(sim_cycle *m, size_t k);
/* The last retired frame (NULL before the first), its statistics and counters. */
const frame_t *sim_cycle_frame(const sim_cycle *m, const vp_stats **st, const sim_counters **c);
/* The counters of retired frame k (from 0), NULL if not retired. */
const sim_counters *sim_cycle_counters(const sim_cycle *m, unsigned k);
const diag_t *sim_cycle_diag(const sim_cycle *m);

/* The counters as a JSON object / a readable summary (with fps against
 * the profile's clock and the 50 Hz budget). */
void sim_counters_json(FILE *f, const sim_counters *c, const profile_t *p);
void sim_counters_text(FILE *f, const sim_counters *c, const profile_t *p);

#endif
