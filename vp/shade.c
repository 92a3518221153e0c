/* shade.c — the VP's per-sample units: the depth store format, the
 * reciprocal unit that divides by depth (eq. 7), intensity, texture
 * addressing, the colour output stage and fog (docs/vp.md §3-§6), and the
 * output stage's shading of a run of a face's samples with only the units
 * the face uses (vp_shade_run).  Integer arithmetic only; every rounding is
 * named where it happens. */
#include "units.h"
#include "simd.h"

#include <stdlib.h>
#include <string.h>

uint32_t vp_depth_value(const alb_vp *vp, int64_t n, int exp)
{
    return units_depth(n, units_depth_shift(vp, exp), ((int64_t)1 << vp->prof.depth_bits) - 1);
}

vp_recip vp_reciprocal(int64_t n, unsigned rb)
{
    /* Normalise n to rb bits (truncating the rest), then one integer
     * division: rm = floor(2^(2rb-1) / dm), in [2^(rb-1), 2^rb]. */
    unsigned nb = fix_bitlen((uint64_t)n);
    int64_t dm = nb > rb ? n >> (nb - rb) : n << (rb - nb);
    vp_recip r = {((int64_t)1 << (2 * rb - 1)) / dm, (int)nb - (int)rb};
    return r;
}

/* The reciprocal ROM holds every quotient of the unit: the same bits as the
 * division above, one table read per sample. */
#define ROM_MAX_BITS 16

int vp_recip_rom_init(alb_vp *vp)
{
    unsigned rb = vp->prof.recip_bits;
    if (rb > ROM_MAX_BITS)
        return 0;   /* wider units divide */
    size_t n = (size_t)1 << (rb - 1);
    vp->recip_rom = malloc(n * sizeof *vp->recip_rom);
    if (!vp->recip_rom)
        return -1;
    for (size_t i = 0; i < n; i++)
        vp->recip_rom[i] = (uint32_t)(((int64_t)1 << (2 * rb - 1)) / (int64_t)(n + i));
    return 0;
}

vp_recip vp_reciprocal_rom(const alb_vp *vp, int64_t n) { return units_recip(vp, n); }

int64_t vp_ratio(int64_t num, int e_num, vp_recip r, int e_den, unsigned rb, int frac)
{
    return units_ratio(num, e_num, r, e_den, rb, frac);
}

uint16_t vp_scale_colour8(const alb_vp *vp, unsigned c8)
{
    /* 0..255 to 0..2^CB - 1, round half up */
    uint32_t top = (1u << vp->prof.colour_bits) - 1;
    return (uint16_t)((2 * c8 * top + 255) / 510);
}

/* Every unit on, for every sample: the reciprocal, intensity, texture
 * addressing (a white texel for untextured faces) and fog are all evaluated
 * and the face's flags select which results count.  The fill loops of fill.c
 * evaluate only the units a face uses; `all_units=1` makes the VP run this
 * instead, and the pixels must not change (tests/test_vp_features.c). */
void vp_shade_sample(const alb_vp *vp, const vp_face_setup *fs, int64_t nz, int64_t col,
                     int64_t row, uint16_t rgb[3])
{
    static const uint32_t white = 0xFFFFFF;
    const unsigned fi = vp->prof.shade_frac_bits, rb = vp->prof.recip_bits;
    const int64_t one = (int64_t)1 << fi;
    const int ez = fs->depth.exp;
    vp_recip rc = units_recip(vp, nz);   /* nz > 0: the sample passed the depth test */
    /* eq. (7): intensity = shade / depth, clamped to [0, 1] */
    int64_t shaded = fix_clamp(vp_ratio(units_form_at(&fs->shade, col, row), fs->shade.exp, rc,
                                        ez, rb, (int)fi), 0, one);
    /* nearest texel: the fractions of u and v, tex_log2 bits each */
    const uint32_t *texels = fs->texels ? fs->texels : &white;
    unsigned lg = fs->texels ? fs->tex_log2 : 0;
    unsigned u = units_fraction(units_form_at(&fs->tex_u, col, row), fs->tex_u.exp, rc, ez, rb, lg);
    unsigned v = units_fraction(units_form_at(&fs->tex_v, col, row), fs->tex_v.exp, rc, ez, rb, lg);
    uint32_t fetched = texels[((size_t)v << lg) + u];
    int64_t vis = units_fog_visibility(&vp->frame, vp_ratio(1, (int)vp->p, rc, ez, rb, 8), one);

    int64_t intensity = fs->flags & ALB_WS_FACE_SHADE ? shaded : one;
    uint32_t texel = fs->flags & ALB_WS_FACE_TEXTURE ? fetched : white;
    bool fog = vp->frame.fog && (fs->flags & ALB_WS_FACE_FOG);
    const uint64_t top = (1u << vp->prof.colour_bits) - 1;
    for (int ch = 0; ch < 3; ch++) {
        uint64_t m = (uint64_t)fs->rgb[ch] * (texel >> (16 - 8 * ch) & 0xFF) * (uint64_t)intensity;
        uint16_t out = units_output(m, top, fi);
        rgb[ch] = fog ? units_fog_blend(out, vp->fog_rgb[ch], vis, fi) : out;
    }
}

/* ---- the output stage's shading: only the units a face uses ---- */

enum { U_SHADE = 1, U_TEXTURE = 2, U_FOG = 4 };   /* vp_frame_units' bits */
_Static_assert(U_FOG == 4 && (U_SHADE | U_TEXTURE) == 3, "vp_frame_units' masks");

unsigned vp_face_units(const vp_face_setup *fs)
{
    return (fs->flags & ALB_WS_FACE_SHADE ? U_SHADE : 0) |
           (fs->flags & ALB_WS_FACE_TEXTURE ? U_TEXTURE : 0) | (fs->flags & ALB_WS_FACE_FOG ? U_FOG : 0);
}

void vp_flat_colour(const alb_vp *vp, const vp_face_setup *fs, uint16_t rgb[3])
{
    const unsigned fi = vp->prof.shade_frac_bits;
    const uint64_t top = (1u << vp->prof.colour_bits) - 1;
    for (int ch = 0; ch < 3; ch++)
        rgb[ch] = units_output((uint64_t)fs->rgb[ch] * 0xFF << fi, top, fi);
}

/* ---- eq. (7) along a run, the reciprocal's normalisation fixed ----
 *
 * The depth form N_z is linear along a row and positive at every sample a
 * face wrote (its depth beat 0), so its bit length — the reciprocal unit's
 * normalising shift — changes only where N_z crosses a power of two: a run
 * splits into stretches of one bit length, each found with one division,
 * and in a stretch every shift of the reciprocal and of the ratio is a
 * constant.  The samples are the reciprocal unit's and units_ratio's, bit
 * for bit; with the ROM and intensity alone (no texture, no fog: a Gouraud
 * face) the stretch runs four samples a step in AVX2 where the host has it
 * (tests/test_vp_features.c checks both forms sample by sample). */

/* The end of the stretch from sample c on (before c1) where N_z, nz at c
 * and dz a column on, keeps its bit length nb. */
static uint32_t stretch_end(int64_t nz, int64_t dz, unsigned nb, uint32_t c, uint32_t c1)
{
    uint64_t k;
    if (dz > 0)          /* the first N_z >= 2^nb */
        k = ((((uint64_t)1 << nb) - (uint64_t)nz) + (uint64_t)dz - 1) / (uint64_t)dz;
    else if (dz < 0)     /* the first N_z < 2^(nb - 1) */
        k = ((uint64_t)nz - ((uint64_t)1 << (nb - 1))) / (uint64_t)-dz + 1;
    else
        return c1;
    return k >= c1 - c ? c1 : c + (uint32_t)k;
}

/* The reciprocal of N_z through the ROM in a stretch of bit length nb: the
 * normalisation of units_recip with its shift known. */
static inline vp_recip stretch_recip(const alb_vp *vp, int64_t nz, int rs)
{
    const int64_t dm = rs >= 0 ? nz >> rs : nz << -rs;
    return (vp_recip){vp->recip_rom[dm - ((int64_t)1 << (vp->prof.recip_bits - 1))], rs};
}

#if VP_AVX2
#include <immintrin.h>

/* Four samples of a Gouraud face's stretch a step: N_z and N_s in four
 * 64-bit lanes, the ROM gathered, the 35 x 17-bit product from two 32-bit
 * multiplies (exact: it fits 63 bits, the profile's constraint), the ratio's
 * floor and clamp (units_ratio, fix_clamp), and the output stage's rounding
 * (units_output): floor(x / 65025) = x * 2164359683 >> 47 for every x <
 * 2^32 (the error 31747 x / 2^47 stays below 1/65025;
 * tests/test_vp_features.c proves it for the largest x). */
#define DIV65025_MUL 2164359683u
#define DIV65025_SHIFT 47

/* units_output of one channel in four lanes: intensity `in` times kc =
 * base x 255 x (2^CB - 1), rounded half up to the frame store */
__attribute__((target("avx2"))) static inline __m256i channel_avx2(__m256i in, __m256i kc,
                                                                 __m256i den, __m128i vfi,
                                                                 __m256i mul)
{
    const __m256i m2 = _mm256_slli_epi64(_mm256_mul_epu32(in, kc), 1);
    const __m256i x = _mm256_srl_epi64(_mm256_add_epi64(m2, den), vfi);
    return _mm256_srli_epi64(_mm256_mul_epu32(x, mul), DIV65025_SHIFT);
}
__attribute__((target("avx2"))) static uint32_t
gouraud_stretch_avx2(const alb_vp *vp, const vp_face_setup *fs, int64_t nz, int64_t ns, uint32_t n,
                     int rs, uint16_t *out)
{
    const unsigned rb = vp->prof.recip_bits, fi = vp->prof.shade_frac_bits;
    const int64_t one = (int64_t)1 << fi, dz = fs->depth.step_c, ds = fs->shade.step_c;
    const uint64_t top = (1u << vp->prof.colour_bits) - 1;
    /* the ratio's exponent: units_ratio_shift with the stretch's rm shift */
    const int k = fs->shade.exp - fs->depth.exp - (2 * (int)rb - 1) - rs + (int)fi;
    const __m256i zero = _mm256_setzero_si256(), vone = _mm256_set1_epi64x(one);
    const __m256i half = _mm256_set1_epi64x((int64_t)1 << (rb - 1));
    const __m256i thr = _mm256_set1_epi64x(k >= 63 ? 0 : k >= 0 ? one >> k : 0);
    const __m128i vrs = _mm_cvtsi32_si128(rs >= 0 ? rs : -rs);
    const __m128i vk = _mm_cvtsi32_si128(k >= 0 ? (k > 63 ? 64 : k) : (-k > 63 ? 64 : -k));
    const __m256i den = _mm256_set1_epi64x((int64_t)((uint64_t)65025 << fi));
    const __m128i vfi = _mm_cvtsi32_si128((int)fi + 1);
    const __m256i mul = _mm256_set1_epi64x(DIV65025_MUL);
    __m256i kc[3];   /* base x white texel x (2^CB - 1): m top = I kc */
    for (int c = 0; c < 3; c++)
        kc[c] = _mm256_set1_epi64x((int64_t)((uint64_t)fs->rgb[c] * 255 * top));
    __m256i vz = _mm256_setr_epi64x(nz, nz + dz, nz + 2 * dz, nz + 3 * dz);
    __m256i vs = _mm256_setr_epi64x(ns, ns + ds, ns + 2 * ds, ns + 3 * ds);
    const __m256i stz = _mm256_set1_epi64x(4 * dz), sts = _mm256_set1_epi64x(4 * ds);
    /* the three channels of two samples into twelve bytes of each half */
    const __m256i pack = _mm256_setr_epi8(0, 1, 2, 3, 4, 5, 8, 9, 10, 11, 12, 13, -1, -1, -1, -1, 0, 1,
                                          2, 3, 4, 5, 8, 9, 10, 11, 12, 13, -1, -1, -1, -1);
    uint32_t i = 0;
    for (; i + 4 <= n; i += 4) {
        const __m256i dm = rs >= 0 ? _mm256_srl_epi64(vz, vrs) : _mm256_sll_epi64(vz, vrs);
        const __m256i rm = _mm256_cvtepu32_epi64(_mm256_i64gather_epi32(
            (const int *)(const void *)vp->recip_rom, _mm256_sub_epi64(dm, half), 4));
        const __m256i p = _mm256_add_epi64(
            _mm256_mul_epu32(vs, rm), _mm256_slli_epi64(_mm256_mul_epi32(_mm256_srli_epi64(vs, 32), rm), 32));
        __m256i in;   /* the intensity, clamped to [0, one] */
        if (k < 0) {
            /* floor(p / 2^-k); a negative p clamps to 0 */
            const __m256i q = _mm256_srl_epi64(p, vk);
            in = _mm256_andnot_si256(_mm256_cmpgt_epi64(zero, p),
                                     _mm256_blendv_epi8(q, vone, _mm256_cmpgt_epi64(q, vone)));
        } else {
            /* p 2^k, saturating: above one >> k it is past one */
            in = _mm256_and_si256(_mm256_cmpgt_epi64(p, zero),
                                  _mm256_blendv_epi8(_mm256_sll_epi64(p, vk), vone,
                                                     _mm256_cmpgt_epi64(p, thr)));
        }
        /* R | G << 16 | B << 32 in each lane */
        const __m256i word = _mm256_or_si256(
            _mm256_or_si256(channel_avx2(in, kc[0], den, vfi, mul),
                            _mm256_slli_epi64(channel_avx2(in, kc[1], den, vfi, mul), 16)),
            _mm256_slli_epi64(channel_avx2(in, kc[2], den, vfi, mul), 32));
        /* each half's sixteen-byte store spills four bytes into the next
         * sample, which the next store writes: the low half's into the high
         * half's, the high half's into the next group's, or, for the last
         * group, twelve bytes exactly */
        const __m256i rgb = _mm256_shuffle_epi8(word, pack);
        const __m128i high = _mm256_extracti128_si256(rgb, 1);
        _mm_storeu_si128((__m128i *)(void *)(out + 3 * i), _mm256_castsi256_si128(rgb));
        if (i + 4 < n) {
            _mm_storeu_si128((__m128i *)(void *)(out + 3 * i + 6), high);
        } else {
            _mm_storel_epi64((__m128i *)(void *)(out + 3 * i + 6), high);
            const uint32_t last = (uint32_t)_mm_extract_epi32(high, 2);
            memcpy(out + 3 * i + 10, &last, 4);
        }
        vz = _mm256_add_epi64(vz, stz);
        vs = _mm256_add_epi64(vs, sts);
    }
    return i;
}

/* The same eight samples a step in AVX-512 (F and BW): the clamp by an
 * unsigned minimum and masks, the three channels of eight samples put
 * together by one permutation and written by one masked store, and the
 * stretch's last samples by masks too (the gather reads only their ROM
 * entries). */
__attribute__((target("avx512f,avx512bw"))) static inline __m512i
channel_avx512(__m512i in, __m512i kc, __m512i den, __m128i vfi, __m512i mul)
{
    const __m512i m2 = _mm512_slli_epi64(_mm512_mul_epu32(in, kc), 1);
    const __m512i x = _mm512_srl_epi64(_mm512_add_epi64(m2, den), vfi);
    return _mm512_srli_epi64(_mm512_mul_epu32(x, mul), DIV65025_SHIFT);
}

__attribute__((target("avx512f,avx512bw"))) static uint32_t
gouraud_stretch_avx512(const alb_vp *vp, const vp_face_setup *fs, int64_t nz, int64_t ns, uint32_t n,
                       int rs, uint16_t *out)
{
    const unsigned rb = vp->prof.recip_bits, fi = vp->prof.shade_frac_bits;
    const int64_t one = (int64_t)1 << fi, dz = fs->depth.step_c, ds = fs->shade.step_c;
    const uint64_t top = (1u << vp->prof.colour_bits) - 1;
    const int k = fs->shade.exp - fs->depth.exp - (2 * (int)rb - 1) - rs + (int)fi;
    const __m512i zero = _mm512_setzero_si512(), vone = _mm512_set1_epi64(one);
    const __m512i half = _mm512_set1_epi64((int64_t)1 << (rb - 1));
    const __m512i thr = _mm512_set1_epi64(k >= 63 ? 0 : k >= 0 ? one >> k : 0);
    const __m128i vrs = _mm_cvtsi32_si128(rs >= 0 ? rs : -rs);
    const __m128i vk = _mm_cvtsi32_si128(k >= 0 ? (k > 63 ? 64 : k) : (-k > 63 ? 64 : -k));
    const __m512i den = _mm512_set1_epi64((int64_t)((uint64_t)65025 << fi));
    const __m128i vfi = _mm_cvtsi32_si128((int)fi + 1);
    const __m512i mul = _mm512_set1_epi64(DIV65025_MUL);
    __m512i kc[3];
    for (int c = 0; c < 3; c++)
        kc[c] = _mm512_set1_epi64((int64_t)((uint64_t)fs->rgb[c] * 255 * top));
    __m512i vz = _mm512_set_epi64(nz + 7 * dz, nz + 6 * dz, nz + 5 * dz, nz + 4 * dz, nz + 3 * dz,
                                  nz + 2 * dz, nz + dz, nz);
    __m512i vs = _mm512_set_epi64(ns + 7 * ds, ns + 6 * ds, ns + 5 * ds, ns + 4 * ds, ns + 3 * ds,
                                  ns + 2 * ds, ns + ds, ns);
    const __m512i stz = _mm512_set1_epi64(8 * dz), sts = _mm512_set1_epi64(8 * ds);
    /* the 16-bit words R, G, B of lane j are words 4j .. 4j + 2 */
    const __m512i pack = _mm512_set_epi16(0, 0, 0, 0, 0, 0, 0, 0, 30, 29, 28, 26, 25, 24, 22, 21, 20,
                                          18, 17, 16, 14, 13, 12, 10, 9, 8, 6, 5, 4, 2, 1, 0);
    for (uint32_t i = 0; i < n; i += 8) {
        const uint32_t left = n - i < 8 ? n - i : 8;
        const __mmask8 lanes = (__mmask8)((1u << left) - 1);
        const __m512i dm = rs >= 0 ? _mm512_srl_epi64(vz, vrs) : _mm512_sll_epi64(vz, vrs);
        const __m512i rm = _mm512_cvtepu32_epi64(_mm512_mask_i64gather_epi32(
            _mm256_setzero_si256(), lanes, _mm512_sub_epi64(dm, half),
            (const void *)vp->recip_rom, 4));
        const __m512i p = _mm512_add_epi64(
            _mm512_mul_epu32(vs, rm), _mm512_slli_epi64(_mm512_mul_epi32(_mm512_srli_epi64(vs, 32), rm), 32));
        __m512i in;
        if (k < 0) {
            in = _mm512_maskz_mov_epi64(_mm512_cmpge_epi64_mask(p, zero),
                                        _mm512_min_epu64(_mm512_srl_epi64(p, vk), vone));
        } else {
            in = _mm512_maskz_mov_epi64(_mm512_cmpgt_epi64_mask(p, zero),
                                        _mm512_mask_mov_epi64(_mm512_sll_epi64(p, vk),
                                                              _mm512_cmpgt_epi64_mask(p, thr), vone));
        }
        const __m512i word = _mm512_or_si512(
            _mm512_or_si512(channel_avx512(in, kc[0], den, vfi, mul),
                            _mm512_slli_epi64(channel_avx512(in, kc[1], den, vfi, mul), 16)),
            _mm512_slli_epi64(channel_avx512(in, kc[2], den, vfi, mul), 32));
        _mm512_mask_storeu_epi16(out + 3 * i, (__mmask32)((1u << (3 * left)) - 1),
                                 _mm512_permutexvar_epi16(pack, word));
        vz = _mm512_add_epi64(vz, stz);
        vs = _mm512_add_epi64(vs, sts);
    }
    return n;
}
#endif

/* A stretch of a face that uses intensity and nothing else, in plain C from
 * sample i on. */
static inline void gouraud_stretch(const alb_vp *vp, const vp_face_setup *fs, int64_t nz, int64_t ns,
                                   uint32_t i, uint32_t n, int rs, uint16_t *out)
{
    const unsigned fi = vp->prof.shade_frac_bits, rb = vp->prof.recip_bits;
    const int64_t one = (int64_t)1 << fi;
    const uint64_t top = (1u << vp->prof.colour_bits) - 1;
    nz += (int64_t)i * fs->depth.step_c;
    ns += (int64_t)i * fs->shade.step_c;
    for (; i < n; i++, nz += fs->depth.step_c, ns += fs->shade.step_c) {
        const vp_recip rc = stretch_recip(vp, nz, rs);
        const int64_t in = fix_clamp(units_ratio(ns, fs->shade.exp, rc, fs->depth.exp, rb, (int)fi), 0, one);
        for (int c = 0; c < 3; c++)
            out[3 * i + (unsigned)c] = units_output((uint64_t)fs->rgb[c] * 255 * (uint64_t)in, top, fi);
    }
}

/* Samples [c0, c1) of row r of a Gouraud face through the ROM: stretch by
 * stretch, `isa` a constant (0: plain C, 1: AVX2 as far as it goes, 2:
 * AVX-512). */
static inline __attribute__((always_inline)) void
gouraud_run(const alb_vp *vp, const vp_face_setup *fs, uint32_t r, uint32_t c0, uint32_t c1,
            uint16_t *out, const int isa)
{
    int64_t nz = units_form_at(&fs->depth, c0, r), ns = units_form_at(&fs->shade, c0, r);
    for (uint32_t c = c0; c < c1;) {
        const unsigned nb = fix_bitlen((uint64_t)nz);   /* nz > 0: the face wrote here */
        const uint32_t e = stretch_end(nz, fs->depth.step_c, nb, c, c1);
        const int rs = (int)nb - (int)vp->prof.recip_bits;
        uint32_t done = 0;
#if VP_AVX2
        if (isa == 2)
            done = gouraud_stretch_avx512(vp, fs, nz, ns, e - c, rs, out);
        else if (isa == 1)
            done = gouraud_stretch_avx2(vp, fs, nz, ns, e - c, rs, out);
#else
        (void)isa;
#endif
        gouraud_stretch(vp, fs, nz, ns, done, e - c, rs, out);
        nz += (int64_t)(e - c) * fs->depth.step_c;
        ns += (int64_t)(e - c) * fs->shade.step_c;
        out += 3 * (size_t)(e - c);
        c = e;
    }
}

/* Samples [c0, c1) of row r of a face using `units`, a constant at each
 * call site, so every test of it folds away: the unused units are absent
 * and the forms the face uses are stepped by addition along the row. */
static inline __attribute__((always_inline)) void
shade_run(const alb_vp *vp, const vp_face_setup *fs, uint32_t r, uint32_t c0, uint32_t c1,
          uint16_t *out, const unsigned units, const int isa)
{
    if (!units) {   /* a flat, unfogged face: one colour */
        vp_fill_rgb(out, c1 - c0, fs->flat);
        return;
    }
    if (units == U_SHADE && vp->recip_rom) {
        gouraud_run(vp, fs, r, c0, c1, out, isa);
        return;
    }
    const unsigned fi = vp->prof.shade_frac_bits, rb = vp->prof.recip_bits, lg = fs->tex_log2;
    const int64_t one = (int64_t)1 << fi;
    const int ez = fs->depth.exp;
    const uint64_t top = (1u << vp->prof.colour_bits) - 1;
    /* every form stepped exactly along the row: N(c + 1, r) = N(c, r) + step_c */
    int64_t nz = units_form_at(&fs->depth, c0, r);
    int64_t ns = units & U_SHADE ? units_form_at(&fs->shade, c0, r) : 0;
    int64_t nu = units & U_TEXTURE ? units_form_at(&fs->tex_u, c0, r) : 0;
    int64_t nv = units & U_TEXTURE ? units_form_at(&fs->tex_v, c0, r) : 0;
    for (uint32_t c = c0; c < c1; c++, out += 3) {
        /* nz > 0: the face wrote this sample, so its depth was not 0 */
        vp_recip rc = units_recip(vp, nz);
        if (units & (U_SHADE | U_TEXTURE)) {
            int64_t intensity = one;
            if (units & U_SHADE)
                intensity = fix_clamp(units_ratio(ns, fs->shade.exp, rc, ez, rb, (int)fi), 0, one);
            uint32_t texel = 0xFFFFFF;
            if (units & U_TEXTURE) {
                unsigned u = units_fraction(nu, fs->tex_u.exp, rc, ez, rb, lg);
                unsigned v = units_fraction(nv, fs->tex_v.exp, rc, ez, rb, lg);
                texel = fs->texels[((size_t)v << lg) + u];
            }
            for (int i = 0; i < 3; i++)
                out[i] = units_output((uint64_t)fs->rgb[i] * (texel >> (16 - 8 * i) & 0xFF) *
                                          (uint64_t)intensity,
                                      top, fi);
        } else {
            memcpy(out, fs->flat, sizeof fs->flat);
        }
        if (units & U_FOG) {
            int64_t zq = units_ratio(1, (int)vp->p, rc, ez, rb, 8);
            int64_t vis = units_fog_visibility(&vp->frame, zq, one);
            for (int i = 0; i < 3; i++)
                out[i] = units_fog_blend(out[i], vp->fog_rgb[i], vis, fi);
        }
        nz += fs->depth.step_c;
        if (units & U_SHADE)
            ns += fs->shade.step_c;
        if (units & U_TEXTURE)
            nu += fs->tex_u.step_c, nv += fs->tex_v.step_c;
    }
}

/* Every unit on: each sample through vp_shade_sample. */
static void shade_all_units(const alb_vp *vp, const vp_face_setup *fs, uint32_t r, uint32_t c0,
                            uint32_t c1, uint16_t *out)
{
    for (uint32_t c = c0; c < c1; c++, out += 3)
        vp_shade_sample(vp, fs, units_form_at(&fs->depth, c, r), c, r, out);
}

typedef void (*shade_fn)(const alb_vp *, const vp_face_setup *, uint32_t, uint32_t, uint32_t,
                         uint16_t *);
#define SHADE_UNITS(n) \
    static void shade_##n(const alb_vp *vp, const vp_face_setup *fs, uint32_t r, uint32_t c0, \
                          uint32_t c1, uint16_t *out) \
    { \
        shade_run(vp, fs, r, c0, c1, out, n, 0); \
    }
SHADE_UNITS(0) SHADE_UNITS(1) SHADE_UNITS(2) SHADE_UNITS(3)
SHADE_UNITS(4) SHADE_UNITS(5) SHADE_UNITS(6) SHADE_UNITS(7)
#undef SHADE_UNITS

/* Gouraud faces with the SIMD stretches (the other units have none). */
static void shade_1_avx2(const alb_vp *vp, const vp_face_setup *fs, uint32_t r, uint32_t c0,
                         uint32_t c1, uint16_t *out)
{
    shade_run(vp, fs, r, c0, c1, out, U_SHADE, 1);
}

static void shade_1_avx512(const alb_vp *vp, const vp_face_setup *fs, uint32_t r, uint32_t c0,
                           uint32_t c1, uint16_t *out)
{
    shade_run(vp, fs, r, c0, c1, out, U_SHADE, 2);
}

static const shade_fn shade_for_units[3][8] = {
    {shade_0, shade_1, shade_2, shade_3, shade_4, shade_5, shade_6, shade_7},
    {shade_0, shade_1_avx2, shade_2, shade_3, shade_4, shade_5, shade_6, shade_7},
    {shade_0, shade_1_avx512, shade_2, shade_3, shade_4, shade_5, shade_6, shade_7},
};

unsigned vp_shade_isa_host(void)
{
#if VP_AVX2
    __builtin_cpu_init();
    if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw"))
        return 2;
    if (__builtin_cpu_supports("avx2"))
        return 1;
#endif
    return 0;
}

void vp_shade_run(const alb_vp *vp, const vp_face_setup *fs, uint32_t r, uint32_t c0, uint32_t c1,
                  uint16_t *rgb)
{
    if (vp->prof.all_units) {
        shade_all_units(vp, fs, r, c0, c1, rgb);
        return;
    }
    shade_for_units[vp->shade_isa][vp_frame_units(vp, fs)](vp, fs, r, c0, c1, rgb);
}

void vp_sample_colour(const alb_vp *vp, const vp_face_setup *fs, uint32_t c, uint32_t r,
                      uint16_t rgb[3])
{
    vp_shade_run(vp, fs, r, c, c + 1, rgb);
}
