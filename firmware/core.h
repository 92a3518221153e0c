/* core.h — the portable firmware core of the board side of the bridge
 * (docs/usb-protocol.md): packet parser with resynchronisation after
 * garbage, CRC, sequence tracking, error state and RESUME, result memory,
 * counters, HID reports.  Behind a small hardware-abstraction table (fw_hal)
 * so the same code runs on the FX2LP (firmware/fx2/) and in the simulated
 * board on the host (firmware/sim/).  Plain C for sdcc: no 64-bit types, no
 * dynamic memory, no recursion. */
#ifndef ALBATROS_FW_CORE_H
#define ALBATROS_FW_CORE_H

#include "proto.h"

#include <stdint.h>

typedef struct {
    void *ctx;
    /* word-stream bytes toward the VP (a multiple of 4, whole words) */
    void (*vp_words)(void *ctx, const uint8_t *data, uint16_t len);
    /* abandon the VP's partial frame and parser state (RESUME: full = 0;
     * configuration and texture memory are kept), or its whole stream
     * (RESET: full = 1, a new stream with its own CONFIG follows) */
    void (*vp_restart)(void *ctx, uint8_t full);
    /* bytes toward the host on the bulk IN endpoint (one whole packet) */
    void (*send)(void *ctx, const uint8_t *data, uint16_t len);
    /* frames mode: a tile of RGB888 pixels for the display (may be NULL) */
    void (*tile)(void *ctx, uint32_t frame, uint16_t x, uint16_t y, uint16_t w, uint16_t h,
                 const uint8_t *rgb);
    /* READBACK: send frame `frame`'s store with fw_send_packet as PIXELS
     * packets; returns 0, or 1 if the board does not keep that frame.  May
     * be NULL (the board answers READBACK with ERROR BAD_TYPE). */
    uint8_t (*readback)(void *ctx, uint32_t frame);
} fw_hal;

#define FW_RESULTS 16   /* RESULTs kept for QUERY */

typedef struct {
    uint32_t frame, crc, cyc_lo, cyc_hi, faces;
} fw_result;

typedef struct {
    const fw_hal *hal;
    uint8_t *buf;             /* reassembly buffer: header + max payload + CRC */
    uint16_t max_payload;
    uint16_t fill;            /* bytes in buf */
    uint32_t rx_seq;          /* next sequence number expected */
    uint32_t tx_seq;
    uint8_t synced;           /* a RESET has been seen */
    uint8_t error_state;      /* WORDS dropped until RESUME */
    uint8_t mode;
    uint8_t resume_wait;      /* after RESUME: skip words until the FRAME of resume_frame */
    uint32_t resume_frame;
    uint32_t counters[9];     /* STATUS layout, in order */
    uint32_t last_error[4];   /* code, seq, expected, detail */
    fw_result results[FW_RESULTS];
    uint8_t nresults, next_result;
    /* board identity for INFO */
    uint16_t width, height, fw_version;
    uint8_t colour_bits;
    uint32_t serial;
    char name[16];
    uint8_t scratch[PROTO_HEADER + 40 + PROTO_TRAILER];   /* outgoing packets */
} fw_core;

/* buf must hold PROTO_HEADER + max_payload + PROTO_TRAILER bytes. */
void fw_init(fw_core *c, const fw_hal *hal, uint8_t *buf, uint16_t max_payload);
/* Bytes received on the bulk OUT endpoint, in any pieces. */
void fw_rx(fw_core *c, const uint8_t *data, uint16_t len);
/* The VP finished a frame: RESULT to the host, kept for QUERY. */
void fw_frame_done(fw_core *c, const fw_result *r);
/* The VP found the word stream malformed at word `word` of the frame. */
void fw_vp_error(fw_core *c, uint32_t word);
/* Send one packet of the board's numbering from two pieces of payload (for
 * a HAL's READBACK answer); the pieces go out through hal->send as they are. */
void fw_send_packet(fw_core *c, uint8_t type, const uint8_t *head, uint16_t head_len,
                    const uint8_t *body, uint16_t body_len);
/* HID: fill a GET_REPORT (report[0] = id on entry; 64 bytes); returns the
 * length, 0 for an unknown report.  SET_REPORT: returns 0 if accepted. */
uint8_t fw_hid_get(fw_core *c, uint8_t *report);
uint8_t fw_hid_set(fw_core *c, const uint8_t *report, uint8_t len);

#endif
