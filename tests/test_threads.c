/* test_threads.c — the functional renderer on its worker threads
 * (vp/parallel.c): frames of several batches of faces, with ties in every
 * sample two faces share, drawn by one VP whose thread count changes from
 * one run to the next, each the same as on one thread — every plane and
 * every statistic, the first tie and the faces that kept and lost it; and
 * the shares the threads take their work from. */
#include "t.h"

#include "gp_helpers.h"
#include "../vp/vp_internal.h"

#include <pthread.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
    alb_frame f;
    alb_vp_stats st;
    unsigned n;
} first_frame;

static int keep(void *ctx, const alb_frame *f, const alb_vp_stats *st)
{
    first_frame *k = ctx;
    if (k->n++ == 0) {
        if (alb_frame_copy(&k->f, f))
            return -1;
        k->st = *st;
    }
    return 0;
}

/* Every face of the scene text twice, the copy in another colour: the
 * copy ties with the first in every sample they share and loses each. */
static char *twice(const char *text)
{
    size_t n = strlen(text);
    char *out = malloc(2 * n + 1), *o = out;
    if (!out)
        return NULL;
    for (const char *line = text; *line;) {
        const char *end = strchr(line, '\n');
        size_t len = end ? (size_t)(end - line) + 1 : strlen(line);
        memcpy(o, line, len);
        o += len;
        const char *colour = strstr(line, " colour ");
        if (line[0] == ' ' && line[1] == 'f' && line[2] == ' ' && colour && colour < line + len) {
            size_t head = (size_t)(colour - line);
            memcpy(o, line, head);
            o += head;
            o += sprintf(o, " colour 7 7 7\n");
        }
        line += len;
    }
    *o = '\0';
    return out;
}

static int run_on(alb_vp *vp, const alb_ws_buf *b, first_frame *k)
{
    alb_diag d;
    alb_diag_init(&d, NULL);
    memset(k, 0, sizeof *k);
    return alb_vp_run_stream(vp, b->w, b->n, "test", keep, k, &d) != ALB_OK || k->n != 1;
}

TEST(threads_batches_and_ties_as_on_one_thread)
{
    scenegen_params gp = scenegen_defaults();
    gp.faces = 1600;   /* 3200 faces drawn: four batches of the threaded renderer */
    gp.behind = 0;
    gp.backfacing = 0;
    gp.size = 0.25;
    gp.flat = false;
    char *text = scenegen_random(3, &gp), *both = text ? twice(text) : NULL;
    alb_profile p;
    alb_ws_buf b;
    CHECK(both && alb_profile_lookup("a256", &p) == 0);
    if (!both || stream_of(both, &p, &b)) {
        CHECK_MSG(0, "no stream of the scene");
        free(text);
        free(both);
        return;
    }
    alb_diag d;
    alb_diag_init(&d, NULL);
    alb_vp *one = NULL, *many = NULL;
    first_frame ref, got;
    CHECK(alb_vp_create(&one, &p, &d) == ALB_OK && alb_vp_create(&many, &p, &d) == ALB_OK);
    if (one && many && !run_on(one, &b, &ref)) {
        CHECK_MSG(ref.st.faces > 2 * VP_BATCH, "%llu faces", (unsigned long long)ref.st.faces);
        CHECK_MSG(ref.st.depth_ties > 1000, "%llu ties", (unsigned long long)ref.st.depth_ties);
        /* the thread count changed on the same VP between the runs: the
         * workers stopped and started again */
        static const unsigned counts[] = {2, 3, 1, 5, 2, 8};
        for (unsigned i = 0; i < sizeof counts / sizeof counts[0]; i++) {
            CHECK(alb_vp_set_threads(many, counts[i]) == 0);
            CHECK_EQ(alb_vp_threads(many), counts[i]);
            if (run_on(many, &b, &got)) {
                CHECK_MSG(0, "the run on %u threads failed", counts[i]);
                continue;
            }
            CHECK_MSG(alb_frame_count_differences(&got.f, &ref.f) == 0,
                      "%zu pixels differ on %u threads", alb_frame_count_differences(&got.f, &ref.f),
                      counts[i]);
            CHECK_MSG(!memcmp(&got.st, &ref.st, sizeof got.st),
                      "statistics differ on %u threads (ties %llu / %llu, kept %llu / %llu)", counts[i],
                      (unsigned long long)got.st.depth_ties, (unsigned long long)ref.st.depth_ties,
                      (unsigned long long)got.st.tie_kept, (unsigned long long)ref.st.tie_kept);
            alb_frame_free(&got.f);
        }
        alb_frame_free(&ref.f);
    } else {
        CHECK_MSG(0, "the run on one thread failed");
    }
    alb_vp_destroy(one);
    alb_vp_destroy(many);
    alb_ws_buf_free(&b);
    free(text);
    free(both);
}

/* ---- shares (vp_shares: the tiles and the output stage's rows) ---- */

/* One thread alone takes every item: its own share from the front, then
 * each other share in turn from the back.  Worked by hand: three shares
 * [0, 2), [2, 5), [5, 6), taken by thread 1. */
TEST(shares_alone_take_own_front_then_others_backs)
{
    static vp_shares s;
    const unsigned start[] = {0, 2, 5, 6}, want[] = {2, 3, 4, 5, 1, 0};
    vp_shares_init_at(&s, start, 3);
    unsigned got[8], n = 0, item;
    while (n < 8 && vp_shares_take(&s, 1, &item))
        got[n++] = item;
    CHECK_EQ(n, 6);
    for (unsigned i = 0; i < n && i < 6; i++)
        CHECK_MSG(got[i] == want[i], "take %u: item %u, want %u", i, got[i], want[i]);
    /* empty shares: nothing to take, for any thread */
    const unsigned none[] = {0, 0, 0};
    vp_shares_init_at(&s, none, 2);
    CHECK(!vp_shares_take(&s, 0, &item) && !vp_shares_take(&s, 1, &item));
}

typedef struct {
    vp_shares *s;
    unsigned id, n;
    unsigned *got;            /* the items taken, in order */
} taker;

static void *take_all(void *arg)
{
    taker *t = arg;
    unsigned item;
    while (vp_shares_take(t->s, t->id, &item))
        t->got[t->n++] = item;
    return NULL;
}

/* Threads taking at once: every item once, and each thread's items from
 * its own share a run from the share's front, in order. */
TEST(shares_give_every_item_once_on_threads)
{
    static vp_shares s;
    static const unsigned threads[] = {2, 3, 5, 8}, items[] = {1, 7, 64, 1000, 20000};
    uint64_t seed = 11;
    for (unsigned a = 0; a < sizeof threads / sizeof threads[0]; a++)
        for (unsigned b = 0; b < sizeof items / sizeof items[0]; b++) {
            const unsigned n = threads[a], m = items[b];
            unsigned start[9];
            start[0] = 0, start[n] = m;
            for (unsigned i = 1; i < n; i++) {   /* random cuts, in order, some shares empty */
                const unsigned cut = (unsigned)(t_rand(&seed) % (m + 1));
                start[i] = cut < start[i - 1] ? start[i - 1] : cut;
            }
            vp_shares_init_at(&s, start, n);
            unsigned *got = calloc((size_t)n * m, sizeof *got), *seen = calloc(m, sizeof *seen);
            taker tk[8];
            pthread_t tid[8];
            unsigned started = 0;
            if (!got || !seen) {
                CHECK_MSG(0, "out of memory");
                free(got);
                free(seen);
                return;
            }
            for (unsigned i = 0; i < n; i++) {
                tk[i] = (taker){&s, i, 0, got + (size_t)i * m};
                started += pthread_create(&tid[i], NULL, take_all, &tk[i]) == 0;
            }
            CHECK_EQ(started, n);
            for (unsigned i = 0; i < started; i++)
                pthread_join(tid[i], NULL);
            bool once = true, runs = true;
            for (unsigned i = 0; i < n; i++) {
                unsigned next = start[i];   /* the owner's next item of its share */
                for (unsigned q = 0; q < tk[i].n; q++) {
                    const unsigned it = tk[i].got[q];
                    once &= it < m && ++seen[it] == 1;
                    if (it >= start[i] && it < start[i + 1])
                        runs &= it == next++;
                }
            }
            for (unsigned k = 0; k < m; k++)
                once &= seen[k] == 1;
            CHECK_MSG(once, "%u threads, %u items: an item taken twice or never", n, m);
            CHECK_MSG(runs, "%u threads, %u items: an owner's items not a run from its share's front",
                      n, m);
            free(got);
            free(seen);
        }
}

/* The tiles shared by cost: a hand-worked case, then the rule on random
 * costs — each share begins at the first item with at least total * i / n
 * before it, and lists its items the costliest first, ties in order. */
TEST(share_by_cost_cuts_at_equal_cost_and_orders_costliest_first)
{
    const uint64_t cost[] = {1, 1, 1, 1, 8, 1, 1, 1};
    unsigned start[3];
    uint16_t order[8];
    vp_share_by_cost(cost, 8, 2, start, order);
    /* total 15: share 1 begins where 7.5 is before it, after the 8 (12) */
    CHECK(start[0] == 0 && start[1] == 5 && start[2] == 8);
    static const uint16_t want[] = {4, 0, 1, 2, 3, 5, 6, 7};
    CHECK(!memcmp(order, want, sizeof want));

    uint64_t seed = 5;
    static uint64_t c[VP_MAX_TILES];
    static uint16_t o[VP_MAX_TILES];
    bool ok = true;
    for (unsigned round = 0; round < 200 && ok; round++) {
        const unsigned m = 1 + (unsigned)(t_rand(&seed) % VP_MAX_TILES), n = 1 + (unsigned)(t_rand(&seed) % 8);
        for (unsigned t = 0; t < m; t++)   /* a few very costly, many alike */
            c[t] = 1 + (t_rand(&seed) % 8 == 0 ? t_rand(&seed) % 100000 : t_rand(&seed) % 4);
        unsigned st[9];
        vp_share_by_cost(c, m, n, st, o);
        uint64_t total = 0;
        for (unsigned t = 0; t < m; t++)
            total += c[t];
        ok &= st[0] == 0 && st[n] == m;

        static uint64_t prefix[VP_MAX_TILES + 1];   /* the cost before item t */
        prefix[0] = 0;
        for (unsigned t = 0; t < m; t++)
            prefix[t + 1] = prefix[t] + c[t];
        for (unsigned i = 1; i < n && ok; i++) {
            const uint64_t want_before = total * i / n;
            ok &= st[i] >= st[i - 1] && st[i] <= m && prefix[st[i]] >= want_before &&
                  (st[i] == 0 || prefix[st[i] - 1] < want_before);
        }
        for (unsigned i = 0; i < n && ok; i++) {
            static bool in[VP_MAX_TILES];
            memset(in, 0, sizeof in);
            for (unsigned p = st[i]; p < st[i + 1]; p++) {
                ok &= o[p] >= st[i] && o[p] < st[i + 1] && !in[o[p]];
                if (ok)
                    in[o[p]] = true;
                if (p > st[i])
                    ok &= c[o[p - 1]] > c[o[p]] || (c[o[p - 1]] == c[o[p]] && o[p - 1] < o[p]);
            }
        }
        CHECK_MSG(ok, "round %u: %u items in %u shares against the rule", round, m, n);
    }
}
