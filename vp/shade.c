/* shade.c — the VP's per-sample units: the depth store format, the
 * reciprocal unit that divides by depth (eq. 7), intensity, texture
 * addressing, the colour output stage and fog (docs/vp.md §3-§6).  Integer
 * arithmetic only; every rounding is named where it happens. */
#include "units.h"

#include <stdlib.h>

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
