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

/* What the emulator says a frame must be, and what the board said. */
typedef struct {
    uint32_t number;
    size_t first_word, end_word;    /* the FRAME packet .. after FRAME_END */
    uint32_t crc;                   /* of the emulator's frame store */
    uint64_t cycles;                /* the emulator's cycle count */
    const uint16_t *rgb;            /* the emulator's frame store (for READBACK) */
    unsigned width, height;
    /* filled by stream_run */
    bool have;
    uint32_t board_crc;
    uint64_t board_cycles;
    unsigned resends;
} stream_frame;

typedef struct {
    unsigned timeout_ms;            /* wait for a RESULT (default 2000) */
    unsigned retries;               /* resends of one frame (default 3) */
    size_t chunk_bytes;             /* WORDS payload (default: board's max) */
    unsigned window;                /* frames ahead of the last RESULT (16) */
    bool readback;                  /* locate the first wrong pixel of a bad frame */
    FILE *log;                      /* progress and events; NULL = quiet */
    bool progress;                  /* a progress line (terminal) */
} stream_opts;

typedef struct {
    unsigned frames, matched, crc_mismatch, cycle_mismatch;
    uint64_t bytes, packets, resumes, queries;
    uint64_t board_errors[9];       /* ERROR packets by code */
    uint64_t rx_crc_errors, rx_garbage, rx_gaps, rx_duplicates;
    double seconds;
    char first_problem[600];        /* the first disagreement or failure, readable */
} stream_report;

void stream_opts_default(stream_opts *o);

/* Split a word stream into frames (FRAME .. FRAME_END); -1 if malformed. */
int stream_frames(const uint32_t *w, size_t n, stream_frame **frames, unsigned *nframes);

/* Send w[0..n) through t; fill frames[].have/board_*; 0 if every frame came
 * back and matched, 1 if some disagreed, -1 if the link failed (the report
 * says why and where). */
int stream_run(transport_t *t, const uint32_t *w, size_t n, stream_frame *frames, unsigned nframes,
               const stream_opts *o, stream_report *r);

/* Frames mode (docs/usb-protocol.md): finished frames, RGB888, row 0 at the
 * top, sent as TILE packets to a board that displays them. */
typedef struct {
    uint32_t number;
    unsigned width, height;
    const uint8_t *rgb;
} stream_tiles_frame;

/* Switch the board to frames mode (HID MODE), RESET, then each frame's tiles
 * and a PING whose STATUS confirms it; a frame whose tiles met a CRC error or
 * a gap on the way goes again (up to o->retries).  0 if every frame was
 * shown, -1 if the link failed (r says why).  r->frames counts the frames
 * confirmed, r->resumes the resends. */
int stream_tiles(transport_t *t, const stream_tiles_frame *frames, unsigned nframes,
                 const stream_opts *o, stream_report *r);

#endif
