/* profile.h — a member of the Albatros family: screen size, subdivision and
 * bit widths, bounding-edge method.  Named profiles plus key=value overrides
 * (docs/profiles.md).  Both the GP and the VP are configured from one. */
#ifndef ALBATROS_PROFILE_H
#define ALBATROS_PROFILE_H

#include "diag.h"

#include <stdbool.h>
#include <stddef.h>

/* The library exports what its public headers declare, nothing else. */
#pragma GCC visibility push(default)
#ifdef __cplusplus
extern "C" {
#endif

typedef enum {
    ALB_BOUND_NONE = 0,   /* no bounding edges */
    ALB_BOUND_ALBATROS,   /* the paper's rule: sector codes, table, <= 2 per face */
    ALB_BOUND_BOX,        /* bounding box: 4 axis-parallel edges, 90 degrees */
    ALB_BOUND_BISECTOR    /* perpendicular to each vertex bisector, 90 degrees */
} alb_bound_method;

/* The largest screen side (alb_profile_check), and the largest value --set
 * takes for any numeric field. */
#define ALB_PROFILE_MAX_SIDE 8192
#define ALB_PROFILE_MAX_VALUE 16777215u   /* 2^24 - 1: the largest frame_faces */

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
    alb_bound_method bound;
    bool cull_backfaces;      /* GP drops faces whose back the observer sees */
    /* the clocked micro-architecture (docs/microarchitecture.md) */
    unsigned clock_khz;       /* modelled clock */
    unsigned fifo_depth;      /* GP -> VP FIFO, 32-bit words */
    unsigned face_slots;      /* edge store: faces loaded ahead of the engine */
    unsigned edge_units;      /* edges the engine evaluates per clock */
    unsigned fill_rate;       /* samples the fill unit issues per clock */
    unsigned fill_queue;      /* cells between engine and fill unit */
    unsigned frame_queue;     /* FRAME registers held: the open frame's and those
                                 taken while it drains */
    unsigned divider_latency; /* reciprocal unit pipeline stages */
    unsigned shade_latency;   /* shading, texture, fog, write stages */
    unsigned gp_face_cycles;  /* GP time per face packet, before its words */
    unsigned gp_edge_cycles;  /* ... plus this per edge */
    unsigned gp_frame_cycles; /* ... per FRAME packet */
    unsigned frame_faces;     /* FACE packets a frame may carry (docs/limits.md) */
    /* the emulator, not the hardware */
    unsigned all_units;       /* 1: every shading unit for every sample (same pixels, slower) */
    unsigned simd;            /* 1: the host's fastest SIMD forms, chosen at run time; 0: the
                                 plain ones (same pixels and counts, slower) */
} alb_profile;

/* Fill *p with the named profile; returns 0, or -1 if unknown. */
int alb_profile_lookup(const char *name, alb_profile *p);
/* Names of the built-in profiles, NULL-terminated. */
const char *const *alb_profile_names(void);
/* Apply "key=value"; on error returns -1 with a message in err. */
int alb_profile_set(alb_profile *p, const char *assignment, char *err, size_t errlen);
/* Check the constraints between fields; -1 with a message on failure. */
int alb_profile_check(const alb_profile *p, char *err, size_t errlen);
/* The named profile (NULL: a512) with "key=value" overrides (a
 * NULL-terminated list, or NULL), checked: what --profile and --set give.
 * ALB_ERR_CONFIG with d saying why. */
alb_err alb_profile_open(alb_profile *p, const char *name, const char *const *sets, alb_diag *d);
/* One line per field, "key=value", as accepted by alb_profile_set. */
void alb_profile_describe(const alb_profile *p, char *buf, size_t len);

const char *alb_bound_method_name(alb_bound_method m);
int alb_bound_method_parse(const char *s, alb_bound_method *m);

/* Screen sample grid (docs/number-formats.md §3): sample coordinates are
 * integers in units of 2^-sample_shift of the screen's [-1,1] range. */
unsigned alb_profile_levels(const alb_profile *p);        /* log2(max(w,h)) + aa */
unsigned alb_profile_sample_shift(const alb_profile *p);  /* == alb_profile_levels */

#ifdef __cplusplus
}
#endif
#pragma GCC visibility pop

#endif
