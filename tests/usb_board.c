/* usb_board.c — a board on an emulated USB bus, for tests/usb-umockdev.sh.
 * umockdev's testbed (libumockdev 0.17: a UMockdevIoctlBase attached to a
 * device node with umockdev_testbed_attach_ioctl) presents the FX2
 * firmware's descriptors in sysfs and /dev, and this program answers the
 * ioctls of usbfs (USBDEVFS_*) and hidraw (HIDIOC*) as the kernel would, with
 * the simulated board (firmware/sim/board.c: the firmware core and this
 * project's VP) behind the endpoints.  The command after "--" (the albatros
 * binary) runs unchanged under it: real libusb, real URBs, real events.
 *
 *   umockdev-wrapper usb_board [options] -- albatros stream ...
 *
 * The board checks what a host must get right and a real board could only
 * suffer from: every bulk OUT transfer ends with a short or a zero-length
 * packet, IN buffers are whole packets, no halt is cleared with transfers
 * still queued on the endpoint, no interface is released and no device
 * closed with URBs in flight.  Each breach is a "VIOLATION" line; the last
 * line is the summary, with the board's own counters (what arrived damaged,
 * out of order or twice).  The exit status is the command's (124: it did not
 * finish in time, 125: this program failed).  docs/usb-protocol.md,
 * "Testing without hardware", says what umockdev can emulate and how the
 * gaps are filled (the node's readiness, permissions). */
#include "../firmware/core.h"
#include "../firmware/fx2/usb.h"
#include "../firmware/sim/board.h"
#include "albatros/exr.h"
#include "albatros/link.h"
#include "albatros/profile.h"

#include <umockdev.h>

#include <errno.h>
#include <fcntl.h>
#include <linux/hidraw.h>
#include <linux/input.h>
#include <linux/usbdevice_fs.h>
#include <signal.h>
#include <spawn.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/ioctl.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

extern char **environ;

#define SYSFS_USB   "/sys/devices/pci0000:00/0000:00:14.0/usb1/1-1"
#define SYSFS_HID   SYSFS_USB "/1-1:1.1/0003:1209:0001.0001"
#define HIDRAW_NODE "/dev/hidraw0"
#define SHOWN       8          /* violations printed; all are counted */
#define PAGE        4096
#define SERIAL      "00000001" /* the simulated core's serial (board.c), as usb.c prints it */

/* ---- URBs ---- */

typedef struct urb {
    struct urb *next;
    UMockdevIoctlData *data;      /* the usbdevfs_urb in the client's memory */
    UMockdevIoctlData *buf;       /* its buffer (NULL if empty) */
    unsigned long addr;           /* the client's address of it: DISCARDURB names it so */
    uint8_t type, ep;
    unsigned flags;
    int len, done, status;
    uint8_t *in;                  /* IN data, copied into buf when reaped */
} urb;

typedef struct {
    urb *head, *tail;
} queue;

static void q_push(queue *q, urb *u)
{
    u->next = NULL;
    if (q->tail)
        q->tail->next = u;
    else
        q->head = u;
    q->tail = u;
}

static urb *q_pop(queue *q)
{
    urb *u = q->head;
    if (u) {
        q->head = u->next;
        if (!q->head)
            q->tail = NULL;
    }
    return u;
}

/* Take u out of q; false if it is not there. */
static bool q_remove(queue *q, urb *u)
{
    urb *prev = NULL;
    for (urb *x = q->head; x; prev = x, x = x->next)
        if (x == u) {
            if (prev)
                prev->next = x->next;
            else
                q->head = x->next;
            if (q->tail == x)
                q->tail = prev;
            return true;
        }
    return false;
}

static unsigned q_len(const queue *q)
{
    unsigned n = 0;
    for (const urb *u = q->head; u; u = u->next)
        n++;
    return n;
}

static void urb_free(urb *u)
{
    if (u->data)
        g_object_unref(u->data);
    if (u->buf)
        g_object_unref(u->buf);
    free(u->in);
    free(u);
}

/* One open file of a device node, its URBs in flight and done. */
typedef struct client {
    struct client *next;
    UMockdevIoctlClient *c;
    queue out, in, done;
    unsigned plug;                /* which plug-in of the board it opened */
    bool closed, hid;
} client;

/* A packet the board has committed toward the host: 0 .. mps bytes; one
 * shorter than mps ends the host's transfer. */
typedef struct pkt {
    struct pkt *next;
    unsigned len;
    uint8_t data[];
} pkt;

typedef struct {
    /* options */
    alb_profile prof;
    unsigned mps_override, payload, bus_mbps, timeout_s;
    bool full_speed, hidraw, no_zlp, in_zlp, close_race, stuck_close, old_caps, sink;
    long hid_delay_ms, acl_delay_ms, hid_short, nak_ms, replug_ms, sigint_ms, flip;
    uint64_t nak_after, stall_out, stall_in, unplug_after;
    const char *results_path, *shim, *golden;
    char **cmd;
    /* the bus */
    UMockdevTestbed *tb;
    const char *root;
    UMockdevIoctlBase *usb_handler, *hid_handler;
    GMutex lock;
    unsigned devnum, plug;        /* the device number now; plug-ins so far */
    bool present;                 /* in the testbed now */
    bool gone;                    /* unplugged: clients of the old plug see ENODEV */
    bool removed;                 /* ... and its sysfs and /dev entries are gone */
    int ready_fd;
    bool ready;
    client *clients;
    sim_board *board;
    /* --sink: the firmware core alone, its words counted and dropped (no
     * VP), for throughput: what the bus path costs, not the VP */
    fw_core core;
    fw_hal hal;
    uint8_t *core_buf, *sink_tx;
    size_t sink_tx_len, sink_tx_cap;
    uint64_t sink_bytes;
    unsigned mps;
    bool out_halted, in_halted;
    pkt *tx_head, *tx_tail;
    bool unterminated;            /* the last OUT URB ended on a packet boundary, no ZLP */
    int unterminated_len;
    /* scripted events */
    double plug_time, unplug_time, nak_start, nak_until, credit_time, credit;
    bool nak_forever, nak_done, stall_out_done, stall_in_done, unplug_done;
    bool race_armed, race_done, hid_added, acl_open, sigint_sent, hid_attached;
    pid_t child;
    /* counts */
    uint64_t bytes_out, bytes_in, urbs_out, urbs_in, zlp_out, zlp_in, short_in, halts_cleared,
        discards, partial_in, control, hid_reports;
    unsigned violations;
    FILE *results;
    alb_link_rx rx;
    /* the last RESULT of each frame the board sent (--golden) */
    struct seen {
        uint32_t frame, crc;
        uint64_t cycles;
    } seen[256];
    unsigned nseen;
} mock;

static double now_s(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static void __attribute__((format(printf, 2, 3))) violation(mock *m, const char *fmt, ...)
{
    if (m->violations++ < SHOWN) {
        va_list ap;
        va_start(ap, fmt);
        fprintf(stderr, "usb_board: VIOLATION: ");
        vfprintf(stderr, fmt, ap);
        fputc('\n', stderr);
        va_end(ap);
    }
}

static void __attribute__((noreturn, format(printf, 1, 2))) die(const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    fprintf(stderr, "usb_board: ");
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
    va_end(ap);
    exit(125);
}

/* ---- readiness: usbfs sets POLLOUT while a URB waits to be reaped ----
 * umockdev's node for a USB device is a plain file, always ready, on which
 * libusb would spin; here it is a FIFO the board keeps full (no POLLOUT)
 * and drains by one page (POLLOUT) while any URB is done and not reaped. */

static void fifo_fill(int fd)
{
    static const uint8_t page[PAGE];
    while (write(fd, page, PAGE) == PAGE)
        ;
}

static void update_ready(mock *m)
{
    bool any = false;
    for (client *c = m->clients; c; c = c->next)
        if (!c->closed && !c->hid && c->plug == m->plug && c->done.head)
            any = true;
    if (m->ready_fd < 0 || any == m->ready)
        return;
    uint8_t page[PAGE];
    memset(page, 0, sizeof page);
    if ((any ? read(m->ready_fd, page, PAGE) : write(m->ready_fd, page, PAGE)) != PAGE)
        die("the readiness FIFO: %s", strerror(errno));
    m->ready = any;
}

/* ---- the board's side of the endpoints ---- */

static void record_results(mock *m, const uint8_t *data, size_t len)
{
    if ((!m->results && !m->golden) || alb_link_rx_feed(&m->rx, data, len))
        return;
    alb_link_packet p;
    while (alb_link_rx_next(&m->rx, &p) == 1) {
        if (p.type != PROTO_T_RESULT || p.len < PROTO_RESULT_BYTES)
            continue;
        struct seen r = {PROTO_GET32(p.payload + PROTO_RESULT_FRAME),
                         PROTO_GET32(p.payload + PROTO_RESULT_CRC),
                         PROTO_GET32(p.payload + PROTO_RESULT_CYC_LO) |
                             (uint64_t)PROTO_GET32(p.payload + PROTO_RESULT_CYC_HI) << 32};
        if (m->results)
            fprintf(m->results, "frame=%u crc=%08x cycles=%llu\n", r.frame, r.crc,
                    (unsigned long long)r.cycles);
        unsigned i = 0;
        while (i < m->nseen && m->seen[i].frame != r.frame)
            i++;
        if (i < sizeof m->seen / sizeof *m->seen) {
            m->seen[i] = r;   /* a frame sent again after a replug: its last word */
            m->nseen += i == m->nseen;
        }
    }
}

static void sink_words(void *ctx, const uint8_t *data, uint16_t len)
{
    (void)data;
    ((mock *)ctx)->sink_bytes += len;
}

static void sink_restart(void *ctx, uint8_t full) { (void)ctx, (void)full; }

static void sink_send(void *ctx, const uint8_t *data, uint16_t len)
{
    mock *m = ctx;
    if (m->sink_tx_len + len > m->sink_tx_cap) {
        size_t cap = m->sink_tx_cap ? 2 * m->sink_tx_cap : 4096;
        while (cap < m->sink_tx_len + len)
            cap *= 2;
        if (!(m->sink_tx = realloc(m->sink_tx, cap)))
            die("out of memory");
        m->sink_tx_cap = cap;
    }
    memcpy(m->sink_tx + m->sink_tx_len, data, len);
    m->sink_tx_len += len;
}

/* The board behind the endpoints: the simulated one, or the sink. */
static void board_rx(mock *m, const uint8_t *data, size_t len)
{
    if (!m->sink) {
        sim_board_rx(m->board, data, len);
        return;
    }
    for (size_t k; len; data += k, len -= k) {
        k = len > 0x8000 ? 0x8000 : len;
        fw_rx(&m->core, data, (uint16_t)k);
    }
}

static size_t board_tx(mock *m, uint8_t *buf, size_t cap)
{
    if (!m->sink)
        return sim_board_tx(m->board, buf, cap);
    size_t n = m->sink_tx_len < cap ? m->sink_tx_len : cap;
    if (!n)
        return 0;   /* nothing yet (and perhaps no buffer: memcpy may not see NULL) */
    memcpy(buf, m->sink_tx, n);
    memmove(m->sink_tx, m->sink_tx + n, m->sink_tx_len - n);
    m->sink_tx_len -= n;
    return n;
}

static int board_hid_get(mock *m, uint8_t *rep, size_t len)
{
    if (!m->sink)
        return sim_board_hid_get(m->board, rep, len);
    return len >= PROTO_HID_REPORT && fw_hid_get(&m->core, rep) ? 0 : -1;
}

static int board_hid_set(mock *m, const uint8_t *rep, size_t len)
{
    if (!m->sink)
        return sim_board_hid_set(m->board, rep, len);
    return fw_hid_set(&m->core, rep, (uint8_t)(len > 255 ? 255 : len)) ? -1 : 0;
}

static void tx_push(mock *m, const uint8_t *data, unsigned len)
{
    pkt *p = malloc(sizeof *p + (len ? len : 1));
    if (!p)
        die("out of memory");
    p->next = NULL;
    p->len = len;
    memcpy(p->data, data, len);
    if (m->tx_tail)
        m->tx_tail->next = p;
    else
        m->tx_head = p;
    m->tx_tail = p;
}

static void tx_clear(mock *m)
{
    while (m->tx_head) {
        pkt *p = m->tx_head;
        m->tx_head = p->next;
        free(p);
    }
    m->tx_tail = NULL;
}

/* What the board has for the host, committed as the FX2 firmware commits
 * its IN buffers: each protocol packet as packets of mps bytes, the last
 * one short, or followed by a zero-length packet if it filled its last one
 * (not with --no-zlp: a board that forgets it). */
static void board_commit(mock *m)
{
    static uint8_t buf[1 << 16];
    size_t n;
    while ((n = board_tx(m, buf, sizeof buf)) > 0) {
        record_results(m, buf, n);
        for (size_t at = 0; at < n;) {
            size_t plen = n - at;
            if (plen >= PROTO_HEADER &&
                PROTO_HEADER + PROTO_GET32(buf + at + PROTO_OFF_LEN) + PROTO_TRAILER <= plen)
                plen = PROTO_HEADER + PROTO_GET32(buf + at + PROTO_OFF_LEN) + PROTO_TRAILER;
            if ((m->close_race || m->stuck_close) && plen > PROTO_OFF_TYPE &&
                buf[at + PROTO_OFF_TYPE] == PROTO_T_STATUS)
                m->race_armed = true;   /* the stream's closing PING is answered */
            for (size_t k = 0; k < plen; k += m->mps)
                tx_push(m, buf + at + k, (unsigned)(plen - k < m->mps ? plen - k : m->mps));
            if (plen % m->mps == 0 && !m->no_zlp)
                tx_push(m, buf, 0);
            if (m->in_zlp)
                tx_push(m, buf, 0);   /* a board that also sends empty packets */
            at += plen;
        }
    }
}

static void complete_urb(client *c, urb *u, int status)
{
    u->status = status;
    q_push(&c->done, u);
}

static void fail_queue(client *c, queue *q, int status)
{
    while (q->head)
        complete_urb(c, q_pop(q), status);
}

/* USBDEVFS_URB_BULK_CONTINUATION: after a URB of a transfer libusb split
 * fails (or ends short with SHORT_NOT_OK), the kernel cancels the rest of
 * that transfer, the queued URBs marked as its continuation. */
static void cancel_continuation(client *c, queue *q)
{
    while (q->head && (q->head->flags & USBDEVFS_URB_BULK_CONTINUATION))
        complete_urb(c, q_pop(q), -ECONNRESET);
}

/* IN: the committed packets into the URBs the host has queued, in order. */
static void service_in(mock *m, client *c)
{
    while (c->in.head && m->tx_head && !m->in_halted && !m->gone) {
        urb *u = c->in.head;
        pkt *p = m->tx_head;
        if (m->stall_in && !m->stall_in_done && m->bytes_in + p->len > m->stall_in) {
            /* the endpoint halts: this URB ends with what it got, the
             * queued ones fail, the packet waits for CLEAR_FEATURE(HALT) */
            m->stall_in_done = m->in_halted = true;
            fail_queue(c, &c->in, -EPIPE);
            break;
        }
        if (u->done + (int)p->len > u->len) {
            violation(m, "a bulk IN buffer of %d bytes is not a whole number of %u-byte packets "
                      "(the kernel reports babble)", u->len, m->mps);
            complete_urb(c, q_pop(&c->in), -EOVERFLOW);
            continue;
        }
        memcpy(u->in + u->done, p->data, p->len);
        u->done += (int)p->len;
        m->bytes_in += p->len;
        bool ends = p->len < m->mps;
        if (p->len == 0)
            m->zlp_in++;
        else if (ends)
            m->short_in++;
        m->tx_head = p->next;
        if (!m->tx_head)
            m->tx_tail = NULL;
        free(p);
        if (ends || u->done == u->len) {
            q_pop(&c->in);
            int st = ends && u->done < u->len && (u->flags & USBDEVFS_URB_SHORT_NOT_OK)
                         ? -EREMOTEIO : 0;
            complete_urb(c, u, st);
            if (st)
                cancel_continuation(c, &c->in);
        }
    }
}

static void unplug(mock *m);

static void start_nak(mock *m, double t)
{
    m->nak_done = true;
    m->nak_start = t;
    if (m->nak_ms > 0)
        m->nak_until = t + (double)m->nak_ms / 1000.0;
    else
        m->nak_forever = true;
}

/* OUT: the host's URBs into the board a packet at a time, as far as the
 * board takes them (NAK, halt, a paced bus); the board's answers go out on
 * IN as they come. */
static void service_out(mock *m, client *c)
{
    double t = now_s();
    if (m->bus_mbps) {
        m->credit += (t - m->credit_time) * m->bus_mbps * 1e6;
        if (m->credit > 65536)
            m->credit = 65536;   /* an idle bus saves nothing up */
        m->credit_time = t;
    }
    while (c->out.head && !m->out_halted && !m->gone && !m->nak_forever && t >= m->nak_until) {
        urb *u = c->out.head;
        if (u->done == 0 && m->unterminated) {
            m->unterminated = false;
            if (!(u->flags & USBDEVFS_URB_BULK_CONTINUATION))
                violation(m, "a bulk OUT transfer of %d bytes, a whole number of %u-byte "
                          "packets, ended without a zero-length packet: the board cannot see "
                          "where it ends", m->unterminated_len, m->mps);
        }
        int k = u->len - u->done < (int)m->mps ? u->len - u->done : (int)m->mps;
        if (k > 0) {
            if (m->bus_mbps && m->credit < k)
                break;
            uint64_t after = m->bytes_out + (uint64_t)k;
            if (m->stall_out && !m->stall_out_done && after > m->stall_out) {
                m->stall_out_done = m->out_halted = true;
                fail_queue(c, &c->out, -EPIPE);
                break;
            }
            if (m->unplug_after && !m->unplug_done && after > m->unplug_after) {
                unplug(m);
                break;
            }
            if (m->nak_after && !m->nak_done && after > m->nak_after) {
                start_nak(m, t);
                break;
            }
            board_rx(m, u->buf->data + u->done, (size_t)k);
            u->done += k;
            m->bytes_out += (uint64_t)k;
            m->credit -= k;
            board_commit(m);
            service_in(m, c);
            continue;
        }
        /* the transfer's end as the board sees it */
        if (u->len % (int)m->mps == 0) {
            if (u->len == 0 || (u->flags & USBDEVFS_URB_ZERO_PACKET))
                m->zlp_out++;
            else {
                m->unterminated = true;   /* unless the next URB continues it */
                m->unterminated_len = u->len;
            }
        }
        complete_urb(c, q_pop(&c->out), 0);
    }
}

static void service(mock *m)
{
    for (client *c = m->clients; c; c = c->next)
        if (!c->closed && !c->hid && c->plug == m->plug) {
            service_out(m, c);
            service_in(m, c);
        }
    update_ready(m);
}

/* The device goes away mid-transfer: what is queued ends with ESHUTDOWN
 * (libusb: LIBUSB_TRANSFER_NO_DEVICE), every later call gets ENODEV; the
 * testbed entries go in the main loop. */
static void unplug(mock *m)
{
    m->unplug_done = m->gone = true;
    m->unplug_time = now_s();
    for (client *c = m->clients; c; c = c->next)
        if (!c->closed && !c->hid && c->plug == m->plug) {
            fail_queue(c, &c->out, -ESHUTDOWN);
            fail_queue(c, &c->in, -ESHUTDOWN);
        }
    /* the old node stays ready for good: libusb reaps, then sees ENODEV */
    if (m->ready_fd >= 0) {
        uint8_t page[PAGE];
        while (read(m->ready_fd, page, PAGE) > 0)
            ;
        close(m->ready_fd);
        m->ready_fd = -1;
        m->ready = false;
    }
    tx_clear(m);
}

/* ---- descriptors ---- */

/* The configuration for the link's speed, the bulk packet size replaced by
 * --mps if given. */
static void config_desc(const mock *m, uint8_t *out)
{
    memcpy(out, m->full_speed ? desc_config_fs : desc_config_hs, DESC_CONFIG_LEN);
    for (unsigned i = 0; i + 6 < DESC_CONFIG_LEN; i += out[i] ? out[i] : 1u)
        if (out[i + 1] == 5 && (out[i + 3] & 3) == 2 && m->mps_override) {
            out[i + 4] = (uint8_t)m->mps_override;
            out[i + 5] = (uint8_t)(m->mps_override >> 8);
        }
}

static size_t string_desc(unsigned index, uint8_t *out, size_t cap)
{
    const char *s = index == 3 ? SERIAL : index >= 1 && index <= 2 ? desc_string_text[index - 1]
                                                                   : NULL;
    if (index == 0) {
        static const uint8_t langs[] = {4, 3, 0x09, 0x04};
        memcpy(out, langs, 4);
        return 4;
    }
    if (!s)
        return 0;
    size_t n = 2;
    for (; *s && n + 2 <= cap && n + 2 <= 255; s++, n += 2)
        out[n] = (uint8_t)*s, out[n + 1] = 0;
    out[0] = (uint8_t)n;
    out[1] = 3;
    return n;
}

/* A control transfer on endpoint 0, as the FX2 firmware answers it
 * (firmware/fx2/usb.c): descriptors, and the HID class requests of a board
 * whose HID interface no kernel driver holds.  Returns the data length
 * (IN) or -EPIPE (a STALL). */
static int control(mock *m, client *c, uint8_t *setup, uint8_t *data, int cap)
{
    uint8_t type = setup[0], req = setup[1];
    unsigned value = setup[2] | setup[3] << 8, index = setup[4] | setup[5] << 8;
    int len = setup[6] | setup[7] << 8;
    uint8_t tmp[256];
    size_t n = 0;
    (void)c;
    m->control++;
    if (len > cap)
        return -EOVERFLOW;
    if (type == 0x80 && req == 6) {   /* GET_DESCRIPTOR */
        switch (value >> 8) {
        case 1: memcpy(tmp, desc_device, n = DESC_DEVICE_LEN); break;
        case 2: config_desc(m, tmp); n = DESC_CONFIG_LEN; break;
        case 3: n = string_desc(value & 0xFF, tmp, sizeof tmp); break;
        case 6: memcpy(tmp, desc_qualifier, n = DESC_QUALIFIER_LEN); break;
        default: return -EPIPE;
        }
        if (!n)
            return -EPIPE;
        n = n < (size_t)len ? n : (size_t)len;
        memcpy(data, tmp, n);
        return (int)n;
    }
    if ((type & 0x7F) == 0x21 && index == PROTO_IF_HID && (value >> 8) == 3) {
        /* HID 1.11, 7.2: GET_REPORT / SET_REPORT of a feature report */
        if (m->hidraw)
            return -EBUSY;   /* usbhid holds the interface: usbfs refuses */
        uint8_t rep[PROTO_HID_REPORT] = {(uint8_t)(value & 0xFF)};
        m->hid_reports++;
        if (req == 1 && type == 0xA1) {
            if (board_hid_get(m, rep, sizeof rep))
                return -EPIPE;
            n = (size_t)len < sizeof rep ? (size_t)len : sizeof rep;
            memcpy(data, rep, n);
            return (int)n;
        }
        if (req == 9 && type == 0x21)
            return board_hid_set(m, data, (size_t)len) ? -EPIPE : 0;
    }
    if (type == 0x00 && req == 9)   /* SET_CONFIGURATION */
        return 0;
    return -EPIPE;
}

/* ---- usbfs ---- */

static client *client_of(mock *m, UMockdevIoctlClient *uc)
{
    for (client *c = m->clients; c; c = c->next)
        if (c->c == uc)
            return c;
    return NULL;
}

static UMockdevIoctlData *resolve(UMockdevIoctlData *d, size_t off, size_t len)
{
    GError *err = NULL;
    UMockdevIoctlData *r = umockdev_ioctl_data_resolve(d, off, len, &err);
    if (err) {
        fprintf(stderr, "usb_board: reading the client's memory: %s\n", err->message);
        g_error_free(err);
        return NULL;
    }
    return r;
}

static bool dead(const mock *m, const client *c) { return c->plug != m->plug || m->gone; }

static int submit(mock *m, client *c, UMockdevIoctlData *arg)
{
    if (dead(m, c))
        return -ENODEV;
    UMockdevIoctlData *ud = resolve(arg, 0, sizeof(struct usbdevfs_urb));
    if (!ud)
        return -EFAULT;
    struct usbdevfs_urb k;
    memcpy(&k, ud->data, sizeof k);
    urb *u = calloc(1, sizeof *u);
    if (!u)
        die("out of memory");
    u->data = ud;
    u->addr = ud->client_addr;
    u->type = k.type;
    u->ep = k.endpoint;
    u->flags = k.flags;
    u->len = k.buffer_length;
    if (u->len > 0) {
        u->buf = resolve(ud, offsetof(struct usbdevfs_urb, buffer), (size_t)u->len);
        if (!u->buf) {
            urb_free(u);
            return -EFAULT;
        }
    }
    if (u->type == USBDEVFS_URB_TYPE_CONTROL) {
        if (u->len < 8) {
            urb_free(u);
            return -EINVAL;
        }
        u->in = calloc(1, (size_t)u->len);
        if (!u->in)
            die("out of memory");
        memcpy(u->in, u->buf->data, (size_t)u->len);
        int r = control(m, c, u->in, u->in + 8, u->len - 8);
        if (r == -EBUSY || r == -EOVERFLOW) {
            urb_free(u);
            return r;
        }
        u->done = r > 0 ? r : 0;
        complete_urb(c, u, r < 0 ? r : 0);
        update_ready(m);
        return 0;
    }
    if (u->type != USBDEVFS_URB_TYPE_BULK || (u->ep != PROTO_EP_OUT && u->ep != PROTO_EP_IN)) {
        urb_free(u);
        return -ENOENT;   /* no such endpoint in this configuration */
    }
    if (u->ep == PROTO_EP_IN) {
        m->urbs_in++;
        u->in = malloc((size_t)u->len + 1);
        if (!u->in)
            die("out of memory");
        q_push(&c->in, u);
        if (m->in_halted)
            fail_queue(c, &c->in, -EPIPE);
    } else {
        m->urbs_out++;
        q_push(&c->out, u);
        if (m->out_halted)
            fail_queue(c, &c->out, -EPIPE);
    }
    service(m);
    return 0;
}

static int reap(mock *m, client *c, UMockdevIoctlData *arg)
{
    urb *u = q_pop(&c->done);
    if (!u)
        return dead(m, c) ? -ENODEV : -EAGAIN;
    struct usbdevfs_urb *k = (struct usbdevfs_urb *)u->data->data;
    k->status = u->status;
    k->actual_length = u->done;
    if (u->type == USBDEVFS_URB_TYPE_CONTROL) {
        if (u->done && (u->in[0] & 0x80))
            memcpy(u->buf->data + 8, u->in + 8, (size_t)u->done);
    } else if (u->ep == PROTO_EP_IN && u->done) {
        memcpy(u->buf->data, u->in, (size_t)u->done);
    }
    UMockdevIoctlData *pd = resolve(arg, 0, sizeof(void *));
    if (!pd) {
        urb_free(u);
        return -EFAULT;
    }
    /* the pointer the client gets back is its own URB, now written back */
    umockdev_ioctl_data_set_ptr(pd, 0, u->data);
    g_object_unref(pd);
    u->data = NULL;   /* pd's parent owns it now */
    urb_free(u);
    update_ready(m);
    return 0;
}

static int discard(mock *m, client *c, unsigned long addr)
{
    m->discards++;
    if (dead(m, c))
        return -ENODEV;
    queue *qs[] = {&c->out, &c->in};
    for (int i = 0; i < 2; i++)
        for (urb *u = qs[i]->head; u; u = u->next)
            if (u->addr == addr && m->stuck_close && m->race_armed) {
                /* --stuck-close: a discard that never completes (the
                 * transfer's callback never comes) */
                if (!m->race_done)
                    fprintf(stderr, "usb_board: keeping the host's cancelled URBs for good\n");
                m->race_done = true;
                return 0;
            } else if (u->addr == addr) {
                if (u == c->in.head && m->race_armed && !m->race_done && u->next) {
                    /* --close-race: the board answers into the next IN URB
                     * just as the host starts cancelling them */
                    m->race_done = true;
                    fprintf(stderr, "usb_board: answering into an IN URB as the host cancels\n");
                    urb *v = u->next;
                    uint8_t p[PROTO_HEADER + PROTO_TRAILER];
                    size_t n = alb_link_encode(p, PROTO_T_STATUS, 0, NULL, 0);
                    memcpy(v->in, p, n < (size_t)v->len ? n : (size_t)v->len);
                    v->done = (int)(n < (size_t)v->len ? n : (size_t)v->len);
                    q_remove(&c->in, v);
                    complete_urb(c, v, 0);
                }
                if (u->ep == PROTO_EP_IN && u->done)
                    m->partial_in++;
                q_remove(qs[i], u);
                complete_urb(c, u, -ECONNRESET);
                update_ready(m);
                return 0;
            }
    return -EINVAL;   /* done already (or never ours): libusb reaps it */
}

static unsigned in_flight(const client *c, unsigned ep)
{
    unsigned n = 0;
    const queue *qs[] = {&c->out, &c->in, &c->done};
    for (int i = 0; i < 3; i++)
        for (const urb *u = qs[i]->head; u; u = u->next)
            if (ep == 0x100 ? u->type == USBDEVFS_URB_TYPE_BULK : u->ep == ep)
                n++;
    return n;
}

static int clear_halt(mock *m, client *c, unsigned ep)
{
    if (dead(m, c))
        return -ENODEV;
    if (ep != PROTO_EP_OUT && ep != PROTO_EP_IN)
        return -ENOENT;
    unsigned n = in_flight(c, ep);
    if (n)
        violation(m, "CLEAR_FEATURE(HALT) on endpoint 0x%02x with %u URBs still queued or not "
                  "reaped there: they go after it, out of order (cancel and drain first)", ep, n);
    m->halts_cleared++;
    if (ep == PROTO_EP_OUT)
        m->out_halted = false;
    else
        m->in_halted = false;
    service(m);
    return 0;
}

static unsigned caps(const mock *m)
{
    return m->old_caps ? USBDEVFS_CAP_ZERO_PACKET | USBDEVFS_CAP_BULK_CONTINUATION
                       : USBDEVFS_CAP_ZERO_PACKET | USBDEVFS_CAP_BULK_CONTINUATION |
                             USBDEVFS_CAP_NO_PACKET_SIZE_LIM | USBDEVFS_CAP_BULK_SCATTER_GATHER |
                             USBDEVFS_CAP_REAP_AFTER_DISCONNECT;
}

static int usbfs_ioctl(mock *m, client *c, unsigned long req, UMockdevIoctlData *arg)
{
    unsigned long raw = *(unsigned long *)arg->data;
    if (req == USBDEVFS_SUBMITURB)
        return submit(m, c, arg);
    if (req == USBDEVFS_REAPURBNDELAY || req == USBDEVFS_REAPURB)
        return reap(m, c, arg);
    if (req == USBDEVFS_DISCARDURB)
        return discard(m, c, raw);
    if (dead(m, c))
        return -ENODEV;
    if (req == USBDEVFS_GET_SPEED)
        return m->full_speed ? 2 : 3;   /* USB_SPEED_FULL, USB_SPEED_HIGH */
    if (req == USBDEVFS_RESET || req == USBDEVFS_SETINTERFACE || req == USBDEVFS_SETCONFIGURATION)
        return 0;
    UMockdevIoctlData *d = resolve(arg, 0, _IOC_SIZE(req) ? _IOC_SIZE(req) : 4);
    if (!d)
        return -EFAULT;
    int r = -ENOTTY;
    unsigned v = *(unsigned *)d->data;
    if (req == USBDEVFS_GET_CAPABILITIES) {
        *(uint32_t *)d->data = caps(m);
        r = 0;
    } else if (req == USBDEVFS_CLAIMINTERFACE) {
        r = v > PROTO_IF_HID ? -ENOENT : v == PROTO_IF_HID && m->hidraw ? -EBUSY : 0;
    } else if (req == USBDEVFS_RELEASEINTERFACE) {
        unsigned n = v == PROTO_IF_DATA ? in_flight(c, 0x100) : 0;
        if (n)
            violation(m, "the data interface released with %u URBs in flight (cancel them and "
                      "wait for their callbacks first)", n);
        r = v > PROTO_IF_HID ? -EINVAL : 0;
    } else if (req == USBDEVFS_CLEAR_HALT) {
        r = clear_halt(m, c, v);
    } else if (req == USBDEVFS_GETDRIVER) {
        struct usbdevfs_getdriver *g = (struct usbdevfs_getdriver *)d->data;
        if (g->interface == PROTO_IF_HID && m->hidraw) {
            snprintf(g->driver, sizeof g->driver, "usbhid");
            r = 0;
        } else {
            r = -ENODATA;
        }
    } else if (req == USBDEVFS_CONNECTINFO) {
        struct usbdevfs_connectinfo *ci = (struct usbdevfs_connectinfo *)d->data;
        ci->devnum = m->devnum;
        ci->slow = 0;
        r = 0;
    } else {
        static bool told;
        if (!told)
            fprintf(stderr, "usb_board: unhandled usbfs ioctl 0x%lx\n", req);
        told = true;
    }
    g_object_unref(d);
    return r;
}

/* ---- hidraw ---- */

static int hidraw_ioctl(mock *m, client *c, unsigned long req, UMockdevIoctlData *arg)
{
    if (dead(m, c))
        return -ENODEV;
    unsigned size = _IOC_SIZE(req), nr = _IOC_NR(req);
    if (_IOC_TYPE(req) != 'H' || !size)
        return -ENOTTY;
    UMockdevIoctlData *d = resolve(arg, 0, size);
    if (!d)
        return -EFAULT;
    uint8_t *b = d->data;
    int r = -ENOTTY;
    if (req == HIDIOCGRDESCSIZE) {
        *(int *)b = DESC_HID_REPORT_LEN;
        r = 0;
    } else if (req == HIDIOCGRDESC) {
        struct hidraw_report_descriptor *rd = (struct hidraw_report_descriptor *)b;
        rd->size = DESC_HID_REPORT_LEN;
        memcpy(rd->value, desc_hid_report, DESC_HID_REPORT_LEN);
        r = 0;
    } else if (req == HIDIOCGRAWINFO) {
        struct hidraw_devinfo *di = (struct hidraw_devinfo *)b;
        di->bustype = BUS_USB;
        di->vendor = (int16_t)PROTO_VID;
        di->product = (int16_t)PROTO_PID;
        r = 0;
    } else if (nr == _IOC_NR(HIDIOCGFEATURE(0))) {
        uint8_t rep[PROTO_HID_REPORT] = {b[0]};
        m->hid_reports++;
        if (board_hid_get(m, rep, sizeof rep)) {
            r = -EPIPE;   /* the board STALLs a report it does not have */
        } else {
            unsigned n = size < sizeof rep ? size : (unsigned)sizeof rep;
            if (m->hid_short >= 0 && (unsigned)m->hid_short < n)
                n = (unsigned)m->hid_short;
            memcpy(b, rep, n);
            r = (int)n;
        }
    } else if (nr == _IOC_NR(HIDIOCSFEATURE(0))) {
        m->hid_reports++;
        r = board_hid_set(m, b, size) ? -EPIPE : (int)size;
    } else if (nr == _IOC_NR(HIDIOCGRAWNAME(0)) || nr == _IOC_NR(HIDIOCGRAWUNIQ(0)) ||
               nr == _IOC_NR(HIDIOCGRAWPHYS(0))) {
        const char *s = nr == _IOC_NR(HIDIOCGRAWUNIQ(0)) ? SERIAL : desc_string_text[1];
        snprintf((char *)b, size, "%s", s);
        r = (int)strlen((char *)b) + 1;
    }
    g_object_unref(d);
    return r;
}

/* ---- the handlers, in umockdev's worker thread ---- */

/* A client's file closed: what it left in flight is a breach. */
static void client_closed(mock *m, client *c)
{
    c->closed = true;
    unsigned n = q_len(&c->out) + q_len(&c->in) + q_len(&c->done);
    if (n && !c->hid)
        violation(m, "the device closed with %u URBs in flight or not reaped (%u OUT, %u IN "
                  "pending, %u done)", n, q_len(&c->out), q_len(&c->in), q_len(&c->done));
    if (m->unterminated && !c->hid && !dead(m, c)) {
        m->unterminated = false;
        violation(m, "the last bulk OUT transfer (%d bytes, a whole number of %u-byte packets) "
                  "ended without a zero-length packet", m->unterminated_len, m->mps);
    }
    queue *qs[] = {&c->out, &c->in, &c->done};
    for (int i = 0; i < 3; i++)
        while (qs[i]->head)
            urb_free(q_pop(qs[i]));
    update_ready(m);
}

/* umockdev 0.17 never emits client-vanished and its "connected" property
 * does not always notify: the main loop looks (tick). */
static void check_closed(mock *m)
{
    for (client *c = m->clients; c; c = c->next)
        if (!c->closed && !umockdev_ioctl_client_get_connected(c->c))
            client_closed(m, c);
}

static void add_client(mock *m, UMockdevIoctlClient *uc, bool hid)
{
    g_mutex_lock(&m->lock);
    client *c = calloc(1, sizeof *c);
    if (!c)
        die("out of memory");
    c->c = g_object_ref(uc);
    c->hid = hid;
    c->plug = m->plug;
    c->next = m->clients;
    m->clients = c;
    g_mutex_unlock(&m->lock);
}

static void on_usb_client(UMockdevIoctlBase *h, UMockdevIoctlClient *uc, gpointer data)
{
    (void)h;
    add_client(data, uc, false);
}

static void on_hid_client(UMockdevIoctlBase *h, UMockdevIoctlClient *uc, gpointer data)
{
    (void)h;
    add_client(data, uc, true);
}

static gboolean on_ioctl(UMockdevIoctlBase *h, UMockdevIoctlClient *uc, gpointer data)
{
    mock *m = data;
    unsigned long req = umockdev_ioctl_client_get_request(uc);
    UMockdevIoctlData *arg = umockdev_ioctl_client_get_arg(uc);
    g_mutex_lock(&m->lock);
    client *c = client_of(m, uc);
    int r = !c ? -EBADF : h == m->hid_handler ? hidraw_ioctl(m, c, req, arg)
                                              : usbfs_ioctl(m, c, req, arg);
    g_mutex_unlock(&m->lock);
    umockdev_ioctl_client_complete(uc, r < 0 ? -1 : r, r < 0 ? -r : 0);
    return TRUE;
}

/* ---- the testbed: plugging the board in and out ---- */

static void hex(char *out, const uint8_t *b, size_t n)
{
    for (size_t i = 0; i < n; i++)
        sprintf(out + 2 * i, "%02X", b[i]);
}

static void add(mock *m, const char *text)
{
    GError *err = NULL;
    if (!umockdev_testbed_add_from_string(m->tb, text, &err))
        die("adding a device to the testbed: %s", err ? err->message : "?");
}

static char *node_path(const mock *m, char *buf, size_t cap)
{
    snprintf(buf, cap, "%s/dev/bus/usb/001/%03u", m->root, m->devnum);
    return buf;
}

static void set_access(mock *m, bool open)
{
    char p[512];
    chmod(node_path(m, p, sizeof p), open ? 0666 : 0600);
    snprintf(p, sizeof p, "%s%s", m->root, HIDRAW_NODE);
    chmod(p, open ? 0666 : 0600);
    m->acl_open = open;
}

static void add_hid(mock *m)
{
    char rd[2 * DESC_HID_REPORT_LEN + 1], text[2048];
    hex(rd, desc_hid_report, DESC_HID_REPORT_LEN);
    snprintf(text, sizeof text,
             "P: /devices/pci0000:00/0000:00:14.0/usb1/1-1/1-1:1.1/0003:1209:0001.0001\n"
             "E: SUBSYSTEM=hid\nE: DRIVER=hid-generic\nE: HID_ID=0003:00001209:00000001\n"
             "E: HID_NAME=%s %s\nE: HID_UNIQ=%s\nH: report_descriptor=%s\n\n"
             "P: /devices/pci0000:00/0000:00:14.0/usb1/1-1/1-1:1.1/0003:1209:0001.0001/hidraw/hidraw0\n"
             "N: hidraw0=00\nE: DEVNAME=/dev/hidraw0\nE: SUBSYSTEM=hidraw\nE: MAJOR=241\nE: MINOR=0\n"
             "A: dev=241:0\nL: device=../../../0003:1209:0001.0001\n",
             desc_string_text[0], desc_string_text[1], SERIAL, rd);
    /* a plain file as the node ("=00"), not umockdev's pty, which could not
     * be created again after a replug: only ioctls reach it */
    add(m, text);
    if (!m->hid_attached) {
        GError *err = NULL;
        if (!umockdev_testbed_attach_ioctl(m->tb, HIDRAW_NODE, m->hid_handler, &err))
            die("attaching the hidraw handler: %s", err ? err->message : "?");
        m->hid_attached = true;
    }
    char p[512];
    snprintf(p, sizeof p, "%s%s", m->root, HIDRAW_NODE);
    chmod(p, m->acl_open ? 0666 : 0600);
    m->hid_added = true;
}

static void plug(mock *m)
{
    uint8_t desc[DESC_DEVICE_LEN + DESC_CONFIG_LEN];
    memcpy(desc, desc_device, DESC_DEVICE_LEN);
    config_desc(m, desc + DESC_DEVICE_LEN);
    char dh[2 * sizeof desc + 1], text[4096], p[512];
    hex(dh, desc, sizeof desc);
    m->devnum++;
    snprintf(text, sizeof text,
             "P: " "/devices/pci0000:00/0000:00:14.0/usb1/1-1" "\nN: bus/usb/001/%03u\n"
             "E: DEVNAME=/dev/bus/usb/001/%03u\nE: DEVTYPE=usb_device\nE: DRIVER=usb\n"
             "E: PRODUCT=1209/1/100\nE: SUBSYSTEM=usb\nE: BUSNUM=001\nE: DEVNUM=%03u\n"
             "E: MAJOR=189\nE: MINOR=%u\n"
             "A: busnum=1\nA: devnum=%u\nA: speed=%s\nA: bConfigurationValue=1\n"
             "A: bNumConfigurations=1\nA: bNumInterfaces= 2\nA: idVendor=1209\nA: idProduct=0001\n"
             "A: manufacturer=%s\nA: product=%s\nA: serial=%s\nA: dev=189:%u\nH: descriptors=%s\n\n"
             "P: /devices/pci0000:00/0000:00:14.0/usb1/1-1/1-1:1.0\nE: DEVTYPE=usb_interface\n"
             "E: SUBSYSTEM=usb\nE: INTERFACE=255/0/0\nA: bInterfaceNumber=00\nA: bInterfaceClass=ff\n\n"
             "P: /devices/pci0000:00/0000:00:14.0/usb1/1-1/1-1:1.1\nE: DEVTYPE=usb_interface\n"
             "E: SUBSYSTEM=usb\nE: INTERFACE=3/0/0\n%sA: bInterfaceNumber=01\nA: bInterfaceClass=03\n",
             m->devnum, m->devnum, m->devnum, m->devnum - 1, m->devnum,
             m->full_speed ? "12" : "480", desc_string_text[0], desc_string_text[1], SERIAL,
             m->devnum - 1, dh, m->hidraw ? "E: DRIVER=usbhid\n" : "");
    add(m, text);
    /* the node: a FIFO kept full, drained while a URB waits to be reaped */
    node_path(m, p, sizeof p);
    unlink(p);
    if (mkfifo(p, 0666) || (m->ready_fd = open(p, O_RDWR | O_NONBLOCK)) < 0)
        die("the device node %s: %s", p, strerror(errno));
    fifo_fill(m->ready_fd);
    m->ready = false;
    char dev[64];
    snprintf(dev, sizeof dev, "/dev/bus/usb/001/%03u", m->devnum);
    GError *err = NULL;
    if (!umockdev_testbed_attach_ioctl(m->tb, dev, m->usb_handler, &err))
        die("attaching the usbfs handler: %s", err ? err->message : "?");
    m->plug++;
    m->gone = m->removed = false;
    m->present = true;
    m->out_halted = m->in_halted = false;
    m->unterminated = false;
    m->plug_time = now_s();
    m->hid_added = false;
    set_access(m, m->acl_delay_ms == 0);
    if (m->hidraw && m->hid_delay_ms == 0)
        add_hid(m);
}

static void remove_from_testbed(mock *m)
{
    const char *paths[] = {SYSFS_HID "/hidraw/hidraw0", SYSFS_HID, SYSFS_USB "/1-1:1.1",
                           SYSFS_USB "/1-1:1.0", SYSFS_USB};
    /* children first: remove_device takes each one's bus and class links */
    for (unsigned i = m->hid_added ? 0 : 2; i < 5; i++) {
        umockdev_testbed_uevent(m->tb, paths[i], "remove");
        umockdev_testbed_remove_device(m->tb, paths[i]);
    }
    m->removed = true;
    m->present = false;
}

/* A new board, as after a power cycle: the core starts from its power-on
 * state (no RESET seen). */
static void new_board(mock *m)
{
    if (m->sink) {
        free(m->core_buf);
        if (!(m->core_buf = malloc(PROTO_HEADER + PROTO_MAX_PAYLOAD + PROTO_TRAILER)))
            die("out of memory");
        m->hal = (fw_hal){m, sink_words, sink_restart, sink_send, NULL, NULL};
        fw_init(&m->core, &m->hal, m->core_buf,
                (uint16_t)(m->payload ? m->payload : PROTO_MAX_PAYLOAD));
        m->core.width = (uint16_t)m->prof.width;
        m->core.height = (uint16_t)m->prof.height;
        m->core.colour_bits = (uint8_t)m->prof.colour_bits;
        m->core.serial = 1;
        memcpy(m->core.name, "albatros-sink", 14);
        m->sink_tx_len = 0;
        return;
    }
    char err[200];
    sim_board_destroy(m->board);
    m->board = sim_board_create(&m->prof, err, sizeof err);
    if (!m->board)
        die("%s", err);
    if (m->payload)
        sim_board_set_max_payload(m->board, (uint16_t)m->payload);
    if (m->flip >= 0)   /* a faulty VP: the host and --golden must both notice */
        sim_board_flip(m->board, (uint32_t)m->flip, 5, 7, 1, 0);
}

/* ---- the main loop: scripted events, the paced bus, the command ---- */

static void tick(mock *m)
{
    double t = now_s();
    g_mutex_lock(&m->lock);
    if (m->present && !m->gone) {
        if (m->hidraw && !m->hid_added && t >= m->plug_time + (double)m->hid_delay_ms / 1000)
            add_hid(m);
        if (!m->acl_open && m->acl_delay_ms > 0 && t >= m->plug_time + (double)m->acl_delay_ms / 1000)
            set_access(m, true);   /* udev has applied the ACL */
    }
    if (m->gone && !m->removed)
        remove_from_testbed(m);
    if (m->removed && m->replug_ms >= 0 && t >= m->unplug_time + (double)m->replug_ms / 1000) {
        m->replug_ms = -1;
        new_board(m);
        plug(m);
    }
    if (m->sigint_ms >= 0 && m->nak_done && !m->sigint_sent &&
        t >= m->nak_start + (double)m->sigint_ms / 1000) {
        m->sigint_sent = true;
        kill(m->child, SIGINT);
    }
    if (m->nak_until > 0 && t >= m->nak_until)
        m->nak_until = 0;
    service(m);
    check_closed(m);
    g_mutex_unlock(&m->lock);
}

static pid_t spawn(mock *m)
{
    /* the command's environment: ours (UMOCKDEV_DIR, LD_PRELOAD), with the
     * permission shim in front of umockdev's preload */
    size_t n = 0;
    while (environ[n])
        n++;
    char **env = calloc(n + 2, sizeof *env);
    char *pre = NULL;
    if (!env)
        die("out of memory");
    size_t k = 0;
    for (size_t i = 0; i < n; i++)
        if (strncmp(environ[i], "LD_PRELOAD=", 11) || !m->shim)
            env[k++] = environ[i];
        else if ((pre = malloc(strlen(environ[i]) + strlen(m->shim) + 2))) {
            sprintf(pre, "LD_PRELOAD=%s:%s", m->shim, environ[i] + 11);
            env[k++] = pre;
        }
    env[k] = NULL;
    pid_t pid;
    int rc = posix_spawnp(&pid, m->cmd[0], NULL, NULL, m->cmd, env);
    free(env);
    free(pre);
    if (rc)
        die("running %s: %s", m->cmd[0], strerror(rc));
    return pid;
}

static void counters(mock *m, uint32_t *v)
{
    uint8_t rep[PROTO_HID_REPORT] = {PROTO_HID_COUNTERS};
    memset(v, 0, PROTO_STATUS_BYTES);
    if (!board_hid_get(m, rep, sizeof rep))
        for (unsigned i = 0; i < PROTO_STATUS_BYTES / 4; i++)
            v[i] = PROTO_GET32(rep + 1 + 4 * i);
}

static void summary(mock *m)
{
    uint32_t v[PROTO_STATUS_BYTES / 4];
    counters(m, v);
    fprintf(stderr, "usb_board: %s speed, %u-byte packets; bulk OUT %llu bytes in %llu URBs (%llu "
            "zero-length packets), IN %llu bytes in %llu URBs (%llu short, %llu zero-length, %llu "
            "cut off with data); %llu halts cleared, %llu discards, %llu control, %llu HID "
            "reports; plugged in %u times; board: %u packets, %u bad CRCs, %u gaps, %u "
            "duplicates, %u garbage bytes, %u frames, %u dropped; %u violations\n",
            m->full_speed ? "full" : "high", m->mps, (unsigned long long)m->bytes_out,
            (unsigned long long)m->urbs_out, (unsigned long long)m->zlp_out,
            (unsigned long long)m->bytes_in, (unsigned long long)m->urbs_in,
            (unsigned long long)m->short_in, (unsigned long long)m->zlp_in,
            (unsigned long long)m->partial_in, (unsigned long long)m->halts_cleared,
            (unsigned long long)m->discards, (unsigned long long)m->control,
            (unsigned long long)m->hid_reports, m->plug, v[0], v[1], v[2], v[3], v[4], v[5], v[8],
            m->violations);
}

/* --golden DIR: what the board sent over the emulated bus against the
 * golden vector's own files, not the host's emulator: each frame's cycles
 * as expected.cycles has them, its CRC that of expected.NNNN.exr's exact
 * frame store (vp.R, vp.G, vp.B).  Returns the frames that differ or were
 * never reported. */
static unsigned golden(const mock *m, const char *dir)
{
    char path[1024], line[512];
    snprintf(path, sizeof path, "%s/expected.cycles", dir);
    FILE *f = fopen(path, "r");
    if (!f)
        die("%s: %s", path, strerror(errno));
    unsigned frames = 0, bad = 0;
    while (fgets(line, sizeof line, f)) {
        unsigned frame;
        unsigned long long cycles;
        if (sscanf(line, "frame=%u cycles=%llu", &frame, &cycles) != 2)
            continue;
        frames++;
        snprintf(path, sizeof path, "%s/expected.%04u.exr", dir, frame);
        alb_frame fr;
        alb_diag d;
        alb_diag_init(&d, NULL);
        if (alb_exr_read_frame(path, &fr, &d))
            die("%s: %s", path, d.msg);
        uint32_t crc = alb_link_frame_crc(fr.rgb, (size_t)fr.width * fr.height);
        alb_frame_free(&fr);
        const struct seen *r = NULL;
        for (unsigned i = 0; i < m->nseen; i++)
            if (m->seen[i].frame == frame)
                r = &m->seen[i];
        if (!r || r->crc != crc || r->cycles != cycles) {
            bad++;
            fprintf(stderr, "usb_board: GOLDEN MISMATCH: frame %u: %s%08x, %llu cycles; %s has "
                    "%08x, %llu cycles\n", frame, r ? "the board sent CRC " : "never reported; ",
                    r ? r->crc : 0, r ? (unsigned long long)r->cycles : 0, dir, crc, cycles);
        }
    }
    fclose(f);
    if (!frames)
        die("%s/expected.cycles: no frame=N cycles=C lines", dir);
    fprintf(stderr, "usb_board: golden: %u of %u frames as %s has them (CRC of the frame store, "
            "cycles)\n", frames - bad, frames, dir);
    return bad;
}

static void usage(void)
{
    fprintf(stderr,
            "usage: umockdev-wrapper usb_board [options] -- COMMAND [ARGS]\n"
            "  --profile NAME, --set K=V   the VP the board runs (as the stream's)\n"
            "  --payload N         largest payload in INFO (default 16384)\n"
            "  --speed full|high   the link (default high); --mps N: bulk wMaxPacketSize\n"
            "  --hid hidraw|none   usbhid bound with a hidraw node (default), or no driver\n"
            "  --hid-delay MS      the hidraw node appears MS after the USB device\n"
            "  --hid-short N       HID GET_FEATURE returns N bytes\n"
            "  --acl-delay MS|never  the nodes open to the user MS after arrival\n"
            "  --nak-after B:MS    after B bytes OUT, NAK for MS (0: for good)\n"
            "  --sigint MS         SIGINT to the command MS after the NAK began\n"
            "  --stall-out B, --stall-in B   halt the endpoint at byte B\n"
            "  --unplug-after B:MS unplug after B bytes OUT, back after MS (-1: never)\n"
            "  --no-zlp, --in-zlp  IN without the ZLP after a whole packet / with spurious ones\n"
            "  --close-race        answer into an IN URB as the host starts cancelling\n"
            "  --stuck-close       at the end, cancelled URBs never come back\n"
            "  --old-caps          usbfs without NO_PACKET_SIZE_LIM (libusb splits transfers)\n"
            "  --bus-mbps N        pace bulk OUT at N MB/s (in 1 ms steps)\n"
            "  --sink              the firmware core alone, words dropped (throughput)\n"
            "  --results FILE      each RESULT the board sends, a line\n"
            "  --golden DIR        check the RESULTs against a golden vector's files\n"
            "  --flip F            the board's VP gets one bit of frame F wrong\n"
            "  --shim SO           LD_PRELOAD'ed in front of umockdev's into the command\n"
            "  --timeout S         kill the command after S seconds (default 60)\n");
    exit(125);
}

static long num(const char *s)
{
    char *end;
    long v = strtol(s, &end, 0);
    if (end == s || *end)
        die("%s: expected a number", s);
    return v;
}

static void pair(const char *s, uint64_t *a, long *b)
{
    char *end;
    *a = strtoull(s, &end, 0);
    if (end == s || *end != ':')
        die("%s: expected BYTES:MS", s);
    *b = num(end + 1);
}

static void parse(mock *m, int argc, char **argv)
{
    alb_profile_lookup("a256", &m->prof);
    m->hidraw = true;
    m->hid_short = m->sigint_ms = m->replug_ms = m->flip = -1;
    m->timeout_s = 60;
    int i = 1;
    for (; i < argc && strcmp(argv[i], "--"); i++) {
        const char *o = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        bool flag = true;
        char err[200];
        if (!strcmp(o, "--no-zlp")) m->no_zlp = true;
        else if (!strcmp(o, "--in-zlp")) m->in_zlp = true;
        else if (!strcmp(o, "--close-race")) m->close_race = true;
        else if (!strcmp(o, "--stuck-close")) m->stuck_close = true;
        else if (!strcmp(o, "--old-caps")) m->old_caps = true;
        else if (!strcmp(o, "--sink")) m->sink = true;
        else flag = false;
        if (flag)
            continue;
        if (!v)
            usage();
        i++;
        if (!strcmp(o, "--profile")) {
            if (alb_profile_lookup(v, &m->prof))
                die("--profile %s: no such profile", v);
        } else if (!strcmp(o, "--set")) {
            if (alb_profile_set(&m->prof, v, err, sizeof err))
                die("--set %s: %s", v, err);
        } else if (!strcmp(o, "--payload")) m->payload = (unsigned)num(v);
        else if (!strcmp(o, "--speed")) m->full_speed = !strcmp(v, "full");
        else if (!strcmp(o, "--mps")) m->mps_override = (unsigned)num(v);
        else if (!strcmp(o, "--hid")) m->hidraw = strcmp(v, "none") != 0;
        else if (!strcmp(o, "--hid-delay")) m->hid_delay_ms = num(v);
        else if (!strcmp(o, "--hid-short")) m->hid_short = num(v);
        else if (!strcmp(o, "--acl-delay")) m->acl_delay_ms = !strcmp(v, "never") ? -1 : num(v);
        else if (!strcmp(o, "--nak-after")) pair(v, &m->nak_after, &m->nak_ms);
        else if (!strcmp(o, "--sigint")) m->sigint_ms = num(v);
        else if (!strcmp(o, "--stall-out")) m->stall_out = (uint64_t)num(v);
        else if (!strcmp(o, "--stall-in")) m->stall_in = (uint64_t)num(v);
        else if (!strcmp(o, "--unplug-after")) pair(v, &m->unplug_after, &m->replug_ms);
        else if (!strcmp(o, "--bus-mbps")) m->bus_mbps = (unsigned)num(v);
        else if (!strcmp(o, "--results")) m->results_path = v;
        else if (!strcmp(o, "--golden")) m->golden = v;
        else if (!strcmp(o, "--flip")) m->flip = num(v);
        else if (!strcmp(o, "--shim")) m->shim = v;
        else if (!strcmp(o, "--timeout")) m->timeout_s = (unsigned)num(v);
        else usage();
    }
    if (i + 1 >= argc)
        usage();
    m->cmd = argv + i + 1;
    m->mps = m->mps_override ? m->mps_override : m->full_speed ? 64u : PROTO_BULK_MAXPKT;
}

int main(int argc, char **argv)
{
    static mock mk;
    mock *m = &mk;
    parse(m, argc, argv);
    g_mutex_init(&m->lock);
    m->ready_fd = -1;
    alb_link_rx_init(&m->rx);
    if (m->results_path && !(m->results = fopen(m->results_path, "w")))
        die("%s: %s", m->results_path, strerror(errno));
    m->tb = umockdev_testbed_new();
    if (!umockdev_in_mock_environment())
        die("run me under umockdev-wrapper (libumockdev-preload in LD_PRELOAD)");
    m->root = umockdev_testbed_get_root_dir(m->tb);
    m->usb_handler = umockdev_ioctl_base_new();
    m->hid_handler = umockdev_ioctl_base_new();
    g_signal_connect(m->usb_handler, "handle-ioctl", G_CALLBACK(on_ioctl), m);
    g_signal_connect(m->hid_handler, "handle-ioctl", G_CALLBACK(on_ioctl), m);
    g_signal_connect(m->usb_handler, "client-connected", G_CALLBACK(on_usb_client), m);
    g_signal_connect(m->hid_handler, "client-connected", G_CALLBACK(on_hid_client), m);
    new_board(m);
    m->devnum = 1;
    g_mutex_lock(&m->lock);
    plug(m);
    m->credit_time = now_s();
    g_mutex_unlock(&m->lock);
    m->child = spawn(m);
    double start = now_s();
    int status = 0, rc = 125;
    for (;;) {
        pid_t w = waitpid(m->child, &status, WNOHANG);
        if (w == m->child) {
            rc = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
            break;
        }
        if (now_s() - start > m->timeout_s) {
            kill(m->child, SIGKILL);
            waitpid(m->child, &status, 0);
            fprintf(stderr, "usb_board: %s did not finish in %u s\n", m->cmd[0], m->timeout_s);
            rc = 124;
            break;
        }
        tick(m);
        struct timespec nap = {0, 1000000};
        nanosleep(&nap, NULL);
    }
    /* the command's sockets close as it exits: wait for the handlers to see it */
    for (int i = 0; i < 500; i++) {
        g_mutex_lock(&m->lock);
        check_closed(m);
        bool open = false;
        for (client *c = m->clients; c; c = c->next)
            open |= !c->closed;
        g_mutex_unlock(&m->lock);
        if (!open)
            break;
        struct timespec nap = {0, 2000000};
        nanosleep(&nap, NULL);
    }
    g_mutex_lock(&m->lock);
    summary(m);
    unsigned bad = m->golden ? golden(m, m->golden) : 0;
    g_mutex_unlock(&m->lock);
    if (m->results)
        fclose(m->results);
    return rc ? rc : bad ? 1 : 0;
}
