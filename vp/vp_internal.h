/* vp_internal.h — the VP's state and units, shared by its files and tests. */
#ifndef ALBATROS_VP_INTERNAL_H
#define ALBATROS_VP_INTERNAL_H

#include "albatros/vp.h"

#include <stdbool.h>

/* An edge as the subdivision engine uses it: h(C, R) = a C + b R + c in
 * doubled sample coordinates (C = 2 x column, R = 2 x row, row 0 at the top;
 * a cell border at column k is C = 2k, a sample centre C = 2k + 1).  A point
 * is inside iff h >= 0; the tie rule is folded into c (docs/vp.md §2). */
typedef struct {
    int64_t a, b, c;
} vp_edge_fn;

/* A linear form evaluated at samples: N(X, Y) = mA X + mB Y + mC 2^P, with
 * X, Y the sample position in units of 2^-P of the screen (docs/vp.md §3). */
typedef struct {
    int64_t step_c;      /* N difference between neighbouring columns */
    int64_t step_r;      /* ... rows (downward) */
    int64_t origin;      /* N at sample (0, 0) */
    int exp;             /* value = N * 2^(exp - P) */
} vp_form_fn;

/* Per-face shading set-up. */
typedef struct {
    uint32_t id;
    unsigned flags;
    uint8_t rgb[3];
    vp_form_fn depth, shade, tex_u, tex_v;
    const uint32_t *texels;
    unsigned tex_log2;
    unsigned units;          /* the shading units the face uses (fill.c) */
    uint16_t flat[3];        /* its colour where it uses neither intensity nor texture */
} vp_face_setup;

struct alb_vp {
    alb_profile prof;
    unsigned sw, sh;         /* sample grid */
    unsigned lw, lh;         /* their log2 */
    unsigned p;              /* evaluation scale: max(lw, lh) = levels */
    alb_ws_config cfg;
    bool configured;
    uint32_t *s_depth;       /* sample store */
    uint32_t *s_face;
    uint8_t *s_level;
    uint16_t *s_rgb;
    uint32_t *tex[ALB_WS_MAX_TEXTURES];
    uint8_t tex_log2[ALB_WS_MAX_TEXTURES];
    alb_ws_frame frame;
    uint16_t bg[3];          /* background in frame-store units */
    uint16_t fog_rgb[3];
    alb_vp_stats st;
    uint32_t *recip_rom;
    /* the threaded functional renderer (parallel.c) */
    unsigned threads;
    struct vp_loaded_face *batch;   /* faces loaded, waiting for the workers */
    unsigned nbatch;     /* floor(2^(2RB-1) / dm) for dm in [2^(RB-1), 2^RB) */
};

/* A face as the edge store holds it: shading set-up and edge functions. */
typedef struct vp_loaded_face {
    vp_face_setup fs;
    vp_edge_fn e[ALB_WS_MAX_EDGES];
    unsigned n;
} vp_loaded_face;

/* ---- the subdivision engine as a resumable walk (vp.c) ---- */

typedef struct {
    uint32_t c0, r0;         /* top-left sample */
    uint8_t wl, hl;          /* log2 of width and height in samples */
    uint8_t level;
    uint64_t active;         /* edges not yet known to hold the cell inside */
} vp_cell;

typedef enum {
    VP_STEP_OUT,             /* an edge has the cell wholly outside */
    VP_STEP_SPLIT,           /* an edge crosses: four (or two) children pushed */
    VP_STEP_FILL,            /* every edge holds the cell: fill all its samples */
    VP_STEP_SAMPLE_IN,       /* a single sample inside every edge */
    VP_STEP_SAMPLE_OUT       /* a single sample outside some edge */
} vp_step_kind;

typedef struct {
    vp_step_kind kind;
    vp_cell cell;
    unsigned edges;          /* active edges the step evaluated */
} vp_step;

typedef struct {
    const vp_edge_fn *e;
    vp_cell stack[3 * ALB_VP_MAX_LEVELS + 4];
    unsigned top;
    /* A walk clipped to one tile — a cell of the same quadtree, so any cell
     * holds it, lies in it, or misses it: only the cells meeting the tile are
     * visited, a FILL larger than the tile fills the tile (at the cell's
     * level), and a cell is counted in vp->st only by the tile holding its
     * top-left sample.  The tiles of a level partition the screen, so their
     * walks together do and count exactly what the whole walk does. */
    bool clipped;
    vp_cell tile;
} vp_walk;

void vp_walk_begin(vp_walk *w, const alb_vp *vp, const vp_loaded_face *f);
void vp_walk_begin_tile(vp_walk *w, const alb_vp *vp, const vp_loaded_face *f, const vp_cell *tile);
/* The next cell step in the engine's order; false when the face is done.
 * Counts the cell in vp->st. */
bool vp_walk_next(alb_vp *vp, vp_walk *w, vp_step *step);
/* Write the samples of a FILL or SAMPLE_IN cell (depth test, shading), with
 * only the shading units the face uses (fill.c). */
void vp_fill(alb_vp *vp, const vp_face_setup *fs, const vp_cell *k);
/* The units a face's flags ask for, and its colour with none of them. */
unsigned vp_face_units(const vp_face_setup *fs);
void vp_flat_colour(const alb_vp *vp, const vp_face_setup *fs, uint16_t rgb[3]);
/* Faces loaded before the threads draw them, and the most tiles a screen
 * is cut into (parallel.c). */
#define VP_BATCH 1024
#define VP_MAX_TILES 1024
/* Draw the batched faces (parallel.c); nothing if the batch is empty. */
void vp_flush_batch(alb_vp *vp);
/* fn(vp, ctx, first, end) over rows [0, rows) in chunks, on the VP's
 * threads; the chunks must touch disjoint memory. */
typedef void (*vp_row_fn)(alb_vp *vp, void *ctx, uint32_t first, uint32_t end);
void vp_parallel_rows(alb_vp *vp, uint32_t rows, vp_row_fn fn, void *ctx);
/* dst += src, field by field. */
void vp_stats_add(alb_vp_stats *dst, const alb_vp_stats *src);
/* Count a face the engine takes in the frame's statistics. */
void vp_count_face(alb_vp *vp, const vp_loaded_face *f);
/* The edge store's set-up of a FACE packet; ALB_ERR_STREAM for a texture
 * never loaded. */
alb_err vp_load_face(alb_vp *vp, const alb_ws_face *f, vp_loaded_face *out, alb_diag *d);
/* Samples in a cell. */
static inline uint32_t vp_cell_samples(const vp_cell *k) { return 1u << (k->wl + k->hl); }

/* Edge set-up (vp.c). */
void vp_edge_setup(const alb_vp *vp, const alb_ws_edge *e, vp_edge_fn *fn);
void vp_form_setup(const alb_vp *vp, const alb_ws_form *f, vp_form_fn *fn);

/* Shading units (shade.c). */
uint32_t vp_depth_value(const alb_vp *vp, int64_t n, int exp);
void vp_shade_sample(const alb_vp *vp, const vp_face_setup *fs, int64_t nz, int64_t col,
                     int64_t row, uint16_t rgb[3]);
uint16_t vp_scale_colour8(const alb_vp *vp, unsigned c8);

/* The reciprocal unit: 1/n ~ rm * 2^-(2 RB - 1) * 2^-shift for n > 0. */
typedef struct {
    int64_t rm;
    int shift;
} vp_recip;
vp_recip vp_reciprocal(int64_t n, unsigned recip_bits);
/* The same through the VP's table (the hardware's reciprocal ROM). */
vp_recip vp_reciprocal_rom(const alb_vp *vp, int64_t n);
/* Build the table; -1 if out of memory. */
int vp_recip_rom_init(alb_vp *vp);
/* floor(num / den * 2^(e_num - e_den + frac)) through the reciprocal. */
int64_t vp_ratio(int64_t num, int e_num, vp_recip r, int e_den, unsigned recip_bits, int frac);

#endif
