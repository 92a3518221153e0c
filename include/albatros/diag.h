/* diag.h — error codes and located diagnostics.  Library code never prints
 * or exits: it returns an alb_err and fills a alb_diag saying where (file, line,
 * column, or byte offset) and what was expected.  Only main() prints. */
#ifndef ALBATROS_DIAG_H
#define ALBATROS_DIAG_H

#include <stdio.h>

/* The library exports what its public headers declare, nothing else. */
#pragma GCC visibility push(default)
#ifdef __cplusplus
extern "C" {
#endif

typedef enum {
    ALB_OK = 0,
    ALB_ERR_IO,        /* a file could not be read or written */
    ALB_ERR_PARSE,     /* text input is malformed */
    ALB_ERR_GEOMETRY,  /* degenerate geometry (collinear, non-planar, ...) */
    ALB_ERR_STREAM,    /* a word stream is malformed */
    ALB_ERR_LIMIT,     /* a documented limit was exceeded */
    ALB_ERR_CONFIG,    /* a profile or option is invalid */
    ALB_ERR_NOMEM,
    ALB_ERR_MISMATCH,  /* a comparison found a difference */
    ALB_ERR_INTERRUPTED /* stopped by SIGINT or SIGTERM */
} alb_err;

const char *alb_strerror(alb_err e);

/* Free what the library allocated for the caller (streams of
 * alb_ws_read_file and alb_gp_compile_file): for bindings whose allocator
 * is not the library's. */
void alb_free(void *p);

typedef struct {
    char file[256];
    unsigned line, col;    /* 1-based; 0 = not applicable */
    long long offset;      /* byte offset, -1 = not applicable */
    char msg[512];
    FILE *warn;            /* where warnings go; NULL = count them only */
    unsigned warnings;
} alb_diag;

void alb_diag_init(alb_diag *d, FILE *warn);
/* Record an error located at file:line:col (line/col may be 0). */
alb_err alb_diag_at(alb_diag *d, alb_err e, const char *file, unsigned line,
                unsigned col, const char *fmt, ...)
    __attribute__((format(printf, 6, 7)));
/* Record an error located at a byte offset of file. */
alb_err alb_diag_off(alb_diag *d, alb_err e, const char *file, long long offset,
                 const char *fmt, ...) __attribute__((format(printf, 5, 6)));
/* A warning: printed to d->warn with its location, counted. */
void alb_diag_warn(alb_diag *d, const char *file, unsigned line, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));
/* The same line as alb_diag_print, without the newline, into buf
 * (snprintf's return). */
int alb_diag_format(const alb_diag *d, char *buf, size_t len);
/* "file:line:col: error: msg" (or "file: offset N: ...") on f. */
void alb_diag_print(const alb_diag *d, FILE *f);

#ifdef __cplusplus
}
#endif
#pragma GCC visibility pop

#endif
