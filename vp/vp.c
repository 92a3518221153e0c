/* vp.c — the video processor's input parser, edge store, subdivision engine
 * and output stage (docs/vp.md).  A face is the intersection of the
 * half-planes of its edges; the screen is subdivided recursively into cells,
 * each classified against every edge by comparing the edge's positions at the
 * cell's borders with the cell's bounds — exact integers, so the middle of a
 * cell is the mean of its borders and every sample is decided exactly. */
#include "units.h"
#include "simd.h"

#include <stdlib.h>
#include <string.h>

static alb_err vp_create(alb_vp **out, const alb_profile *prof, bool counters_only, alb_diag *d)
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
    vp_depth_forms_t forms[3];
    const char *names[3];
    /* the host's fastest forms, or with simd=0 the plain C ones (the last) */
    unsigned nforms = counters_only ? vp_depth_forms_untagged(forms, names) : vp_depth_forms(forms, names);
    vp->depth_forms = forms[prof->simd ? 0 : nforms - 1];
    vp->walk_avx2 = prof->simd && vp_walk_avx2_host();
    vp->shade_isa = prof->simd ? vp_shade_isa_host() : 0;
    vp->counters_only = counters_only;
    /* counters alone: no output stage, so no scratch and no reciprocal ROM */
    if (vp_store_init(vp) || (!counters_only && (vp_scratch_for(vp, 1) || vp_recip_rom_init(vp)))) {
        alb_vp_destroy(vp);
        return alb_diag_at(d, ALB_ERR_NOMEM, "", 0, 0, "out of memory for a %ux%u sample store",
                       vp->sw, vp->sh);
    }
    *out = vp;
    return ALB_OK;
}

alb_err alb_vp_create(alb_vp **out, const alb_profile *prof, alb_diag *d)
{
    return vp_create(out, prof, false, d);
}

alb_err vp_create_counters(alb_vp **out, const alb_profile *prof, alb_diag *d)
{
    return vp_create(out, prof, true, d);
}

void alb_vp_destroy(alb_vp *vp)
{
    if (!vp)
        return;
    for (unsigned i = 0; i < ALB_WS_MAX_TEXTURES; i++)
        free(vp->tex[i]);
    free(vp->recip_rom);
    vp_threads_free(vp);
    free(vp->scratch);
    vp_store_free(vp);
    free(vp);
}

const alb_vp_stats *alb_vp_stats_get(const alb_vp *vp) { return &vp->st; }

int alb_vp_frame_alloc(const alb_vp *vp, alb_frame *f, bool with_cycles)
{
    return alb_vp_frame_alloc_planes(vp, f, ALB_FRAME_PLANES | (with_cycles ? ALB_FRAME_CYCLES : 0));
}

int alb_vp_frame_alloc_planes(const alb_vp *vp, alb_frame *f, unsigned planes)
{
    if (alb_frame_alloc_planes(f, vp->prof.width, vp->prof.height, planes))
        return -1;
    f->colour_bits = vp->prof.colour_bits;
    f->depth_bits = vp->prof.depth_bits;
    f->aa_levels = vp->prof.aa_levels;
    f->near = vp->cfg.near;
    return 0;
}

alb_err alb_vp_config(alb_vp *vp, const alb_ws_config *c, alb_diag *d)
{
    vp_flush_batch(vp);   /* the faces given are drawn under the old configuration */
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
    vp_flush_batch(vp);   /* no face drawn while its texture may change */
    size_t n = (size_t)1 << (2 * t->log2size);
    uint32_t *mem = malloc(n * sizeof *mem);
    if (!mem)
        return alb_diag_at(d, ALB_ERR_NOMEM, "", 0, 0, "out of memory for texture %u", t->id);
    memcpy(mem, t->texels, n * sizeof *mem);
    /* faces of this frame drawn with the old texels are shaded with them
     * when the frame is resolved */
    if (vp->tex[t->id] && vp_store_retire_texture(vp, vp->tex[t->id])) {
        free(mem);
        return alb_diag_at(d, ALB_ERR_NOMEM, "", 0, 0, "out of memory for texture %u", t->id);
    }
    vp->tex[t->id] = mem;
    vp->tex_log2[t->id] = t->log2size;
    return ALB_OK;
}

void alb_vp_frame_begin(alb_vp *vp, const alb_ws_frame *f)
{
    vp_flush_batch(vp);   /* faces given before it are the last frame's */
    vp->frame = *f;
    memset(&vp->st, 0, sizeof vp->st);
    for (int i = 0; i < 3; i++) {
        vp->bg[i] = vp_scale_colour8(vp, f->background >> (16 - 8 * i) & 0xFF);
        vp->fog_rgb[i] = vp_scale_colour8(vp, f->fog_rgb >> (16 - 8 * i) & 0xFF);
    }
    /* the store is cleared tile by tile as the frame's fills reach it */
    vp_store_begin(vp);
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
static inline __attribute__((always_inline)) int classify(const vp_edge_fn *e, vp_cell *k)
{
    const int64_t c0 = 2 * (int64_t)k->c0, r0 = 2 * (int64_t)k->r0;
    const int64_t w = (int64_t)2 << k->wl, h = (int64_t)2 << k->hl;
    uint64_t act = k->active;
    while (act) {
        unsigned i = (unsigned)__builtin_ctzll(act);
        act &= act - 1;
        const vp_edge_fn *f = &e[i];
        /* h is linear: its extremes over the cell are at opposite corners,
         * h at the top-left one plus the sides' positive or negative parts */
        int64_t h0 = f->a * c0 + f->b * r0 + f->c, ax = f->a * w, by = f->b * h;
        int64_t hmax = h0 + (ax > 0 ? ax : 0) + (by > 0 ? by : 0);
        if (hmax < 0)
            return -1;
        int64_t hmin = h0 + (ax < 0 ? ax : 0) + (by < 0 ? by : 0);
        if (hmin >= 0) {
            k->active &= ~(1ull << i);
            k->edges--;
        }
    }
    return k->active ? 0 : 1;
}

static inline bool sample_inside(const vp_edge_fn *e, uint64_t active, uint32_t c, uint32_t r)
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
    w->n = f->n;
    w->narrow = f->narrow;
    w->lanes_ready = false;
    w->top = 0;
    if (f->narrow) {
        unsigned i = 0;
        for (; i < f->n; i++)
            w->ea[i] = f->e[i].a, w->eb[i] = f->e[i].b, w->ec[i] = f->e[i].c;
        for (; i % 4; i++)
            w->ea[i] = w->eb[i] = w->ec[i] = 0;
    }
    w->stack[w->top++] = (vp_cell){.wl = (uint8_t)vp->lw, .hl = (uint8_t)vp->lh,
                                   .edges = (uint8_t)f->n,
                                   .active = f->n == 64 ? ~0ull : (1ull << f->n) - 1};
}

/* A child onto the stack. */
static inline void push(vp_walk *w, uint32_t c0, uint32_t r0, uint8_t wl, uint8_t hl, uint8_t level,
                        const vp_cell *parent)
{
    w->stack[w->top++] = (vp_cell){c0, r0, wl, hl, level, parent->edges, parent->active};
}

bool vp_walk_next(alb_vp *vp, vp_walk *w, vp_step *step)
{
    if (!w->top)
        return false;
    vp_cell *k = &step->cell;
    *k = w->stack[--w->top];
    vp->st.cells[k->level]++;
    step->edges = k->edges;
    if (k->wl == 0 && k->hl == 0) {
        /* a single sample: decided at its centre */
        vp->st.samples_tested++;
        step->kind = sample_inside(w->e, k->active, k->c0, k->r0) ? VP_STEP_SAMPLE_IN
                                                                 : VP_STEP_SAMPLE_OUT;
        return true;
    }
    int cls = classify(w->e, k);
    if (cls < 0) {
        vp->st.cells_outside++;
        step->kind = VP_STEP_OUT;
        return true;
    }
    if (cls > 0) {
        vp->st.cells_inside++;
        step->kind = VP_STEP_FILL;
        return true;
    }
    vp->st.cells_split++;
    step->kind = VP_STEP_SPLIT;
    /* children, visited top-left, top-right, bottom-left, bottom-right (so
     * pushed in reverse); a side already one sample long is not split */
    const uint8_t wl = k->wl ? k->wl - 1 : 0, hl = k->hl ? k->hl - 1 : 0, l = k->level + 1;
    const uint32_t c0 = k->c0, r0 = k->r0, dx = k->wl ? 1u << wl : 0, dy = k->hl ? 1u << hl : 0;
    if (dy) {
        if (dx)
            push(w, c0 + dx, r0 + dy, wl, hl, l, k);
        push(w, c0, r0 + dy, wl, hl, l, k);
    }
    if (dx)
        push(w, c0 + dx, r0, wl, hl, l, k);
    push(w, c0, r0, wl, hl, l, k);
    return true;
}

/* ---- the functional engine: the same walk, drawing as it goes ----
 *
 * The clocked models need the walk a step at a time (vp_walk_next); the
 * functional renderer only its outcome.  This is the same walk — the same
 * cells in the same order, classified alike, counted alike, each sample
 * decided at the same level — as a recursion that fills as it goes and
 * decides the last levels' cells and samples where their parent splits,
 * without a step apiece.  Equal to vp_walk_next with vp_fill on every
 * statistic and every sample (tests/test_timing.c compares the functional
 * fidelity with the clocked ones).
 *
 * The engine is one body compiled for two instruction sets: the baseline
 * (SSE2 lanes on x86-64, plain C elsewhere and with -DALB_NO_SIMD) and, where
 * the compiler can target it, AVX2 with POPCNT, which the VP takes when the
 * host has them and the profile's `simd` allows (alb_vp_create).  `isa` is a
 * constant at every call; it chooses the lanes of the edge arithmetic and
 * how bits are counted, never what is computed. */

enum { ISA_BASE, ISA_AVX2 };
#if VP_AVX2
#include <immintrin.h>
#define ISA_AVX2_TARGET __attribute__((target("avx2,popcnt")))
#endif

bool vp_walk_avx2_host(void)
{
#if VP_AVX2
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("popcnt");
#else
    return false;
#endif
}

/* Set bits of a mask: the POPCNT instruction where the instruction set has
 * it, else plain C. */
static inline unsigned popcount_isa(uint64_t m, const int isa)
{
    if (VP_AVX2 && isa == ISA_AVX2)
        return (unsigned)__builtin_popcountll(m);
    return vp_popcount(m);
}

/* The children of a cell k that splits, in the walk's order: bit 0 the
 * top-left, 1 top-right, 2 bottom-left, 3 bottom-right; a side one sample
 * long is not split. */
static inline unsigned children_present(uint32_t dx, uint32_t dy)
{
    return 1u | (dx ? 2u : 0) | (dy ? 4u : 0) | (dx && dy ? 8u : 0);
}

void vp_timer_init(vp_timer *tm, const alb_profile *p, int64_t *take_ring)
{
    /* docs/microarchitecture.md: a step evaluates edge_units edges a cycle
     * (one cycle with none), a fill issues fill_rate samples a cycle */
    memset(tm, 0, sizeof *tm);
    for (unsigned e = 0; e <= ALB_WS_MAX_EDGES; e++)
        tm->step_cycles[e] = (uint8_t)(e ? (e + p->edge_units - 1) / p->edge_units : 1);
    for (unsigned s = 0; s < sizeof tm->fill_cycles / sizeof *tm->fill_cycles; s++)
        tm->fill_cycles[s] = ((1ull << s) + p->fill_rate - 1) / p->fill_rate;
    tm->take_ring = take_ring;
    tm->fill_queue = p->fill_queue;
    for (unsigned i = 0; take_ring && i < p->fill_queue; i++)
        take_ring[i] = INT64_MIN / 4;
}

/* The timer's part of a step on cell k evaluating `edges` edges, and of a
 * hand-over to the fill unit in its last cycle; nothing without a timer
 * (`timed` is a constant at every call site). */
static inline void timer_step(vp_timer *tm, const vp_cell *k, unsigned edges, const bool timed)
{
    if (!timed)
        return;
    unsigned c = tm->step_cycles[edges];
    tm->pending += c;
    if (tm->charge)
        tm->charge(tm, k, c);
}

static inline void timer_hand_over(vp_timer *tm, const vp_cell *k, const bool timed)
{
    if (timed)
        vp_timer_hand_over(tm, k);
}

/* Children that are single samples, each the walk's next step in turn:
 * decided at their centres, the active edges at the top-left one and the
 * others a column (2a) or a row (2b) on. */
static inline __attribute__((always_inline)) void
draw_samples(alb_vp *vp, vp_walk *w, const vp_face_setup *fs, const vp_cell *k,
             unsigned present, vp_timer *tm, const bool timed)
{
    const int64_t cc = 2 * (int64_t)k->c0 + 1, rr = 2 * (int64_t)k->r0 + 1;
    unsigned in = present;
    for (uint64_t act = k->active; act && in; act &= act - 1) {
        const vp_edge_fn *f = &w->e[__builtin_ctzll(act)];
        int64_t h = f->a * cc + f->b * rr + f->c;
        in &= (h >= 0) | (h + 2 * f->a >= 0) << 1 | (h + 2 * f->b >= 0) << 2 |
              (h + 2 * (f->a + f->b) >= 0) << 3;
    }
    const uint8_t l = k->level + 1;
    vp->st.cells[l] += vp_bits4(present);
    vp->st.samples_tested += vp_bits4(present);
    for (unsigned j = 0; j < 4; j++) {
        vp_cell c = {k->c0 + (j & 1), k->r0 + (j >> 1), 0, 0, l, 0, 0};
        if (present >> j & 1)
            timer_step(tm, &c, k->edges, timed);
        if (in >> j & 1) {
            units_fill_sample(vp, fs, c.c0, c.r0, l);
            timer_hand_over(tm, &c, timed);
        }
    }
}

/* A cell the walk found inside every edge. */
static inline void draw_fill(alb_vp *vp, const vp_face_setup *fs, const vp_cell *k)
{
    vp_fill(vp, fs, k);
}

/* ---- an 8 x 8 cell that splits, decided in one pass ----
 *
 * Its four 4 x 4 children, their 2 x 2 children and the samples of those
 * that split.  Every active edge of the cell crosses it (else the cell would
 * be out or would not split).  Per edge, its values at the children's and
 * grandchildren's corners give their extremes as in draw_split, and its
 * values at the 64 sample centres, a column (2a) or a row (2b) apart, the
 * samples outside: sign masks.  A cell's verdict against the parent's active
 * edges is its verdict against its own: an edge that holds a cell holds
 * every cell and sample in it and rejects none. */
typedef struct {
    unsigned out4, held4;    /* children (bit 2 cy + cx): rejected, held by every edge */
    unsigned out2, held2;    /* grandchildren (bit 4 gy + gx) likewise */
    uint64_t outside;        /* samples outside some edge (bit 8 sy + sx) */
    uint32_t loose4;         /* byte j: edges not holding child j (the timer's) */
    uint32_t loose2[4];      /* byte gx of word gy: edges not holding grandchild (gx, gy) */
} block8_verdicts;

/* 4 bits to 4 bytes: counts of the edges that do not hold each cell */
static const uint32_t spread4[16] = {
    0x00000000, 0x00000001, 0x00000100, 0x00000101, 0x00010000, 0x00010001, 0x00010100,
    0x00010101, 0x01000000, 0x01000001, 0x01000100, 0x01000101, 0x01010000, 0x01010001,
    0x01010100, 0x01010101};

/* One edge's verdicts in 64-bit lanes, two at a time (vp/simd.h): any edge. */
static inline __attribute__((always_inline)) void
edge_block8(const vp_edge_fn *f, int64_t c0, int64_t r0, block8_verdicts *v)
{
    const int64_t a = f->a, b = f->b, h = a * c0 + b * r0 + f->c;
    /* children: sides 8 in doubled coordinates */
    const int64_t a8 = 8 * a, b8 = 8 * b;
    const v2 up4 = v2_splat((a8 > 0 ? a8 : 0) + (b8 > 0 ? b8 : 0));
    const v2 down4 = v2_splat((a8 < 0 ? a8 : 0) + (b8 < 0 ? b8 : 0));
    const v2 top = v2_set(h, h + a8), bottom = v2_set(h + b8, h + a8 + b8);
    v->out4 |= v2_neg(v2_add(top, up4)) | v2_neg(v2_add(bottom, up4)) << 2;
    const unsigned loose4 = v2_neg(v2_add(top, down4)) | v2_neg(v2_add(bottom, down4)) << 2;
    v->held4 &= ~loose4;
    v->loose4 += spread4[loose4];
    /* grandchildren: sides 4, a row of four a step */
    const int64_t a4 = 4 * a, b4 = 4 * b;
    const v2 up2 = v2_splat((a4 > 0 ? a4 : 0) + (b4 > 0 ? b4 : 0));
    const v2 down2 = v2_splat((a4 < 0 ? a4 : 0) + (b4 < 0 ? b4 : 0));
    const v2 row4 = v2_splat(b4);
    v2 left = v2_set(h, h + a4), right = v2_set(h + 2 * a4, h + 3 * a4);
    unsigned out2 = 0, loose2 = 0;
    for (unsigned gy = 0; gy < 4; gy++, left = v2_add(left, row4), right = v2_add(right, row4)) {
        out2 |= (v2_neg(v2_add(left, up2)) | v2_neg(v2_add(right, up2)) << 2) << 4 * gy;
        const unsigned loose = v2_neg(v2_add(left, down2)) | v2_neg(v2_add(right, down2)) << 2;
        loose2 |= loose << 4 * gy;
        v->loose2[gy] += spread4[loose];
    }
    v->out2 |= out2;
    v->held2 &= ~loose2;
    /* samples: the top-left one's centre, then columns and rows on */
    const int64_t s = h + a + b, a2 = 2 * a;
    v2 x0 = v2_set(s, s + a2), x1 = v2_set(s + 2 * a2, s + 3 * a2);
    v2 x2 = v2_set(s + 4 * a2, s + 5 * a2), x3 = v2_set(s + 6 * a2, s + 7 * a2);
    const v2 row = v2_splat(2 * b);
    uint64_t outside = 0;
    for (unsigned sy = 0; sy < 8; sy++) {
        outside |= (uint64_t)(v2_neg(x0) | v2_neg(x1) << 2 | v2_neg(x2) << 4 | v2_neg(x3) << 6)
                   << 8 * sy;
        x0 = v2_add(x0, row), x1 = v2_add(x1, row), x2 = v2_add(x2, row), x3 = v2_add(x3, row);
    }
    v->outside |= outside;
}

#if VP_AVX2
/* An edge's offsets for the 32-bit lanes (vp_lanes8), once per face. */
ISA_AVX2_TARGET static void narrow_lanes(const vp_edge_fn *f, vp_lanes8 *ln)
{
    const int32_t a = (int32_t)f->a, b = (int32_t)f->b, a4 = 4 * a, b4 = 4 * b, a8 = 8 * a, b8 = 8 * b;
    const __m256i va = _mm256_set1_epi32(a), vb = _mm256_set1_epi32(b);
    /* a (2x + 1) + b; 4a gx + 4b gy */
    _mm256_storeu_si256((__m256i *)(void *)ln->row0,
                        _mm256_add_epi32(_mm256_mullo_epi32(va, _mm256_setr_epi32(1, 3, 5, 7, 9, 11, 13, 15)), vb));
    _mm256_storeu_si256((__m256i *)(void *)ln->g01,
                        _mm256_add_epi32(_mm256_mullo_epi32(va, _mm256_setr_epi32(0, 4, 8, 12, 0, 4, 8, 12)),
                                         _mm256_mullo_epi32(vb, _mm256_setr_epi32(0, 0, 0, 0, 4, 4, 4, 4))));
    ln->t4[0] = 0, ln->t4[1] = a8, ln->t4[2] = b8, ln->t4[3] = a8 + b8;
    ln->up4 = (a8 > 0 ? a8 : 0) + (b8 > 0 ? b8 : 0);
    ln->down4 = (a8 < 0 ? a8 : 0) + (b8 < 0 ? b8 : 0);
    ln->up2 = (a4 > 0 ? a4 : 0) + (b4 > 0 ? b4 : 0);
    ln->down2 = (a4 < 0 ? a4 : 0) + (b4 < 0 ? b4 : 0);
    ln->step2 = 2 * b;
}

/* The same verdicts in 32-bit lanes, eight at a time, for an edge of a
 * narrow face (vp_loaded_face.narrow: |a| + |b| < 2^27).  The edge crosses
 * the cell, so at every point of it |h| <= hmax - hmin = 16 (|a| + |b|) <
 * 2^31: each value below is exact in 32 bits.  The samples' signs survive
 * the signed saturating packs to bytes, four rows to a register. */
ISA_AVX2_TARGET static inline void edge_block8_narrow(const vp_edge_fn *f, const vp_lanes8 *ln,
                                                      int64_t c0, int64_t r0, block8_verdicts *v,
                                                      const bool timed)
{
    const int32_t h = (int32_t)(f->a * c0 + f->b * r0 + f->c);
    const __m256i vh = _mm256_set1_epi32(h);
    /* children: their top-left corners in lanes 0..3 */
    const __m128i t4 = _mm_add_epi32(_mm256_castsi256_si128(vh),
                                     _mm_loadu_si128((const __m128i *)(const void *)ln->t4));
    v->out4 |= (unsigned)_mm_movemask_ps(_mm_castsi128_ps(_mm_add_epi32(t4, _mm_set1_epi32(ln->up4))));
    const unsigned loose4 =
        (unsigned)_mm_movemask_ps(_mm_castsi128_ps(_mm_add_epi32(t4, _mm_set1_epi32(ln->down4))));
    v->held4 &= ~loose4;
    /* grandchildren: rows 0 and 1 of their corners in one register, 2 and 3
     * in the other */
    const __m256i g01 = _mm256_add_epi32(vh, _mm256_loadu_si256((const __m256i *)(const void *)ln->g01));
    const __m256i g23 = _mm256_add_epi32(g01, _mm256_set1_epi32(4 * ln->step2));
    const __m256i up2 = _mm256_set1_epi32(ln->up2), down2 = _mm256_set1_epi32(ln->down2);
    v->out2 |= (unsigned)_mm256_movemask_ps(_mm256_castsi256_ps(_mm256_add_epi32(g01, up2))) |
               (unsigned)_mm256_movemask_ps(_mm256_castsi256_ps(_mm256_add_epi32(g23, up2))) << 8;
    const unsigned loose2 =
        (unsigned)_mm256_movemask_ps(_mm256_castsi256_ps(_mm256_add_epi32(g01, down2))) |
        (unsigned)_mm256_movemask_ps(_mm256_castsi256_ps(_mm256_add_epi32(g23, down2))) << 8;
    v->held2 &= ~loose2;
    if (timed) {
        v->loose4 += spread4[loose4];
#pragma GCC unroll 4
        for (unsigned gy = 0; gy < 4; gy++)
            v->loose2[gy] += spread4[loose2 >> 4 * gy & 0xF];
    }
    /* samples: row sy in a register, 2b apart */
    const __m256i step = _mm256_set1_epi32(ln->step2);
    __m256i r[8];
    r[0] = _mm256_add_epi32(vh, _mm256_loadu_si256((const __m256i *)(const void *)ln->row0));
#pragma GCC unroll 7
    for (unsigned sy = 1; sy < 8; sy++)
        r[sy] = _mm256_add_epi32(r[sy - 1], step);
    /* per 128-bit half the packs give bytes of rows 0..3 (or 4..7), columns
     * 0..3 in the low half and 4..7 in the high: the permutation puts each
     * row's eight bytes together, so byte 8 y + x is sample (x, y) */
    const __m256i order = _mm256_setr_epi32(0, 4, 1, 5, 2, 6, 3, 7);
    const __m256i q0 = _mm256_packs_epi16(_mm256_packs_epi32(r[0], r[1]), _mm256_packs_epi32(r[2], r[3]));
    const __m256i q1 = _mm256_packs_epi16(_mm256_packs_epi32(r[4], r[5]), _mm256_packs_epi32(r[6], r[7]));
    const uint32_t m0 = (uint32_t)_mm256_movemask_epi8(_mm256_permutevar8x32_epi32(q0, order));
    const uint32_t m1 = (uint32_t)_mm256_movemask_epi8(_mm256_permutevar8x32_epi32(q1, order));
    v->outside |= (uint64_t)m0 | (uint64_t)m1 << 32;
}

/* The same over all the cell's active edges at once where no edge's own
 * verdicts are counted (no timer, or one whose steps all take a cycle):
 * the signs that reject or loosen a cell or sample are ORed over the edges
 * in the registers, and turned into masks once. */
typedef struct {
    __m128i out4, loose4;
    __m256i out2[2], loose2[2];
    __m256i rows[4];          /* rows 2i and 2i + 1 of samples, packed to 16 bits */
} block8_signs;

ISA_AVX2_TARGET static inline void edge_block8_signs(const vp_edge_fn *f, const vp_lanes8 *ln, int64_t c0,
                                                     int64_t r0, block8_signs *s)
{
    const int32_t h = (int32_t)(f->a * c0 + f->b * r0 + f->c);
    const __m256i vh = _mm256_set1_epi32(h);
    const __m128i t4 = _mm_add_epi32(_mm256_castsi256_si128(vh),
                                     _mm_loadu_si128((const __m128i *)(const void *)ln->t4));
    s->out4 = _mm_or_si128(s->out4, _mm_add_epi32(t4, _mm_set1_epi32(ln->up4)));
    s->loose4 = _mm_or_si128(s->loose4, _mm_add_epi32(t4, _mm_set1_epi32(ln->down4)));
    const __m256i g01 = _mm256_add_epi32(vh, _mm256_loadu_si256((const __m256i *)(const void *)ln->g01));
    const __m256i g23 = _mm256_add_epi32(g01, _mm256_set1_epi32(4 * ln->step2));
    const __m256i up2 = _mm256_set1_epi32(ln->up2), down2 = _mm256_set1_epi32(ln->down2);
    s->out2[0] = _mm256_or_si256(s->out2[0], _mm256_add_epi32(g01, up2));
    s->out2[1] = _mm256_or_si256(s->out2[1], _mm256_add_epi32(g23, up2));
    s->loose2[0] = _mm256_or_si256(s->loose2[0], _mm256_add_epi32(g01, down2));
    s->loose2[1] = _mm256_or_si256(s->loose2[1], _mm256_add_epi32(g23, down2));
    const __m256i step = _mm256_set1_epi32(ln->step2);
    __m256i r = _mm256_add_epi32(vh, _mm256_loadu_si256((const __m256i *)(const void *)ln->row0));
#pragma GCC unroll 4
    for (unsigned i = 0; i < 4; i++) {
        const __m256i next = _mm256_add_epi32(r, step);
        s->rows[i] = _mm256_or_si256(s->rows[i], _mm256_packs_epi32(r, next));
        r = _mm256_add_epi32(next, step);
    }
}

/* The masks of the signs ORed over the edges into v (as edge_block8_narrow
 * would have left them, but the timer's counts). */
ISA_AVX2_TARGET static inline void block8_signs_done(const block8_signs *s, block8_verdicts *v);

/* Every active edge's signs ORed, then their masks into v. */
ISA_AVX2_TARGET static inline void block8_narrow_all(const vp_walk *w, uint64_t active, int64_t c0, int64_t r0,
                                              block8_verdicts *v)
{
    block8_signs sg;
    sg.out4 = sg.loose4 = _mm_setzero_si128();
    sg.out2[0] = sg.out2[1] = sg.loose2[0] = sg.loose2[1] = _mm256_setzero_si256();
    sg.rows[0] = sg.rows[1] = sg.rows[2] = sg.rows[3] = _mm256_setzero_si256();
    for (; active; active &= active - 1) {
        const unsigned i = (unsigned)__builtin_ctzll(active);
        edge_block8_signs(&w->e[i], &w->lanes[i], c0, r0, &sg);
    }
    block8_signs_done(&sg, v);
}

ISA_AVX2_TARGET static inline void block8_signs_done(const block8_signs *s, block8_verdicts *v)
{
    v->out4 |= (unsigned)_mm_movemask_ps(_mm_castsi128_ps(s->out4));
    v->held4 &= ~(unsigned)_mm_movemask_ps(_mm_castsi128_ps(s->loose4));
    v->out2 |= (unsigned)_mm256_movemask_ps(_mm256_castsi256_ps(s->out2[0])) |
               (unsigned)_mm256_movemask_ps(_mm256_castsi256_ps(s->out2[1])) << 8;
    v->held2 &= ~((unsigned)_mm256_movemask_ps(_mm256_castsi256_ps(s->loose2[0])) |
                  (unsigned)_mm256_movemask_ps(_mm256_castsi256_ps(s->loose2[1])) << 8);
    const __m256i order = _mm256_setr_epi32(0, 4, 1, 5, 2, 6, 3, 7);
    const __m256i q0 = _mm256_packs_epi16(s->rows[0], s->rows[1]);
    const __m256i q1 = _mm256_packs_epi16(s->rows[2], s->rows[3]);
    const uint32_t m0 = (uint32_t)_mm256_movemask_epi8(_mm256_permutevar8x32_epi32(q0, order));
    const uint32_t m1 = (uint32_t)_mm256_movemask_epi8(_mm256_permutevar8x32_epi32(q1, order));
    v->outside |= (uint64_t)m0 | (uint64_t)m1 << 32;
}
#endif

/* A 16-bit mask of grandchildren (bit 4 gy + gx) as their samples (bit 8 sy
 * + sx), and a 4-bit mask of children likewise: from tables, a byte of
 * grandchildren (two rows of four) at a time.  Entry b of the first is
 * rows 2i and 2i + 1 of cells to their four rows of samples: each bit
 * doubled within its row, each row doubled. */
#define S2(n) (((n) & 1 ? 0x03u : 0) | ((n) & 2 ? 0x0Cu : 0) | ((n) & 4 ? 0x30u : 0) | ((n) & 8 ? 0xC0u : 0))
#define S4(b) ((S2((b) & 15) * 0x0101u) | (S2((b) >> 4) * 0x0101u) << 16)
#define S4x4(b) S4(b), S4((b) + 1), S4((b) + 2), S4((b) + 3)
#define S4x16(b) S4x4(b), S4x4((b) + 4), S4x4((b) + 8), S4x4((b) + 12)
#define S4x64(b) S4x16(b), S4x16((b) + 16), S4x16((b) + 32), S4x16((b) + 48)
static const uint32_t grandchild_rows[256] = {S4x64(0), S4x64(64), S4x64(128), S4x64(192)};
#undef S2
#undef S4
#undef S4x4
#undef S4x16
#undef S4x64

static inline uint64_t samples_of_grandchildren(unsigned g)
{
    return grandchild_rows[g & 0xFF] | (uint64_t)grandchild_rows[g >> 8 & 0xFF] << 32;
}

static inline uint64_t samples_of_children(unsigned c)
{
    static const uint64_t children[16] = {
#define C4(c) (((c) & 1 ? 0x0F0F0F0Full : 0) | ((c) & 2 ? 0xF0F0F0F0ull : 0) | \
               ((c) & 4 ? 0x0F0F0F0F00000000ull : 0) | ((c) & 8 ? 0xF0F0F0F000000000ull : 0))
        C4(0), C4(1), C4(2),  C4(3),  C4(4),  C4(5),  C4(6),  C4(7),
        C4(8), C4(9), C4(10), C4(11), C4(12), C4(13), C4(14), C4(15)
#undef C4
    };
    return children[c & 15];
}

/* The steps below an 8 x 8 cell k in the walk's order, for the timer: each
 * child, each grandchild of a split child, each sample of a split
 * grandchild, and the hand-overs of those found inside.  The walk's order
 * gives the hand-overs and the engine cycles before each, which then go
 * through the fill queue together (vp_timer_hand_overs).  With `unit` every
 * step takes one cycle (the face has no more edges than the engine has edge
 * units), so the edges a step evaluates are not needed; with `charged` each
 * step and fill is charged to its cell on the per-pixel map, whose sums do
 * not depend on when.  Both are constants at each call. */
typedef struct {
    uint32_t gap[4 + 16 + 64];   /* engine cycles before each hand-over */
    uint32_t fill[4 + 16 + 64];  /* its fill's cycles */
    unsigned n;
    uint32_t since;              /* cycles since the last */
    uint64_t engine, filled;     /* the sums */
} hand_over_list;

static inline __attribute__((always_inline)) void
time_step(vp_timer *tm, hand_over_list *h, const vp_cell *k, uint32_t x, uint32_t y, uint8_t lg,
          uint8_t level, unsigned edges, const bool unit, const bool charged)
{
    const unsigned c = unit ? 1 : tm->step_cycles[edges];
    h->since += c;
    h->engine += c;
    if (charged) {
        const vp_cell cell = {k->c0 + x, k->r0 + y, (uint8_t)(lg / 2), (uint8_t)(lg / 2), level, 0, 0};
        tm->charge(tm, &cell, c);
    }
}

static inline __attribute__((always_inline)) void
time_hand_over(vp_timer *tm, hand_over_list *h, const vp_cell *k, uint32_t x, uint32_t y, uint8_t lg,
               uint8_t level, const bool charged)
{
    const uint32_t f = (uint32_t)tm->fill_cycles[lg];
    if (charged) {
        const vp_cell cell = {k->c0 + x, k->r0 + y, (uint8_t)(lg / 2), (uint8_t)(lg / 2), level, 0, 0};
        tm->charge(tm, &cell, f);
    }
    h->gap[h->n] = h->since;
    h->fill[h->n++] = f;
    h->filled += f;
    h->since = 0;
}

static inline __attribute__((always_inline)) void
time_split8_body(vp_timer *tm, const vp_cell *k, const block8_verdicts *v, unsigned in4,
                 unsigned in2, uint64_t fine, const bool unit, const bool charged)
{
    const uint8_t l = k->level + 1;
    hand_over_list h;
    h.n = 0, h.since = 0, h.engine = 0, h.filled = 0;
    for (unsigned j = 0; j < 4; j++) {
        const uint32_t cx = 4 * (j & 1), cy = 4 * (j >> 1);
        time_step(tm, &h, k, cx, cy, 4, l, k->edges, unit, charged);
        if (v->out4 >> j & 1)
            continue;
        if (in4 >> j & 1) {
            time_hand_over(tm, &h, k, cx, cy, 4, l, charged);
            continue;
        }
        for (unsigned i = 0; i < 4; i++) {
            const uint32_t gx = cx / 2 + (i & 1), gy = cy / 2 + (i >> 1), g = 4 * gy + gx;
            time_step(tm, &h, k, 2 * gx, 2 * gy, 2, (uint8_t)(l + 1), v->loose4 >> 8 * j & 0xFF,
                      unit, charged);
            if (v->out2 >> g & 1)
                continue;
            if (in2 >> g & 1) {
                time_hand_over(tm, &h, k, 2 * gx, 2 * gy, 2, (uint8_t)(l + 1), charged);
                continue;
            }
            /* the grandchild's samples inside: bits 0, 1 of its rows */
            const unsigned edges = v->loose2[gy] >> 8 * gx & 0xFF;
            const uint64_t rows = fine >> (16 * gy + 2 * gx);
            const unsigned in = (unsigned)(rows & 3) | (unsigned)(rows >> 6 & 0xC);
            for (unsigned q = 0; q < 4; q++) {
                const uint32_t sx = 2 * gx + (q & 1), sy = 2 * gy + (q >> 1);
                time_step(tm, &h, k, sx, sy, 0, (uint8_t)(l + 2), edges, unit, charged);
                if (in >> q & 1)
                    time_hand_over(tm, &h, k, sx, sy, 0, (uint8_t)(l + 2), charged);
            }
        }
    }
    vp_timer_hand_overs(tm, h.gap, h.fill, h.n, h.since, h.engine, h.filled);
}

/* The unit-step case without a per-pixel map (`unit && !charged`, the
 * common one: a face with no more edges than the engine has edge units, and
 * no frame asked for): every step takes one cycle, so only where the
 * hand-overs fall among the steps matters, and that is read straight from
 * the verdict masks.  Each of the 84 steps the walk may make below the cell
 * has a fixed slot — child j at 21 (j & 1) of word j >> 1, its grandchild k
 * (in the walk's order) 1 + 5 k on, that one's four samples the next four —
 * and three masks over the slots: `s` the steps made (a child always; its
 * grandchildren if it splits; their samples if they split), `h` the steps
 * that hand a cell over, and `long4`, `long2` those of whole children and
 * grandchildren, whose fills may take more than a cycle.  A step's cycle
 * in the block is the number of steps made before it. */
typedef struct {
    uint64_t s[2], h[2], long4[2], long2[2];
    unsigned steps0;          /* the steps made in word 0 */
} unit_timeline;

/* Child j's slots; k its grandchildren g + 0, 1, 4, 5 (a child that does
 * not split has none in in2, split2 or the samples, a grandchild that does
 * not split no sample in nibs). */
static inline __attribute__((always_inline)) void
unit_child(unit_timeline *u, unsigned j, unsigned in4, unsigned split4, unsigned in2,
           unsigned split2, uint64_t nibs)
{
    static const unsigned step[4] = {0, 1, 4, 5};
    const unsigned w = j >> 1, b = 21 * (j & 1), g0 = 8 * (j >> 1) + 2 * (j & 1);
    const uint64_t s4 = split4 >> j & 1, b4 = in4 >> j & 1;
    uint64_t s = 1ull << b, h = b4 << b, l2 = 0;
    for (unsigned k = 0; k < 4; k++) {
        const unsigned g = g0 + step[k], at = b + 1 + 5 * k;
        const uint64_t b2 = in2 >> g & 1;
        s |= (s4 | 0x1Eull * (split2 >> g & 1)) << at;
        h |= (b2 | (nibs >> 4 * g & 0xF) << 1) << at;
        l2 |= b2 << at;
    }
    u->s[w] |= s, u->h[w] |= h, u->long4[w] |= b4 << b, u->long2[w] |= l2;
}

static inline __attribute__((always_inline)) void
unit_timeline_of(unit_timeline *u, unsigned in4, unsigned split4, unsigned in2, unsigned split2,
                 uint64_t fine, const int isa)
{
    /* the samples inside (bit 8 sy + sx) as a nibble per grandchild g = 4 gy
     * + gx, in the walk's order: its upper row's pair of bits, then its
     * lower row's — each 16-bit lane one row of grandchildren, its even row
     * and its odd row spread two bits to four */
    uint64_t even = fine & 0x00FF00FF00FF00FFull, odd = fine >> 8 & 0x00FF00FF00FF00FFull;
    even = (even | even << 4) & 0x0F0F0F0F0F0F0F0Full;
    even = (even | even << 2) & 0x3333333333333333ull;
    odd = (odd | odd << 4) & 0x0F0F0F0F0F0F0F0Full;
    odd = (odd | odd << 2) & 0x3333333333333333ull;
    const uint64_t nibs = even | odd << 2;
    *u = (unit_timeline){{0, 0}, {0, 0}, {0, 0}, {0, 0}, 0};
    unit_child(u, 0, in4, split4, in2, split2, nibs);
    unit_child(u, 1, in4, split4, in2, split2, nibs);
    unit_child(u, 2, in4, split4, in2, split2, nibs);
    unit_child(u, 3, in4, split4, in2, split2, nibs);
    u->steps0 = popcount_isa(u->s[0], isa);
}

/* The cycle in the block (0 = its first) of the step in slot p of word w. */
static inline __attribute__((always_inline)) unsigned
unit_cycle(const unit_timeline *u, unsigned w, unsigned p, const int isa)
{
    return (w ? u->steps0 : 0) + popcount_isa(u->s[w] & ((1ull << p) - 1), isa);
}

/* A hand-over's fill cycles by its slot's kind. */
static inline __attribute__((always_inline)) uint64_t
unit_fill(const unit_timeline *u, unsigned w, unsigned p, uint64_t f0, uint64_t f2, uint64_t f4)
{
    return u->long4[w] >> p & 1 ? f4 : u->long2[w] >> p & 1 ? f2 : f0;
}

/* Whether every fill of the slots `m` (f cycles each) ends by the next
 * hand-over's step: then the fill unit never makes a later cell wait. */
static inline __attribute__((always_inline)) bool
unit_fills_keep_up(const unit_timeline *u, const uint64_t m[2], uint64_t f, const int isa)
{
    if (f <= 1)
        return true;
    for (unsigned w = 0; w < 2; w++)
        for (uint64_t x = m[w]; x; x &= x - 1) {
            const unsigned p = (unsigned)__builtin_ctzll(x);
            const uint64_t later = u->h[w] & ~((2ull << p) - 1);   /* p < 42 */
            unsigned next;
            if (later)
                next = unit_cycle(u, w, (unsigned)__builtin_ctzll(later), isa);
            else if (w == 0 && u->h[1])
                next = unit_cycle(u, 1, (unsigned)__builtin_ctzll(u->h[1]), isa);
            else
                continue;   /* the last hand-over: the next block's entry test */
            if (next - unit_cycle(u, w, p, isa) < f)
                return false;
        }
    return true;
}

static inline __attribute__((always_inline)) void
time_split8_unit(vp_timer *tm, unsigned in4, unsigned split4, unsigned in2, unsigned split2,
                 uint64_t fine, const int isa)
{
    unit_timeline u;
    unit_timeline_of(&u, in4, split4, in2, split2, fine, isa);
    const unsigned steps = u.steps0 + popcount_isa(u.s[1], isa);
    const unsigned n = popcount_isa(u.h[0], isa) + popcount_isa(u.h[1], isa);
    if (!n) {
        tm->pending += steps;
        return;
    }
    const uint64_t f0 = tm->fill_cycles[0], f2 = tm->fill_cycles[2], f4 = tm->fill_cycles[4];
    const unsigned n4 = popcount_isa(u.long4[0], isa) + popcount_isa(u.long4[1], isa);
    const unsigned n2 = popcount_isa(u.long2[0], isa) + popcount_isa(u.long2[1], isa);
    const uint64_t filled = f0 * (n - n4 - n2) + f2 * n2 + f4 * n4;
    const unsigned q = tm->fill_queue;
    /* e: the engine's last cycle so far; the step of the block's cycle c
     * ends in e + c + 1 if nothing waits */
    const int64_t e = tm->now - 1 + (int64_t)tm->pending;
    const unsigned fw = u.h[0] ? 0 : 1, first = unit_cycle(&u, fw, (unsigned)__builtin_ctzll(u.h[fw]), isa);
    const unsigned lw = u.h[1] ? 1 : 0, lp = 63 - (unsigned)__builtin_clzll(u.h[lw]);
    const unsigned last = unit_cycle(&u, lw, lp, isa);
    /* Nothing waits in the block when the fill unit is free by the cycle
     * after the first hand-over and each fill ends by the next hand-over:
     * then each cell is taken in the cycle after its step, put = end.  With
     * a queue of two or more, the cell fill_queue back was taken at least a
     * cycle before (takes grow by a cycle or more), so there is room too. */
    if (q >= 2 && f0 == 1 && tm->fill_free <= e + first + 2 && unit_fills_keep_up(&u, u.long4, f4, isa) &&
        unit_fills_keep_up(&u, u.long2, f2, isa)) {
        /* the ring: the takes of the last fill_queue cells, newest last */
        unsigned slot = tm->take_slot + n;
        slot = (q & (q - 1)) == 0 ? slot & (q - 1) : slot % q;
        unsigned left = n < q ? n : q, s = slot;
        for (int w = 1; w >= 0 && left; w--)
            for (uint64_t x = u.h[w]; x && left; left--) {
                const unsigned p = 63 - (unsigned)__builtin_clzll(x);
                x &= ~(1ull << p);
                s = s ? s - 1 : q - 1;
                tm->take_ring[s] = e + (int64_t)unit_cycle(&u, (unsigned)w, p, isa) + 2;
            }
        tm->take_slot = slot;
        tm->now = e + (int64_t)last + 2;
        tm->fill_free = tm->now + (int64_t)unit_fill(&u, lw, lp, f0, f2, f4);
        tm->engine += tm->pending + last + 1;
        tm->pending = steps - (last + 1);
        tm->cells += n;
        tm->fill += filled;
        return;
    }
    /* else each hand-over through the fill queue's recurrence, its gap the
     * cycles since the previous one */
    vp_queue rec = vp_queue_of(tm, e);
    unsigned done = 0;
    for (unsigned w = 0; w < 2; w++)
        for (uint64_t x = u.h[w]; x; x &= x - 1) {
            const unsigned p = (unsigned)__builtin_ctzll(x), c = unit_cycle(&u, w, p, isa);
            vp_queue_take(&rec, tm->take_ring, q, c + 1 - done, unit_fill(&u, w, p, f0, f2, f4));
            done = c + 1;
        }
    vp_queue_end(tm, &rec, n, steps - done, steps, filled);
}

/* The other cases: steps of several cycles (more edges than edge units),
 * or each step charged to the per-pixel map. */
static void time_split8(vp_timer *tm, const vp_cell *k, const block8_verdicts *v, unsigned in4,
                        unsigned in2, uint64_t fine, bool unit)
{
    if (!tm->charge)
        time_split8_body(tm, k, v, in4, in2, fine, false, false);
    else if (unit)
        time_split8_body(tm, k, v, in4, in2, fine, true, true);
    else
        time_split8_body(tm, k, v, in4, in2, fine, false, true);
}

/* Then the counts, one masked fill of the block's samples, each with the
 * level that decided it, and for a timer the steps in the walk's order. */
static inline __attribute__((always_inline)) void
draw_split8(alb_vp *vp, vp_walk *w, const vp_face_setup *fs, const vp_cell *k, vp_timer *tm,
            const bool timed, const int isa)
{
    /* the grandchildren in the quadrants of children m (bit j: child j;
     * child 0 has grandchildren 0, 1, 4, 5) */
    static const uint16_t quadrants[16] = {
        0x0000, 0x0033, 0x00CC, 0x00FF, 0x3300, 0x3333, 0x33CC, 0x33FF,
        0xCC00, 0xCC33, 0xCCCC, 0xCCFF, 0xFF00, 0xFF33, 0xFFCC, 0xFFFF};
    block8_verdicts v = {0, 0xF, 0, 0xFFFF, 0, 0, {0, 0, 0, 0}};
    const int64_t c0 = 2 * (int64_t)k->c0, r0 = 2 * (int64_t)k->r0;
    /* every step one cycle (the step table is monotone): no edge counts */
    const bool unit = timed && tm->step_cycles[w->n] == 1;
    /* the block's rows of the depth and tag store are asked for now, so the
     * edges' verdicts run while they come: small faces scattered over the
     * screen find them outside the caches, and the fill waited for them
     * (docs/performance.md); a hint only, no value depends on it.  Not in
     * the timed walk: there it adds 2.5% to a run's instructions (built-in
     * scene, a1024) and no gain could be measured on the loaded machine */
    if (!timed) {
        const size_t at = (size_t)k->r0 * vp->sw + k->c0, sw = vp->sw;
        const uint32_t *d = vp->s_depth + at, *t = vp->s_tag + at;
#pragma GCC unroll 8
        for (unsigned y = 0; y < 8; y++, d += sw, t += sw) {
            __builtin_prefetch(d, 1);
            __builtin_prefetch(t, 1);
        }
    }
#if VP_AVX2
    if (isa == ISA_AVX2 && w->narrow) {
        if (!w->lanes_ready) {   /* the face's first 8 x 8 cell that splits */
            for (unsigned i = 0; i < w->n; i++)
                narrow_lanes(&w->e[i], &w->lanes[i]);
            w->lanes_ready = true;
        }
        if (timed && !unit) {
            for (uint64_t act = k->active; act; act &= act - 1) {
                const unsigned i = (unsigned)__builtin_ctzll(act);
                edge_block8_narrow(&w->e[i], &w->lanes[i], c0, r0, &v, true);
            }
        } else {
            block8_narrow_all(w, k->active, c0, r0, &v);
        }
    } else
#endif
    {
        for (uint64_t act = k->active; act; act &= act - 1)
            edge_block8(&w->e[__builtin_ctzll(act)], c0, r0, &v);
    }
    const uint8_t l = k->level + 1;
    const unsigned in4 = ~v.out4 & v.held4 & 0xF, split4 = ~v.out4 & ~v.held4 & 0xF;
    const unsigned seen2 = quadrants[split4];   /* the grandchildren visited: of split children */
    const unsigned in2 = seen2 & ~v.out2 & v.held2, split2 = seen2 & ~v.out2 & ~v.held2;
    const uint64_t tested = samples_of_grandchildren(split2);
    const uint64_t fine = tested & ~v.outside, mid = samples_of_grandchildren(in2);
    const uint64_t fill = samples_of_children(in4) | mid | fine;
    const unsigned nsplit2 = popcount_isa(split2, isa);
    vp->st.cells[l] += 4;
    vp->st.cells[l + 1] += 4 * vp_bits4(split4);
    vp->st.cells[l + 2] += 4 * nsplit2;
    vp->st.samples_tested += 4 * nsplit2;
    vp->st.cells_outside += vp_bits4(v.out4) + popcount_isa(seen2 & v.out2, isa);
    vp->st.cells_inside += vp_bits4(in4) + popcount_isa(in2, isa);
    vp->st.cells_split += vp_bits4(split4) + nsplit2;
    if (fill)
        vp_fill_block8(vp, fs, k->c0, k->r0, fill, mid, fine, l);
    if (timed && unit && !tm->charge)
        time_split8_unit(tm, in4, split4, in2, split2, fine, isa);
    else if (timed)
        time_split8(tm, k, &v, in4, in2, fine, unit);
}

/* ---- any other cell that splits ---- */

/* The walk below cell c, which splits, in the instantiation of (timed, isa). */
static void split_base(alb_vp *vp, vp_walk *w, const vp_face_setup *fs, const vp_cell *k,
                       vp_timer *tm);
static void split_base_timed(alb_vp *vp, vp_walk *w, const vp_face_setup *fs,
                             const vp_cell *k, vp_timer *tm);
#if VP_AVX2
ISA_AVX2_TARGET static void split_avx2(alb_vp *vp, vp_walk *w, const vp_face_setup *fs,
                                       const vp_cell *k, vp_timer *tm);
ISA_AVX2_TARGET static void split_avx2_timed(alb_vp *vp, vp_walk *w, const vp_face_setup *fs,
                                             const vp_cell *k, vp_timer *tm);
#endif
static inline __attribute__((always_inline)) void
split_below(alb_vp *vp, vp_walk *w, const vp_face_setup *fs, const vp_cell *c, vp_timer *tm,
            const bool timed, const int isa)
{
#if VP_AVX2
    if (isa == ISA_AVX2) {
        if (timed)
            split_avx2_timed(vp, w, fs, c, tm);
        else
            split_avx2(vp, w, fs, c, tm);
        return;
    }
#else
    (void)isa;
#endif
    if (timed)
        split_base_timed(vp, w, fs, c, tm);
    else
        split_base(vp, w, fs, c, tm);
}

#if VP_AVX2
/* children_verdicts with the four children in four 64-bit lanes */
ISA_AVX2_TARGET static inline unsigned
children_verdicts_avx2(const vp_walk *w, const vp_cell *k, int64_t cw, int64_t ch, int64_t ox,
                       int64_t oy, uint64_t held[4])
{
    const int64_t c0 = 2 * (int64_t)k->c0, r0 = 2 * (int64_t)k->r0;
    const __m256i zero = _mm256_setzero_si256();
    __m256i any = zero, hv = zero;
    for (uint64_t act = k->active; act; act &= act - 1) {
        const unsigned i = (unsigned)__builtin_ctzll(act);
        const vp_edge_fn *f = &w->e[i];
        const int64_t h = f->a * c0 + f->b * r0 + f->c, ax = f->a * cw, by = f->b * ch;
        const int64_t up = (ax > 0 ? ax : 0) + (by > 0 ? by : 0);
        const int64_t down = (ax < 0 ? ax : 0) + (by < 0 ? by : 0);
        const int64_t hx = ox ? ax : 0, hy = oy ? by : 0;   /* ox is cw or 0, oy ch or 0 */
        const __m256i t = _mm256_add_epi64(_mm256_set1_epi64x(h), _mm256_setr_epi64x(0, hx, hy, hx + hy));
        /* a lane's maximum is negative in some edge: the sign bit of their OR */
        any = _mm256_or_si256(any, _mm256_add_epi64(t, _mm256_set1_epi64x(up)));
        const __m256i loose = _mm256_cmpgt_epi64(zero, _mm256_add_epi64(t, _mm256_set1_epi64x(down)));
        hv = _mm256_or_si256(hv, _mm256_andnot_si256(loose, _mm256_set1_epi64x((int64_t)1 << i)));
    }
    _mm256_storeu_si256((__m256i *)(void *)held, hv);
    return (unsigned)_mm256_movemask_pd(_mm256_castsi256_pd(any));
}
#endif

#if VP_AVX2
/* The same for a narrow face's cell with at least EDGES_AT_ONCE active
 * edges, four edges a step in 64-bit lanes (vp_walk.ea, eb, ec; the
 * children one after the other): every edge of the face, since an edge that
 * holds the parent holds its children and rejects none, and a spare lane
 * (a = b = c = 0) neither.  The face is narrow, so a and b are exact in the
 * products' 32 bits.  Fewer active edges are fewer steps edge by edge
 * (callgrind, random 10 000 flat faces at a1024: from 4 on, 2.5% fewer
 * instructions in all; from 2, 3 or 6 on, 0.6% to 1.7%). */
#define EDGES_AT_ONCE 4
ISA_AVX2_TARGET static inline unsigned
children_verdicts_edges_avx2(const vp_walk *w, const vp_cell *k, unsigned wl1, unsigned hl1, bool ox,
                             bool oy, uint64_t held[4])
{
    const __m256i c0 = _mm256_set1_epi64x(2 * (int64_t)k->c0), r0 = _mm256_set1_epi64x(2 * (int64_t)k->r0);
    const __m128i sx = _mm_cvtsi32_si128((int)wl1), sy = _mm_cvtsi32_si128((int)hl1);
    const __m256i zero = _mm256_setzero_si256();
    __m256i any[4] = {zero, zero, zero, zero};
    for (unsigned g = 0; g < w->n; g += 4) {
        const __m256i a = _mm256_loadu_si256((const __m256i *)(const void *)(w->ea + g));
        const __m256i b = _mm256_loadu_si256((const __m256i *)(const void *)(w->eb + g));
        const __m256i h = _mm256_add_epi64(_mm256_add_epi64(_mm256_mul_epi32(a, c0), _mm256_mul_epi32(b, r0)),
                                           _mm256_loadu_si256((const __m256i *)(const void *)(w->ec + g)));
        /* a child's sides: a (2 << wl), b (2 << hl); its extremes' offsets */
        const __m256i ax = _mm256_sll_epi64(a, sx), by = _mm256_sll_epi64(b, sy);
        const __m256i up = _mm256_add_epi64(_mm256_andnot_si256(_mm256_cmpgt_epi64(zero, ax), ax),
                                            _mm256_andnot_si256(_mm256_cmpgt_epi64(zero, by), by));
        const __m256i down = _mm256_sub_epi64(_mm256_add_epi64(ax, by), up);
        __m256i t[4];
        t[0] = h;
        t[1] = ox ? _mm256_add_epi64(h, ax) : h;
        t[2] = oy ? _mm256_add_epi64(h, by) : h;
        t[3] = oy ? _mm256_add_epi64(t[1], by) : t[1];
#pragma GCC unroll 4
        for (unsigned j = 0; j < 4; j++) {
            any[j] = _mm256_or_si256(any[j], _mm256_add_epi64(t[j], up));
            const unsigned loose =
                (unsigned)_mm256_movemask_pd(_mm256_castsi256_pd(_mm256_add_epi64(t[j], down)));
            held[j] |= (uint64_t)(~loose & 0xF) << g;
        }
    }
    unsigned out = 0;
#pragma GCC unroll 4
    for (unsigned j = 0; j < 4; j++)
        out |= (unsigned)(_mm256_movemask_pd(_mm256_castsi256_pd(any[j])) != 0) << j;
    return out;
}
#endif

/* Edge by edge, the children's verdicts: out (bit j: some edge rejects
 * child j) and held[j] (the edges holding child j wholly).  An edge's value
 * at a child's top-left corner is the parent's corner value plus a child's
 * side or not (`ox`, `oy`: 0 where the side is not split), and its extremes
 * over the child add the positive or the negative parts of the child's
 * sides `cw`, `ch` (h is linear) — the walk's classify, four cells at a
 * time: scalar in the baseline, the four children in four 64-bit lanes with
 * AVX2. */
static inline __attribute__((always_inline)) unsigned
children_verdicts(const vp_walk *w, const vp_cell *k, int64_t cw, int64_t ch, int64_t ox, int64_t oy,
                  uint64_t held[4], const int isa)
{
    const int64_t c0 = 2 * (int64_t)k->c0, r0 = 2 * (int64_t)k->r0;
    unsigned out = 0;
#if VP_AVX2
    if (isa == ISA_AVX2 && w->narrow && popcount_isa(k->active, isa) >= EDGES_AT_ONCE)
        return children_verdicts_edges_avx2(w, k, (unsigned)__builtin_ctzll((uint64_t)cw),
                                            (unsigned)__builtin_ctzll((uint64_t)ch), ox != 0, oy != 0,
                                            held);
    if (isa == ISA_AVX2)
        return children_verdicts_avx2(w, k, cw, ch, ox, oy, held);
#endif
    (void)isa;
    for (uint64_t act = k->active; act; act &= act - 1) {
        const unsigned i = (unsigned)__builtin_ctzll(act);
        const vp_edge_fn *f = &w->e[i];
        const int64_t h = f->a * c0 + f->b * r0 + f->c, ax = f->a * cw, by = f->b * ch;
        const int64_t up = (ax > 0 ? ax : 0) + (by > 0 ? by : 0);
        const int64_t down = (ax < 0 ? ax : 0) + (by < 0 ? by : 0);
        const int64_t hx = f->a * ox, hy = f->b * oy;
        const int64_t t[4] = {h, h + hx, h + hy, h + hx + hy};
        for (unsigned j = 0; j < 4; j++) {
            out |= (unsigned)(t[j] + up < 0) << j;
            held[j] |= (uint64_t)(t[j] + down >= 0) << i;
        }
    }
    return out;
}

/* The cells below cell k, which splits: its children classified together,
 * then each in turn a step — counted, rejected, filled, or split further. */
static inline __attribute__((always_inline)) void
draw_split(alb_vp *vp, vp_walk *w, const vp_face_setup *fs, const vp_cell *k, vp_timer *tm,
           const bool timed, const int isa)
{
    const uint8_t wl = k->wl ? k->wl - 1 : 0, hl = k->hl ? k->hl - 1 : 0, l = k->level + 1;
    const uint32_t dx = k->wl ? 1u << wl : 0, dy = k->hl ? 1u << hl : 0;
    if (k->wl == 3 && k->hl == 3) {
        draw_split8(vp, w, fs, k, tm, timed, isa);
        return;
    }
    const unsigned present = children_present(dx, dy);
    if (!(wl | hl)) {
        draw_samples(vp, w, fs, k, present, tm, timed);
        return;
    }
    const int64_t cw = (int64_t)2 << wl, ch = (int64_t)2 << hl;    /* a child's sides */
    uint64_t held[4] = {0, 0, 0, 0};
    const unsigned out = children_verdicts(w, k, cw, ch, dx ? cw : 0, dy ? ch : 0, held, isa);
    vp_cell c = {0, 0, wl, hl, l, 0, 0};
    /* without a timer the steps need no order: the children counted at
     * once, those rejected not visited */
    const unsigned visit = timed ? present : present & ~out;
    if (!timed) {
        vp->st.cells[l] += vp_bits4(present);
        vp->st.cells_outside += vp_bits4(present & out);
    }
    for (unsigned m = visit; m; m &= m - 1) {
        const unsigned j = (unsigned)__builtin_ctz(m);
        c.c0 = k->c0 + (j & 1 ? dx : 0), c.r0 = k->r0 + (j & 2 ? dy : 0);
        if (timed) {
            vp->st.cells[l]++;
            timer_step(tm, &c, k->edges, timed);
            if (out >> j & 1) {
                vp->st.cells_outside++;
                continue;
            }
        }
        c.active = k->active & ~held[j];
        if (!c.active) {
            vp->st.cells_inside++;
            draw_fill(vp, fs, &c);
            timer_hand_over(tm, &c, timed);
            continue;
        }
        vp->st.cells_split++;
        if (timed)
            c.edges = (uint8_t)popcount_isa(c.active, isa);
        /* an 8 x 8 child here, not through a call: they are the most
         * numerous cells that split */
        if (wl == 3 && hl == 3)
            draw_split8(vp, w, fs, &c, tm, timed, isa);
        else
            split_below(vp, w, fs, &c, tm, timed, isa);
    }
}

static void split_base(alb_vp *vp, vp_walk *w, const vp_face_setup *fs, const vp_cell *k,
                       vp_timer *tm)
{
    draw_split(vp, w, fs, k, tm, false, ISA_BASE);
}

static void split_base_timed(alb_vp *vp, vp_walk *w, const vp_face_setup *fs,
                             const vp_cell *k, vp_timer *tm)
{
    draw_split(vp, w, fs, k, tm, true, ISA_BASE);
}

#if VP_AVX2
ISA_AVX2_TARGET static void split_avx2(alb_vp *vp, vp_walk *w, const vp_face_setup *fs,
                                       const vp_cell *k, vp_timer *tm)
{
    draw_split(vp, w, fs, k, tm, false, ISA_AVX2);
}

ISA_AVX2_TARGET static void split_avx2_timed(alb_vp *vp, vp_walk *w, const vp_face_setup *fs,
                                             const vp_cell *k, vp_timer *tm)
{
    draw_split(vp, w, fs, k, tm, true, ISA_AVX2);
}
#endif

/* The walk below cell k, which splits, on the host's instruction set. */
static inline __attribute__((always_inline)) void
draw_below(alb_vp *vp, vp_walk *w, const vp_face_setup *fs, const vp_cell *k, vp_timer *tm,
           const bool timed)
{
    if (vp->walk_avx2)
        split_below(vp, w, fs, k, tm, timed, VP_AVX2 ? ISA_AVX2 : ISA_BASE);
    else
        split_below(vp, w, fs, k, tm, timed, ISA_BASE);
}

/* The walk of a face from the top cell (never a single sample: a screen is
 * at least 2 x 2). */
static inline __attribute__((always_inline)) void
draw_walk(alb_vp *vp, vp_walk *w, const vp_face_setup *fs, vp_timer *tm, const bool timed)
{
    vp_cell k = w->stack[0];
    vp->st.cells[k.level]++;
    timer_step(tm, &k, k.edges, timed);
    int cls = classify(w->e, &k);
    if (cls < 0) {
        vp->st.cells_outside++;
    } else if (cls > 0) {
        vp->st.cells_inside++;
        draw_fill(vp, fs, &k);
        timer_hand_over(tm, &k, timed);
    } else {
        vp->st.cells_split++;
        draw_below(vp, w, fs, &k, tm, timed);
    }
}

void vp_draw_face(alb_vp *vp, const vp_loaded_face *f)
{
    vp_walk w;
    vp_walk_begin(&w, vp, f);
    draw_walk(vp, &w, &f->fs, NULL, false);
}

void vp_draw_face_timed(alb_vp *vp, const vp_loaded_face *f, vp_timer *tm)
{
    vp_walk w;
    vp_walk_begin(&w, vp, f);
    draw_walk(vp, &w, &f->fs, tm, true);
}

/* ---- the walk split at a level of tiles (the threads, parallel.c) ---- */

/* The cells below cell k, which splits, down to level tl: the children's
 * verdicts as in draw_split, each child counted, and each child found
 * inside or splitting at level tl handed to `job`. */
static inline __attribute__((always_inline)) void
tiles_below(alb_vp *vp, const vp_walk *w, const vp_cell *k, unsigned tl, vp_tile_job_fn job, void *ctx,
            const int isa);
static void tiles_below_base(alb_vp *vp, const vp_walk *w, const vp_cell *k, unsigned tl,
                             vp_tile_job_fn job, void *ctx)
{
    tiles_below(vp, w, k, tl, job, ctx, ISA_BASE);
}
#if VP_AVX2
ISA_AVX2_TARGET static void tiles_below_avx2(alb_vp *vp, const vp_walk *w, const vp_cell *k,
                                             unsigned tl, vp_tile_job_fn job, void *ctx)
{
    tiles_below(vp, w, k, tl, job, ctx, ISA_AVX2);
}
#endif

static inline __attribute__((always_inline)) void
tiles_below(alb_vp *vp, const vp_walk *w, const vp_cell *k, unsigned tl, vp_tile_job_fn job, void *ctx,
            const int isa)
{
    const uint8_t wl = k->wl ? k->wl - 1 : 0, hl = k->hl ? k->hl - 1 : 0, l = k->level + 1;
    const uint32_t dx = k->wl ? 1u << wl : 0, dy = k->hl ? 1u << hl : 0;
    const int64_t cw = (int64_t)2 << wl, ch = (int64_t)2 << hl;
    uint64_t held[4] = {0, 0, 0, 0};
    const unsigned present = children_present(dx, dy);
    const unsigned out = children_verdicts(w, k, cw, ch, dx ? cw : 0, dy ? ch : 0, held, isa);
    for (unsigned j = 0; j < 4; j++) {
        if (!(present >> j & 1))
            continue;
        vp->st.cells[l]++;
        if (out >> j & 1) {
            vp->st.cells_outside++;
            continue;
        }
        vp_cell c = {k->c0 + (j & 1 ? dx : 0), k->r0 + (j & 2 ? dy : 0), wl, hl, l, 0,
                     k->active & ~held[j]};
        c.edges = (uint8_t)vp_popcount(c.active);
        if (!c.active) {
            vp->st.cells_inside++;
            job(ctx, &c, true);
            continue;
        }
        vp->st.cells_split++;
        if (l == tl)
            job(ctx, &c, false);
#if VP_AVX2
        else if (isa == ISA_AVX2)
            tiles_below_avx2(vp, w, &c, tl, job, ctx);
#endif
        else
            tiles_below_base(vp, w, &c, tl, job, ctx);
    }
}

void vp_walk_to_tiles(alb_vp *vp, const vp_loaded_face *f, unsigned tl, vp_tile_job_fn job, void *ctx)
{
    vp_walk w;
    vp_walk_begin(&w, vp, f);
    vp_cell k = w.stack[0];
    vp->st.cells[k.level]++;
    const int cls = classify(f->e, &k);
    if (cls < 0) {
        vp->st.cells_outside++;
    } else if (cls > 0) {
        vp->st.cells_inside++;
        job(ctx, &k, true);
    } else {
        vp->st.cells_split++;
        if (k.level == tl)
            job(ctx, &k, false);
#if VP_AVX2
        else if (vp->walk_avx2)
            tiles_below_avx2(vp, &w, &k, tl, job, ctx);
#endif
        else
            tiles_below_base(vp, &w, &k, tl, job, ctx);
    }
}

void vp_draw_below(alb_vp *vp, const vp_loaded_face *f, const vp_cell *k)
{
    vp_walk w;
    vp_walk_begin(&w, vp, f);
    draw_below(vp, &w, &f->fs, k, NULL, false);
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
    out->narrow = true;
    for (unsigned i = 0; i < f->n_edges; i++) {
        vp_edge_setup(vp, &f->edge[i], &out->e[i]);
        /* the walk's 32-bit lanes (vp_walk.narrow) */
        int64_t a = out->e[i].a, b = out->e[i].b;
        out->narrow &= (a < 0 ? -a : a) + (b < 0 ? -b : b) < (int64_t)1 << 27;
    }
    out->n = f->n_edges;
    fs->units = vp_face_units(fs);
    units_depth_range(units_depth_shift(vp, fs->depth.exp), ((int64_t)1 << vp->prof.depth_bits) - 1,
                      &fs->depth_lo, &fs->depth_hi);
    vp_flat_colour(vp, fs, fs->flat);
    return ALB_OK;
}

alb_err alb_vp_face(alb_vp *vp, const alb_ws_face *f, alb_diag *d)
{
    if (vp->batch) {
        /* threaded: load now (the stream's order of errors), draw in batches */
        alb_err err = vp_load_face(vp, f, &vp->batch[vp->nbatch], d);
        if (!err)
            err = vp_begin_face(vp, &vp->batch[vp->nbatch], d);
        if (err)
            return err;
        if (++vp->nbatch == VP_BATCH)
            vp_batch_full(vp);
        return ALB_OK;
    }
    vp_loaded_face lf;
    alb_err err = vp_load_face(vp, f, &lf, d);
    if (!err)
        err = vp_begin_face(vp, &lf, d);
    if (err)
        return err;
    vp_draw_face(vp, &lf);
    return ALB_OK;
}

/* ---- output stage ---- */

void alb_vp_frame_end(alb_vp *vp, alb_frame *out)
{
    vp_flush_batch(vp);
    out->number = vp->frame.number;
    out->near = vp->cfg.near;
    vp_store_resolve(vp, out);
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
