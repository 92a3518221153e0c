/* transport_usb.c — the real board: bulk data through libusb-1.0's
 * asynchronous API with several transfers in flight each way, control
 * through hidapi (hidraw back end, so the kernel keeps the HID interface and
 * libusb claims only the data interface).  Error messages carry
 * libusb_error_name() and what we were doing; LIBUSB_ERROR_ACCESS names the
 * udev rule to install (docs/usb-protocol.md, "Permissions").  `albatros
 * board` opens the HID interface alone (alb_transport_hid_open), so it works
 * beside a running stream.
 *
 * Completion callbacks only record what happened.  Everything that needs
 * the device or the order of the queue — clearing a halt, sending the rest
 * of a transfer again — is done by service(), from the loops that wait for
 * events, once every transfer in flight on the endpoint has come back: a
 * transfer resubmitted from a callback would go behind the ones still
 * queued, out of order, and libusb's synchronous calls cannot be completed
 * from inside its event handling (libusb docs, "Multi-threaded
 * applications and asynchronous I/O"). */
#include "albatros/transport.h"
#include "../../firmware/proto.h"

#include <errno.h>
#include <hidapi.h>
#include <libusb.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/time.h>
#include <time.h>
#include <wchar.h>

#define OUT_TRANSFERS      16          /* 16 x 64 KiB: ~0.5 s at a 2 MB/s stream */
#define OUT_BYTES          (128u * PROTO_BULK_MAXPKT)
#define IN_TRANSFERS       4
#define IN_BYTES           (32u * PROTO_BULK_MAXPKT)
/* An IN transfer ends after this even without a short packet, with what it
 * holds: a board that ends a reply of whole packets without a zero-length
 * packet still gets through (libusb: TIMED_OUT, actual_length > 0). */
#define IN_TIMEOUT_MS      200
#define IO_TIMEOUT_MS      5000
#define OUT_IDLE_ROUNDS    3           /* watchdog rounds without progress: the link failed */
#define HID_GRACE_MS       2000        /* a hidraw node follows its USB device */
/* cancelled transfers come back within milliseconds; one that has not after
 * twice the I/O timeout (1 to 10 s) never will */
#define CLOSE_DEADLINE_MIN_MS 1000
#define CLOSE_DEADLINE_MAX_MS 10000
#define OPEN_POLL_MS       100

typedef struct usb_link usb_link;

typedef enum {
    OUT_FREE,
    OUT_FILLING,              /* write() is filling it; not submitted */
    OUT_FLIGHT,               /* submitted, its callback not run yet */
    OUT_RESEND                /* came back stalled or cancelled: the rest goes again */
} out_state;

typedef struct {
    usb_link *u;
    struct libusb_transfer *xfer;
    uint8_t *buf;
    size_t len;               /* bytes in the transfer */
    size_t sent;              /* of which the board took in attempts that ended early */
    out_state state;
    uint64_t order;           /* submission number: resends go in this order */
} out_slot;

typedef struct {
    usb_link *u;
    struct libusb_transfer *xfer;
    uint8_t *buf;
    bool busy;
} in_slot;

struct usb_link {
    libusb_context *ctx;
    libusb_device_handle *h;
    hid_device *hid;
    out_slot *out;
    unsigned n_out;
    size_t out_bytes;
    in_slot in[IN_TRANSFERS];
    size_t in_bytes;
    unsigned filling;         /* the OUT_FILLING slot, or n_out */
    uint64_t next_order;
    unsigned busy_out, busy_in;
    unsigned out_mps, in_mps;
    unsigned io_timeout_ms;
    double out_clock;         /* when the board last took OUT data (or was given some) */
    unsigned out_idle_rounds;
    /* recovery to do in service(): */
    bool out_stalled, out_timed_out, out_cancelling, in_stalled, in_cancelling;
    unsigned out_stall_rounds, in_stall_rounds;   /* halts cleared without progress since */
    bool closing;             /* usb_close has begun: callbacks submit nothing */
    bool gone, failed;
    uint8_t *rx;              /* received, not yet read */
    size_t rx_len, rx_cap;
    char error[400];
    char serial[64];          /* the opened device's serial string, "" if none */
    bool hid_only;            /* alb_transport_hid_open: no data interface, no transfers */
    bool hid_by_libusb;       /* no hidraw node: HID class requests on endpoint 0 */
    bool hid_claimed;
    bool data_claimed;
    const volatile sig_atomic_t *stop;   /* alb_transport_usb_set_stop */
    alb_tr_usb_link stats;
};

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static void set_error(usb_link *u, const char *doing, int rc)
{
    if (u->failed)
        return;
    u->failed = true;
    snprintf(u->error, sizeof u->error, "%s: %s", doing, libusb_error_name(rc));
    if (rc == LIBUSB_ERROR_NO_DEVICE)
        u->gone = true;
}

/* libusb_error_name() of what a transfer's status amounts to. */
static int status_error(enum libusb_transfer_status st)
{
    switch (st) {
    case LIBUSB_TRANSFER_TIMED_OUT: return LIBUSB_ERROR_TIMEOUT;
    case LIBUSB_TRANSFER_STALL: return LIBUSB_ERROR_PIPE;
    case LIBUSB_TRANSFER_NO_DEVICE: return LIBUSB_ERROR_NO_DEVICE;
    case LIBUSB_TRANSFER_OVERFLOW: return LIBUSB_ERROR_OVERFLOW;
    case LIBUSB_TRANSFER_CANCELLED: return LIBUSB_ERROR_INTERRUPTED;
    default: return LIBUSB_ERROR_IO;
    }
}

/* ---- completions: record, never resubmit out of order ---- */

static void LIBUSB_CALL out_done(struct libusb_transfer *x)
{
    out_slot *s = x->user_data;
    usb_link *u = s->u;
    u->busy_out--;
    size_t got = x->actual_length > 0 ? (size_t)x->actual_length : 0;
    s->sent += got;
    if (got) {   /* the board takes data: the watchdog starts again */
        u->out_clock = now();
        u->out_idle_rounds = 0;
        u->out_stall_rounds = 0;
    }
    if (s->sent >= s->len && x->status != LIBUSB_TRANSFER_NO_DEVICE) {
        s->state = OUT_FREE;   /* all of it went, whatever the status says */
        if (x->flags & LIBUSB_TRANSFER_ADD_ZERO_PACKET)
            u->stats.zero_length_packets++;
        return;
    }
    switch (x->status) {
    case LIBUSB_TRANSFER_STALL:
        u->out_stalled = true;
        s->state = OUT_RESEND;
        return;
    case LIBUSB_TRANSFER_CANCELLED:    /* the watchdog's (service) or ours closing */
    case LIBUSB_TRANSFER_TIMED_OUT:
        if (!u->closing) {
            s->state = OUT_RESEND;
            return;
        }
        break;
    case LIBUSB_TRANSFER_COMPLETED:    /* short: the kernel does not end OUT so */
        set_error(u, "bulk OUT: a transfer ended short", LIBUSB_ERROR_IO);
        break;
    default:
        set_error(u, "bulk OUT", status_error(x->status));
        break;
    }
    s->state = OUT_FREE;   /* its bytes are lost with the link */
}

static void submit_in(usb_link *u, in_slot *s);

static void LIBUSB_CALL in_done(struct libusb_transfer *x)
{
    in_slot *s = x->user_data;
    usb_link *u = s->u;
    s->busy = false;
    u->busy_in--;
    /* every completion may carry data, a timed-out or cancelled one too;
     * callbacks run in completion order, which is the order of the data */
    if (x->actual_length > 0) {
        size_t need = u->rx_len + (size_t)x->actual_length;
        if (need > u->rx_cap) {
            size_t cap = u->rx_cap ? u->rx_cap * 2 : 65536;
            while (cap < need)
                cap *= 2;
            uint8_t *nr = realloc(u->rx, cap);
            if (!nr) {
                set_error(u, "bulk IN: out of memory", LIBUSB_ERROR_NO_MEM);
                return;
            }
            u->rx = nr;
            u->rx_cap = cap;
        }
        memcpy(u->rx + u->rx_len, x->buffer, (size_t)x->actual_length);
        u->rx_len += (size_t)x->actual_length;
        u->in_stall_rounds = 0;
        if (x->status == LIBUSB_TRANSFER_TIMED_OUT)
            u->stats.in_partial++;
    }
    switch (x->status) {
    case LIBUSB_TRANSFER_COMPLETED:
    case LIBUSB_TRANSFER_TIMED_OUT:
    case LIBUSB_TRANSFER_CANCELLED:
        /* Resubmitting an IN transfer here keeps the order: data goes to
         * the queued transfers first, this one is last in line again. */
        if (!u->closing && !u->failed && !u->in_stalled)
            submit_in(u, s);
        return;
    case LIBUSB_TRANSFER_STALL:
        u->in_stalled = true;
        return;
    default:
        set_error(u, "bulk IN", status_error(x->status));
        return;
    }
}

static void submit_in(usb_link *u, in_slot *s)
{
    libusb_fill_bulk_transfer(s->xfer, u->h, PROTO_EP_IN, s->buf, (int)u->in_bytes, in_done, s,
                              IN_TIMEOUT_MS);
    int rc = libusb_submit_transfer(s->xfer);
    if (rc) {
        set_error(u, "submitting a bulk IN transfer", rc);
        return;
    }
    s->busy = true;
    u->busy_in++;
}

static int submit_out(usb_link *u, out_slot *s)
{
    /* no libusb timeout: a timed-out transfer would let the next one start
     * in its place; the watchdog in service() cancels all of them at once */
    libusb_fill_bulk_transfer(s->xfer, u->h, PROTO_EP_OUT, s->buf, (int)s->len, out_done, s, 0);
    /* a transfer of whole packets ends with a zero-length one, so the board
     * sees where it ends (the endpoint's own packet size, not 512) */
    s->xfer->flags = s->len % u->out_mps == 0 ? LIBUSB_TRANSFER_ADD_ZERO_PACKET : 0;
    int rc = libusb_submit_transfer(s->xfer);
    if (rc) {
        set_error(u, "submitting a bulk OUT transfer", rc);
        s->state = OUT_FREE;
        return -1;
    }
    if (!u->busy_out)
        u->out_clock = now();   /* the board has had nothing to take until now */
    s->state = OUT_FLIGHT;
    s->order = u->next_order++;
    u->busy_out++;
    return 0;
}

/* ---- recovery, outside the callbacks ---- */

/* Cancel every OUT transfer in flight, the last submitted first, so that
 * none starts in the place of an earlier one being cancelled. */
static void cancel_out(usb_link *u)
{
    /* n_out is small: order the flying ones by submission, cancel backwards */
    out_slot *fly[ALB_TR_USB_MAX_TRANSFERS];
    unsigned n = 0;
    for (unsigned i = 0; i < u->n_out; i++)
        if (u->out[i].state == OUT_FLIGHT)
            fly[n++] = &u->out[i];
    for (unsigned i = 1; i < n; i++)
        for (unsigned j = i; j > 0 && fly[j - 1]->order > fly[j]->order; j--) {
            out_slot *t = fly[j];
            fly[j] = fly[j - 1];
            fly[j - 1] = t;
        }
    while (n--)
        libusb_cancel_transfer(fly[n]->xfer);   /* NOT_FOUND: it is completing anyway */
}

static void cancel_in(usb_link *u)
{
    for (unsigned i = IN_TRANSFERS; i-- > 0;)
        if (u->in[i].busy)
            libusb_cancel_transfer(u->in[i].xfer);
}

/* The transfers that came back early, their unsent bytes again, in the
 * order they were first submitted. */
static void resend_out(usb_link *u)
{
    for (;;) {
        out_slot *first = NULL;
        for (unsigned i = 0; i < u->n_out; i++)
            if (u->out[i].state == OUT_RESEND && (!first || u->out[i].order < first->order))
                first = &u->out[i];
        if (!first || u->failed)
            return;
        size_t rest = first->len - first->sent;
        u->stats.resent_bytes += rest;
        memmove(first->buf, first->buf + first->sent, rest);
        first->len = rest;
        first->sent = 0;
        if (submit_out(u, first))
            return;
    }
}

static bool recovering(const usb_link *u)
{
    return u->out_stalled || u->out_timed_out;
}

/* What the callbacks left to do: the OUT watchdog, a stalled endpoint's
 * halt cleared and its transfers resubmitted — each once every transfer on
 * that endpoint has come back. */
static void service(usb_link *u)
{
    if (u->failed || u->closing || u->hid_only)
        return;
    if (u->busy_out && !recovering(u) && (now() - u->out_clock) * 1000 >= u->io_timeout_ms) {
        if (++u->out_idle_rounds >= OUT_IDLE_ROUNDS) {
            char what[160];
            snprintf(what, sizeof what, "bulk OUT: the board took no data for %u x %u ms",
                     OUT_IDLE_ROUNDS, u->io_timeout_ms);
            set_error(u, what, LIBUSB_ERROR_TIMEOUT);
            return;
        }
        u->out_timed_out = true;
        u->stats.out_timeouts++;
    }
    if (recovering(u)) {
        if (u->busy_out) {
            if (!u->out_cancelling)
                cancel_out(u);
            u->out_cancelling = true;
            return;   /* their callbacks first */
        }
        if (u->out_stalled) {
            if (u->out_stall_rounds++ >= 1) {
                set_error(u, "bulk OUT: the endpoint stalled again after its halt was cleared",
                          LIBUSB_ERROR_PIPE);
                return;
            }
            int rc = libusb_clear_halt(u->h, PROTO_EP_OUT);
            if (rc) {
                set_error(u, "clearing the halt of bulk OUT after a stall", rc);
                return;
            }
            u->stats.halts_cleared++;
        }
        u->out_stalled = u->out_timed_out = u->out_cancelling = false;
        resend_out(u);
    }
    if (u->in_stalled) {
        if (u->busy_in) {
            if (!u->in_cancelling)
                cancel_in(u);
            u->in_cancelling = true;
            return;
        }
        if (u->in_stall_rounds++ >= 1) {
            set_error(u, "bulk IN: the endpoint stalled again after its halt was cleared",
                      LIBUSB_ERROR_PIPE);
            return;
        }
        int rc = libusb_clear_halt(u->h, PROTO_EP_IN);
        if (rc) {
            set_error(u, "clearing the halt of bulk IN after a stall", rc);
            return;
        }
        u->stats.halts_cleared++;
        u->in_stalled = u->in_cancelling = false;
        for (unsigned i = 0; i < IN_TRANSFERS && !u->failed; i++)
            submit_in(u, &u->in[i]);
    }
}

/* Handle events for up to ms, then what they left to do. */
static void wait_events(usb_link *u, unsigned ms)
{
    struct timeval tv = {(time_t)(ms / 1000), (suseconds_t)(ms % 1000) * 1000};
    int rc = libusb_handle_events_timeout_completed(u->ctx, &tv, NULL);
    if (rc && rc != LIBUSB_ERROR_INTERRUPTED)
        set_error(u, "handling USB events", rc);
    service(u);
}

/* ---- operations ---- */

static alb_tr_status status_of(alb_transport *t, usb_link *u)
{
    if (!u->failed)
        return ALB_TR_OK;
    snprintf(t->error, sizeof t->error, "%s", u->error);
    return u->gone ? ALB_TR_GONE : ALB_TR_ERROR;
}

static bool interrupted(alb_transport *t, usb_link *u, const char *doing)
{
    if (!u->stop || !*u->stop)
        return false;
    snprintf(t->error, sizeof t->error, "%s: interrupted", doing);
    return true;
}

/* Submit the slot being filled, once no recovery is under way (a transfer
 * submitted before the resends would overtake them).  -1: interrupted. */
static int submit_filling(alb_transport *t, usb_link *u)
{
    while (recovering(u) && !u->failed) {
        if (interrupted(t, u, "writing to the board"))
            return -1;
        wait_events(u, 100);
    }
    if (!u->failed && u->filling < u->n_out && u->out[u->filling].len)
        submit_out(u, &u->out[u->filling]);
    u->filling = u->n_out;
    return 0;
}

static alb_tr_status usb_flush(alb_transport *t)
{
    usb_link *u = t->impl;
    if (u->filling < u->n_out && submit_filling(t, u))
        return ALB_TR_ERROR;
    return status_of(t, u);
}

static alb_tr_status usb_write(alb_transport *t, const uint8_t *data, size_t len)
{
    usb_link *u = t->impl;
    while (len && !u->failed) {
        if (u->filling == u->n_out) {
            /* a free transfer, waiting for one while all are in flight (the
             * board NAKs: flow control) or waiting to be resent */
            unsigned i;
            for (;;) {
                for (i = 0; i < u->n_out && u->out[i].state != OUT_FREE; i++)
                    ;
                if (i < u->n_out || u->failed)
                    break;
                if (interrupted(t, u, "writing to the board"))
                    return ALB_TR_ERROR;
                wait_events(u, 100);
            }
            if (u->failed)
                break;
            u->filling = i;
            u->out[i] = (out_slot){u, u->out[i].xfer, u->out[i].buf, 0, 0, OUT_FILLING, 0};
        }
        out_slot *s = &u->out[u->filling];
        size_t k = u->out_bytes - s->len < len ? u->out_bytes - s->len : len;
        memcpy(s->buf + s->len, data, k);
        s->len += k;
        data += k;
        len -= k;
        if (s->len == u->out_bytes && submit_filling(t, u))
            return ALB_TR_ERROR;
    }
    return status_of(t, u);
}

static alb_tr_status usb_read(alb_transport *t, uint8_t *buf, size_t cap, size_t *got, unsigned timeout_ms)
{
    usb_link *u = t->impl;
    double start = now();
    *got = 0;
    /* a reader waits for the board: what write() queued must go first */
    if (u->filling < u->n_out && submit_filling(t, u))
        return ALB_TR_ERROR;
    for (;;) {
        wait_events(u, 0);
        if (u->rx_len || u->failed)
            break;
        double ms = (now() - start) * 1000;
        if (ms >= timeout_ms)
            return ALB_TR_TIMEOUT;
        if (interrupted(t, u, "reading from the board"))
            return ALB_TR_ERROR;
        double left = timeout_ms - ms;
        wait_events(u, left < 50 ? (unsigned)left + 1 : 50);
    }
    size_t n = u->rx_len < cap ? u->rx_len : cap;
    if (n) {   /* u->rx may not exist yet */
        memcpy(buf, u->rx, n);
        memmove(u->rx, u->rx + n, u->rx_len - n);
        u->rx_len -= n;
    }
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
    if ((size_t)rc != len) {
        snprintf(t->error, sizeof t->error, "HID %s_REPORT %u through libusb: %d of the report's "
                 "%zu bytes", get ? "GET" : "SET", buf[0], rc, len);
        return ALB_TR_ERROR;
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
    /* hidapi: byte 0 is the report ID, the buffer one byte longer than the
     * report; it returns the bytes it got, the ID included */
    int n = hid_get_feature_report(u->hid, buf, len);
    if (n < 0) {
        snprintf(t->error, sizeof t->error, "HID GET_REPORT %u: %ls", buf[0], hid_error(u->hid));
        return ALB_TR_ERROR;
    }
    if ((size_t)n != len) {
        snprintf(t->error, sizeof t->error, "HID GET_REPORT %u: the board sent %d of the report's "
                 "%zu bytes", buf[0], n, len);
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
    int n = u->hid ? hid_send_feature_report(u->hid, buf, len) : -1;
    if (n < 0 || (size_t)n != len) {
        if (n < 0)
            snprintf(t->error, sizeof t->error, "HID SET_REPORT %u: %ls", buf[0],
                     u->hid ? hid_error(u->hid) : L"no HID interface open");
        else
            snprintf(t->error, sizeof t->error, "HID SET_REPORT %u: %d of the report's %zu bytes "
                     "sent", buf[0], n, len);
        return ALB_TR_ERROR;
    }
    return ALB_TR_OK;
}

/* Tear down in order: no callback submits anything from here on; cancel
 * every transfer; handle events until all their callbacks have run; release
 * the interfaces; close.  A transfer whose callback never comes (by the
 * deadline) may still be written by the kernel: its memory, and the handle
 * and context it belongs to, are left allocated rather than freed under it. */
static void usb_close(alb_transport *t)
{
    usb_link *u = t->impl;
    u->closing = true;
    if (u->out)
        cancel_out(u);
    cancel_in(u);
    unsigned wait_ms = 2 * (u->io_timeout_ms ? u->io_timeout_ms : IO_TIMEOUT_MS);
    wait_ms = wait_ms < CLOSE_DEADLINE_MIN_MS ? CLOSE_DEADLINE_MIN_MS
            : wait_ms > CLOSE_DEADLINE_MAX_MS ? CLOSE_DEADLINE_MAX_MS : wait_ms;
    double deadline = now() + wait_ms / 1000.0;
    while (u->ctx && (u->busy_out || u->busy_in) && now() < deadline) {
        struct timeval tv = {0, 100000};
        if (libusb_handle_events_timeout_completed(u->ctx, &tv, NULL) &&
            !(u->busy_out || u->busy_in))
            break;
    }
    bool drained = !u->busy_out && !u->busy_in;
    if (u->hid)
        hid_close(u->hid);
    hid_exit();
    if (!drained) {
        free(t);   /* u, its transfers, handle and context stay: see above */
        return;
    }
    for (unsigned i = 0; u->out && i < u->n_out; i++) {
        libusb_free_transfer(u->out[i].xfer);
        free(u->out[i].buf);
    }
    free(u->out);
    for (unsigned i = 0; i < IN_TRANSFERS; i++) {
        libusb_free_transfer(u->in[i].xfer);
        free(u->in[i].buf);
    }
    if (u->h) {
        if (u->data_claimed)
            libusb_release_interface(u->h, PROTO_IF_DATA);
        if (u->hid_claimed)
            libusb_release_interface(u->h, PROTO_IF_HID);
        libusb_close(u->h);
    }
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

int alb_transport_usb_link(const alb_transport *t, alb_tr_usb_link *out)
{
    if (t->ops != &usb_ops)
        return -1;
    *out = ((const usb_link *)t->impl)->stats;
    return 0;
}

static const char udev_hint[] =
    " — no permission to open the device: install firmware/udev/70-albatros.rules into "
    "/etc/udev/rules.d/, run 'sudo udevadm control --reload && sudo udevadm trigger', and "
    "replug the board (docs/usb-protocol.md, \"Permissions\")";

static void nap_ms(unsigned ms)
{
    struct timespec nap = {0, (long)ms * 1000000};
    nanosleep(&nap, NULL);
}

/* Open the first matching device (serial if given): 0, or the libusb error
 * of the last candidate (LIBUSB_ERROR_NOT_FOUND if there was none). */
static int try_open(usb_link *u, uint16_t vid, uint16_t pid, const char *serial)
{
    libusb_device **list;
    ssize_t n = libusb_get_device_list(u->ctx, &list);
    int rc = n < 0 ? (int)n : LIBUSB_ERROR_NOT_FOUND;
    for (ssize_t i = 0; i < n && !u->h; i++) {
        struct libusb_device_descriptor dd;
        if (libusb_get_device_descriptor(list[i], &dd) || dd.idVendor != vid || dd.idProduct != pid)
            continue;
        libusb_device_handle *h;
        int orc = libusb_open(list[i], &h);
        if (orc) {
            if (rc == LIBUSB_ERROR_NOT_FOUND || orc == LIBUSB_ERROR_ACCESS)
                rc = orc;   /* ACCESS says most about what to do */
            continue;
        }
        char sn[64] = "";
        if (dd.iSerialNumber &&
            libusb_get_string_descriptor_ascii(h, dd.iSerialNumber, (unsigned char *)sn, sizeof sn) < 0)
            sn[0] = 0;
        if (serial && strcmp(serial, sn)) {
            libusb_close(h);
            continue;
        }
        u->h = h;
        snprintf(u->serial, sizeof u->serial, "%s", sn);
        rc = 0;
    }
    if (n >= 0)
        libusb_free_device_list(list, 1);
    return rc;
}

/* The device, looked for every OPEN_POLL_MS for wait_ms (hot-plug: a board
 * still enumerating), and while opening it is refused for up to
 * ALB_TR_USB_ACCESS_GRACE_MS after the first refusal: udev applies the ACL
 * (uaccess, or the plugdev group) a moment after the node appears. */
static int find_and_open(usb_link *u, uint16_t vid, uint16_t pid, const char *serial,
                         unsigned wait_ms, char *err, size_t errlen)
{
    double start = now(), refused = 0;
    for (;;) {
        int rc = try_open(u, vid, pid, serial);
        if (rc == 0)
            return 0;
        double t = now();
        if (rc == LIBUSB_ERROR_ACCESS && refused == 0)
            refused = t;
        bool waiting = (t - start) * 1000 < wait_ms ||
                       (rc == LIBUSB_ERROR_ACCESS && (t - refused) * 1000 < ALB_TR_USB_ACCESS_GRACE_MS);
        if (!waiting) {
            snprintf(err, errlen, "opening USB device %04x:%04x%s%s: %s%s", vid, pid,
                     serial ? " serial " : "", serial ? serial : "", libusb_error_name(rc),
                     rc == LIBUSB_ERROR_ACCESS ? udev_hint
                     : rc == LIBUSB_ERROR_NOT_FOUND ? " (is the board plugged in? 'albatros board "
                                                      "list' shows what is)" : "");
            return -1;
        }
        nap_ms(OPEN_POLL_MS);
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
 * is given (the same string libusb matched), retried for wait_ms, and while
 * its node refuses us for up to ALB_TR_USB_ACCESS_GRACE_MS (the ACL, as for
 * the USB node). */
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
    double start = now(), refused = 0;
    for (;;) {
        errno = 0;
        u->hid = hid_open(vid, pid, serial ? wserial : NULL);
        if (u->hid)
            return 0;
        const wchar_t *why = hid_error(NULL);
        bool denied = errno == EACCES || (why && wcsstr(why, L"Permission denied"));
        double t = now();
        if (denied && refused == 0)
            refused = t;
        if ((t - start) * 1000 >= wait_ms &&
            !(denied && (t - refused) * 1000 < ALB_TR_USB_ACCESS_GRACE_MS)) {
            snprintf(err, errlen, "opening the HID interface of %04x:%04x%s%s with hidapi: %ls%s",
                     vid, pid, serial ? " serial " : "", serial ? serial : "", why ? why : L"?",
                     denied ? udev_hint : " (permissions? see docs/usb-protocol.md)");
            return -1;
        }
        nap_ms(OPEN_POLL_MS);
    }
}

static int setup_transfers(usb_link *u, char *err, size_t errlen)
{
    u->out = calloc(u->n_out, sizeof *u->out);
    if (!u->out)
        goto nomem;
    for (unsigned i = 0; i < u->n_out; i++) {
        u->out[i] = (out_slot){u, libusb_alloc_transfer(0), malloc(u->out_bytes), 0, 0, OUT_FREE, 0};
        if (!u->out[i].xfer || !u->out[i].buf)
            goto nomem;
    }
    for (unsigned i = 0; i < IN_TRANSFERS; i++) {
        u->in[i] = (in_slot){u, libusb_alloc_transfer(0), malloc(u->in_bytes), false};
        if (!u->in[i].xfer || !u->in[i].buf)
            goto nomem;
    }
    for (unsigned i = 0; i < IN_TRANSFERS && !u->failed; i++)
        submit_in(u, &u->in[i]);
    u->filling = u->n_out;
    if (u->failed) {
        snprintf(err, errlen, "%s", u->error);
        return -1;
    }
    return 0;
nomem:
    snprintf(err, errlen, "out of memory for USB transfers");
    return -1;
}

/* The link's speed and packet sizes (the active configuration's
 * wMaxPacketSize: 512 at high speed, 64 or less at full speed), and the
 * buffers made whole numbers of packets. */
static int link_params(usb_link *u, const alb_tr_usb_tuning *tn, char *err, size_t errlen)
{
    libusb_device *dev = libusb_get_device(u->h);
    static const char *const names[] = {"unknown", "low", "full", "high", "super", "super+"};
    static const unsigned mbps[] = {0, 1, 12, 480, 5000, 10000};
    int sp = libusb_get_device_speed(dev);
    if (sp < 0 || sp > LIBUSB_SPEED_SUPER_PLUS)
        sp = LIBUSB_SPEED_UNKNOWN;
    int mo = libusb_get_max_packet_size(dev, PROTO_EP_OUT);
    int mi = libusb_get_max_packet_size(dev, PROTO_EP_IN);
    if (mo <= 0 || mi <= 0) {
        snprintf(err, errlen, "reading the bulk endpoints' wMaxPacketSize (0x%02x, 0x%02x): %s",
                 PROTO_EP_OUT, PROTO_EP_IN, libusb_error_name(mo <= 0 ? mo : mi));
        return -1;
    }
    u->out_mps = (unsigned)mo;
    u->in_mps = (unsigned)mi;
    unsigned n = tn && tn->out_transfers ? tn->out_transfers : OUT_TRANSFERS;
    size_t bytes = tn && tn->out_bytes ? tn->out_bytes : OUT_BYTES;
    if (n > ALB_TR_USB_MAX_TRANSFERS || bytes > ALB_TR_USB_MAX_BYTES) {
        snprintf(err, errlen, "USB tuning: at most %u transfers of %u bytes", ALB_TR_USB_MAX_TRANSFERS,
                 ALB_TR_USB_MAX_BYTES);
        return -1;
    }
    u->n_out = n;
    u->out_bytes = bytes < u->out_mps ? u->out_mps : bytes - bytes % u->out_mps;
    u->in_bytes = IN_BYTES < u->in_mps ? u->in_mps : IN_BYTES - IN_BYTES % u->in_mps;
    u->io_timeout_ms = tn && tn->io_timeout_ms ? tn->io_timeout_ms : IO_TIMEOUT_MS;
    u->stats.speed = names[sp];
    u->stats.speed_mbps = mbps[sp];
    u->stats.out_packet = u->out_mps;
    u->stats.in_packet = u->in_mps;
    u->stats.out_transfers = u->n_out;
    u->stats.in_transfers = IN_TRANSFERS;
    u->stats.out_bytes = u->out_bytes;
    u->stats.in_bytes = u->in_bytes;
    return 0;
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

/* The stream's HID side: through hidraw when a kernel driver (usbhid) holds
 * interface 1 — its node may lag the USB device's, so it is waited for —
 * else as class requests on endpoint 0 through this handle. */
static int stream_hid(alb_transport *t, uint16_t vid, uint16_t pid, char *err, size_t errlen)
{
    usb_link *u = t->impl;
    const char *sn = u->serial[0] ? u->serial : NULL;
    int driver = libusb_kernel_driver_active(u->h, PROTO_IF_HID);
    if (open_hid(u, vid, pid, sn, driver == 0 ? 0 : HID_GRACE_MS, err, errlen) == 0)
        return 0;
    if (driver != 0)
        return -1;   /* the message says what */
    int rc = libusb_claim_interface(u->h, PROTO_IF_HID);
    if (rc) {
        char why[300];
        snprintf(why, sizeof why, "%s", err);
        snprintf(err, errlen, "%s; claiming the HID interface for class requests: %s", why,
                 libusb_error_name(rc));
        return -1;
    }
    u->hid_claimed = u->hid_by_libusb = u->stats.hid_by_libusb = true;
    return 0;
}

alb_transport *alb_transport_usb_open_tuned(uint16_t vid, uint16_t pid, const char *serial,
                                            unsigned wait_ms, const alb_tr_usb_tuning *tuning,
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
        goto fail;
    }
    u->data_claimed = true;
    if (link_params(u, tuning, err, errlen) || setup_transfers(u, err, errlen) ||
        stream_hid(t, vid, pid, err, errlen))
        goto fail;
    return t;
fail:
    usb_close(t);
    return NULL;
}

alb_transport *alb_transport_usb_open(uint16_t vid, uint16_t pid, const char *serial, unsigned wait_ms,
                                char *err, size_t errlen)
{
    return alb_transport_usb_open_tuned(vid, pid, serial, wait_ms, NULL, err, errlen);
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
            if (dd.iSerialNumber &&
                libusb_get_string_descriptor_ascii(h, dd.iSerialNumber, (unsigned char *)sn,
                                                   sizeof sn) < 0)
                snprintf(sn, sizeof sn, "?");
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
