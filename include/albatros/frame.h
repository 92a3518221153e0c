/* frame.h — a finished frame as the VP's output stage delivers it: the frame
 * store (colour), depth store, face ids, decision levels and coverage, per
 * pixel, row 0 at the top of the screen (docs/vp.md, "Frames").  Sinks (EXR,
 * PNG, USB) read this and nothing else of the VP.  Part of the VP library's
 * public interface: include vp/vp.h, which includes this. */
#ifndef ALBATROS_FRAME_H
#define ALBATROS_FRAME_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/* The library exports what its public headers declare, nothing else. */
#pragma GCC visibility push(default)
#ifdef __cplusplus
extern "C" {
#endif

#define ALB_FRAME_NO_FACE  0xFFFFFFFFu  /* face.id where no face covers the pixel */
#define ALB_FRAME_NO_LEVEL 0xFFu        /* vp.level where no face covers the pixel */

typedef struct {
    unsigned width, height;     /* pixels */
    unsigned colour_bits;       /* frame store values are 0 .. 2^colour_bits - 1 */
    unsigned depth_bits;        /* depth store values are near/Z in 0.depth_bits */
    unsigned aa_levels;         /* samples per pixel: 4^aa_levels */
    float near;                 /* the scene's near distance (for Z in scene units) */
    uint32_t number;            /* frame number from the stream */
    uint16_t *rgb;              /* 3 per pixel: R, G, B frame store values */
    uint32_t *depth;            /* depth store of the pixel's nearest sample; 0 = none */
    uint32_t *face;             /* face id of that sample, ALB_FRAME_NO_FACE if none */
    uint8_t *level;             /* subdivision level that decided that sample */
    uint16_t *coverage;         /* covered samples of 4^aa_levels */
    uint32_t *cycles;           /* VP cycles spent per pixel; NULL when not modelled */
} alb_frame;

/* Allocate a frame's planes (cycles only if with_cycles); -1 if out of memory. */
int alb_frame_alloc(alb_frame *f, unsigned width, unsigned height, bool with_cycles);
/* The planes of a frame, for a frame with only some of them: the output
 * stage (alb_vp_frame_end) resolves only the planes a frame has, so a sink
 * that needs the colour alone pays for the colour alone; the others stay
 * NULL.  A frame with every plane is what the sinks, the comparisons and
 * the digest take. */
#define ALB_FRAME_RGB      0x01u
#define ALB_FRAME_DEPTH    0x02u
#define ALB_FRAME_FACE     0x04u
#define ALB_FRAME_LEVEL    0x08u
#define ALB_FRAME_COVERAGE 0x10u
#define ALB_FRAME_CYCLES   0x20u
#define ALB_FRAME_PLANES   0x1Fu   /* every plane but cycles */
int alb_frame_alloc_planes(alb_frame *f, unsigned width, unsigned height, unsigned planes);
/* The planes a frame has (ALB_FRAME_* bits). */
unsigned alb_frame_planes(const alb_frame *f);
void alb_frame_free(alb_frame *f);
/* Deep copy into dst (allocated here, with the planes src has); -1 if out
 * of memory. */
int alb_frame_copy(alb_frame *dst, const alb_frame *src);

/* Z in scene units of a depth store value: near / (d / 2^depth_bits);
 * +infinity for d = 0 (no surface). */
float alb_frame_z(const alb_frame *f, uint32_t d);

/* How two frames of one size differ (albatros compare, the tests). */
typedef struct {
    size_t pixels, face_diff, colour_diff, coverage_diff;
    unsigned max_error;         /* largest channel difference, frame-store units */
    double mean_error;          /* mean absolute channel difference */
    double psnr;                /* dB against 2^colour_bits - 1; +inf if equal */
} alb_frame_diff;
void alb_frame_compare(const alb_frame *a, const alb_frame *b, alb_frame_diff *r);
/* The first pixel (raster order) and plane where two frames of one size
 * differ, in the order face.id, vp.R, vp.G, vp.B, vp.depth, vp.level,
 * vp.coverage, vp.cycles (where both have them): true with *at the pixel's
 * index, *channel its name and *va, *vb the values; false if none.  *count
 * (may be NULL) gets the number of pixels that differ. */
bool alb_frame_first_diff(const alb_frame *a, const alb_frame *b, size_t *at,
                          const char **channel, uint64_t *va, uint64_t *vb, size_t *count);
/* Pixels where any plane differs — colour, depth, face, level, coverage, and
 * cycles where both have them; (size_t)-1 if the sizes or formats differ. */
size_t alb_frame_count_differences(const alb_frame *a, const alb_frame *b);
/* One number for the exact planes and format of a frame: CRC-32 over R, G,
 * B, depth, face, level, coverage (and cycles if present) pixel by pixel,
 * then the size and formats (emu/frame_out.c; docs/golden-vectors.md). */
uint32_t alb_frame_digest(const alb_frame *f);

#ifdef __cplusplus
}
#endif
#pragma GCC visibility pop

#endif
