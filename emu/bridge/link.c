/* link.c — packet codec of the host side of the bridge. */
#include "albatros/link.h"
#include "../../firmware/proto.h"

#include <stdlib.h>
#include <string.h>
#ifdef ALB_NO_EXTERNAL
/* Built without external libraries (make crosscheck's musl build,
 * docs/golden-vectors.md): no zlib, so the firmware's CRC-32, which gives
 * the same values, under zlib's name. */
typedef unsigned long uLong;
typedef uint8_t Bytef;
static uLong crc32_z(uLong crc, const Bytef *p, size_t n)
{
    while (n) {
        uint16_t k = n > 0x8000 ? 0x8000 : (uint16_t)n;
        crc = proto_crc32((uint32_t)crc, p, k);
        p += k;
        n -= k;
    }
    return crc;
}
#else
#include <zlib.h>
#endif

/* The protocol's CRC-32 (docs/usb-protocol.md) is zlib's: the same
 * polynomial, presets and chaining as the firmware's own (firmware/crc32.c,
 * written for the 8051), computed here by the library every host has. */
static uint32_t crc_of(const uint8_t *p, size_t n)
{
    return (uint32_t)crc32_z(0, p, n);
}

size_t alb_link_encode(uint8_t *out, uint8_t type, uint32_t seq, const uint8_t *payload, uint32_t len)
{
    out[0] = PROTO_MAGIC0, out[1] = PROTO_MAGIC1, out[2] = PROTO_MAGIC2, out[3] = PROTO_MAGIC3;
    out[PROTO_OFF_TYPE] = type;
    out[PROTO_OFF_FLAGS] = 0;
    out[PROTO_OFF_RSVD] = out[PROTO_OFF_RSVD + 1] = 0;
    PROTO_PUT32(out + PROTO_OFF_SEQ, seq);
    PROTO_PUT32(out + PROTO_OFF_LEN, len);
    if (len)
        memcpy(out + PROTO_HEADER, payload, len);
    size_t n = PROTO_HEADER + len;
    PROTO_PUT32(out + n, crc_of(out, n));
    return n + PROTO_TRAILER;
}

void alb_link_rx_init(alb_link_rx *rx) { memset(rx, 0, sizeof *rx); }

void alb_link_rx_free(alb_link_rx *rx)
{
    free(rx->buf);
    memset(rx, 0, sizeof *rx);
}

int alb_link_rx_feed(alb_link_rx *rx, const uint8_t *data, size_t len)
{
    if (rx->start && rx->start == rx->len)
        rx->start = rx->len = 0;
    if (rx->len + len > rx->cap) {
        if (rx->start) {   /* compact first */
            memmove(rx->buf, rx->buf + rx->start, rx->len - rx->start);
            rx->len -= rx->start;
            rx->start = 0;
        }
        if (rx->len + len > rx->cap) {
            size_t cap = rx->cap ? rx->cap : 4096;
            while (cap < rx->len + len)
                cap *= 2;
            uint8_t *nb = realloc(rx->buf, cap);
            if (!nb)
                return -1;
            rx->buf = nb;
            rx->cap = cap;
        }
    }
    memcpy(rx->buf + rx->len, data, len);
    rx->len += len;
    return 0;
}

static bool is_magic(const uint8_t *p)
{
    return p[0] == PROTO_MAGIC0 && p[1] == PROTO_MAGIC1 && p[2] == PROTO_MAGIC2 &&
           p[3] == PROTO_MAGIC3;
}

int alb_link_rx_next(alb_link_rx *rx, alb_link_packet *p)
{
    if (!rx->buf)
        return 0;   /* nothing fed yet (and no buffer to point into) */
    for (;;) {
        size_t avail = rx->len - rx->start;
        const uint8_t *b = rx->buf + rx->start;
        /* find the magic */
        size_t skip = 0;
        while (skip + 4 <= avail && !is_magic(b + skip))
            skip++;
        if (skip + 4 > avail) {
            /* keep up to 3 bytes that may start a magic */
            size_t keep = avail < 3 ? avail : 3;
            rx->garbage += avail - keep;
            rx->start = rx->len - keep;
            return 0;
        }
        rx->garbage += skip;
        rx->start += skip;
        b += skip;
        avail -= skip;
        if (avail < PROTO_HEADER)
            return 0;
        uint32_t len = PROTO_GET32(b + PROTO_OFF_LEN);
        if (b[PROTO_OFF_RSVD] || b[PROTO_OFF_RSVD + 1] || len > PROTO_MAX_PAYLOAD) {
            rx->garbage++;
            rx->start++;   /* one byte after the candidate's magic start */
            continue;
        }
        size_t total = PROTO_HEADER + len + PROTO_TRAILER;
        if (avail < total)
            return 0;
        if (crc_of(b, PROTO_HEADER + len) != PROTO_GET32(b + PROTO_HEADER + len)) {
            rx->crc_errors++;
            rx->garbage++;
            rx->start++;
            continue;
        }
        p->type = b[PROTO_OFF_TYPE];
        p->seq = PROTO_GET32(b + PROTO_OFF_SEQ);
        p->len = len;
        p->payload = b + PROTO_HEADER;
        rx->start += total;
        rx->packets++;
        if (rx->have_seq && p->seq != rx->expect_seq) {
            if (p->seq > rx->expect_seq)
                rx->seq_gaps++;
            else
                rx->duplicates++;
        }
        rx->have_seq = true;
        rx->expect_seq = p->seq + 1;
        return 1;
    }
}

uint32_t alb_link_frame_crc(const uint16_t *rgb, size_t pixels)
{
    uLong crc = crc32_z(0, NULL, 0);
    const uint16_t probe = 1;
    if (*(const uint8_t *)&probe)   /* little-endian: the store is the byte sequence */
        return (uint32_t)crc32_z(crc, (const Bytef *)rgb, 6 * pixels);
    uint8_t chunk[3 * 2 * 256];
    for (size_t i = 0; i < pixels;) {
        size_t n = pixels - i < 256 ? pixels - i : 256;
        for (size_t k = 0; k < 3 * n; k++) {
            uint16_t v = rgb[3 * i + k];
            chunk[2 * k] = (uint8_t)v;
            chunk[2 * k + 1] = (uint8_t)(v >> 8);
        }
        crc = crc32_z(crc, chunk, 6 * n);
        i += n;
    }
    return (uint32_t)crc;
}

void alb_link_rgb888(const uint16_t *rgb, size_t pixels, unsigned colour_bits, uint8_t *out)
{
    uint32_t top = (1u << colour_bits) - 1;
    for (size_t i = 0; i < 3 * pixels; i++)
        out[i] = (uint8_t)((2 * 255 * (uint32_t)rgb[i] + top) / (2 * top));
}

static unsigned get16(const uint8_t *p) { return (unsigned)p[0] | (unsigned)p[1] << 8; }

int alb_link_info_decode(const uint8_t *rep, alb_link_info *out)
{
    memset(out, 0, sizeof *out);
    if (memcmp(rep + PROTO_INFO_MAGIC, "ALBI", 4))
        return -1;
    memcpy(out->name, rep + PROTO_INFO_NAME, 16);
    out->protocol = get16(rep + PROTO_INFO_PROTO);
    out->firmware = get16(rep + PROTO_INFO_FW);
    out->width = get16(rep + PROTO_INFO_WIDTH);
    out->height = get16(rep + PROTO_INFO_HEIGHT);
    out->colour_bits = rep[PROTO_INFO_CBITS];
    out->mode = rep[PROTO_INFO_MODE];
    out->serial = PROTO_GET32(rep + PROTO_INFO_SERIAL);
    out->max_payload = get16(rep + PROTO_INFO_MAXPAY);
    return 0;
}

/* indexed by PROTO_E_* (proto.h) */
static const char *const error_names[][2] = {
    {"unknown code", "unknown"},     {"bad CRC", "bad_crc"},
    {"sequence gap", "seq_gap"},     {"duplicate", "duplicate"},
    {"bad type", "bad_type"},        {"bad length", "bad_length"},
    {"malformed stream", "stream"},  {"wrong mode", "mode"},
    {"overflow", "overflow"},
};
#define N_ERROR_NAMES (sizeof error_names / sizeof error_names[0])

const char *alb_link_error_name(uint32_t code)
{
    return error_names[code < N_ERROR_NAMES ? code : 0][0];
}

const char *alb_link_error_key(uint32_t code)
{
    return error_names[code < N_ERROR_NAMES ? code : 0][1];
}
