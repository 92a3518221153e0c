/* shade.c — the VP's per-sample units: the depth store format, the
 * reciprocal unit that divides by depth (eq. 7), intensity, texture
 * addressing, the colour output stage and fog (docs/vp.md §3-§6), and the
 * output stage's shading of a run of a face's samples with only the units
 * the face uses (vp_shade_run).  Integer arithmetic only; every rounding is
 * named where it happens. */
#include "units.h"

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

enum { U_SHADE = 1, U_TEXTURE = 2, U_FOG = 4 };

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

/* Samples [c0, c1) of row r of a face using `units`, a constant at each
 * call site, so every test of it folds away: the unused units are absent
 * and the forms the face uses are stepped by addition along the row. */
static inline __attribute__((always_inline)) void
shade_run(const alb_vp *vp, const vp_face_setup *fs, uint32_t r, uint32_t c0, uint32_t c1,
          uint16_t *out, const unsigned units)
{
    if (!units) {   /* a flat, unfogged face: one colour */
        vp_fill_rgb(out, c1 - c0, fs->flat);
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
        shade_run(vp, fs, r, c0, c1, out, n); \
    }
SHADE_UNITS(0) SHADE_UNITS(1) SHADE_UNITS(2) SHADE_UNITS(3)
SHADE_UNITS(4) SHADE_UNITS(5) SHADE_UNITS(6) SHADE_UNITS(7)
#undef SHADE_UNITS

static const shade_fn shade_for_units[8] = {
    shade_0, shade_1, shade_2, shade_3, shade_4, shade_5, shade_6, shade_7,
};

void vp_shade_run(const alb_vp *vp, const vp_face_setup *fs, uint32_t r, uint32_t c0, uint32_t c1,
                  uint16_t *rgb)
{
    if (vp->prof.all_units) {
        shade_all_units(vp, fs, r, c0, c1, rgb);
        return;
    }
    /* fog is a frame's choice as well as the face's */
    unsigned units = fs->units & (vp->frame.fog ? 7u : (unsigned)~U_FOG & 7u);
    shade_for_units[units](vp, fs, r, c0, c1, rgb);
}

void vp_sample_colour(const alb_vp *vp, const vp_face_setup *fs, uint32_t c, uint32_t r,
                      uint16_t rgb[3])
{
    vp_shade_run(vp, fs, r, c, c + 1, rgb);
}
