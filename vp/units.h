/* units.h — the VP's per-sample arithmetic units as inline functions, shared
 * by the fill (fill.c, the functional engine's walk in vp.c) and the output
 * stage's shading (shade.c): the depth store format and one sample's depth
 * test, the reciprocal ROM, the ratio of two forms, the texture fraction,
 * fog visibility and the colour output stage (docs/vp.md §4-§6).  Integer
 * arithmetic only. */
#ifndef ALBATROS_VP_UNITS_H
#define ALBATROS_VP_UNITS_H

#include "vp_internal.h"
#include "../common/fix.h"

/* N of a form at sample (c, r). */
static inline int64_t units_form_at(const vp_form_fn *f, int64_t c, int64_t r)
{
    return f->origin + c * f->step_c + r * f->step_r;
}

/* The shift from a depth form's N to the store: near/Z = N 2^(exp - P),
 * stored as unsigned 0.depth_bits. */
static inline int units_depth_shift(const alb_vp *vp, int exp)
{
    return exp - (int)vp->p + (int)vp->prof.depth_bits;
}

/* The stored depth: truncated, saturating at max (nearer than `near`), 0 for
 * a plane behind the observer here (n <= 0). */
static inline uint32_t units_depth(int64_t n, int sh, int64_t max)
{
    if (n <= 0)
        return 0;
    int64_t v = sh >= 0 ? fix_shl_sat(n, (unsigned)sh, 0, max) : fix_floor_shr(n, (unsigned)-sh);
    return (uint32_t)(v > max ? max : v);
}

/* The N whose stored depth lies strictly inside the store's range — neither
 * 0 (underflow, or N <= 0) nor max (saturation) — are lo <= N <= hi, none
 * where lo > hi: units_depth is monotone in N.  (max = 2^depth_bits - 1 is
 * odd, so for sh > 0 every N <= max >> sh stays below max.) */
static inline void units_depth_range(int sh, int64_t max, int64_t *lo, int64_t *hi)
{
    if (sh >= 0) {
        *lo = 1;
        *hi = sh >= 62 ? 0 : sh == 0 ? max - 1 : max >> sh;
        return;
    }
    const unsigned s = (unsigned)-sh;
    if (s >= 63) {
        *lo = 1, *hi = 0;
        return;
    }
    /* floor(N / 2^s) > 0 from N = 2^s; < max below max 2^s */
    *lo = (int64_t)1 << s;
    *hi = max > (INT64_MAX >> s) ? INT64_MAX : (max << s) - 1;
}

/* Ties in the depth store (docs/vp.md §4: equal d, 0 < d < max — two faces
 * in one depth step, the earlier kept; ties at the saturated max are
 * depth_saturated's): `ties` of them by face fs, `idx` the lowest-indexed
 * of those, which is kept with the faces that kept and lost it if it is the
 * frame's lowest yet — the same sample whatever the tiling. */
static inline void units_note_ties(alb_vp *vp, const vp_face_setup *fs, uint64_t ties, size_t idx)
{
    if (!vp->st.depth_ties || idx < vp->st.tie_sample) {
        vp->st.tie_sample = idx;
        /* without a tag plane (counters alone) vp_store_name_tie finds the
         * face that kept it when the frame's counters are taken */
        vp->st.tie_kept = vp->s_tag ? vp_frame_face(vp, vp->s_tag[idx])->id : 0;
        vp->tie_lost_face = fs->tag >> VP_TAG_LEVEL_BITS;
        vp->st.tie_lost = fs->id;
        vp->st.tie_depth = vp->s_depth[idx];
    }
    vp->st.depth_ties += ties;
}

/* The fill unit on one sample (c, r) of face fs decided at `level`: its
 * depth through the depth unit and the depth test (docs/vp.md §4), counted
 * in vp->st.  The fill loops of fill.c do the same a row at a time. */
static inline void units_fill_sample(alb_vp *vp, const vp_face_setup *fs, uint32_t c, uint32_t r,
                                     uint8_t level)
{
    vp_cell k = {.c0 = c, .r0 = r, .level = level};
    vp_touch(vp, &k);
    const int64_t dmax = ((int64_t)1 << vp->prof.depth_bits) - 1;
    const int64_t z = units_form_at(&fs->depth, c, r);
    const size_t idx = (size_t)r * vp->sw + c;
    uint32_t dv = units_depth(z, units_depth_shift(vp, fs->depth.exp), dmax);
    vp->st.samples_covered++;
    vp->st.depth_underflow += dv == 0 && z > 0;
    vp->st.depth_saturated += dv == (uint32_t)dmax;
    /* a later face wins only if strictly nearer; 0, no surface, never wins */
    if (dv > vp->s_depth[idx]) {
        vp->s_depth[idx] = dv;
        if (vp->s_tag)
            vp->s_tag[idx] = fs->tag | level;
        vp->st.samples_written++;
        if (dv > vp->st.depth_nearest)
            vp->st.depth_nearest = dv;
    } else if (dv != 0 && dv == vp->s_depth[idx] && dv != (uint32_t)dmax) {
        units_note_ties(vp, fs, 1, idx);
    }
}

/* 1/n for n > 0 through the reciprocal ROM (or the divider, wider units). */
static inline vp_recip units_recip(const alb_vp *vp, int64_t n)
{
    unsigned rb = vp->prof.recip_bits;
    if (!vp->recip_rom)
        return vp_reciprocal(n, rb);
    unsigned nb = fix_bitlen((uint64_t)n);
    int64_t dm = nb > rb ? n >> (nb - rb) : n << (rb - nb);
    vp_recip r = {vp->recip_rom[dm - ((int64_t)1 << (rb - 1))], (int)nb - (int)rb};
    return r;
}

/* The exponent of 2 that turns num * rm into the fixed-point result. */
static inline int units_ratio_shift(int e_num, vp_recip r, int e_den, unsigned rb, int frac)
{
    return e_num - e_den - (2 * (int)rb - 1) - r.shift + frac;
}

/* floor(num / den * 2^(e_num - e_den + frac)) through the reciprocal r of
 * den: truncated toward minus infinity, saturated at +-2^62. */
static inline int64_t units_ratio(int64_t num, int e_num, vp_recip r, int e_den, unsigned rb,
                                  int frac)
{
    int64_t p = num * r.rm;
    int k = units_ratio_shift(e_num, r, e_den, rb, frac);
    if (k >= 0)
        return fix_shl_sat(p, (unsigned)k, -((int64_t)1 << 62), (int64_t)1 << 62);
    return fix_floor_shr(p, (unsigned)-k);
}

/* floor(num/den 2^(e_num - e_den + bits)) mod 2^bits: the fraction of a
 * texture coordinate; wrap-around (periodic texture) makes overflow harmless. */
static inline unsigned units_fraction(int64_t num, int e_num, vp_recip r, int e_den,
                                      unsigned rb, unsigned bits)
{
    int64_t p = num * r.rm;
    int k = units_ratio_shift(e_num, r, e_den, rb, (int)bits);
    uint64_t v = k >= 64  ? 0
                 : k >= 0 ? (uint64_t)p << k
                          : (uint64_t)fix_floor_shr(p, (unsigned)-k);
    return (unsigned)(v & ((1u << bits) - 1));
}

/* Fog visibility in 0..one of a sample at distance zq (Z/near, 24.8):
 * linear between the frame's fog near and far, truncated. */
static inline int64_t units_fog_visibility(const alb_ws_frame *fr, int64_t zq, int64_t one)
{
    if (zq <= fr->fog_near)
        return one;
    if (zq >= fr->fog_far)
        return 0;
    return ((int64_t)fr->fog_far - zq) * one / ((int64_t)fr->fog_far - fr->fog_near);
}

/* The output stage: base x texel x intensity (m, in units of 255 * 255 *
 * 2^FI) scaled to the frame store, round half up: (2 m (2^CB - 1) + D) / 2D
 * with D = 255 * 255 * 2^FI, computed as floor(floor(x / 2^(FI+1)) / 65025) —
 * the same integer, a shift and a division by a constant. */
static inline uint16_t units_output(uint64_t m, uint64_t top, unsigned fi)
{
    const uint64_t den = (uint64_t)255 * 255 << fi;
    return (uint16_t)(((2 * m * top + den) >> (fi + 1)) / 65025u);
}

/* Blend toward the fog colour, round half up. */
static inline uint16_t units_fog_blend(int64_t c, int64_t fog_c, int64_t vis, unsigned fi)
{
    int64_t one = (int64_t)1 << fi;
    return (uint16_t)((c * vis + fog_c * (one - vis) + one / 2) >> fi);
}

#endif
