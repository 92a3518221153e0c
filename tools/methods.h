/* methods.h — the classic hidden-surface methods the Albatros VP is compared
 * with (ALBATROS.md §8; the seeds 000, 002-004): z-buffer, scan-line
 * z-buffer, Watkins' span scan-line, Warnock's subdivision, the painter's
 * depth sort (Newell) and ray casting.  Each renders one frame of a scene into
 * the VP's frame format, sampling at pixel centres with the reference's
 * observer transform and shading (tools/ref.h), so that frames compare with
 * the VP's and the reference's pixel by pixel (docs/methods.md). */
#ifndef ALBATROS_METHODS_H
#define ALBATROS_METHODS_H

#include "albatros/profile.h"
#include "albatros/gp.h"
#include "albatros/vp.h"

typedef struct {
    const char *name;      /* "zbuffer", "painter", ... */
    const char *summary;   /* one line: what it is and how it fails */
    /* Render frame `frame` of s into out (allocated here at the profile's
     * size; free with alb_frame_free).  0 on success; -1 if out of memory, the
     * frame does not exist, or p->aa_levels is not 0 (no anti-aliasing). */
    int (*render)(const alb_scene *s, const alb_profile *p, unsigned frame, alb_frame *out);
} method;

/* Every method, in a fixed order; *n receives how many. */
const method *methods_all(unsigned *n);
/* The method called name, NULL if none is. */
const method *method_find(const char *name);

#endif
