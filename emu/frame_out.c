/* frame_out.c — what the sinks compute from a finished frame outside the VP:
 * the EXR Z channel's distance and compare's error measures, in floating
 * point (the VP itself has none: docs/number-formats.md §0), and a digest of
 * the exact planes, by which a build without OpenEXR checks the golden
 * vectors' frames (docs/golden-vectors.md, "Another C library"). */
#include "albatros/frame.h"

#include <math.h>
#include <string.h>

float alb_frame_z(const alb_frame *f, uint32_t d)
{
    if (d == 0)
        return INFINITY;
    /* one correctly rounded double division, then one rounding to float */
    return (float)((double)f->near / ldexp((double)d, -(int)f->depth_bits));
}

void alb_frame_compare(const alb_frame *a, const alb_frame *b, alb_frame_diff *r)
{
    memset(r, 0, sizeof *r);
    size_t n = (size_t)a->width * a->height;
    double sq = 0, sum = 0;
    r->pixels = n;
    for (size_t i = 0; i < n; i++) {
        r->face_diff += a->face[i] != b->face[i];
        r->coverage_diff += a->coverage[i] != b->coverage[i];
        bool differs = false;
        for (int ch = 0; ch < 3; ch++) {
            int d = (int)a->rgb[3 * i + ch] - (int)b->rgb[3 * i + ch];
            unsigned ad = (unsigned)(d < 0 ? -d : d);
            differs |= ad != 0;
            if (ad > r->max_error)
                r->max_error = ad;
            sum += ad;
            sq += (double)d * d;
        }
        r->colour_diff += differs;
    }
    r->mean_error = sum / (3.0 * (double)n);
    double peak = ldexp(1, (int)a->colour_bits) - 1, mse = sq / (3.0 * (double)n);
    r->psnr = mse > 0 ? 10 * log10(peak * peak / mse) : INFINITY;
}

/* CRC-32 (IEEE 802.3, reflected, as zlib's and the protocol's), table by
 * table: a dependency of none (the build without external libraries uses
 * it too). */
typedef struct {
    uint32_t t[256];
} crc_table;

static void crc_table_make(crc_table *c)
{
    for (uint32_t i = 0; i < 256; i++) {
        uint32_t v = i;
        for (int k = 0; k < 8; k++)
            v = v & 1 ? v >> 1 ^ 0xEDB88320u : v >> 1;
        c->t[i] = v;
    }
}

static uint32_t crc_add(const crc_table *c, uint32_t crc, const uint8_t *p, size_t n)
{
    crc = ~crc;
    while (n--)
        crc = c->t[(crc ^ *p++) & 0xFF] ^ crc >> 8;
    return ~crc;
}

/* The CRC-32 of the planes a golden vector compares, pixel by pixel in
 * raster order, little-endian: R, G, B (u16 each), depth (u32), face
 * (u32), level (u8), coverage (u16), and cycles (u32) when the frame has
 * them; then width, height, colour_bits, depth_bits, aa_levels and number
 * (u32 each). */
static uint8_t *put(uint8_t *p, uint32_t v, unsigned bytes)
{
    for (unsigned i = 0; i < bytes; i++, v >>= 8)
        *p++ = (uint8_t)v;
    return p;
}

uint32_t alb_frame_digest(const alb_frame *f)
{
    crc_table ct;
    crc_table_make(&ct);
    uint8_t buf[24];
    uint32_t crc = 0;
    size_t n = (size_t)f->width * f->height;
    for (size_t i = 0; i < n; i++) {
        uint8_t *p = buf;
        for (int ch = 0; ch < 3; ch++)
            p = put(p, f->rgb[3 * i + ch], 2);
        p = put(p, f->depth[i], 4);
        p = put(p, f->face[i], 4);
        p = put(p, f->level[i], 1);
        p = put(p, f->coverage[i], 2);
        if (f->cycles)
            p = put(p, f->cycles[i], 4);
        crc = crc_add(&ct, crc, buf, (size_t)(p - buf));
    }
    const uint32_t meta[6] = {f->width, f->height, f->colour_bits, f->depth_bits, f->aa_levels,
                              f->number};
    for (int k = 0; k < 6; k++) {
        put(buf, meta[k], 4);
        crc = crc_add(&ct, crc, buf, 4);
    }
    return crc;
}
