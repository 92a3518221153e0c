/* transport.h — how the host reaches a board: a table of operations with
 * two back ends, USB (libusb-1.0 bulk + hidapi control) and the simulated
 * board in this process (no hardware, no kernel modules), and a fault-
 * injecting wrapper for tests (docs/usb-protocol.md). */
#ifndef ALBATROS_TRANSPORT_H
#define ALBATROS_TRANSPORT_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

typedef struct transport transport_t;

typedef enum {
    TR_OK = 0,
    TR_TIMEOUT,      /* nothing within the time given */
    TR_ERROR,        /* an I/O error; the message says what */
    TR_GONE          /* the device disconnected */
} tr_status;

typedef struct {
    const char *name;
    /* Queue bytes toward the board (bulk OUT).  May block while every
     * transfer is in flight (the board is NAKing): that is flow control. */
    tr_status (*write)(transport_t *t, const uint8_t *data, size_t len);
    /* Push out a partly filled transfer (with a zero-length packet if its
     * length is a multiple of the endpoint's packet size). */
    tr_status (*flush)(transport_t *t);
    /* Bytes from the board (bulk IN) within timeout_ms: TR_OK with *got > 0,
     * or TR_TIMEOUT with *got == 0. */
    tr_status (*read)(transport_t *t, uint8_t *buf, size_t cap, size_t *got, unsigned timeout_ms);
    /* HID feature reports: buf[0] is the report ID, len includes it. */
    tr_status (*hid_get)(transport_t *t, uint8_t *buf, size_t len);
    tr_status (*hid_set)(transport_t *t, const uint8_t *buf, size_t len);
    void (*close)(transport_t *t);
} transport_ops;

struct transport {
    const transport_ops *ops;
    void *impl;
    char error[512];          /* the last error, with what we were doing */
    size_t max_payload;       /* largest payload the board takes (from INFO) */
};

/* USB: the first device with vid:pid (or the one with this serial); waits
 * up to wait_ms for it to appear (hot-plug).  NULL with *err on failure. */
transport_t *transport_usb_open(uint16_t vid, uint16_t pid, const char *serial, unsigned wait_ms,
                                char *err, size_t errlen);
/* List matching USB devices on f; returns how many. */
int transport_usb_list(uint16_t vid, uint16_t pid, void *f, char *err, size_t errlen);

/* The simulated board (firmware/sim/): the firmware core and this project's
 * VP, in process.  profile_name: the VP it runs. */
struct sim_board;
transport_t *transport_sim_open(const char *profile_name, char *err, size_t errlen);
/* The simulated board behind a sim transport, for fault injection. */
struct sim_board *transport_sim_board(transport_t *t);

/* Faults on the link, for tests: a wrapper around any transport. */
typedef struct {
    uint64_t corrupt_byte;    /* flip a bit in the n-th byte sent (1-based; 0 = none) */
    uint64_t drop_packet;     /* drop the n-th packet sent (whole write call) */
    uint64_t duplicate_packet;/* send the n-th packet twice */
    uint64_t swap_packet;     /* send the n-th and (n+1)-th packets in reverse order */
    uint64_t silence_after;   /* the board stops answering after n bytes read */
    uint64_t disconnect_after;/* the device vanishes after n bytes written */
    uint64_t corrupt_reply;   /* flip a bit in the n-th byte read */
} tr_faults;
transport_t *transport_faulty(transport_t *inner, const tr_faults *f);

#endif
