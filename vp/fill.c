/* fill.c — the fill unit: the samples of a cell that every edge of a face
 * holds, through the depth test into the sample store (docs/vp.md §4).  A
 * sample nearer than the store's takes the face's depth and tag; its colour
 * is the output stage's (store.c), so the fill is the same for every face.
 * A sample whose depth equals the store's (0 < d < max) is a tie: the
 * earlier face keeps it, and the tie is counted (depth_ties), the one at the
 * lowest sample index kept with the faces that kept and lost it.  The
 * largest depth written is the frame's nearest surface (depth_nearest).
 *
 * Depth is a linear form, so over a cell its extremes are at two corners.
 * A cell whose depths all lie inside the store's range — none saturates at
 * `near`, none underflows to 0 — is filled by the fast loop, which needs no
 * per-sample test but the depth comparison (SIMD where the host has it);
 * any other cell by the plain loop, which decides each sample through the
 * depth unit.  The fast loop comes in two shapes: a whole cell (every
 * sample of a rectangle) and an 8 x 8 block with a mask (the samples the
 * walk decided in one pass below an 8 x 8 cell, vp.c), each in the host's
 * fastest form.  All give the same bits (tests/test_fill.c), and each has
 * a twin without the tag plane for the store of counters alone
 * (vp_create_counters; tests/test_counters.c). */
#include "units.h"

#include <string.h>

#include "simd.h"

typedef struct {
    uint64_t written, underflow, saturated, ties;
    size_t tie;               /* the first tied sample in raster order, if ties */
    uint32_t nearest;         /* the largest depth written */
} fill_counts;

/* A cell's counts into the frame's statistics. */
static void add_counts(alb_vp *vp, const vp_face_setup *fs, uint64_t covered, const fill_counts *n)
{
    vp->st.samples_covered += covered;
    vp->st.depth_underflow += n->underflow;
    vp->st.depth_saturated += n->saturated;
    vp->st.samples_written += n->written;
    if (n->nearest > vp->st.depth_nearest)
        vp->st.depth_nearest = n->nearest;
    if (n->ties)
        units_note_ties(vp, fs, n->ties, n->tie);
}

/* The fast loop's result into a cell's counts; `base` is the store index of
 * the rectangle's first sample. */
static inline void add_rect(fill_counts *n, const vp_rect_result *x, size_t base)
{
    n->written += x->written;
    /* the lowest index: a cell filled in parts may meet a later row first */
    if (x->ties && (!n->ties || base + x->first_tie < n->tie))
        n->tie = base + x->first_tie;
    n->ties += x->ties;
    n->nearest = x->nearest > n->nearest ? x->nearest : n->nearest;
}

/* One sample through the depth unit and the depth test: the plain loop's
 * body (docs/vp.md §4). */
static inline void sample_plain(uint32_t *depth, uint32_t *tag, size_t idx, int64_t z, int sh,
                                int64_t dmax, uint32_t t, fill_counts *k)
{
    uint32_t dv = units_depth(z, sh, dmax);
    k->underflow += dv == 0 && z > 0;
    k->saturated += dv == (uint32_t)dmax;
    /* a later face wins only if strictly nearer: equal depths keep the
     * earlier face (docs/vp.md §4); 0, no surface, never wins */
    if (dv > depth[idx]) {
        depth[idx] = dv;
        if (tag)   /* NULL: the store of counters alone (vp_create_counters) */
            tag[idx] = t;
        k->written++;
        k->nearest = dv > k->nearest ? dv : k->nearest;
    } else if (dv != 0 && dv == depth[idx] && dv != (uint32_t)dmax && k->ties++ == 0) {
        k->tie = idx;
    }
}

/* ---- the fast loop: every depth in the store's range ----
 *
 * The stored depth is then z >> sr << sl exactly (one of the shifts is 0),
 * never 0 nor the maximum, so a sample ties where it equals the store's.
 * Forms: plain C, SSE2 four samples a step, AVX2 eight; one of each shape
 * is chosen for the host when the VP is made (vp_depth_forms). */

/* The plain form of one sample (also the SIMD forms' tails).  Every form
 * is one body compiled twice: `tagged` (a constant at each call) writes the
 * tag plane, or leaves it out for the store of counters alone, which has
 * none (vp_create_counters) — the same depths and counts either way. */
static inline __attribute__((always_inline)) void
sample_fast(uint32_t *depth, uint32_t *tag, size_t i, int64_t z, unsigned sr, unsigned sl,
            uint32_t t, size_t at, vp_rect_result *r, const bool tagged)
{
    uint32_t dv = (uint32_t)(((uint64_t)z >> sr) << sl);
    bool win = dv > depth[i], tie = dv == depth[i];
    depth[i] = win ? dv : depth[i];
    if (tagged)
        tag[i] = win ? t : tag[i];
    r->written += win;
    r->nearest = win && dv > r->nearest ? dv : r->nearest;
    if (tie && r->ties++ == 0)
        r->first_tie = at;
}

static inline __attribute__((always_inline)) vp_rect_result
rect_plain(uint32_t *depth, uint32_t *tag, size_t stride, uint32_t w, uint32_t h, int64_t z,
           int64_t dc, int64_t dr, unsigned sr, unsigned sl, uint32_t t, const bool tagged)
{
    vp_rect_result r = {0, 0, 0, 0};
    for (uint32_t y = 0; y < h; y++, z += dr) {
        int64_t zc = z;
        for (uint32_t x = 0; x < w; x++, zc += dc)
            sample_fast(depth, tag, y * stride + x, zc, sr, sl, t, y * stride + x, &r, tagged);
    }
    return r;
}

/* A rectangle of clean tiles (no surface anywhere: store 0, so every sample
 * wins): stored without reading, the same values as the rectangle's fill. */
static inline __attribute__((always_inline)) void
store_plain(uint32_t *depth, uint32_t *tag, size_t stride, uint32_t w, uint32_t h, int64_t z,
            int64_t dc, int64_t dr, unsigned sr, unsigned sl, uint32_t t, const bool tagged)
{
    for (uint32_t y = 0; y < h; y++, z += dr) {
        int64_t zc = z;
        for (uint32_t x = 0; x < w; x++, zc += dc) {
            depth[y * stride + x] = (uint32_t)(((uint64_t)zc >> sr) << sl);
            if (tagged)
                tag[y * stride + x] = t;
        }
    }
}

/* Samples `mask` (bit 8y + x) of the 8 x 8 block: tag t[0], or t[1] where
 * `mid` has the sample, t[2] where `fine` has it. */
static inline uint32_t block_tag(uint64_t mid, uint64_t fine, unsigned b, const uint32_t t[3])
{
    return fine >> b & 1 ? t[2] : mid >> b & 1 ? t[1] : t[0];
}

static inline __attribute__((always_inline)) vp_rect_result
block8_plain(uint32_t *depth, uint32_t *tag, size_t stride, int64_t z, int64_t dc, int64_t dr,
             unsigned sr, unsigned sl, uint64_t mask, uint64_t mid, uint64_t fine,
             const uint32_t t[3], const bool tagged)
{
    vp_rect_result r = {0, 0, 0, 0};
    for (uint64_t m = mask; m; m &= m - 1) {   /* raster order: the first tie is the lowest */
        const unsigned b = (unsigned)__builtin_ctzll(m), x = b & 7, y = b >> 3;
        sample_fast(depth, tag, y * stride + x, z + (int64_t)x * dc + (int64_t)y * dr, sr, sl,
                    block_tag(mid, fine, b, t), y * stride + x, &r, tagged);
    }
    return r;
}

/* The plain forms with the tag plane and without. */
static vp_rect_result rect_plain_c(uint32_t *depth, uint32_t *tag, size_t stride, uint32_t w,
                                   uint32_t h, int64_t z, int64_t dc, int64_t dr, unsigned sr,
                                   unsigned sl, uint32_t t)
{
    return rect_plain(depth, tag, stride, w, h, z, dc, dr, sr, sl, t, true);
}

static vp_rect_result rect_plain_c_untagged(uint32_t *depth, uint32_t *tag, size_t stride,
                                            uint32_t w, uint32_t h, int64_t z, int64_t dc,
                                            int64_t dr, unsigned sr, unsigned sl, uint32_t t)
{
    return rect_plain(depth, tag, stride, w, h, z, dc, dr, sr, sl, t, false);
}

static void store_plain_c(uint32_t *depth, uint32_t *tag, size_t stride, uint32_t w, uint32_t h,
                          int64_t z, int64_t dc, int64_t dr, unsigned sr, unsigned sl, uint32_t t)
{
    store_plain(depth, tag, stride, w, h, z, dc, dr, sr, sl, t, true);
}

static void store_plain_c_untagged(uint32_t *depth, uint32_t *tag, size_t stride, uint32_t w,
                                   uint32_t h, int64_t z, int64_t dc, int64_t dr, unsigned sr,
                                   unsigned sl, uint32_t t)
{
    store_plain(depth, tag, stride, w, h, z, dc, dr, sr, sl, t, false);
}

static vp_rect_result block8_plain_c(uint32_t *depth, uint32_t *tag, size_t stride, int64_t z,
                                     int64_t dc, int64_t dr, unsigned sr, unsigned sl,
                                     uint64_t mask, uint64_t mid, uint64_t fine, const uint32_t t[3])
{
    return block8_plain(depth, tag, stride, z, dc, dr, sr, sl, mask, mid, fine, t, true);
}

static vp_rect_result block8_plain_c_untagged(uint32_t *depth, uint32_t *tag, size_t stride,
                                              int64_t z, int64_t dc, int64_t dr, unsigned sr,
                                              unsigned sl, uint64_t mask, uint64_t mid,
                                              uint64_t fine, const uint32_t t[3])
{
    return block8_plain(depth, tag, stride, z, dc, dr, sr, sl, mask, mid, fine, t, false);
}

#if VP_SSE2
/* four samples a step: their depths in two registers of two 64-bit lanes,
 * shifted, narrowed to 32 bits, compared unsigned (by flipping the sign
 * bits) and merged where they win */
static inline __attribute__((always_inline)) vp_rect_result
rect_sse2_body(uint32_t *depth, uint32_t *tag, size_t stride, uint32_t w, uint32_t h, int64_t z,
               int64_t dc, int64_t dr, unsigned sr, unsigned sl, uint32_t t, const bool tagged)
{
    vp_rect_result res = {0, 0, 0, 0};
    const __m128i step = _mm_set1_epi64x(4 * dc), vsr = _mm_cvtsi32_si128((int)sr),
                  vsl = _mm_cvtsi32_si128((int)sl), sign = _mm_set1_epi32(INT32_MIN),
                  vt = _mm_set1_epi32((int)t);
    __m128i best = sign;   /* 0, flipped */
    for (uint32_t y = 0; y < h; y++, z += dr) {
        __m128i lo = _mm_set_epi64x(z + dc, z), hi = _mm_set_epi64x(z + 3 * dc, z + 2 * dc);
        uint32_t *dp = depth + y * stride, *tp = tagged ? tag + y * stride : NULL;
        uint32_t i = 0;
        for (; i + 4 <= w; i += 4) {
            __m128i a = _mm_sll_epi64(_mm_srl_epi64(lo, vsr), vsl);
            __m128i b = _mm_sll_epi64(_mm_srl_epi64(hi, vsr), vsl);
            __m128i dv = _mm_castps_si128(_mm_shuffle_ps(_mm_castsi128_ps(a), _mm_castsi128_ps(b),
                                                         _MM_SHUFFLE(2, 0, 2, 0)));
            __m128i *d = (__m128i *)(void *)(dp + i), *g = tagged ? (__m128i *)(void *)(tp + i) : NULL;
            __m128i old = _mm_loadu_si128(d), fdv = _mm_xor_si128(dv, sign);
            __m128i win = _mm_cmpgt_epi32(fdv, _mm_xor_si128(old, sign));
            _mm_storeu_si128(d, _mm_or_si128(_mm_and_si128(win, dv), _mm_andnot_si128(win, old)));
            if (tagged)
                _mm_storeu_si128(g, _mm_or_si128(_mm_and_si128(win, vt),
                                                 _mm_andnot_si128(win, _mm_loadu_si128(g))));
            /* the largest written (flipped: 0 is INT32_MIN where none won) */
            __m128i cand = _mm_or_si128(_mm_and_si128(win, fdv), _mm_andnot_si128(win, sign));
            __m128i gt = _mm_cmpgt_epi32(cand, best);
            best = _mm_or_si128(_mm_and_si128(gt, cand), _mm_andnot_si128(gt, best));
            unsigned wm = (unsigned)_mm_movemask_ps(_mm_castsi128_ps(win));
            unsigned tie = (unsigned)_mm_movemask_ps(_mm_castsi128_ps(_mm_cmpeq_epi32(dv, old)));
            res.written += vp_bits4(wm);
            if (tie) {
                if (!res.ties)
                    res.first_tie = y * stride + i + (unsigned)__builtin_ctz(tie);
                res.ties += vp_bits4(tie);
            }
            lo = _mm_add_epi64(lo, step);
            hi = _mm_add_epi64(hi, step);
        }
        for (int64_t zc = z + (int64_t)i * dc; i < w; i++, zc += dc)
            sample_fast(dp, tp, i, zc, sr, sl, t, y * stride + i, &res, tagged);
    }
    uint32_t lanes[4];
    _mm_storeu_si128((__m128i *)(void *)lanes, _mm_xor_si128(best, sign));
    for (int k = 0; k < 4; k++)
        res.nearest = lanes[k] > res.nearest ? lanes[k] : res.nearest;
    return res;
}

static vp_rect_result rect_sse2(uint32_t *depth, uint32_t *tag, size_t stride, uint32_t w,
                                uint32_t h, int64_t z, int64_t dc, int64_t dr, unsigned sr,
                                unsigned sl, uint32_t t)
{
    return rect_sse2_body(depth, tag, stride, w, h, z, dc, dr, sr, sl, t, true);
}

static vp_rect_result rect_sse2_untagged(uint32_t *depth, uint32_t *tag, size_t stride, uint32_t w,
                                         uint32_t h, int64_t z, int64_t dc, int64_t dr, unsigned sr,
                                         unsigned sl, uint32_t t)
{
    return rect_sse2_body(depth, tag, stride, w, h, z, dc, dr, sr, sl, t, false);
}
#endif

#if VP_AVX2
#include <immintrin.h>

/* eight samples a step: four 64-bit lanes in each of two registers, the low
 * halves gathered into eight 32-bit lanes; the new depth is the unsigned
 * maximum, and a sample wins where that is not the old depth */
__attribute__((target("avx2,popcnt"))) static inline __m256i narrow8(__m256i lo, __m256i hi, __m128i vsr,
                                                              __m128i vsl)
{
    __m256i a = _mm256_sll_epi64(_mm256_srl_epi64(lo, vsr), vsl);
    __m256i b = _mm256_sll_epi64(_mm256_srl_epi64(hi, vsr), vsl);
    /* per 128-bit half: a0 a1 b0 b1 | a2 a3 b2 b3; then a0..a3 b0..b3 */
    __m256i dv = _mm256_castps_si256(_mm256_shuffle_ps(_mm256_castsi256_ps(a), _mm256_castsi256_ps(b),
                                                       _MM_SHUFFLE(2, 0, 2, 0)));
    return _mm256_permute4x64_epi64(dv, _MM_SHUFFLE(3, 1, 2, 0));
}

__attribute__((target("avx2,popcnt"))) static inline unsigned hmax8(__m256i v)
{
    __m128i m = _mm_max_epu32(_mm256_castsi256_si128(v), _mm256_extracti128_si256(v, 1));
    m = _mm_max_epu32(m, _mm_shuffle_epi32(m, _MM_SHUFFLE(1, 0, 3, 2)));
    m = _mm_max_epu32(m, _mm_shuffle_epi32(m, _MM_SHUFFLE(2, 3, 0, 1)));
    return (unsigned)_mm_cvtsi128_si32(m);
}

/* Eight samples of one row: `in` the lanes that take part (all ones in a
 * whole cell), tv their tags; `at` the row offset of lane 0 for the first
 * tie. */
__attribute__((target("avx2,popcnt"))) static inline __attribute__((always_inline)) void
row8_avx2(uint32_t *dp, uint32_t *tp, __m256i dv, __m256i in, __m256i tv, size_t at, __m256i *best,
          vp_rect_result *res, const bool tagged)
{
    __m256i *d = (__m256i *)(void *)dp, *g = (__m256i *)(void *)tp;
    __m256i old = _mm256_loadu_si256(d), nearer = _mm256_max_epu32(dv, old);
    __m256i win = _mm256_andnot_si256(_mm256_cmpeq_epi32(nearer, old), in);
    _mm256_storeu_si256(d, _mm256_blendv_epi8(old, dv, win));
    if (tagged)
        _mm256_storeu_si256(g, _mm256_blendv_epi8(_mm256_loadu_si256(g), tv, win));
    *best = _mm256_max_epu32(*best, _mm256_and_si256(win, dv));
    unsigned wm = (unsigned)_mm256_movemask_ps(_mm256_castsi256_ps(win));
    unsigned tie = (unsigned)_mm256_movemask_ps(_mm256_castsi256_ps(
        _mm256_and_si256(_mm256_cmpeq_epi32(dv, old), in)));
    res->written += (unsigned)__builtin_popcount(wm);
    if (tie) {
        if (!res->ties)
            res->first_tie = at + (unsigned)__builtin_ctz(tie);
        res->ties += (unsigned)__builtin_popcount(tie);
    }
}

/* Eight samples of a whole cell's row: every lane takes part, so the new
 * depth is the maximum itself and the samples that lost are counted in
 * lanes (`lost`, -1 a sample), summed once for the cell. */
__attribute__((target("avx2,popcnt"))) static inline __attribute__((always_inline)) void
whole8_avx2(uint32_t *dp, uint32_t *tp, __m256i dv, __m256i tv, size_t at, __m256i *best,
            __m256i *lost, vp_rect_result *res, const bool tagged)
{
    __m256i *d = (__m256i *)(void *)dp, *g = (__m256i *)(void *)tp;
    const __m256i old = _mm256_loadu_si256(d), nearer = _mm256_max_epu32(dv, old);
    const __m256i kept = _mm256_cmpeq_epi32(nearer, old);
    _mm256_storeu_si256(d, nearer);
    if (tagged)
        _mm256_storeu_si256(g, _mm256_blendv_epi8(tv, _mm256_loadu_si256(g), kept));
    *best = _mm256_max_epu32(*best, _mm256_andnot_si256(kept, dv));
    *lost = _mm256_add_epi32(*lost, kept);
    const unsigned tie = (unsigned)_mm256_movemask_ps(_mm256_castsi256_ps(_mm256_cmpeq_epi32(dv, old)));
    if (tie) {
        if (!res->ties)
            res->first_tie = at + (unsigned)__builtin_ctz(tie);
        res->ties += (unsigned)__builtin_popcount(tie);
    }
}

__attribute__((target("avx2,popcnt"))) static inline __attribute__((always_inline)) vp_rect_result
rect_avx2_body(uint32_t *depth, uint32_t *tag, size_t stride, uint32_t w, uint32_t h, int64_t z,
               int64_t dc, int64_t dr, unsigned sr, unsigned sl, uint32_t t, const bool tagged)
{
    vp_rect_result res = {0, 0, 0, 0};
    const __m256i step = _mm256_set1_epi64x(8 * dc), four = _mm256_set1_epi64x(4 * dc),
                  down = _mm256_set1_epi64x(dr), vt = _mm256_set1_epi32((int)t);
    __m256i lost = _mm256_setzero_si256();   /* -1 a lane per sample that did not win */
    uint32_t whole = 0;                      /* samples in the whole-register steps */
    const __m128i vsr = _mm_cvtsi32_si128((int)sr), vsl = _mm_cvtsi32_si128((int)sl);
    /* lanes four apart hold one short row's samples in their low half */
    const __m256i in4 = _mm256_setr_epi32(-1, -1, -1, -1, 0, 0, 0, 0);
    __m256i row = _mm256_set_epi64x(z + 3 * dc, z + 2 * dc, z + dc, z), best = _mm256_setzero_si256();
    for (uint32_t y = 0; y < h; y++, z += dr, row = _mm256_add_epi64(row, down)) {
        uint32_t *dp = depth + y * stride, *tp = tagged ? tag + y * stride : NULL;
        __m256i lo = row, hi = _mm256_add_epi64(row, four);
        uint32_t i = 0;
        for (; i + 8 <= w; i += 8) {
            whole8_avx2(dp + i, tagged ? tp + i : NULL, narrow8(lo, hi, vsr, vsl), vt, y * stride + i,
                        &best, &lost, &res, tagged);
            lo = _mm256_add_epi64(lo, step);
            hi = _mm256_add_epi64(hi, step);
            whole += 8;
        }
        if (i + 4 <= w) {   /* four more (a cell four samples wide): half a register */
            __m256i dv = narrow8(lo, hi, vsr, vsl);
            __m128i *d = (__m128i *)(void *)(dp + i);
            __m128i old = _mm_loadu_si128(d), dv4 = _mm256_castsi256_si128(dv);
            __m128i win = _mm_andnot_si128(_mm_cmpeq_epi32(_mm_max_epu32(dv4, old), old),
                                           _mm256_castsi256_si128(in4));
            _mm_storeu_si128(d, _mm_blendv_epi8(old, dv4, win));
            if (tagged) {
                __m128i *g = (__m128i *)(void *)(tp + i);
                _mm_storeu_si128(g, _mm_blendv_epi8(_mm_loadu_si128(g), _mm256_castsi256_si128(vt), win));
            }
            best = _mm256_max_epu32(best, _mm256_and_si256(_mm256_castsi128_si256(win), dv));
            unsigned wm = (unsigned)_mm_movemask_ps(_mm_castsi128_ps(win));
            unsigned tie = (unsigned)_mm_movemask_ps(_mm_castsi128_ps(_mm_cmpeq_epi32(dv4, old)));
            res.written += (unsigned)__builtin_popcount(wm);
            if (tie) {
                if (!res.ties)
                    res.first_tie = y * stride + i + (unsigned)__builtin_ctz(tie);
                res.ties += (unsigned)__builtin_popcount(tie);
            }
            i += 4;
        }
        for (int64_t zc = z + (int64_t)i * dc; i < w; i++, zc += dc)
            sample_fast(dp, tp, i, zc, sr, sl, t, y * stride + i, &res, tagged);
    }
    unsigned m = hmax8(best);
    res.nearest = m > res.nearest ? m : res.nearest;
    /* the lanes' losses summed: the samples of the whole steps that won */
    __m128i l4 = _mm_add_epi32(_mm256_castsi256_si128(lost), _mm256_extracti128_si256(lost, 1));
    l4 = _mm_add_epi32(l4, _mm_shuffle_epi32(l4, _MM_SHUFFLE(1, 0, 3, 2)));
    l4 = _mm_add_epi32(l4, _mm_shuffle_epi32(l4, _MM_SHUFFLE(2, 3, 0, 1)));
    res.written += whole + (uint32_t)_mm_cvtsi128_si32(l4);
    return res;
}

/* The most common widths, 8 and 16 samples (cells, tiles), with the width a
 * constant: rows the compiler lays out in full. */
__attribute__((target("avx2,popcnt"))) static vp_rect_result
rect_avx2(uint32_t *depth, uint32_t *tag, size_t stride, uint32_t w, uint32_t h, int64_t z,
          int64_t dc, int64_t dr, unsigned sr, unsigned sl, uint32_t t)
{
    if (w == 8)
        return rect_avx2_body(depth, tag, stride, 8, h, z, dc, dr, sr, sl, t, true);
    if (w == 16)
        return rect_avx2_body(depth, tag, stride, 16, h, z, dc, dr, sr, sl, t, true);
    return rect_avx2_body(depth, tag, stride, w, h, z, dc, dr, sr, sl, t, true);
}

__attribute__((target("avx2,popcnt"))) static vp_rect_result
rect_avx2_untagged(uint32_t *depth, uint32_t *tag, size_t stride, uint32_t w, uint32_t h, int64_t z,
                   int64_t dc, int64_t dr, unsigned sr, unsigned sl, uint32_t t)
{
    if (w == 8)
        return rect_avx2_body(depth, tag, stride, 8, h, z, dc, dr, sr, sl, t, false);
    if (w == 16)
        return rect_avx2_body(depth, tag, stride, 16, h, z, dc, dr, sr, sl, t, false);
    return rect_avx2_body(depth, tag, stride, w, h, z, dc, dr, sr, sl, t, false);
}

/* The clean rectangle's store, eight samples a step (w a multiple of 8). */
__attribute__((target("avx2,popcnt"))) static inline __attribute__((always_inline)) void
store_avx2_body(uint32_t *depth, uint32_t *tag, size_t stride, uint32_t w, uint32_t h, int64_t z,
                int64_t dc, int64_t dr, unsigned sr, unsigned sl, uint32_t t, const bool tagged)
{
    if (w % 8) {
        store_plain(depth, tag, stride, w, h, z, dc, dr, sr, sl, t, tagged);
        return;
    }
    const __m256i step = _mm256_set1_epi64x(8 * dc), four = _mm256_set1_epi64x(4 * dc),
                  down = _mm256_set1_epi64x(dr), vt = _mm256_set1_epi32((int)t);
    const __m128i vsr = _mm_cvtsi32_si128((int)sr), vsl = _mm_cvtsi32_si128((int)sl);
    __m256i row = _mm256_set_epi64x(z + 3 * dc, z + 2 * dc, z + dc, z);
    for (uint32_t y = 0; y < h; y++, row = _mm256_add_epi64(row, down)) {
        uint32_t *dp = depth + y * stride, *tp = tagged ? tag + y * stride : NULL;
        __m256i lo = row, hi = _mm256_add_epi64(row, four);
        for (uint32_t i = 0; i < w; i += 8) {
            _mm256_storeu_si256((__m256i *)(void *)(dp + i), narrow8(lo, hi, vsr, vsl));
            if (tagged)
                _mm256_storeu_si256((__m256i *)(void *)(tp + i), vt);
            lo = _mm256_add_epi64(lo, step);
            hi = _mm256_add_epi64(hi, step);
        }
    }
}

__attribute__((target("avx2,popcnt"))) static void
store_avx2(uint32_t *depth, uint32_t *tag, size_t stride, uint32_t w, uint32_t h, int64_t z,
           int64_t dc, int64_t dr, unsigned sr, unsigned sl, uint32_t t)
{
    store_avx2_body(depth, tag, stride, w, h, z, dc, dr, sr, sl, t, true);
}

__attribute__((target("avx2,popcnt"))) static void
store_avx2_untagged(uint32_t *depth, uint32_t *tag, size_t stride, uint32_t w, uint32_t h, int64_t z,
                    int64_t dc, int64_t dr, unsigned sr, unsigned sl, uint32_t t)
{
    store_avx2_body(depth, tag, stride, w, h, z, dc, dr, sr, sl, t, false);
}

/* The masked 8 x 8 block: a row a step, its byte of the mask spread over
 * the lanes (a table: lane i of entry b is all ones where bit i of b is
 * set), the tags chosen by the level masks. */
#define LANE(b, i) ((b) >> (i) & 1 ? -1 : 0)
#define LANES(b) {LANE(b, 0), LANE(b, 1), LANE(b, 2), LANE(b, 3), LANE(b, 4), LANE(b, 5), LANE(b, 6), LANE(b, 7)}
#define LANES4(b) LANES(b), LANES((b) + 1), LANES((b) + 2), LANES((b) + 3)
#define LANES16(b) LANES4(b), LANES4((b) + 4), LANES4((b) + 8), LANES4((b) + 12)
#define LANES64(b) LANES16(b), LANES16((b) + 16), LANES16((b) + 32), LANES16((b) + 48)
static const int32_t byte_lanes[256][8] __attribute__((aligned(32))) = {
    LANES64(0), LANES64(64), LANES64(128), LANES64(192)};
#undef LANE
#undef LANES
#undef LANES4
#undef LANES16
#undef LANES64

__attribute__((target("avx2,popcnt"))) static inline __m256i lanes_of(unsigned byte)
{
    return _mm256_load_si256((const __m256i *)(const void *)byte_lanes[byte]);
}

__attribute__((target("avx2,popcnt"))) static inline __attribute__((always_inline)) vp_rect_result
block8_avx2_body(uint32_t *depth, uint32_t *tag, size_t stride, int64_t z, int64_t dc, int64_t dr,
                 unsigned sr, unsigned sl, uint64_t mask, uint64_t mid, uint64_t fine,
                 const uint32_t t[3], const bool tagged)
{
    vp_rect_result res = {0, 0, 0, 0};
    const __m256i down = _mm256_set1_epi64x(dr), four = _mm256_set1_epi64x(4 * dc);
    const __m256i t0 = _mm256_set1_epi32((int)t[0]), t1 = _mm256_set1_epi32((int)t[1]),
                  t2 = _mm256_set1_epi32((int)t[2]);
    const __m128i vsr = _mm_cvtsi32_si128((int)sr), vsl = _mm_cvtsi32_si128((int)sl);
    __m256i lo = _mm256_set_epi64x(z + 3 * dc, z + 2 * dc, z + dc, z), best = _mm256_setzero_si256();
#pragma GCC unroll 8
    for (unsigned y = 0; y < 8; y++, lo = _mm256_add_epi64(lo, down)) {
        const unsigned m = (unsigned)(mask >> 8 * y) & 0xFF;
        if (!m)
            continue;
        __m256i tv = t0;
        if (tagged) {
            tv = _mm256_blendv_epi8(t0, t1, lanes_of((unsigned)(mid >> 8 * y) & 0xFF));
            tv = _mm256_blendv_epi8(tv, t2, lanes_of((unsigned)(fine >> 8 * y) & 0xFF));
        }
        row8_avx2(depth + y * stride, tagged ? tag + y * stride : NULL,
                  narrow8(lo, _mm256_add_epi64(lo, four), vsr, vsl), lanes_of(m), tv,
                  y * stride, &best, &res, tagged);
    }
    res.nearest = hmax8(best);
    return res;
}

__attribute__((target("avx2,popcnt"))) static vp_rect_result
block8_avx2(uint32_t *depth, uint32_t *tag, size_t stride, int64_t z, int64_t dc, int64_t dr,
            unsigned sr, unsigned sl, uint64_t mask, uint64_t mid, uint64_t fine, const uint32_t t[3])
{
    return block8_avx2_body(depth, tag, stride, z, dc, dr, sr, sl, mask, mid, fine, t, true);
}

__attribute__((target("avx2,popcnt"))) static vp_rect_result
block8_avx2_untagged(uint32_t *depth, uint32_t *tag, size_t stride, int64_t z, int64_t dc,
                     int64_t dr, unsigned sr, unsigned sl, uint64_t mask, uint64_t mid,
                     uint64_t fine, const uint32_t t[3])
{
    return block8_avx2_body(depth, tag, stride, z, dc, dr, sr, sl, mask, mid, fine, t, false);
}
#endif

static unsigned depth_forms(vp_depth_forms_t f[3], const char *name[3], const bool tagged)
{
    unsigned k = 0;
#if VP_AVX2
    __builtin_cpu_init();
    if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("popcnt")) {
        f[k] = tagged ? (vp_depth_forms_t){rect_avx2, block8_avx2, store_avx2}
                      : (vp_depth_forms_t){rect_avx2_untagged, block8_avx2_untagged,
                                           store_avx2_untagged};
        name[k++] = "AVX2";
    }
#endif
#if VP_SSE2
    /* the masked block and the store in SSE2 are the plain forms: hosts
     * with SSE2 and without AVX2 predate 2013 */
    f[k] = tagged ? (vp_depth_forms_t){rect_sse2, block8_plain_c, store_plain_c}
                  : (vp_depth_forms_t){rect_sse2_untagged, block8_plain_c_untagged,
                                       store_plain_c_untagged};
    name[k++] = "SSE2";
#endif
    f[k] = tagged ? (vp_depth_forms_t){rect_plain_c, block8_plain_c, store_plain_c}
                  : (vp_depth_forms_t){rect_plain_c_untagged, block8_plain_c_untagged,
                                       store_plain_c_untagged};
    name[k++] = "plain C";
    return k;
}

unsigned vp_depth_forms(vp_depth_forms_t f[3], const char *name[3])
{
    return depth_forms(f, name, true);
}

unsigned vp_depth_forms_untagged(vp_depth_forms_t f[3], const char *name[3])
{
    return depth_forms(f, name, false);
}

/* ---- cells and blocks ---- */

/* The tag plane from sample idx on; NULL in the store of counters alone,
 * which has none (vp_create_counters: its forms never touch it). */
static inline uint32_t *tags_at(const alb_vp *vp, size_t idx)
{
    return vp->s_tag ? vp->s_tag + idx : NULL;
}

/* The least and the greatest N of the depth form over the rectangle of
 * w x h samples whose first has N = z (h is linear: its extremes are at two
 * corners). */
static inline void depth_extremes(const vp_face_setup *fs, uint32_t w, uint32_t h, int64_t z,
                                  int64_t *zmin, int64_t *zmax)
{
    const int64_t ec = (int64_t)(w - 1) * fs->depth.step_c, er = (int64_t)(h - 1) * fs->depth.step_r;
    *zmin = z + (ec < 0 ? ec : 0) + (er < 0 ? er : 0);
    *zmax = z + (ec > 0 ? ec : 0) + (er > 0 ? er : 0);
}

/* Whether every N from zmin to zmax lies in the store's range: the fast
 * loop's. */
static inline bool depth_in_range(const alb_vp *vp, const vp_face_setup *fs, int64_t zmin, int64_t zmax)
{
    return !vp->plain_fill && zmin >= fs->depth_lo && zmax <= fs->depth_hi;
}

/* ---- depth floors ----
 *
 * A sample's stored depth only grows during a frame, so once a fill has
 * covered a whole tile of the store, or a whole 8 x 8 block of samples, none
 * of its samples is ever again below that face's least depth over it: the
 * tile's floor (tile_floor) or the block's (block_floor), 0 when the frame
 * begins; either bounds a block's samples from below.  A fill of the fast
 * loop whose greatest depth over its cell (or 8 x 8 block, or tile) is below
 * such a bound can neither win a sample (it must be strictly nearer) nor tie
 * one: it writes nothing and counts nothing but the samples it covers — the
 * store and the counts its depth tests would have left, without the tests.
 * Faces drawn behind others skip so.  Tiles' floors are raised by the fills
 * of whole tiles (fill_tiles), blocks' by the fills of 8 x 8 cells (the
 * most numerous of small faces' cells found inside). */

/* The depth the fast loop stores for N = z (in the store's range). */
static inline uint32_t fast_depth(int64_t z, unsigned sr, unsigned sl)
{
    return (uint32_t)(((uint64_t)z >> sr) << sl);
}

/* A bound below every depth of the block of sample (c, r), and so of a cell
 * of 8 x 8 samples or fewer there.  Only 8 x 8 cells raise it, and those
 * exist only on square screens (a cell keeps the screen's aspect until a
 * side is one sample), whose store tiles are 16 x 16 or the whole screen:
 * a block lies in one tile, so in one thread's tiles (parallel.c). */
static inline uint32_t *block_floor_at(const alb_vp *vp, uint32_t c, uint32_t r)
{
    return vp->block_floor + (size_t)(r >> 3) * vp->block_row + (c >> 3);
}

/* A floor raised to d if that is higher; written only then: the floors of
 * tiles that other threads draw share its cache line. */
static inline void floor_raise(uint32_t *f, uint32_t d)
{
    if (d > *f)
        *f = d;
}

static inline uint32_t floor_of(const alb_vp *vp, uint32_t c, uint32_t r)
{
    const uint32_t t = vp->tile_floor[vp_tile_of(vp, c, r)];
    const uint32_t b = *block_floor_at(vp, c, r);
    return t > b ? t : b;
}

/* The fast loop over a cell that covers whole tiles of the store: tile row
 * by tile row, spans of clean tiles stored without reading (no clearing:
 * every sample beats the cleared store's 0) — or, in the store of counters
 * alone, left to the face's depth form until another fill reaches them
 * (VP_TILE_PLANE) — and runs of touched tiles through the depth test, but
 * tiles whose floor the face is wholly below.  Each tile's floor rises to
 * the face's least depth over it. */
static void fill_tiles(alb_vp *vp, const vp_cell *k, const vp_face_setup *fs, int64_t z, unsigned sr,
                       unsigned sl, uint32_t t, fill_counts *n)
{
    const int64_t dc = fs->depth.step_c, dr = fs->depth.step_r;
    const unsigned twl = vp->tile_wl, thl = vp->tile_hl;
    const uint32_t tw = 1u << twl, th = 1u << thl, c1 = k->c0 + (1u << k->wl), r1 = k->r0 + (1u << k->hl);
    for (uint32_t r = k->r0; r < r1; r += th) {
        const size_t row = (size_t)(r >> thl) << vp->tiles_lw;
        uint8_t *clean = vp->tile_clean + row;
        uint32_t *floor = vp->tile_floor + row;
        for (uint32_t c = k->c0; c < c1;) {
            const uint8_t cl = clean[c >> twl];
            uint32_t e = c + tw;
            while (e < c1 && clean[e >> twl] == cl)
                e += tw;
            const int64_t zc = z + (int64_t)(c - k->c0) * dc + (int64_t)(r - k->r0) * dr;
            const size_t idx = (size_t)r * vp->sw + c;
            if (cl == VP_TILE_CLEAN) {
                if (vp->counters_only) {
                    uint32_t *face = vp->tile_face + row;
                    for (uint32_t x = c >> twl; x < e >> twl; x++)
                        face[x] = t >> VP_TAG_LEVEL_BITS;
                    memset(clean + (c >> twl), VP_TILE_PLANE, (e - c) >> twl);
                } else {
                    vp->depth_forms.store(vp->s_depth + idx, tags_at(vp, idx), vp->sw, e - c, th, zc,
                                          dc, dr, sr, sl, t);
                    memset(clean + (c >> twl), VP_TILE_TOUCHED, (e - c) >> twl);
                }
                n->written += (uint64_t)(e - c) * th;
                /* depth is monotone in N: the span's largest at a corner */
                int64_t zmin, zmax;
                depth_extremes(fs, e - c, th, zc, &zmin, &zmax);
                const uint32_t top = fast_depth(zmax, sr, sl);
                n->nearest = top > n->nearest ? top : n->nearest;
                for (uint32_t x = c >> twl; x < e >> twl; x++) {
                    depth_extremes(fs, tw, th, zc + (int64_t)((x << twl) - c) * dc, &zmin, &zmax);
                    floor[x] = fast_depth(zmin, sr, sl);
                }
                c = e;
                continue;
            }
            /* touched tiles: the runs of those the face may reach */
            uint32_t run = c;   /* the first tile of the run not yet filled */
            for (uint32_t x = c; x <= e; x += tw) {
                int64_t zmin = 0, zmax = 0;
                bool below = false;
                if (x < e) {
                    depth_extremes(fs, tw, th, zc + (int64_t)(x - c) * dc, &zmin, &zmax);
                    below = fast_depth(zmax, sr, sl) < floor[x >> twl];
                }
                if ((x == e || below) && x > run) {
                    const size_t at = (size_t)r * vp->sw + run;
                    for (uint32_t y = run >> twl; cl == VP_TILE_PLANE && y < x >> twl; y++)
                        vp_clear_tile(vp, row + y);   /* another face's plane: written out first */
                    vp_rect_result res = vp->depth_forms.rect(vp->s_depth + at, tags_at(vp, at), vp->sw,
                                                              x - run, th, zc + (int64_t)(run - c) * dc,
                                                              dc, dr, sr, sl, t);
                    add_rect(n, &res, at);
                }
                if (x == e)
                    break;
                if (below)
                    run = x + tw;
                floor_raise(&floor[x >> twl], fast_depth(zmin, sr, sl));
            }
            c = e;
        }
    }
}

/* The samples of cell k for face fs. */
static void fill_cell(alb_vp *vp, const vp_face_setup *fs, const vp_cell *k)
{
    const uint32_t cw = 1u << k->wl, ch = 1u << k->hl, t = fs->tag | k->level;
    const int sh = units_depth_shift(vp, fs->depth.exp);
    const int64_t dc = fs->depth.step_c, dr = fs->depth.step_r;
    int64_t z = units_form_at(&fs->depth, k->c0, k->r0), zmin, zmax;
    size_t idx = (size_t)k->r0 * vp->sw + k->c0;
    fill_counts n = {0, 0, 0, 0, 0, 0};
    depth_extremes(fs, cw, ch, z, &zmin, &zmax);
    if (depth_in_range(vp, fs, zmin, zmax)) {
        /* every sample in range: z > 0, so the shifts are exact */
        const unsigned sr = sh < 0 ? (unsigned)-sh : 0, sl = sh > 0 ? (unsigned)sh : 0;
        if (k->wl >= vp->tile_wl && k->hl >= vp->tile_hl) {
            fill_tiles(vp, k, fs, z, sr, sl, t, &n);
        } else {
            vp_touch(vp, k);
            /* a cell within a tile: within a block too if it is no larger */
            const bool small = k->wl <= 3 && k->hl <= 3;
            if (!small || fast_depth(zmax, sr, sl) >= floor_of(vp, k->c0, k->r0)) {
                vp_rect_result x = vp->depth_forms.rect(vp->s_depth + idx, tags_at(vp, idx), vp->sw, cw,
                                                        ch, z, dc, dr, sr, sl, t);
                add_rect(&n, &x, idx);
                if (k->wl == 3 && k->hl == 3)   /* an 8 x 8 cell: its block's floor */
                    floor_raise(block_floor_at(vp, k->c0, k->r0), fast_depth(zmin, sr, sl));
            }
        }
    } else {
        vp_touch(vp, k);
        const int64_t dmax = ((int64_t)1 << vp->prof.depth_bits) - 1;
        for (uint32_t r = 0; r < ch; r++, z += dr, idx += vp->sw) {
            int64_t zc = z;
            for (uint32_t c = 0; c < cw; c++, zc += dc)
                sample_plain(vp->s_depth, vp->s_tag, idx + c, zc, sh, dmax, t, &n);
        }
    }
    add_counts(vp, fs, (uint64_t)cw * ch, &n);
}

void vp_fill(alb_vp *vp, const vp_face_setup *fs, const vp_cell *k)
{
    if (!(k->wl | k->hl))   /* a single sample, the most numerous */
        units_fill_sample(vp, fs, k->c0, k->r0, k->level);
    else
        fill_cell(vp, fs, k);
}

void vp_fill_block8(alb_vp *vp, const vp_face_setup *fs, uint32_t c0, uint32_t r0, uint64_t mask,
                    uint64_t mid, uint64_t fine, uint8_t l)
{
    const vp_cell k = {.c0 = c0, .r0 = r0, .wl = 3, .hl = 3};
    vp_touch(vp, &k);
    const uint32_t t[3] = {fs->tag | l, fs->tag | (uint32_t)(l + 1), fs->tag | (uint32_t)(l + 2)};
    const int sh = units_depth_shift(vp, fs->depth.exp);
    const int64_t dc = fs->depth.step_c, dr = fs->depth.step_r;
    const int64_t z = units_form_at(&fs->depth, c0, r0);
    const size_t idx = (size_t)r0 * vp->sw + c0;
    fill_counts n = {0, 0, 0, 0, 0, 0};
    int64_t zmin, zmax;
    depth_extremes(fs, 8, 8, z, &zmin, &zmax);
    if (depth_in_range(vp, fs, zmin, zmax)) {
        const unsigned sr = sh < 0 ? (unsigned)-sh : 0, sl = sh > 0 ? (unsigned)sh : 0;
        if (fast_depth(zmax, sr, sl) >= floor_of(vp, c0, r0)) {
            vp_rect_result x = vp->depth_forms.block8(vp->s_depth + idx, tags_at(vp, idx), vp->sw, z,
                                                      dc, dr, sr, sl, mask, mid, fine, t);
            add_rect(&n, &x, idx);
        }
    } else {
        const int64_t dmax = ((int64_t)1 << vp->prof.depth_bits) - 1;
        for (uint64_t m = mask; m; m &= m - 1) {
            const unsigned b = (unsigned)__builtin_ctzll(m), x = b & 7, y = b >> 3;
            sample_plain(vp->s_depth, vp->s_tag, idx + y * vp->sw + x,
                         z + (int64_t)x * dc + (int64_t)y * dr, sh, dmax, block_tag(mid, fine, b, t),
                         &n);
        }
    }
    add_counts(vp, fs, vp_popcount(mask), &n);
}
