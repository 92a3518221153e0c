/* fill.c — the fill unit: the samples of a cell that every edge of a face
 * holds, through the depth test into the sample store, shaded.
 *
 * A face uses some of the shading units — intensity (eq. 7), texture, fog —
 * and most faces of most scenes use few: a flat face's colour is one
 * constant.  So the loop is compiled once per combination of units, the
 * units a face does not use absent from it, and the forms it does use
 * stepped by addition along the cell's rows.  The arithmetic is that of
 * units.h either way; `all_units=1` (docs/profiles.md) runs every unit for
 * every sample instead (vp_shade_sample), with the same pixels. */
#include "units.h"

#include <string.h>

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

/* Ties in the depth store (equal d, 0 < d < max: two faces in one depth
 * step, the earlier kept; ties at the saturated max are depth_saturated's):
 * counted, and the one at the lowest sample index kept for the warning of
 * docs/vp.md §4 — the same sample whatever the tiling. */
static void note_ties(alb_vp *vp, uint64_t ties, size_t idx, uint32_t lost)
{
    if (!vp->st.depth_ties || idx < vp->st.tie_sample) {
        vp->st.tie_sample = idx;
        vp->st.tie_kept = vp->s_face[idx];
        vp->st.tie_lost = lost;
        vp->st.tie_depth = vp->s_depth[idx];
    }
    vp->st.depth_ties += ties;
}

/* The samples of cell k for a face using `units`; a constant at each call
 * site, so every test of it below folds away. */
static inline __attribute__((always_inline)) void
fill_cell(alb_vp *vp, const vp_face_setup *fs, const vp_cell *k, const unsigned units)
{
    const uint32_t cw = 1u << k->wl, ch = 1u << k->hl;
    const unsigned fi = vp->prof.shade_frac_bits, rb = vp->prof.recip_bits, lg = fs->tex_log2;
    const int64_t one = (int64_t)1 << fi;
    const int ez = fs->depth.exp, dsh = units_depth_shift(vp, ez);
    const int64_t dmax = ((int64_t)1 << vp->prof.depth_bits) - 1;
    const uint64_t top = (1u << vp->prof.colour_bits) - 1;
    const uint32_t id = fs->id;
    const uint8_t level = k->level;
    uint32_t *const s_depth = vp->s_depth, *const s_face = vp->s_face;
    uint8_t *const s_level = vp->s_level;
    uint16_t *const s_rgb = vp->s_rgb;
    /* counted locally: the stores below are through uint8_t, which may alias
     * anything, and would make the compiler reload vp->st each sample */
    uint64_t underflow = 0, saturated = 0, written = 0, ties = 0;
    size_t tie_idx = SIZE_MAX;

    /* every form stepped exactly along the rows: N(c + 1, r) = N(c, r) + step_c */
    int64_t z0 = units_form_at(&fs->depth, k->c0, k->r0);
    int64_t s0 = units & U_SHADE ? units_form_at(&fs->shade, k->c0, k->r0) : 0;
    int64_t u0 = units & U_TEXTURE ? units_form_at(&fs->tex_u, k->c0, k->r0) : 0;
    int64_t v0 = units & U_TEXTURE ? units_form_at(&fs->tex_v, k->c0, k->r0) : 0;
    for (uint32_t r = 0; r < ch; r++) {
        size_t idx = (size_t)(k->r0 + r) * vp->sw + k->c0;
        int64_t nz = z0, ns = s0, nu = u0, nv = v0;
        for (uint32_t c = 0; c < cw; c++, idx++) {
            uint32_t dv = units_depth(nz, dsh, dmax);
            underflow += dv == 0 && nz > 0;
            saturated += dv == (uint32_t)dmax;
            /* a later face wins only if strictly nearer: equal depths keep
             * the earlier face (docs/vp.md §4); 0 is "no surface" */
            if (dv != 0 && dv > s_depth[idx]) {
                written++;
                s_depth[idx] = dv;
                s_face[idx] = id;
                s_level[idx] = level;
                uint16_t *out = s_rgb + 3 * idx;
                if (!(units & (U_SHADE | U_TEXTURE))) {
                    memcpy(out, fs->flat, sizeof fs->flat);
                }
                if (units) {
                    vp_recip rc = units_recip(vp, nz);
                    if (units & (U_SHADE | U_TEXTURE)) {
                        int64_t intensity = one;
                        if (units & U_SHADE)
                            intensity = fix_clamp(
                                units_ratio(ns, fs->shade.exp, rc, ez, rb, (int)fi), 0, one);
                        uint32_t texel = 0xFFFFFF;
                        if (units & U_TEXTURE) {
                            unsigned u = units_fraction(nu, fs->tex_u.exp, rc, ez, rb, lg);
                            unsigned v = units_fraction(nv, fs->tex_v.exp, rc, ez, rb, lg);
                            texel = fs->texels[((size_t)v << lg) + u];
                        }
                        for (int i = 0; i < 3; i++)
                            out[i] = units_output((uint64_t)fs->rgb[i] *
                                                      (texel >> (16 - 8 * i) & 0xFF) *
                                                      (uint64_t)intensity,
                                                  top, fi);
                    }
                    if (units & U_FOG) {
                        int64_t zq = units_ratio(1, (int)vp->p, rc, ez, rb, 8);
                        int64_t vis = units_fog_visibility(&vp->frame, zq, one);
                        for (int i = 0; i < 3; i++)
                            out[i] = units_fog_blend(out[i], vp->fog_rgb[i], vis, fi);
                    }
                }
            } else if (dv != 0 && dv == s_depth[idx] && dv != (uint32_t)dmax && ties++ == 0) {
                tie_idx = idx;   /* raster order within the cell: the first is the lowest */
            }
            nz += fs->depth.step_c;
            if (units & U_SHADE)
                ns += fs->shade.step_c;
            if (units & U_TEXTURE)
                nu += fs->tex_u.step_c, nv += fs->tex_v.step_c;
        }
        z0 += fs->depth.step_r;
        if (units & U_SHADE)
            s0 += fs->shade.step_r;
        if (units & U_TEXTURE)
            u0 += fs->tex_u.step_r, v0 += fs->tex_v.step_r;
    }
    vp->st.samples_covered += (uint64_t)cw * ch;
    vp->st.depth_underflow += underflow;
    vp->st.depth_saturated += saturated;
    vp->st.samples_written += written;
    if (ties)
        note_ties(vp, ties, tie_idx, id);
}


/* Every unit on: the same walk, each written sample through vp_shade_sample. */
static void fill_all_units(alb_vp *vp, const vp_face_setup *fs, const vp_cell *k)
{
    const uint32_t cw = 1u << k->wl, ch = 1u << k->hl;
    vp->st.samples_covered += (uint64_t)cw * ch;
    for (uint32_t r = k->r0; r < k->r0 + ch; r++)
        for (uint32_t c = k->c0; c < k->c0 + cw; c++) {
            size_t idx = (size_t)r * vp->sw + c;
            int64_t nz = units_form_at(&fs->depth, c, r);
            uint32_t dv = vp_depth_value(vp, nz, fs->depth.exp);
            vp->st.depth_underflow += dv == 0 && nz > 0;
            vp->st.depth_saturated += dv == (uint32_t)(((uint64_t)1 << vp->prof.depth_bits) - 1);
            if (dv != 0 && dv == vp->s_depth[idx] &&
                dv != (uint32_t)(((uint64_t)1 << vp->prof.depth_bits) - 1))
                note_ties(vp, 1, idx, fs->id);
            if (dv == 0 || dv <= vp->s_depth[idx])
                continue;
            vp->st.samples_written++;
            vp->s_depth[idx] = dv;
            vp->s_face[idx] = fs->id;
            vp->s_level[idx] = k->level;
            vp_shade_sample(vp, fs, nz, c, r, vp->s_rgb + 3 * idx);
        }
}

#define FILL_UNITS(n) \
    static void fill_##n(alb_vp *vp, const vp_face_setup *fs, const vp_cell *k) \
    { \
        fill_cell(vp, fs, k, n); \
    }
FILL_UNITS(0) FILL_UNITS(1) FILL_UNITS(2) FILL_UNITS(3)
FILL_UNITS(4) FILL_UNITS(5) FILL_UNITS(6) FILL_UNITS(7)
#undef FILL_UNITS

static void (*const fill_for_units[8])(alb_vp *, const vp_face_setup *, const vp_cell *) = {
    fill_0, fill_1, fill_2, fill_3, fill_4, fill_5, fill_6, fill_7,
};

void vp_fill(alb_vp *vp, const vp_face_setup *fs, const vp_cell *k)
{
    if (vp->prof.all_units) {
        fill_all_units(vp, fs, k);
        return;
    }
    /* fog is a frame's choice as well as the face's */
    unsigned units = fs->units & (vp->frame.fog ? 7u : (unsigned)~U_FOG & 7u);
    fill_for_units[units](vp, fs, k);
}
