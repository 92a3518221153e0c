/* model.h — the golden model as an object a testbench drives ("step and
 * compare", docs/cosim.md): create it from a profile, push words as the
 * FIFO's producer, advance it N cycles or to the next event, read its
 * events.  The same object runs the functional and timed fidelities where
 * they apply (frames, and the timed model's cycle counts). */
#ifndef ALBATROS_MODEL_H
#define ALBATROS_MODEL_H

#include "diag.h"
#include "frame.h"
#include "profile.h"
#include "sim.h"
#include "vp.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/* The library exports what its public headers declare, nothing else. */
#pragma GCC visibility push(default)
#ifdef __cplusplus
extern "C" {
#endif

typedef struct alb_model alb_model;

typedef struct {
    alb_fidelity fidelity;    /* ALB_FIDELITY_CYCLE: clock by clock (the default);
                                 TIMED: each frame's cycles as it ends;
                                 FUNCTIONAL: frames only */
    alb_producer producer;    /* cycle fidelity: the model's GP output stage
                                 (the default) or the caller pushes into the FIFO */
    uint32_t events;          /* ALB_EV_* kinds to record; the cycle fidelity
                                 has them all, the others ALB_EV_FRAME only.
                                 Kinds not recorded cost nothing */
    unsigned threads;         /* functional fidelity: threads (0 or 1: one) */
    const char *name;         /* the stream's name in messages ("<stream>") */
} alb_model_config;

/* Cycle fidelity, GP producer, frame events only, one thread. */
void alb_model_config_default(alb_model_config *c);

/* A model of the profile p (c NULL: the defaults).  d (may be NULL) says
 * why on failure. */
alb_err alb_model_create(alb_model **m, const alb_profile *p, const alb_model_config *c,
                         alb_diag *d);
/* The same from a profile's name and "key=value" overrides (NULL-terminated
 * list, or NULL), as albatros --profile NAME --set KEY=VALUE takes them. */
alb_err alb_model_open(alb_model **m, const char *profile, const char *const *overrides,
                       const alb_model_config *c, alb_diag *d);
void alb_model_destroy(alb_model *m);

/* Offer words of the stream, in order; returns how many were taken.
 * GP producer (and the timed and functional fidelities): all of them.
 * External producer: at most one — the word the FIFO takes in the next
 * cycle — and none if the FIFO will be full at that cycle's start or a
 * word is already waiting for it.  A word after END is an error. */
size_t alb_model_push(alb_model *m, const uint32_t *w, size_t n);

/* Run `cycles` clocks (fewer once the stream has ended and everything
 * retired).  The timed and functional fidelities have no clock to step:
 * they did their work in alb_model_push. */
alb_err alb_model_step(alb_model *m, uint64_t cycles);

typedef enum {
    ALB_STOP_CYCLES,          /* max_cycles ran */
    ALB_STOP_EVENT,           /* a cycle recorded an event of a kind asked for */
    ALB_STOP_DONE             /* END taken and everything retired */
} alb_stop;
/* Run until a cycle records an event of a kind in `until`, at most
 * max_cycles clocks, or the end; *why (may be NULL) says which. */
alb_err alb_model_run(alb_model *m, uint32_t until, uint64_t max_cycles, alb_stop *why);

/* The oldest recorded event not read yet: 1 with *ev filled, 0 if none. */
int alb_model_event(alb_model *m, alb_event *ev);
/* All of them at once, oldest first (valid until the model runs again),
 * and how many to drop as read. */
size_t alb_model_events(const alb_model *m, const alb_event **ev);
void alb_model_consume(alb_model *m, size_t n);

/* The next cycle's number (cycle fidelity; the timed fidelity: one past the
 * last frame's retirement; functional: 0). */
uint64_t alb_model_cycle(const alb_model *m);
/* END taken and everything retired: nothing more will happen. */
bool alb_model_done(const alb_model *m);
/* Words the FIFO holds now (cycle fidelity), or 0. */
uint64_t alb_model_fifo_level(const alb_model *m);
/* Frames retired so far. */
unsigned alb_model_frames(const alb_model *m);
/* The last frame retired — its pixels, statistics, counters (NULL before the
 * first; counters NULL in the functional fidelity) — valid until the next. */
const alb_frame *alb_model_frame(const alb_model *m);
const alb_vp_stats *alb_model_frame_stats(const alb_model *m);
/* The counters of retired frame k (from 0); NULL if not retired or not
 * timed.  In the timed fidelity they may still grow with later words. */
const alb_sim_counters *alb_model_counters(const alb_model *m, unsigned k);
/* What went wrong last ("" if nothing): file, offset and message. */
const char *alb_model_error(const alb_model *m);

#ifdef __cplusplus
}
#endif
#pragma GCC visibility pop

#endif
