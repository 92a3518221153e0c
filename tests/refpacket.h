/* refpacket.h — the bridge's packets and CRC written again, independently of
 * firmware/ and emu/bridge/, for tests that check those against it: CRC-32
 * bit by bit (IEEE 802.3, reflected), little-endian fields, and a packet
 * encoder (docs/usb-protocol.md). */
#ifndef ALBATROS_TEST_REFPACKET_H
#define ALBATROS_TEST_REFPACKET_H

#include <stddef.h>
#include <stdint.h>

uint32_t ref_crc32(const uint8_t *p, size_t n);
/* ref_crc32 continued over more bytes (ref_crc32_more(0, ...) = ref_crc32). */
uint32_t ref_crc32_more(uint32_t crc, const uint8_t *p, size_t n);
void le32(uint8_t *p, uint32_t v);
uint32_t rd32(const uint8_t *p);
/* A packet into out (16 + len + 4 bytes): its length. */
size_t enc(uint8_t *out, uint8_t type, uint32_t seq, const void *pay, uint32_t len);

#endif
