/* sim.h — the clocked model of GP output stage, FIFO and VP at three
 * fidelities (docs/microarchitecture.md): cycle (every unit ticked per
 * clock), timed (event times without idle clocks) and functional (pixels). */
#ifndef ALBATROS_SIM_H
#define ALBATROS_SIM_H

#include "diag.h"
#include "json.h"
#include "profile.h"
#include "vp.h"

#include <stddef.h>
#include <stdint.h>

/* The library exports what its public headers declare, nothing else. */
#pragma GCC visibility push(default)
#ifdef __cplusplus
extern "C" {
#endif

typedef enum { ALB_FIDELITY_FUNCTIONAL, ALB_FIDELITY_TIMED, ALB_FIDELITY_CYCLE } alb_fidelity;

const char *alb_fidelity_name(alb_fidelity f);
int alb_fidelity_parse(const char *s, alb_fidelity *f);

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
} alb_sim_counters;

#define ALB_SIM_COUNTER_FIELDS(X) \
    X(cycles) X(retire) X(gp_busy) X(gp_stall) X(parser_busy) X(parser_starve) \
    X(parser_blocked) X(engine_busy) X(engine_stall) X(fill_busy) X(fifo_sum) X(fifo_peak)

struct alb_vcd;

/* The units a VCD trace can be limited to, by their scope names
 * (docs/microarchitecture.md, "Traces"): bit i of a mask is unit i.  A
 * trace keeps the units whose scopes its writer keeps (alb_vcd_keep_scope). */
const char *alb_sim_trace_unit_name(unsigned i);   /* NULL past the last */
#define ALB_SIM_TRACE_ALL 0x3fu                     /* every unit */
/* A comma-separated list of unit names, or "all", into *mask; -1 on an
 * unknown or empty name, its start and length in *bad and *badlen. */
int alb_sim_trace_units_parse(const char *list, unsigned *mask, const char **bad, size_t *badlen);

/* ---- events of the cycle model (docs/cosim.md) ---- */

/* Kinds, one bit each, in the order a cycle reports them. */
enum {
    ALB_EV_PUSH = 1u << 0,    /* the producer pushed a word into the FIFO */
    ALB_EV_POP = 1u << 1,     /* the parser popped a word */
    ALB_EV_LOAD = 1u << 2,    /* a FACE's last word popped: the face is in a slot */
    ALB_EV_START = 1u << 3,   /* the engine took a face */
    ALB_EV_CELL = 1u << 4,    /* a step decided a cell (its last cycle) */
    ALB_EV_END = 1u << 5,     /* the engine finished a face; its slot is free next cycle */
    ALB_EV_FILL = 1u << 6,    /* the fill unit took a cell */
    ALB_EV_WRITE = 1u << 7,   /* a sample written at the end of the cycle */
    ALB_EV_FRAME = 1u << 8,   /* a frame retired */
    ALB_EV_ALL = 0x1ffu
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
} alb_event;

/* sizeof(alb_event), for bindings that lay the struct out themselves. */
size_t alb_event_size(void);

/* The kind's name ("push", ...), NULL for anything else; a comma-separated
 * list of names, or "all", into a mask (-1 naming the bad one); one event as
 * the text line of docs/cosim.md (snprintf's return). */
const char *alb_sim_event_name(uint32_t kind);
int alb_sim_events_parse(const char *list, uint32_t *mask, const char **bad, size_t *badlen);
int alb_sim_event_format(const alb_event *e, char *buf, size_t len);

/* Events handed over in batches by alb_sim_run (cycle fidelity): nonzero stops the run. */
typedef int (*alb_events_fn)(void *ctx, const alb_event *ev, size_t n);

typedef struct {
    alb_fidelity fid;
    struct alb_vcd *vcd;          /* cycle fidelity only; NULL = no trace */
    uint64_t vcd_from, vcd_to;/* cycle window of the trace */
    unsigned threads;         /* functional fidelity: threads (0 or 1: one; vp/parallel.c) */
    uint32_t events;          /* cycle fidelity: the kinds to hand to on_events */
    alb_events_fn on_events;
    void *events_ctx;
    bool counters_only;       /* timed and cycle fidelities: no frame is wanted, only
                                 each frame's statistics and counters; the model makes
                                 the depth tests (samples_written, depth_ties) and no
                                 colour or per-pixel cycles, and the sink's frame has
                                 no planes (rgb ... cycles NULL) */
} alb_sim_options;

/* sc is NULL in functional fidelity; f->cycles is filled in the others. */
typedef int (*alb_sim_sink)(void *ctx, const alb_frame *f, const alb_vp_stats *vs, const alb_sim_counters *sc);

alb_err alb_sim_run(const alb_profile *p, const uint32_t *w, size_t n, const char *name,
                const alb_sim_options *opt, alb_sim_sink sink, void *ctx, alb_diag *d);

/* The timed model fed a word stream as it arrives (the simulated board):
 * alb_sim_feed_words takes the whole packets of w[0, n) not taken yet — w is the
 * same stream, grown since the last call — and leaves a packet cut short at
 * n for the next call; on_frame gets each frame at its FRAME_END, with its
 * pixels, statistics and cycle count (its other counters may still grow with
 * later words).  Errors as alb_sim_run's, located in the whole stream. */
typedef struct alb_sim_feed alb_sim_feed;
alb_err alb_sim_feed_open(alb_sim_feed **f, const alb_profile *p, const char *name, alb_sim_sink on_frame,
                      void *ctx, alb_diag *d);
alb_err alb_sim_feed_words(alb_sim_feed *f, const uint32_t *w, size_t n, alb_diag *d);
/* The first word of the frame being received, or, between frames, of the
 * next packet: where a RESUME takes the stream up again. */
size_t alb_sim_feed_frame_start(const alb_sim_feed *f);
void alb_sim_feed_close(alb_sim_feed *f);

/* Who feeds the FIFO in a clocked run (docs/cosim.md). */
typedef enum {
    ALB_PRODUCER_GP,          /* the model's GP output stage pushes the words given,
                                 with the profile's GP timing */
    ALB_PRODUCER_EXTERNAL     /* the caller is the FIFO's producer: a word a cycle at most */
} alb_producer;

/* The counters as a JSON object / a readable summary (with fps against
 * the profile's clock and the 50 Hz budget). */
void alb_sim_counters_json(alb_json *j, const alb_sim_counters *c, const alb_profile *p);
void alb_sim_counters_text(FILE *f, const alb_sim_counters *c, const alb_profile *p);

#ifdef __cplusplus
}
#endif
#pragma GCC visibility pop

#endif
