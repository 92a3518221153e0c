/* stream.h — `albatros stream`'s engine: send a word stream to a board over
 * any transport, collect its per-frame RESULTs, compare them with the
 * emulator's frames and cycle counts, and recover from link errors
 * (docs/usb-protocol.md, "Errors"). */
#ifndef ALBATROS_STREAM_H
#define ALBATROS_STREAM_H

#include "transport.h"

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

/* The library exports what its public headers declare, nothing else. */
#pragma GCC visibility push(default)
#ifdef __cplusplus
extern "C" {
#endif

/* What the emulator says a frame must be, and what the board said. */
typedef struct {
    uint32_t number;
    size_t first_word, end_word;    /* the FRAME packet .. after FRAME_END */
    uint32_t crc;                   /* of the emulator's frame store */
    uint64_t cycles;                /* the emulator's cycle count */
    const uint16_t *rgb;            /* the emulator's frame store (for READBACK) */
    unsigned width, height;
    /* filled by alb_stream_run */
    bool have;
    uint32_t board_crc;
    uint64_t board_cycles;
    unsigned resends;
} alb_stream_frame;

typedef struct {
    unsigned timeout_ms;            /* wait for a RESULT (default 2000) */
    unsigned retries;               /* resends of one frame (default 3) */
    size_t chunk_bytes;             /* WORDS payload, at most the board's (0: the board's) */
    unsigned window;                /* frames ahead of the last RESULT (16) */
    bool readback;                  /* locate the first wrong pixel of a bad frame */
    FILE *log;                      /* progress and events; NULL = quiet */
    bool progress;                  /* a progress line (terminal) */
    /* set by a signal handler (Ctrl-C): stop at the next packet, report what
     * was confirmed so far; NULL: never */
    const volatile sig_atomic_t *stop;
    /* After the board disconnects (alb_stream_run only): close `old`, wait for
     * the board to come back and open it again — NULL with err if it did
     * not.  The stream then starts over on the new link (a board that went
     * away has lost its state), frames already confirmed staying confirmed.
     * NULL: a disconnect ends the stream. */
    alb_transport *(*reattach)(void *ctx, alb_transport *old, char *err, size_t errlen);
    void *reattach_ctx;
    unsigned reattach_max;          /* disconnects survived (default 3) */
    /* A board's cycle counts reported, not compared: a frame matches on its
     * CRC alone.  For a real FPGA board, whose VP takes the words as USB
     * delivers them, not at the GP's pace the emulator counts with
     * (docs/fpga.md); the simulated boards keep the comparison. */
    bool cycles_unchecked;
} alb_stream_opts;

#define ALB_STREAM_ERROR_CODES 9        /* PROTO_E_* 1..8; slot 0 counts unknown codes */

typedef struct {
    unsigned frames, matched, crc_mismatch, cycle_mismatch;
    bool cycles_unchecked;          /* o->cycles_unchecked: cycle_mismatch counted only */
    uint64_t bytes, packets, resumes, queries;
    uint64_t board_errors[ALB_STREAM_ERROR_CODES];   /* ERROR packets by code */
    uint64_t rx_crc_errors, rx_garbage, rx_gaps, rx_duplicates;   /* the host's decoder */
    size_t max_payload;             /* payload used: the board's INFO, chunk_bytes */
    bool interrupted;               /* o->stop was set: the report is partial */
    unsigned reattaches;            /* disconnects the stream survived (o->reattach) */
    alb_transport *link;              /* the link at the end: the one given, another
                                       after a disconnect, NULL if the board did
                                       not come back (the caller closes it) */
    double seconds;
    char first_problem[600];        /* the first disagreement or failure, readable */
    char first_link_error[300];     /* the first loss on the link, even if recovered:
                                       which packet, what it carried */
} alb_stream_report;

/* ERROR packets the board sent, all codes. */
uint64_t alb_stream_board_errors(const alb_stream_report *r);

void alb_stream_opts_default(alb_stream_opts *o);

/* Split a word stream into frames (FRAME .. FRAME_END); -1 if malformed. */
int alb_stream_frames(const uint32_t *w, size_t n, alb_stream_frame **frames, unsigned *nframes);

/* Send w[0..n) through t, in payloads no longer than the board's INFO
 * report allows; fill frames[].have/board_*; 0 if every frame came back and
 * matched, 1 if some disagreed, -1 if the link failed (the report says why
 * and where), -2 if o->stop was set (r->frames: confirmed so far). */
int alb_stream_run(alb_transport *t, const uint32_t *w, size_t n, alb_stream_frame *frames, unsigned nframes,
               const alb_stream_opts *o, alb_stream_report *r);

/* Frames mode (docs/usb-protocol.md): finished frames, RGB888, row 0 at the
 * top, sent as TILE packets to a board that displays them. */
typedef struct {
    uint32_t number;
    unsigned width, height;
    const uint8_t *rgb;
} alb_stream_tiles_frame;

/* Switch the board to frames mode (HID MODE), RESET, then each frame's tiles
 * and a PING whose STATUS confirms it; a frame whose tiles met a CRC error or
 * a gap on the way goes again (up to o->retries).  0 if every frame was
 * shown, -1 if the link failed (r says why), -2 if o->stop was set.
 * r->frames counts the frames confirmed, r->resumes the resends.  Tiles fit
 * the payload of the board's INFO report. */
int alb_stream_tiles(alb_transport *t, const alb_stream_tiles_frame *frames, unsigned nframes,
                 const alb_stream_opts *o, alb_stream_report *r);

#ifdef __cplusplus
}
#endif
#pragma GCC visibility pop

#endif
