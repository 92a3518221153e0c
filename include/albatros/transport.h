/* transport.h — how the host reaches a board: a table of operations with
 * two back ends, USB (libusb-1.0 bulk + hidapi control) and the simulated
 * board in this process (no hardware, no kernel modules), and a fault-
 * injecting wrapper for tests (docs/usb-protocol.md). */
#ifndef ALBATROS_TRANSPORT_H
#define ALBATROS_TRANSPORT_H

#include "profile.h"

#include <signal.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/* The library exports what its public headers declare, nothing else. */
#pragma GCC visibility push(default)
#ifdef __cplusplus
extern "C" {
#endif

typedef struct alb_transport alb_transport;

typedef enum {
    ALB_TR_OK = 0,
    ALB_TR_TIMEOUT,      /* nothing within the time given */
    ALB_TR_ERROR,        /* an I/O error; the message says what */
    ALB_TR_GONE          /* the device disconnected */
} alb_tr_status;

typedef struct {
    const char *name;
    /* Queue bytes toward the board (bulk OUT).  May block while every
     * transfer is in flight (the board is NAKing): that is flow control. */
    alb_tr_status (*write)(alb_transport *t, const uint8_t *data, size_t len);
    /* Push out a partly filled transfer (with a zero-length packet if its
     * length is a multiple of the endpoint's packet size). */
    alb_tr_status (*flush)(alb_transport *t);
    /* Bytes from the board (bulk IN) within timeout_ms: ALB_TR_OK with *got > 0,
     * or ALB_TR_TIMEOUT with *got == 0. */
    alb_tr_status (*read)(alb_transport *t, uint8_t *buf, size_t cap, size_t *got, unsigned timeout_ms);
    /* HID feature reports: buf[0] is the report ID, len includes it. */
    alb_tr_status (*hid_get)(alb_transport *t, uint8_t *buf, size_t len);
    alb_tr_status (*hid_set)(alb_transport *t, const uint8_t *buf, size_t len);
    void (*close)(alb_transport *t);
} alb_transport_ops;

struct alb_transport {
    const alb_transport_ops *ops;
    void *impl;
    char error[512];          /* the last error, with what we were doing */
    size_t max_payload;       /* largest payload the transport carries; the
                                 board's own limit is in its INFO report,
                                 which the streamer reads (stream.c) */
};

/* USB: the first device with vid:pid (or the one with this serial); waits
 * up to wait_ms for it to appear (hot-plug), and keeps trying for
 * ALB_TR_USB_ACCESS_GRACE_MS while opening it is refused (LIBUSB_ERROR_ACCESS:
 * udev applies its ACL a moment after the device arrives).  The HID
 * interface is opened as well, waited for as long when a kernel driver holds
 * it (its hidraw node follows the USB device).  NULL with *err on failure. */
alb_transport *alb_transport_usb_open(uint16_t vid, uint16_t pid, const char *serial, unsigned wait_ms,
                                char *err, size_t errlen);
#define ALB_TR_USB_ACCESS_GRACE_MS 2000

/* How the bulk link is driven (docs/usb-protocol.md, "Throughput"); 0 in a
 * field means its default. */
typedef struct {
    unsigned out_transfers;   /* bulk OUT transfers in flight (default 16, at most 64) */
    size_t out_bytes;         /* each one's buffer (default 65536), rounded down to a whole
                                 number of the endpoint's packets, at most 16 MiB */
    unsigned io_timeout_ms;   /* the board may NAK this long before the transfers in flight
                                 are cancelled and their unsent bytes sent again, in order;
                                 three such rounds without progress fail the link (5000) */
} alb_tr_usb_tuning;
#define ALB_TR_USB_MAX_TRANSFERS 64
#define ALB_TR_USB_MAX_BYTES     (16u << 20)
/* alb_transport_usb_open with tuning (NULL: the defaults). */
alb_transport *alb_transport_usb_open_tuned(uint16_t vid, uint16_t pid, const char *serial,
                                            unsigned wait_ms, const alb_tr_usb_tuning *tuning,
                                            char *err, size_t errlen);

/* What a USB link is and what it went through. */
typedef struct {
    const char *speed;        /* "low", "full", "high", "super", "super+", "unknown" */
    unsigned speed_mbps;      /* 1 (1.5), 12, 480, 5000, 10000; 0 unknown */
    unsigned out_packet, in_packet;   /* the bulk endpoints' wMaxPacketSize */
    unsigned out_transfers, in_transfers;
    size_t out_bytes, in_bytes;
    bool hid_by_libusb;       /* HID reports as class requests (no hidraw node) */
    uint64_t zero_length_packets;   /* OUT transfers of whole packets, ended by a ZLP */
    uint64_t out_timeouts;    /* the board took nothing for io_timeout_ms: cancelled, resent */
    uint64_t halts_cleared;   /* stalls recovered, either endpoint */
    uint64_t resent_bytes;    /* sent again after a stall or a timeout, from where each
                                 transfer had stopped */
    uint64_t in_partial;      /* IN transfers ended by their timeout with data in them
                                 (a board that does not end a reply with a short packet) */
} alb_tr_usb_link;
/* 0 and *out filled for a transport alb_transport_usb_open made; -1 for
 * any other (the simulated board, a fault wrapper). */
int alb_transport_usb_link(const alb_transport *t, alb_tr_usb_link *out);
/* A flag a signal handler sets (Ctrl-C): once it is nonzero, a USB call
 * that would block (bulk OUT while every transfer is in flight and the board
 * NAKs, a read's wait) returns at once with ALB_TR_ERROR.  No effect on other
 * transports, which never block for long. */
void alb_transport_usb_set_stop(alb_transport *t, const volatile sig_atomic_t *stop);

/* The board's HID interface alone (control: INFO, RESET, MODE, counters),
 * through hidraw, so it works while another process streams on the bulk
 * interface.  A system without a hidraw node for the board (no usbhid
 * driver bound) falls back to HID class requests on endpoint 0 through
 * libusb, which claims the HID interface, never the data interface.
 * write/read fail: there is no bulk link.  NULL with *err on failure. */
alb_transport *alb_transport_hid_open(uint16_t vid, uint16_t pid, const char *serial, unsigned wait_ms,
                                char *err, size_t errlen);

typedef struct {
    unsigned bus, address;
    uint16_t vid, pid;
    char serial[64];          /* "?" if it could not be read */
    bool no_access;           /* LIBUSB_ERROR_ACCESS opening it: see firmware/udev/ */
} alb_tr_usb_device;

/* Matching USB devices into out[0 .. max); returns how many there are
 * (may exceed max), or -1 with *err. */
int alb_transport_usb_list(uint16_t vid, uint16_t pid, alb_tr_usb_device *out, int max, char *err,
                       size_t errlen);

/* A transport of the caller's own (a simulated board, a network link):
 * allocate an alb_transport, set ops (and impl, max_payload), and hand it to
 * alb_stream_run; ops->close frees it.  firmware/sim/transport.c is one. */

/* Faults on the link, for tests: a wrapper around any transport.  Every n
 * counts from 1; "packet" is a whole write call, so the n-th packet sent has
 * sequence number n - 1 (the first is the RESET).  A kind that can strike
 * more than once takes up to ALB_TR_FAULTS_EACH n, in any order, 0 marking an
 * unused entry; the board falls silent and the device vanishes only once. */
#define ALB_TR_FAULTS_EACH 8
typedef struct {
    uint64_t corrupt_byte[ALB_TR_FAULTS_EACH];     /* flip a bit in the n-th byte sent */
    uint64_t drop_packet[ALB_TR_FAULTS_EACH];      /* drop the n-th packet sent */
    uint64_t truncate_packet[ALB_TR_FAULTS_EACH];  /* send only the first half of the n-th packet */
    uint64_t duplicate_packet[ALB_TR_FAULTS_EACH]; /* send the n-th packet twice */
    uint64_t swap_packet[ALB_TR_FAULTS_EACH];      /* send the n-th and (n+1)-th packets in reverse
                                                  order (not if the n-th is the packet sent
                                                  after one held back for a swap) */
    uint64_t corrupt_reply[ALB_TR_FAULTS_EACH];    /* flip a bit in the n-th byte read */
    uint64_t silence_after;   /* the board stops answering after n bytes read (0: never) */
    uint64_t disconnect_after;/* the device vanishes after n bytes written (0: never) */
} alb_tr_faults;
alb_transport *alb_transport_faulty(alb_transport *inner, const alb_tr_faults *f);

#ifdef __cplusplus
}
#endif
#pragma GCC visibility pop

#endif
