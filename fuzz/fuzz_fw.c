/* fuzz_fw.c — the firmware's packet parser (firmware/core.c): whatever the
 * host sends on the bulk OUT endpoint, cut into USB-sized pieces, with HID
 * reports, finished frames and VP errors between them.
 *
 * The input's first byte seeds the cuts; the rest is the byte stream.
 * Oracles beyond the sanitizers: the VP only ever receives whole words and
 * no more than one payload at a time, and every packet the board sends
 * back — ERROR, STATUS, RESULT, PIXELS — is well formed, numbered without
 * gap or repeat, as the host's decoder (emu/bridge/link.c) checks it. */
#include "fuzz.h"
#include "albatros/link.h"
#include "../firmware/core.h"

#include <stdlib.h>
#include <string.h>

#define MAX_PAYLOAD 1024u   /* small, so that oversized lengths are reached */

typedef struct {
    fw_core core;
    uint8_t buf[PROTO_HEADER + MAX_PAYLOAD + PROTO_TRAILER];
    alb_link_rx back;             /* what the board sent, decoded by the host */
    unsigned got;             /* packets decoded */
} board;

static void check(int ok)
{
    if (!ok)
        abort();
}

static void on_words(void *ctx, const uint8_t *data, uint16_t len)
{
    (void)ctx;
    check(len % 4 == 0 && len <= MAX_PAYLOAD);
    volatile uint8_t sum = 0;
    for (uint16_t i = 0; i < len; i++)   /* every byte readable (ASan) */
        sum += data[i];
    (void)sum;
}

static void on_restart(void *ctx, uint8_t full)
{
    (void)ctx;
    check(full <= 1);
}

/* A packet may come in pieces (fw_send_packet's header, head, body, CRC),
 * each decoded as it comes.  After a RESET the board numbers its packets
 * from 0 again (docs/usb-protocol.md): a header with sequence number 0
 * starts the decoder's expectation afresh. */
static void on_send(void *ctx, const uint8_t *data, uint16_t len)
{
    board *b = ctx;
    if (len >= PROTO_HEADER && data[0] == PROTO_MAGIC0 && PROTO_GET32(data + PROTO_OFF_SEQ) == 0)
        b->back.have_seq = false;
    check(alb_link_rx_feed(&b->back, data, len) == 0);
    alb_link_packet p;
    while (alb_link_rx_next(&b->back, &p) == 1) {
        check(p.type & 0x80);
        b->got++;
    }
}

static void on_tile(void *ctx, uint32_t frame, uint16_t x, uint16_t y, uint16_t w, uint16_t h,
                    const uint8_t *rgb)
{
    (void)ctx, (void)frame, (void)x, (void)y;
    check((uint32_t)w * h * 3 <= MAX_PAYLOAD);
    volatile uint8_t sum = 0;
    for (uint32_t i = 0; i < (uint32_t)w * h * 3; i++)
        sum += rgb[i];
    (void)sum;
}

/* The board keeps frames 0..3: two PIXELS packets each. */
static uint8_t on_readback(void *ctx, uint32_t frame)
{
    board *b = ctx;
    if (frame > 3)
        return 1;
    uint8_t head[12] = {0}, body[24];
    memset(body, (int)frame, sizeof body);
    for (int k = 0; k < 2; k++) {
        head[4] = (uint8_t)(4 * k);   /* first pixel */
        head[8] = 4;                  /* count */
        fw_send_packet(&b->core, PROTO_T_PIXELS, head, sizeof head, body, sizeof body);
    }
    return 0;
}

static const fw_hal hal = {NULL, on_words, on_restart, on_send, on_tile, on_readback};

static uint32_t next(uint32_t *s)
{
    *s ^= *s << 13;
    *s ^= *s >> 17;
    *s ^= *s << 5;
    return *s;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static board b;
    if (size < 1)
        return 0;
    memset(&b, 0, sizeof b);
    fw_hal h = hal;
    h.ctx = &b;
    fw_init(&b.core, &h, b.buf, MAX_PAYLOAD);
    b.core.width = 64;
    b.core.height = 64;
    alb_link_rx_init(&b.back);
    uint32_t s = 0x9E3779B9u ^ data[0];
    uint32_t frame = 0;
    data++, size--;
    while (size) {
        uint32_t r = next(&s);
        size_t piece = 1 + r % 512;   /* a USB packet is at most 512 bytes */
        piece = piece < size ? piece : size;
        fw_rx(&b.core, data, (uint16_t)piece);
        data += piece, size -= piece;
        switch (r >> 28) {
        case 0: {
            fw_result res = {frame++, r, r >> 3, 0, 7};
            fw_frame_done(&b.core, &res);
            break;
        }
        case 1:
            fw_vp_error(&b.core, r >> 10);
            break;
        case 2: {
            uint8_t report[PROTO_HID_REPORT] = {(uint8_t)(1 + (r >> 20) % 6)};
            check(fw_hid_get(&b.core, report) <= PROTO_HID_REPORT);
            break;
        }
        case 3: {
            /* a SET_REPORT from the next bytes of the input */
            uint8_t report[PROTO_HID_REPORT] = {0};
            uint8_t n = (uint8_t)(size < sizeof report ? size : sizeof report);
            memcpy(report, data, n);
            fw_hid_set(&b.core, report, n);
            break;
        }
        default:
            break;
        }
    }
    /* everything the board said decoded cleanly, in order */
    check(b.back.crc_errors == 0 && b.back.garbage == 0 && b.back.seq_gaps == 0 &&
          b.back.duplicates == 0 && b.back.start == b.back.len && (b.got > 0) == (b.back.len > 0));
    alb_link_rx_free(&b.back);
    return 0;
}
