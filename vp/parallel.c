/* parallel.c — the functional VP on several threads, bit-identical to one.
 *
 * The screen is cut into tiles, the cells of one level of the subdivision
 * quadtree, and each tile belongs to one thread at a time.  Faces are loaded
 * in stream order into a batch; then every tile draws every face of the
 * batch, in stream order, with a walk clipped to the tile (vp.c).  A sample
 * lies in one tile only, so it sees the same faces in the same order as on
 * one thread: the same depth tests, the same winner, the same colour and
 * decision level.  Each thread counts into its own statistics, and a cell is
 * counted by the tile holding its top-left sample only, so the sums are the
 * single-threaded counts too (tests/test_vp.c checks all of it). */
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

typedef struct {
    alb_vp *vp;
    vp_cell tiles[VP_MAX_TILES];
    unsigned ntiles;
    atomic_uint next;         /* the next tile to take */
} job;

typedef struct {
    job *j;
    alb_vp local;               /* the VP's state, with statistics of its own */
} worker;

static void *work(void *arg)
{
    worker *wk = arg;
    job *j = wk->j;
    for (;;) {
        unsigned t = atomic_fetch_add(&j->next, 1);
        if (t >= j->ntiles)
            return NULL;
        for (unsigned i = 0; i < j->vp->nbatch; i++) {
            vp_draw_face_tile(&wk->local, &j->vp->batch[i], &j->tiles[t]);
        }
    }
}

/* The tiles: the cells of the first level with at least 8 per thread (for
 * balance; threads take them as they finish), at most VP_MAX_TILES, and no
 * smaller than the sample store's tiles (store.c), so that each store tile
 * is cleared by the one thread whose tile holds it. */
static void make_tiles(const alb_vp *vp, job *j)
{
    unsigned want = 8 * vp->threads, l = 0, wl = vp->lw, hl = vp->lh;
    while (l < vp->tile_level && (1u << ((vp->lw - wl) + (vp->lh - hl))) < want &&
           (4u << ((vp->lw - wl) + (vp->lh - hl))) <= VP_MAX_TILES) {
        l++;
        wl -= wl > 0;
        hl -= hl > 0;
    }
    j->ntiles = 0;
    for (uint32_t r = 0; r < vp->sh; r += 1u << hl)
        for (uint32_t c = 0; c < vp->sw; c += 1u << wl)
            j->tiles[j->ntiles++] = (vp_cell){c, r, (uint8_t)wl, (uint8_t)hl, (uint8_t)l, 0, 0};
}

void vp_flush_batch(alb_vp *vp)
{
    if (!vp->nbatch)
        return;
    job *j = malloc(sizeof *j);
    worker *wk = calloc(vp->threads, sizeof *wk);
    pthread_t tid[ALB_VP_MAX_THREADS];
    bool started[ALB_VP_MAX_THREADS] = {false};
    unsigned nw = j && wk ? vp->threads : 0;
    if (j) {
        j->vp = vp;
        make_tiles(vp, j);
        atomic_init(&j->next, 0);
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
