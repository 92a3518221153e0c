/* profile.h — a member of the Albatros family: screen size, subdivision and
 * bit widths, bounding-edge method.  Named profiles plus key=value overrides
 * (docs/profiles.md).  Both the GP and the VP are configured from one. */
#ifndef ALBATROS_PROFILE_H
#define ALBATROS_PROFILE_H

#include <stdbool.h>
#include <stddef.h>

typedef enum {
    BOUND_NONE = 0,   /* no bounding edges */
    BOUND_ALBATROS,   /* the paper's rule: sector codes, table, <= 2 per face */
    BOUND_BOX,        /* bounding box: 4 axis-parallel edges, 90 degrees */
    BOUND_BISECTOR    /* perpendicular to each vertex bisector, 90 degrees */
} bound_method;

/* The largest screen side (profile_check), and the largest value --set
 * takes for any numeric field. */
#define PROFILE_MAX_SIDE 8192
#define PROFILE_MAX_VALUE 16777215u   /* 2^24 - 1: the largest frame_faces */

typedef struct {
    char name[32];
    unsigned width, height;   /* pixels; powers of two */
    unsigned aa_levels;       /* extra subdivision levels below the pixel */
    unsigned edge_frac_bits;  /* F of the unsigned 3.F edge intercepts */
    unsigned coef_bits;       /* signed mantissa bits of linear forms */
    unsigned depth_bits;      /* depth store: unsigned 0.depth_bits of near/Z */
    unsigned colour_bits;     /* frame store bits per colour channel */
    unsigned recip_bits;      /* mantissa bits of the VP's reciprocal unit */
    unsigned shade_frac_bits; /* fraction bits of intensity after eq. (7) */
    bound_method bound;
    bool cull_backfaces;      /* GP drops faces whose back the observer sees */
    /* the clocked micro-architecture (docs/microarchitecture.md) */
    unsigned clock_khz;       /* modelled clock */
    unsigned fifo_depth;      /* GP -> VP FIFO, 32-bit words */
    unsigned face_slots;      /* edge store: faces loaded ahead of the engine */
    unsigned edge_units;      /* edges the engine evaluates per clock */
    unsigned fill_rate;       /* samples the fill unit issues per clock */
    unsigned fill_queue;      /* cells between engine and fill unit */
    unsigned divider_latency; /* reciprocal unit pipeline stages */
    unsigned shade_latency;   /* shading, texture, fog, write stages */
    unsigned gp_face_cycles;  /* GP time per face packet, before its words */
    unsigned gp_edge_cycles;  /* ... plus this per edge */
    unsigned gp_frame_cycles; /* ... per FRAME packet */
    unsigned frame_faces;     /* FACE packets a frame may carry (docs/limits.md) */
    /* the emulator, not the hardware */
    unsigned all_units;       /* 1: every shading unit for every sample (same pixels, slower) */
} profile_t;

/* Fill *p with the named profile; returns 0, or -1 if unknown. */
int profile_lookup(const char *name, profile_t *p);
/* Names of the built-in profiles, NULL-terminated. */
const char *const *profile_names(void);
/* Apply "key=value"; on error returns -1 with a message in err. */
int profile_set(profile_t *p, const char *assignment, char *err, size_t errlen);
/* Check the constraints between fields; -1 with a message on failure. */
int profile_check(const profile_t *p, char *err, size_t errlen);
/* One line per field, "key=value", as accepted by profile_set. */
void profile_describe(const profile_t *p, char *buf, size_t len);

const char *bound_method_name(bound_method m);
int bound_method_parse(const char *s, bound_method *m);

/* Screen sample grid (docs/number-formats.md §3): sample coordinates are
 * integers in units of 2^-sample_shift of the screen's [-1,1] range. */
unsigned profile_levels(const profile_t *p);        /* log2(max(w,h)) + aa */
unsigned profile_sample_shift(const profile_t *p);  /* == profile_levels */

#endif
