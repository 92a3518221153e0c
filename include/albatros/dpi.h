/* dpi.h — the model for SystemVerilog testbenches through DPI-C
 * (albatros_pkg.sv imports these): opaque handles (chandle), strings and
 * ints only, so no svdpi.h is needed on either side.  docs/cosim.md,
 * "SystemVerilog". */
#ifndef ALBATROS_DPI_H
#define ALBATROS_DPI_H

/* The library exports what its public headers declare, nothing else. */
#pragma GCC visibility push(default)
#ifdef __cplusplus
extern "C" {
#endif

/* The fields of the current event (alb_dpi_field), as albatros_pkg.sv
 * numbers them. */
enum {
    ALB_DPI_CYCLE, ALB_DPI_KIND, ALB_DPI_FACE, ALB_DPI_INDEX, ALB_DPI_WORD, ALB_DPI_SLOT,
    ALB_DPI_EDGES, ALB_DPI_X, ALB_DPI_Y, ALB_DPI_WL, ALB_DPI_HL, ALB_DPI_LEVEL,
    ALB_DPI_RESULT, ALB_DPI_DEPTH, ALB_DPI_R, ALB_DPI_G, ALB_DPI_B, ALB_DPI_NUMBER,
    ALB_DPI_CYCLES, ALB_DPI_CRC, ALB_DPI_FIELDS
};

/* A cycle model of the named profile with key=value overrides separated
 * by spaces or commas; producer 0 the GP stage, 1 the testbench; events an ALB_EV_*
 * mask.  NULL on failure: alb_dpi_open_error says why. */
void *alb_dpi_open(const char *profile, const char *sets, int producer, int events);
const char *alb_dpi_open_error(void);
void alb_dpi_close(void *m);
/* One word offered: 1 taken, 0 not now (a full FIFO), -1 an error. */
int alb_dpi_push(void *m, unsigned int word);
/* Every word of a stream file (binary or memh): how many, or -1. */
int alb_dpi_push_file(void *m, const char *path);
/* Clocks: 0, or -1 on an error. */
int alb_dpi_step(void *m, int cycles);
/* Run until an event of a kind in `until`, at most max_cycles: the
 * alb_stop (0 cycles ran out, 1 event, 2 done), or -1. */
int alb_dpi_run(void *m, int until, long long max_cycles);
/* Take the next event as the current one: its kind, 0 if there is none. */
int alb_dpi_next(void *m);
/* A field of the current event (ALB_DPI_*), 0 for a field it lacks. */
long long alb_dpi_field(void *m, int field);
long long alb_dpi_cycle(void *m);
int alb_dpi_done(void *m);
/* The last error ("" if none). */
const char *alb_dpi_error(void *m);

#ifdef __cplusplus
}
#endif
#pragma GCC visibility pop

#endif
