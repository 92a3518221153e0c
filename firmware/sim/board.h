/* board.h — the simulated board: the firmware core (firmware/core.c) with
 * this project's VP behind it, in the host process, so the bridge can be
 * exercised end to end with no hardware.  It answers with the frame CRCs
 * and cycle counts a correct FPGA would (docs/usb-protocol.md). */
#ifndef ALBATROS_SIM_BOARD_H
#define ALBATROS_SIM_BOARD_H

#include "albatros/profile.h"

#include "albatros/transport.h"

#include <stddef.h>
#include <stdint.h>

typedef struct sim_board sim_board;

sim_board *sim_board_create(const alb_profile *p, char *err, size_t errlen);
/* The RTL board: the verilated reference RTL as the VP (rtl_vp.h, loaded by
 * rtl_load.c: path NULL for the one `make rtl-board` built for p's profile,
 * or an object or its directory, whose parameters differing from p's are
 * then described in warn).  Its INFO name is "albatros-rtl". */
sim_board *sim_board_create_rtl(const alb_profile *p, const char *path, char *warn,
                                size_t warnlen, char *err, size_t errlen);
/* What RTL boards clocked, for a report: a board given one adds to it, when
 * destroyed, the cycles its RTLs clocked (every restart included), the time
 * that took, and its object's file. */
typedef struct {
    uint64_t cycles;
    double seconds;
    char file[4200];
} sim_rtl_tally;
void sim_board_rtl_tally(sim_board *b, sim_rtl_tally *t);
void sim_board_destroy(sim_board *b);
/* The largest payload the board accepts (and announces in INFO), at most
 * PROTO_MAX_PAYLOAD: a board like the FX2, which takes 492 bytes.  Longer
 * packets are then garbage to it, as to the real firmware (core.c). */
void sim_board_set_max_payload(sim_board *b, uint16_t max_payload);
/* Bytes from the host's bulk OUT transfers. */
void sim_board_rx(sim_board *b, const uint8_t *data, size_t len);
/* Bytes the board has for the host's bulk IN; returns how many were copied. */
size_t sim_board_tx(sim_board *b, uint8_t *buf, size_t cap);
/* HID feature reports (buf[0] = report ID, 64 bytes). */
int sim_board_hid_get(sim_board *b, uint8_t *buf, size_t len);
int sim_board_hid_set(sim_board *b, const uint8_t *buf, size_t len);

/* Frames mode: the display (RGB888, width x height of the profile, row 0 at
 * the top), the frame number of the last tile and how many tiles came. */
const uint8_t *sim_board_display(const sim_board *b, uint32_t *frame, uint64_t *tiles);

/* A deliberately faulty VP: flip bit `bit` of channel `ch` of pixel (x, y)
 * in frame `frame`'s frame store before its CRC. */
void sim_board_flip(sim_board *b, uint32_t frame, unsigned x, unsigned y, unsigned ch,
                    unsigned bit);

/* The transport to a simulated board in this process (transport.c): bytes
 * written are its bulk OUT, its answers are read back as bulk IN.  p: the
 * VP it runs (the profile with every --set and --size the emulator runs
 * with); max_payload: the largest payload it accepts and announces in INFO
 * (0: PROTO_MAX_PAYLOAD; the FX2 firmware takes 492, one USB packet less
 * header and CRC). */
alb_transport *sim_board_transport(const alb_profile *p, size_t max_payload, char *err,
                                   size_t errlen);
/* The same with the RTL board (sim_board_create_rtl's path and warn). */
alb_transport *sim_board_transport_rtl(const alb_profile *p, size_t max_payload, const char *path,
                                       char *warn, size_t warnlen, char *err, size_t errlen);
/* The simulated board behind such a transport (fault injection); NULL for
 * any other transport. */
sim_board *sim_board_of(alb_transport *t);

#endif
