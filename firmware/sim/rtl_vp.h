/* rtl_vp.h — the VP of the RTL board: the reference RTL (rtl/alb_*.sv)
 * verilated with its frame-store memory (rtl/bench/alb_frame_mem.sv) into a
 * shared object, one per parameter set (rtl/board/build.sh), which the
 * simulated board loads instead of running the C model behind the firmware
 * core (firmware/sim/rtl_load.c, docs/usb-protocol.md "The RTL board").
 * Plain C: the board (C) and the object (C++, rtl/board/rtl_vp.cpp) share it. */
#ifndef ALBATROS_SIM_RTL_VP_H
#define ALBATROS_SIM_RTL_VP_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Raised on any change of the structures below; a board refuses an object
 * of another ABI. */
#define ALB_RTL_VP_ABI 2
/* The one symbol the object exports: a function returning its table. */
#define ALB_RTL_VP_SYMBOL "alb_rtl_vp_get_api"
/* The object's file in a build directory (rtl/board/build.sh DIR ...). */
#define ALB_RTL_VP_FILE "albatros-rtl-board.so"

typedef struct alb_rtl_vp alb_rtl_vp;

/* A frame the RTL retired and scanned out, in frame order. */
typedef struct {
    uint32_t number;        /* ev_frame: the FRAME packet's number */
    uint64_t cycles;        /* ev_frame: the frame's cycle count */
    uint32_t crc;           /* ev_crc: the output stage's frame CRC */
    bool crc_from_rtl;      /* false: the next retirement cut the scan-out
                               off (ev_scan_overrun), crc is 0: the board
                               takes the CRC of rgb instead (rtl/README.md) */
    uint32_t faces;         /* ev_load events of the frame */
    const uint16_t *rgb;    /* the display store resolved right after the
                               retirement (docs/vp.md §6), R G B a pixel, row
                               0 first; valid until the next call */
} alb_rtl_vp_frame;

/* The GP output stage's timing (docs/microarchitecture.md): the board
 * pushes the words into the RTL's FIFO at the cycles the model's GP would. */
typedef struct {
    unsigned gp_face_cycles, gp_edge_cycles, gp_frame_cycles;
} alb_rtl_vp_config;

typedef struct {
    unsigned abi;           /* ALB_RTL_VP_ABI */
    /* The profile's parameters it was built with, "WIDTH=32 HEIGHT=32 ..."
     * in the order of rtl/profile-params.sh; and the board's own. */
    const char *params;
    unsigned scan_pixels;
    const char *verilator;  /* the Verilator version that built it */
    alb_rtl_vp *(*open)(const alb_rtl_vp_config *c, char *err, size_t errlen);
    void (*close)(alb_rtl_vp *v);
    /* The stream w[0, n) from its first word (the same stream, grown since
     * the last call).  Clocks the RTL as far as these words allow: up to the
     * cycle in which the GP would push a word not given yet, or, once the
     * stream's END is pushed, until every frame is scanned out.  Returns 0,
     * or -1 on an RTL error (error()) or an RTL that stopped (err says). */
    int (*run)(alb_rtl_vp *v, const uint32_t *w, size_t n, char *err, size_t errlen);
    /* FRAME packets in the words given so far.  Where a RESUME of frame
     * `number` takes the stream up again: the first word of the last FRAME
     * packet of that number given, else (as alb_sim_feed_frame_start) of the
     * frame being received, or between frames of the next packet.  The RTL
     * reports a frame later than the C model (after its scan-out, and only
     * once the words after it came), so the host may resume a frame the
     * board has whole. */
    uint32_t (*frames_given)(const alb_rtl_vp *v);
    size_t (*frame_start)(const alb_rtl_vp *v, uint32_t number);
    /* The next finished frame into *f: 1, or 0 if none is finished. */
    int (*next_frame)(alb_rtl_vp *v, alb_rtl_vp_frame *f);
    /* The RTL's sticky error: its code (rtl/README.md) and the word's index,
     * 0 if none. */
    unsigned (*error)(alb_rtl_vp *v, uint32_t *word);
    /* A faulty frame store: when frame `number` retires, bit `bit` of
     * channel `ch` of the first covered sample at or after pixel (x, y) in
     * raster order is flipped in the memory, so the RTL's scan-out and CRC
     * see it (bit + 2 aa: the pixel's resolved value moves by 2^bit). */
    void (*flip)(alb_rtl_vp *v, uint32_t number, unsigned x, unsigned y, unsigned ch,
                 unsigned bit);
    /* Cycles clocked so far and the seconds spent clocking them. */
    void (*speed)(const alb_rtl_vp *v, uint64_t *cycles, double *seconds);
} alb_rtl_vp_api;

typedef const alb_rtl_vp_api *(*alb_rtl_vp_api_fn)(void);

#ifdef __cplusplus
}
#endif

#endif
