/* shade.c — the VP's per-sample units: the depth store format, the
 * reciprocal unit that divides by depth (eq. 7), intensity, texture
 * addressing, the colour output stage and fog (docs/vp.md §3-§6).  Integer
 * arithmetic only; every rounding is named where it happens. */
#include "vp_internal.h"
#include "../common/fix.h"

#include <stdlib.h>

static int64_t form_at(const vp_form_fn *f, int64_t c, int64_t r)
{
    return f->origin + c * f->step_c + r * f->step_r;
}

uint32_t vp_depth_value(const vp_t *vp, int64_t n, int exp)
{
    /* near/Z = n 2^(exp - P), stored as unsigned 0.depth_bits, truncated,
     * saturating at the largest value (nearer than `near`) */
    if (n <= 0)
        return 0;   /* the plane is behind the observer here */
    int64_t max = ((int64_t)1 << vp->prof.depth_bits) - 1;
    int sh = exp - (int)vp->p + (int)vp->prof.depth_bits;
    int64_t v = sh >= 0 ? fix_shl_sat(n, (unsigned)sh, 0, max) : fix_floor_shr(n, (unsigned)-sh);
    return (uint32_t)(v > max ? max : v);
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

int vp_recip_rom_init(vp_t *vp)
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

vp_recip vp_reciprocal_rom(const vp_t *vp, int64_t n)
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
static int ratio_shift(int e_num, vp_recip r, int e_den, unsigned rb, int frac)
{
    return e_num - e_den - (2 * (int)rb - 1) - r.shift + frac;
}

int64_t vp_ratio(int64_t num, int e_num, vp_recip r, int e_den, unsigned rb, int frac)
{
    int64_t p = num * r.rm;
    int k = ratio_shift(e_num, r, e_den, rb, frac);
    if (k >= 0)
        return fix_shl_sat(p, (unsigned)k, -((int64_t)1 << 62), (int64_t)1 << 62);
    return fix_floor_shr(p, (unsigned)-k);   /* truncate toward minus infinity */
}

/* floor(num/den 2^(e_num - e_den + bits)) mod 2^bits: the fraction of a
 * texture coordinate; wrap-around (periodic texture) makes overflow harmless. */
static unsigned ratio_fraction(int64_t num, int e_num, vp_recip r, int e_den, unsigned rb,
                               unsigned bits)
{
    int64_t p = num * r.rm;
    int k = ratio_shift(e_num, r, e_den, rb, (int)bits);
    uint64_t v = k >= 64 ? 0 : k >= 0 ? (uint64_t)p << k : (uint64_t)fix_floor_shr(p, (unsigned)-k);
    return (unsigned)(v & ((1u << bits) - 1));
}

uint16_t vp_scale_colour8(const vp_t *vp, unsigned c8)
{
    /* 0..255 to 0..2^CB - 1, round half up */
    uint32_t top = (1u << vp->prof.colour_bits) - 1;
    return (uint16_t)((2 * c8 * top + 255) / 510);
}

/* Fog visibility in 0..2^FI of a sample at distance zq (Z/near, 24.8). */
static int64_t fog_visibility(const ws_frame *fr, int64_t zq, int64_t one)
{
    if (zq <= fr->fog_near)
        return one;
    if (zq >= fr->fog_far)
        return 0;
    /* linear in distance between fog near and far, truncated */
    return ((int64_t)fr->fog_far - zq) * one / ((int64_t)fr->fog_far - fr->fog_near);
}

void vp_shade_sample(const vp_t *vp, const vp_face_setup *fs, int64_t nz, int64_t col,
                     int64_t row, uint16_t rgb[3])
{
    const unsigned fi = vp->prof.shade_frac_bits, rb = vp->prof.recip_bits;
    const int64_t one = (int64_t)1 << fi;
    bool fog = vp->frame.fog && (fs->flags & WS_FACE_FOG);
    vp_recip rc = {0, 0};
    if (fs->flags & (WS_FACE_SHADE | WS_FACE_TEXTURE) || fog)
        rc = vp_reciprocal_rom(vp, nz);
    int ez = fs->depth.exp;
    /* eq. (7): intensity = shade / depth, clamped to [0, 1] */
    int64_t intensity = one;
    if (fs->flags & WS_FACE_SHADE)
        intensity = fix_clamp(vp_ratio(form_at(&fs->shade, col, row), fs->shade.exp, rc, ez, rb,
                                       (int)fi), 0, one);
    uint32_t texel = 0xFFFFFF;
    if (fs->flags & WS_FACE_TEXTURE) {
        /* nearest texel: the fractions of u and v, tex_log2 bits each */
        unsigned lg = fs->tex_log2;
        unsigned u = ratio_fraction(form_at(&fs->tex_u, col, row), fs->tex_u.exp, rc, ez, rb, lg);
        unsigned v = ratio_fraction(form_at(&fs->tex_v, col, row), fs->tex_v.exp, rc, ez, rb, lg);
        texel = fs->texels[((size_t)v << lg) + u];
    }
    /* output stage: base x texel x intensity scaled to the frame store,
     * round half up: (2 m (2^CB - 1) + D) / 2D with D = 255 * 255 * 2^FI,
     * computed as floor(floor(x / 2^(FI+1)) / 65025) — the same integer, a
     * shift and a division by a constant */
    const uint64_t top = (1u << vp->prof.colour_bits) - 1;
    const uint64_t den = (uint64_t)255 * 255 << fi;
    int64_t vis = one;
    if (fog) {
        int64_t zq = vp_ratio(1, (int)vp->p, rc, ez, rb, 8);
        vis = fog_visibility(&vp->frame, zq, one);
    }
    for (int ch = 0; ch < 3; ch++) {
        uint64_t m = (uint64_t)fs->rgb[ch] * (texel >> (16 - 8 * ch) & 0xFF) * (uint64_t)intensity;
        int64_t out = (int64_t)(((2 * m * top + den) >> (fi + 1)) / 65025u);
        if (fog)   /* blend toward the fog colour, round half up */
            out = (out * vis + (int64_t)vp->fog_rgb[ch] * (one - vis) + one / 2) >> fi;
        rgb[ch] = (uint16_t)out;
    }
}
