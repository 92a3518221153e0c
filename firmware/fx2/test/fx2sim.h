/* fx2sim.h — the FX2LP around the firmware image in s51: s51 simulates a
 * plain 8051 with RAM where the FX2 has its USB registers, so this plays the
 * chip's USB side and FPGA bus by breakpoints on the firmware's own register
 * writes (docs/usb-protocol.md, "The firmware on an 8051 simulator"):
 *
 *   host bulk OUT     the USB packet into EP2FIFOBUF, EP2BCH:L, EP2EMPTY
 *                     cleared; OUTPKTEND (the 8051 hands the buffer back)
 *                     sets EP2EMPTY again
 *   host bulk IN      a write of EP6BCL commits EP6FIFOBUF[0, EP6BCH:L)
 *   FPGA words        a write of EP4BCL commits EP4FIFOBUF[0, EP4BCH:L); the
 *                     FPGA drains at once (EP4EMPTY stays set)
 *   FPGA records      into EP8FIFOBUF, EP8BCH:L, EP8EMPTY cleared; INPKTEND
 *                     sets it again
 *   VP restart        a write of PA0 (IOA bit 0) high: restart, full = PA1
 *   control           SETUPDAT and SUDAV in USBIRQ; a write of EP0BCL is an
 *                     IN data stage of EP0BUF[0, n) — or, for a control
 *                     write, the arming of EP0 for its OUT data, answered by
 *                     the data in EP0BUF and its length in EP0BCL; STALL and
 *                     HSNAK read from EP0CS at the end of the request
 *   HID input         a write of EP1INBC commits EP1INBUF
 *   autopointers      s51 has none: at each call of the firmware's xcopy()
 *                     the copy it is about to make with them is made here,
 *                     and its loop then runs over plain RAM, so its cycles
 *                     are the real loop's.  The EP4 and EP6 buffers, which
 *                     the firmware fills only this way and never reads, are
 *                     kept here rather than in s51 (every byte through
 *                     s51's console costs a few system calls); that nothing
 *                     else writes them is checked (fx2_check_buffers)
 *
 * The firmware's main loop calls usb_poll() once a turn; every input is
 * given while it is stopped there and runs until it is back, one turn.
 * FX2SIM_TRACE=1 in the environment prints every stop on stderr. */
#ifndef ALBATROS_FX2SIM_H
#define ALBATROS_FX2SIM_H

#include "listing.h"
#include "s51.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

typedef struct {
    uint8_t data[512];
    uint16_t len;
} fx2_packet;

#define FX2_QUEUE 256        /* packets kept per kind between fx2_clear calls */

typedef struct {
    fx2_packet pkt[FX2_QUEUE];
    size_t n;
} fx2_queue;

typedef struct {
    s51_t s;
    const listing_t *lst;
    unsigned a_usb_poll, a_xcopy;
    /* what the firmware did since the last fx2_clear */
    fx2_queue in;             /* EP6: bulk IN packets to the host */
    fx2_queue ep0;            /* EP0 IN data stages */
    fx2_queue ep1;            /* EP1 IN: HID input reports */
    uint8_t *fpga;            /* bytes committed to the FPGA through EP4 */
    size_t nfpga, capfpga;
    uint8_t restart[FX2_QUEUE];   /* each VP restart pulse: its PA1 (full) */
    size_t nrestart;
    bool stalled, acked;      /* the last control request: STALL, HSNAK set */
    bool ep2_taken;           /* the last bulk OUT packet was handed back */
    bool ep8_taken;
    /* the chip's side */
    uint8_t ep2[512];         /* the USB packet in EP2FIFOBUF */
    uint16_t ep2_len;
    uint8_t ep4[512], ep6[512];   /* EP4FIFOBUF and EP6FIFOBUF, filled by xcopy */
    uint8_t stat;             /* EP2468STAT as the USB and FPGA sides set it */
    const uint8_t *ctl_out;   /* a control write's data, until EP0 is armed */
    uint16_t ctl_out_len;
    bool ctl_in;              /* the request in progress is device-to-host */
    /* clocks */
    uint64_t clocks;          /* simulated in all runs so far */
    uint64_t turn_clocks;     /* in the last turn of the main loop */
    unsigned long xcopies, xcopy_bytes;
    char error[600];
} fx2_t;

/* Start s51 (-t cpu) on the image, the chip's registers at their reset
 * values, and run the firmware to its main loop.  preload: s51_open's.
 * 0, or -1 with f->error. */
int fx2_open(fx2_t *f, const char *cpu, const char *ihx, const listing_t *l,
             const char *preload);
void fx2_close(fx2_t *f);
/* Forget the outputs collected so far. */
void fx2_clear(fx2_t *f);

/* One USB packet (0..512 bytes) from the host on EP2; one turn. */
int fx2_bulk_out(fx2_t *f, const uint8_t *data, uint16_t len);
/* A control request: SETUP, and for a control write its OUT data. */
int fx2_control(fx2_t *f, const uint8_t setup[8], const uint8_t *out, uint16_t out_len);
/* A record from the FPGA on EP8 (0..512 bytes); one turn. */
int fx2_record(fx2_t *f, const uint8_t *data, uint16_t len);
/* The USB frame number (SOF counter) becomes `frame`; one turn. */
int fx2_frame(fx2_t *f, uint16_t frame);
/* One turn with nothing new. */
int fx2_turn(fx2_t *f);
/* A USB bus reset (URES in USBIRQ); one turn. */
int fx2_bus_reset(fx2_t *f);
/* n bytes of the chip's external RAM (its registers: EP2CS, TOGCTL, ...). */
int fx2_peek(fx2_t *f, unsigned addr, uint8_t *out, unsigned n);

/* That the firmware wrote the EP4 and EP6 buffers only through xcopy (they
 * still hold the pattern fx2_open put in s51's copy of them). */
int fx2_check_buffers(fx2_t *f);

/* Patch the image in the simulator's code memory (a planted bug). */
int fx2_patch_rom(fx2_t *f, unsigned addr, uint8_t value);

#endif
