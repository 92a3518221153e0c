/* link.h — the host's side of the bulk protocol (docs/usb-protocol.md):
 * packet encoding, and a decoder of the board's packets with the same
 * resynchronisation rules as the firmware, counting every loss. */
#ifndef ALBATROS_LINK_H
#define ALBATROS_LINK_H



#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/* The library exports what its public headers declare, nothing else. */
#pragma GCC visibility push(default)
#ifdef __cplusplus
extern "C" {
#endif

/* Encode one packet into out (PROTO_HEADER + len + PROTO_TRAILER bytes). */
size_t alb_link_encode(uint8_t *out, uint8_t type, uint32_t seq, const uint8_t *payload, uint32_t len);

typedef struct {
    uint8_t type;
    uint32_t seq;
    uint32_t len;
    const uint8_t *payload;   /* valid until the next link_rx_* call */
} alb_link_packet;

typedef struct {
    uint8_t *buf;
    size_t len, cap, start;   /* unread bytes are buf[start .. len) */
    bool have_seq;
    uint32_t expect_seq;
    /* losses seen on the way in */
    uint64_t crc_errors, garbage, seq_gaps, duplicates, packets;
} alb_link_rx;

void alb_link_rx_init(alb_link_rx *rx);
void alb_link_rx_free(alb_link_rx *rx);
/* Append received bytes; -1 if out of memory. */
int alb_link_rx_feed(alb_link_rx *rx, const uint8_t *data, size_t len);
/* The next valid packet: 1 with *p filled, 0 if more bytes are needed.
 * Bad candidates are skipped (counted); sequence gaps and duplicates are
 * counted and the packet is still returned (p->seq tells). */
int alb_link_rx_next(alb_link_rx *rx, alb_link_packet *p);

/* The CRC of a frame store as the protocol defines it: R, G, B of every
 * pixel as 16-bit little-endian, row 0 first (docs/usb-protocol.md). */
uint32_t alb_link_frame_crc(const uint16_t *rgb, size_t pixels);

/* Frames mode's pixels: frame store values of colour_bits each scaled to
 * 8 bits, round half up (v * 255 / (2^cb - 1)); 3 bytes a pixel. */
void alb_link_rgb888(const uint16_t *rgb, size_t pixels, unsigned colour_bits, uint8_t *out);

/* The board's INFO report (HID feature report 1), decoded. */
typedef struct {
    char name[17];
    unsigned protocol, firmware, width, height, colour_bits, mode;
    uint32_t serial;
    unsigned max_payload;     /* the largest bulk payload the board accepts */
} alb_link_info;

/* Decode an INFO report (rep[0] the report ID, then PROTO_HID_REPORT - 1
 * bytes); -1 if it lacks the ALBI magic (not an albatros board). */
int alb_link_info_decode(const uint8_t *rep, alb_link_info *out);

/* ERROR codes (PROTO_E_*): a readable name, and a key for JSON; codes the
 * host does not know are "unknown". */
const char *alb_link_error_name(uint32_t code);
const char *alb_link_error_key(uint32_t code);

#ifdef __cplusplus
}
#endif
#pragma GCC visibility pop

#endif
