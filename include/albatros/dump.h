/* dump.h — a frame as an RTL bench dumps it (docs/cosim.md, "Frame store
 * dumps"): one 128-bit record per pixel, row 0 first, as $writememh text
 * (32 hex digits a line) or raw (16 bytes a pixel, little-endian):
 *
 *   bits 127..96 face id     95..64 depth store value d
 *         63..48 R  47..32 G  31..16 B (frame store values)
 *         15..8  level       7..0  coverage (samples covered)
 *
 * so `albatros compare` can hold it against the model's frame. */
#ifndef ALBATROS_DUMP_H
#define ALBATROS_DUMP_H

#include "diag.h"
#include "frame.h"

/* The library exports what its public headers declare, nothing else. */
#pragma GCC visibility push(default)
#ifdef __cplusplus
extern "C" {
#endif

typedef enum {
    ALB_DUMP_MEMH,            /* $writememh text */
    ALB_DUMP_RAW              /* 16 bytes a pixel */
} alb_dump_format;

#define ALB_DUMP_RECORD_BYTES 16

/* Write f's pixels ("-" is stdout for memh). */
alb_err alb_dump_write(const char *path, const alb_frame *f, alb_dump_format fmt, alb_diag *d);
/* Read a dump of a frame shaped like `shape` (its size and formats: width,
 * height, colour_bits, depth_bits, aa_levels, near, number are copied);
 * memh or raw is told from the bytes.  *out is allocated (alb_frame_free).
 * Errors name the line (memh) or byte offset (raw), the pixel and field. */
alb_err alb_dump_read(const char *path, const alb_frame *shape, alb_frame *out, alb_diag *d);
/* Whether the file's first bytes are an OpenEXR file's (else a dump). */
bool alb_dump_is_exr(const char *path);

#ifdef __cplusplus
}
#endif
#pragma GCC visibility pop

#endif
