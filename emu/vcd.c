/* vcd.c — the VCD writer (IEEE 1364 §18): a $timescale of 1 ps with times at
 * the modelled clock's edges, one $scope module per unit (or per unit kept:
 * alb_vcd_keep_scope drops the others' declarations and values), identifiers of
 * printable characters, $dumpvars with initial values, no $date — two runs
 * give byte-identical files.  Its buffer is written with write(2), which a
 * signal handler may call, so SIGINT, SIGTERM, SIGABRT and SIGSEGV still
 * leave a complete trace. */
#include "albatros/vcd.h"
#include "albatros/file.h"

#include <errno.h>
#include <stdbool.h>
#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define BUF 65536
#define MAX_KEEP 16

struct alb_vcd {
    alb_out out;              /* a temporary file renamed into place at the end */
    int fd;
    int failed;
    size_t len;
    char buf[BUF];
    uint64_t value[ALB_VCD_MAX_VARS];
    unsigned width[ALB_VCD_MAX_VARS];
    unsigned nvars;
    uint64_t period;          /* ps */
    uint64_t now, written;    /* current time; last "#t" written (+1, 0 = none) */
    uint64_t last_cycle;
    uint64_t from, to;        /* the cycles traced (alb_vcd_window) */
    bool in_window;           /* the current time is one of them */
    bool started, dumped;     /* the window's first time came; $dumpvars written */
    uint64_t dump_time;       /* of $dumpvars: the window's first */
    char keep[MAX_KEEP][32];  /* scopes kept below the top one; none: all */
    unsigned nkeep;
    unsigned depth;           /* of the scope being declared */
    unsigned dropped;         /* depth of the dropped scope being declared, 0 none */
};

/* The trace a fatal signal must complete: one per process. */
static alb_vcd *active;

static void flush(alb_vcd *v)
{
    size_t off = 0;
    while (off < v->len) {
        ssize_t k = write(v->fd, v->buf + off, v->len - off);
        if (k < 0) {
            if (errno == EINTR)
                continue;
            if (!v->failed)
                v->failed = errno ? errno : EIO;
            break;
        }
        off += (size_t)k;
    }
    v->len = 0;
}

static void put(alb_vcd *v, const char *s, size_t n)
{
    if (v->len + n > BUF)
        flush(v);
    memcpy(v->buf + v->len, s, n);
    v->len += n;
}

static void puts_(alb_vcd *v, const char *s) { put(v, s, strlen(s)); }

/* "#t\n" without stdio: a signal handler writes it too. */
static int time_line(uint64_t x, char t[32])
{
    char rev[24];
    int k = 0, n = 0;
    do
        rev[k++] = (char)('0' + x % 10);
    while ((x /= 10) && k < 23);
    t[n++] = '#';
    while (k)
        t[n++] = rev[--k];
    t[n++] = '\n';
    return n;
}

static void value_line(alb_vcd *v, unsigned id, uint64_t value);

/* The window's first time is complete: every variable's value then, as
 * $dumpvars — the values the run had reached, not reset zeros — so the
 * trace starts at the window with all its signals known. */
static void dump_values(alb_vcd *v)
{
    char t[32];
    put(v, t, (size_t)time_line(v->dump_time, t));
    puts_(v, "$dumpvars\n");
    for (unsigned i = 0; i < v->nvars; i++)
        if (v->width[i])
            value_line(v, i, v->value[i]);
    puts_(v, "$end\n");
    v->written = v->dump_time + 1;
    v->dumped = true;
}

/* Async-signal-safe: a final timestamp, the buffer, then the default action. */
static void on_fatal(int sig)
{
    if (active) {
        char t[32];
        if (!active->dumped)   /* a trace with its values, however short */
            dump_values(active);
        int n = time_line(active->now + active->period, t);
        if (active->len + (size_t)n <= BUF) {
            memcpy(active->buf + active->len, t, (size_t)n);
            active->len += (size_t)n;
        }
        flush(active);
        /* the trace is complete up to now: put it under its name */
        alb_out_commit_in_signal(&active->out);
        active = NULL;
    }
    signal(sig, SIG_DFL);
    raise(sig);
}

alb_vcd *alb_vcd_open(const char *path, alb_diag *d)
{
    alb_vcd *v = calloc(1, sizeof *v);
    if (!v) {
        alb_diag_at(d, ALB_ERR_NOMEM, path, 0, 0, "out of memory");
        return NULL;
    }
    if (alb_out_open(&v->out, path, 0, d)) {
        free(v);
        return NULL;
    }
    v->fd = v->out.fd;
    puts_(v, "$version albatros cycle model $end\n$timescale 1ps $end\n");
    v->to = UINT64_MAX;   /* every cycle unless alb_vcd_window says otherwise */
    active = v;
    signal(SIGABRT, on_fatal);
    signal(SIGSEGV, on_fatal);
    return v;
}

int alb_vcd_keep_scope(alb_vcd *v, const char *module)
{
    if (v->nkeep == MAX_KEEP || strlen(module) >= sizeof v->keep[0])
        return -1;
    strcpy(v->keep[v->nkeep++], module);
    return 0;
}

static int kept(const alb_vcd *v, const char *module)
{
    for (unsigned i = 0; i < v->nkeep; i++)
        if (!strcmp(v->keep[i], module))
            return 1;
    return !v->nkeep;
}

void alb_vcd_scope(alb_vcd *v, const char *module)
{
    char line[128];
    v->depth++;
    if (!v->dropped && v->depth == 2 && !kept(v, module))
        v->dropped = v->depth;
    if (v->dropped)
        return;
    snprintf(line, sizeof line, "$scope module %s $end\n", module);
    puts_(v, line);
}

void alb_vcd_upscope(alb_vcd *v)
{
    if (v->dropped) {
        if (v->depth-- == v->dropped)
            v->dropped = 0;
        return;
    }
    v->depth -= v->depth > 0;
    puts_(v, "$upscope $end\n");
}

/* Identifier of variable id: printable characters '!' .. '~'. */
static int ident(unsigned id, char *out)
{
    int n = 0;
    do {
        out[n++] = (char)('!' + id % 94);
        id /= 94;
    } while (id);
    out[n] = 0;
    return n;
}

void alb_vcd_var(alb_vcd *v, unsigned id, const char *name, unsigned width)
{
    char line[160], code[8];
    if (id >= ALB_VCD_MAX_VARS || v->dropped)
        return;
    ident(id, code);
    snprintf(line, sizeof line, "$var wire %u %s %s $end\n", width, code, name);
    puts_(v, line);
    v->width[id] = width;
    if (id >= v->nvars)
        v->nvars = id + 1;
}

int alb_vcd_declared(const alb_vcd *v, unsigned id)
{
    return id < v->nvars && v->width[id];
}

static void value_line(alb_vcd *v, unsigned id, uint64_t value)
{
    char line[96], code[8];
    int n = 0;
    if (v->width[id] == 1) {
        line[n++] = value ? '1' : '0';
    } else {
        line[n++] = 'b';
        int top = 63;
        while (top > 0 && !(value >> top & 1))
            top--;
        for (int b = top; b >= 0; b--)
            line[n++] = (char)('0' + (value >> b & 1));
        line[n++] = ' ';
    }
    int k = ident(id, code);
    memcpy(line + n, code, (size_t)k);
    n += k;
    line[n++] = '\n';
    put(v, line, (size_t)n);
}

void alb_vcd_window(alb_vcd *v, uint64_t from, uint64_t to)
{
    v->from = from;
    v->to = to;
}

void alb_vcd_begin(alb_vcd *v, uint64_t period_ps)
{
    v->period = period_ps ? period_ps : 1;
    puts_(v, "$enddefinitions $end\n");
    v->written = 0;   /* none: $dumpvars comes at the window's first time */
}

void alb_vcd_time(alb_vcd *v, uint64_t cycle, int half)
{
    uint64_t now = cycle * v->period + (half ? v->period / 2 : 0);
    if (v->started && !v->dumped && now != v->now)
        dump_values(v);
    v->now = now;
    v->last_cycle = cycle;
    v->in_window = cycle >= v->from && cycle <= v->to;
    if (v->in_window && !v->started) {
        v->started = true;
        v->dump_time = now;
    }
}

void alb_vcd_set(alb_vcd *v, unsigned id, uint64_t value)
{
    /* a variable not declared or in a dropped scope has width 0 */
    if (id >= v->nvars || v->value[id] == value || !v->width[id])
        return;
    /* before the window, and at its first time: the value only, for
     * $dumpvars; after it, nothing */
    if (!v->dumped) {
        v->value[id] = value;
        return;
    }
    if (!v->in_window)
        return;
    if (v->written != v->now + 1) {
        char t[32];
        int n = snprintf(t, sizeof t, "#%llu\n", (unsigned long long)v->now);
        put(v, t, (size_t)n);
        v->written = v->now + 1;
    }
    v->value[id] = value;
    value_line(v, id, value);
}

void alb_vcd_end(alb_vcd *v, uint64_t cycle)
{
    char t[32];
    /* a window the run never reached: its values at the end, so the file
     * still has them */
    if (!v->started)
        v->dump_time = v->now;
    if (!v->dumped)
        dump_values(v);
    /* the file ends with the window: the end of its last cycle */
    if (v->to < UINT64_MAX && cycle > v->to + 1)
        cycle = v->to + 1;
    uint64_t end = cycle * v->period;
    if (v->written != end + 1 && end + 1 > v->written) {
        put(v, t, (size_t)time_line(end, t));
        v->written = end + 1;
    }
}

void alb_vcd_abort(alb_vcd *v)
{
    if (!v)
        return;
    if (active == v)
        active = NULL;
    alb_out_abort(&v->out);
    free(v);
}

int alb_vcd_close(alb_vcd *v)
{
    if (!v)
        return 0;
    if (active == v)
        active = NULL;
    flush(v);
    alb_diag d;
    alb_diag_init(&d, NULL);
    int bad = v->failed;
    if (bad)
        alb_out_abort(&v->out);   /* the old trace, if any, stays */
    else if (alb_out_commit(&v->out, &d) != ALB_OK)
        bad = errno ? errno : EIO;
    free(v);
    return bad;
}
