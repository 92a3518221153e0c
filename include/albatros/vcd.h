/* vcd.h — Value Change Dump traces of the cycle model, for GTKWave
 * (docs/microarchitecture.md, "Traces").  Written through its own buffer
 * with write(2), so a trace is completed on SIGINT and on a crash. */
#ifndef ALBATROS_VCD_H
#define ALBATROS_VCD_H

#include "diag.h"

#include <stdint.h>

/* The library exports what its public headers declare, nothing else. */
#pragma GCC visibility push(default)
#ifdef __cplusplus
extern "C" {
#endif

typedef struct alb_vcd alb_vcd;

#define ALB_VCD_MAX_VARS 64

alb_vcd *alb_vcd_open(const char *path, alb_diag *d);
/* Before the declarations: keep only the scopes so named (each call adds
 * one) among those directly inside the top scope; the others are dropped
 * with their variables, which alb_vcd_set then ignores.  No call keeps all.
 * -1 if the name is too long or there are too many. */
int alb_vcd_keep_scope(alb_vcd *v, const char *module);
/* Declarations, before alb_vcd_begin.  Identifiers need not be contiguous. */
void alb_vcd_scope(alb_vcd *v, const char *module);
void alb_vcd_upscope(alb_vcd *v);
void alb_vcd_var(alb_vcd *v, unsigned id, const char *name, unsigned width);
/* Whether variable id is in the trace (declared and not dropped). */
int alb_vcd_declared(const alb_vcd *v, unsigned id);
/* Trace only cycles from..to (before alb_vcd_begin; default: all).  Values
 * set before the window are kept, not written: the trace starts at the
 * window's first time with $dumpvars of every variable's value then, and
 * ends at the end of its last cycle (alb_vcd_end). */
void alb_vcd_window(alb_vcd *v, uint64_t from, uint64_t to);
/* End the header.  $dumpvars follows at the first traced time, with the
 * values set by then (variables never set are 0). */
void alb_vcd_begin(alb_vcd *v, uint64_t period_ps);
/* The current time: cycle, and which half of it (0 rising edge, 1 falling). */
void alb_vcd_time(alb_vcd *v, uint64_t cycle, int half);
/* Record a value; only changes are written, and none of a variable not
 * in the trace. */
void alb_vcd_set(alb_vcd *v, unsigned id, uint64_t value);
/* A final timestamp after the last cycle (or the window's, if sooner). */
void alb_vcd_end(alb_vcd *v, uint64_t cycle);
/* Flush and close: the trace goes under its name (file.h); 0, or the
 * errno of the first failed write (the old file, if any, is then kept). */
int alb_vcd_close(alb_vcd *v);
/* Give up before the run: nothing is written, an old trace stays. */
void alb_vcd_abort(alb_vcd *v);

#ifdef __cplusplus
}
#endif
#pragma GCC visibility pop

#endif
