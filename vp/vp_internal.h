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

/* A rectangle of the fill's fast loop (fill.c, vp_depth_forms): samples
 * written, samples tied, the first tied one (its offset from the first
 * sample, rows `stride` apart, if any) and the largest depth written. */
typedef struct {
    uint32_t written, ties;
    size_t first_tie;
    uint32_t nearest;
} vp_rect_result;
typedef vp_rect_result (*vp_depth_rect_fn)(uint32_t *depth, uint32_t *tag, size_t stride,
                                           uint32_t w, uint32_t h, int64_t z, int64_t dc,
                                           int64_t dr, unsigned sr, unsigned sl, uint32_t t);
typedef vp_rect_result (*vp_depth_block8_fn)(uint32_t *depth, uint32_t *tag, size_t stride,
                                             int64_t z, int64_t dc, int64_t dr, unsigned sr,
                                             unsigned sl, uint64_t mask, uint64_t mid,
                                             uint64_t fine, const uint32_t t[3]);
typedef void (*vp_depth_store_fn)(uint32_t *depth, uint32_t *tag, size_t stride, uint32_t w,
                                  uint32_t h, int64_t z, int64_t dc, int64_t dr, unsigned sr,
                                  unsigned sl, uint32_t t);
/* One form of each shape: a rectangle, a masked 8 x 8 block, and a
 * rectangle of clean tiles, stored without reading. */
typedef struct {
    vp_depth_rect_fn rect;
    vp_depth_block8_fn block8;
    vp_depth_store_fn store;
} vp_depth_forms_t;

/* Per-face shading set-up. */
typedef struct {
    uint32_t id;
    unsigned flags;
    uint8_t rgb[3];
    vp_form_fn depth, shade, tex_u, tex_v;
    const uint32_t *texels;
    unsigned tex_log2;
    unsigned units;          /* the shading units the face uses (shade.c) */
    int64_t depth_lo, depth_hi;   /* the depth form's N in the store's range
                                     (units_depth_range): the fill's fast loop */
    uint16_t flat[3];        /* its colour where it uses neither intensity nor texture */
    uint32_t tag;            /* its index in the frame's face list, << VP_TAG_LEVEL_BITS
                                (vp_begin_face): what the samples it writes hold */
} vp_face_setup;

/* A tile of the store this frame (alb_vp.tile_clean): no fill has reached
 * it (its planes are stale, read as cleared), a fill has (its planes hold
 * its samples), or — the store of counters alone — a single fill of one
 * face has covered it while clean, and its depths are that face's depth
 * form, written out only when another fill reaches it (vp_clear_tile):
 * a tile that nothing else reaches is never written. */
#define VP_TILE_TOUCHED 0
#define VP_TILE_CLEAN 1
#define VP_TILE_PLANE 2

/* A sample's tag: the face that wrote it — its index among the faces the
 * engine took this frame — and the level that decided it; VP_TAG_NONE where
 * no face did.  The colour is computed from the tag when the frame is
 * resolved (store.c), so a sample another face overwrites is never shaded. */
#define VP_TAG_LEVEL_BITS 5          /* levels 0 .. ALB_VP_MAX_LEVELS - 1 < 32 */
#define VP_TAG_LEVEL_MASK ((1u << VP_TAG_LEVEL_BITS) - 1)
#define VP_TAG_NONE 0xFFFFFFFFu
#define VP_MAX_FRAME_FACES ((1u << (32 - VP_TAG_LEVEL_BITS)) - 1)
_Static_assert(ALB_VP_MAX_LEVELS <= VP_TAG_LEVEL_MASK + 1, "a tag's level field holds every level");

struct alb_vp {
    alb_profile prof;
    unsigned sw, sh;         /* sample grid */
    unsigned lw, lh;         /* their log2 */
    unsigned p;              /* evaluation scale: max(lw, lh) = levels */
    alb_ws_config cfg;
    bool configured;
    /* the sample store (store.c): two planes, depth and tag, cleared tile by
     * tile when a fill first touches a tile in the frame; the store of
     * counters alone (vp_create_counters) has no tag plane (s_tag NULL) */
    uint32_t *s_depth;
    uint32_t *s_tag;
    /* a VP for counters alone (vp_create_counters): no tag plane, no
     * reciprocal ROM, no output stage.  A tie's kept face, which the tag
     * plane would name, is found when the frame's counters are taken
     * (vp_store_name_tie) from the edges of the frame's faces, logged as
     * they begin: face i's are edge_log[edge_at[i] .. edge_at[i + 1]) */
    bool counters_only;
    vp_edge_fn *edge_log;
    size_t nedge_log, cap_edge_log;
    size_t *edge_at;         /* cap_faces + 1 */
    uint32_t tie_lost_face;  /* the frame's index of the face that lost the lowest tie */
    uint8_t *tile_clean;     /* per tile: VP_TILE_CLEAN, VP_TILE_TOUCHED or VP_TILE_PLANE */
    uint32_t *tile_face;     /* counters alone: a VP_TILE_PLANE tile's face (frame index) */
    uint32_t *tile_floor;    /* per tile: a depth no sample of it is below this frame (0
                                until a fill covers it whole; fill.c) */
    uint32_t *block_floor;   /* the same per 8 x 8 block of samples, rows of block_row */
    unsigned block_row, block_rows;
    unsigned tile_level;     /* tiles are the quadtree's cells of this level */
    unsigned tile_wl, tile_hl;   /* their log2 width and height in samples */
    unsigned tiles_lw;       /* log2 of tiles per row */
    /* the faces the engine took this frame, for the output stage's shading */
    vp_face_setup *faces;
    uint32_t nfaces, cap_faces;
    /* per face of the frame, its flat colour as a sample's six bytes in
     * the RGB plane (store.c, flat_word), and one more entry for the
     * background: the output stage's flat frames */
    uint64_t *flat_colour;
    uint32_t *tex[ALB_WS_MAX_TEXTURES];
    uint8_t tex_log2[ALB_WS_MAX_TEXTURES];
    /* textures replaced while faces of the frame still refer to them: freed
     * when the frame is resolved */
    uint32_t **old_tex;
    unsigned nold_tex, cap_old_tex;
    bool plain_fill;         /* tests: the fill's plain loops only, no fast path */
    bool walk_avx2;          /* the functional engine's AVX2 instantiation (vp.c) */
    unsigned shade_isa;      /* the output stage's stretches: 0 plain C, 1 AVX2, 2 AVX-512
                                (shade.c) */
    vp_depth_forms_t depth_forms;   /* the fast loop's forms, the host's fastest */
    alb_ws_frame frame;
    uint16_t bg[3];          /* background in frame-store units */
    uint16_t fog_rgb[3];
    alb_vp_stats st;
    uint32_t *recip_rom;
    /* the threaded functional renderer (parallel.c) */
    unsigned char *scratch;  /* the output stage's rows, vp_store_scratch_bytes per thread */
    struct vp_loaded_face *batch;   /* faces loaded, waiting for the workers */
    struct vp_loaded_face *batches[2];   /* batch is one, the other may be drawn meanwhile */
    struct vp_pool *pool;    /* the worker threads, threads - 1 of them */
    struct batch_job *par[2];   /* their work on each batch, kept from one to the next */
    struct batch_job *inflight;   /* a batch the workers draw while the next is loaded */
    unsigned nbatch;         /* faces in the batch */
};

/* A face as the edge store holds it: shading set-up and edge functions. */
typedef struct vp_loaded_face {
    vp_face_setup fs;
    vp_edge_fn e[ALB_WS_MAX_EDGES];
    unsigned n;
    bool narrow;             /* every edge has |a| + |b| < 2^27 (vp_walk.narrow) */
} vp_loaded_face;

/* ---- the subdivision engine as a resumable walk (vp.c) ---- */

typedef struct {
    uint32_t c0, r0;         /* top-left sample */
    uint8_t wl, hl;          /* log2 of width and height in samples */
    uint8_t level;
    uint8_t edges;           /* how many: the bits of active */
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

/* An edge's values within an 8 x 8 cell relative to its top-left corner,
 * for the functional engine's 32-bit lanes (vp.c): at the centres of the
 * cell's first row of samples, at the corners of the first two rows of its
 * 2 x 2 cells and of its 4 x 4 cells, and the extremes over those. */
typedef struct {
    int32_t row0[8];         /* a (2x + 1) + b, x = 0..7 (doubled coordinates) */
    int32_t g01[8];          /* 4a gx + 4b gy, gx = 0..3, gy = 0..1 */
    int32_t t4[4];           /* 8a cx + 8b cy, cx, cy = 0..1 */
    int32_t up4, down4, up2, down2;   /* a 4 x 4 and a 2 x 2 cell's extremes */
    int32_t step2;           /* 2b: a row of samples on */
} vp_lanes8;

typedef struct {
    const vp_edge_fn *e;
    /* the face's edges are narrow: an edge crossing an 8 x 8 cell has |h| <
     * 2^31 at every point of it, so the functional engine may decide such a
     * cell's samples in 32-bit lanes (vp.c), with these offsets */
    bool narrow;
    unsigned n;              /* its edges */
    bool lanes_ready;        /* lanes computed (when the walk first needs them) */
    vp_lanes8 lanes[ALB_WS_MAX_EDGES];
    /* a narrow face's edges as arrays of a, b and c, four to a group (the
     * last group's spare lanes 0): the functional engine's children
     * verdicts four edges at a time (vp.c) */
    int64_t ea[ALB_WS_MAX_EDGES], eb[ALB_WS_MAX_EDGES], ec[ALB_WS_MAX_EDGES];
    vp_cell stack[3 * ALB_VP_MAX_LEVELS + 4];
    unsigned top;
} vp_walk;

void vp_walk_begin(vp_walk *w, const alb_vp *vp, const vp_loaded_face *f);
/* The next cell step in the engine's order; false when the face is done.
 * Counts the cell in vp->st. */
bool vp_walk_next(alb_vp *vp, vp_walk *w, vp_step *step);
/* The functional engine (vp.c): a face's whole walk with its fills, the
 * same cells, counts and samples as vp_walk_next and vp_fill step by step. */
void vp_draw_face(alb_vp *vp, const vp_loaded_face *f);
/* The same walk cut at the cells of level tl, the tiles of the threads
 * (parallel.c): vp_walk_to_tiles makes and counts the cells above them and
 * gives each tile the face reaches to `job` in the walk's order — a cell
 * found inside (fill: at its level, over every tile it holds) or a tile
 * that splits, with the edges still active; vp_draw_below walks and counts
 * the cells below such a tile.  Together they do and count exactly what
 * vp_draw_face does. */
typedef void (*vp_tile_job_fn)(void *ctx, const vp_cell *k, bool fill);
void vp_walk_to_tiles(alb_vp *vp, const vp_loaded_face *f, unsigned tl, vp_tile_job_fn job, void *ctx);
void vp_draw_below(alb_vp *vp, const vp_loaded_face *f, const vp_cell *k);
/* Whether the host runs the engine's AVX2 instantiation (vp.c). */
bool vp_walk_avx2_host(void);
/* ... and the output stage's shading forms (shade.c): 0 plain C, 1 AVX2,
 * 2 AVX-512, the best the host runs. */
unsigned vp_shade_isa_host(void);
/* What the timed model needs of a walk besides its fills: each step's
 * cycles, and at each hand-over of a FILL or SAMPLE_IN cell to the fill
 * unit, in the walk's order, the recurrences of the fill queue
 * (docs/microarchitecture.md, "Fidelities"; emu/sim_timed.c owns the rest
 * of the model).  Steps between two hand-overs only add engine cycles, so
 * the timer sums them; the hand-over takes the sum, its own step's
 * included.  The queue lives here, with the walk, so that a hand-over costs
 * no call. */
typedef struct vp_timer {
    uint8_t step_cycles[ALB_WS_MAX_EDGES + 1];   /* a step's cycles by the edges it evaluates */
    uint64_t fill_cycles[2 * (ALB_VP_MAX_LEVELS - 1) + 1];   /* a fill's by log2 of its samples */
    uint64_t pending;         /* engine cycles of the steps since the last hand-over */
    int64_t now;              /* the engine's next cycle */
    int64_t fill_free;        /* the first cycle the fill unit can take a cell */
    int64_t *take_ring;       /* the cycles it took the last fill_queue cells (at first,
                                 long before the first cycle) */
    unsigned take_slot;       /* cells % fill_queue: the oldest of them, the next to write */
    unsigned fill_queue;
    uint64_t cells;           /* cells handed over */
    uint64_t engine, stall, fill;   /* engine cycles, engine stalls, fill cycles, summed */
    /* each step's and each fill's cycles on its cell (the per-pixel cycle
     * map), or NULL */
    void (*charge)(struct vp_timer *tm, const vp_cell *k, uint64_t cycles);
    void *ctx;
} vp_timer;
/* The durations from the profile; take_ring has room for fill_queue cycles
 * (set here). */
void vp_timer_init(vp_timer *tm, const alb_profile *p, int64_t *take_ring);

/* Cells handed over to the fill unit, each in the last cycle of the
 * engine's step: cell i taking fill[i] cycles after gap[i] engine cycles
 * (the first after the timer's pending ones too), then `after` cycles of
 * steps; `engine` and `filled` are the sums of the gaps with `after` and of
 * the fills.  Engine cycles count when a hand-over ends them; those after
 * the last stay pending.  The queue held fewer than fill_queue cells at the start of a
 * hand-over's cycle (the cell fill_queue back had been taken), or the
 * engine stalls until it does; the fill unit takes the cell when it is
 * free.  (The per-pixel map's charges are the caller's.) */
/* The queue's recurrence, a hand-over at a time (vp_timer_hand_overs):
 * the engine's last cycle, the fill unit's first free one, the stalls so
 * far and the ring's next slot. */
typedef struct {
    int64_t e, fill_free;
    uint64_t stall;
    unsigned slot;
} vp_queue;

static inline vp_queue vp_queue_of(const vp_timer *tm, int64_t e)
{
    return (vp_queue){e, tm->fill_free, 0, tm->take_slot};
}

/* A cell handed over gap engine cycles after the previous, fill cycles. */
static inline __attribute__((always_inline)) void
vp_queue_take(vp_queue *q, int64_t *ring, unsigned queue, uint64_t gap, uint64_t fill)
{
    const int64_t end = q->e + (int64_t)gap, room = ring[q->slot] + 1;
    const int64_t put = room > end ? room : end;
    const int64_t take = put + 1 > q->fill_free ? put + 1 : q->fill_free;
    q->stall += (uint64_t)(put - end);
    q->fill_free = take + (int64_t)fill;
    ring[q->slot] = take;
    q->slot = q->slot + 1 == queue ? 0 : q->slot + 1;
    q->e = put;
}

/* The n hand-overs' effect on the timer (see vp_timer_hand_overs). */
static inline void vp_queue_end(vp_timer *tm, const vp_queue *q, unsigned n, uint64_t after,
                                uint64_t engine, uint64_t filled)
{
    if (n) {   /* the engine's cycles up to the last hand-over are counted */
        tm->now = q->e + 1;
        tm->engine += tm->pending + engine - after;
        tm->pending = after;
    } else {
        tm->pending += after;
    }
    tm->fill_free = q->fill_free, tm->take_slot = q->slot, tm->cells += n;
    tm->stall += q->stall, tm->fill += filled;
}

static inline void vp_timer_hand_overs(vp_timer *tm, const uint32_t *gap, const uint32_t *fill,
                                       unsigned n, uint64_t after, uint64_t engine, uint64_t filled)
{
    /* e: the engine's last cycle so far; the ring starts far in the past,
     * so the first fill_queue cells wait for none */
    vp_queue q = vp_queue_of(tm, tm->now - 1 + (int64_t)tm->pending);
    for (unsigned i = 0; i < n; i++)
        vp_queue_take(&q, tm->take_ring, tm->fill_queue, gap[i], fill[i]);
    vp_queue_end(tm, &q, n, after, engine, filled);
}

/* One cell k handed over after the timer's pending cycles. */
static inline void vp_timer_hand_over(vp_timer *tm, const vp_cell *k)
{
    const uint32_t none = 0, f = (uint32_t)tm->fill_cycles[k->wl + k->hl];
    if (tm->charge)
        tm->charge(tm, k, f);
    vp_timer_hand_overs(tm, &none, &f, 1, 0, 0, f);
}
/* vp_draw_face with a timer: the same fills and statistics, and the timer
 * called as vp_walk_next's steps would have it. */
void vp_draw_face_timed(alb_vp *vp, const vp_loaded_face *f, vp_timer *tm);
/* The samples of a FILL or SAMPLE_IN cell through the depth test: each
 * sample nearer than the store's gets the face's depth and tag (fill.c). */
void vp_fill(alb_vp *vp, const vp_face_setup *fs, const vp_cell *k);
/* The fill's fast loop (fill.c) on the samples of a rectangle of w x h, or
 * on those of an 8 x 8 block that `mask` has (bit 8 y + x), of depths z +
 * x dc + y dr, all in the store's range: stored as z >> sr << sl with tag t
 * (the block: t[0], or t[1] where `mid` has the sample, t[2] where `fine`
 * has it) where they win; counts what won and what tied; the store form
 * writes every sample of a rectangle whose store is clean.  vp_depth_forms
 * lists the forms the host can run, the fastest first (the VP takes that
 * one). */
unsigned vp_depth_forms(vp_depth_forms_t forms[3], const char *name[3]);
/* The same forms, in the same order, for the store of counters alone: the
 * same depths and results, the tag plane neither read nor written (its
 * pointer may be NULL). */
unsigned vp_depth_forms_untagged(vp_depth_forms_t forms[3], const char *name[3]);
/* The samples `mask` (bit 8 y + x) of the 8 x 8 block at (c0, r0) through
 * the depth test, decided at level l, or l + 1 where `mid` has them, l + 2
 * where `fine` has them (fill.c). */
void vp_fill_block8(alb_vp *vp, const vp_face_setup *fs, uint32_t c0, uint32_t r0, uint64_t mask,
                    uint64_t mid, uint64_t fine, uint8_t l);
/* count x size bytes for a plane of the sample store or of a frame, zeroed
 * if asked, in huge pages where the host offers them (store.c); NULL if
 * out of memory; free() frees it. */
void *vp_plane_alloc(size_t count, size_t size, bool zeroed);
/* Clear the tiles of cell k that no fill has touched yet this frame, or
 * write out those a face's plane holds (store.c); vp_touch is the same,
 * quicker for a cell within one tile. */
void vp_touch_tiles(alb_vp *vp, const vp_cell *k);
/* The store tile that holds sample (c, r). */
static inline size_t vp_tile_of(const alb_vp *vp, uint32_t c, uint32_t r)
{
    return ((size_t)(r >> vp->tile_hl) << vp->tiles_lw) + (c >> vp->tile_wl);
}
void vp_clear_tile(alb_vp *vp, size_t tile);
static inline void vp_touch(alb_vp *vp, const vp_cell *k)
{
    if (k->wl > vp->tile_wl || k->hl > vp->tile_hl) {
        vp_touch_tiles(vp, k);
        return;
    }
    size_t t = vp_tile_of(vp, k->c0, k->r0);
    if (vp->tile_clean[t])
        vp_clear_tile(vp, t);
}
/* The units a face's flags ask for, and its colour with none of them. */
unsigned vp_face_units(const vp_face_setup *fs);
void vp_flat_colour(const alb_vp *vp, const vp_face_setup *fs, uint16_t rgb[3]);
/* The colour the output stage gives sample (c, r) of face fs (shade.c):
 * only the units the face uses, or every unit with all_units=1. */
void vp_sample_colour(const alb_vp *vp, const vp_face_setup *fs, uint32_t c, uint32_t r,
                      uint16_t rgb[3]);
/* Colours of the samples [c0, c1) of row r, all of face fs, into rgb (3 per
 * sample): the forms stepped along the row, the units the face uses. */
void vp_shade_run(const alb_vp *vp, const vp_face_setup *fs, uint32_t r, uint32_t c0,
                  uint32_t c1, uint16_t *rgb);
/* The sample store (store.c): allocate it and its tiles; forget the frame's
 * faces and clean every tile; resolve into a frame. */
int vp_store_init(alb_vp *vp);
/* A VP for the timed model's counters alone (docs/microarchitecture.md,
 * "Timing without frames"): the statistics and fills of alb_vp_create's,
 * bit for bit, but its store has no tag plane and it has no reciprocal
 * ROM nor output stage — never resolve a frame from it. */
alb_err vp_create_counters(alb_vp **out, const alb_profile *prof, alb_diag *d);
/* The face that kept the frame's lowest tie (st.tie_kept) in a VP for
 * counters alone, replayed at that sample over the faces before the one
 * that lost it; call before the frame's statistics are taken (nothing in
 * a VP with a tag plane, which names it as the tie is met). */
void vp_store_name_tie(alb_vp *vp);
void vp_store_free(alb_vp *vp);
void vp_store_begin(alb_vp *vp);
void vp_store_resolve(alb_vp *vp, alb_frame *out);
/* n copies of one colour (3 per sample) (store.c). */
void vp_fill_rgb(uint16_t *out, size_t n, const uint16_t rgb[3]);
/* The output stage of a frame whose faces are all flat: a sample's colour
 * is a palette entry (alb_vp.flat_colour: a face's, and after the frame's
 * faces the background's for no face).  Samples go eight a step; a step of
 * one face (at any level), as most are where faces are large, takes its
 * colour's pattern over 48 bytes in three stores — a test whose branch
 * mispredicts where faces are small, so a row after one with many steps of
 * more than one face stores every step sample by sample (store.c). */
typedef struct {
    const uint64_t *pal;
    uint32_t nfaces;
    bool by_sample;           /* no test: every step sample by sample */
    size_t steps, mixed;      /* steps so far, and those of more than one face */
} vp_flat_rows;
/* The colours of the n > 0 samples whose tags are tag[0, n), the steps
 * counted in *fr. */
void vp_flat_samples(uint16_t *out, const uint32_t *tag, size_t n, vp_flat_rows *fr);
/* The shading units face fs uses in this frame (shade.c: bit 0 intensity,
 * 1 texture, 2 fog — a frame's choice as well as the face's); none: the
 * face's flat colour everywhere. */
static inline unsigned vp_frame_units(const alb_vp *vp, const vp_face_setup *fs)
{
    return fs->units & (vp->frame.fog ? 7u : 3u);
}
/* The output stage's scratch for one thread (vp->scratch). */
size_t vp_store_scratch_bytes(const alb_vp *vp);
/* Scratch for n threads; -1 if out of memory (parallel.c). */
int vp_scratch_for(alb_vp *vp, unsigned n);
/* The set-up of the frame's face that a tag names. */
static inline const vp_face_setup *vp_frame_face(const alb_vp *vp, uint32_t tag)
{
    return &vp->faces[tag >> VP_TAG_LEVEL_BITS];
}
/* Keep texture memory a face of this frame may still be shaded with. */
int vp_store_retire_texture(alb_vp *vp, uint32_t *texels);
/* Faces loaded before the threads draw them, and the most tiles a screen
 * is cut into (parallel.c). */
#define VP_BATCH 1024
#define VP_MAX_TILES 1024
/* Stop the VP's worker threads, every batch drawn first, and free their work; the VP
 * on one thread (parallel.c). */
void vp_threads_free(alb_vp *vp);
/* Draw the batched faces and any batch the workers still draw (parallel.c):
 * then every face given is in the store. */
void vp_flush_batch(alb_vp *vp);
/* The batch is full: its faces go to the workers, drawn while the caller
 * loads the next batch (parallel.c). */
void vp_batch_full(alb_vp *vp);
/* Room in the frame's face list for `more` faces without moving it (the
 * workers read it while faces are added); -1 if out of memory (store.c). */
int vp_store_reserve_faces(alb_vp *vp, uint32_t more);
/* fn(vp, ctx, worker, first, end) over rows [0, rows) in chunks, on the
 * VP's threads (worker < alb_vp_threads: which one); the chunks must touch
 * disjoint memory. */
typedef void (*vp_row_fn)(alb_vp *vp, void *ctx, unsigned worker, uint32_t first, uint32_t end);
void vp_parallel_rows(alb_vp *vp, uint32_t rows, vp_row_fn fn, void *ctx);
/* dst += src, field by field. */
void vp_stats_add(alb_vp_stats *dst, const alb_vp_stats *src);
/* Work cut into items, shared out between n threads (parallel.c): thread i
 * takes the items of its share from the front, then those of the others,
 * in turn from i + 1, from their backs; each item is taken once. */
typedef struct {
    struct {
        _Atomic uint64_t fb;  /* the next item from the front | one past the last << 32 */
        char pad[64 - sizeof(uint64_t)];   /* a cache line a share */
    } at[ALB_VP_MAX_THREADS];
    unsigned n;
} vp_shares;
/* Share i the items [start[i], start[i + 1]), start[n] = the count. */
void vp_shares_init_at(vp_shares *s, const unsigned *start, unsigned n);
/* `items` items in n shares as equal as can be. */
void vp_shares_init(vp_shares *s, unsigned items, unsigned n);
/* The next item for thread i into *item; false when every share is done. */
bool vp_shares_take(vp_shares *s, unsigned i, unsigned *item);
/* Items of cost[] (each at least 1) in n shares, runs in their order of
 * about the same cost: share i starts at start[i] (start[n] = items); and
 * order[] the items of each share, the costliest first (ties in their
 * order), at the share's own places. */
void vp_share_by_cost(const uint64_t *cost, unsigned items, unsigned n, unsigned *start, uint16_t *order);
/* A face the engine takes: counted in the frame's statistics and added to
 * its face list, which gives it its tag.  ALB_ERR_NOMEM, or ALB_ERR_STREAM
 * past VP_MAX_FRAME_FACES faces in a frame (d says which). */
alb_err vp_begin_face(alb_vp *vp, vp_loaded_face *f, alb_diag *d);
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
