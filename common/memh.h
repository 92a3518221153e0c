/* memh.h — $readmemh text (IEEE 1800-2017 21.4), the form RTL benches load
 * and dump memories in: hex values separated by white space, // and block
 * comments, underscores inside numbers, @address markers.  A reader of the
 * project's own (word streams, frame-store dumps) hands each value to a
 * callback; a file with holes (an address that is not the next value's) or
 * x/z digits is refused, naming the line and column. */
#ifndef ALBATROS_MEMH_H
#define ALBATROS_MEMH_H

#include "albatros/diag.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#define MEMH_MAX_BITS 128

/* value[0] holds bits 31..0, value[1] bits 63..32, ...; return nonzero to
 * stop (memh_scan then returns ALB_ERR_NOMEM unless d was filled). */
typedef int (*memh_fn)(void *ctx, const uint32_t *value, unsigned line, unsigned col);

/* Scan text for values of at most `bits` bits (a multiple of 32). */
alb_err memh_scan(const char *text, size_t len, const char *path, unsigned bits, memh_fn fn,
                  void *ctx, alb_diag *d);
/* Whether text looks like memh rather than binary: its first bytes are hex
 * digits, white space, comments or an address, all printable. */
bool memh_looks_like(const char *text, size_t len);

#endif
