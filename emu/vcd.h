/* vcd.h — Value Change Dump traces of the cycle model, for GTKWave
 * (docs/microarchitecture.md, "Traces").  Written through its own buffer
 * with write(2), so a trace is completed on SIGINT and on a crash. */
#ifndef ALBATROS_VCD_H
#define ALBATROS_VCD_H

#include "../common/diag.h"

#include <stdint.h>

typedef struct vcd vcd_t;

#define VCD_MAX_VARS 64

vcd_t *vcd_open(const char *path, diag_t *d);
/* Before the declarations: keep only the scopes so named (each call adds
 * one) among those directly inside the top scope; the others are dropped
 * with their variables, which vcd_set then ignores.  No call keeps all.
 * -1 if the name is too long or there are too many. */
int vcd_keep_scope(vcd_t *v, const char *module);
/* Declarations, before vcd_begin.  Identifiers need not be contiguous. */
void vcd_scope(vcd_t *v, const char *module);
void vcd_upscope(vcd_t *v);
void vcd_var(vcd_t *v, unsigned id, const char *name, unsigned width);
/* Whether variable id is in the trace (declared and not dropped). */
int vcd_declared(const vcd_t *v, unsigned id);
/* End the header; all variables start at 0. */
void vcd_begin(vcd_t *v, uint64_t period_ps);
/* The current time: cycle, and which half of it (0 rising edge, 1 falling). */
void vcd_time(vcd_t *v, uint64_t cycle, int half);
/* Record a value; only changes are written, and none of a variable not
 * in the trace. */
void vcd_set(vcd_t *v, unsigned id, uint64_t value);
/* A final timestamp after the last cycle. */
void vcd_end(vcd_t *v, uint64_t cycle);
/* Flush and close; -1 if any write failed. */
int vcd_close(vcd_t *v);

#endif
