/* refpacket.c — see refpacket.h. */
#include "refpacket.h"

#include <string.h>

uint32_t ref_crc32_more(uint32_t crc, const uint8_t *p, size_t n)
{
    crc = ~crc;
    while (n--) {
        crc ^= *p++;
        for (int k = 0; k < 8; k++)
            crc = (crc & 1) ? (crc >> 1) ^ 0xEDB88320u : crc >> 1;
    }
    return ~crc;
}

uint32_t ref_crc32(const uint8_t *p, size_t n) { return ref_crc32_more(0, p, n); }

void le32(uint8_t *p, uint32_t v)
{
    for (int i = 0; i < 4; i++)
        p[i] = (uint8_t)(v >> (8 * i));
}

uint32_t rd32(const uint8_t *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

size_t enc(uint8_t *out, uint8_t type, uint32_t seq, const void *pay, uint32_t len)
{
    memcpy(out, "ALB1", 4);
    out[4] = type;
    out[5] = out[6] = out[7] = 0;
    le32(out + 8, seq);
    le32(out + 12, len);
    if (len)
        memcpy(out + 16, pay, len);
    le32(out + 16 + len, ref_crc32(out, 16 + (size_t)len));
    return 20 + (size_t)len;
}
