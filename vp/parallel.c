/* parallel.c — the functional VP on several threads, bit-identical to one.
 *
 * The screen is cut into tiles, the cells of one level of the subdivision
 * quadtree, and each tile belongs to one thread at a time.  Faces are loaded
 * in stream order into a batch; then, on the caller's thread, each face's
 * walk is made down to the level of the tiles (vp_walk_to_tiles), and every
 * tile the face reaches — a cell found inside, or a tile that splits — is
 * put on that tile's list, in stream order.  The threads then take the
 * tiles, and each walks its list: fills, and the walks below the tiles
 * (vp_draw_below).  A sample lies in one tile only, so it sees the same
 * faces in the same order as on one thread: the same depth tests, the same
 * winner, the same colour and decision level.  Every cell is counted once —
 * above the tiles by the caller, below by the tile's thread, each into
 * statistics of its own — so the sums are the single-threaded counts too
 * (tests/test_timing.c checks all of it). */
#define _GNU_SOURCE   /* sched_getaffinity: the cores this process may run on */
#include "vp_internal.h"

#include <pthread.h>
#include <sched.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

unsigned alb_vp_cores(void)
{
    /* the cores taskset, numactl or a batch system left us, not all online */
    cpu_set_t set;
    long n = sched_getaffinity(0, sizeof set, &set) == 0 ? CPU_COUNT(&set)
                                                         : sysconf(_SC_NPROCESSORS_ONLN);
    return n < 1 ? 1 : n > ALB_VP_MAX_THREADS ? ALB_VP_MAX_THREADS : (unsigned)n;
}

/* The output stage's scratch rows for n threads; -1 if out of memory (the
 * old scratch kept). */
int vp_scratch_for(alb_vp *vp, unsigned n)
{
    size_t per = vp_store_scratch_bytes(vp);
    if (!per)
        return 0;
    unsigned char *s = realloc(vp->scratch, per * n);
    if (!s)
        return -1;
    vp->scratch = s;
    return 0;
}

int alb_vp_set_threads(alb_vp *vp, unsigned n)
{
    vp_flush_batch(vp);
    n = n ? n : alb_vp_cores();
    n = n > ALB_VP_MAX_THREADS ? ALB_VP_MAX_THREADS : n;
    int rc = 0;
    if (n > 1 && !vp->batch && !(vp->batch = malloc(VP_BATCH * sizeof *vp->batch)))
        rc = -1;
    if (!rc && n > 1 && vp_scratch_for(vp, n))
        rc = -1;   /* one thread's scratch is there since alb_vp_create */
    vp->threads = rc ? 1 : n;
    if (vp->threads == 1) {
        free(vp->batch);
        vp->batch = NULL;
    }
    return rc;
}

unsigned alb_vp_threads(const alb_vp *vp) { return vp->threads ? vp->threads : 1; }

void vp_stats_add(alb_vp_stats *dst, const alb_vp_stats *src)
{
    for (unsigned l = 0; l < ALB_VP_MAX_LEVELS; l++)
        dst->cells[l] += src->cells[l];
#define ADD(f) dst->f += src->f;
    ADD(cells_inside) ADD(cells_outside) ADD(cells_split) ADD(samples_tested)
    ADD(samples_covered) ADD(samples_written) ADD(depth_saturated) ADD(depth_underflow)
    ADD(faces) ADD(edges) ADD(faces_shaded) ADD(faces_textured) ADD(faces_fogged)
#undef ADD
    /* the tie at the lowest sample: the same whichever tiles drew it */
    if (src->depth_ties && (!dst->depth_ties || src->tie_sample < dst->tie_sample)) {
        dst->tie_sample = src->tie_sample;
        dst->tie_kept = src->tie_kept;
        dst->tie_lost = src->tie_lost;
        dst->tie_depth = src->tie_depth;
    }
    dst->depth_ties += src->depth_ties;
    /* the nearest surface of the frame: the largest of the tiles' */
    if (src->depth_nearest > dst->depth_nearest)
        dst->depth_nearest = src->depth_nearest;
}

/* A tile's part of a face: fill it at the level of the cell that held it,
 * or walk below it (the cell, with its active edges). */
typedef struct {
    uint32_t face;            /* in the batch */
    bool fill;
    vp_cell cell;
} tile_job;

typedef struct {
    tile_job *a;
    size_t n, cap;
} job_list;

typedef struct {
    alb_vp *vp;
    vp_cell tiles[VP_MAX_TILES];
    job_list jobs[VP_MAX_TILES];
    unsigned ntiles, per_row;
    uint8_t wl, hl;           /* the tiles' sides, log2 */
    uint32_t face;            /* the face being put on the lists */
    bool nomem;
    atomic_uint next;         /* the next tile to take */
} job;

typedef struct {
    job *j;
    alb_vp local;               /* the VP's state, with statistics of its own */
} worker;

static void job_add(job *j, unsigned t, bool fill, const vp_cell *k)
{
    job_list *l = &j->jobs[t];
    if (l->n == l->cap) {
        size_t cap = l->cap ? 2 * l->cap : 64;
        tile_job *a = realloc(l->a, cap * sizeof *a);
        if (!a) {
            j->nomem = true;
            return;
        }
        l->a = a;
        l->cap = cap;
    }
    l->a[l->n++] = (tile_job){j->face, fill, *k};
}

/* vp_walk_to_tiles' job: a cell found inside fills each tile it holds at
 * its own level; a tile that splits is walked below. */
static void put_on_tiles(void *ctx, const vp_cell *k, bool fill)
{
    job *j = ctx;
    const uint32_t tc0 = k->c0 >> j->wl, tr0 = k->r0 >> j->hl;
    if (!fill) {
        job_add(j, tr0 * j->per_row + tc0, false, k);
        return;
    }
    const uint32_t tc1 = (k->c0 + (1u << k->wl) - 1) >> j->wl, tr1 = (k->r0 + (1u << k->hl) - 1) >> j->hl;
    for (uint32_t tr = tr0; tr <= tr1; tr++)
        for (uint32_t tc = tc0; tc <= tc1; tc++) {
            const unsigned t = tr * j->per_row + tc;
            vp_cell c = j->tiles[t];
            c.level = k->level;
            job_add(j, t, true, &c);
        }
}

static void *work(void *arg)
{
    worker *wk = arg;
    job *j = wk->j;
    for (;;) {
        unsigned t = atomic_fetch_add(&j->next, 1);
        if (t >= j->ntiles)
            return NULL;
        const job_list *l = &j->jobs[t];
        for (size_t i = 0; i < l->n; i++) {
            const vp_loaded_face *f = &j->vp->batch[l->a[i].face];
            if (l->a[i].fill)
                vp_fill(&wk->local, &f->fs, &l->a[i].cell);
            else
                vp_draw_below(&wk->local, f, &l->a[i].cell);
        }
    }
}

/* The tiles: the cells of the first level with at least 8 per thread (for
 * balance; threads take them as they finish), at most VP_MAX_TILES, and no
 * smaller than the sample store's tiles (store.c), so that each store tile
 * is cleared by the one thread whose tile holds it. */
static unsigned make_tiles(const alb_vp *vp, job *j)
{
    unsigned want = 8 * vp->threads, l = 0, wl = vp->lw, hl = vp->lh;
    while (l < vp->tile_level && (1u << ((vp->lw - wl) + (vp->lh - hl))) < want &&
           (4u << ((vp->lw - wl) + (vp->lh - hl))) <= VP_MAX_TILES) {
        l++;
        wl -= wl > 0;
        hl -= hl > 0;
    }
    j->ntiles = 0;
    j->wl = (uint8_t)wl, j->hl = (uint8_t)hl;
    j->per_row = vp->sw >> wl;
    for (uint32_t r = 0; r < vp->sh; r += 1u << hl)
        for (uint32_t c = 0; c < vp->sw; c += 1u << wl)
            j->tiles[j->ntiles++] = (vp_cell){c, r, (uint8_t)wl, (uint8_t)hl, (uint8_t)l, 0, 0};
    return l;
}

void vp_flush_batch(alb_vp *vp)
{
    if (!vp->nbatch)
        return;
    job *j = calloc(1, sizeof *j);
    worker *wk = calloc(vp->threads, sizeof *wk);
    pthread_t tid[ALB_VP_MAX_THREADS];
    bool started[ALB_VP_MAX_THREADS] = {false};
    unsigned nw = j && wk ? vp->threads : 0;
    if (nw) {
        /* the walks above the tiles, on this thread, counted in vp->st */
        alb_vp_stats before = vp->st;
        j->vp = vp;
        const unsigned tl = make_tiles(vp, j);
        atomic_init(&j->next, 0);
        for (j->face = 0; j->face < vp->nbatch && !j->nomem; j->face++)
            vp_walk_to_tiles(vp, &vp->batch[j->face], tl, put_on_tiles, j);
        if (j->nomem) {   /* no memory for the lists: one thread, as if none was tried */
            vp->st = before;
            nw = 0;
        }
    }
    for (unsigned i = 0; i < nw; i++) {
        wk[i].j = j;
        wk[i].local = *vp;
        memset(&wk[i].local.st, 0, sizeof wk[i].local.st);
    }
    /* workers 1.. on threads of their own, worker 0 here; a thread that
     * cannot be started leaves its tiles to the others */
    for (unsigned i = 1; i < nw; i++)
        started[i] = pthread_create(&tid[i], NULL, work, &wk[i]) == 0;
    if (nw) {
        work(&wk[0]);
    } else {
        /* no memory for the job: one thread, the whole screen */
        for (unsigned i = 0; i < vp->nbatch; i++)
            vp_draw_face(vp, &vp->batch[i]);
    }
    for (unsigned i = 0; i < nw; i++) {
        if (i && started[i])
            pthread_join(tid[i], NULL);
        vp_stats_add(&vp->st, &wk[i].local.st);
    }
    if (j)
        for (unsigned t = 0; t < j->ntiles; t++)
            free(j->jobs[t].a);
    free(wk);
    free(j);
    vp->nbatch = 0;
}

/* ---- rows split between the threads (clearing and resolving the store) ---- */

typedef struct {
    vp_row_fn fn;
    alb_vp *vp;
    void *ctx;
    uint32_t rows, chunk;
    atomic_uint next;
} row_job;

typedef struct {
    row_job *j;
    unsigned worker;
} row_worker;

static void *row_work(void *arg)
{
    row_worker *w = arg;
    row_job *j = w->j;
    for (;;) {
        uint32_t k = atomic_fetch_add(&j->next, 1);
        uint32_t r0 = k * j->chunk;
        if (k >= (j->rows + j->chunk - 1) / j->chunk)
            return NULL;
        j->fn(j->vp, j->ctx, w->worker, r0, r0 + j->chunk < j->rows ? r0 + j->chunk : j->rows);
    }
}

void vp_parallel_rows(alb_vp *vp, uint32_t rows, vp_row_fn fn, void *ctx)
{
    unsigned nt = alb_vp_threads(vp);
    if (nt <= 1 || rows < 2 * nt) {
        fn(vp, ctx, 0, 0, rows);
        return;
    }
    row_job j = {fn, vp, ctx, rows, (rows + 4 * nt - 1) / (4 * nt), 0};
    atomic_init(&j.next, 0);
    pthread_t tid[ALB_VP_MAX_THREADS];
    row_worker w[ALB_VP_MAX_THREADS];
    bool started[ALB_VP_MAX_THREADS] = {false};
    for (unsigned i = 0; i < nt; i++)
        w[i] = (row_worker){&j, i};
    for (unsigned i = 1; i < nt; i++)
        started[i] = pthread_create(&tid[i], NULL, row_work, &w[i]) == 0;
    row_work(&w[0]);
    for (unsigned i = 1; i < nt; i++)
        if (started[i])
            pthread_join(tid[i], NULL);
}
