/* png.h — 8-bit RGB PNG previews of a frame's planes (colour, depth, face
 * ids, decision levels, cycles, coverage) and a diff image of two frames,
 * through libpng's simplified writer.  Output is deterministic (no time chunk). */
#ifndef ALBATROS_PREVIEW_H
#define ALBATROS_PREVIEW_H

#include "diag.h"
#include "vp.h"

/* The library exports what its public headers declare, nothing else. */
#pragma GCC visibility push(default)
#ifdef __cplusplus
extern "C" {
#endif

typedef enum {
    ALB_PREVIEW_COLOUR,    /* frame store scaled to 8 bits, rounded */
    ALB_PREVIEW_DEPTH,     /* grey: nearest white .. farthest 40, log2 scale; no face black */
    ALB_PREVIEW_FACE,      /* a saturated hue hashed from the face id; no face black */
    ALB_PREVIEW_LEVEL,     /* ramp blue (level 0, a large cell) .. red (the last level:
                         * log2(max(w,h)) + aa); no face black */
    ALB_PREVIEW_CYCLES,    /* heat map black-red-yellow-white, scaled by the frame's max */
    ALB_PREVIEW_COVERAGE   /* grey = coverage / 4^aa */
} alb_preview_view;

/* Write an 8-bit RGB PNG of one view of the frame.  The false-colour views
 * (level, cycles, depth) add their colour key below the frame's H rows
 * (docs/vp.md §7).  ALB_ERR_CONFIG if the view needs a plane the frame
 * lacks (cycles) or the frame's parameters are unusable; ALB_ERR_IO (through
 * alb_out, file.h: the old file stays until the new one is complete);
 * ALB_ERR_NOMEM. */
alb_err alb_preview_write(const char *path, const alb_frame *f, alb_preview_view view, alb_diag *d);

/* Parse "colour|depth|face|level|cycles|coverage"; 0, or -1 if unknown. */
int alb_preview_view_parse(const char *name, alb_preview_view *view);
const char *alb_preview_view_name(alb_preview_view view);

/* Diff image of two frames of equal size: grey (the first frame's colour at
 * 1/4 of its luminance) where they agree, bright red where the face ids
 * differ, yellow where only the colour differs (any channel; frames of
 * different colour_bits are compared as value / (2^colour_bits - 1)).
 * *face_diff counts the red pixels; *colour_diff counts every pixel whose
 * colour differs, whether or not its face id differs too.  Either may be
 * NULL.  ALB_ERR_MISMATCH (with nothing written) if the sizes differ. */
alb_err alb_preview_write_diff(const char *path, const alb_frame *a, const alb_frame *b,
                       unsigned *face_diff, unsigned *colour_diff, alb_diag *d);

#ifdef __cplusplus
}
#endif
#pragma GCC visibility pop

#endif
