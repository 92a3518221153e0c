/* proto.h — the host <-> board protocol of docs/usb-protocol.md: USB ids,
 * bulk packet framing, packet types, HID reports, error codes.  Shared by the
 * host (emu/) and the firmware (firmware/), so it stays plain C that sdcc
 * compiles for the FX2's 8051: no 64-bit types, no structs on the wire. */
#ifndef ALBATROS_PROTO_H
#define ALBATROS_PROTO_H

#include <stdint.h>

/* pid.codes test VID/PID, for testing only (overridable on the host). */
#define PROTO_VID 0x1209u
#define PROTO_PID 0x0001u

#define PROTO_VERSION 1u

/* USB layout: interface 0 vendor-specific with two bulk endpoints, interface
 * 1 HID with an interrupt IN endpoint. */
#define PROTO_IF_DATA     0
#define PROTO_IF_HID      1
#define PROTO_EP_OUT      0x02u   /* host -> board bulk */
#define PROTO_EP_IN       0x86u   /* board -> host bulk */
#define PROTO_EP_HID_IN   0x81u   /* HID interrupt IN */
#define PROTO_BULK_MAXPKT 512u    /* high speed */

/* ---- bulk packets: header, payload, CRC-32 ---- */

#define PROTO_MAGIC0 0x41u   /* 'A' */
#define PROTO_MAGIC1 0x4Cu   /* 'L' */
#define PROTO_MAGIC2 0x42u   /* 'B' */
#define PROTO_MAGIC3 0x31u   /* '1' */
#define PROTO_HEADER      16u
#define PROTO_TRAILER     4u      /* CRC-32 of header and payload */
#define PROTO_MAX_PAYLOAD 16384u

/* header byte offsets (little-endian fields) */
#define PROTO_OFF_TYPE   4u
#define PROTO_OFF_FLAGS  5u
#define PROTO_OFF_RSVD   6u       /* two zero bytes */
#define PROTO_OFF_SEQ    8u
#define PROTO_OFF_LEN    12u

/* host -> board */
#define PROTO_T_RESET  0x01u      /* restart the link: seq, parser, error state */
#define PROTO_T_WORDS  0x02u      /* word-stream chunk: payload 4n bytes, LE words */
#define PROTO_T_RESUME 0x03u      /* payload u32 frame: drop the partial frame, expect its FRAME */
#define PROTO_T_QUERY  0x04u      /* payload u32 frame: send that frame's RESULT again */
#define PROTO_T_TILE   0x05u      /* frames mode: u32 frame, u16 x y w h, w*h RGB888 */
#define PROTO_T_PING   0x06u      /* answer with STATUS */
#define PROTO_T_READBACK 0x07u    /* payload u32 frame: send its frame store as PIXELS */
/* board -> host */
#define PROTO_T_RESULT 0x81u      /* a frame done: see PROTO_RESULT_* */
#define PROTO_T_STATUS 0x82u      /* counters: see PROTO_STATUS_* */
#define PROTO_T_ERROR  0x83u      /* u32 code, u32 seq, u32 expected, u32 detail */
#define PROTO_T_PIXELS 0x84u      /* u32 frame, u32 first pixel, u32 count, count x RGB u16 LE */

/* RESULT payload (u32 LE each) */
#define PROTO_RESULT_FRAME   0u
#define PROTO_RESULT_CRC     4u    /* CRC-32 of the frame store, docs/usb-protocol.md */
#define PROTO_RESULT_CYC_LO  8u
#define PROTO_RESULT_CYC_HI  12u
#define PROTO_RESULT_FACES   16u
#define PROTO_RESULT_BYTES   20u

/* STATUS payload (u32 LE each), also HID report 4 */
#define PROTO_STATUS_RX_PACKETS  0u
#define PROTO_STATUS_CRC_ERRORS  4u
#define PROTO_STATUS_SEQ_GAPS    8u
#define PROTO_STATUS_DUPLICATES  12u
#define PROTO_STATUS_GARBAGE     16u   /* bytes skipped resynchronising */
#define PROTO_STATUS_FRAMES      20u
#define PROTO_STATUS_TX_PACKETS  24u
#define PROTO_STATUS_LAST_ERROR  28u
#define PROTO_STATUS_DROPPED     32u   /* WORDS packets discarded in error state */
#define PROTO_STATUS_BYTES       36u

/* error codes (ERROR packets, HID report 5) */
#define PROTO_E_NONE       0u
#define PROTO_E_BAD_CRC    1u
#define PROTO_E_SEQ_GAP    2u
#define PROTO_E_DUPLICATE  3u
#define PROTO_E_BAD_TYPE   4u
#define PROTO_E_BAD_LENGTH 5u
#define PROTO_E_STREAM     6u      /* the word stream itself is malformed */
#define PROTO_E_MODE       7u      /* packet not valid in the current mode */
#define PROTO_E_OVERFLOW   8u

/* ---- HID reports: 64 bytes, byte 0 the report ID ---- */

#define PROTO_HID_REPORT 64u
#define PROTO_HID_INFO      1u   /* feature, GET */
#define PROTO_HID_RESET     2u   /* feature, SET: byte 1 what */
#define PROTO_HID_MODE      3u   /* feature, SET/GET: byte 1 mode */
#define PROTO_HID_COUNTERS  4u   /* feature GET and input: STATUS layout from byte 1 */
#define PROTO_HID_LASTERR   5u   /* feature GET: code, seq, expected, detail, text */

#define PROTO_RESET_LINK     1u
#define PROTO_RESET_COUNTERS 2u
#define PROTO_RESET_ALL      3u

#define PROTO_MODE_IDLE  0u
#define PROTO_MODE_WORDS 1u      /* the board runs the VP on a word stream */
#define PROTO_MODE_TILES 2u      /* the board displays frames sent as tiles */

/* INFO report layout (after the ID byte) */
#define PROTO_INFO_MAGIC   1u    /* "ALBI" */
#define PROTO_INFO_PROTO   5u    /* u16 protocol version */
#define PROTO_INFO_FW      7u    /* u16 firmware version */
#define PROTO_INFO_WIDTH   9u    /* u16 */
#define PROTO_INFO_HEIGHT  11u   /* u16 */
#define PROTO_INFO_CBITS   13u   /* u8 colour bits */
#define PROTO_INFO_MODE    14u   /* u8 */
#define PROTO_INFO_SERIAL  15u   /* u32 */
#define PROTO_INFO_NAME    19u   /* 16 chars, NUL padded */
#define PROTO_INFO_MAXPAY  35u   /* u16 largest payload the board accepts */

/* CRC-32 (IEEE 802.3, reflected, as zlib's crc32): start with crc = 0 and
 * feed data in pieces. */
uint32_t proto_crc32(uint32_t crc, const uint8_t *data, uint16_t len);

/* Little-endian helpers */
#define PROTO_GET32(p) ((uint32_t)(p)[0] | (uint32_t)(p)[1] << 8 | (uint32_t)(p)[2] << 16 | \
                        (uint32_t)(p)[3] << 24)
#define PROTO_PUT32(p, v) ((p)[0] = (uint8_t)(v), (p)[1] = (uint8_t)((v) >> 8), \
                           (p)[2] = (uint8_t)((v) >> 16), (p)[3] = (uint8_t)((v) >> 24))

#endif
