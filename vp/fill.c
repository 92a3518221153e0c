/* fill.c — the fill unit: the samples of a cell that every edge of a face
 * holds, through the depth test into the sample store (docs/vp.md §4).  A
 * sample nearer than the store's takes the face's depth and tag; its colour
 * is the output stage's (store.c), so the fill is the same for every face.
 * A sample whose depth equals the store's (0 < d < max) is a tie: the
 * earlier face keeps it, and the tie is counted (depth_ties), the one at the
 * lowest sample index kept with the faces that kept and lost it.
 *
 * Depth is a linear form, so over a cell its extremes are at two corners.
 * A cell whose depths all lie inside the store's range — none saturates at
 * `near`, none underflows to 0 — is filled by the fast row loop, which needs
 * no per-sample test but the depth comparison (SIMD where the host has it);
 * any other cell by the plain loop, which decides each sample through the
 * depth unit.  Both give the same bits (tests/test_fill.c). */
#include "units.h"

#include <string.h>

#include "simd.h"

typedef struct {
    uint64_t written, underflow, saturated, ties;
    size_t tie;               /* the first tied sample in raster order, if ties */
} fill_counts;

/* A cell's counts into the frame's statistics. */
static void add_counts(alb_vp *vp, const vp_face_setup *fs, uint64_t covered, const fill_counts *n)
{
    vp->st.samples_covered += covered;
    vp->st.depth_underflow += n->underflow;
    vp->st.depth_saturated += n->saturated;
    vp->st.samples_written += n->written;
    if (n->ties)
        units_note_ties(vp, fs, n->ties, n->tie);
}

/* The plain loop over one row, samples idx .. idx + n - 1 of the store:
 * each sample through the depth unit. */
static inline void row_plain(alb_vp *vp, size_t idx, uint32_t n, int64_t z, int64_t dz, int sh,
                             int64_t dmax, uint32_t t, fill_counts *k)
{
    uint32_t *depth = vp->s_depth + idx, *tag = vp->s_tag + idx;
    for (uint32_t i = 0; i < n; i++, z += dz) {
        uint32_t dv = units_depth(z, sh, dmax);
        k->underflow += dv == 0 && z > 0;
        k->saturated += dv == (uint32_t)dmax;
        /* a later face wins only if strictly nearer: equal depths keep the
         * earlier face (docs/vp.md §4); 0, no surface, never wins */
        if (dv > depth[i]) {
            depth[i] = dv;
            tag[i] = t;
            k->written++;
        } else if (dv != 0 && dv == depth[i] && dv != (uint32_t)dmax && k->ties++ == 0) {
            k->tie = idx + i;
        }
    }
}

/* The fast loop over one row whose depths z + i dz all lie in the store's
 * range: the stored depth is then z >> sr << sl exactly (one of the shifts
 * is 0), never 0 nor the maximum, so a sample ties where it equals the
 * store's.  Three forms, one chosen for the host when the VP is made
 * (vp_depth_rows): plain C, SSE2 four samples a step, AVX2 eight; the same
 * bits (tests/test_fill.c). */

/* The plain form's loop from sample i on; the others' tails. */
static inline vp_row_result row_tail(uint32_t *depth, uint32_t *tag, uint32_t i, uint32_t n,
                                     int64_t z, int64_t dz, unsigned sr, unsigned sl, uint32_t t,
                                     vp_row_result r)
{
    z += (int64_t)i * dz;
    for (; i < n; i++, z += dz) {
        uint32_t dv = (uint32_t)(((uint64_t)z >> sr) << sl);
        bool win = dv > depth[i], tie = dv == depth[i];
        depth[i] = win ? dv : depth[i];
        tag[i] = win ? t : tag[i];
        r.written += win;
        if (tie && r.ties++ == 0)
            r.first_tie = i;
    }
    return r;
}

static vp_row_result row_plain_c(uint32_t *depth, uint32_t *tag, uint32_t n, int64_t z, int64_t dz,
                                 unsigned sr, unsigned sl, uint32_t t)
{
    return row_tail(depth, tag, 0, n, z, dz, sr, sl, t, (vp_row_result){0, 0, 0});
}

#if VP_SSE2
/* four samples a step: their depths in two registers of two 64-bit lanes,
 * shifted, narrowed to 32 bits, compared unsigned (by flipping the sign
 * bits) and merged where they win */
static inline __attribute__((always_inline)) vp_row_result row_sse2_body(uint32_t *depth, uint32_t *tag, uint32_t n, int64_t z,
                                          int64_t dz, unsigned sr, unsigned sl, uint32_t t)
{
    vp_row_result res = {0, 0, 0};
    uint32_t i = 0;
    const __m128i step = _mm_set1_epi64x(4 * dz), vsr = _mm_cvtsi32_si128((int)sr),
                  vsl = _mm_cvtsi32_si128((int)sl), sign = _mm_set1_epi32(INT32_MIN),
                  vt = _mm_set1_epi32((int)t);
    __m128i lo = _mm_set_epi64x(z + dz, z), hi = _mm_set_epi64x(z + 3 * dz, z + 2 * dz);
    for (; i + 4 <= n; i += 4) {
        __m128i a = _mm_sll_epi64(_mm_srl_epi64(lo, vsr), vsl);
        __m128i b = _mm_sll_epi64(_mm_srl_epi64(hi, vsr), vsl);
        __m128i dv = _mm_castps_si128(_mm_shuffle_ps(_mm_castsi128_ps(a), _mm_castsi128_ps(b),
                                                     _MM_SHUFFLE(2, 0, 2, 0)));
        __m128i *dp = (__m128i *)(void *)(depth + i), *tp = (__m128i *)(void *)(tag + i);
        __m128i old = _mm_loadu_si128(dp);
        __m128i win = _mm_cmpgt_epi32(_mm_xor_si128(dv, sign), _mm_xor_si128(old, sign));
        _mm_storeu_si128(dp, _mm_or_si128(_mm_and_si128(win, dv), _mm_andnot_si128(win, old)));
        _mm_storeu_si128(tp, _mm_or_si128(_mm_and_si128(win, vt),
                                          _mm_andnot_si128(win, _mm_loadu_si128(tp))));
        unsigned w = (unsigned)_mm_movemask_ps(_mm_castsi128_ps(win));
        unsigned tie = (unsigned)_mm_movemask_ps(_mm_castsi128_ps(_mm_cmpeq_epi32(dv, old)));
        res.written += (0x4332322132212110ull >> (4 * w)) & 0xF;
        if (tie) {
            if (!res.ties)
                res.first_tie = i + (unsigned)__builtin_ctz(tie);
            res.ties += (0x4332322132212110ull >> (4 * tie)) & 0xF;
        }
        lo = _mm_add_epi64(lo, step);
        hi = _mm_add_epi64(hi, step);
    }
    return row_tail(depth, tag, i, n, z, dz, sr, sl, t, res);
}

static vp_row_result row_sse2(uint32_t *depth, uint32_t *tag, uint32_t n, int64_t z, int64_t dz,
                              unsigned sr, unsigned sl, uint32_t t)
{
    return row_sse2_body(depth, tag, n, z, dz, sr, sl, t);
}
#endif

#if VP_AVX2
#include <immintrin.h>
/* eight samples a step: four 64-bit lanes in each of two registers, the low
 * halves gathered into eight 32-bit lanes; the new depth is the unsigned
 * maximum, and a sample wins where that is not the old depth */
__attribute__((target("avx2"))) static vp_row_result
row_avx2(uint32_t *depth, uint32_t *tag, uint32_t n, int64_t z, int64_t dz, unsigned sr,
         unsigned sl, uint32_t t)
{
    vp_row_result res = {0, 0, 0};
    uint32_t i = 0;
    const __m256i step = _mm256_set1_epi64x(8 * dz), vt = _mm256_set1_epi32((int)t);
    const __m128i vsr = _mm_cvtsi32_si128((int)sr), vsl = _mm_cvtsi32_si128((int)sl);
    __m256i lo = _mm256_set_epi64x(z + 3 * dz, z + 2 * dz, z + dz, z);
    __m256i hi = _mm256_add_epi64(lo, _mm256_set1_epi64x(4 * dz));
    for (; i + 8 <= n; i += 8) {
        __m256i a = _mm256_sll_epi64(_mm256_srl_epi64(lo, vsr), vsl);
        __m256i b = _mm256_sll_epi64(_mm256_srl_epi64(hi, vsr), vsl);
        /* per 128-bit half: a0 a1 b0 b1 | a2 a3 b2 b3; then a0..a3 b0..b3 */
        __m256i dv = _mm256_castps_si256(_mm256_shuffle_ps(_mm256_castsi256_ps(a),
                                                           _mm256_castsi256_ps(b),
                                                           _MM_SHUFFLE(2, 0, 2, 0)));
        dv = _mm256_permute4x64_epi64(dv, _MM_SHUFFLE(3, 1, 2, 0));
        __m256i *dp = (__m256i *)(void *)(depth + i), *tp = (__m256i *)(void *)(tag + i);
        __m256i old = _mm256_loadu_si256(dp), nearer = _mm256_max_epu32(dv, old);
        __m256i lost = _mm256_cmpeq_epi32(nearer, old);
        _mm256_storeu_si256(dp, nearer);
        _mm256_storeu_si256(tp, _mm256_blendv_epi8(vt, _mm256_loadu_si256(tp), lost));
        unsigned l = (unsigned)_mm256_movemask_ps(_mm256_castsi256_ps(lost));
        unsigned tie = (unsigned)_mm256_movemask_ps(_mm256_castsi256_ps(_mm256_cmpeq_epi32(dv, old)));
        res.written += 8 - (unsigned)__builtin_popcount(l);
        if (tie) {
            if (!res.ties)
                res.first_tie = i + (unsigned)__builtin_ctz(tie);
            res.ties += (unsigned)__builtin_popcount(tie);
        }
        lo = _mm256_add_epi64(lo, step);
        hi = _mm256_add_epi64(hi, step);
    }
    if (i + 4 <= n) {   /* four more (the rows of cells four samples wide): one half */
        __m256i a = _mm256_sll_epi64(_mm256_srl_epi64(lo, vsr), vsl);
        __m128i dv = _mm_castps_si128(_mm_shuffle_ps(_mm256_castps256_ps128(_mm256_castsi256_ps(a)),
                                                     _mm256_extractf128_ps(_mm256_castsi256_ps(a), 1),
                                                     _MM_SHUFFLE(2, 0, 2, 0)));
        __m128i *dp = (__m128i *)(void *)(depth + i), *tp = (__m128i *)(void *)(tag + i);
        __m128i old = _mm_loadu_si128(dp), nearer = _mm_max_epu32(dv, old);
        __m128i lost = _mm_cmpeq_epi32(nearer, old);
        _mm_storeu_si128(dp, nearer);
        _mm_storeu_si128(tp, _mm_blendv_epi8(_mm256_castsi256_si128(vt), _mm_loadu_si128(tp), lost));
        unsigned l = (unsigned)_mm_movemask_ps(_mm_castsi128_ps(lost));
        unsigned tie = (unsigned)_mm_movemask_ps(_mm_castsi128_ps(_mm_cmpeq_epi32(dv, old)));
        res.written += 4 - (unsigned)__builtin_popcount(l);
        if (tie) {
            if (!res.ties)
                res.first_tie = i + (unsigned)__builtin_ctz(tie);
            res.ties += (unsigned)__builtin_popcount(tie);
        }
        i += 4;
    }
    return row_tail(depth, tag, i, n, z, dz, sr, sl, t, res);
}
#endif

unsigned vp_depth_rows(vp_depth_row_fn fn[3], const char *name[3])
{
    unsigned k = 0;
#if VP_AVX2
    __builtin_cpu_init();
    if (__builtin_cpu_supports("avx2"))
        fn[k] = row_avx2, name[k++] = "AVX2";
#endif
#if VP_SSE2
    fn[k] = row_sse2, name[k++] = "SSE2";
#endif
    fn[k] = row_plain_c, name[k++] = "plain C";
    return k;
}

/* The samples of cell k for face fs. */
static void fill_cell(alb_vp *vp, const vp_face_setup *fs, const vp_cell *k)
{
    vp_touch(vp, k);
    const uint32_t cw = 1u << k->wl, ch = 1u << k->hl, t = fs->tag | k->level;
    const int sh = units_depth_shift(vp, fs->depth.exp);
    const int64_t dmax = ((int64_t)1 << vp->prof.depth_bits) - 1;
    const int64_t dc = fs->depth.step_c, dr = fs->depth.step_r;
    int64_t z = units_form_at(&fs->depth, k->c0, k->r0);
    /* the depth form's extremes over the cell, at two of its corners */
    const int64_t ec = (int64_t)(cw - 1) * dc, er = (int64_t)(ch - 1) * dr;
    const int64_t zmin = z + (ec < 0 ? ec : 0) + (er < 0 ? er : 0);
    const int64_t zmax = z + (ec > 0 ? ec : 0) + (er > 0 ? er : 0);
    size_t idx = (size_t)k->r0 * vp->sw + k->c0;
    fill_counts n = {0, 0, 0, 0, 0};
    if (!vp->plain_fill && zmin > 0 && units_depth(zmin, sh, dmax) > 0 &&
        units_depth(zmax, sh, dmax) < (uint32_t)dmax) {
        /* every sample in range: z > 0, so the shifts are exact */
        const unsigned sr = sh < 0 ? (unsigned)-sh : 0, sl = sh > 0 ? (unsigned)sh : 0;
        /* rows of eight samples or more: the host's fastest form; shorter
         * ones (most cells) inline, four a step */
        const vp_depth_row_fn row = cw >= 8 ? vp->depth_row : NULL;
        for (uint32_t r = 0; r < ch; r++, z += dr, idx += vp->sw) {
            uint32_t *depth = vp->s_depth + idx, *tag = vp->s_tag + idx;
#if VP_SSE2
            vp_row_result x = row ? row(depth, tag, cw, z, dc, sr, sl, t)
                                  : row_sse2_body(depth, tag, cw, z, dc, sr, sl, t);
#else
            vp_row_result x = row ? row(depth, tag, cw, z, dc, sr, sl, t)
                                  : row_plain_c(depth, tag, cw, z, dc, sr, sl, t);
#endif
            n.written += x.written;
            if (x.ties && !n.ties)
                n.tie = idx + x.first_tie;   /* raster order: the first is the lowest */
            n.ties += x.ties;
        }
    } else {
        for (uint32_t r = 0; r < ch; r++, z += dr, idx += vp->sw)
            row_plain(vp, idx, cw, z, dc, sh, dmax, t, &n);
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

/* Samples in a 4-bit mask. */
static inline unsigned bits4(unsigned m) { return (0x4332322132212110ull >> (4 * m)) & 0xF; }

/* The samples `mask` (bit 4y + x) of the 4 x 4 block at (c0, r0), each
 * decided at level l, or l - 1 where its bit of `coarse` is set.  As for a
 * cell: where the block's depths are all in the store's range, the fast
 * loop, a row of four at a time, the mask choosing the samples; else the
 * plain loop, sample by sample. */
void vp_fill_block4(alb_vp *vp, const vp_face_setup *fs, uint32_t c0, uint32_t r0, uint16_t mask,
                    uint16_t coarse, uint8_t l)
{
    const vp_cell k = {.c0 = c0, .r0 = r0, .wl = 2, .hl = 2};
    vp_touch(vp, &k);
    const int sh = units_depth_shift(vp, fs->depth.exp);
    const int64_t dmax = ((int64_t)1 << vp->prof.depth_bits) - 1;
    const int64_t dc = fs->depth.step_c, dr = fs->depth.step_r;
    const uint32_t t_fine = fs->tag | l, t_coarse = fs->tag | (uint32_t)(l - 1);
    int64_t z = units_form_at(&fs->depth, c0, r0);
    const int64_t zmin = z + (dc < 0 ? 3 * dc : 0) + (dr < 0 ? 3 * dr : 0);
    const int64_t zmax = z + (dc > 0 ? 3 * dc : 0) + (dr > 0 ? 3 * dr : 0);
    size_t idx = (size_t)r0 * vp->sw + c0;
    fill_counts n = {0, 0, 0, 0, 0};
    const uint64_t covered = bits4(mask & 0xF) + bits4(mask >> 4 & 0xF) + bits4(mask >> 8 & 0xF) +
                             bits4(mask >> 12);
    if (!vp->plain_fill && zmin > 0 && units_depth(zmin, sh, dmax) > 0 &&
        units_depth(zmax, sh, dmax) < (uint32_t)dmax) {
        const unsigned sr = sh < 0 ? (unsigned)-sh : 0, sl = sh > 0 ? (unsigned)sh : 0;
        for (unsigned y = 0; y < 16; y += 4, z += dr, idx += vp->sw) {
            const unsigned m = mask >> y & 0xF, cm = coarse >> y & 0xF;
            if (!m)
                continue;
            uint32_t *depth = vp->s_depth + idx, *tag = vp->s_tag + idx;
            unsigned tie = 0;   /* the row's tied samples, bit x */
#if VP_SSE2
            /* four lanes: the row's depths narrowed as in the fast rows,
             * the depth test where the mask has the sample */
            static const int32_t lane[16][4] = {
                {0, 0, 0, 0},   {-1, 0, 0, 0},   {0, -1, 0, 0},   {-1, -1, 0, 0},
                {0, 0, -1, 0},  {-1, 0, -1, 0},  {0, -1, -1, 0},  {-1, -1, -1, 0},
                {0, 0, 0, -1},  {-1, 0, 0, -1},  {0, -1, 0, -1},  {-1, -1, 0, -1},
                {0, 0, -1, -1}, {-1, 0, -1, -1}, {0, -1, -1, -1}, {-1, -1, -1, -1}};
            const __m128i vsr = _mm_cvtsi32_si128((int)sr), vsl = _mm_cvtsi32_si128((int)sl);
            const __m128i sign = _mm_set1_epi32(INT32_MIN);
            __m128i a = _mm_sll_epi64(_mm_srl_epi64(_mm_set_epi64x(z + dc, z), vsr), vsl);
            __m128i b = _mm_sll_epi64(_mm_srl_epi64(_mm_set_epi64x(z + 3 * dc, z + 2 * dc), vsr), vsl);
            __m128i dv = _mm_castps_si128(_mm_shuffle_ps(_mm_castsi128_ps(a), _mm_castsi128_ps(b),
                                                         _MM_SHUFFLE(2, 0, 2, 0)));
            __m128i *dp = (__m128i *)(void *)depth, *tp = (__m128i *)(void *)tag;
            __m128i old = _mm_loadu_si128(dp);
            __m128i win = _mm_and_si128(_mm_loadu_si128((const __m128i *)(const void *)lane[m]),
                                        _mm_cmpgt_epi32(_mm_xor_si128(dv, sign), _mm_xor_si128(old, sign)));
            _mm_storeu_si128(dp, _mm_or_si128(_mm_and_si128(win, dv), _mm_andnot_si128(win, old)));
            __m128i cl = _mm_loadu_si128((const __m128i *)(const void *)lane[cm]);
            __m128i tv = _mm_or_si128(_mm_and_si128(cl, _mm_set1_epi32((int)t_coarse)),
                                      _mm_andnot_si128(cl, _mm_set1_epi32((int)t_fine)));
            _mm_storeu_si128(tp, _mm_or_si128(_mm_and_si128(win, tv),
                                              _mm_andnot_si128(win, _mm_loadu_si128(tp))));
            n.written += bits4((unsigned)_mm_movemask_ps(_mm_castsi128_ps(win)));
            tie = m & (unsigned)_mm_movemask_ps(_mm_castsi128_ps(_mm_cmpeq_epi32(dv, old)));
#else
            int64_t zc = z;
            for (unsigned x = 0; x < 4; x++, zc += dc) {
                uint32_t dv = (uint32_t)(((uint64_t)zc >> sr) << sl);
                if (!(m >> x & 1))
                    continue;
                if (dv == depth[x])
                    tie |= 1u << x;
                if (dv <= depth[x])
                    continue;
                depth[x] = dv;
                tag[x] = cm >> x & 1 ? t_coarse : t_fine;
                n.written++;
            }
#endif
            if (tie) {
                if (!n.ties)
                    n.tie = idx + (unsigned)__builtin_ctz(tie);
                n.ties += bits4(tie);
            }
        }
    } else {
        for (unsigned y = 0; y < 16; y += 4, z += dr, idx += vp->sw) {
            uint32_t *depth = vp->s_depth + idx, *tag = vp->s_tag + idx;
            int64_t zc = z;
            for (unsigned x = 0; x < 4; x++, zc += dc) {
                unsigned bit = 1u << (y + x);
                if (!(mask & bit))
                    continue;
                uint32_t dv = units_depth(zc, sh, dmax);
                n.underflow += dv == 0 && zc > 0;
                n.saturated += dv == (uint32_t)dmax;
                if (dv > depth[x]) {
                    depth[x] = dv;
                    tag[x] = coarse & bit ? t_coarse : t_fine;
                    n.written++;
                } else if (dv != 0 && dv == depth[x] && dv != (uint32_t)dmax && n.ties++ == 0) {
                    n.tie = idx + x;
                }
            }
        }
    }
    add_counts(vp, fs, covered, &n);
}
