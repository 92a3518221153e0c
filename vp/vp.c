/* vp.c — the video processor's input parser, edge store, subdivision engine
 * and output stage (docs/vp.md).  A face is the intersection of the
 * half-planes of its edges; the screen is subdivided recursively into cells,
 * each classified against every edge by comparing the edge's positions at the
 * cell's borders with the cell's bounds — exact integers, so the middle of a
 * cell is the mean of its borders and every sample is decided exactly. */
#include "vp_internal.h"
#include "../common/fix.h"

#include <stdlib.h>
#include <string.h>

alb_err alb_vp_create(alb_vp **out, const alb_profile *prof, alb_diag *d)
{
    char msg[256];
    if (alb_profile_check(prof, msg, sizeof msg))
        return alb_diag_at(d, ALB_ERR_CONFIG, "", 0, 0, "%s", msg);
    alb_vp *vp = calloc(1, sizeof *vp);
    if (!vp)
        return alb_diag_at(d, ALB_ERR_NOMEM, "", 0, 0, "out of memory");
    vp->prof = *prof;
    vp->lw = fix_log2(prof->width) + prof->aa_levels;
    vp->lh = fix_log2(prof->height) + prof->aa_levels;
    vp->sw = 1u << vp->lw;
    vp->sh = 1u << vp->lh;
    vp->p = vp->lw > vp->lh ? vp->lw : vp->lh;
    size_t n = (size_t)vp->sw * vp->sh;
    vp->s_depth = malloc(n * sizeof *vp->s_depth);
    vp->s_face = malloc(n * sizeof *vp->s_face);
    vp->s_level = malloc(n * sizeof *vp->s_level);
    vp->s_rgb = malloc(3 * n * sizeof *vp->s_rgb);
    if (!vp->s_depth || !vp->s_face || !vp->s_level || !vp->s_rgb || vp_recip_rom_init(vp)) {
        alb_vp_destroy(vp);
        return alb_diag_at(d, ALB_ERR_NOMEM, "", 0, 0, "out of memory for a %ux%u sample store",
                       vp->sw, vp->sh);
    }
    *out = vp;
    return ALB_OK;
}

void alb_vp_destroy(alb_vp *vp)
{
    if (!vp)
        return;
    for (unsigned i = 0; i < ALB_WS_MAX_TEXTURES; i++)
        free(vp->tex[i]);
    free(vp->recip_rom);
    free(vp->batch);
    free(vp->s_depth);
    free(vp->s_face);
    free(vp->s_level);
    free(vp->s_rgb);
    free(vp);
}

const alb_vp_stats *alb_vp_stats_get(const alb_vp *vp) { return &vp->st; }

int alb_vp_frame_alloc(const alb_vp *vp, alb_frame *f, bool with_cycles)
{
    if (alb_frame_alloc(f, vp->prof.width, vp->prof.height, with_cycles))
        return -1;
    f->colour_bits = vp->prof.colour_bits;
    f->depth_bits = vp->prof.depth_bits;
    f->aa_levels = vp->prof.aa_levels;
    f->near = vp->cfg.near;
    return 0;
}

alb_err alb_vp_config(alb_vp *vp, const alb_ws_config *c, alb_diag *d)
{
    if (c->edge_frac_bits != vp->prof.edge_frac_bits || c->coef_bits != vp->prof.coef_bits)
        return alb_diag_at(d, ALB_ERR_CONFIG, "", 0, 0,
                       "the stream's formats (edge_frac_bits=%u coef_bits=%u) differ from the "
                       "profile's (%u, %u): use --set edge_frac_bits=%u --set coef_bits=%u",
                       c->edge_frac_bits, c->coef_bits, vp->prof.edge_frac_bits,
                       vp->prof.coef_bits, c->edge_frac_bits, c->coef_bits);
    vp->cfg = *c;
    vp->configured = true;
    return ALB_OK;
}

alb_err alb_vp_texture(alb_vp *vp, const alb_ws_texture *t, alb_diag *d)
{
    size_t n = (size_t)1 << (2 * t->log2size);
    uint32_t *mem = malloc(n * sizeof *mem);
    if (!mem)
        return alb_diag_at(d, ALB_ERR_NOMEM, "", 0, 0, "out of memory for texture %u", t->id);
    memcpy(mem, t->texels, n * sizeof *mem);
    free(vp->tex[t->id]);
    vp->tex[t->id] = mem;
    vp->tex_log2[t->id] = t->log2size;
    return ALB_OK;
}

/* Sample rows [r0, r1): no surface, the background colour. */
static void clear_rows(alb_vp *vp, void *ctx, uint32_t r0, uint32_t r1)
{
    (void)ctx;
    size_t a = (size_t)r0 * vp->sw, n = (size_t)(r1 - r0) * vp->sw;
    memset(vp->s_depth + a, 0, n * sizeof *vp->s_depth);
    memset(vp->s_face + a, 0xFF, n * sizeof *vp->s_face);
    memset(vp->s_level + a, ALB_FRAME_NO_LEVEL, n);
    for (size_t i = a; i < a + n; i++)
        memcpy(vp->s_rgb + 3 * i, vp->bg, sizeof vp->bg);
}

void alb_vp_frame_begin(alb_vp *vp, const alb_ws_frame *f)
{
    vp->frame = *f;
    memset(&vp->st, 0, sizeof vp->st);
    for (int i = 0; i < 3; i++) {
        vp->bg[i] = vp_scale_colour8(vp, f->background >> (16 - 8 * i) & 0xFF);
        vp->fog_rgb[i] = vp_scale_colour8(vp, f->fog_rgb >> (16 - 8 * i) & 0xFF);
    }
    vp_parallel_rows(vp, vp->sh, clear_rows, NULL);
}

/* ---- set-up of edges and forms (docs/vp.md §2, §3) ---- */

void vp_edge_setup(const alb_vp *vp, const alb_ws_edge *e, vp_edge_fn *fn)
{
    /* With the intercepts q1, q2 (3.F after the +3 shift) a vertical edge is
     * at x_e(y) = X1 + (X2 - X1)(y + 1)/2.  Scaled by S_H 2^F, its position
     * at the border of row r is E(r) = q1 S_H + (q2 - q1)(S_H - r), and the
     * border of column c is at B(c) = 2^(F+1+lh-lw) (S_W + c); G = B - E >= 0
     * on the face's side when R = 0.  Horizontal edges likewise with the roles
     * of rows and columns exchanged (y grows upward, rows downward). */
    int64_t q1 = e->x1, q2 = e->x2, sw = vp->sw, sh = vp->sh;
    unsigned f = vp->cfg.edge_frac_bits;
    int64_t alpha, beta, gamma;
    if (e->u) {
        int64_t k = (int64_t)1 << (f + 1 + vp->lh - vp->lw);
        alpha = k;
        beta = q2 - q1;
        gamma = k * sw - q2 * sh;
    } else {
        int64_t k = (int64_t)1 << (f + 1 + vp->lw - vp->lh);
        alpha = -(q2 - q1);
        beta = -k;
        gamma = 2 * k * sh - q1 * sw;
    }
    /* doubled coordinates: G2(C, R) = alpha C + beta R + 2 gamma = 2 G */
    if (e->r == 0) {         /* inside: G >= 0 — a sample on the line is in */
        fn->a = alpha, fn->b = beta, fn->c = 2 * gamma;
    } else {                 /* inside: G < 0, i.e. -G2 - 1 >= 0 — on the line is out */
        fn->a = -alpha, fn->b = -beta, fn->c = -2 * gamma - 1;
    }
}

void vp_form_setup(const alb_vp *vp, const alb_ws_form *f, vp_form_fn *fn)
{
    /* Sample (c, r) is at X = (2c + 1 - S_W) 2^(P - lw), Y = (S_H - 2r - 1)
     * 2^(P - lh) in units of 2^-P; N = mA X + mB Y + mC 2^P exactly. */
    int64_t xs = (int64_t)1 << (vp->p - vp->lw), ys = (int64_t)1 << (vp->p - vp->lh);
    fn->step_c = 2 * (int64_t)f->m[0] * xs;
    fn->step_r = -2 * (int64_t)f->m[1] * ys;
    fn->origin = (int64_t)f->m[0] * (1 - (int64_t)vp->sw) * xs +
                 (int64_t)f->m[1] * ((int64_t)vp->sh - 1) * ys +
                 (int64_t)f->m[2] * ((int64_t)1 << vp->p);
    fn->exp = f->exp;
}

/* ---- the subdivision engine ---- */

/* Classify cell k against its active edges: -1 outside, 1 inside (every
 * edge holds it wholly), 0 crossing; k->active loses the edges that hold it. */
static int classify(const vp_edge_fn *e, vp_cell *k)
{
    int64_t c0 = 2 * (int64_t)k->c0, c1 = 2 * ((int64_t)k->c0 + (1 << k->wl));
    int64_t r0 = 2 * (int64_t)k->r0, r1 = 2 * ((int64_t)k->r0 + (1 << k->hl));
    uint64_t act = k->active;
    while (act) {
        unsigned i = (unsigned)__builtin_ctzll(act);
        act &= act - 1;
        const vp_edge_fn *f = &e[i];
        /* h is linear: its extremes over the cell are at opposite corners */
        int64_t hmin = f->a * (f->a > 0 ? c0 : c1) + f->b * (f->b > 0 ? r0 : r1) + f->c;
        int64_t hmax = f->a * (f->a > 0 ? c1 : c0) + f->b * (f->b > 0 ? r1 : r0) + f->c;
        if (hmax < 0)
            return -1;
        if (hmin >= 0)
            k->active &= ~(1ull << i);
    }
    return k->active ? 0 : 1;
}

static bool sample_inside(const vp_edge_fn *e, uint64_t active, uint32_t c, uint32_t r)
{
    int64_t cc = 2 * (int64_t)c + 1, rr = 2 * (int64_t)r + 1;
    while (active) {
        unsigned i = (unsigned)__builtin_ctzll(active);
        active &= active - 1;
        if (e[i].a * cc + e[i].b * rr + e[i].c < 0)
            return false;
    }
    return true;
}

void vp_walk_begin(vp_walk *w, const alb_vp *vp, const vp_loaded_face *f)
{
    w->e = f->e;
    w->top = 0;
    w->clipped = false;
    w->stack[w->top++] = (vp_cell){0, 0, (uint8_t)vp->lw, (uint8_t)vp->lh, 0,
                                   f->n == 64 ? ~0ull : (1ull << f->n) - 1};
}

void vp_walk_begin_tile(vp_walk *w, const alb_vp *vp, const vp_loaded_face *f, const vp_cell *tile)
{
    vp_walk_begin(w, vp, f);
    w->clipped = true;
    w->tile = *tile;
}

static bool meets_tile(const vp_walk *w, const vp_cell *k)
{
    const vp_cell *t = &w->tile;
    return k->c0 < t->c0 + (1u << t->wl) && t->c0 < k->c0 + (1u << k->wl) &&
           k->r0 < t->r0 + (1u << t->hl) && t->r0 < k->r0 + (1u << k->hl);
}

/* Whether this walk counts cell k: the tile holding its top-left sample. */
static bool owns(const vp_walk *w, const vp_cell *k)
{
    const vp_cell *t = &w->tile;
    return !w->clipped || (k->c0 - t->c0 < (1u << t->wl) && k->r0 - t->r0 < (1u << t->hl));
}

bool vp_walk_next(alb_vp *vp, vp_walk *w, vp_step *step)
{
    if (!w->top)
        return false;
    vp_cell k = w->stack[--w->top];
    bool own = owns(w, &k);
    vp->st.cells[k.level] += own;
    step->edges = (unsigned)__builtin_popcountll(k.active);
    step->cell = k;
    if (k.wl == 0 && k.hl == 0) {
        /* a single sample: decided at its centre */
        vp->st.samples_tested++;
        step->kind = sample_inside(w->e, k.active, k.c0, k.r0) ? VP_STEP_SAMPLE_IN
                                                               : VP_STEP_SAMPLE_OUT;
        return true;
    }
    int cls = classify(w->e, &k);
    step->cell = k;
    if (cls < 0) {
        vp->st.cells_outside += own;
        step->kind = VP_STEP_OUT;
        return true;
    }
    if (cls > 0) {
        vp->st.cells_inside += own;
        step->kind = VP_STEP_FILL;
        if (w->clipped && (k.wl > w->tile.wl || k.hl > w->tile.hl)) {
            /* fill only the tile's part, as decided at this cell's level */
            step->cell = w->tile;
            step->cell.level = k.level;
        }
        return true;
    }
    vp->st.cells_split += own;
    step->kind = VP_STEP_SPLIT;
    /* children, visited top-left, top-right, bottom-left, bottom-right;
     * a side already one sample long is not split */
    uint8_t wl = k.wl ? k.wl - 1 : 0, hl = k.hl ? k.hl - 1 : 0;
    vp_cell kids[4];
    unsigned nk = 0;
    for (unsigned dy = 0; dy < (k.hl ? 2u : 1u); dy++)
        for (unsigned dx = 0; dx < (k.wl ? 2u : 1u); dx++) {
            vp_cell c = {k.c0 + (dx << wl), k.r0 + (dy << hl), wl, hl, (uint8_t)(k.level + 1),
                         k.active};
            if (!w->clipped || meets_tile(w, &c))
                kids[nk++] = c;
        }
    while (nk)
        w->stack[w->top++] = kids[--nk];
    return true;
}

alb_err vp_load_face(alb_vp *vp, const alb_ws_face *f, vp_loaded_face *out, alb_diag *d)
{
    vp_face_setup *fs = &out->fs;
    memset(fs, 0, sizeof *fs);
    fs->id = f->id;
    fs->flags = f->flags;
    fs->rgb[0] = (uint8_t)(f->rgb >> 16), fs->rgb[1] = (uint8_t)(f->rgb >> 8),
    fs->rgb[2] = (uint8_t)f->rgb;
    vp_form_setup(vp, &f->depth, &fs->depth);
    if (f->flags & ALB_WS_FACE_SHADE)
        vp_form_setup(vp, &f->shade, &fs->shade);
    if (f->flags & ALB_WS_FACE_TEXTURE) {
        if (!vp->tex[f->texture])
            return alb_diag_at(d, ALB_ERR_STREAM, "", 0, 0,
                           "face %u uses texture %u, which no TEXTURE packet loaded", f->id,
                           f->texture);
        vp_form_setup(vp, &f->tex_u, &fs->tex_u);
        vp_form_setup(vp, &f->tex_v, &fs->tex_v);
        fs->texels = vp->tex[f->texture];
        fs->tex_log2 = vp->tex_log2[f->texture];
    }
    for (unsigned i = 0; i < f->n_edges; i++)
        vp_edge_setup(vp, &f->edge[i], &out->e[i]);
    out->n = f->n_edges;
    fs->units = vp_face_units(fs);
    vp_flat_colour(vp, fs, fs->flat);
    return ALB_OK;
}

void vp_count_face(alb_vp *vp, const vp_loaded_face *f)
{
    vp->st.faces++;
    vp->st.edges += f->n;
    vp->st.faces_shaded += (f->fs.flags & ALB_WS_FACE_SHADE) != 0;
    vp->st.faces_textured += (f->fs.flags & ALB_WS_FACE_TEXTURE) != 0;
    vp->st.faces_fogged += vp->frame.fog && (f->fs.flags & ALB_WS_FACE_FOG);
}

alb_err alb_vp_face(alb_vp *vp, const alb_ws_face *f, alb_diag *d)
{
    if (vp->batch) {
        /* threaded: load now (the stream's order of errors), draw in batches */
        alb_err err = vp_load_face(vp, f, &vp->batch[vp->nbatch], d);
        if (err)
            return err;
        vp_count_face(vp, &vp->batch[vp->nbatch]);
        if (++vp->nbatch == VP_BATCH)
            vp_flush_batch(vp);
        return ALB_OK;
    }
    vp_loaded_face lf;
    alb_err err = vp_load_face(vp, f, &lf, d);
    if (err)
        return err;
    vp_count_face(vp, &lf);
    vp_walk w;
    vp_step step;
    vp_walk_begin(&w, vp, &lf);
    while (vp_walk_next(vp, &w, &step))
        if (step.kind == VP_STEP_FILL || step.kind == VP_STEP_SAMPLE_IN)
            vp_fill(vp, &lf.fs, &step.cell);
    return ALB_OK;
}

/* ---- output stage ---- */

/* Pixel rows [y0, y1) of out from their 4^aa samples. */
static void resolve_rows(alb_vp *vp, void *ctx, uint32_t y0, uint32_t y1)
{
    alb_frame *out = ctx;
    unsigned aa = vp->prof.aa_levels, n = 1u << aa;
    for (unsigned y = y0; y < y1; y++)
        for (unsigned x = 0; x < vp->prof.width; x++) {
            /* the pixel's nearest sample gives depth, face and level (ties:
             * the first in raster order); colour is the mean of its samples,
             * rounded half up */
            uint32_t sum[3] = {0, 0, 0}, best = 0;
            size_t best_idx = (size_t)(y << aa) * vp->sw + (x << aa);
            unsigned covered = 0;
            for (unsigned sy = 0; sy < n; sy++)
                for (unsigned sx = 0; sx < n; sx++) {
                    size_t i = (size_t)((y << aa) + sy) * vp->sw + (x << aa) + sx;
                    for (int ch = 0; ch < 3; ch++)
                        sum[ch] += vp->s_rgb[3 * i + ch];
                    covered += vp->s_face[i] != ALB_FRAME_NO_FACE;
                    if (vp->s_depth[i] > best) {
                        best = vp->s_depth[i];
                        best_idx = i;
                    }
                }
            size_t p = (size_t)y * vp->prof.width + x;
            for (int ch = 0; ch < 3; ch++)
                out->rgb[3 * p + ch] = (uint16_t)((sum[ch] + (n * n / 2)) >> (2 * aa));
            out->depth[p] = vp->s_depth[best_idx];
            out->face[p] = vp->s_face[best_idx];
            out->level[p] = vp->s_level[best_idx];
            out->coverage[p] = (uint16_t)covered;
        }
}

void alb_vp_frame_end(alb_vp *vp, alb_frame *out)
{
    vp_flush_batch(vp);
    unsigned aa = vp->prof.aa_levels;
    out->number = vp->frame.number;
    out->near = vp->cfg.near;
    if (aa == 0) {
        /* one sample per pixel: the store is the frame */
        size_t np = (size_t)vp->prof.width * vp->prof.height;
        memcpy(out->rgb, vp->s_rgb, 3 * np * sizeof *out->rgb);
        memcpy(out->depth, vp->s_depth, np * sizeof *out->depth);
        memcpy(out->face, vp->s_face, np * sizeof *out->face);
        memcpy(out->level, vp->s_level, np);
        for (size_t i = 0; i < np; i++)
            out->coverage[i] = vp->s_face[i] != ALB_FRAME_NO_FACE;
        return;
    }
    vp_parallel_rows(vp, vp->prof.height, resolve_rows, out);
}

/* The packets of r's words into the VP, each finished frame to sink, until
 * the words or the stream end. */
static alb_err run_packets(alb_vp *vp, alb_ws_reader *r, alb_ws_event *ev, alb_frame *frame,
                           alb_vp_frame_sink sink, void *ctx, alb_diag *d)
{
    alb_err e = ALB_OK;
    bool refused = false;     /* by the VP, not by the decoder: ev is that packet */
    while (!e && !r->ended && r->pos < r->n) {
        refused = false;
        if ((e = alb_ws_next(r, ev, d)))
            break;
        refused = true;
        switch (ev->kind) {
        case ALB_WS_EV_CONFIG:
            if ((e = alb_vp_config(vp, &ev->u.config, d)))
                break;
            alb_frame_free(frame);
            if (alb_vp_frame_alloc(vp, frame, false))
                e = alb_diag_at(d, ALB_ERR_NOMEM, r->name, 0, 0, "out of memory for a frame");
            break;
        case ALB_WS_EV_TEXTURE:
            e = alb_vp_texture(vp, &ev->u.texture, d);
            break;
        case ALB_WS_EV_FRAME:
            alb_vp_frame_begin(vp, &ev->u.frame);
            break;
        case ALB_WS_EV_FACE:
            e = alb_vp_face(vp, &ev->u.face, d);
            break;
        case ALB_WS_EV_FRAME_END:
            alb_vp_frame_end(vp, frame);
            if (sink && sink(ctx, frame, &vp->st))
                e = ALB_ERR_IO;
            break;
        case ALB_WS_EV_END:
            break;
        }
    }
    if (e && refused && (ev->kind == ALB_WS_EV_CONFIG || ev->kind == ALB_WS_EV_FACE) && d->offset < 0 &&
        !d->line) {
        /* a packet the decoder accepted but this VP cannot take: say where */
        char msg[sizeof d->msg];
        memcpy(msg, d->msg, sizeof msg);
        alb_diag_off(d, e, r->name, (long long)ev->first * 4, "word %zu: %s", ev->first, msg);
    }
    return e;
}

alb_err alb_vp_run_stream(alb_vp *vp, const uint32_t *w, size_t n, const char *name,
                      alb_vp_frame_sink sink, void *ctx, alb_diag *d)
{
    alb_ws_reader r;
    alb_ws_event *ev = malloc(sizeof *ev);
    alb_frame frame;
    memset(&frame, 0, sizeof frame);
    if (!ev)
        return alb_diag_at(d, ALB_ERR_NOMEM, name, 0, 0, "out of memory");
    alb_ws_reader_init(&r, w, n, name);
    r.max_faces = vp->prof.frame_faces;
    alb_err e = run_packets(vp, &r, ev, &frame, sink, ctx, d);
    /* the words ran out before END: the decoder says so */
    if (!e && !r.ended)
        e = alb_ws_next(&r, ev, d);
    alb_frame_free(&frame);
    free(ev);
    return e;
}

struct alb_vp_feed {
    alb_vp *vp;
    alb_ws_reader r;
    alb_ws_event *ev;
    alb_frame frame;
    alb_vp_frame_sink sink;
    void *ctx;
    unsigned long long fed;   /* words before the current piece */
};

alb_err alb_vp_feed_open(alb_vp_feed **out, alb_vp *vp, const char *name, alb_vp_frame_sink sink,
                         void *ctx, alb_diag *d)
{
    alb_vp_feed *f = calloc(1, sizeof *f);
    if (f && !(f->ev = malloc(sizeof *f->ev))) {
        free(f);
        f = NULL;
    }
    *out = f;
    if (!f)
        return alb_diag_at(d, ALB_ERR_NOMEM, name, 0, 0, "out of memory");
    f->vp = vp;
    f->sink = sink;
    f->ctx = ctx;
    alb_ws_reader_init(&f->r, NULL, 0, name);
    f->r.max_faces = vp->prof.frame_faces;
    return ALB_OK;
}

alb_err alb_vp_feed_words(alb_vp_feed *f, const uint32_t *w, size_t n, alb_diag *d)
{
    /* the reader keeps its state (CONFIG seen, inside a frame) from piece
     * to piece; only its words change */
    f->r.w = w;
    f->r.n = n;
    f->r.pos = 0;
    alb_err e = run_packets(f->vp, &f->r, f->ev, &f->frame, f->sink, f->ctx, d);
    if (!e && f->r.pos < n)
        e = alb_diag_off(d, ALB_ERR_STREAM, f->r.name, (long long)(f->fed + f->r.pos) * 4,
                         "words after END");
    if (e && d->offset >= 0)   /* located in the whole stream, not the piece */
        d->offset += (long long)f->fed * 4;
    f->fed += n;
    return e;
}

void alb_vp_feed_close(alb_vp_feed *f)
{
    if (!f)
        return;
    alb_frame_free(&f->frame);
    free(f->ev);
    free(f);
}
