/* speed.h — how fast the FX2 image parses what the bridge sends: the
 * bridge's own streamer (emu/bridge/stream.c) runs a word stream against
 * the simulated board with a transport that records every transfer; the
 * transfers then go, as USB packets, through the image in s51, with the
 * FPGA's RESULT records and the USB frame counter at the stream's frame
 * rate, and s51's counts give the cycles (docs/usb-protocol.md, "The
 * firmware on an 8051 simulator"). */
#ifndef ALBATROS_SPEED_H
#define ALBATROS_SPEED_H

#include "listing.h"

#include <stdbool.h>

typedef struct {
    unsigned fps;      /* the stream's frame rate (USB frames between records) */
    bool profile;      /* where the cycles go, by function */
} speed_opts;

/* 0 if the figures were measured (and printed), else 1 with a message. */
int speed_run(const char *ihx, const listing_t *l, const char *stream_path, const char *preload,
              const speed_opts *o);

#endif
