/* fx2_s51.c — the FX2 firmware image, as sdcc built it, run on the s51 8051
 * simulator with the chip's USB side and FPGA bus played around it
 * (fx2sim.h), and checked against the portable core built for the host
 * (firmware/core.c, as tests/test_fw_core.c uses it): every packet, HID
 * report, word and VP restart the image produces must be the host core's,
 * input by input.  Also the image's speed, from s51's cycle counts
 * (docs/usb-protocol.md, "The firmware on an 8051 simulator").
 *
 *   fx2_s51 check IMAGE.ihx [--cpu C52] [--plant crc|magic] [--only NAME]
 *   fx2_s51 speed IMAGE.ihx STREAM [--fps 50] [--profile]
 *   fx2_s51 opcodes IMAGE.ihx
 *
 * The listings (*.rst) and .map are read from the image's directory. */
#include "fx2sim.h"
#include "../../../tests/refpacket.h"
#include "i8051.h"
#include "listing.h"
#include "speed.h"
#include "../board.h"
#include "../usb.h"
#include "../../core.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* The FX2 board's identity and payload limit (firmware/fx2/main.c,
 * board_init; docs/usb-protocol.md: 512 − header − CRC). */
#define BOARD_PAYLOAD (PROTO_BULK_MAXPKT - PROTO_HEADER - PROTO_TRAILER)
#define BOARD_WIDTH   FX2_BOARD_WIDTH
#define BOARD_HEIGHT  FX2_BOARD_HEIGHT
#define BOARD_CBITS   FX2_BOARD_COLOUR_BITS
#define BOARD_FW      0x0100
#define BOARD_SERIAL  1u
#define BOARD_NAME    "FX2LP+FPGA VP"
#define HID_PERIOD    100u   /* USB frames between COUNTERS input reports (main.c) */

/* the test's own encoder and bit-by-bit CRC-32: tests/refpacket.c */

/* ---- the host core: the reference ---- */

typedef struct {
    fw_core core;
    fw_hal hal;
    uint8_t buf[PROTO_HEADER + BOARD_PAYLOAD + PROTO_TRAILER];
    fx2_queue in;
    uint8_t *words;
    size_t nwords, cap;
    uint8_t restart[FX2_QUEUE];
    size_t nrestart;
    /* Words in the EP4 buffer being filled (main.c): the FPGA sees a buffer
     * when it is full or the EP2 packet ends, and a VP restart empties EP4,
     * so words the core forwarded just before a RESET or RESUME in the
     * same USB packet never reach the FPGA.  (The bridge sends every packet
     * in a transfer of its own, so with it they never exist.) */
    size_t ep4_fill;
    bool overflow;
    /* poll_hid's memory (main.c): the last report's frame and CRC */
    uint16_t hid_frame;
    uint32_t hid_sum;
} ref_t;

static void ref_words(void *ctx, const uint8_t *d, uint16_t len)
{
    ref_t *r = ctx;
    if (r->nwords + len > r->cap) {
        size_t cap = r->cap ? r->cap * 2 : 65536;
        while (cap < r->nwords + len)
            cap *= 2;
        uint8_t *p = realloc(r->words, cap);
        if (!p) {
            r->overflow = true;
            return;
        }
        r->words = p;
        r->cap = cap;
    }
    memcpy(r->words + r->nwords, d, len);
    r->nwords += len;
    r->ep4_fill = (r->ep4_fill + len) % 512u;
}

static void ref_restart(void *ctx, uint8_t full)
{
    ref_t *r = ctx;
    r->nwords -= r->ep4_fill < r->nwords ? r->ep4_fill : r->nwords;
    r->ep4_fill = 0;
    if (r->nrestart < FX2_QUEUE)
        r->restart[r->nrestart++] = full;
    else
        r->overflow = true;
}

static void ref_send(void *ctx, const uint8_t *d, uint16_t len)
{
    ref_t *r = ctx;
    if (r->in.n == FX2_QUEUE || len > sizeof r->in.pkt[0].data) {
        r->overflow = true;
        return;
    }
    memcpy(r->in.pkt[r->in.n].data, d, len);
    r->in.pkt[r->in.n++].len = len;
}

static void ref_init(ref_t *r)
{
    memset(r, 0, sizeof *r);
    r->hal.ctx = r;
    r->hal.vp_words = ref_words;
    r->hal.vp_restart = ref_restart;
    r->hal.send = ref_send;   /* no tile, no readback: the FX2's HAL */
    fw_init(&r->core, &r->hal, r->buf, BOARD_PAYLOAD);
    r->core.width = BOARD_WIDTH;
    r->core.height = BOARD_HEIGHT;
    r->core.colour_bits = BOARD_CBITS;
    r->core.fw_version = BOARD_FW;
    r->core.serial = BOARD_SERIAL;
    memcpy(r->core.name, BOARD_NAME, strlen(BOARD_NAME));
}

static void ref_clear(ref_t *r)
{
    r->in.n = 0;
    r->nwords = 0;
    r->nrestart = 0;
}

/* ---- a scenario: the image and the host core, fed the same ---- */

typedef struct {
    fx2_t f;
    ref_t r;
    unsigned steps;
    bool bad;
    char why[1200];
    uint32_t seq;             /* the host's next sequence number */
    uint64_t rng;
} pair_t;

/* Deterministic pseudo-random numbers (xorshift64*). */
static uint64_t t_rand(uint64_t *s)
{
    *s ^= *s >> 12;
    *s ^= *s << 25;
    *s ^= *s >> 27;
    return *s * 0x2545F4914F6CDD1DULL;
}

static listing_t g_lst;
static const char *g_image, *g_cpu = "C52";
static int g_plant;           /* 0 none, 1 a CRC table byte, 2 the magic */
static bool g_verbose;
static const char *g_preload;  /* s51_fastpoll.so beside this program, if there */

static bool failf(pair_t *p, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static bool failf(pair_t *p, const char *fmt, ...)
{
    if (p->bad)
        return false;
    int n = snprintf(p->why, sizeof p->why, "input %u: ", p->steps);
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(p->why + n, sizeof p->why - (size_t)n, fmt, ap);
    va_end(ap);
    p->bad = true;
    return false;
}

static const char *type_name(uint8_t t)
{
    switch (t) {
    case PROTO_T_RESULT: return "RESULT";
    case PROTO_T_STATUS: return "STATUS";
    case PROTO_T_ERROR: return "ERROR";
    default: return "?";
    }
}

static bool same_queue(pair_t *p, const char *what, const fx2_queue *img, const fx2_queue *want)
{
    for (size_t i = 0; i < img->n || i < want->n; i++) {
        if (i >= img->n)
            return failf(p, "%s %zu (%s) missing: the host core sent %zu, the image %zu", what,
                         i, want->pkt[i].len > 4 ? type_name(want->pkt[i].data[4]) : "-",
                         want->n, img->n);
        if (i >= want->n)
            return failf(p, "%s %zu (%u bytes, %s) is extra: the host core sent %zu", what, i,
                         img->pkt[i].len, img->pkt[i].len > 4 ? type_name(img->pkt[i].data[4]) :
                         "-", want->n);
        const fx2_packet *a = &img->pkt[i], *b = &want->pkt[i];
        size_t k = 0;
        while (k < a->len && k < b->len && a->data[k] == b->data[k])
            k++;
        if (k < a->len || k < b->len) {
            if (a->len != b->len && (k == a->len || k == b->len))
                return failf(p, "%s %zu: %u bytes, the host core's %u", what, i, a->len, b->len);
            return failf(p, "%s %zu (%s): byte %zu is 0x%02x, the host core's 0x%02x", what, i,
                         b->len > 4 ? type_name(b->data[4]) : "-", k, a->data[k], b->data[k]);
        }
    }
    return true;
}

/* Everything the image did since the last compare against the host core. */
static bool compare(pair_t *p)
{
    fx2_t *f = &p->f;
    ref_t *r = &p->r;
    if (r->overflow)
        return failf(p, "the reference overflowed its queues");
    if (!same_queue(p, "bulk IN packet", &f->in, &r->in))
        return false;
    size_t k = 0;
    while (k < f->nfpga && k < r->nwords && f->fpga[k] == r->words[k])
        k++;
    if (k < f->nfpga || k < r->nwords) {
        if (k == f->nfpga || k == r->nwords)
            return failf(p, "%zu word bytes reached the FPGA, the host core forwarded %zu",
                         f->nfpga, r->nwords);
        return failf(p, "word byte %zu to the FPGA is 0x%02x, the host core's 0x%02x", k,
                     f->fpga[k], r->words[k]);
    }
    if (f->nrestart != r->nrestart)
        return failf(p, "%zu VP restart pulses, the host core %zu", f->nrestart, r->nrestart);
    for (size_t i = 0; i < f->nrestart; i++)
        if (f->restart[i] != r->restart[i])
            return failf(p, "VP restart %zu: VP_NEW_STREAM %u, the host core's full %u", i,
                         f->restart[i], r->restart[i]);
    fx2_clear(f);
    ref_clear(r);
    return true;
}

static bool sim_ok(pair_t *p, int rc)
{
    return rc ? failf(p, "%s", p->f.error) : true;
}

/* One USB packet on EP2 to both. */
static bool usb(pair_t *p, const uint8_t *d, uint16_t n)
{
    if (p->bad)
        return false;
    p->steps++;
    if (!sim_ok(p, fx2_bulk_out(&p->f, d, n)))
        return false;
    if (!p->f.ep2_taken)
        return failf(p, "the firmware did not hand EP2 back (OUTPKTEND)");
    fw_rx(&p->r.core, d, n);
    p->r.ep4_fill = 0;   /* the end of an EP2 packet commits EP4 */
    if (g_verbose) {
        fprintf(stderr, "input %u: USB packet of %u bytes:", p->steps, n);
        for (unsigned i = 0; i < n && i < 24; i++)
            fprintf(stderr, " %02x", d[i]);
        fprintf(stderr, "%s; image: %zu IN, %zu FPGA bytes; host core: %zu IN, %zu bytes, "
                "fill %u, error state %u\n", n > 24 ? " ..." : "", p->f.in.n, p->f.nfpga,
                p->r.in.n, p->r.nwords, p->r.core.fill, p->r.core.error_state);
    }
    return compare(p);
}

/* A host transfer: 512-byte USB packets, the last short, or a zero-length
 * packet after an exact multiple (docs/usb-protocol.md). */
static bool transfer(pair_t *p, const uint8_t *d, size_t n)
{
    size_t off = 0;
    while (off < n) {
        uint16_t k = n - off > PROTO_BULK_MAXPKT ? PROTO_BULK_MAXPKT : (uint16_t)(n - off);
        if (!usb(p, d + off, k))
            return false;
        off += k;
    }
    return n % PROTO_BULK_MAXPKT ? true : usb(p, d, 0);
}

/* Bytes cut into USB packets of the sizes in cuts[] (cycled). */
static bool cut(pair_t *p, const uint8_t *d, size_t n, const uint16_t *cuts, size_t ncuts)
{
    size_t off = 0, i = 0;
    while (off < n) {
        uint16_t k = cuts[i++ % ncuts];
        if (k > n - off)
            k = (uint16_t)(n - off);
        if (!usb(p, d + off, k))
            return false;
        off += k;
    }
    return true;
}

/* A packet of the host's numbering, as its own transfer. */
static bool pkt(pair_t *p, uint8_t type, const void *pay, uint32_t len)
{
    uint8_t b[PROTO_HEADER + 1024 + PROTO_TRAILER];
    if (len > 1024)
        return failf(p, "test packet too long");
    size_t n = enc(b, type, p->seq++, pay, len);
    return transfer(p, b, n);
}

static bool pkt_u32(pair_t *p, uint8_t type, uint32_t v)
{
    uint8_t b[4];
    le32(b, v);
    return pkt(p, type, b, 4);
}

static void words_of(uint8_t *b, size_t nwords, uint32_t base)
{
    for (size_t i = 0; i < nwords; i++)
        le32(b + 4 * i, base + (uint32_t)i * 0x01010101u);
}

static bool words(pair_t *p, size_t nwords, uint32_t base)
{
    uint8_t b[1024];
    words_of(b, nwords, base);
    return pkt(p, PROTO_T_WORDS, b, (uint32_t)(4 * nwords));
}

/* A control request to both: the image through EP0, the host core by the
 * rules of firmware/fx2/usb.c; expected = the host core's report. */
static bool control_check(pair_t *p, const char *what, const uint8_t *want, unsigned want_len,
                          uint16_t wlength, bool want_stall)
{
    fx2_t *f = &p->f;
    if (f->stalled != want_stall)
        return failf(p, "%s: %s, expected %s", what, f->stalled ? "stalled" : "answered",
                     want_stall ? "a STALL" : "an answer");
    if (!f->acked)
        return failf(p, "%s: the status stage was not ended (HSNAK)", what);
    fx2_queue exp = {.n = 0};
    if (!want_stall && want) {
        unsigned n = want_len < wlength ? want_len : wlength;
        memcpy(exp.pkt[0].data, want, n);
        exp.pkt[0].len = (uint16_t)n;
        exp.n = 1;
        if (n == 64 && wlength > 64)   /* a full packet shorter than asked: a ZLP ends it */
            exp.pkt[exp.n++].len = 0;
    }
    char label[80];
    snprintf(label, sizeof label, "%s: EP0 packet", what);
    if (!same_queue(p, label, &f->ep0, &exp))
        return false;
    f->ep0.n = 0;
    return compare(p);
}

static void setup_of(uint8_t *s, uint8_t rt, uint8_t req, uint16_t value, uint16_t index,
                     uint16_t length)
{
    s[0] = rt;
    s[1] = req;
    s[2] = (uint8_t)value;
    s[3] = (uint8_t)(value >> 8);
    s[4] = (uint8_t)index;
    s[5] = (uint8_t)(index >> 8);
    s[6] = (uint8_t)length;
    s[7] = (uint8_t)(length >> 8);
}

#define HID_GET_REPORT 0x01
#define HID_SET_REPORT 0x09
#define KIND_INPUT     1
#define KIND_FEATURE   3

static bool get_report(pair_t *p, uint8_t kind, uint8_t id, uint16_t wlength)
{
    uint8_t s[8], rep[PROTO_HID_REPORT] = {0};
    char what[64];
    if (p->bad)
        return false;
    p->steps++;
    snprintf(what, sizeof what, "GET_REPORT(%s %u, %u bytes)", kind == KIND_INPUT ? "input" :
             "feature", id, wlength);
    setup_of(s, 0xA1, HID_GET_REPORT, (uint16_t)(kind << 8 | id), PROTO_IF_HID, wlength);
    if (!sim_ok(p, fx2_control(&p->f, s, NULL, 0)))
        return false;
    /* usb.c: features, and the COUNTERS input report; else a STALL */
    uint8_t n = 0;
    if (kind == KIND_FEATURE || (kind == KIND_INPUT && id == PROTO_HID_COUNTERS)) {
        rep[0] = id;
        n = fw_hid_get(&p->r.core, rep);
    }
    return control_check(p, what, rep, n, wlength, n == 0);
}

static bool set_report(pair_t *p, uint8_t id, const uint8_t *rep, uint8_t len)
{
    uint8_t s[8];
    char what[64];
    if (p->bad)
        return false;
    p->steps++;
    snprintf(what, sizeof what, "SET_REPORT(feature %u, %u bytes)", id, len);
    setup_of(s, 0x21, HID_SET_REPORT, (uint16_t)(KIND_FEATURE << 8 | id), PROTO_IF_HID, len);
    if (!sim_ok(p, fx2_control(&p->f, s, rep, len)))
        return false;
    /* usb.c: the data's ID must be the request's */
    bool ok = len && rep[0] == id && fw_hid_set(&p->r.core, rep, len) == 0;
    return control_check(p, what, NULL, 0, 0, !ok);
}

static bool set_hid(pair_t *p, uint8_t id, uint8_t v)
{
    uint8_t rep[PROTO_HID_REPORT] = {id, v};
    return set_report(p, id, rep, PROTO_HID_REPORT);
}

/* A record from the FPGA on EP8 (main.c, poll_ep8). */
static bool record(pair_t *p, const uint8_t *d, uint16_t n)
{
    if (p->bad)
        return false;
    p->steps++;
    if (!sim_ok(p, fx2_record(&p->f, d, n)))
        return false;
    if (!p->f.ep8_taken)
        return failf(p, "the firmware did not hand EP8 back (INPKTEND)");
    if (n == PROTO_RESULT_BYTES) {
        fw_result r = {rd32(d), rd32(d + 4), rd32(d + 8), rd32(d + 12), rd32(d + 16)};
        fw_frame_done(&p->r.core, &r);
    } else {
        fw_vp_error(&p->r.core, n == 4 ? rd32(d) : 0xFFFFFFFFu);
    }
    return compare(p);
}

static bool result(pair_t *p, uint32_t frame, uint32_t crc)
{
    uint8_t b[PROTO_RESULT_BYTES];
    le32(b, frame);
    le32(b + 4, crc);
    le32(b + 8, 100000u + frame);
    le32(b + 12, 0);
    le32(b + 16, 7u * frame);
    return record(p, b, sizeof b);
}

/* A new USB frame number: a COUNTERS input report when HID_PERIOD frames
 * have passed and the counters changed (main.c, poll_hid). */
static bool usb_frame(pair_t *p, uint16_t frame)
{
    if (p->bad)
        return false;
    p->steps++;
    if (!sim_ok(p, fx2_frame(&p->f, frame)))
        return false;
    fx2_queue exp = {.n = 0};
    ref_t *r = &p->r;
    frame &= 0x7FFu;
    if (((frame - r->hid_frame) & 0x7FFu) >= HID_PERIOD) {
        uint8_t rep[PROTO_HID_REPORT] = {PROTO_HID_COUNTERS};
        fw_hid_get(&r->core, rep);
        r->hid_frame = frame;
        uint32_t sum = ref_crc32(rep, sizeof rep);
        if (sum != r->hid_sum) {
            r->hid_sum = sum;
            memcpy(exp.pkt[0].data, rep, sizeof rep);
            exp.pkt[0].len = sizeof rep;
            exp.n = 1;
        }
    }
    if (!same_queue(p, "HID input report", &p->f.ep1, &exp))
        return false;
    p->f.ep1.n = 0;
    return compare(p);
}

static bool enumerate(pair_t *p)
{
    uint8_t s[8];
    setup_of(s, 0x00, 0x09, 1, 0, 0);   /* SET_CONFIGURATION 1 */
    p->steps++;
    if (!sim_ok(p, fx2_control(&p->f, s, NULL, 0)))
        return false;
    return control_check(p, "SET_CONFIGURATION", NULL, 0, 0, false);
}

/* ---- the scenarios ---- */

/* Enumeration: bulk data waits until the device is configured; standard
 * requests answer with the descriptors of descriptors.c. */
static bool sc_enumeration(pair_t *p)
{
    uint8_t b[64], s[8];
    size_t n = enc(b, PROTO_T_RESET, 0, NULL, 0);
    p->steps++;
    if (!sim_ok(p, fx2_bulk_out(&p->f, b, (uint16_t)n)))
        return false;
    if (p->f.ep2_taken || p->f.in.n)
        return failf(p, "an unconfigured device took bulk data");
    /* configured, it reads the waiting packet in the same turn */
    setup_of(s, 0x00, 0x09, 1, 0, 0);   /* SET_CONFIGURATION 1 */
    p->steps++;
    if (!sim_ok(p, fx2_control(&p->f, s, NULL, 0)))
        return false;
    if (!p->f.ep2_taken)
        return failf(p, "the configured device did not take the waiting packet");
    fw_rx(&p->r.core, b, (uint16_t)n);
    if (!control_check(p, "SET_CONFIGURATION", NULL, 0, 0, false))
        return false;
    static const struct {
        const char *what;
        uint16_t value, length;
        const uint8_t *want;
        unsigned len;
    } d[] = {
        {"GET_DESCRIPTOR(device)", 0x0100, 64, desc_device, DESC_DEVICE_LEN},
        {"GET_DESCRIPTOR(device, 8 bytes)", 0x0100, 8, desc_device, DESC_DEVICE_LEN},
        {"GET_DESCRIPTOR(configuration)", 0x0200, 255, desc_config_hs, DESC_CONFIG_LEN},
        {"GET_DESCRIPTOR(qualifier)", 0x0600, 10, desc_qualifier, DESC_QUALIFIER_LEN},
        {"GET_DESCRIPTOR(HID report)", 0x2200, 255, desc_hid_report, DESC_HID_REPORT_LEN},
    };
    for (size_t i = 0; i < sizeof d / sizeof d[0]; i++) {
        setup_of(s, i == 4 ? 0x81 : 0x80, 0x06, d[i].value, 0, d[i].length);
        p->steps++;
        if (!sim_ok(p, fx2_control(&p->f, s, NULL, 0)) ||
            !control_check(p, d[i].what, d[i].want, d[i].len, d[i].length, false))
            return false;
    }
    /* the serial number string: the board's serial in hex, UTF-16LE */
    char hex[9];
    snprintf(hex, sizeof hex, "%08X", BOARD_SERIAL);
    b[0] = 2 + 16;
    b[1] = 3;
    for (int i = 0; i < 8; i++) {
        b[2 + 2 * i] = (uint8_t)hex[i];
        b[3 + 2 * i] = 0;
    }
    setup_of(s, 0x80, 0x06, 0x0303, 0x0409, 255);
    p->steps++;
    if (!sim_ok(p, fx2_control(&p->f, s, NULL, 0)) ||
        !control_check(p, "GET_DESCRIPTOR(string 3)", b, b[0], 255, false))
        return false;
    setup_of(s, 0x80, 0x06, 0x0304, 0x0409, 255);   /* no string 4 */
    p->steps++;
    return sim_ok(p, fx2_control(&p->f, s, NULL, 0)) &&
           control_check(p, "GET_DESCRIPTOR(string 4)", NULL, 0, 255, true);
}

/* RESET, WORDS of several lengths (up to the full 492), PING. */
static bool sc_reset_words(pair_t *p)
{
    if (!enumerate(p))
        return false;
    p->seq = 0;
    if (!pkt(p, PROTO_T_RESET, NULL, 0))
        return false;
    static const size_t lens[] = {1, 2, 3, 17, 64, 100, BOARD_PAYLOAD / 4, 0, 5};
    for (size_t i = 0; i < sizeof lens / sizeof lens[0]; i++)
        if (!words(p, lens[i], 0x10203040u + (uint32_t)i))
            return false;
    if (!pkt(p, PROTO_T_PING, NULL, 0))
        return false;
    /* a second RESET in the middle of the numbering restarts it */
    p->seq = 1000;
    return pkt(p, PROTO_T_RESET, NULL, 0) && words(p, 9, 0xCAFE0000u) &&
           pkt(p, PROTO_T_PING, NULL, 0);
}

/* Enough words to fill EP4's two buffers many times over: the buffer
 * commits, the wait for the FPGA and EP4's reset between them. */
static bool sc_many_words(pair_t *p)
{
    if (!enumerate(p))
        return false;
    p->seq = 0;
    if (!pkt(p, PROTO_T_RESET, NULL, 0))
        return false;
    for (uint32_t i = 0; i < 12; i++)
        if (!words(p, BOARD_PAYLOAD / 4 - (i % 3), 0x01000000u * i))
            return false;
    return pkt(p, PROTO_T_PING, NULL, 0);
}

/* The refusals: before RESET, bad lengths, unknown types, READBACK and
 * TILE (the FX2 has neither), sequence gaps, duplicates, RESUME. */
static bool sc_errors(pair_t *p)
{
    uint8_t b[16] = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16};
    if (!enumerate(p))
        return false;
    p->seq = 5;
    if (!words(p, 3, 1) || !pkt(p, PROTO_T_PING, NULL, 0))   /* before any RESET: MODE */
        return false;
    p->seq = 0;
    if (!pkt(p, PROTO_T_RESET, b, 4))                         /* RESET with payload */
        return false;
    p->seq = 0;
    if (!pkt(p, PROTO_T_RESET, NULL, 0) || !pkt(p, 0x55, b, 8) ||      /* unknown type */
        !pkt(p, PROTO_T_WORDS, b, 6) ||                                /* not whole words */
        !pkt(p, PROTO_T_PING, b, 1) ||                                 /* PING with payload */
        !pkt_u32(p, PROTO_T_READBACK, 0) ||                            /* not on the FX2 */
        !pkt(p, PROTO_T_TILE, b, 15) ||                                /* words mode */
        !pkt(p, PROTO_T_QUERY, b, 3) || !pkt(p, PROTO_T_RESUME, b, 5))  /* bad lengths */
        return false;
    if (!words(p, 4, 0x11111111u))
        return false;
    p->seq += 3;   /* three packets lost: a gap, the error state */
    if (!words(p, 4, 0x22222222u) || !words(p, 4, 0x33333333u))
        return false;
    p->seq -= 2;   /* an old number again: a duplicate */
    if (!words(p, 2, 0x44444444u))
        return false;
    p->seq += 2;
    /* RESUME frame 7: words dropped up to its FRAME word */
    uint8_t w[40];
    words_of(w, 10, 0x55555555u);
    le32(w + 12, 0xF0000007u);
    if (!pkt_u32(p, PROTO_T_RESUME, 7) || !pkt(p, PROTO_T_WORDS, w, 12) ||
        !pkt(p, PROTO_T_WORDS, w, 40) || !words(p, 3, 0x66666666u))
        return false;
    /* WORDS and a RESUME in one USB packet: the restart empties EP4, so
     * those words never reach the FPGA (main.c; the reference knows) */
    uint8_t two[128];
    size_t k = enc(two, PROTO_T_WORDS, p->seq++, w, 40);
    k += enc(two + k, PROTO_T_RESUME, p->seq++, w + 12, 4);
    if (!usb(p, two, (uint16_t)k) || !pkt(p, PROTO_T_WORDS, w + 12, 28))
        return false;
    /* HID MODE idle: WORDS refused; back to words mode */
    if (!set_hid(p, PROTO_HID_MODE, PROTO_MODE_IDLE) || !words(p, 2, 0x77777777u) ||
        !set_hid(p, PROTO_HID_MODE, PROTO_MODE_WORDS) || !words(p, 2, 0x88888888u))
        return false;
    return pkt(p, PROTO_T_PING, NULL, 0) && get_report(p, KIND_FEATURE, PROTO_HID_LASTERR, 64);
}

/* RESULT and ERROR records from the FPGA, the result memory and QUERY. */
static bool sc_results(pair_t *p)
{
    if (!enumerate(p))
        return false;
    p->seq = 0;
    if (!pkt(p, PROTO_T_QUERY, NULL, 0) || !pkt(p, PROTO_T_RESET, NULL, 0) ||
        !pkt_u32(p, PROTO_T_QUERY, 0))   /* nothing kept yet */
        return false;
    for (uint32_t fr = 0; fr < 20; fr++)   /* more than the 16 kept */
        if (!result(p, fr, 0xC0DE0000u + fr * 0x1111u))
            return false;
    static const uint32_t ask[] = {19, 4, 3, 0, 18, 20, 0xFFFFFFFFu};
    for (size_t i = 0; i < sizeof ask / sizeof ask[0]; i++)
        if (!pkt_u32(p, PROTO_T_QUERY, ask[i]))
            return false;
    uint8_t e[7] = {0x34, 0x12, 0, 0, 9, 9, 9};
    if (!record(p, e, 4) || !words(p, 2, 1) ||   /* a stream error: error state */
        !pkt_u32(p, PROTO_T_RESUME, 21) || !record(p, e, 7) ||   /* an unknown record */
        !pkt_u32(p, PROTO_T_RESUME, 21))
        return false;
    return result(p, 21, 0xABCDEF01u) && pkt_u32(p, PROTO_T_QUERY, 21) &&
           pkt(p, PROTO_T_PING, NULL, 0);
}

/* Bad CRCs, corrupted headers and lengths: resynchronisation. */
static bool sc_crc(pair_t *p)
{
    uint8_t b[600], w[64];
    if (!enumerate(p))
        return false;
    p->seq = 0;
    if (!pkt(p, PROTO_T_RESET, NULL, 0))
        return false;
    words_of(w, 16, 0x01020304u);
    for (unsigned at = 0; at < 84; at += 7) {   /* a flipped bit anywhere: header, payload, CRC */
        size_t n = enc(b, PROTO_T_WORDS, p->seq, w, 64);
        b[at] ^= (uint8_t)(1u << (at % 8));
        if (!transfer(p, b, n))
            return false;
        if (!words(p, 16, 0x0A0B0C0Du + at))   /* the next one is good (a gap first) */
            return false;
        if (!pkt_u32(p, PROTO_T_RESUME, 0))
            return false;
    }
    /* a length above the payload limit: garbage, no ERROR, then a gap */
    size_t n = enc(b, PROTO_T_WORDS, p->seq++, w, 8);
    le32(b + PROTO_OFF_LEN, BOARD_PAYLOAD + 4);
    if (!transfer(p, b, n) || !words(p, 2, 5))
        return false;
    /* nonzero reserved bytes */
    n = enc(b, PROTO_T_PING, p->seq++, NULL, 0);
    b[PROTO_OFF_RSVD] = 1;
    if (!transfer(p, b, n) || !pkt(p, PROTO_T_PING, NULL, 0))
        return false;
    return get_report(p, KIND_FEATURE, PROTO_HID_COUNTERS, 64);
}

/* Garbage between packets, magic look-alikes, packets split over USB
 * packets at every kind of boundary (the reassembly buffer), several in
 * one USB packet, full-size packets with their zero-length packets. */
static bool sc_resync(pair_t *p)
{
    static uint8_t s[8192];
    uint8_t w[BOARD_PAYLOAD];
    size_t n = 0;
    if (!enumerate(p))
        return false;
    p->seq = 0;
    n += enc(s + n, PROTO_T_RESET, p->seq++, NULL, 0);
    memcpy(s + n, "xyzALBALB", 9);   /* garbage with partial magics */
    n += 9;
    words_of(w, 10, 0x99887766u);
    n += enc(s + n, PROTO_T_WORDS, p->seq++, w, 40);
    memcpy(s + n, "AL", 2);
    n += 2;
    n += enc(s + n, PROTO_T_PING, p->seq++, NULL, 0);
    memcpy(s + n, "ALB1", 4);   /* a magic followed by nonsense */
    n += 4;
    memset(s + n, 0xFF, 12);
    n += 12;
    words_of(w, BOARD_PAYLOAD / 4, 0x10000000u);
    n += enc(s + n, PROTO_T_WORDS, p->seq++, w, BOARD_PAYLOAD);
    for (int i = 0; i < 4; i++)
        n += enc(s + n, PROTO_T_WORDS, p->seq++, w + 16 * i, 4u * (7u + (unsigned)i));
    n += enc(s + n, PROTO_T_PING, p->seq++, NULL, 0);
    static const uint16_t cuts1[] = {512, 3, 1, 17, 200, 511, 2};
    if (!cut(p, s, n, cuts1, sizeof cuts1 / sizeof cuts1[0]))
        return false;
    /* the same stream, byte by byte over the first packets */
    static const uint16_t cuts2[] = {1};
    size_t first = n < 120 ? n : 120;
    p->seq = 0;
    if (!cut(p, s, first, cuts2, 1))
        return false;
    static const uint16_t cuts3[] = {64, 100, 512};
    if (!cut(p, s + first, n - first, cuts3, 3))
        return false;
    /* full-size packets each in its own transfer: 512 bytes and a ZLP */
    for (int i = 0; i < 3; i++)
        if (!pkt(p, PROTO_T_WORDS, w, BOARD_PAYLOAD))
            return false;
    return get_report(p, KIND_FEATURE, PROTO_HID_COUNTERS, 64);
}

/* The HID reports: INFO, MODE, COUNTERS (feature and input, on EP0 and
 * EP1), LAST ERROR, RESET; lengths cut short and asked too long. */
static bool sc_hid(pair_t *p)
{
    uint8_t rep[PROTO_HID_REPORT] = {0};
    if (!enumerate(p))
        return false;
    static const uint16_t lens[] = {64, 65, 8, 1};
    for (size_t i = 0; i < sizeof lens / sizeof lens[0]; i++)
        if (!get_report(p, KIND_FEATURE, PROTO_HID_INFO, lens[i]))
            return false;
    if (!get_report(p, KIND_FEATURE, PROTO_HID_MODE, 64) ||
        !get_report(p, KIND_FEATURE, PROTO_HID_COUNTERS, 64) ||
        !get_report(p, KIND_INPUT, PROTO_HID_COUNTERS, 64) ||
        !get_report(p, KIND_INPUT, PROTO_HID_INFO, 64) ||   /* not an input report */
        !get_report(p, KIND_FEATURE, PROTO_HID_LASTERR, 64) ||
        !get_report(p, KIND_FEATURE, PROTO_HID_RESET, 64) ||   /* SET only */
        !get_report(p, KIND_FEATURE, 9, 64))
        return false;
    /* MODE: idle, tiles (no display: refused), 3 (no such mode) */
    if (!set_hid(p, PROTO_HID_MODE, PROTO_MODE_IDLE) ||
        !get_report(p, KIND_FEATURE, PROTO_HID_MODE, 64) ||
        !set_hid(p, PROTO_HID_MODE, PROTO_MODE_TILES) || !set_hid(p, PROTO_HID_MODE, 3) ||
        !set_hid(p, PROTO_HID_MODE, PROTO_MODE_WORDS) ||
        !get_report(p, KIND_FEATURE, PROTO_HID_INFO, 64))
        return false;
    /* some traffic, then RESET through HID: link, counters, both, nonsense */
    p->seq = 0;
    if (!pkt(p, PROTO_T_RESET, NULL, 0) || !words(p, 3, 1) || !pkt(p, PROTO_T_PING, NULL, 0))
        return false;
    /* a half-received packet, then RESET link: its bytes count as garbage */
    uint8_t b[64], w[40];
    words_of(w, 10, 0xA5A5A5A5u);
    size_t n = enc(b, PROTO_T_WORDS, p->seq, w, 40);
    if (!usb(p, b, (uint16_t)(n / 2)) || !set_hid(p, PROTO_HID_RESET, PROTO_RESET_LINK))
        return false;
    p->seq = 0;
    if (!words(p, 2, 3) || !get_report(p, KIND_FEATURE, PROTO_HID_COUNTERS, 64) ||
        !set_hid(p, PROTO_HID_RESET, PROTO_RESET_COUNTERS) ||
        !get_report(p, KIND_FEATURE, PROTO_HID_COUNTERS, 64) ||
        !set_hid(p, PROTO_HID_RESET, PROTO_RESET_ALL) || !set_hid(p, PROTO_HID_RESET, 0) ||
        !set_hid(p, PROTO_HID_RESET, 4) || !set_hid(p, 9, 1))
        return false;
    /* a SET_REPORT whose data carries another ID than the request; a short one */
    rep[0] = PROTO_HID_MODE;
    rep[1] = PROTO_MODE_IDLE;
    if (!set_report(p, PROTO_HID_RESET, rep, 64) || !set_report(p, PROTO_HID_MODE, rep, 1))
        return false;
    /* COUNTERS input reports on EP1 as USB frames pass */
    p->seq = 0;
    if (!pkt(p, PROTO_T_RESET, NULL, 0) || !usb_frame(p, 50) || !usb_frame(p, 100) ||
        !usb_frame(p, 150) || !usb_frame(p, 200) || !words(p, 2, 9) || !usb_frame(p, 250) ||
        !usb_frame(p, 300) || !usb_frame(p, 2040) || !words(p, 1, 9) || !usb_frame(p, 91))
        return false;
    return true;
}

/* Seeded random traffic: good packets of every type, corrupted ones,
 * garbage, cut at random; HID reports and FPGA records in between. */
static bool sc_random(pair_t *p)
{
    static uint8_t s[8192];
    uint8_t pay[BOARD_PAYLOAD + 8];
    if (!enumerate(p))
        return false;
    p->seq = 0;
    for (int round = 0; round < 3 && !p->bad; round++) {
        size_t n = 0;
        while (n < sizeof s - 1024) {
            uint64_t r = t_rand(&p->rng);
            unsigned kind = (unsigned)(r % 16);
            uint32_t len = (uint32_t)((r >> 8) % (BOARD_PAYLOAD / 4 + 1)) * 4;
            for (uint32_t i = 0; i < len; i++)
                pay[i] = (uint8_t)t_rand(&p->rng);
            if (kind < 8) {
                n += enc(s + n, PROTO_T_WORDS, p->seq++, pay, len);
            } else if (kind == 8) {
                n += enc(s + n, PROTO_T_RESET, p->seq++, NULL, 0);
            } else if (kind == 9) {
                n += enc(s + n, PROTO_T_PING, p->seq++, NULL, 0);
            } else if (kind == 10) {
                n += enc(s + n, PROTO_T_QUERY, p->seq++, pay, 4);
            } else if (kind == 11) {
                le32(pay, (uint32_t)(r >> 40) & 0xFFu);
                n += enc(s + n, PROTO_T_RESUME, p->seq++, pay, 4);
            } else if (kind == 12) {   /* corrupted */
                size_t k = enc(s + n, PROTO_T_WORDS, p->seq++, pay, len);
                s[n + (r >> 32) % k] ^= (uint8_t)(1u << ((r >> 20) % 8));
                n += k;
            } else if (kind == 13) {   /* garbage, sometimes magic-like */
                size_t k = 1 + (r >> 24) % 40;
                for (size_t i = 0; i < k; i++)
                    s[n + i] = (r >> 60) & 1 ? "ALB1"[i % 4] : (uint8_t)t_rand(&p->rng);
                n += k;
            } else if (kind == 14) {   /* numbering skips or repeats */
                p->seq += (uint32_t)((r >> 16) % 5) - 2;
            } else {
                n += enc(s + n, (uint8_t)(r >> 48), p->seq++, pay, len & 0x3Fu);
            }
        }
        size_t off = 0;
        while (off < n && !p->bad) {
            uint16_t k = (uint16_t)(1 + t_rand(&p->rng) % PROTO_BULK_MAXPKT);
            if (k > n - off)
                k = (uint16_t)(n - off);
            usb(p, s + off, k);
            off += k;
            uint64_t r = t_rand(&p->rng);
            if (r % 23 == 0)
                get_report(p, KIND_FEATURE, (uint8_t)(1 + (r >> 8) % 5), 64);
            else if (r % 29 == 0)
                result(p, (uint32_t)(r >> 16) & 0xFFu, (uint32_t)(r >> 32));
        }
        pkt(p, PROTO_T_PING, NULL, 0);
    }
    return !p->bad;
}

/* A standard or class request answered by usb.c alone: its data stage
 * and STALL against USB 2.0 chapter 9 (and HID 1.11 §7.2 for the idle rate). */
static bool request(pair_t *p, const char *what, uint8_t rt, uint8_t req, uint16_t value,
                    uint16_t index, uint16_t length, const uint8_t *want, unsigned want_len,
                    bool stall)
{
    uint8_t s[8];
    if (p->bad)
        return false;
    p->steps++;
    setup_of(s, rt, req, value, index, length);
    return sim_ok(p, fx2_control(&p->f, s, NULL, 0)) &&
           control_check(p, what, want, want_len, length, stall);
}

/* A register of the chip after a request. */
static bool reg_is(pair_t *p, const char *name, unsigned addr, uint8_t mask, uint8_t want)
{
    uint8_t v;
    if (!sim_ok(p, fx2_peek(&p->f, addr, &v, 1)))
        return false;
    return (v & mask) == want ? true : failf(p, "%s & 0x%02x is 0x%02x, expected 0x%02x", name,
                                             mask, v & mask, want);
}

#define EP2CS   0xE6A3u
#define EP6CS   0xE6A5u
#define TOGCTL  0xE683u
#define GET_STATUS 0x00
#define CLEAR_FEATURE 0x01
#define SET_FEATURE 0x03
#define ENDPOINT_HALT 0

/* Chapter 9 beyond the descriptors: status, configuration and interface,
 * endpoint halt and its data toggle, HID idle, a bus reset. */
static bool sc_standard(pair_t *p)
{
    static const uint8_t zero2[2] = {0, 0}, halted[2] = {1, 0}, self_powered[2] = {1, 0},
                         one = 1, none = 0, idle = 0x10;
    if (!enumerate(p) ||
        !request(p, "GET_STATUS(device)", 0x80, GET_STATUS, 0, 0, 2, self_powered, 2, false) ||
        !request(p, "GET_CONFIGURATION", 0x80, 0x08, 0, 0, 1, &one, 1, false) ||
        !request(p, "GET_INTERFACE(0)", 0x81, 0x0A, 0, 0, 1, &none, 1, false) ||
        !request(p, "SET_INTERFACE(0, alt 1)", 0x01, 0x0B, 1, 0, 0, NULL, 0, true) ||
        !request(p, "SET_INTERFACE(0, alt 0)", 0x01, 0x0B, 0, 0, 0, NULL, 0, false) ||
        !request(p, "SET_CONFIGURATION(2)", 0x00, 0x09, 2, 0, 0, NULL, 0, true) ||
        !request(p, "a vendor request", 0xC0, 0x42, 0, 0, 4, NULL, 0, true))
        return false;
    /* halt: set by the host, seen in GET_STATUS and EPxCS, cleared with the
     * data toggle reset (TOGCTL: endpoint in bits 3..0, IN in bit 4, R 5) */
    static const struct {
        uint8_t ep;
        unsigned cs;
        uint8_t toggle;
    } ep[] = {{PROTO_EP_OUT, EP2CS, 0x22}, {PROTO_EP_IN, EP6CS, 0x36}};
    for (size_t i = 0; i < 2; i++) {
        if (!request(p, "GET_STATUS(endpoint)", 0x82, GET_STATUS, 0, ep[i].ep, 2, zero2, 2, false) ||
            !request(p, "SET_FEATURE(ENDPOINT_HALT)", 0x02, SET_FEATURE, ENDPOINT_HALT, ep[i].ep, 0,
                     NULL, 0, false) ||
            !reg_is(p, "EPxCS after SET_FEATURE(HALT)", ep[i].cs, 0x01, 0x01) ||
            !request(p, "GET_STATUS(halted endpoint)", 0x82, GET_STATUS, 0, ep[i].ep, 2, halted, 2,
                     false) ||
            !request(p, "CLEAR_FEATURE(ENDPOINT_HALT)", 0x02, CLEAR_FEATURE, ENDPOINT_HALT, ep[i].ep,
                     0, NULL, 0, false) ||
            !reg_is(p, "EPxCS after CLEAR_FEATURE(HALT)", ep[i].cs, 0x01, 0x00) ||
            !reg_is(p, "TOGCTL after CLEAR_FEATURE(HALT)", TOGCTL, 0xFF, ep[i].toggle))
            return false;
    }
    if (!request(p, "GET_STATUS(endpoint 0x04)", 0x82, GET_STATUS, 0, 0x04, 2, NULL, 0, true) ||
        !request(p, "SET_IDLE(16 ms x 4)", 0x21, 0x0A, (uint16_t)(idle << 8), PROTO_IF_HID, 0, NULL,
                 0, false) ||
        !request(p, "GET_IDLE", 0xA1, 0x02, 0, PROTO_IF_HID, 1, &idle, 1, false))
        return false;
    /* a bus reset unconfigures: bulk data waits for SET_CONFIGURATION again */
    p->steps++;
    if (!sim_ok(p, fx2_bus_reset(&p->f)) ||
        !request(p, "GET_CONFIGURATION after a bus reset", 0x80, 0x08, 0, 0, 1, &none, 1, false))
        return false;
    uint8_t b[32];
    size_t n = enc(b, PROTO_T_RESET, 0, NULL, 0);
    p->seq = 1;
    p->steps++;
    if (!sim_ok(p, fx2_bulk_out(&p->f, b, (uint16_t)n)))
        return false;
    if (p->f.ep2_taken)
        return failf(p, "the device took bulk data after a bus reset, unconfigured");
    fw_rx(&p->r.core, b, (uint16_t)n);   /* it will, once configured */
    return request(p, "SET_CONFIGURATION(1)", 0x00, 0x09, 1, 0, 0, NULL, 0, false) &&
           (p->f.ep2_taken || failf(p, "the packet still waits after SET_CONFIGURATION")) &&
           pkt(p, PROTO_T_PING, NULL, 0);
}

typedef struct {
    const char *name;
    bool (*run)(pair_t *p);
} scenario;

static const scenario scenarios[] = {
    {"enumeration", sc_enumeration}, {"standard-requests", sc_standard},
    {"reset-words", sc_reset_words},
    {"many-words", sc_many_words},   {"errors", sc_errors},
    {"results-query", sc_results},   {"crc", sc_crc},
    {"resync", sc_resync},           {"hid", sc_hid},
    {"random", sc_random},
};

/* The planted bugs: a byte of the image changed in the simulator's code
 * memory, which the comparison must notice. */
static int plant(fx2_t *f)
{
    if (!g_plant)
        return 0;
    const char *label = g_plant == 1 ? "_crc_lane" : "_magic";
    long a = listing_addr(&g_lst, label);
    if (a < 0) {
        fprintf(stderr, "fx2_s51: the listings have no %s\n", label);
        return -1;
    }
    /* crc_lane[1][0x5A] (an entry of lane 1, used for one byte value in 256),
     * or the magic's third byte 'B' */
    unsigned at = g_plant == 1 ? (unsigned)a + 256 + 0x5A : (unsigned)a + 2;
    uint8_t v = g_lst.rom[at] ^ (g_plant == 1 ? 0x10 : 0x01);
    if (g_verbose)
        fprintf(stderr, "planted: code[0x%04x] %02x -> %02x (%s)\n", at, g_lst.rom[at], v, label);
    return fx2_patch_rom(f, at, v);
}

/* One scenario on a fresh image on `cpu`; with `reads`, s51's code-fetch
 * counts of the whole session at its end; with `clocks`, its clocks, and
 * no line of its own. */
static bool run_one(size_t i, const char *cpu, uint64_t *reads, uint64_t *clocks)
{
    static pair_t p;
    const scenario *sc = &scenarios[i];
    memset(&p, 0, sizeof p);
    p.rng = 0x9E3779B97F4A7C15ull + i;
    ref_init(&p.r);
    bool ok = false;
    if (fx2_open(&p.f, cpu, g_image, &g_lst, g_preload)) {
        printf("FAIL %s: %s\n", sc->name, p.f.error);
    } else if (plant(&p.f) == 0 && sc->run(&p) && !p.bad &&
               (fx2_check_buffers(&p.f) == 0 || failf(&p, "%s", p.f.error)) &&
               (!reads || s51_rom_reads(&p.f.s, 0, g_lst.code_end - 1, reads) == 0 ||
                failf(&p, "%s", p.f.s.error))) {
        if (!clocks)
            printf("ok   %s: %u inputs, %lu copies, %.2f M cycles of 12 clocks\n", sc->name,
                   p.steps, p.f.xcopies, (double)p.f.clocks / 12e6);
        if (clocks)
            *clocks = p.f.clocks;
        ok = true;
    } else {
        printf("FAIL %s%s%s: %s\n", sc->name, clocks ? " on -t " : "", clocks ? cpu : "",
               p.bad ? p.why : "set-up failed");
    }
    fx2_close(&p.f);
    free(p.r.words);
    return ok;
}

/* make firmware-speed's counting, on one scenario: the classic cycles of
 * the instructions s51 ran (its code-fetch counts at the listings'
 * instruction starts, i8051.c's table) must be its clock count exactly,
 * and their FX2 cycles within 0.1% of its Dallas core's count. */
static bool cycle_counts(void)
{
    size_t i = 3;   /* many-words */
    uint64_t *reads = calloc(g_lst.code_end, sizeof *reads), clocks = 0, dallas = 0;
    bool ok = reads && run_one(i, "C52", reads, &clocks) && run_one(i, "DS320", NULL, &dallas);
    uint64_t classic = 0, fx2 = 0;
    for (unsigned a = 0; ok && a < g_lst.code_end; a++)
        if (g_lst.insn[a]) {
            classic += reads[a] * i8051_opcode(g_lst.rom[a]).classic;
            fx2 += reads[a] * i8051_fx2_cycles(g_lst.rom[a], 1);
        }
    free(reads);
    if (!ok)
        return false;
    double off = 100.0 * ((double)dallas / 4 - (double)fx2) / (double)fx2;
    bool good = classic * 12 == clocks && off > -0.1 && off < 0.1;
    printf("%s cycle-counts: %s: %llu classic cycles counted, s51 -t C52 %llu clocks / 12 = %llu;"
           " %llu FX2 cycles, s51 -t DS320 %.0f (%+.3f%%)\n", good ? "ok  " : "FAIL",
           scenarios[i].name, (unsigned long long)classic, (unsigned long long)clocks,
           (unsigned long long)clocks / 12, (unsigned long long)fx2, (double)dallas / 4, off);
    return good;
}

static int run_check(const char *only)
{
    int pass = 0, failed = 0;
    for (size_t i = 0; i < sizeof scenarios / sizeof scenarios[0]; i++) {
        if (only && strcmp(only, scenarios[i].name))
            continue;
        if (run_one(i, g_cpu, NULL, NULL))
            pass++;
        else
            failed++;
    }
    if (!g_plant && (!only || !strcmp(only, "cycle-counts"))) {
        if (cycle_counts())
            pass++;
        else
            failed++;
    }
    printf("%d passed, %d failed\n", pass, failed);
    return failed ? 1 : 0;
}

/* sdas's cycle column against i8051.c's classic cycles, every instruction
 * of the listings; and every opcode's length against the image. */
static int run_opcodes(void)
{
    unsigned listed = 0, wrong = 0;
    for (unsigned a = 0; a < LISTING_CODE; a++) {
        if (!g_lst.listed[a])
            continue;
        listed++;
        i8051_op o = i8051_opcode(g_lst.rom[a]);
        if (o.classic != g_lst.listed[a] || !g_lst.insn[a]) {
            if (wrong++ < 10)
                printf("0x%04x: opcode 0x%02x: %u cycles here, sdas lists %u\n", a, g_lst.rom[a],
                       o.classic, g_lst.listed[a]);
        }
    }
    /* lengths: each listed instruction is followed by the next one listed
     * or by data or a label's end; check where two listed ones abut */
    unsigned lens = 0;
    for (unsigned a = 0; a + 3 < LISTING_CODE; a++) {
        if (!g_lst.listed[a])
            continue;
        i8051_op o = i8051_opcode(g_lst.rom[a]);
        unsigned next = a + 1;
        while (next < a + 4 && !g_lst.listed[next] && !g_lst.insn[next])
            next++;
        if (next < a + 4 && g_lst.listed[next]) {
            lens++;
            if (next - a != o.len && wrong++ < 10)
                printf("0x%04x: opcode 0x%02x is %u bytes here, %u in the listing\n", a,
                       g_lst.rom[a], o.len, next - a);
        }
    }
    printf("%u listed instructions, %u lengths checked, %u disagreements\n", listed, lens, wrong);
    printf("%d passed, %d failed\n", wrong ? 0 : 1, wrong ? 1 : 0);
    return wrong ? 1 : 0;
}

static int usage(void)
{
    fprintf(stderr,
            "usage: fx2_s51 check IMAGE.ihx [--cpu TYPE] [--plant crc|magic] [--only NAME] [-v]\n"
            "       fx2_s51 speed IMAGE.ihx STREAM [--fps N] [--profile]\n"
            "       fx2_s51 opcodes IMAGE.ihx\n"
            "IMAGE's directory holds the listings (*.rst) and the .map; TYPE is an s51 CPU\n"
            "(C52: the classic 12-clock core; DS320: Dallas's 4-clock core, the FX2's kind)\n");
    return 2;
}

int main(int argc, char **argv)
{
    if (argc < 3)
        return usage();
    const char *cmd = argv[1], *only = NULL, *stream = NULL;
    speed_opts so = {50, false};
    g_image = argv[2];
    int i = 3;
    if (!strcmp(cmd, "speed")) {
        if (argc < 4)
            return usage();
        stream = argv[3];
        i = 4;
    }
    for (; i < argc; i++) {
        if (!strcmp(argv[i], "--cpu") && i + 1 < argc)
            g_cpu = argv[++i];
        else if (!strcmp(argv[i], "--only") && i + 1 < argc)
            only = argv[++i];
        else if (!strcmp(argv[i], "--plant") && i + 1 < argc) {
            i++;
            g_plant = !strcmp(argv[i], "crc") ? 1 : !strcmp(argv[i], "magic") ? 2 : -1;
            if (g_plant < 0)
                return usage();
        } else if (!strcmp(argv[i], "--fps") && i + 1 < argc)
            so.fps = (unsigned)strtoul(argv[++i], NULL, 10);
        else if (!strcmp(argv[i], "--profile"))
            so.profile = true;
        else if (!strcmp(argv[i], "-v"))
            g_verbose = true;
        else
            return usage();
    }
    static char lib[4096];
    snprintf(lib, sizeof lib, "%s", argv[0]);
    char *end = strrchr(lib, '/');
    snprintf(end ? end + 1 : lib, sizeof lib - (size_t)(end ? end + 1 - lib : 0),
             "s51_fastpoll.so");
    if (access(lib, R_OK) == 0)
        g_preload = lib;
    else
        fprintf(stderr, "fx2_s51: no %s: s51 will answer each command ~100 ms late\n", lib);
    char dir[4096];
    snprintf(dir, sizeof dir, "%s", g_image);
    char *slash = strrchr(dir, '/');
    if (slash)
        *slash = 0;
    else
        strcpy(dir, ".");
    if (listing_load(&g_lst, g_image, dir)) {
        fprintf(stderr, "fx2_s51: %s\n", g_lst.error);
        return 2;
    }
    int rc;
    if (!strcmp(cmd, "check"))
        rc = run_check(only);
    else if (!strcmp(cmd, "opcodes"))
        rc = run_opcodes();
    else if (!strcmp(cmd, "speed") && so.fps)
        rc = speed_run(g_image, &g_lst, stream, g_preload, &so);
    else
        rc = usage();
    listing_free(&g_lst);
    return rc;
}
