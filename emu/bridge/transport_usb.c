/* transport_usb.c — the real board: bulk data through libusb-1.0's
 * asynchronous API with several transfers in flight each way, control
 * through hidapi (hidraw back end, so the kernel keeps the HID interface and
 * libusb claims only the data interface).  Error messages carry
 * libusb_error_name() and what we were doing; LIBUSB_ERROR_ACCESS names the
 * udev rule to install (docs/usb-protocol.md, "Permissions").  `albatros
 * board` opens the HID interface alone (alb_transport_hid_open), so it works
 * beside a running stream. */
#include "albatros/transport.h"
#include "../../firmware/proto.h"

#include <hidapi.h>
#include <libusb.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/time.h>
#include <time.h>
#include <wchar.h>

#define OUT_TRANSFERS 16      /* 16 x 64 KiB: ~0.5 s at a 2 MB/s stream */
#define OUT_SIZE      (128u * PROTO_BULK_MAXPKT)
#define IN_TRANSFERS  4
#define IN_SIZE       (32u * PROTO_BULK_MAXPKT)
#define IO_TIMEOUT_MS 5000

typedef struct usb_link usb_link;

typedef struct {
    usb_link *u;
    struct libusb_transfer *xfer;
    uint8_t *buf;
    bool busy;
    int stalls;               /* halts cleared for this transfer */
} slot;

struct usb_link {
    libusb_context *ctx;
    libusb_device_handle *h;
    hid_device *hid;
    slot out[OUT_TRANSFERS], in[IN_TRANSFERS];
    unsigned filling;         /* out slot being filled, or OUT_TRANSFERS */
    size_t fill_len;
    uint8_t *rx;              /* received, not yet read */
    size_t rx_len, rx_cap;
    bool gone, failed;
    char error[400];
    unsigned busy_out, busy_in;
    bool hid_only;            /* alb_transport_hid_open: no data interface, no transfers */
    bool hid_by_libusb;       /* no hidraw node: HID class requests on endpoint 0 */
    const volatile sig_atomic_t *stop;   /* alb_transport_usb_set_stop */
};

static void set_error(usb_link *u, const char *doing, int rc)
{
    if (u->failed)
        return;
    u->failed = true;
    snprintf(u->error, sizeof u->error, "%s: %s", doing, libusb_error_name(rc));
    if (rc == LIBUSB_ERROR_NO_DEVICE)
        u->gone = true;
}

/* ---- completions ---- */

static void LIBUSB_CALL out_done(struct libusb_transfer *x)
{
    slot *s = x->user_data;
    usb_link *u = s->u;
    switch (x->status) {
    case LIBUSB_TRANSFER_COMPLETED:
        if (x->actual_length != x->length)
            set_error(u, "bulk OUT: short write", LIBUSB_ERROR_IO);
        break;
    case LIBUSB_TRANSFER_TIMED_OUT: {
        /* a timed-out transfer may have sent part of its data: resend the
         * rest rather than losing or repeating bytes */
        int done = x->actual_length;
        memmove(s->buf, s->buf + done, (size_t)(x->length - done));
        x->length -= done;
        if (libusb_submit_transfer(x) == 0)
            return;
        set_error(u, "bulk OUT: resubmitting after a timeout", LIBUSB_ERROR_TIMEOUT);
        break;
    }
    case LIBUSB_TRANSFER_STALL:
        if (s->stalls++ == 0 && libusb_clear_halt(u->h, PROTO_EP_OUT) == 0 &&
            libusb_submit_transfer(x) == 0)
            return;
        set_error(u, "bulk OUT: endpoint stalled twice", LIBUSB_ERROR_PIPE);
        break;
    case LIBUSB_TRANSFER_NO_DEVICE:
        set_error(u, "bulk OUT", LIBUSB_ERROR_NO_DEVICE);
        break;
    case LIBUSB_TRANSFER_CANCELLED:
        break;
    default:
        set_error(u, "bulk OUT", LIBUSB_ERROR_IO);
        break;
    }
    s->busy = false;
    u->busy_out--;
}

static void LIBUSB_CALL in_done(struct libusb_transfer *x)
{
    slot *s = x->user_data;
    usb_link *u = s->u;
    /* every completion may carry data, a timed-out one included */
    if (x->actual_length > 0) {
        size_t need = u->rx_len + (size_t)x->actual_length;
        if (need > u->rx_cap) {
            size_t cap = u->rx_cap ? u->rx_cap * 2 : 65536;
            while (cap < need)
                cap *= 2;
            uint8_t *nr = realloc(u->rx, cap);
            if (!nr) {
                set_error(u, "bulk IN: out of memory", LIBUSB_ERROR_NO_MEM);
                s->busy = false;
                u->busy_in--;
                return;
            }
            u->rx = nr;
            u->rx_cap = cap;
        }
        memcpy(u->rx + u->rx_len, x->buffer, (size_t)x->actual_length);
        u->rx_len += (size_t)x->actual_length;
    }
    switch (x->status) {
    case LIBUSB_TRANSFER_COMPLETED:
    case LIBUSB_TRANSFER_TIMED_OUT:
        if (!u->failed && libusb_submit_transfer(x) == 0)
            return;
        break;
    case LIBUSB_TRANSFER_STALL:
        if (s->stalls++ == 0 && libusb_clear_halt(u->h, PROTO_EP_IN) == 0 &&
            libusb_submit_transfer(x) == 0)
            return;
        set_error(u, "bulk IN: endpoint stalled twice", LIBUSB_ERROR_PIPE);
        break;
    case LIBUSB_TRANSFER_NO_DEVICE:
        set_error(u, "bulk IN", LIBUSB_ERROR_NO_DEVICE);
        break;
    case LIBUSB_TRANSFER_CANCELLED:
        break;
    default:
        set_error(u, "bulk IN", LIBUSB_ERROR_IO);
        break;
    }
    s->busy = false;
    u->busy_in--;
}

static void events(usb_link *u, unsigned ms)
{
    struct timeval tv = {(time_t)(ms / 1000), (suseconds_t)(ms % 1000) * 1000};
    int rc = libusb_handle_events_timeout_completed(u->ctx, &tv, NULL);
    if (rc && rc != LIBUSB_ERROR_INTERRUPTED)
        set_error(u, "handling USB events", rc);
}

/* ---- operations ---- */

static alb_tr_status status_of(alb_transport *t, usb_link *u)
{
    if (!u->failed)
        return ALB_TR_OK;
    snprintf(t->error, sizeof t->error, "%s", u->error);
    return u->gone ? ALB_TR_GONE : ALB_TR_ERROR;
}

static int submit_out(usb_link *u, unsigned i)
{
    slot *s = &u->out[i];
    libusb_fill_bulk_transfer(s->xfer, u->h, PROTO_EP_OUT, s->buf, (int)u->fill_len, out_done, s,
                              IO_TIMEOUT_MS);
    /* a transfer of a whole number of packets ends with a zero-length one */
    s->xfer->flags = u->fill_len % PROTO_BULK_MAXPKT == 0 ? LIBUSB_TRANSFER_ADD_ZERO_PACKET : 0;
    s->stalls = 0;
    int rc = libusb_submit_transfer(s->xfer);
    if (rc) {
        set_error(u, "submitting a bulk OUT transfer", rc);
        return -1;
    }
    s->busy = true;
    u->busy_out++;
    u->filling = OUT_TRANSFERS;
    u->fill_len = 0;
    return 0;
}

static alb_tr_status usb_flush(alb_transport *t)
{
    usb_link *u = t->impl;
    if (u->filling < OUT_TRANSFERS && u->fill_len)
        submit_out(u, u->filling);
    return status_of(t, u);
}

static alb_tr_status usb_write(alb_transport *t, const uint8_t *data, size_t len)
{
    usb_link *u = t->impl;
    while (len && !u->failed) {
        if (u->filling == OUT_TRANSFERS) {
            /* a free transfer, waiting for one while all are in flight */
            unsigned i = 0;
            while (!u->failed) {
                for (i = 0; i < OUT_TRANSFERS && u->out[i].busy; i++)
                    ;
                if (i < OUT_TRANSFERS)
                    break;
                if (u->stop && *u->stop) {   /* Ctrl-C while the board NAKs */
                    snprintf(t->error, sizeof t->error, "writing to the board: interrupted");
                    return ALB_TR_ERROR;
                }
                events(u, 100);
            }
            if (u->failed)
                break;
            u->filling = i;
            u->fill_len = 0;
        }
        size_t k = OUT_SIZE - u->fill_len < len ? OUT_SIZE - u->fill_len : len;
        memcpy(u->out[u->filling].buf + u->fill_len, data, k);
        u->fill_len += k;
        data += k;
        len -= k;
        if (u->fill_len == OUT_SIZE)
            submit_out(u, u->filling);
    }
    return status_of(t, u);
}

static alb_tr_status usb_read(alb_transport *t, uint8_t *buf, size_t cap, size_t *got, unsigned timeout_ms)
{
    usb_link *u = t->impl;
    struct timespec start;
    clock_gettime(CLOCK_MONOTONIC, &start);
    *got = 0;
    for (;;) {
        events(u, 0);
        if (u->rx_len || u->failed)
            break;
        struct timespec now;
        clock_gettime(CLOCK_MONOTONIC, &now);
        long ms = (long)(now.tv_sec - start.tv_sec) * 1000 + (now.tv_nsec - start.tv_nsec) / 1000000;
        if (ms >= (long)timeout_ms)
            return ALB_TR_TIMEOUT;
        if (u->stop && *u->stop) {
            snprintf(t->error, sizeof t->error, "reading from the board: interrupted");
            return ALB_TR_ERROR;
        }
        events(u, (unsigned)(timeout_ms - (unsigned)ms < 50 ? timeout_ms - (unsigned)ms : 50));
    }
    size_t n = u->rx_len < cap ? u->rx_len : cap;
    memcpy(buf, u->rx, n);
    memmove(u->rx, u->rx + n, u->rx_len - n);
    u->rx_len -= n;
    *got = n;
    return n ? ALB_TR_OK : status_of(t, u);
}

/* HID class requests (HID 1.11, 7.2) on endpoint 0, for a board whose HID
 * interface has no hidraw node: GET_REPORT / SET_REPORT of a feature report
 * (wValue high byte 3), the report ID in buf[0] as hidapi has it. */
#define HID_GET_REPORT   0x01
#define HID_SET_REPORT   0x09
#define HID_FEATURE      0x0300
#define HID_CTRL_TIMEOUT 1000

static alb_tr_status libusb_hid(alb_transport *t, bool get, uint8_t *buf, size_t len)
{
    usb_link *u = t->impl;
    int rc = libusb_control_transfer(
        u->h, (uint8_t)(LIBUSB_REQUEST_TYPE_CLASS | LIBUSB_RECIPIENT_INTERFACE |
                        (get ? LIBUSB_ENDPOINT_IN : LIBUSB_ENDPOINT_OUT)),
        get ? HID_GET_REPORT : HID_SET_REPORT, (uint16_t)(HID_FEATURE | buf[0]), PROTO_IF_HID, buf,
        (uint16_t)len, HID_CTRL_TIMEOUT);
    if (rc < 0) {
        snprintf(t->error, sizeof t->error, "HID %s_REPORT %u through libusb (no hidraw node): %s",
                 get ? "GET" : "SET", buf[0], libusb_error_name(rc));
        return rc == LIBUSB_ERROR_NO_DEVICE ? ALB_TR_GONE : ALB_TR_ERROR;
    }
    return ALB_TR_OK;
}

static alb_tr_status usb_hid_get(alb_transport *t, uint8_t *buf, size_t len)
{
    usb_link *u = t->impl;
    if (u->hid_by_libusb)
        return libusb_hid(t, true, buf, len);
    if (!u->hid) {
        snprintf(t->error, sizeof t->error, "no HID interface open");
        return ALB_TR_ERROR;
    }
    /* hidapi: byte 0 is the report ID, the buffer one byte longer than the report */
    if (hid_get_feature_report(u->hid, buf, len) < 0) {
        snprintf(t->error, sizeof t->error, "HID GET_REPORT %u: %ls", buf[0], hid_error(u->hid));
        return ALB_TR_ERROR;
    }
    return ALB_TR_OK;
}

static alb_tr_status usb_hid_set(alb_transport *t, const uint8_t *buf, size_t len)
{
    usb_link *u = t->impl;
    if (u->hid_by_libusb) {
        uint8_t copy[PROTO_HID_REPORT + 1];
        if (len > sizeof copy)
            len = sizeof copy;
        memcpy(copy, buf, len);
        return libusb_hid(t, false, copy, len);
    }
    if (!u->hid || hid_send_feature_report(u->hid, buf, len) < 0) {
        snprintf(t->error, sizeof t->error, "HID SET_REPORT %u: %ls", buf[0],
                 u->hid ? hid_error(u->hid) : L"no HID interface open");
        return ALB_TR_ERROR;
    }
    return ALB_TR_OK;
}

/* Tear down in order: cancel every transfer, handle events until all their
 * callbacks have run, release the interface, close. */
static void usb_close(alb_transport *t)
{
    usb_link *u = t->impl;
    for (unsigned i = 0; i < OUT_TRANSFERS; i++)
        if (u->out[i].busy)
            libusb_cancel_transfer(u->out[i].xfer);
    for (unsigned i = 0; i < IN_TRANSFERS; i++)
        if (u->in[i].busy)
            libusb_cancel_transfer(u->in[i].xfer);
    for (int spins = 0; (u->busy_out || u->busy_in) && spins < 200; spins++)
        events(u, 10);
    for (unsigned i = 0; i < OUT_TRANSFERS; i++) {
        libusb_free_transfer(u->out[i].xfer);
        free(u->out[i].buf);
    }
    for (unsigned i = 0; i < IN_TRANSFERS; i++) {
        libusb_free_transfer(u->in[i].xfer);
        free(u->in[i].buf);
    }
    if (u->h) {
        if (!u->hid_only)
            libusb_release_interface(u->h, PROTO_IF_DATA);
        libusb_close(u->h);
    }
    if (u->hid)
        hid_close(u->hid);
    hid_exit();
    if (u->ctx)
        libusb_exit(u->ctx);
    free(u->rx);
    free(u);
    free(t);
}

static const alb_transport_ops usb_ops = {"usb", usb_write, usb_flush, usb_read, usb_hid_get,
                                      usb_hid_set, usb_close};

void alb_transport_usb_set_stop(alb_transport *t, const volatile sig_atomic_t *stop)
{
    if (t->ops == &usb_ops)
        ((usb_link *)t->impl)->stop = stop;
}

static const char udev_hint[] =
    " — no permission to open the device: install firmware/udev/70-albatros.rules into "
    "/etc/udev/rules.d/, run 'sudo udevadm control --reload && sudo udevadm trigger', and "
    "replug the board (docs/usb-protocol.md, \"Permissions\")";

/* The first matching device (serial if given), retried for wait_ms so a board
 * that is just arriving (hot-plug) has time to enumerate. */
static int find_and_open(usb_link *u, uint16_t vid, uint16_t pid, const char *serial,
                         unsigned wait_ms, char *err, size_t errlen)
{
    struct timespec start;
    clock_gettime(CLOCK_MONOTONIC, &start);
    for (;;) {
        libusb_device **list;
        ssize_t n = libusb_get_device_list(u->ctx, &list);
        int rc = LIBUSB_ERROR_NOT_FOUND;
        for (ssize_t i = 0; i < n && !u->h; i++) {
            struct libusb_device_descriptor dd;
            if (libusb_get_device_descriptor(list[i], &dd) || dd.idVendor != vid ||
                dd.idProduct != pid)
                continue;
            libusb_device_handle *h;
            rc = libusb_open(list[i], &h);
            if (rc)
                continue;
            char sn[64] = "";
            if (dd.iSerialNumber)
                libusb_get_string_descriptor_ascii(h, dd.iSerialNumber, (unsigned char *)sn,
                                                   sizeof sn);
            if (serial && strcmp(serial, sn)) {
                libusb_close(h);
                rc = LIBUSB_ERROR_NOT_FOUND;
                continue;
            }
            u->h = h;
        }
        if (n >= 0)
            libusb_free_device_list(list, 1);
        if (u->h)
            return 0;
        struct timespec now;
        clock_gettime(CLOCK_MONOTONIC, &now);
        long ms = (long)(now.tv_sec - start.tv_sec) * 1000 + (now.tv_nsec - start.tv_nsec) / 1000000;
        if (rc == LIBUSB_ERROR_ACCESS || ms >= (long)wait_ms) {
            snprintf(err, errlen, "opening USB device %04x:%04x%s%s: %s%s", vid, pid,
                     serial ? " serial " : "", serial ? serial : "", libusb_error_name(rc),
                     rc == LIBUSB_ERROR_ACCESS ? udev_hint
                     : rc == LIBUSB_ERROR_NOT_FOUND ? " (is the board plugged in? 'albatros board "
                                                      "list' shows what is)" : "");
            return -1;
        }
        struct timespec nap = {0, 100 * 1000000};
        nanosleep(&nap, NULL);
    }
}

/* hidapi takes the serial as a wide string */
static int wide(const char *s, wchar_t *out, size_t cap)
{
    size_t n = mbstowcs(out, s, cap);
    if (n == (size_t)-1 || n >= cap)
        return -1;
    return 0;
}

/* The HID interface through hidraw, of the board with this serial if one
 * is given (the same string libusb matched), retried for wait_ms. */
static int open_hid(usb_link *u, uint16_t vid, uint16_t pid, const char *serial,
                    unsigned wait_ms, char *err, size_t errlen)
{
    wchar_t wserial[64];
    if (serial && wide(serial, wserial, sizeof wserial / sizeof *wserial)) {
        snprintf(err, errlen, "serial %s: not a serial number hidapi can take", serial);
        return -1;
    }
    if (hid_init()) {
        snprintf(err, errlen, "initialising hidapi: %ls", hid_error(NULL));
        return -1;
    }
    struct timespec start;
    clock_gettime(CLOCK_MONOTONIC, &start);
    for (;;) {
        u->hid = hid_open(vid, pid, serial ? wserial : NULL);
        if (u->hid)
            return 0;
        struct timespec now;
        clock_gettime(CLOCK_MONOTONIC, &now);
        long ms = (long)(now.tv_sec - start.tv_sec) * 1000 + (now.tv_nsec - start.tv_nsec) / 1000000;
        if (ms >= (long)wait_ms) {
            snprintf(err, errlen, "opening the HID interface of %04x:%04x%s%s with hidapi: %ls "
                     "(permissions? see docs/usb-protocol.md)", vid, pid, serial ? " serial " : "",
                     serial ? serial : "", hid_error(NULL));
            return -1;
        }
        struct timespec nap = {0, 100 * 1000000};
        nanosleep(&nap, NULL);
    }
}

static int setup_transfers(usb_link *u, char *err, size_t errlen)
{
    for (unsigned i = 0; i < OUT_TRANSFERS; i++) {
        u->out[i] = (slot){u, libusb_alloc_transfer(0), malloc(OUT_SIZE), false, 0};
        if (!u->out[i].xfer || !u->out[i].buf)
            goto nomem;
    }
    for (unsigned i = 0; i < IN_TRANSFERS; i++) {
        u->in[i] = (slot){u, libusb_alloc_transfer(0), malloc(IN_SIZE), false, 0};
        if (!u->in[i].xfer || !u->in[i].buf)
            goto nomem;
        libusb_fill_bulk_transfer(u->in[i].xfer, u->h, PROTO_EP_IN, u->in[i].buf, IN_SIZE, in_done,
                                  &u->in[i], 0);
        int rc = libusb_submit_transfer(u->in[i].xfer);
        if (rc) {
            snprintf(err, errlen, "submitting bulk IN transfers: %s", libusb_error_name(rc));
            return -1;
        }
        u->in[i].busy = true;
        u->busy_in++;
    }
    u->filling = OUT_TRANSFERS;
    return 0;
nomem:
    snprintf(err, errlen, "out of memory for USB transfers");
    return -1;
}

/* A transport with its (empty) USB state, or NULL with a message. */
static alb_transport *usb_transport_new(const alb_transport_ops *ops, char *err, size_t errlen)
{
    alb_transport *t = calloc(1, sizeof *t);
    usb_link *u = calloc(1, sizeof *u);
    if (!t || !u) {
        free(t);
        free(u);
        snprintf(err, errlen, "out of memory");
        return NULL;
    }
    t->ops = ops;
    t->impl = u;
    return t;
}

alb_transport *alb_transport_usb_open(uint16_t vid, uint16_t pid, const char *serial, unsigned wait_ms,
                                char *err, size_t errlen)
{
    alb_transport *t = usb_transport_new(&usb_ops, err, errlen);
    if (!t)
        return NULL;
    usb_link *u = t->impl;
    t->max_payload = PROTO_MAX_PAYLOAD;
    /* libusb reads LIBUSB_DEBUG from the environment itself */
    int rc = libusb_init(&u->ctx);
    if (rc) {
        snprintf(err, errlen, "initialising libusb: %s", libusb_error_name(rc));
        free(u);
        free(t);
        return NULL;
    }
    if (find_and_open(u, vid, pid, serial, wait_ms, err, errlen))
        goto fail;
    if ((rc = libusb_claim_interface(u->h, PROTO_IF_DATA))) {
        snprintf(err, errlen, "claiming the data interface of %04x:%04x: %s%s", vid, pid,
                 libusb_error_name(rc), rc == LIBUSB_ERROR_BUSY ? " (another program has it)" : "");
        libusb_close(u->h);
        u->h = NULL;
        goto fail;
    }
    if (setup_transfers(u, err, errlen))
        goto fail;
    if (open_hid(u, vid, pid, serial, 0, err, errlen))
        goto fail;
    return t;
fail:
    usb_close(t);
    return NULL;
}

static alb_tr_status no_bulk(alb_transport *t)
{
    snprintf(t->error, sizeof t->error, "the board was opened for HID control only: no bulk link");
    return ALB_TR_ERROR;
}

static alb_tr_status hid_only_write(alb_transport *t, const uint8_t *data, size_t len)
{
    (void)data, (void)len;
    return no_bulk(t);
}

static alb_tr_status hid_only_flush(alb_transport *t) { return no_bulk(t); }

static alb_tr_status hid_only_read(alb_transport *t, uint8_t *buf, size_t cap, size_t *got,
                               unsigned timeout_ms)
{
    (void)buf, (void)cap, (void)timeout_ms;
    *got = 0;
    return no_bulk(t);
}

static const alb_transport_ops hid_only_ops = {"hid", hid_only_write, hid_only_flush, hid_only_read,
                                           usb_hid_get, usb_hid_set, usb_close};

alb_transport *alb_transport_hid_open(uint16_t vid, uint16_t pid, const char *serial, unsigned wait_ms,
                                char *err, size_t errlen)
{
    alb_transport *t = usb_transport_new(&hid_only_ops, err, errlen);
    if (!t)
        return NULL;
    usb_link *u = t->impl;
    u->hid_only = true;
    if (open_hid(u, vid, pid, serial, wait_ms, err, errlen) == 0)
        return t;
    /* No hidraw node (no usbhid driver bound, or a mocked bus): the same
     * reports as class requests through libusb, after checking with an INFO
     * that they get through.  The data interface stays free either way. */
    char hid_err[300];
    snprintf(hid_err, sizeof hid_err, "%s", err);
    int rc = libusb_init(&u->ctx);
    if (rc) {
        snprintf(err, errlen, "%s; initialising libusb: %s", hid_err, libusb_error_name(rc));
        goto fail;
    }
    if (find_and_open(u, vid, pid, serial, 0, err, errlen))
        goto fail;
    u->hid_by_libusb = true;
    uint8_t info[PROTO_HID_REPORT + 1] = {PROTO_HID_INFO};
    if (libusb_hid(t, true, info, PROTO_HID_REPORT)) {
        snprintf(err, errlen, "%s", t->error);
        goto fail;
    }
    return t;
fail:
    usb_close(t);
    return NULL;
}

int alb_transport_usb_list(uint16_t vid, uint16_t pid, alb_tr_usb_device *out, int max, char *err,
                       size_t errlen)
{
    libusb_context *ctx;
    int rc = libusb_init(&ctx);
    if (rc) {
        snprintf(err, errlen, "initialising libusb: %s", libusb_error_name(rc));
        return -1;
    }
    libusb_device **list;
    ssize_t n = libusb_get_device_list(ctx, &list);
    int found = 0;
    for (ssize_t i = 0; i < n; i++) {
        struct libusb_device_descriptor dd;
        if (libusb_get_device_descriptor(list[i], &dd) || dd.idVendor != vid || dd.idProduct != pid)
            continue;
        char sn[64] = "?";
        libusb_device_handle *h;
        int orc = libusb_open(list[i], &h);
        if (orc == 0) {
            if (dd.iSerialNumber)
                libusb_get_string_descriptor_ascii(h, dd.iSerialNumber, (unsigned char *)sn,
                                                   sizeof sn);
            libusb_close(h);
        }
        if (found < max) {
            alb_tr_usb_device *d = &out[found];
            *d = (alb_tr_usb_device){libusb_get_bus_number(list[i]), libusb_get_device_address(list[i]),
                                 vid, pid, "", orc == LIBUSB_ERROR_ACCESS};
            snprintf(d->serial, sizeof d->serial, "%s", sn[0] ? sn : "?");
        }
        found++;
    }
    if (n >= 0)
        libusb_free_device_list(list, 1);
    libusb_exit(ctx);
    return found;
}
