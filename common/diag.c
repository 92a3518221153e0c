/* diag.c — located diagnostics (see diag.h). */
#include "albatros/diag.h"

#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

const char *alb_strerror(alb_err e)
{
    switch (e) {
    case ALB_OK: return "success";
    case ALB_ERR_IO: return "input/output error";
    case ALB_ERR_PARSE: return "parse error";
    case ALB_ERR_GEOMETRY: return "degenerate geometry";
    case ALB_ERR_STREAM: return "malformed word stream";
    case ALB_ERR_LIMIT: return "limit exceeded";
    case ALB_ERR_CONFIG: return "invalid configuration";
    case ALB_ERR_NOMEM: return "out of memory";
    case ALB_ERR_MISMATCH: return "mismatch";
    case ALB_ERR_INTERRUPTED: return "interrupted";
    }
    return "unknown error";
}

void alb_diag_init(alb_diag *d, FILE *warn)
{
    memset(d, 0, sizeof *d);
    d->offset = -1;
    d->warn = warn;
}

static void set_file(alb_diag *d, const char *file)
{
    snprintf(d->file, sizeof d->file, "%s", file ? file : "");
}

alb_err alb_diag_at(alb_diag *d, alb_err e, const char *file, unsigned line,
                unsigned col, const char *fmt, ...)
{
    va_list ap;
    set_file(d, file);
    d->line = line;
    d->col = col;
    d->offset = -1;
    va_start(ap, fmt);
    vsnprintf(d->msg, sizeof d->msg, fmt, ap);
    va_end(ap);
    return e;
}

alb_err alb_diag_off(alb_diag *d, alb_err e, const char *file, long long offset,
                 const char *fmt, ...)
{
    va_list ap;
    set_file(d, file);
    d->line = d->col = 0;
    d->offset = offset;
    va_start(ap, fmt);
    vsnprintf(d->msg, sizeof d->msg, fmt, ap);
    va_end(ap);
    return e;
}

void alb_diag_warn(alb_diag *d, const char *file, unsigned line, const char *fmt, ...)
{
    va_list ap;
    d->warnings++;
    if (!d->warn)
        return;
    if (file && *file)
        fprintf(d->warn, line ? "%s:%u: " : "%s: ", file, line);
    fputs("warning: ", d->warn);
    va_start(ap, fmt);
    vfprintf(d->warn, fmt, ap);
    va_end(ap);
    fputc('\n', d->warn);
}

int alb_diag_format(const alb_diag *d, char *buf, size_t len)
{
    if (!d->file[0])
        return snprintf(buf, len, "error: %s", d->msg);
    if (d->line && d->col)
        return snprintf(buf, len, "%s:%u:%u: error: %s", d->file, d->line, d->col, d->msg);
    if (d->line)
        return snprintf(buf, len, "%s:%u: error: %s", d->file, d->line, d->msg);
    if (d->offset >= 0)
        return snprintf(buf, len, "%s: offset %lld: error: %s", d->file, d->offset, d->msg);
    return snprintf(buf, len, "%s: error: %s", d->file, d->msg);
}

void alb_diag_print(const alb_diag *d, FILE *f)
{
    if (d->file[0]) {
        fputs(d->file, f);
        if (d->line) {
            fprintf(f, ":%u", d->line);
            if (d->col)
                fprintf(f, ":%u", d->col);
        } else if (d->offset >= 0) {
            fprintf(f, ": offset %lld", d->offset);
        }
        fputs(": ", f);
    }
    fprintf(f, "error: %s\n", d->msg);
}

void alb_free(void *p) { free(p); }
