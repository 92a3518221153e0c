/* store.c — the sample store and the output stage (docs/vp.md §6, §8).
 *
 * The store holds two planes a sample: its depth and a tag naming the face
 * that wrote it and the level that decided it.  A frame starts with every
 * tile clean — a tile is a cell of one level of the subdivision quadtree —
 * and a tile is cleared only when a fill first touches it, so a frame pays
 * for the part of the screen its faces reach.  Colour is the output stage's
 * work: when the frame is resolved, each sample's colour comes from the face
 * its tag names (the frame keeps the faces it drew), with the same units and
 * the same arithmetic the fill would have used — so a sample that a nearer
 * face overwrites is never shaded.  The store of counters alone (the timed
 * model without frames) has the depth plane only; a tie's kept face is
 * replayed from the frame's faces instead (vp_store_name_tie). */
#define _DEFAULT_SOURCE   /* madvise's MADV_HUGEPAGE, where the C library has it */
#include "units.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#if defined(__linux__)
#include <sys/mman.h>
#endif

#include "simd.h"

/* Tiles of at most 16 x 16 samples: the cells of level max(levels - 4, 0). */
#define TILE_LOG2 4

/* The store's two planes are one block, the tag plane TAG_SKEW samples
 * (2 KiB + 64 bytes) past the end of the depth plane.  A fill reads and
 * writes a sample's depth and then its tag; were the planes a multiple of
 * 4 KiB apart (as two blocks aligned to huge pages are), every tag load
 * would share its address's low 12 bits with the depth store just before
 * it, which the processor's memory disambiguation takes for a dependence
 * (4K aliasing), and both rows would fall in the same sets of the L1
 * cache: 10 to 15% of a 1000-face frame (docs/performance.md). */
#define TAG_SKEW 528

/* A plane of the store or of a frame (vp_internal.h).  From 2 MiB up it is
 * aligned to 2 MiB and offered to Linux's transparent huge pages (madvise):
 * a 1024 x 1024 store is 8 MiB, whose first touch in a fresh process cost
 * 2048 page faults, half of a timed run without frames (docs/performance.md);
 * with huge pages it costs four.  A hint, refused silently where the kernel
 * or the C library has none; the memory is free()d either way. */
#define HUGE_PAGE ((size_t)2 << 20)
void *vp_plane_alloc(size_t count, size_t size, bool zeroed)
{
    if (size && count > SIZE_MAX / size)
        return NULL;
    const size_t bytes = count * size;
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    if (bytes >= HUGE_PAGE) {
        void *p = NULL;
        if (posix_memalign(&p, HUGE_PAGE, bytes))
            return NULL;
        (void)madvise(p, bytes & ~(HUGE_PAGE - 1), MADV_HUGEPAGE);
        return zeroed ? memset(p, 0, bytes) : p;
    }
#endif
    return zeroed ? calloc(count, size) : malloc(bytes);
}

int vp_store_init(alb_vp *vp)
{
    vp->tile_level = vp->p > TILE_LOG2 ? vp->p - TILE_LOG2 : 0;
    vp->tile_wl = vp->lw > vp->tile_level ? vp->lw - vp->tile_level : 0;
    vp->tile_hl = vp->lh > vp->tile_level ? vp->lh - vp->tile_level : 0;
    vp->tiles_lw = vp->lw - vp->tile_wl;
    size_t n = (size_t)vp->sw * vp->sh, tiles = (size_t)1 << (vp->tiles_lw + vp->lh - vp->tile_hl);
    /* counters alone need no tag plane: half the store's memory traffic */
    const size_t planes = vp->counters_only ? n : n + TAG_SKEW + n;
    vp->s_depth = vp_plane_alloc(planes, sizeof *vp->s_depth, false);
    vp->s_tag = vp->counters_only || !vp->s_depth ? NULL : vp->s_depth + n + TAG_SKEW;
    vp->tile_clean = malloc(tiles);
    vp->tile_face = vp->counters_only ? malloc(tiles * sizeof *vp->tile_face) : NULL;
    vp->tile_floor = calloc(tiles, sizeof *vp->tile_floor);
    vp->block_row = (vp->sw + 7) >> 3, vp->block_rows = (vp->sh + 7) >> 3;
    vp->block_floor = calloc((size_t)vp->block_row * vp->block_rows, sizeof *vp->block_floor);
    if (!vp->s_depth || (!vp->counters_only && !vp->s_tag) || !vp->tile_clean || !vp->tile_floor ||
        !vp->block_floor ||
        (vp->counters_only && !vp->tile_face))
        return -1;
    memset(vp->tile_clean, VP_TILE_CLEAN, tiles);
    return 0;
}

static void free_old_textures(alb_vp *vp)
{
    for (unsigned i = 0; i < vp->nold_tex; i++)
        free(vp->old_tex[i]);
    vp->nold_tex = 0;
}

void vp_store_free(alb_vp *vp)
{
    free_old_textures(vp);
    free(vp->old_tex);
    free(vp->faces);
    free(vp->flat_colour);
    free(vp->s_depth);   /* and the tag plane, in the same block */
    free(vp->tile_clean);
    free(vp->tile_face);
    free(vp->tile_floor);
    free(vp->block_floor);
    free(vp->edge_log);
    free(vp->edge_at);
}

void vp_store_begin(alb_vp *vp)
{
    const size_t tiles = (size_t)1 << (vp->tiles_lw + vp->lh - vp->tile_hl);
    memset(vp->tile_clean, VP_TILE_CLEAN, tiles);
    memset(vp->tile_floor, 0, tiles * sizeof *vp->tile_floor);
    memset(vp->block_floor, 0, (size_t)vp->block_row * vp->block_rows * sizeof *vp->block_floor);
    vp->nfaces = 0;
    vp->nedge_log = 0;
    free_old_textures(vp);
}

int vp_store_retire_texture(alb_vp *vp, uint32_t *texels)
{
    if (!vp->nfaces) {        /* no face of the frame can refer to it */
        free(texels);
        return 0;
    }
    if (vp->nold_tex == vp->cap_old_tex) {
        unsigned cap = vp->cap_old_tex ? 2 * vp->cap_old_tex : 4;
        uint32_t **n = realloc(vp->old_tex, cap * sizeof *n);
        if (!n)
            return -1;
        vp->old_tex = n;
        vp->cap_old_tex = cap;
    }
    vp->old_tex[vp->nold_tex++] = texels;
    return 0;
}

/* The face's edges onto the frame's log (a VP for counters alone, which
 * replays them at a tie: vp_store_name_tie); -1 if out of memory. */
static int log_edges(alb_vp *vp, const vp_loaded_face *f)
{
    if (vp->nedge_log + f->n > vp->cap_edge_log) {
        size_t cap = vp->cap_edge_log ? 2 * vp->cap_edge_log : 1024;
        while (cap < vp->nedge_log + f->n)
            cap *= 2;
        vp_edge_fn *n = realloc(vp->edge_log, cap * sizeof *n);
        if (!n)
            return -1;
        vp->edge_log = n;
        vp->cap_edge_log = cap;
    }
    if (f->n)   /* a face of no edges (the whole screen) logs none */
        memcpy(vp->edge_log + vp->nedge_log, f->e, f->n * sizeof *f->e);
    vp->edge_at[vp->nfaces] = vp->nedge_log;
    vp->nedge_log += f->n;
    vp->edge_at[vp->nfaces + 1] = vp->nedge_log;
    return 0;
}

/* Sample (c, r) inside every edge of a face: decided at its centre, as
 * the walk decides it at whatever level (docs/vp.md §2: a cell inside
 * every edge has every sample centre inside, a cell outside one edge every
 * centre outside it). */
static bool centre_inside(const vp_edge_fn *e, size_t n, uint32_t c, uint32_t r)
{
    const int64_t cc = 2 * (int64_t)c + 1, rr = 2 * (int64_t)r + 1;
    for (size_t i = 0; i < n; i++)
        if (e[i].a * cc + e[i].b * rr + e[i].c < 0)
            return false;
    return true;
}

void vp_store_name_tie(alb_vp *vp)
{
    if (vp->s_tag || !vp->st.depth_ties)
        return;
    /* the store's sample before the losing face is the fill's rule run over
     * the faces before it: a face writes where strictly nearer, so the tag
     * would name the first of them with the largest depth there */
    const uint32_t c = (uint32_t)(vp->st.tie_sample & (vp->sw - 1)),
                   r = (uint32_t)(vp->st.tie_sample >> vp->lw);
    const int64_t dmax = ((int64_t)1 << vp->prof.depth_bits) - 1;
    uint32_t depth = 0, kept = 0;
    for (uint32_t i = 0; i < vp->tie_lost_face; i++) {
        const vp_face_setup *fs = &vp->faces[i];
        const size_t at = vp->edge_at[i], n = vp->edge_at[i + 1] - at;
        if (n && !centre_inside(vp->edge_log + at, n, c, r))   /* no edges: the whole screen */
            continue;
        const uint32_t dv = units_depth(units_form_at(&fs->depth, c, r),
                                        units_depth_shift(vp, fs->depth.exp), dmax);
        if (dv > depth) {
            depth = dv;
            kept = i;
        }
    }
    vp->st.tie_kept = vp->faces[kept].id;
}

/* A colour's three channels in one word: the six bytes of a sample of the
 * RGB plane as the plane holds them (red in the low 16 bits on a
 * little-endian host, as every one with SSE2), two bytes of zero. */
static uint64_t flat_word(const uint16_t rgb[3])
{
    uint64_t w = 0;
    memcpy(&w, rgb, 3 * sizeof *rgb);
    return w;
}

int vp_store_reserve_faces(alb_vp *vp, uint32_t more)
{
    uint64_t want = (uint64_t)vp->nfaces + more;
    want = want < VP_MAX_FRAME_FACES ? want : VP_MAX_FRAME_FACES;
    if (vp->cap_faces >= want)
        return 0;
    uint64_t cap = vp->cap_faces ? 2 * (uint64_t)vp->cap_faces : 256;
    while (cap < want)
        cap *= 2;
    cap = cap < VP_MAX_FRAME_FACES ? cap : VP_MAX_FRAME_FACES;
    vp_face_setup *n = realloc(vp->faces, (size_t)cap * sizeof *n);
    if (!n)
        return -1;
    vp->faces = n;
    uint64_t *fc = realloc(vp->flat_colour, ((size_t)cap + 1) * sizeof *fc);
    if (!fc)
        return -1;
    vp->flat_colour = fc;
    if (vp->counters_only) {
        size_t *at = realloc(vp->edge_at, ((size_t)cap + 1) * sizeof *at);
        if (!at)
            return -1;
        vp->edge_at = at;
    }
    vp->cap_faces = (uint32_t)cap;
    return 0;
}

alb_err vp_begin_face(alb_vp *vp, vp_loaded_face *f, alb_diag *d)
{
    if (vp->nfaces == VP_MAX_FRAME_FACES)
        return alb_diag_at(d, ALB_ERR_STREAM, "", 0, 0,
                           "more than %u faces in frame %u: the sample store's tags name at most "
                           "that many", VP_MAX_FRAME_FACES, vp->frame.number);
    if (vp->nfaces == vp->cap_faces && vp_store_reserve_faces(vp, 1))
        return alb_diag_at(d, ALB_ERR_NOMEM, "", 0, 0, "out of memory for the frame's faces");
    if (vp->counters_only && log_edges(vp, f))
        return alb_diag_at(d, ALB_ERR_NOMEM, "", 0, 0, "out of memory for the frame's edges");
    f->fs.tag = vp->nfaces << VP_TAG_LEVEL_BITS;
    vp->flat_colour[vp->nfaces] = flat_word(f->fs.flat);
    vp->faces[vp->nfaces++] = f->fs;
    vp->st.faces++;
    vp->st.edges += f->n;
    vp->st.faces_shaded += (f->fs.flags & ALB_WS_FACE_SHADE) != 0;
    vp->st.faces_textured += (f->fs.flags & ALB_WS_FACE_TEXTURE) != 0;
    vp->st.faces_fogged += vp->frame.fog && (f->fs.flags & ALB_WS_FACE_FOG);
    return ALB_OK;
}

/* ---- clearing ---- */

/* Rows of w samples from idx on cleared: depth 0, no surface, and the tag
 * VP_TAG_NONE where the store has tags. */
static inline __attribute__((always_inline)) void clear_rows(alb_vp *vp, size_t idx, uint32_t w,
                                                             uint32_t h)
{
    for (uint32_t r = 0; r < h; r++, idx += vp->sw) {
        memset(vp->s_depth + idx, 0, w * sizeof *vp->s_depth);
        if (vp->s_tag)
            memset(vp->s_tag + idx, 0xFF, w * sizeof *vp->s_tag);
    }
}

void vp_clear_tile(alb_vp *vp, size_t t)
{
    uint32_t tc = (uint32_t)(t & (((size_t)1 << vp->tiles_lw) - 1)), tr = (uint32_t)(t >> vp->tiles_lw);
    uint32_t w = 1u << vp->tile_wl, h = 1u << vp->tile_hl;
    size_t idx = ((size_t)tr << vp->tile_hl) * vp->sw + ((size_t)tc << vp->tile_wl);
    if (vp->tile_clean[t] == VP_TILE_PLANE) {
        /* the face's depths, as its fill would have stored them (fill.c,
         * fill_tiles: in the store's range, the fast form's shifts) */
        const vp_face_setup *fs = &vp->faces[vp->tile_face[t]];
        const uint32_t c0 = tc << vp->tile_wl, r0 = tr << vp->tile_hl;
        const int sh = units_depth_shift(vp, fs->depth.exp);
        vp->depth_forms.store(vp->s_depth + idx, NULL, vp->sw, w, h, units_form_at(&fs->depth, c0, r0),
                              fs->depth.step_c, fs->depth.step_r, sh < 0 ? (unsigned)-sh : 0,
                              sh > 0 ? (unsigned)sh : 0, 0);
        vp->tile_clean[t] = VP_TILE_TOUCHED;
        return;
    }
    /* a tile of 16 samples a row (every store of 16 x 16 samples or more)
     * with the width a constant: stores the compiler unrolls, not a call a
     * row and plane */
    if (w == 16)
        clear_rows(vp, idx, 16, h);
    else
        clear_rows(vp, idx, w, h);
    vp->tile_clean[t] = VP_TILE_TOUCHED;
}

void vp_touch_tiles(alb_vp *vp, const vp_cell *k)
{
    uint32_t tc0 = k->c0 >> vp->tile_wl, tc1 = (k->c0 + (1u << k->wl) - 1) >> vp->tile_wl;
    uint32_t tr0 = k->r0 >> vp->tile_hl, tr1 = (k->r0 + (1u << k->hl) - 1) >> vp->tile_hl;
    for (uint32_t tr = tr0; tr <= tr1; tr++)
        for (uint32_t tc = tc0; tc <= tc1; tc++) {
            size_t t = ((size_t)tr << vp->tiles_lw) + tc;
            if (vp->tile_clean[t])
                vp_clear_tile(vp, t);
        }
}

/* ---- the output stage ---- */

/* n copies of one sample's colour: eight samples (48 bytes, three 16-byte
 * stores) a step where the host has SSE2, then one at a time. */
#if VP_SSE2
/* Eight samples of one colour: its pattern over 48 bytes. */
static inline void store8_rgb(uint16_t *out, __m128i p0, __m128i p1, __m128i p2)
{
    __m128i *o = (__m128i *)(void *)out;
    _mm_storeu_si128(o, p0);
    _mm_storeu_si128(o + 1, p1);
    _mm_storeu_si128(o + 2, p2);
}

/* A colour's pattern over 48 bytes (eight samples) as three registers,
 * from its word (flat_word, little-endian: x = r | g << 16 | b << 32): the
 * words A = r g b r, B = g b r g, C = b r g b, as A B, C A, B C. */
static inline void rgb_pattern(uint64_t x, __m128i p[3])
{
    const uint64_t A = x | x << 48, B = x >> 16 | x << 32, C = x >> 32 | x << 16;
    p[0] = _mm_set_epi64x((long long)B, (long long)A);
    p[1] = _mm_set_epi64x((long long)A, (long long)C);
    p[2] = _mm_set_epi64x((long long)C, (long long)B);
}
#endif

void vp_fill_rgb(uint16_t *out, size_t n, const uint16_t rgb[3])
{
    size_t i = 0;
#if VP_SSE2
    __m128i p[3];
    rgb_pattern(flat_word(rgb), p);
    const __m128i p0 = p[0], p1 = p[1], p2 = p[2];
    if (n >= 8) {
        for (; i + 8 <= n; i += 8)
            store8_rgb(out + 3 * i, p0, p1, p2);
        if (i < n)   /* the last eight, over some already written: the same values */
            store8_rgb(out + 3 * (n - 8), p0, p1, p2);
        return;
    }
    if (n >= 4) {   /* four samples (24 bytes) at the start and at the end */
        _mm_storeu_si128((__m128i *)(void *)out, p0);
        _mm_storel_epi64((__m128i *)(void *)(out + 8), p1);
        _mm_storeu_si128((__m128i *)(void *)(out + 3 * (n - 4)), p0);
        _mm_storel_epi64((__m128i *)(void *)(out + 3 * (n - 4) + 8), p1);
        return;
    }
#endif
    for (; i < n; i++)
        memcpy(out + 3 * i, rgb, 3 * sizeof *out);
}

/* The plane fills below by 16 bytes where the host has SSE2; the same
 * stores either way. */
static void fill_u32(uint32_t *out, size_t n, uint32_t v)
{
    size_t i = 0;
#if VP_SSE2
    const __m128i x = _mm_set1_epi32((int)v);
    for (; i + 4 <= n; i += 4)
        _mm_storeu_si128((__m128i *)(void *)(out + i), x);
#endif
    for (; i < n; i++)
        out[i] = v;
}

static void fill_u16(uint16_t *out, size_t n, uint16_t v)
{
    size_t i = 0;
#if VP_SSE2
    const __m128i x = _mm_set1_epi16((short)v);
    for (; i + 8 <= n; i += 8)
        _mm_storeu_si128((__m128i *)(void *)(out + i), x);
#endif
    for (; i < n; i++)
        out[i] = v;
}

/* The level field of n tags. */
static void levels_of(uint8_t *out, const uint32_t *tag, size_t n)
{
    size_t i = 0;
#if VP_SSE2
    const __m128i m = _mm_set1_epi32((int)VP_TAG_LEVEL_MASK);
    for (; i + 16 <= n; i += 16) {
        const __m128i *t = (const __m128i *)(const void *)(tag + i);
        /* levels < 32: the signed saturating packs keep them */
        __m128i a = _mm_packs_epi32(_mm_and_si128(_mm_loadu_si128(t), m),
                                    _mm_and_si128(_mm_loadu_si128(t + 1), m));
        __m128i b = _mm_packs_epi32(_mm_and_si128(_mm_loadu_si128(t + 2), m),
                                    _mm_and_si128(_mm_loadu_si128(t + 3), m));
        _mm_storeu_si128((__m128i *)(void *)(out + i), _mm_packus_epi16(a, b));
    }
#endif
    for (; i < n; i++)
        out[i] = (uint8_t)(tag[i] & VP_TAG_LEVEL_MASK);
}

/* Where a row's samples go: with aa = 0 straight into the frame's pixel
 * planes (face, level, coverage), else into tag rows the pixels are
 * resolved from. */
typedef struct {
    uint16_t *rgb;
    uint32_t *depth;
    uint32_t *tag;            /* aa > 0 */
    uint32_t *face;           /* aa = 0 */
    uint8_t *level;
    uint16_t *coverage;
} row_out;

/* Samples [c, e) with no surface: the background.  Planes the frame lacks
 * (NULL) are left out, here and below. */
static inline void emit_none(const alb_vp *vp, const row_out *o, uint32_t c, uint32_t e,
                             const bool pixels)
{
    if (o->rgb)
        vp_fill_rgb(o->rgb + 3 * (size_t)c, e - c, vp->bg);
    if (pixels) {
        if (o->face)
            fill_u32(o->face + c, e - c, ALB_FRAME_NO_FACE);
        if (o->level)
            memset(o->level + c, ALB_FRAME_NO_LEVEL, e - c);
        if (o->coverage)
            fill_u16(o->coverage + c, e - c, 0);
    } else {
        fill_u32(o->tag + c, e - c, VP_TAG_NONE);
    }
}

/* Samples [c, e) of row r, all written by one face. */
static inline void emit_face(const alb_vp *vp, const row_out *o, const uint32_t *tag, uint32_t r,
                             uint32_t c, uint32_t e, const bool pixels)
{
    const vp_face_setup *fs = &vp->faces[tag[c] >> VP_TAG_LEVEL_BITS];
    if (o->rgb && !vp->prof.all_units && !vp_frame_units(vp, fs))
        vp_fill_rgb(o->rgb + 3 * (size_t)c, e - c, fs->flat);   /* vp_shade_run's, without the calls */
    else if (o->rgb)
        vp_shade_run(vp, fs, r, c, e, o->rgb + 3 * (size_t)c);
    if (pixels) {
        if (o->face)
            fill_u32(o->face + c, e - c, fs->id);
        if (o->level)
            levels_of(o->level + c, tag + c, e - c);
        if (o->coverage)
            fill_u16(o->coverage + c, e - c, 1);
    } else {
        memcpy(o->tag + c, tag + c, (e - c) * sizeof *tag);
    }
}

#if VP_SSE2
/* Of the eight tags from tag on, the lanes (a: the first four, b: the
 * next) where the tag, its level bits cleared by m, is `face`. */
static inline void face_lanes8(const uint32_t *tag, __m128i face, __m128i m, __m128i *a, __m128i *b)
{
    const __m128i *p = (const __m128i *)(const void *)tag;
    *a = _mm_cmpeq_epi32(_mm_and_si128(_mm_loadu_si128(p), m), face);
    *b = _mm_cmpeq_epi32(_mm_and_si128(_mm_loadu_si128(p + 1), m), face);
}

/* Whether all eight are (one test for both halves). */
static inline bool face_all8(__m128i a, __m128i b)
{
    return (unsigned)_mm_movemask_epi8(_mm_and_si128(a, b)) == 0xFFFF;
}
#endif

/* The end of the run of samples from e on (before d) whose tags name the
 * face of tag t, at whatever level. */
static inline uint32_t run_end(const uint32_t *tag, uint32_t e, uint32_t d, uint32_t t)
{
#if VP_SSE2
    const __m128i face = _mm_set1_epi32((int)(t & ~VP_TAG_LEVEL_MASK)),
                  m = _mm_set1_epi32((int)~VP_TAG_LEVEL_MASK);
    /* eight a step while they match, then four */
    for (; e + 8 <= d; e += 8) {
        __m128i a, b;
        face_lanes8(tag + e, face, m, &a, &b);
        if (!face_all8(a, b)) {   /* the first sample of another face: four bits a sample */
            const unsigned same = (unsigned)_mm_movemask_epi8(a) | (unsigned)_mm_movemask_epi8(b) << 16;
            return e + (unsigned)__builtin_ctz(~same) / 4;
        }
    }
    for (; e + 4 <= d; e += 4) {
        __m128i x = _mm_and_si128(_mm_loadu_si128((const __m128i *)(const void *)(tag + e)), m);
        const unsigned same = (unsigned)_mm_movemask_epi8(_mm_cmpeq_epi32(x, face));
        if (same != 0xFFFF)   /* the first sample of another face: four bits a sample */
            return e + (unsigned)__builtin_ctz(~same) / 4;
    }
#endif
    while (e < d && (tag[e] ^ t) <= VP_TAG_LEVEL_MASK)
        e++;
    return e;
}

/* The colour of the sample of tag t where every face is flat: its face's
 * from the palette, the background (after the faces) for no face. */
static inline uint64_t flat_of(uint32_t t, const uint64_t *pal, uint32_t nfaces)
{
    const uint32_t k = t >> VP_TAG_LEVEL_BITS;
    return pal[k < nfaces ? k : nfaces];
}

/* A sample is stored as eight bytes, its colour's six and two the next
 * sample overwrites; the last one's six alone. */
void vp_flat_samples(uint16_t *out, const uint32_t *tag, size_t n, vp_flat_rows *fr)
{
    const uint64_t *pal = fr->pal;
    const uint32_t nfaces = fr->nfaces;
    size_t i = 0;
#if VP_SSE2
    const __m128i m = _mm_set1_epi32((int)~VP_TAG_LEVEL_MASK), vn = _mm_set1_epi32((int)nfaces);
    uint32_t pat_of = VP_TAG_NONE;   /* the face (masked tag) of the pattern: none yet */
    __m128i pat[3] = {_mm_setzero_si128(), _mm_setzero_si128(), _mm_setzero_si128()};
    size_t mixed = 0;
    for (; i + 8 < n; i += 8) {
        const uint32_t t = tag[i] & ~VP_TAG_LEVEL_MASK;
        const __m128i face = _mm_set1_epi32((int)t);
        __m128i a, b;
        face_lanes8(tag + i, face, m, &a, &b);
        const bool one = face_all8(a, b);
        mixed += !one;
        if (!fr->by_sample && one) {
            if (t != pat_of) {
                rgb_pattern(flat_of(t, pal, nfaces), pat);
                pat_of = t;
            }
            store8_rgb(out + 3 * i, pat[0], pat[1], pat[2]);
            continue;
        }
        /* the eight palette indices at once (below 2^27: signed compares) */
        const __m128i *p = (const __m128i *)(const void *)(tag + i);
        uint32_t k[8];
        __m128i k0 = _mm_srli_epi32(_mm_loadu_si128(p), VP_TAG_LEVEL_BITS),
                k1 = _mm_srli_epi32(_mm_loadu_si128(p + 1), VP_TAG_LEVEL_BITS);
        k0 = _mm_xor_si128(k0, _mm_and_si128(_mm_xor_si128(k0, vn), _mm_cmpgt_epi32(k0, vn)));
        k1 = _mm_xor_si128(k1, _mm_and_si128(_mm_xor_si128(k1, vn), _mm_cmpgt_epi32(k1, vn)));
        _mm_storeu_si128((__m128i *)(void *)k, k0);
        _mm_storeu_si128((__m128i *)(void *)(k + 4), k1);
#pragma GCC unroll 8
        for (unsigned j = 0; j < 8; j++)
            memcpy(out + 3 * (i + j), &pal[k[j]], 8);
    }
    fr->steps += i / 8;
    fr->mixed += mixed;
#endif
    for (; i + 1 < n; i++) {
        const uint64_t x = flat_of(tag[i], pal, nfaces);
        memcpy(out + 3 * i, &x, 8);
    }
    const uint64_t x = flat_of(tag[i], pal, nfaces);
    memcpy(out + 3 * i, &x, 6);
}

/* One sample row as the output stage sees it: clean tiles are no surface
 * in the background; in the others, runs of samples of one face share
 * their shading set-up and step its forms along the row. */
static inline void sample_row(const alb_vp *vp, uint32_t r, const row_out *o, const bool pixels,
                              vp_flat_rows *flat)
{
    const uint32_t sw = vp->sw, twl = vp->tile_wl;
    const uint8_t *clean = vp->tile_clean + ((size_t)(r >> vp->tile_hl) << vp->tiles_lw);
    const uint32_t *tag = vp->s_tag + (size_t)r * sw;
    for (uint32_t c = 0; c < sw;) {
        /* the span of tiles as clean, or as touched, as the first */
        uint8_t cl = clean[c >> twl];
        uint32_t d = c + (1u << twl);
        while (d < sw && clean[d >> twl] == cl)
            d += 1u << twl;
        if (cl) {
            if (o->depth)
                memset(o->depth + c, 0, (d - c) * sizeof *o->depth);
            emit_none(vp, o, c, d, pixels);
            c = d;
            continue;
        }
        if (o->depth)
            memcpy(o->depth + c, vp->s_depth + (size_t)r * sw + c, (d - c) * sizeof *o->depth);
        if (pixels && !o->rgb && !o->face && !o->level && !o->coverage) {
            c = d;   /* the depth alone: no run of the tags matters */
            continue;
        }
        if (flat && o->rgb && !o->face && !o->level && !o->coverage) {
            vp_flat_samples(o->rgb + 3 * (size_t)c, tag + c, d - c, flat);
            c = d;
            continue;
        }
        while (c < d) {
            uint32_t t = tag[c], e = c + 1;
            if (t == VP_TAG_NONE) {
                /* no face's index has every bit of VP_TAG_NONE's (the
                 * frame's faces are fewer than VP_MAX_FRAME_FACES): a run of
                 * no face is a face's run to run_end */
                e = run_end(tag, e, d, VP_TAG_NONE);
                emit_none(vp, o, c, e, pixels);
            } else {
                e = run_end(tag, e, d, t);
                emit_face(vp, o, tag, r, c, e, pixels);
            }
            c = e;
        }
    }
}

static uint32_t face_of(const alb_vp *vp, uint32_t tag)
{
    return tag == VP_TAG_NONE ? ALB_FRAME_NO_FACE : vp->faces[tag >> VP_TAG_LEVEL_BITS].id;
}

static uint8_t level_of(uint32_t tag)
{
    return tag == VP_TAG_NONE ? ALB_FRAME_NO_LEVEL : (uint8_t)(tag & VP_TAG_LEVEL_MASK);
}

/* Scratch for one worker of the output stage: 2^aa sample rows of colour,
 * depth and tag (none with aa = 0, whose rows go straight to the frame). */
size_t vp_store_scratch_bytes(const alb_vp *vp)
{
    size_t n = vp->prof.aa_levels ? (size_t)vp->sw << vp->prof.aa_levels : 0;
    return n * (3 * sizeof(uint16_t) + 2 * sizeof(uint32_t));
}

/* Pixel rows [y0, y1) of the frame from their 4^aa samples each. */
static void resolve_rows(alb_vp *vp, void *ctx, unsigned worker, uint32_t y0, uint32_t y1)
{
    alb_frame *out = ctx;
    const unsigned aa = vp->prof.aa_levels, n = 1u << aa, w = vp->prof.width;
    const size_t sw = vp->sw;
    if (aa == 0) {
        /* one sample per pixel: the rows are the frame's */
        vp_flat_rows fr = {vp->flat_colour, vp->nfaces, false, 0, 0};
        /* every face flat: none uses a unit in this frame (vp_frame_units,
         * as the frame's statistics count them) */
        const bool all_flat = !vp->prof.all_units && !vp->st.faces_shaded &&
                              !vp->st.faces_textured && !vp->st.faces_fogged;
        vp_flat_rows *flat = all_flat && vp->flat_colour ? &fr : NULL;
        for (uint32_t y = y0; y < y1; y++) {
            size_t p = (size_t)y * w;
            row_out o = {out->rgb ? out->rgb + 3 * p : NULL, out->depth ? out->depth + p : NULL, NULL,
                         out->face ? out->face + p : NULL, out->level ? out->level + p : NULL,
                         out->coverage ? out->coverage + p : NULL};
            if (flat) {
                /* more than a quarter of the last row's steps mixed: this
                 * row by sample */
                fr.by_sample = 4 * fr.mixed > fr.steps;
                fr.steps = fr.mixed = 0;
            }
            sample_row(vp, y, &o, true, flat);
        }
        return;
    }
    unsigned char *scratch = vp->scratch + worker * vp_store_scratch_bytes(vp);
    uint32_t *depth = (uint32_t *)(void *)scratch, *tag = depth + n * sw;
    uint16_t *rgb = (uint16_t *)(void *)(tag + n * sw);
    const bool nearest = out->depth || out->face || out->level;
    for (uint32_t y = y0; y < y1; y++) {
        size_t p = (size_t)y * w;
        for (unsigned sy = 0; sy < n; sy++) {
            row_out o = {out->rgb ? rgb + 3 * sy * sw : NULL, depth + sy * sw, tag + sy * sw, NULL,
                         NULL, NULL};
            sample_row(vp, (y << aa) + sy, &o, false, NULL);
        }
        for (uint32_t x = 0; x < w; x++, p++) {
            /* the pixel's nearest sample gives depth, face and level (ties:
             * the first in raster order); colour is the mean of its samples,
             * rounded half up */
            uint32_t sum[3] = {0, 0, 0}, best = 0;
            size_t best_i = (size_t)x << aa;
            unsigned covered = 0;
            for (unsigned sy = 0; sy < n; sy++)
                for (unsigned sx = 0; sx < n; sx++) {
                    size_t i = sy * sw + ((size_t)x << aa) + sx;
                    if (out->rgb)
                        for (int ch = 0; ch < 3; ch++)
                            sum[ch] += rgb[3 * i + ch];
                    covered += tag[i] != VP_TAG_NONE;
                    if (nearest && depth[i] > best) {
                        best = depth[i];
                        best_i = i;
                    }
                }
            if (out->rgb)
                for (int ch = 0; ch < 3; ch++)
                    out->rgb[3 * p + ch] = (uint16_t)((sum[ch] + (n * n / 2)) >> (2 * aa));
            if (out->depth)
                out->depth[p] = depth[best_i];
            if (out->face)
                out->face[p] = face_of(vp, tag[best_i]);
            if (out->level)
                out->level[p] = level_of(tag[best_i]);
            if (out->coverage)
                out->coverage[p] = (uint16_t)covered;
        }
    }
}

void vp_store_resolve(alb_vp *vp, alb_frame *out)
{
    if (vp->flat_colour)
        vp->flat_colour[vp->nfaces] = flat_word(vp->bg);
    vp_parallel_rows(vp, vp->prof.height, resolve_rows, out);
}
