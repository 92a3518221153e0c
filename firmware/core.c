/* core.c — the board side of the bridge (docs/usb-protocol.md): the bulk
 * packet parser with its resynchronisation, the link's sequence numbers and
 * error state, RESUME, the result memory, counters and the HID reports.
 * Portable C that sdcc compiles for the FX2's 8051 and gcc/clang for the
 * simulated board.  One caller at a time; a HAL callback may report the VP's
 * progress (fw_frame_done, fw_vp_error: a VP run inside vp_words finishes
 * frames there) but must not call fw_rx or the HID functions.
 *
 * Decisions the protocol document leaves open, all visible in the ERRORs:
 *
 *  - fw_init starts in PROTO_MODE_WORDS, the board's job, so a host only
 *    needs HID MODE for tiles or idle.
 *  - Before the first RESET (bulk, or HID RESET link) every packet but RESET
 *    is dropped with ERROR MODE: the board has no sequence number to check
 *    it against.  CRC errors are reported in any state.
 *  - The sequence check comes before the content check: a packet with the
 *    expected number advances rx_seq even when its content is then refused
 *    (BAD_TYPE, BAD_LENGTH, MODE), so one bad packet costs one ERROR and not
 *    also a gap.  After a gap the packet that revealed it is handled as usual
 *    under the error state (a WORDS is dropped, a RESUME leaves the state, a
 *    PING is answered).  Numbers compare in serial arithmetic (seq − rx_seq
 *    as a signed 32-bit distance), so the link survives wrap-around.
 *  - counters[DROPPED] counts every packet that passed the CRC and the
 *    duplicate check but was not acted on: before RESET, WORDS in the error
 *    state, and refused packets (BAD_TYPE, BAD_LENGTH, MODE).  So
 *    rx packets = acted on + duplicates + dropped.
 *  - A length above max_payload cannot be told from a corrupted length
 *    before the CRC: the candidate is rejected as garbage, without ERROR;
 *    the host hears of it through the SEQ_GAP of the next packet.
 *  - RESET also clears the result memory (frame numbers restart with a new
 *    stream) and restarts tx_seq at 0 (numbers run from 0 after RESET in
 *    both directions).  It needs an empty payload, else BAD_LENGTH and no
 *    reset.
 *  - QUERY of a frame not in the result memory: ERROR OVERFLOW, expected =
 *    the frame asked for, detail = the newest frame kept (0xFFFFFFFF if
 *    none), so the host can tell "not done yet" from "forgotten".  Frames
 *    compare on all 32 bits of the RESULT's frame field.
 *  - The error state holds back WORDS only; a TILE is self-contained.
 *  - HID MODE tiles is refused when the HAL has no tile callback.
 *
 * ERROR fields: seq = the offending packet's number (for STREAM: the last
 * packet accepted); expected = the number the board waits for as it sends
 * the ERROR (BAD_CRC, SEQ_GAP, DUPLICATE: the one it wanted instead; a
 * refused packet kept its place, so the one after it; QUERY: the frame asked
 * for); detail = BAD_CRC: the CRC the board computed; SEQ_GAP: packets missing;
 * DUPLICATE: how many numbers behind; BAD_TYPE: the type; BAD_LENGTH: the
 * payload length; MODE: mode << 8 | type; STREAM: the VP's word offset. */
#include "core.h"

#include <string.h>

/* sdcc (the FX2's 8051): the core, its buffer, the bytes given to fw_rx and
 * the reports and results handed over all live in external RAM (fx2/main.c
 * and fx2/usb.c put them there), and a pointer that says so is 2 bytes and
 * dereferences with one MOVX, where a generic pointer calls a library
 * routine for every byte: the difference between fitting the FX2's 16 KB or
 * not.  Elsewhere the qualifier is empty: core_t is fw_core, xbyte uint8_t. */
#ifdef __SDCC_mcs51
#define FW_XDATA __xdata
#else
#define FW_XDATA
#endif
typedef FW_XDATA fw_core core_t;
typedef FW_XDATA uint8_t xbyte;   /* a byte of packet, scratch or report memory */

/* counters[] follows the STATUS payload, one u32 per field */
#define CNT_RX       (PROTO_STATUS_RX_PACKETS / 4u)
#define CNT_CRC      (PROTO_STATUS_CRC_ERRORS / 4u)
#define CNT_GAPS     (PROTO_STATUS_SEQ_GAPS / 4u)
#define CNT_DUPS     (PROTO_STATUS_DUPLICATES / 4u)
#define CNT_GARBAGE  (PROTO_STATUS_GARBAGE / 4u)
#define CNT_FRAMES   (PROTO_STATUS_FRAMES / 4u)
#define CNT_TX       (PROTO_STATUS_TX_PACKETS / 4u)
#define CNT_LASTERR  (PROTO_STATUS_LAST_ERROR / 4u)
#define CNT_DROPPED  (PROTO_STATUS_DROPPED / 4u)
#define CNT_N        (PROTO_STATUS_BYTES / 4u)

#define OVERHEAD     (PROTO_HEADER + PROTO_TRAILER)
#define ERROR_BYTES  16u
#define TILE_HEADER  12u   /* u32 frame, u16 x, y, w, h */
#define LASTERR_TEXT 40u   /* HID report 5: characters of text after the fields */

/* docs/word-format.md §3: a FRAME header word, opcode F0 in bits 31..24 and
 * the frame number modulo 2^24 below */
#define WORD_FRAME(n) (0xF0000000u | ((n) & 0x00FFFFFFu))

static const uint8_t magic[4] = {PROTO_MAGIC0, PROTO_MAGIC1, PROTO_MAGIC2, PROTO_MAGIC3};

/* HID LAST ERROR text, indexed by PROTO_E_* (at most 40 characters each) */
static const char *const error_text[] = {
    "no error",
    "bad CRC",
    "sequence gap",
    "duplicate packet",
    "unknown packet type",
    "bad payload length",
    "malformed word stream",
    "packet not valid in the current mode",
    "frame result no longer kept",
};
#define N_ERROR_TEXT (sizeof error_text / sizeof error_text[0])

/* Little-endian fields as functions rather than proto.h's macros: on the
 * 8051 each expansion of those costs a hundred bytes of code. */
static void put16(xbyte *p, uint16_t v)
{
    p[0] = (uint8_t)v;
    p[1] = (uint8_t)(v >> 8);
}

static uint16_t get16(const xbyte *p) { return (uint16_t)(p[0] | (uint16_t)p[1] << 8); }

static void put32(xbyte *p, uint32_t v)
{
    uint8_t i;
    for (i = 0; i < 4; i++, v >>= 8)
        p[i] = (uint8_t)v;
}

static uint32_t get32(const xbyte *p)
{
    uint32_t v = 0;
    uint8_t i = 4;
    while (i--)
        v = v << 8 | p[i];
    return v;
}

static void put_u32s(xbyte *p, const FW_XDATA uint32_t *v, uint8_t n)
{
    for (; n; n--, p += 4)
        put32(p, *v++);
}

static void count(core_t *c, uint8_t counter) { c->counters[counter]++; }

/* ---- outgoing packets, built in c->scratch ---- */

/* The payload is already at scratch + PROTO_HEADER. */
static void send_packet(core_t *c, uint8_t type, uint8_t len)
{
    xbyte *p = c->scratch;

    memcpy(p, magic, sizeof magic);
    p[PROTO_OFF_TYPE] = type;
    p[PROTO_OFF_FLAGS] = 0;
    p[PROTO_OFF_RSVD] = 0;
    p[PROTO_OFF_RSVD + 1] = 0;
    put32(p + PROTO_OFF_SEQ, c->tx_seq);
    put32(p + PROTO_OFF_LEN, len);
    put32(p + PROTO_HEADER + len, proto_crc32(0, p, (uint16_t)(PROTO_HEADER + len)));
    c->tx_seq++;
    count(c, CNT_TX);
    c->hal->send(c->hal->ctx, p, (uint16_t)(PROTO_HEADER + len + PROTO_TRAILER));
}

static void send_error(core_t *c, uint8_t code, uint32_t seq, uint32_t expected, uint32_t detail)
{
    c->last_error[0] = code;
    c->last_error[1] = seq;
    c->last_error[2] = expected;
    c->last_error[3] = detail;
    c->counters[CNT_LASTERR] = code;
    put_u32s(c->scratch + PROTO_HEADER, c->last_error, 4);
    send_packet(c, PROTO_T_ERROR, ERROR_BYTES);
}

static void send_status(core_t *c)
{
    put_u32s(c->scratch + PROTO_HEADER, c->counters, CNT_N);
    send_packet(c, PROTO_T_STATUS, PROTO_STATUS_BYTES);
}

static void send_result(core_t *c, const FW_XDATA fw_result *r)
{
    xbyte *p = c->scratch + PROTO_HEADER;

    put32(p + PROTO_RESULT_FRAME, r->frame);
    put32(p + PROTO_RESULT_CRC, r->crc);
    put32(p + PROTO_RESULT_CYC_LO, r->cyc_lo);
    put32(p + PROTO_RESULT_CYC_HI, r->cyc_hi);
    put32(p + PROTO_RESULT_FACES, r->faces);
    send_packet(c, PROTO_T_RESULT, PROTO_RESULT_BYTES);
}

/* The packet at q passed the CRC but is not acted on. */
static void drop(core_t *c, uint8_t code, const xbyte *q, uint16_t detail)
{
    count(c, CNT_DROPPED);
    send_error(c, code, get32(q + PROTO_OFF_SEQ), c->rx_seq, detail);
}

/* detail of an ERROR MODE */
#define MODE_DETAIL(c, type) ((uint16_t)((unsigned)(c)->mode << 8 | (unsigned)(type)))

/* ---- link state ---- */

/* RESET, bulk or HID: `next` is the sequence number expected next. */
static void link_reset(core_t *c, uint32_t next)
{
    c->synced = 1;
    c->rx_seq = next;
    c->tx_seq = 0;
    c->error_state = 0;
    c->resume_wait = 0;
    c->nresults = 0;
    c->next_result = 0;
    c->hal->vp_restart(c->hal->ctx, 1);
}

/* 1: the packet takes its place in the numbering (in order, or after a gap
 * that put the link in the error state); 0: a duplicate, dropped. */
static uint8_t accept_seq(core_t *c, uint32_t seq)
{
    uint32_t ahead = seq - c->rx_seq;

    if (ahead == 0) {
        c->rx_seq++;
        return 1;
    }
    if (ahead & 0x80000000u) {   /* serial arithmetic: behind */
        count(c, CNT_DUPS);
        send_error(c, PROTO_E_DUPLICATE, seq, c->rx_seq, c->rx_seq - seq);
        return 0;
    }
    count(c, CNT_GAPS);
    send_error(c, PROTO_E_SEQ_GAP, seq, c->rx_seq, ahead);
    c->error_state = 1;
    c->rx_seq = seq + 1;   /* follow the sender's numbering from here */
    return 1;
}

/* ---- host -> board packets: q the packet, len its payload length ---- */

static void on_words(core_t *c, const xbyte *q, uint16_t len)
{
    const xbyte *pay = q + PROTO_HEADER;
    uint32_t want;

    if (c->mode != PROTO_MODE_WORDS) {
        drop(c, PROTO_E_MODE, q, MODE_DETAIL(c, PROTO_T_WORDS));
        return;
    }
    if (len & 3u) {
        drop(c, PROTO_E_BAD_LENGTH, q, len);
        return;
    }
    if (c->error_state) {
        count(c, CNT_DROPPED);
        return;
    }
    if (c->resume_wait) {
        /* RESUME: the partial frame's words are dropped by design, up to the
         * FRAME header of the frame asked for */
        want = WORD_FRAME(c->resume_frame);
        while (len && get32(pay) != want) {
            pay += 4;
            len -= 4;
        }
        if (!len)
            return;
        c->resume_wait = 0;
    }
    if (len)
        c->hal->vp_words(c->hal->ctx, pay, len);
}

static void on_resume(core_t *c, const xbyte *q, uint16_t len)
{
    if (len != 4) {
        drop(c, PROTO_E_BAD_LENGTH, q, len);
        return;
    }
    c->resume_frame = get32(q + PROTO_HEADER);
    c->resume_wait = 1;
    c->error_state = 0;
    c->hal->vp_restart(c->hal->ctx, 0);
}

#ifndef __SDCC_mcs51
/* READBACK: the HAL sends the frame store, or the board does not keep it.
 * (Not on the FX2: its frames are in the FPGA; READBACK is BAD_TYPE there.) */
static void on_readback(core_t *c, const xbyte *q, uint16_t len)
{
    if (!c->hal->readback) {
        drop(c, PROTO_E_BAD_TYPE, q, PROTO_T_READBACK);
        return;
    }
    if (len != 4) {
        drop(c, PROTO_E_BAD_LENGTH, q, len);
        return;
    }
    if (c->hal->readback(c->hal->ctx, get32(q + PROTO_HEADER)))
        send_error(c, PROTO_E_OVERFLOW, get32(q + PROTO_OFF_SEQ), get32(q + PROTO_HEADER), 0);
}
#endif

static void on_query(core_t *c, const xbyte *q, uint16_t len)
{
    uint32_t frame;
    uint8_t k, idx;

    if (len != 4) {
        drop(c, PROTO_E_BAD_LENGTH, q, len);
        return;
    }
    frame = get32(q + PROTO_HEADER);
    for (k = 1; k <= c->nresults; k++) {   /* newest first */
        idx = (uint8_t)((c->next_result + FW_RESULTS - k) % FW_RESULTS);
        if (c->results[idx].frame == frame) {
            send_result(c, &c->results[idx]);
            return;
        }
    }
    idx = (uint8_t)((c->next_result + FW_RESULTS - 1u) % FW_RESULTS);
    send_error(c, PROTO_E_OVERFLOW, get32(q + PROTO_OFF_SEQ), frame,
               c->nresults ? c->results[idx].frame : 0xFFFFFFFFu);
}

/* u32 frame, u16 x, y, w, h, then w·h RGB888 pixels */
static void on_tile(core_t *c, const xbyte *q, uint16_t len)
{
    const xbyte *pay = q + PROTO_HEADER;
    uint16_t w, h;

    if (c->mode != PROTO_MODE_TILES || !c->hal->tile) {
        drop(c, PROTO_E_MODE, q, MODE_DETAIL(c, PROTO_T_TILE));
        return;
    }
    if (len < TILE_HEADER || (len - TILE_HEADER) % 3u) {
        drop(c, PROTO_E_BAD_LENGTH, q, len);
        return;
    }
    w = get16(pay + 8);
    h = get16(pay + 10);
    if ((uint32_t)w * h != (len - TILE_HEADER) / 3u) {   /* w·h < 2^32 for any u16 pair */
        drop(c, PROTO_E_BAD_LENGTH, q, len);
        return;
    }
    c->hal->tile(c->hal->ctx, get32(pay), get16(pay + 4), get16(pay + 6), w, h, pay + TILE_HEADER);
}

/* A whole packet whose CRC is good; len is its payload length. */
static void on_packet(core_t *c, const xbyte *q, uint16_t len)
{
    uint8_t type = q[PROTO_OFF_TYPE];

    count(c, CNT_RX);
    if (type == PROTO_T_RESET) {
        if (len)
            drop(c, PROTO_E_BAD_LENGTH, q, len);
        else
            link_reset(c, get32(q + PROTO_OFF_SEQ) + 1);
        return;
    }
    if (!c->synced) {
        drop(c, PROTO_E_MODE, q, MODE_DETAIL(c, type));
        return;
    }
    if (!accept_seq(c, get32(q + PROTO_OFF_SEQ)))
        return;
    switch (type) {
    case PROTO_T_WORDS:
        on_words(c, q, len);
        break;
    case PROTO_T_RESUME:
        on_resume(c, q, len);
        break;
    case PROTO_T_QUERY:
        on_query(c, q, len);
        break;
    case PROTO_T_TILE:
        on_tile(c, q, len);
        break;
#ifndef __SDCC_mcs51
    case PROTO_T_READBACK:
        on_readback(c, q, len);
        break;
#endif
    case PROTO_T_PING:
        if (len)
            drop(c, PROTO_E_BAD_LENGTH, q, len);
        else
            send_status(c);
        break;
    default:
        drop(c, PROTO_E_BAD_TYPE, q, type);
        break;
    }
}

/* ---- the receiver ---- */

/* Whether the n bytes at p begin with the magic, or are a prefix of it. */
static uint8_t magic_at(const xbyte *p, uint16_t n)
{
    uint8_t k;
    for (k = 0; k < sizeof magic && k < n; k++)
        if (p[k] != magic[k])
            return 0;
    return 1;
}

#define RX_GARBAGE 0u        /* not a packet: resume one byte further on */
#define RX_WAIT    0xFFFFu   /* maybe a packet: more bytes needed */

/* The candidate at q, rest bytes available: its total length when it is a
 * good packet, else RX_GARBAGE or RX_WAIT.  A bad CRC is counted and
 * answered with ERROR here. */
static uint16_t rx_candidate(core_t *c, const xbyte *q, uint16_t rest)
{
    uint32_t plen, crc;
    uint16_t total;

    if (!magic_at(q, rest))
        return RX_GARBAGE;
    if (rest < PROTO_HEADER)
        return RX_WAIT;
    plen = get32(q + PROTO_OFF_LEN);
    if (q[PROTO_OFF_RSVD] || q[PROTO_OFF_RSVD + 1] || plen > c->max_payload)
        return RX_GARBAGE;
    total = (uint16_t)(plen + OVERHEAD);   /* <= 16404 */
    if (rest < total)
        return RX_WAIT;
    crc = proto_crc32(0, q, (uint16_t)(total - PROTO_TRAILER));
    if (crc != get32(q + total - PROTO_TRAILER)) {
        count(c, CNT_CRC);
        send_error(c, PROTO_E_BAD_CRC, get32(q + PROTO_OFF_SEQ), c->rx_seq, crc);
        return RX_GARBAGE;
    }
    return total;
}

/* Consume what it can of the n bytes at p: whole packets, and garbage up to
 * the next candidate.  It stops at a candidate that is not complete yet (a
 * magic prefix, a partial header, or a valid header with part of its payload
 * and CRC); that candidate is shorter than PROTO_HEADER + max_payload +
 * PROTO_TRAILER, so it always fits c->buf.  Returns the bytes consumed. */
static uint16_t rx_parse(core_t *c, const xbyte *p, uint16_t n)
{
    uint16_t i = 0, total;

    while (i < n) {
        total = rx_candidate(c, p + i, (uint16_t)(n - i));
        if (total == RX_WAIT)
            break;
        if (total == RX_GARBAGE) {
            /* resynchronisation: one byte after the rejected candidate's start */
            count(c, CNT_GARBAGE);
            i++;
            continue;
        }
        on_packet(c, p + i, (uint16_t)(total - OVERHEAD));
        i = (uint16_t)(i + total);
    }
    return i;
}

/* The bytes the candidate held in c->buf lacks before rx_parse can decide on
 * it (rx_parse left it there, so its header, if complete, is valid). */
static uint16_t rx_need(const core_t *c)
{
    if (c->fill < PROTO_HEADER)
        return (uint16_t)(PROTO_HEADER - c->fill);
    return (uint16_t)(get32((const xbyte *)c->buf + PROTO_OFF_LEN) + OVERHEAD - c->fill);
}

void fw_init(fw_core *c, const fw_hal *hal, uint8_t *buf, uint16_t max_payload)
{
    memset(c, 0, sizeof *c);
    c->hal = hal;
    c->buf = buf;
    c->max_payload = max_payload > PROTO_MAX_PAYLOAD ? (uint16_t)PROTO_MAX_PAYLOAD : max_payload;
    c->mode = PROTO_MODE_WORDS;
}

/* Packets wholly inside `data` are handled where they lie; only a packet
 * that straddles two calls is assembled in c->buf, and then only up to its
 * end, so the stream behind it goes back to the in-place path. */
void fw_rx(fw_core *core, const uint8_t *data, uint16_t len)
{
    core_t *c = (core_t *)core;
    uint16_t n;

    while (len) {
        if (c->fill == 0) {
            n = rx_parse(c, (const xbyte *)data, len);
            if (n < len) {   /* an incomplete candidate: keep it */
                memcpy(c->buf, data + n, (uint16_t)(len - n));
                c->fill = (uint16_t)(len - n);
            }
            return;
        }
        n = rx_need(c);
        if (n > len)
            n = len;
        memcpy(c->buf + c->fill, data, n);
        c->fill = (uint16_t)(c->fill + n);
        data += n;
        len = (uint16_t)(len - n);
        n = rx_parse(c, (const xbyte *)c->buf, c->fill);
        if (n) {
            c->fill = (uint16_t)(c->fill - n);
            memmove(c->buf, c->buf + n, c->fill);
        }
    }
}

/* READBACK's packets are for boards that keep their frames (the simulated
 * one); the FX2 target, whose VP frame store sits in the FPGA, leaves them
 * out to fit its 16 KB. */
#ifndef __SDCC_mcs51
void fw_send_packet(fw_core *core, uint8_t type, const uint8_t *head, uint16_t head_len,
                    const uint8_t *body, uint16_t body_len)
{
    core_t *c = (core_t *)core;
    xbyte *p = c->scratch;
    uint32_t len = (uint32_t)head_len + body_len, crc;

    memcpy(p, magic, sizeof magic);
    p[PROTO_OFF_TYPE] = type;
    p[PROTO_OFF_FLAGS] = 0;
    p[PROTO_OFF_RSVD] = 0;
    p[PROTO_OFF_RSVD + 1] = 0;
    put32(p + PROTO_OFF_SEQ, c->tx_seq);
    put32(p + PROTO_OFF_LEN, len);
    crc = proto_crc32(0, p, PROTO_HEADER);
    crc = proto_crc32(crc, head, head_len);
    crc = proto_crc32(crc, body, body_len);
    c->tx_seq++;
    count(c, CNT_TX);
    c->hal->send(c->hal->ctx, p, PROTO_HEADER);
    c->hal->send(c->hal->ctx, head, head_len);
    c->hal->send(c->hal->ctx, body, body_len);
    put32(p, crc);
    c->hal->send(c->hal->ctx, p, PROTO_TRAILER);
}
#endif

void fw_frame_done(fw_core *core, const fw_result *r)
{
    core_t *c = (core_t *)core;
    FW_XDATA fw_result *kept = &c->results[c->next_result];

    memcpy(kept, r, sizeof *kept);
    c->next_result = (uint8_t)((c->next_result + 1u) % FW_RESULTS);
    if (c->nresults < FW_RESULTS)
        c->nresults++;
    count(c, CNT_FRAMES);
    send_result(c, kept);
}

void fw_vp_error(fw_core *core, uint32_t word)
{
    core_t *c = (core_t *)core;
    c->error_state = 1;
    send_error(c, PROTO_E_STREAM, c->rx_seq - 1, c->rx_seq, word);
}

/* ---- HID reports ---- */

static void hid_info(const core_t *c, xbyte *r)
{
    r[PROTO_INFO_MAGIC] = 'A';
    r[PROTO_INFO_MAGIC + 1] = 'L';
    r[PROTO_INFO_MAGIC + 2] = 'B';
    r[PROTO_INFO_MAGIC + 3] = 'I';
    put16(r + PROTO_INFO_PROTO, PROTO_VERSION);
    put16(r + PROTO_INFO_FW, c->fw_version);
    put16(r + PROTO_INFO_WIDTH, c->width);
    put16(r + PROTO_INFO_HEIGHT, c->height);
    r[PROTO_INFO_CBITS] = c->colour_bits;
    r[PROTO_INFO_MODE] = c->mode;
    put32(r + PROTO_INFO_SERIAL, c->serial);
    memcpy(r + PROTO_INFO_NAME, c->name, sizeof c->name);
    put16(r + PROTO_INFO_MAXPAY, c->max_payload);
}

static void hid_lasterr(const core_t *c, xbyte *r)
{
    const char *text = "unknown error";
    uint8_t i;

    put_u32s(r + 1, c->last_error, 4);
    if (c->last_error[0] < N_ERROR_TEXT)
        text = error_text[c->last_error[0]];
    for (i = 0; i < LASTERR_TEXT && text[i]; i++)
        r[17 + i] = (uint8_t)text[i];
}

uint8_t fw_hid_get(fw_core *core, uint8_t *report)
{
    core_t *c = (core_t *)core;
    xbyte *r = (xbyte *)report;
    uint8_t id = r[0];

    if (id != PROTO_HID_INFO && id != PROTO_HID_MODE && id != PROTO_HID_COUNTERS &&
        id != PROTO_HID_LASTERR)
        return 0;
    memset(r + 1, 0, PROTO_HID_REPORT - 1);
    if (id == PROTO_HID_INFO)
        hid_info(c, r);
    else if (id == PROTO_HID_MODE)
        r[1] = c->mode;
    else if (id == PROTO_HID_COUNTERS)
        put_u32s(r + 1, c->counters, CNT_N);
    else
        hid_lasterr(c, r);
    return PROTO_HID_REPORT;
}

/* RESET what: bit 0 the link (as a bulk RESET, the next packet expected
 * being number 0; half-received bytes are discarded and counted as
 * garbage), bit 1 the counters and last error. */
uint8_t fw_hid_set(fw_core *core, const uint8_t *report, uint8_t len)
{
    core_t *c = (core_t *)core;
    uint8_t v;

    if (len < 2)
        return 1;
    v = report[1];
    if (report[0] == PROTO_HID_RESET) {
        if (v < PROTO_RESET_LINK || v > PROTO_RESET_ALL)
            return 1;
        if (v & PROTO_RESET_LINK) {
            c->counters[CNT_GARBAGE] += c->fill;
            c->fill = 0;
            link_reset(c, 0);
        }
        if (v & PROTO_RESET_COUNTERS) {
            memset(c->counters, 0, sizeof c->counters);
            memset(c->last_error, 0, sizeof c->last_error);
        }
        return 0;
    }
    if (report[0] == PROTO_HID_MODE) {
        if (v > PROTO_MODE_TILES || (v == PROTO_MODE_TILES && !c->hal->tile))
            return 1;
        c->mode = v;
        return 0;
    }
    return 1;
}
