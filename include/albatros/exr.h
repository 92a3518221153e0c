/* exr.h — frames to and from OpenEXR files (OpenEXRCore's C API): one
 * scanline part, ZIP, colour as HALF R,G,B (+A), depth as FLOAT Z, and every
 * exact VP plane as a UINT layer channel so verification data survives. */
#ifndef ALBATROS_EXR_H
#define ALBATROS_EXR_H

#include "diag.h"
#include "vp.h"

/* The library exports what its public headers declare, nothing else. */
#pragma GCC visibility push(default)
#ifdef __cplusplus
extern "C" {
#endif

/* Channels written (OpenEXR stores them sorted by name):
 *   R, G, B      HALF   frame store value / (2^colour_bits - 1)
 *   A            HALF   coverage / 4^aa_levels (only if aa_levels > 0)
 *   Z            FLOAT  alb_frame_z(depth store), +inf where no face
 *   face.id      UINT   face id, ALB_FRAME_NO_FACE where no face
 *   vp.level     UINT   deciding subdivision level, ALB_FRAME_NO_LEVEL (255) where no face
 *   vp.depth     UINT   exact depth store, 0 where no face
 *   vp.R, vp.G, vp.B  UINT  exact frame store values
 *   vp.coverage  UINT   covered samples of 4^aa_levels
 *   vp.cycles    UINT   VP cycles per pixel (only if the frame has them)
 * R, G, B are linear light: the store value decoded by sRGB's transfer
 * function, with the chromaticities attribute of the sRGB / Rec. 709
 * primaries and D65 (docs/vp.md §7); the exact values are vp.R, vp.G, vp.B.
 * Header attributes (int): albatros.colour_bits, albatros.depth_bits,
 * albatros.aa_levels, albatros.frame (the uint32 frame number's bits);
 * (float) albatros.near; (string) albatros.colour (what R G B hold) and,
 * from alb_exr_write's options, albatros.software, .profile, .fidelity,
 * .source.  Row 0 of the frame is the file's first (top) line;
 * dataWindow = displayWindow = (0,0)-(w-1,h-1), INCREASING_Y. */

/* Largest width or height either direction accepts. */
#define ALB_EXR_MAX_SIDE 32768u

/* Write one frame; identical frames give byte-identical files (no dates or
 * other varying attributes).  ALB_ERR_CONFIG if the frame's parameters are
 * out of range (size 1..ALB_EXR_MAX_SIDE, colour_bits 1..16, depth_bits 1..32,
 * aa_levels 0..7), ALB_ERR_NOMEM, ALB_ERR_IO.  Written through alb_out
 * (file.h): the old file stays until the new one is complete, a device or
 * FIFO is written straight through and never removed. */
alb_err alb_exr_write_frame(const char *path, const alb_frame *f, alb_diag *d);
/* The same file, its chunks compressed on up to `threads` threads (0 or 1:
 * this one only) and written in order; the bytes do not depend on the
 * number.  ZIP compression is most of a large frame's writing time. */
#define ALB_EXR_MAX_THREADS 64
alb_err alb_exr_write_frame_threads(const char *path, const alb_frame *f, unsigned threads, alb_diag *d);

/* What alb_exr_write puts in the header besides the frame: how many threads
 * compress it (the bytes do not depend on it) and where it came from.  Any
 * string may be NULL (not written). */
typedef struct {
    unsigned threads;        /* 0 or 1: this thread only */
    const char *software;    /* albatros.software: "albatros 0.1.0" */
    const char *profile;     /* albatros.profile */
    const char *fidelity;    /* albatros.fidelity: functional, timed, cycle, reference, a method */
    const char *source;      /* albatros.source: the scene or stream's file name */
} alb_exr_options;
alb_err alb_exr_write(const char *path, const alb_frame *f, const alb_exr_options *opt, alb_diag *d);

/* Read a frame written by alb_exr_write_frame back; *f is allocated with
 * alb_frame_alloc (the caller frees it with alb_frame_free) and is left empty on
 * failure.  Needs a scanline part with R, G, B; other planes are read if
 * present, otherwise: depth 0, face ALB_FRAME_NO_FACE, level ALB_FRAME_NO_LEVEL,
 * coverage 0, cycles NULL, and vp.R/G/B are derived from R/G/B by rounding
 * value * (2^colour_bits - 1).  Missing attributes default to colour_bits 8,
 * depth_bits 24, aa_levels 0, near 1, frame 0.  ALB_ERR_IO (malformed,
 * truncated or unsuitable file; the message names what), ALB_ERR_NOMEM. */
alb_err alb_exr_read_frame(const char *path, alb_frame *f, alb_diag *d);

#ifdef __cplusplus
}
#endif
#pragma GCC visibility pop

#endif
