/* test_cellmeans.c — the VP's edge units need no multiplier (docs/vp.md §2):
 * an edge's value at a cell's middle is the mean of its values at the cell's
 * borders, so the hardware reaches every cell of the subdivision from the
 * screen's four corners with additions and one-bit shifts.  The model
 * evaluates h = aC + bR + c with products.  Here a second engine, written
 * the hardware's way (corner values carried down the stack, children's by
 * means, never a product below the screen's corners), walks random faces
 * beside the model's vp_walk_next; every step must agree — the cell, its
 * verdict and the edges still active — and no mean may round. */
#include "t.h"

#include "albatros/profile.h"
#include "../vp/vp_internal.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_EDGES 12

static uint64_t rng_state = 0x9e3779b97f4a7c15ull;

static uint64_t rng(void)
{
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 7;
    rng_state ^= rng_state << 17;
    return rng_state;
}

typedef struct {
    vp_cell k;
    int64_t h[MAX_EDGES][4];   /* each edge at the corners: tl, tr, bl, br */
} hw_cell;

typedef struct {
    hw_cell stack[3 * ALB_VP_MAX_LEVELS + 4];
    unsigned top;
    unsigned rounded;          /* means whose sum was odd: must stay 0 */
    int maxbits;               /* widest |h| met */
} hw_walk;

static int64_t mean(hw_walk *w, int64_t x, int64_t y)
{
    w->rounded += (unsigned)((x + y) & 1);
    return (x + y) >> 1;       /* arithmetic shift */
}

static void note(hw_walk *w, int64_t h)
{
    uint64_t m = h < 0 ? (uint64_t)-h : (uint64_t)h;
    int bits = m ? 64 - __builtin_clzll(m) : 0;
    if (bits > w->maxbits)
        w->maxbits = bits;
}

/* One step of the multiplier-free engine; false when the face is done. */
static bool hw_next(hw_walk *w, unsigned n, vp_step *out)
{
    if (!w->top)
        return false;
    hw_cell cell = w->stack[--w->top];
    vp_cell *k = &cell.k;
    /* the edges the step evaluates: those active when it starts */
    const unsigned evaluated = (unsigned)__builtin_popcountll(k->active);
    for (unsigned i = 0; i < n; i++)
        for (int j = 0; j < 4; j++)
            note(w, cell.h[i][j]);
    if (k->wl == 0 && k->hl == 0) {
        bool in = true;
        for (unsigned i = 0; i < n; i++)
            if (k->active >> i & 1) {
                int64_t top = mean(w, cell.h[i][0], cell.h[i][1]);
                int64_t bottom = mean(w, cell.h[i][2], cell.h[i][3]);
                in &= mean(w, top, bottom) >= 0;   /* the sample's centre */
            }
        *out = (vp_step){in ? VP_STEP_SAMPLE_IN : VP_STEP_SAMPLE_OUT, *k, evaluated};
        return true;
    }
    for (unsigned i = 0; i < n; i++) {
        if (!(k->active >> i & 1))
            continue;
        int64_t lo = cell.h[i][0], hi = cell.h[i][0];
        for (int j = 1; j < 4; j++) {
            lo = cell.h[i][j] < lo ? cell.h[i][j] : lo;
            hi = cell.h[i][j] > hi ? cell.h[i][j] : hi;
        }
        if (hi < 0) {
            *out = (vp_step){VP_STEP_OUT, *k, evaluated};
            return true;
        }
        if (lo >= 0)
            k->active &= ~(1ull << i);
    }
    if (!k->active) {
        *out = (vp_step){VP_STEP_FILL, *k, evaluated};
        return true;
    }
    *out = (vp_step){VP_STEP_SPLIT, *k, evaluated};
    /* children top-left, top-right, bottom-left, bottom-right; a side one
     * sample long is not split.  Corner grid of the parent: 3 x 3 points. */
    unsigned nx = k->wl ? 2 : 1, ny = k->hl ? 2 : 1;
    uint8_t wl = k->wl ? k->wl - 1 : 0, hl = k->hl ? k->hl - 1 : 0;
    int64_t g[MAX_EDGES][3][3];
    for (unsigned i = 0; i < n; i++) {
        int64_t *h = cell.h[i];
        g[i][0][0] = h[0], g[i][0][2] = h[1], g[i][2][0] = h[2], g[i][2][2] = h[3];
        g[i][0][1] = nx == 2 ? mean(w, h[0], h[1]) : h[1];
        g[i][2][1] = nx == 2 ? mean(w, h[2], h[3]) : h[3];
        g[i][1][0] = ny == 2 ? mean(w, h[0], h[2]) : h[2];
        g[i][1][2] = ny == 2 ? mean(w, h[1], h[3]) : h[3];
        g[i][1][1] = nx == 2 && ny == 2 ? mean(w, g[i][0][1], g[i][2][1])
                     : nx == 2          ? g[i][2][1]
                                        : g[i][1][2];
    }
    hw_cell kids[4];
    unsigned nk = 0;
    for (unsigned dy = 0; dy < ny; dy++)
        for (unsigned dx = 0; dx < nx; dx++) {
            hw_cell *c = &kids[nk++];
            c->k = (vp_cell){.c0 = k->c0 + (dx << wl), .r0 = k->r0 + (dy << hl), .wl = wl,
                             .hl = hl, .level = (uint8_t)(k->level + 1), .active = k->active};
            /* a child's corners in the parent's grid: a side not split
             * spans the whole grid (index 0 to 2 via the far corner) */
            unsigned x0 = nx == 2 ? dx : 0, x1 = nx == 2 ? dx + 1 : 2;
            unsigned y0 = ny == 2 ? dy : 0, y1 = ny == 2 ? dy + 1 : 2;
            for (unsigned i = 0; i < n; i++) {
                c->h[i][0] = g[i][y0][x0], c->h[i][1] = g[i][y0][x1];
                c->h[i][2] = g[i][y1][x0], c->h[i][3] = g[i][y1][x1];
            }
        }
    while (nk)
        w->stack[w->top++] = kids[--nk];
    return true;
}

static alb_vp *make_vp(const char *name, const char *const *sets)
{
    alb_profile p;
    if (alb_profile_lookup(name, &p))
        return NULL;
    char err[300];
    for (; sets && *sets; sets++)
        if (alb_profile_set(&p, *sets, err, sizeof err))
            return NULL;
    alb_vp *vp = NULL;
    alb_diag d;
    alb_diag_init(&d, NULL);
    if (alb_vp_create(&vp, &p, &d))
        return NULL;
    vp->cfg.edge_frac_bits = p.edge_frac_bits;
    return vp;
}

/* Random faces of 1..MAX_EDGES edges in the VP format — both orientations,
 * both R, intercepts over the whole 3.F range — walked by both engines. */
static void check_profile(const char *name, const char *const *sets, unsigned faces)
{
    alb_vp *vp = make_vp(name, sets);
    CHECK_MSG(vp != NULL, "profile %s", name);
    if (!vp)
        return;
    uint32_t qmax = (8u << vp->cfg.edge_frac_bits) - 1;
    static hw_walk hw;
    memset(&hw, 0, sizeof hw);
    unsigned long steps = 0, verdicts[5] = {0};
    unsigned bad = 0;
    for (unsigned t = 0; t < faces && !bad; t++) {
        vp_loaded_face f;
        memset(&f, 0, sizeof f);
        f.n = 1 + (unsigned)(rng() % MAX_EDGES);
        hw.top = 0;
        hw_cell *root = &hw.stack[hw.top++];
        root->k = (vp_cell){.wl = (uint8_t)vp->lw, .hl = (uint8_t)vp->lh, .active = (1ull << f.n) - 1};
        /* near the screen's middle most of the time, so faces are neither
         * all outside nor all inside */
        uint32_t span = (rng() & 3) ? (2u << vp->cfg.edge_frac_bits) : qmax + 1;
        uint32_t base = (rng() & 3) ? (3u << vp->cfg.edge_frac_bits) : 0;
        int64_t C1 = 2 * (int64_t)vp->sw, R1 = 2 * (int64_t)vp->sh;
        for (unsigned i = 0; i < f.n; i++) {
            alb_ws_edge e = {.u = (uint8_t)(rng() & 1), .r = (uint8_t)(rng() & 1),
                         .x1 = base + (uint32_t)(rng() % span), .x2 = base + (uint32_t)(rng() % span)};
            vp_edge_setup(vp, &e, &f.e[i]);
            /* the edge unit loads the screen's corners; the rest is means */
            const vp_edge_fn *fn = &f.e[i];
            root->h[i][0] = fn->c;
            root->h[i][1] = fn->a * C1 + fn->c;
            root->h[i][2] = fn->b * R1 + fn->c;
            root->h[i][3] = fn->a * C1 + fn->b * R1 + fn->c;
        }
        vp_walk w;
        vp_walk_begin(&w, vp, &f);
        vp_step a, b;
        for (;;) {
            bool more_vp = vp_walk_next(vp, &w, &a), more_hw = hw_next(&hw, f.n, &b);
            if (more_vp != more_hw) {
                CHECK_MSG(0, "%s face %u: the model %s after %lu steps, the hardware walk %s",
                          name, t, more_vp ? "goes on" : "stops", steps,
                          more_hw ? "goes on" : "stops");
                bad++;
                break;
            }
            if (!more_vp)
                break;
            steps++;
            verdicts[a.kind]++;
            bool same = a.kind == b.kind && a.cell.c0 == b.cell.c0 && a.cell.r0 == b.cell.r0 &&
                        a.cell.wl == b.cell.wl && a.cell.hl == b.cell.hl &&
                        a.cell.level == b.cell.level && a.edges == b.edges &&
                        (a.kind == VP_STEP_OUT || a.cell.active == b.cell.active);
            if (!same) {
                CHECK_MSG(0, "%s face %u: cell (%u, %u) level %u: the model says %d (active %llx,"
                          " %u evaluated), the hardware walk %d at (%u, %u) level %u (active "
                          "%llx, %u evaluated)",
                          name, t, a.cell.c0, a.cell.r0, a.cell.level, a.kind,
                          (unsigned long long)a.cell.active, a.edges, b.kind, b.cell.c0,
                          b.cell.r0, b.cell.level, (unsigned long long)b.cell.active, b.edges);
                bad++;
                break;
            }
        }
    }
    CHECK_EQ(bad, 0);
    CHECK_EQ(hw.rounded, 0);
    /* every verdict occurs, so the comparison is not vacuous */
    for (int v = 0; v < 5; v++)
        CHECK_MSG(verdicts[v] > 0, "%s: verdict %d never met", name, v);
    /* the edge registers: |h| < 2^(F + 6 + max(lw, lh)) (docs/vp.md §2) */
    int bound = (int)vp->cfg.edge_frac_bits + 6 + (int)(vp->lw > vp->lh ? vp->lw : vp->lh);
    CHECK_MSG(hw.maxbits <= bound, "%s: |h| needs %d bits, more than %d", name, hw.maxbits,
              bound);
    printf("# %s: %lu steps (out %lu, split %lu, fill %lu, sample in %lu, out %lu), |h| < 2^%d\n",
           name, steps, verdicts[0], verdicts[1], verdicts[2], verdicts[3], verdicts[4],
           hw.maxbits);
    alb_vp_destroy(vp);
}

TEST(subdivision_by_cell_means_equals_the_model)
{
    static const char *const rect[] = {"width=512", "height=128", NULL};
    static const char *const wide[] = {"width=64", "height=256", NULL};
    static const char *const fine[] = {"edge_frac_bits=16", NULL};
    check_profile("t32", NULL, 30000);
    check_profile("a256", rect, 3000);
    check_profile("a256", wide, 3000);
    check_profile("a1024", fine, 600);
}
