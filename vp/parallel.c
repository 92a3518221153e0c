/* parallel.c — the functional VP on several threads, bit-identical to one.
 *
 * The screen is cut into tiles, the cells of one level of the subdivision
 * quadtree, and each tile belongs to one thread at a time.  Faces are loaded
 * in stream order into a batch; then each face's walk is made down to the
 * level of the tiles (vp_walk_to_tiles; a large batch's faces in chunks,
 * runs of them that the threads take as they finish), and every tile the
 * face reaches — a cell found inside, or a tile that splits — is put on
 * that tile's list, in stream order.  The threads then take the tiles
 * (each the run of its share first: vp_shares), and walk each tile's list:
 * fills, and the walks below the tiles (vp_draw_below).  A sample lies in
 * one tile only, so it sees the same faces in the same order as on one
 * thread: the same depth tests, the same winner, the same colour and
 * decision level.  Every cell is counted once — above the tiles by the
 * thread that walked its face's chunk, below by the tile's thread, each
 * into statistics of its own — so the sums are the single-threaded counts
 * too (tests/test_timing.c checks all of it). */
#define _GNU_SOURCE   /* sched_getaffinity: the cores this process may run on */
#include "vp_internal.h"

#include <pthread.h>
#include <sched.h>
#include <signal.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
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

/* ---- the threads: started once, woken for each task ----
 *
 * alb_vp_set_threads starts threads - 1 workers that live as long as the VP
 * (or until the count changes).  A task is a function every worker and the
 * caller run once, as worker 0 .. n; the caller waits for the workers to be
 * done with it.  Two tasks may be given at once (two slots): a worker done
 * with the first goes on to the second while the caller still works at the
 * first (the walk of the next batch after the draw of this one).  Between
 * tasks a worker first watches the task counter for a while (a
 * frame's batches follow each other within a fraction of a millisecond, and
 * a sleeping thread takes tens of microseconds to wake), then sleeps on a
 * condition variable; it watches only if the VP has no more threads than
 * the process has cores, so that a waiting worker never takes a core from
 * one that works. */

typedef void (*vp_task_fn)(void *ctx, unsigned worker);

typedef struct vp_pool vp_pool;

typedef struct {
    vp_pool *pool;
    unsigned id;              /* 1 .. n */
} pool_arg;

struct vp_pool {
    pthread_mutex_t mu;
    pthread_cond_t go, done;
    pthread_t tid[ALB_VP_MAX_THREADS];
    pool_arg arg[ALB_VP_MAX_THREADS];
    unsigned n;               /* workers started */
    bool spin;                /* watch before sleeping */
    atomic_uint gen;          /* tasks given so far; task g is in slot g % 2 */
    struct {
        vp_task_fn fn;        /* written before gen is raised */
        void *ctx;
        atomic_uint pending;  /* workers still on it */
    } slot[2];
    atomic_bool quit;
};

/* How long a waiting thread watches before it sleeps. */
#define POOL_SPIN_NS 200000

static uint64_t mono_ns(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (uint64_t)t.tv_sec * 1000000000u + (uint64_t)t.tv_nsec;
}

static inline void cpu_relax(void)
{
#if defined(__x86_64__) || defined(__i386__)
    __builtin_ia32_pause();
#endif
}

/* Watch *a until it equals `v` (want) or differs from it (!want), for a
 * while; whether it did.  The core is offered to any other thread that
 * wants it every few microseconds. */
static bool spin_until(const atomic_uint *a, unsigned v, bool want)
{
    const uint64_t t0 = mono_ns();
    for (;;) {
        for (unsigned i = 0; i < 256; i++) {
            if ((atomic_load_explicit(a, memory_order_acquire) == v) == want)
                return true;
            cpu_relax();
        }
        if (mono_ns() - t0 > POOL_SPIN_NS)
            return false;
        sched_yield();
    }
}

static void *pool_main(void *argp)
{
    const pool_arg *arg = argp;
    vp_pool *p = arg->pool;
    unsigned seen = 0;
    for (;;) {
        /* a worker that sees the task while it watches takes no lock: the
         * task was written before the counter was raised (release), and is
         * read after it was seen raised (acquire) */
        if (atomic_load_explicit(&p->gen, memory_order_acquire) == seen &&
            (!p->spin || !spin_until(&p->gen, seen, false))) {
            pthread_mutex_lock(&p->mu);
            while (atomic_load(&p->gen) == seen && !atomic_load(&p->quit))
                pthread_cond_wait(&p->go, &p->mu);
            pthread_mutex_unlock(&p->mu);
        }
        atomic_thread_fence(memory_order_acquire);
        if (atomic_load(&p->quit))
            return NULL;
        /* the tasks in the order given, one after the other */
        const unsigned k = seen++ % 2;
        p->slot[k].fn(p->slot[k].ctx, arg->id);
        if (atomic_fetch_sub_explicit(&p->slot[k].pending, 1, memory_order_acq_rel) == 1) {
            pthread_mutex_lock(&p->mu);
            pthread_cond_signal(&p->done);
            pthread_mutex_unlock(&p->mu);
        }
    }
}

static void pool_stop(vp_pool *p)
{
    if (!p)
        return;
    pthread_mutex_lock(&p->mu);
    atomic_store(&p->quit, true);
    atomic_fetch_add(&p->gen, 1);
    pthread_cond_broadcast(&p->go);
    pthread_mutex_unlock(&p->mu);
    for (unsigned i = 0; i < p->n; i++)
        pthread_join(p->tid[i], NULL);
    pthread_cond_destroy(&p->go);
    pthread_cond_destroy(&p->done);
    pthread_mutex_destroy(&p->mu);
    free(p);
}

/* A pool of `workers` threads (fewer if the system starts fewer), or NULL:
 * out of memory (*nomem set), or not one thread could be started (the
 * caller then works alone).  The workers take no signals: they are the
 * caller's to handle. */
static vp_pool *pool_start(unsigned workers, bool spin, bool *nomem)
{
    *nomem = true;
    vp_pool *p = calloc(1, sizeof *p);
    if (!p)
        return NULL;
    if (pthread_mutex_init(&p->mu, NULL)) {
        free(p);
        return NULL;
    }
    if (pthread_cond_init(&p->go, NULL)) {
        pthread_mutex_destroy(&p->mu);
        free(p);
        return NULL;
    }
    if (pthread_cond_init(&p->done, NULL)) {
        pthread_cond_destroy(&p->go);
        pthread_mutex_destroy(&p->mu);
        free(p);
        return NULL;
    }
    atomic_init(&p->gen, 0);
    atomic_init(&p->slot[0].pending, 0);
    atomic_init(&p->slot[1].pending, 0);
    atomic_init(&p->quit, false);
    p->spin = spin;
    sigset_t all, old;
    sigfillset(&all);
    pthread_sigmask(SIG_SETMASK, &all, &old);
    for (unsigned i = 0; i < workers && i < ALB_VP_MAX_THREADS; i++) {
        p->arg[p->n] = (pool_arg){p, p->n + 1};
        if (pthread_create(&p->tid[p->n], NULL, pool_main, &p->arg[p->n]))
            break;   /* the others take its share */
        p->n++;
    }
    pthread_sigmask(SIG_SETMASK, &old, NULL);
    *nomem = false;
    if (!p->n) {
        pool_stop(p);
        return NULL;
    }
    return p;
}

/* Back when every worker is done with task `task` (pool_post's number). */
static void pool_wait(vp_pool *p, unsigned task)
{
    if (!p)
        return;
    atomic_uint *pending = &p->slot[task % 2].pending;
    if (p->spin)
        spin_until(pending, 0, true);
    pthread_mutex_lock(&p->mu);
    while (atomic_load_explicit(pending, memory_order_acquire))
        pthread_cond_wait(&p->done, &p->mu);
    pthread_mutex_unlock(&p->mu);
}

/* fn(ctx, i) on worker i, 1 .. n, after the tasks given before it, without
 * waiting for them (pool_wait does); the task's number.  The task two
 * before it must be done (it is waited for here if not: its slot). */
static unsigned pool_post(vp_pool *p, vp_task_fn fn, void *ctx)
{
    if (!p)
        return 0;
    const unsigned g = atomic_load_explicit(&p->gen, memory_order_relaxed), k = g % 2;
    pool_wait(p, g - 2);
    /* no worker reads the slot: every one is done with the task in it */
    p->slot[k].fn = fn;
    p->slot[k].ctx = ctx;
    atomic_store_explicit(&p->slot[k].pending, p->n, memory_order_relaxed);
    pthread_mutex_lock(&p->mu);
    atomic_fetch_add_explicit(&p->gen, 1, memory_order_release);
    pthread_cond_broadcast(&p->go);
    pthread_mutex_unlock(&p->mu);
    return g;
}

/* fn(ctx, 0) here and fn(ctx, i) on worker i, 1 .. n; back when all are. */
static void pool_run(vp_pool *p, vp_task_fn fn, void *ctx)
{
    const unsigned task = pool_post(p, fn, ctx);
    fn(ctx, 0);
    pool_wait(p, task);
}

/* The workers of the VP's pool and the caller. */
static unsigned pool_threads(const vp_pool *p) { return p ? p->n + 1 : 1; }

/* ---- shares: work cut into items, each thread its own run first ----
 *
 * Thread i of n takes the items of its share from the front, then helps
 * the others with theirs, in turn from i + 1, from the back of theirs.  A
 * thread keeps the same part of the screen from batch to batch and frame to
 * frame — the tiles it drew are in its cache when it draws them again, and
 * their rows when it resolves them — where items taken from one counter
 * fell to either thread at random, and every sample of the store moved
 * between the cores' caches (1024², two threads: a 44-face frame 1.58x of
 * one thread, 1.81x with shares; docs/performance.md).  A share's front and
 * back are one word, so that its owner and a helper never take the same
 * item.  The tiles are shared by their cost when last drawn, each share
 * about the same, and taken the costliest first, so that what is left to
 * help with at the end is the cheapest (vp_share_by_cost). */

void vp_shares_init_at(vp_shares *s, const unsigned *start, unsigned n)
{
    s->n = n;
    for (unsigned i = 0; i < n; i++)
        atomic_init(&s->at[i].fb, (uint64_t)start[i] | (uint64_t)start[i + 1] << 32);
}

void vp_shares_init(vp_shares *s, unsigned items, unsigned n)
{
    unsigned start[ALB_VP_MAX_THREADS + 1];
    for (unsigned i = 0; i <= n; i++)
        start[i] = (unsigned)((uint64_t)items * i / n);
    vp_shares_init_at(s, start, n);
}

/* Share o's first item (own) or last (!own) into *item; false if none is
 * left. */
static bool share_take(vp_shares *s, unsigned o, bool own, unsigned *item)
{
    uint64_t fb = atomic_load_explicit(&s->at[o].fb, memory_order_relaxed);
    for (;;) {
        const uint32_t f = (uint32_t)fb, b = (uint32_t)(fb >> 32);
        if (f >= b)
            return false;   /* done: no write to its line */
        const uint64_t to = own ? fb + 1 : (uint64_t)f | (uint64_t)(b - 1) << 32;
        if (atomic_compare_exchange_weak_explicit(&s->at[o].fb, &fb, to, memory_order_relaxed,
                                                  memory_order_relaxed)) {
            *item = own ? f : b - 1;
            return true;
        }
    }
}

bool vp_shares_take(vp_shares *s, unsigned i, unsigned *item)
{
    for (unsigned k = 0; k < s->n; k++)
        if (share_take(s, (i + k) % s->n, k == 0, item))
            return true;
    return false;
}

/* ---- faces drawn on the threads ----
 *
 * A batch is walked above the tiles in chunks, runs of its faces in stream
 * order that the threads take as they finish, each chunk onto lists of its
 * own, a list a tile; then drawn, each tile's chunks' lists in turn: stream
 * order.  A full batch is drawn by the workers while the caller loads the
 * next; when the next is full, the caller joins the draw, and the walk of
 * the next is given as the task after it: a thread done with its tiles
 * walks chunks of the next batch instead of waiting for the others. */

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

typedef struct batch_job batch_job;

/* One thread's part: the VP's state with statistics of its own, and the
 * chunk it walks.  Apart from the next thread's by a cache line. */
typedef struct {
    batch_job *j;
    alb_vp local;
    uint32_t face;            /* the face being put on the lists */
    unsigned chunk;           /* the chunk it is in */
    bool nomem;
    char apart[64];
} worker;

/* Chunks of a batch: at most this many a thread, and at most VP_CHUNKS. */
#define VP_CHUNKS_PER_THREAD 8
#define VP_CHUNKS 128

struct batch_job {
    alb_vp *vp;
    const vp_loaded_face *faces;   /* the batch (one of vp->batches) */
    uint32_t nfaces;
    vp_cell tiles[VP_MAX_TILES];
    unsigned ntiles, per_row, level, nw;
    uint8_t wl, hl;           /* the tiles' sides, log2 */
    unsigned nchunks;         /* this batch's */
    unsigned most_chunks;     /* of any batch: lists for so many */
    atomic_uint next_chunk;   /* the next chunk to walk */
    job_list *lists;          /* chunk c's list for tile t: lists[c * VP_MAX_TILES + t] */
    vp_shares take;           /* the tiles' places in `order`, a run of them a thread */
    uint16_t order[VP_MAX_TILES];   /* the tiles of each share, the costliest first */
    _Atomic uint32_t *cost;   /* each tile's work when it was last drawn (tile_cost) */
    _Atomic uint32_t own_cost[VP_MAX_TILES];   /* the VP's first batch_job's: both point to it */
    unsigned task;            /* its draw's task (pool_post) */
    worker *wk;               /* nw of them */
};

static void job_add(worker *w, unsigned t, bool fill, const vp_cell *k)
{
    job_list *l = &w->j->lists[(size_t)w->chunk * VP_MAX_TILES + t];
    if (l->n == l->cap) {
        size_t cap = l->cap ? 2 * l->cap : 64;
        tile_job *a = realloc(l->a, cap * sizeof *a);
        if (!a) {
            w->nomem = true;
            return;
        }
        l->a = a;
        l->cap = cap;
    }
    l->a[l->n++] = (tile_job){w->face, fill, *k};
}

/* vp_walk_to_tiles' job: a cell found inside fills each tile it holds at
 * its own level; a tile that splits is walked below. */
static void put_on_tiles(void *ctx, const vp_cell *k, bool fill)
{
    worker *w = ctx;
    const batch_job *j = w->j;
    const uint32_t tc0 = k->c0 >> j->wl, tr0 = k->r0 >> j->hl;
    if (!fill) {
        job_add(w, tr0 * j->per_row + tc0, false, k);
        return;
    }
    const uint32_t tc1 = (k->c0 + (1u << k->wl) - 1) >> j->wl, tr1 = (k->r0 + (1u << k->hl) - 1) >> j->hl;
    for (uint32_t tr = tr0; tr <= tr1; tr++)
        for (uint32_t tc = tc0; tc <= tc1; tc++) {
            const unsigned t = tr * j->per_row + tc;
            vp_cell c = j->tiles[t];
            c.level = k->level;
            job_add(w, t, true, &c);
        }
}

/* Batches shorter than this are one chunk, walked above the tiles on the
 * caller's thread alone when nothing else is in flight. */
#define VP_WALK_ALONE 64

/* The lines of face f that a walk reads first (its set-up and first edges)
 * fetched ahead: the faces were loaded on the caller's core, and a walk
 * waits on them (10 000 faces, two threads: 2% of the frame). */
static inline void face_prefetch(const vp_loaded_face *f)
{
    const char *p = (const char *)f;
    for (size_t b = 0; b < offsetof(vp_loaded_face, e) + 4 * sizeof f->e[0]; b += 64)
        __builtin_prefetch(p + b);
}

/* A tile's work, from the statistics before and after its draw: cells
 * classified, samples covered, jobs begun; in rough units of a covered
 * sample, saturated.  It orders the tiles of the next batch. */
static uint32_t tile_cost(const alb_vp_stats *before, const alb_vp_stats *after, size_t jobs)
{
    const uint64_t cells = (after->cells_inside + after->cells_outside + after->cells_split) -
                           (before->cells_inside + before->cells_outside + before->cells_split);
    const uint64_t w = 32 * cells + (after->samples_covered - before->samples_covered) + 256 * (uint64_t)jobs;
    return w < UINT32_MAX ? (uint32_t)w : UINT32_MAX;
}

/* The walk's task: thread i takes chunks until none is left, and walks each
 * chunk's faces down to the tiles, onto the chunk's lists. */
static void walk_task(void *ctx, unsigned i)
{
    batch_job *j = ctx;
    worker *w = &j->wk[i];
    for (;;) {
        const unsigned c = atomic_fetch_add_explicit(&j->next_chunk, 1, memory_order_relaxed);
        if (c >= j->nchunks || w->nomem)
            return;
        job_list *l = &j->lists[(size_t)c * VP_MAX_TILES];
        for (unsigned t = 0; t < j->ntiles; t++)
            l[t].n = 0;
        w->chunk = c;
        const uint32_t f0 = (uint32_t)((uint64_t)j->nfaces * c / j->nchunks),
                       f1 = (uint32_t)((uint64_t)j->nfaces * (c + 1) / j->nchunks);
        for (w->face = f0; w->face < f1 && !w->nomem; w->face++) {
            if (w->face + 2 < f1)
                face_prefetch(&j->faces[w->face + 2]);
            vp_walk_to_tiles(&w->local, &j->faces[w->face], j->level, put_on_tiles, w);
        }
    }
}

/* The draw's: each thread takes the tiles of its share, then helps the
 * others (vp_shares), and walks each tile's jobs — chunk 0's list, then
 * chunk 1's, ...: stream order. */
static void draw_task(void *ctx, unsigned i)
{
    batch_job *j = ctx;
    alb_vp *local = &j->wk[i].local;
    unsigned at;
    while (vp_shares_take(&j->take, i, &at)) {
        const unsigned t = j->order[at];
        const alb_vp_stats before = local->st;
        size_t jobs = 0;
        for (unsigned c = 0; c < j->nchunks; c++) {
            const job_list *l = &j->lists[(size_t)c * VP_MAX_TILES + t];
            jobs += l->n;
            for (size_t q = 0; q < l->n; q++) {
                const tile_job *b = &l->a[q];
                if (q + 2 < l->n)
                    face_prefetch(&j->faces[l->a[q + 2].face]);
                const vp_loaded_face *f = &j->faces[b->face];
                if (b->fill)
                    vp_fill(local, &f->fs, &b->cell);
                else
                    vp_draw_below(local, f, &b->cell);
            }
        }
        atomic_store_explicit(&j->cost[t], tile_cost(&before, &local->st, jobs), memory_order_relaxed);
    }
}

/* The tiles: the cells of the first level with at least VP_TILES_PER_THREAD
 * per thread (for balance: a thread done with its share takes from the
 * others'), at most VP_MAX_TILES, and no smaller than the sample store's
 * tiles (store.c), so that each store tile is cleared by the one thread
 * whose tile holds it.  Fewer, larger tiles: fewer levels walked above them
 * and fewer jobs, and a large face's rows filled in longer runs; more: a
 * finer balance.  With the next batch's walk after a draw, a thread done
 * early has work, and eight are the better (docs/performance.md). */
#define VP_TILES_PER_THREAD 8
static void make_tiles(const alb_vp *vp, batch_job *j)
{
    unsigned want = VP_TILES_PER_THREAD * j->nw, l = 0, wl = vp->lw, hl = vp->lh;
    while (l < vp->tile_level && (1u << ((vp->lw - wl) + (vp->lh - hl))) < want &&
           (4u << ((vp->lw - wl) + (vp->lh - hl))) <= VP_MAX_TILES) {
        l++;
        wl -= wl > 0;
        hl -= hl > 0;
    }
    j->ntiles = 0;
    j->level = l;
    j->wl = (uint8_t)wl, j->hl = (uint8_t)hl;
    j->per_row = vp->sw >> wl;
    for (uint32_t r = 0; r < vp->sh; r += 1u << hl)
        for (uint32_t c = 0; c < vp->sw; c += 1u << wl)
            j->tiles[j->ntiles++] = (vp_cell){c, r, (uint8_t)wl, (uint8_t)hl, (uint8_t)l, 0, 0};
}

void vp_share_by_cost(const uint64_t *cost, unsigned items, unsigned n, unsigned *start, uint16_t *order)
{
    uint64_t total = 0, sum = 0;
    for (unsigned t = 0; t < items; t++)
        total += cost[t];
    for (unsigned t = 0, i = 0; i <= n; i++) {
        const uint64_t want = total * i / n;   /* share i begins where this much is before it */
        while (t < items && sum < want)
            sum += cost[t++];
        start[i] = i == n ? items : t;
    }
    for (unsigned i = 0; i < n; i++)
        for (unsigned p = start[i]; p < start[i + 1]; p++) {
            unsigned q = p;
            for (; q > start[i] && cost[order[q - 1]] < cost[p]; q--)
                order[q] = order[q - 1];
            order[q] = (uint16_t)p;
        }
}

/* The tiles shared out by their costs when last drawn (the tiles are the
 * same from batch to batch, the costs from the last batch or frame; each at
 * least 1: equal shares before any cost is known). */
static void share_tiles(batch_job *j)
{
    uint64_t cost[VP_MAX_TILES];
    for (unsigned t = 0; t < j->ntiles; t++)
        cost[t] = 1 + (uint64_t)atomic_load_explicit(&j->cost[t], memory_order_relaxed);
    unsigned start[ALB_VP_MAX_THREADS + 1];
    vp_share_by_cost(cost, j->ntiles, j->nw, start, j->order);
    vp_shares_init_at(&j->take, start, j->nw);
}

/* The batch being loaded (vp->batch) made ready to walk as j: its tiles,
 * chunks, and each thread's state with statistics of its own. */
static void batch_ready(alb_vp *vp, batch_job *j)
{
    j->faces = vp->batch;
    j->nfaces = vp->nbatch;
    make_tiles(vp, j);
    share_tiles(j);
    const unsigned most = j->most_chunks;
    j->nchunks = j->nfaces < VP_WALK_ALONE ? 1 : j->nfaces < most ? j->nfaces : most;
    atomic_init(&j->next_chunk, 0);
    for (unsigned i = 0; i < j->nw; i++) {
        worker *w = &j->wk[i];
        w->local = *vp;
        memset(&w->local.st, 0, sizeof w->local.st);
        w->nomem = false;
    }
}

/* Whether j's walk found memory for its lists. */
static bool batch_walked(const batch_job *j)
{
    bool ok = true;
    for (unsigned i = 0; i < j->nw; i++)
        ok &= !j->wk[i].nomem;
    return ok;
}

/* The batch in flight drawn to its end, the caller taking tiles too, and
 * its counts into the VP's. */
static void inflight_done(alb_vp *vp)
{
    batch_job *j = vp->inflight;
    for (unsigned i = 0; i < j->nw; i++)
        vp_stats_add(&vp->st, &j->wk[i].local.st);
    vp->inflight = NULL;
}

static void finish_inflight(alb_vp *vp)
{
    if (!vp->inflight)
        return;
    draw_task(vp->inflight, 0);
    pool_wait(vp->pool, vp->inflight->task);
    inflight_done(vp);
}

/* The loaded batch walked above the tiles as j, and the batch in flight
 * drawn to its end: with one in flight, the walk is the task after its
 * draw; a short batch with none is walked here (less work than a hand-over
 * to the threads).  False if out of memory for the lists. */
static bool walk_batch(alb_vp *vp, batch_job *j)
{
    batch_ready(vp, j);
    if (vp->inflight) {
        const unsigned walk = pool_post(vp->pool, walk_task, j);
        draw_task(vp->inflight, 0);
        walk_task(j, 0);
        pool_wait(vp->pool, vp->inflight->task);
        pool_wait(vp->pool, walk);
        inflight_done(vp);
    } else if (j->nchunks == 1) {
        walk_task(j, 0);
    } else {
        pool_run(vp->pool, walk_task, j);
    }
    return batch_walked(j);
}

/* j's draw given to the workers; the caller joins it in finish_inflight
 * (or walk_batch). */
static void draw_post(alb_vp *vp, batch_job *j)
{
    j->task = pool_post(vp->pool, draw_task, j);
    vp->inflight = j;
}

/* The loaded batch drawn here and now: on the threads, or with no memory
 * for the lists on this one, the whole screen, as if no thread had been
 * tried (the walks above the tiles were counted only in the workers'
 * statistics). */
static void draw_batch_now(alb_vp *vp, batch_job *j, bool walked)
{
    if (walked) {
        draw_post(vp, j);
        finish_inflight(vp);
    } else {
        for (unsigned i = 0; i < vp->nbatch; i++)
            vp_draw_face(vp, &vp->batch[i]);
    }
    vp->nbatch = 0;
}

/* Which of the two batches is being loaded. */
static unsigned batch_index(const alb_vp *vp) { return vp->batch == vp->batches[0] ? 0 : 1; }

void vp_flush_batch(alb_vp *vp)
{
    if (!vp->nbatch) {
        finish_inflight(vp);
        return;
    }
    batch_job *j = vp->par[batch_index(vp)];
    draw_batch_now(vp, j, walk_batch(vp, j));
}

void vp_batch_full(alb_vp *vp)
{
    const unsigned cur = batch_index(vp);
    batch_job *j = vp->par[cur];
    const bool walked = walk_batch(vp, j);
    /* nothing in flight now; the workers read the face list (a tie names
     * the face that kept it) while the next batch's faces are added: room
     * for them first (drawn here and now if there is none), and the
     * threads' state the VP's as it is now (the list may have moved, even
     * if the room was not all found), the walk's statistics kept */
    const bool room = walked && !vp_store_reserve_faces(vp, VP_BATCH);
    for (unsigned i = 0; walked && i < j->nw; i++) {
        const alb_vp_stats st = j->wk[i].local.st;
        j->wk[i].local = *vp;
        j->wk[i].local.st = st;
    }
    if (room) {
        draw_post(vp, j);
        vp->batch = vp->batches[cur ^ 1];
        vp->nbatch = 0;
        return;
    }
    draw_batch_now(vp, j, walked);
}

static void batch_job_free(batch_job *j)
{
    if (!j)
        return;
    if (j->lists)
        for (size_t k = 0; k < (size_t)j->most_chunks * VP_MAX_TILES; k++)
            free(j->lists[k].a);
    free(j->lists);
    free(j->wk);
    free(j);
}

static batch_job *batch_job_new(alb_vp *vp, unsigned nw)
{
    batch_job *j = calloc(1, sizeof *j);
    if (!j)
        return NULL;
    const unsigned chunks = nw * VP_CHUNKS_PER_THREAD < VP_CHUNKS ? nw * VP_CHUNKS_PER_THREAD : VP_CHUNKS;
    if (!(j->wk = calloc(nw, sizeof *j->wk)) ||
        !(j->lists = calloc((size_t)chunks * VP_MAX_TILES, sizeof *j->lists))) {
        free(j->wk);
        free(j);
        return NULL;
    }
    j->vp = vp;
    j->nw = nw;
    j->most_chunks = chunks;
    j->cost = j->own_cost;
    for (unsigned i = 0; i < nw; i++)
        j->wk[i].j = j;
    return j;
}

/* ---- rows split between the threads (clearing and resolving the store) ---- */

typedef struct {
    vp_row_fn fn;
    alb_vp *vp;
    void *ctx;
    uint32_t rows, chunk;
    vp_shares take;           /* the chunks, a run of them a thread */
} row_job;

static void row_task(void *arg, unsigned id)
{
    row_job *j = arg;
    unsigned k;
    while (vp_shares_take(&j->take, id, &k)) {
        uint32_t r0 = k * j->chunk;
        j->fn(j->vp, j->ctx, id, r0, r0 + j->chunk < j->rows ? r0 + j->chunk : j->rows);
    }
}

void vp_parallel_rows(alb_vp *vp, uint32_t rows, vp_row_fn fn, void *ctx)
{
    unsigned nt = pool_threads(vp->pool);
    if (nt <= 1 || rows < 2 * nt) {
        fn(vp, ctx, 0, 0, rows);
        return;
    }
    /* four chunks a thread: thread i's run the rows of the tiles it draws
     * (its share of the tiles, cut the same way, row by row) */
    row_job j = {.fn = fn, .vp = vp, .ctx = ctx, .rows = rows, .chunk = (rows + 4 * nt - 1) / (4 * nt)};
    vp_shares_init(&j.take, (rows + j.chunk - 1) / j.chunk, nt);
    pool_run(vp->pool, row_task, &j);
}

/* ---- the count ---- */

void vp_threads_free(alb_vp *vp)
{
    finish_inflight(vp);
    pool_stop(vp->pool);
    vp->pool = NULL;
    for (unsigned k = 0; k < 2; k++) {
        batch_job_free(vp->par[k]);
        vp->par[k] = NULL;
        free(vp->batches[k]);
        vp->batches[k] = NULL;
    }
    vp->batch = NULL;
    vp->nbatch = 0;
}

int alb_vp_set_threads(alb_vp *vp, unsigned n)
{
    vp_flush_batch(vp);
    n = n ? n : alb_vp_cores();
    n = n > ALB_VP_MAX_THREADS ? ALB_VP_MAX_THREADS : n;
    if (n == alb_vp_threads(vp))
        return 0;
    vp_threads_free(vp);
    if (n == 1)
        return 0;
    /* the workers: n - 1 threads (fewer if the system gives fewer; none,
     * and the VP draws on the caller's thread as it would on one) */
    bool nomem = false;
    if (vp_scratch_for(vp, n))
        return -1;   /* one thread's scratch is there since alb_vp_create */
    if (!(vp->pool = pool_start(n - 1, n <= alb_vp_cores(), &nomem)))
        return nomem ? -1 : 0;
    const unsigned nt = pool_threads(vp->pool);
    for (unsigned k = 0; k < 2; k++)
        if (!(vp->batches[k] = malloc(VP_BATCH * sizeof *vp->batches[k])) ||
            !(vp->par[k] = batch_job_new(vp, nt))) {
            vp_threads_free(vp);
            return -1;
        }
    vp->par[1]->cost = vp->par[0]->own_cost;   /* one table of the tiles' costs */
    vp->batch = vp->batches[0];
    return 0;
}

unsigned alb_vp_threads(const alb_vp *vp) { return pool_threads(vp->pool); }
