/* s51.h — drive Debian's 8051 simulator (sdcc-ucsim's s51) through its
 * command console on a pair of pipes: load an Intel-hex image, set fetch and
 * event (memory write) breakpoints, run to the next stop, read and write its
 * memories.  s51 prints no prompt when its console is not a terminal, so the
 * end of every command's output is found by a sentinel command after it
 * (`expression N` prints N in decimal, a line no other command prints).
 * Host code for the firmware tests (tests/firmware-s51.sh). */
#ifndef ALBATROS_S51_H
#define ALBATROS_S51_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <sys/types.h>

typedef struct {
    bool open;                /* s51_open started it: s51_close has work to do */
    pid_t pid;
    int to, from;             /* the console's stdin and stdout */
    char *out;                /* the last command's output, NUL-terminated */
    size_t len, cap;
    unsigned sentinel;
    unsigned timeout_ms;      /* per command */
    char error[512];          /* what failed, for the caller's message */
} s51_t;

/* Why a run stopped. */
typedef enum {
    S51_FETCH,                /* a fetch breakpoint: pc is the instruction not yet run */
    S51_WRITE,                /* an event breakpoint: the instruction before pc wrote addr */
    S51_LIMIT                 /* the instruction limit was reached (a hang) */
} s51_stop_kind;

typedef struct {
    s51_stop_kind kind;
    unsigned pc;
    char space[8];            /* S51_WRITE: "xram", "sfr", "bits", "iram" */
    unsigned addr;
    uint64_t ticks;           /* clocks the run took (s51 counts oscillator clocks) */
    /* the registers s51 prints at the stop */
    bool regs;
    unsigned sp, dptr;
    uint8_t stack[8];         /* stack[k] = iram[sp - k] */
} s51_stop;

/* Start `s51 -t cpu image`, with the library `preload` (NULL: none) in
 * its LD_PRELOAD (s51_fastpoll.c).  0, or -1 with s->error. */
int s51_open(s51_t *s, const char *cpu, const char *image, const char *preload);
void s51_close(s51_t *s);

/* One console command (printf-style); its output in s->out.  0 or -1. */
int s51_cmd(s51_t *s, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

/* n bytes of memory space `mem` ("xram", "iram", "sfr", "rom") from addr. */
int s51_read(s51_t *s, const char *mem, unsigned addr, uint8_t *out, unsigned n);
int s51_write(s51_t *s, const char *mem, unsigned addr, const uint8_t *v, unsigned n);
int s51_read8(s51_t *s, const char *mem, unsigned addr, uint8_t *v);
int s51_write8(s51_t *s, const char *mem, unsigned addr, uint8_t v);

/* Breakpoints: at an instruction, or on writes to one location. */
int s51_break_fetch(s51_t *s, unsigned addr);
int s51_break_write(s51_t *s, const char *mem, unsigned addr);

/* Run at most max_insns instructions, to the next breakpoint. */
int s51_run(s51_t *s, unsigned long max_insns, s51_stop *stop);

/* The clocks simulated since the start (s51's "time" timer). */
int s51_clocks(s51_t *s, uint64_t *clocks);

/* Per-address read counts of code memory in [from, to] (instruction bytes
 * fetched and MOVC reads), into count[0 .. to - from]. */
int s51_rom_reads(s51_t *s, unsigned from, unsigned to, uint64_t *count);

#endif
